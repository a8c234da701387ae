/* test_grad_random.c - design gradients (study/pom_grad.h) against central
 * differences of whole simulations on random designs and maneuvers (issue
 * 29 item 1, docs/optimize.md "Design gradients", "Verification").
 *
 * Each case draws a shipped architecture, the design keys' values uniformly
 * within +-20 % of the shipped ones (coil resistance and force constant, the
 * PID's K_P and tau_D, a limb body's mass, a geometry ratio) and a target
 * uniformly within +-3 mm per actuator (+-0.2 rad on the 3-RRR's revolute
 * actuators, --arch), and compares every defined gradient
 * with the honest whole-run reference (pom_grad_reference): central
 * differences at H = REF_STEP |p|, H/2 and H/4, Richardson-extrapolated from the
 * two smallest, with an error estimate E (the Richardson pair's disagreement
 * plus the runs' integration error class_run_error over the step) and a kink test
 * (the h^2 law of the differences, forward against backward at H/4). The
 * comparison is on elasticities (p / M) dM/dp: the error of a derivative in
 * the units the gradient is used in (a parameter that barely moves a metric
 * has a tiny derivative whose relative error says nothing). Bounds (the
 * issue's): energies 1e-5, settling times 1e-4; the final pointing error (a
 * ~1e-6 rad residual) 1e-3; the peak coil current 1e-4. A derivative meets
 * its bound when |sens - ref| <= bound + E, and every compared derivative
 * must meet it (with --against, at both noise margins). A reference whose E exceeds
 * REF_SHARE of the bound cannot check the derivative to the bound: counted as "reference not
 * differentiable at this step" when its kink test fired, as "reference
 * unresolved" otherwise, never compared and never dropped silently; so is a
 * gradient the engine reports undefined (never settled, grazing, ...).
 *
 * argv[1]: the number of cases (default 10; the long-labelled run: 100).
 * argv[2]: an elasticity added to every sensitivity before the comparison
 * (default 0): the test must then fail (test_grad_random_perturbed).
 * argv[3]: the first case to run (default 0; the cases before it are drawn
 * and skipped): a long run split into ranges that run side by side.
 * --margin M (anywhere): the sensitivities' noise margin
 * (pom_grad_options.sens_noise_margin, default 3e2; docs/optimize.md 12.4).
 * --rel-step R: the sensitivities' differencing step (pom_grad_options.rel_step,
 * default 3e-6).
 * --error-test off: the sensitivities out of CVODES' error test
 * (pom_grad_options.error_control 0, gradient.sens_error_test = "off";
 * docs/optimize.md 12.5, "The error test"); the check runs at rtol 1e-12.
 * --ref-step S: the reference's largest step H = S |p| (default REF_STEP,
 * 4e-3): a reference that moves with it was not differentiable there
 * (the cache of --ref-cache does not record it: one step per PREFIX).
 * --dry: each case only drawn and classified (runs, or not run and why),
 * nothing simulated; the checks then fail (nothing compared).
 * --against M0: each case's sensitivities also at the noise margin M0, held
 * to the same bounds: since the perturbed models follow the nominal's
 * saturation pattern (docs/optimize.md 12.1), the error does not follow
 * the margin, and a design that meets the bounds at one margin and not at
 * another is the defect that change removed (test_grad_random_margin,
 * test_grad_random_3rrr_margin).
 * --cases A,B,...: run only these cases (of the first argv[1]).
 * --verbose: every compared derivative printed with its error, not only
 * those beyond their bound.
 * --ref-cache PREFIX: the references (which do not depend on the
 * sensitivities' settings) are read from PREFIX.N (case N) when present and
 * written there otherwise: the same cases at several margins run the 37
 * whole simulations of each reference once (same build only).
 * --arch FILE: every case on that architecture only (3pss.cfg, 3sps.cfg or
 * 3rrr.cfg: the 3-RRR with rotary voice coils, its own keys, ranges and
 * targets within +-0.2 rad; test_grad_random_3rrr; or a catalog
 * architecture, catalog/3rss_radial.cfg, catalog/3ruu_wrist.cfg or
 * catalog/3pss_inclined.cfg, each with its keys, ranges and targets in
 * archs[]: test_grad_random_catalog); without it the cases
 * alternate the 3P-S-S/S and 3S-P-S/S, the sequence of docs/optimize.md
 * 12.4's tables. */
#include "check.h"
#include "grad_test_util.h"
#include "pom_arch_file.h"
#include "pom_dyn_print.h"
#include "pom_grad.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RTOL "1e-12"

/* The relative integration error of one run's metrics at rtol 1e-12, the
 * part that is not smooth in the design (docs/optimize.md 12.4, measured:
 * the central differences at 2.5e-4 |p| of runs at rtol 1e-12 and 2e-12
 * disagree by elasticities up to 2.3e-6 (energies), 6.4e-6 (settling
 * times), 1.3e-6 (peak current), 9e-5 (final pointing error), i.e. run
 * errors of 2.9e-10, 8e-10, 1.6e-10, 1.1e-8): about 3x those. */
static const double class_run_error[4] = {1e-9, 3e-9, 5e-8, 5e-10};

/* The largest step of the reference (relative to |p|): its noise, run_error
 * / (H/4) in elasticity, stays below REF_SHARE of the bounds (4e-6 x 1.5
 * against 1e-5 on the energies) while the h^4 residue of the Richardson
 * pair stays far below (measured: |R1 - R2| ~ 1e-7). */
#define REF_STEP 4e-3

/* A reference must be this much better than the bound to check a
 * derivative against it. */
#define REF_SHARE 0.25

static const char *const class_name[4] = {"energy", "settling-time", "pointing", "peak-current"};
/* The peak current has no bound in the issue: 1e-4, which the plain suite's
 * 10 cases meet (worst 6.7e-5) and, since a maximum near a saturated
 * voltage's corner is reported undefined (docs/optimize.md 12.2; before,
 * up to 2.7e-2 there), the 100-design run too (worst 4.8e-7). */
static const double class_bound[4] = {1e-5, 1e-4, 1e-3, 1e-4};
/* The sensitivities are integrated to the relative tolerance max(rtol, M eps
 * pbar / h) = 2.2e-8 at the default noise margin M = 3e2 (against the
 * differencing's rounding, docs/optimize.md 12.1, 12.4): every one of the
 * 2315 energies of the 100 designs within 1e-5 (at M = 1e3, 7.4e-8, three
 * were not: cases 56 and 70, up to 1.96e-5, while the perturbed models
 * clamped their own voltages; since they follow the nominal's pattern,
 * worst 8.7e-7 at 3e2 and 8.6e-7 at 1e3). */

typedef struct {
  const char *file;
  const char *keys[6];
  double lo[6], hi[6]; /* the design's range, factors of the shipped value */
  double target;       /* the joint targets' half-width (m or rad) */
  const char *unit;    /* the targets' printed unit (1e-3 of the SI one) */
} arch_case;

static const arch_case archs[] = {
    {"3pss.cfg",
     {"actuator.resistance_ohm", "actuator.force_constant_N_per_A", "controller.kp",
      "controller.kd_s", "inertia.link.mass_kg", "geometry.limb_length"},
     {0.8, 0.8, 0.8, 0.8, 0.8, 0.95},
     {1.2, 1.2, 1.2, 1.2, 1.2, 1.05},
     3e-3,
     "mm"},
    {"3sps.cfg",
     {"actuator.resistance_ohm", "actuator.force_constant_N_per_A", "controller.kp",
      "controller.kd_s", "inertia.platform.moments_kgm2[2]", "geometry.platform_radius_mm"},
     /* the axial moment at most the sum of the other two (2.02e-6) */
     {0.8, 0.8, 0.8, 0.8, 0.8, 0.9},
     {1.2, 1.2, 1.2, 1.2, 1.0, 1.1},
     3e-3,
     "mm"},
    /* only with --arch 3rrr.cfg (the default sequence alternates the two
     * above): rotary voice coils on revolute joints. Targets within +-0.2
     * rad: the 3P-S-S/S's +-3 mm through the 15 mm/rad lever its config is
     * scaled by (the same 2.5 V sensor step at 12.5 V/rad, the same platform
     * rotation at the isotropic home's 1 rad/rad), 38 % of the +-30 deg
     * range (the 3 mm: half of the +-6 mm stroke) */
    {"3rrr.cfg",
     {"actuator.resistance_ohm", "actuator.torque_constant_Nm_per_A", "controller.kp",
      "controller.kd_s", "inertia.link_density_kg_m3", "geometry.proximal_angle_deg"},
     {0.8, 0.8, 0.8, 0.8, 0.8, 0.95},
     {1.2, 1.2, 1.2, 1.2, 1.2, 1.05},
     0.2,
     "mrad"},
    /* Catalog architectures (docs/catalog.md; kinematics from the .arch limb
     * tables by jets), only with --arch. The catalog configs carry no
     * montecarlo ranges: the ranges are the 3-RRR's (+-20 % on the drive
     * and the masses, +-5 % on the geometry key the config writes; the
     * .arch defaults are not config keys). C09: rotary voice coils on a
     * radial crank, the 3-RRR's actuator group and the same 15 mm lever
     * (sigma = 1 rad/rad), so the 3-RRR's +-0.2 rad targets (the rotor's
     * range +-30 deg) */
    {"catalog/3rss_radial.cfg",
     {"actuator.resistance_ohm", "actuator.torque_constant_Nm_per_A", "controller.kp",
      "controller.kd_s", "inertia.crank.mass_kg", "geometry.platform_radius_mm"},
     {0.8, 0.8, 0.8, 0.8, 0.8, 0.95},
     {1.2, 1.2, 1.2, 1.2, 1.2, 1.05},
     0.2,
     "mrad"},
    /* C13: the 3-RUU wrist (universal joints, revolute pairs only; the
     * crank an arc body of the .arch); its scale u_radius_mm sets only the
     * bodies' sizes and inertias (the angles fix the kinematics), the link
     * mass its own group's; the 3-RRR's actuator and angles (C03), so the
     * same +-0.2 rad targets */
    {"catalog/3ruu_wrist.cfg",
     {"actuator.resistance_ohm", "actuator.torque_constant_Nm_per_A", "controller.kp",
      "controller.kd_s", "inertia.link.mass_kg", "geometry.u_radius_mm"},
     {0.8, 0.8, 0.8, 0.8, 0.8, 0.95},
     {1.2, 1.2, 1.2, 1.2, 1.2, 1.05},
     0.2,
     "mrad"},
    /* C11: the 3P-S-S/S with inclined pistons, the linear voice coils of
     * configs/3pss.cfg: its +-3 mm targets (half the +-6 mm stroke) */
    {"catalog/3pss_inclined.cfg",
     {"actuator.resistance_ohm", "actuator.force_constant_N_per_A", "controller.kp",
      "controller.kd_s", "inertia.piston.mass_kg", "geometry.platform_radius_mm"},
     {0.8, 0.8, 0.8, 0.8, 0.8, 0.95},
     {1.2, 1.2, 1.2, 1.2, 1.2, 1.05},
     3e-3,
     "mm"},
};
#define N_ARCHS ((int)(sizeof archs / sizeof archs[0]))

/* --verbose: every compared derivative printed, not only those beyond */
static int verbose;

/* The shipped config with rigid joints, rtol RTOL and no wall-clock budget,
 * as a string config. */
static pom_cfg *rigid_config(const char *file) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, file);
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  static char text[1 << 16], out[(1 << 16) + 256];
  size_t n = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[n] = '\0';
  /* the solver group's rtol and the joints group's model, both replaced or
   * added at the group's opening brace */
  out[0] = '\0';
  const char *p = text;
  while (*p) {
    char line[1024];
    const char *t = next_line(&p, line, sizeof line);
    if (strncmp(t, "rtol", 4) == 0 && strchr(t, '=')) {
      /* no wall-clock budget: at a small noise margin a 3S-P-S/S
       * sensitivity run takes over 60 s on a loaded machine (the steps
       * stay bounded by solver.max_steps) */
      strcat(out, "  rtol = " RTOL ";\n  max_wall_s = 0.0;\n");
    } else if (strncmp(t, "model", 5) == 0 && strchr(t, '=') && strstr(t, "parasitic")) {
      strcat(out, "  model = \"rigid\";\n");
    } else {
      strcat(out, line);
      if (strncmp(t, "joints = {", 10) == 0 && !strstr(text, "model = \"rigid\""))
        strcat(out, "  model = \"rigid\";\n");
    }
  }
  pom_cfg *cfg = NULL;
  pom_error err;
  if (pom_cfg_load_string(&cfg, out, path, &err) != POM_OK) {
    printf("  config: %s\n", err.message);
    return NULL;
  }
  return cfg;
}

static int metric_class(int k) {
  if (k <= POM_GRAD_ENERGY_3) return 0;
  if (k == POM_GRAD_FINAL_POINTING_ERROR) return 2;
  if (k == POM_GRAD_PEAK_CURRENT) return 3;
  return 1;
}

/* The reference of case c in the cache PREFIX.c: read (write 0; 0 when
 * absent) or written (write 1; 0 on a write error). No cache: 0 on a read,
 * 1 on a write. */
static int cached_reference(const char *prefix, int c, pom_grad_ref *ref, int write) {
  if (!prefix) return write;
  char path[512];
  snprintf(path, sizeof path, "%s.%d", prefix, c);
  FILE *f = fopen(path, write ? "wb" : "rb");
  if (!f) return 0;
  size_t n = write ? fwrite(ref, sizeof *ref, POM_GRAD_N_METRICS, f)
                   : fread(ref, sizeof *ref, POM_GRAD_N_METRICS, f);
  int ok = fclose(f) == 0 && n == POM_GRAD_N_METRICS;
  if (!ok && write) printf("  reference cache %s: write failed\n", path);
  return ok;
}

/* Whether case c is in the comma-separated list (NULL: every case). */
static int in_list(const char *list, int c) {
  if (!list) return 1;
  for (const char *p = list; *p;) {
    char *end = NULL;
    long v = strtol(p, &end, 10);
    if (end == p) return 0;
    if (v == c) return 1;
    p = *end == ',' ? end + 1 : end;
  }
  return 0;
}

/* What one setting of the sensitivities measured over the cases. */
typedef struct {
  double margin;
  pom_grad *gs[N_ARCHS];
  long compared[4], over[4], kink[4], unresolved[4], undefined[4], ref_undefined, light, light_ref;
  long why[POM_DYN_GRAD_PEAK_KINK + 1];
  double worst[4], worst_ref[4];
  long steps, sens_evals;
} tally;

/* Compares one case's gradients gr (metrics mt) with the reference ref at
 * the design v of architecture a, into t; returns the case's worst energy
 * elasticity error. */
static double compare(tally *t, int a, const double *v, int nk, const pom_dyn_metrics *mt,
                      const pom_dyn_grad *gr, const pom_grad_ref *ref, double shift) {
  double worst_energy = 0.0;
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    if (k == POM_GRAD_TRACKING_RMS_ERROR) continue; /* the PID follows no trajectory */
    const pom_dyn_dmetric *d = pom_grad_metric_grad(gr, (pom_grad_metric)k);
    const char *name = pom_grad_metric_name((pom_grad_metric)k);
    double M = pom_grad_metric_value(mt, (pom_grad_metric)k);
    int cls = metric_class(k);
    if (!d->defined) {
      ++t->undefined[cls];
      ++t->why[d->why];
      continue;
    }
    if (!ref[k].defined) { /* a perturbed run failed or lost the metric: say so */
      printf("  %s: the reference is undefined (a perturbed run failed)\n", name);
      ++t->ref_undefined;
      check_true(0);
      continue;
    }
    const double tol = class_bound[cls];
    for (int j = 0; j < nk; ++j) {
      double s = fabs(v[j]) / fabs(M);
      double sens = d->d[j] + shift / s;
      double e = fabs(sens - ref[k].d[j]) * s, E = ref[k].err[j] * s;
      if (!(E <= REF_SHARE * tol)) {
        if (ref[k].kink[j]) {
          ++t->kink[cls];
          printf("  %s / %s: reference not differentiable at this step (spread %.1e; sens "
                 "%+.6e, D(H/4) %+.6e)\n",
                 name, archs[a].keys[j], E, d->d[j], ref[k].d[j]);
        } else {
          ++t->unresolved[cls];
        }
        continue;
      }
      ++t->compared[cls];
      if (verbose)
        printf("  %s / %s: sens %+.9e ref %+.9e elasticity error %.2e (reference %.1e)\n", name,
               archs[a].keys[j], sens, ref[k].d[j], e, E);
      t->worst[cls] = fmax(t->worst[cls], e);
      if (cls == 0) worst_energy = fmax(worst_energy, e);
      t->worst_ref[cls] = fmax(t->worst_ref[cls], E);
      if (!(e <= tol + E)) {
        ++t->over[cls];
        printf("  %s %s / %s: sens %+.9e ref %+.9e (+- %.1e) elasticity error %.2e > %.0e + "
               "%.1e%s\n",
               "FAIL", name, archs[a].keys[j], sens, ref[k].d[j], ref[k].err[j], e, tol, E,
               ref[k].kink[j] ? " (kink test fired, spread small)" : "");
        check_true(0);
      }
    }
  }
  return worst_energy;
}

static void print_tally(const tally *t, long ran) {
  printf("noise margin %g:\n", t->margin);
  for (int cls = 0; cls < 4; ++cls)
    printf("%-13s bound %.0e: %ld compared, %ld beyond the bound; worst elasticity error %.2e "
           "(reference error <= %.1e); not compared: %ld reference not differentiable at this "
           "step, %ld reference unresolved, %ld gradient undefined\n",
           class_name[cls], class_bound[cls], t->compared[cls], t->over[cls], t->worst[cls],
           t->worst_ref[cls], t->kink[cls], t->unresolved[cls], t->undefined[cls]);
  printf("undefined gradients by reason:");
  for (int w = 1; w <= POM_DYN_GRAD_PEAK_KINK; ++w)
    if (t->why[w]) printf(" %s %ld;", pom_dyn_grad_why_text((pom_dyn_grad_why)w), t->why[w]);
  printf("\nreferences undefined (a perturbed run failed): %ld\n", t->ref_undefined);
  printf("designs not run, their drive mode outside BDF 3's sector (high loop gain): %ld; a "
         "reference design's: %ld\n",
         t->light, t->light_ref);
  printf("sensitivity runs of the %ld cases: %ld steps, %ld sensitivity right-hand sides\n", ran,
         t->steps, t->sens_evals);
}

int main(int argc, char **argv) {
  /* the named options first, then the positional arguments */
  double margin = POM_DYN_SENS_MARGIN_DEFAULT, against = 0.0, rel_step = 0.0, ref_step = REF_STEP;
  const char *list = NULL, *cache = NULL, *arch_file = NULL;
  int dry = 0, error_test = 1;
  char *pos[4] = {argv[0], NULL, NULL, NULL};
  int npos = 1;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--margin") == 0 && i + 1 < argc) {
      margin = atof(argv[++i]);
    } else if (strcmp(argv[i], "--rel-step") == 0 && i + 1 < argc) {
      rel_step = atof(argv[++i]);
    } else if (strcmp(argv[i], "--error-test") == 0 && i + 1 < argc) {
      const char *v = argv[++i];
      if (strcmp(v, "on") != 0 && strcmp(v, "off") != 0) {
        printf("--error-test %s: on or off\n", v);
        return 2;
      }
      error_test = strcmp(v, "on") == 0;
    } else if (strcmp(argv[i], "--dry") == 0) {
      dry = 1;
    } else if (strcmp(argv[i], "--ref-step") == 0 && i + 1 < argc) {
      ref_step = atof(argv[++i]);
    } else if (strcmp(argv[i], "--against") == 0 && i + 1 < argc) {
      against = atof(argv[++i]);
    } else if (strcmp(argv[i], "--cases") == 0 && i + 1 < argc) {
      list = argv[++i];
    } else if (strcmp(argv[i], "--ref-cache") == 0 && i + 1 < argc) {
      cache = argv[++i];
    } else if (strcmp(argv[i], "--verbose") == 0) {
      verbose = 1;
    } else if (strcmp(argv[i], "--arch") == 0 && i + 1 < argc) {
      arch_file = argv[++i];
    } else if (npos < 4) {
      pos[npos++] = argv[i];
    }
  }
  /* --arch FILE: every case on that architecture (the default: the first
   * two alternating, the sequence the 100-design figures were measured on) */
  int only = -1;
  for (int a = 0; a < N_ARCHS && arch_file; ++a)
    if (strcmp(arch_file, archs[a].file) == 0) only = a;
  if (arch_file && only < 0) {
    printf("--arch %s: not one of the test's architectures:", arch_file);
    for (int a = 0; a < N_ARCHS; ++a)
      printf(" %s", archs[a].file);
    printf("\n");
    return 1;
  }
  /* a catalog architecture: its .arch file registered (the shipped
   * catalog/, as pomlab does) before its config is loaded */
  if (only >= 0 && strncmp(archs[only].file, "catalog/", 8) == 0) {
    pom_error err;
    if (pom_arch_files_register_all(&err) != POM_OK) {
      printf("architecture files: %s\n", err.message);
      return 1;
    }
  }
  int cases = npos > 1 ? atoi(pos[1]) : 10;
  double shift = npos > 2 ? atof(pos[2]) : 0.0;
  int first = npos > 3 ? atoi(pos[3]) : 0;
  setvbuf(stdout, NULL, _IOLBF, 0); /* a long run's progress as it goes */
  /* the long run (9 min on 2 cores) only when asked, as test_docs_long */
  const char *lg = getenv("POMLAB_LONG"), *dl = getenv("POMLAB_DOCS_LONG");
  int to_run = 0;
  for (int c = first > 0 ? first : 0; c < cases; ++c)
    to_run += in_list(list, c);
  if (to_run > 10 && !(lg && strcmp(lg, "1") == 0) && !(dl && strcmp(dl, "1") == 0)) {
    printf("skipped: %d cases run with POMLAB_LONG=1\n", to_run);
    return 77;
  }
  pom_rng rng;
  pom_rng_seed(&rng, 20261129, 29);
  /* the setting under test, and with --against the other margin */
  tally tl[2];
  memset(tl, 0, sizeof tl);
  tl[0].margin = margin;
  tl[1].margin = against;
  const int ns = against > 0.0 ? 2 : 1;
  long ran = 0;
  int nk = 6;
  for (int t = 0; t < ns; ++t) {
    pom_grad_options opt;
    pom_grad_options_defaults(&opt);
    opt.sens_noise_margin = tl[t].margin;
    if (rel_step > 0.0) opt.rel_step = rel_step;
    opt.error_control = error_test;
    for (int a = 0; a < N_ARCHS; ++a) {
      if (only >= 0 ? a != only : a >= 2) continue;
      pom_cfg *cfg = rigid_config(archs[a].file);
      check_true(cfg != NULL);
      if (!cfg) return check_summary("test_grad_random");
      pom_error err;
      pom_status st = pom_grad_create(&tl[t].gs[a], cfg, archs[a].keys, nk, &opt, &err);
      if (st != POM_OK) printf("  create: %s\n", err.message);
      check_true(st == POM_OK);
      pom_cfg_destroy(cfg);
      if (st != POM_OK) return check_summary("test_grad_random");
    }
  }
  double nominal[N_ARCHS][6];
  for (int a = 0; a < N_ARCHS; ++a)
    for (int j = 0; j < nk; ++j)
      nominal[a][j] = tl[0].gs[a] ? pom_grad_value(tl[0].gs[a], j) : 0.0;
  for (int c = 0; c < cases; ++c) {
    int a = only >= 0 ? only : c % 2;
    double v[6], q[3];
    for (int j = 0; j < nk; ++j)
      v[j] = nominal[a][j] *
             (archs[a].lo[j] + (archs[a].hi[j] - archs[a].lo[j]) * pom_rng_uniform(&rng));
    for (int i = 0; i < 3; ++i)
      q[i] = archs[a].target * (2.0 * pom_rng_uniform(&rng) - 1.0);
    pom_error err;
    if (c < first || !in_list(list, c)) continue;
    pom_dyn_metrics mt[2], m0;
    pom_dyn_grad gr[2];
    int ok = 1;
    for (int t = 0; t < ns && ok; ++t)
      if (pom_grad_set_values(tl[t].gs[a], v, &err) != POM_OK) {
        printf("case %d: design refused: %s\n", c, err.message);
        ok = 0;
      }
    /* A design whose drive mode lies outside BDF 3's sector (damping ratio
     * below 0.070, docs/dynamics.md 7 "Order and stability") is integrated
     * at order 2, which at rtol 1e-12 needs steps of ~1e-8 s: its plain run
     * stops at solver.max_steps (measured: 3-RRR case 1, K_P +13 %, K_t
     * +13 %, R_c -18 %: 200000 steps at t = 2.8 ms). Only the 3-RRR's draws
     * reach it (its shipped mode at 85.3 deg, the linear designs' at 80 deg):
     * counted and printed, never compared. */
    double wd = 0.0, zd = 0.0;
    if (ok && pom_dyn_drive_mode_light(pom_grad_model(tl[0].gs[a]), &wd, &zd)) {
      printf("case %3d %s: not run: the drive mode rings at %.3g rad/s, damping ratio %.3g "
             "(below 0.070)\n",
             c, archs[a].file, wd, zd);
      for (int t = 0; t < ns; ++t)
        ++tl[t].light;
      continue;
    }
    /* The same for the reference's designs v +- h e_j (h = H, H/2, H/4): a
     * design next to the sector's edge has perturbed designs beyond it,
     * whose runs stop at solver.max_steps (measured: catalog/3rss_radial.cfg
     * case 180, every reference undefined). Not run either, printed. */
    int edge = -1;
    for (int j = 0; j < nk && ok && edge < 0; ++j)
      for (int s = 0; s < 6 && edge < 0; ++s) {
        double w[6];
        memcpy(w, v, sizeof w);
        w[j] += (s % 2 ? -1.0 : 1.0) * ref_step * fabs(v[j]) / (double)(1 << (s / 2));
        if (pom_grad_set_values(tl[0].gs[a], w, &err) != POM_OK) {
          printf("case %d: design refused: %s\n", c, err.message);
          ok = 0;
        } else if (pom_dyn_drive_mode_light(pom_grad_model(tl[0].gs[a]), &wd, &zd)) {
          edge = j;
        }
      }
    if (ok && pom_grad_set_values(tl[0].gs[a], v, &err) != POM_OK) ok = 0;
    if (ok && edge >= 0) {
      printf("case %3d %s: not run: a reference design (%s moved) rings at %.3g rad/s, damping "
             "ratio %.3g (below 0.070)\n",
             c, archs[a].file, archs[a].keys[edge], wd, zd);
      for (int t = 0; t < ns; ++t)
        ++tl[t].light_ref;
      continue;
    }
    if (dry) {
      printf("case %3d %s: runs\n", c, archs[a].file);
      continue;
    }
    ++ran;
    if (ok && zd > 0.0) printf("case %3d: drive mode damping ratio %.3g\n", c, zd);
    for (int t = 0; t < ns && ok; ++t)
      if (pom_grad_maneuver_joint(tl[t].gs[a], q, &mt[t], &gr[t], &err) != POM_OK) {
        printf("case %d (%s): maneuver failed: %s\n", c, archs[a].file, mt[t].reason);
        ok = 0;
      }
    check_true(ok);
    if (!ok) continue;
    double H[6], run_error[POM_GRAD_N_METRICS];
    for (int j = 0; j < nk; ++j)
      H[j] = ref_step * fabs(v[j]);
    for (int k = 0; k < POM_GRAD_N_METRICS; ++k)
      run_error[k] = class_run_error[metric_class(k)];
    pom_grad_ref ref[POM_GRAD_N_METRICS];
    if (!cached_reference(cache, c, ref, 0)) {
      check_true(pom_grad_reference(tl[0].gs[a], q, NULL, H, run_error, &m0, ref, &err) == POM_OK &&
                 cached_reference(cache, c, ref, 1));
      printf("case %3d: the plain run %ld steps\n", c, m0.steps);
    }
    for (int t = 0; t < ns; ++t) {
      printf("case %3d %s q (%+.3f, %+.3f, %+.3f) %s, margin %g: %ld steps, %ld sensitivity "
             "right-hand sides, %ld restarts (%ld resyncs)\n",
             c, archs[a].file, q[0] * 1e3, q[1] * 1e3, q[2] * 1e3, archs[a].unit, tl[t].margin,
             mt[t].steps, gr[t].sens_rhs_evals, gr[t].restarts, gr[t].resyncs);
      tl[t].steps += mt[t].steps;
      tl[t].sens_evals += gr[t].sens_rhs_evals;
      double we = compare(&tl[t], a, v, nk, &mt[t], &gr[t], ref, shift);
      printf("  margin %g: worst energy elasticity error %.2e\n", tl[t].margin, we);
    }
  }
  for (int t = 0; t < ns; ++t)
    print_tally(&tl[t], ran);
  const tally *t0 = &tl[0];
  /* the comparison must have happened: a case run (not every design's
   * drive mode outside BDF 3's sector), most derivatives compared */
  check_true(ran > 0);
  check_true(t0->compared[0] >= ran * 4 * nk * 3 / 4);
  check_true(t0->compared[1] >= ran * nk);
  /* the peak current: 222 of 600 on the 100 designs (56 near a corner);
   * over a few cases only, all maxima may lie at corners; on C09 (a
   * rotary drive near BDF 3's sector edge, 16 designs run of 600) 21 of
   * 96, 12 on a kink of the current: at least a fifth, not a quarter */
  if (ran >= 10) check_true(t0->compared[3] >= ran * nk / 5);
  if (ns == 2) {
    /* both margins were held to the bounds above (compare); the energies'
     * worst errors side by side */
    printf("energies: worst elasticity error %.2e at margin %g, %.2e at %g\n", t0->worst[0],
           t0->margin, tl[1].worst[0], tl[1].margin);
    check_true(tl[1].compared[0] >= ran * 4 * nk * 3 / 4);
  }
  for (int t = 0; t < ns; ++t)
    for (int a = 0; a < N_ARCHS; ++a)
      pom_grad_destroy(tl[t].gs[a]);
  return check_summary("test_grad_random");
}
