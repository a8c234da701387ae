/* test_serial_sing.c - the pose's serial bit on limbs whose two IK roots meet
 * (docs/kinematics-tables.md 3.2): the hand-coded 3P-S-S/S, its table twin
 * (catalog/3pss.arch) and the 3-RSS/S radial and tangential cranks
 * (configs/catalog/3rss_*.cfg, tables).
 *
 * configs/3pss.cfg itself has no serial singularity anywhere in SO(3): its
 * platform points stay within 2.81 r_c of their vertical slider lines, and
 * the rod is L = 3.27 r_c long, so |l . a| = sqrt(L^2 - |d_perp|^2) > 0
 * (measured below: the edge search finds no edge). The test therefore also
 * runs it with limb_length = 1.5 (L = 1.5 r_c < 2 r_c, the largest distance
 * of a platform point from its slider line), hand-coded and table.
 *
 * A P-S-S limb is singular where its rod is perpendicular to the slider axis
 * (l . a = 0), an R-S-S limb where its rod is perpendicular to the crank
 * point's velocity a x arm (rod and crank in one plane with the axis: folded
 * or stretched). Both are folds: the limb's two IK roots meet there, past it
 * the limb cannot be assembled. So the edge of the reachable set along a path
 * from home is such a singularity of the limb that fails. The test
 *  1. walks from home along 12 fixed rotation axes, finds the edge by
 *     bisection (to ~1e-16 rad) and evaluates the pose delta inside it:
 *     - the transmission of the failing limb vanishes like sqrt(delta)
 *       (lambda^2 / delta the same at delta = 1e-8 and 1e-10 to 1e-2): the
 *       fold law behind POM_KIN_SERIAL_TOL = sqrt(POM_KIN_SING_TOL);
 *     - the serial bit is set at delta = 1e-10 and 1e-12 and names that limb
 *       (serial_limbs = the limbs whose transmission is <= the tolerance,
 *       which contains it); it is clear at delta = 1e-3;
 *  2. at 2000 random reachable poses (Euler angles within +-30 deg) the bit
 *     is clear; on the P-S-S limbs the transmission is the root gap over the
 *     rod length, |q+ - q-| / (2 L) (a property of the quadratic,
 *     independent of the limb op's formula): the ratio |q+ - q-| / lambda is
 *     one constant per limb to 1e-9. */
#include "check.h"
#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"
#include "catalog_test_util.h" /* after pom_kinematics.h */

#include <math.h>
#include <stdio.h>
#include <string.h>

static int verbose = 0;

/* arch with its design parameter `key` set to value (rebuilt from the design) */
static int with_param(pom_kin_arch *a, const char *key, double value) {
  const pom_kin_arch_type *t = a->type;
  for (int k = 0; k < t->n_params; ++k)
    if (!strcmp(t->params[k].key, key)) {
      pom_kin_design d = a->design;
      d.x[k] = value * t->params[k].to_si;
      pom_error err;
      pom_error_clear(&err);
      if (pom_kin_arch_from_design(a, t, &d, &err) == POM_OK) return 1;
      printf("%s = %g: %s\n", key, value, err.message);
      return 0;
    }
  printf("%s: no parameter %s\n", t->name, key);
  return 0;
}

static void rotvec(double R[9], const double axis[3], double t) {
  pom_m3_axis_angle(R, axis, t);
}

static int reachable(const pom_kin_arch *a, const double axis[3], double t, int *bad) {
  double R[9];
  pom_kin_pose p;
  rotvec(R, axis, t);
  pom_kin_pose_evaluate(a, R, &p, NULL);
  if (bad) *bad = p.unreachable_limb;
  return p.reachable;
}

/* 1. the edge of the reachable set along 12 axes */
static void edges(const char *label, const pom_kin_arch *a, int min_edges) {
  int n_edges = 0, set_ok = 1, clear_ok = 1, names_ok = 1, n_par = 0, n_par10 = 0;
  double worst_law = 0.0, lam_min = INFINITY, lam_max = 0.0;
  for (int e = 0; e < 12; ++e) {
    /* axes off the 3-fold symmetry (no two limbs fold at once) */
    const double az = (e * 30.0 + 7.0) * POM_DEG, el = (e % 3 - 1) * 35.0 * POM_DEG + 11 * POM_DEG;
    double axis[3] = {cos(el) * cos(az), cos(el) * sin(az), sin(el)};
    double lo = 0.0, hi = -1.0;
    for (double t = 0.01; t <= POM_PI; t += 0.01)
      if (!reachable(a, axis, t, NULL)) {
        hi = t;
        break;
      }
    if (hi < 0.0) continue; /* reachable all the way round this axis */
    lo = hi - 0.01;
    for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
      double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      if (reachable(a, axis, mid, NULL))
        lo = mid;
      else
        hi = mid;
    }
    int bad = -1;
    reachable(a, axis, hi, &bad);
    if (bad < 0) continue;
    ++n_edges;
    const double ds[4] = {1e-3, 1e-8, 1e-10, 1e-12};
    double lam[4];
    for (int m = 0; m < 4; ++m) {
      double R[9];
      pom_kin_pose p;
      rotvec(R, axis, lo - ds[m]);
      pom_kin_pose_evaluate(a, R, &p, NULL);
      lam[m] = p.reachable ? p.transmission[bad] : NAN;
      unsigned expect = 0;
      for (int i = 0; i < 3; ++i)
        if (p.reachable && p.transmission[i] <= POM_KIN_SERIAL_TOL) expect |= 1u << i;
      const int ser = (p.singular & POM_KIN_SING_SERIAL) != 0;
      if (!p.reachable || p.serial_limbs != expect) names_ok = 0;
      if (m == 0 && ser) clear_ok = 0;
      if (m >= 2 && !(ser && (p.serial_limbs >> bad & 1u))) set_ok = 0;
      if (m >= 2 && (p.singular & POM_KIN_SING_PARALLEL)) ++n_par;
      if (m == 2 && (p.singular & POM_KIN_SING_PARALLEL)) ++n_par10;
      if (verbose)
        printf("%s axis %d: edge at %.6f rad (limb %d), delta %.0e: transmission %.3g %.3g %.3g, "
               "serial limbs %u, bits %d, dexterity %.3g\n",
               label, e, lo, bad + 1, ds[m], p.transmission[0], p.transmission[1],
               p.transmission[2], p.serial_limbs, p.singular, p.dexterity);
    }
    /* the fold law: lambda^2 / delta constant */
    worst_law = fmax(worst_law, fabs(lam[2] * lam[2] / ds[2] / (lam[1] * lam[1] / ds[1]) - 1.0));
    lam_min = fmin(lam_min, lam[2]);
    lam_max = fmax(lam_max, lam[2]);
  }
  printf("%s: %d edges of 12 axes; lambda^2 / delta at 1e-10 over that at 1e-8 - 1: worst %.2g; "
         "lambda at delta = 1e-10: %.3g .. %.3g; serial bit set at 1e-10, 1e-12 on the failing "
         "limb: %s, clear at 1e-3: %s, serial_limbs = {lambda <= tol}: %s; parallel bit also set "
         "at %d of the %d poses at 1e-10, 1e-12\n",
         label, n_edges, worst_law, lam_min, lam_max, set_ok ? "yes" : "NO",
         clear_ok ? "yes" : "NO", names_ok ? "yes" : "NO", n_par, 2 * n_edges);
  check_true(n_edges >= min_edges);
  check_true(worst_law <= 1e-2);
  check_true(set_ok && clear_ok && names_ok);
  /* beside a fold the failing limb's row grows like 1/lambda, so J's
   * dexterity falls like lambda ~ sqrt(delta): about 1e-6 at delta = 1e-10,
   * where the parallel bit (dexterity <= 1e-7, measured accurately) must be
   * clear; at 1e-12 it may reach 1e-7 (docs/kinematics-modes.md 6.5) */
  check_true(n_par10 == 0);
}

/* 2. random reachable poses: the bit clear; on P-S-S limbs lambda = |q+ - q-| / (2 L) */
static void generic(const char *label, const pom_kin_arch *a, int pss) {
  pom_rng rng;
  pom_rng_seed(&rng, 27, 0);
  int used = 0, n_serial = 0;
  double min_lam = INFINITY, ratio0[3] = {0.0, 0.0, 0.0}, worst_ratio = 0.0;
  for (int tries = 0; used < 2000 && tries < 20000; ++tries) {
    double e[3], R[9];
    for (int k = 0; k < 3; ++k)
      e[k] = pom_rng_range(&rng, -30.0, 30.0) * POM_DEG;
    pom_euler_zyx_to_matrix(R, e);
    pom_kin_pose p;
    pom_kin_pose_evaluate(a, R, &p, NULL);
    if (!p.reachable) continue;
    ++used;
    n_serial += (p.singular & POM_KIN_SING_SERIAL) != 0;
    for (int i = 0; i < 3; ++i) {
      min_lam = fmin(min_lam, p.transmission[i]);
      if (!pss) continue;
      pom_kin_arch other = *a;
      double qo;
      if (!check_true(a->type->flip_branch(&other, i) &&
                      other.type->limb(&other, i, R, &qo, NULL, NULL)))
        continue;
      const double ratio = fabs(qo - p.q[i]) / p.transmission[i]; /* 2 L */
      if (ratio0[i] == 0.0) ratio0[i] = ratio;
      worst_ratio = fmax(worst_ratio, fabs(ratio / ratio0[i] - 1.0));
    }
  }
  printf("%s: %d random reachable poses: serial bit on %d, smallest transmission %.3g", label, used,
         n_serial, min_lam);
  if (pss)
    printf("; |q+ - q-| / transmission = %.6g %.6g %.6g mm (2 L) to %.2g", ratio0[0] * 1e3,
           ratio0[1] * 1e3, ratio0[2] * 1e3, worst_ratio);
  printf("\n");
  check_true(used == 2000);
  check_true(n_serial == 0 && min_lam > POM_KIN_SERIAL_TOL);
  if (pss) check_true(worst_ratio <= 1e-9);
}

int main(int argc, char **argv) {
  verbose = argc > 1 && !strcmp(argv[1], "-v");
  pom_error err;
  pom_error_clear(&err);
  if (pom_arch_files_register_all(&err) != POM_OK) {
    printf("%s\n", err.message);
    return 1;
  }
  /* short: limb_length = 1.5 (0 = as configured); min_edges: 0 where no
   * edge exists (configs/3pss.cfg as shipped) */
  static const struct {
    const char *cfg, *arch, *label;
    int pss, short_link, min_edges;
  } cases[] = {
      {"configs/3pss.cfg", NULL, "3P-S-S/S hand-coded, as shipped", 1, 0, 0},
      {"configs/3pss.cfg", NULL, "3P-S-S/S hand-coded, L = 1.5 r_c", 1, 1, 6},
      {"configs/3pss.cfg", "3PSS-table", "3P-S-S/S table, L = 1.5 r_c", 1, 1, 6},
      {"configs/catalog/3rss_radial.cfg", NULL, "3-RSS/S radial (table)", 0, 0, 6},
      {"configs/catalog/3rss_tangential.cfg", NULL, "3-RSS/S tangential (table)", 0, 0, 6}};
  /* the report's text names the serial limbs */
  char sb[80];
  check_true(
      !strcmp(pom_kin_singular_text(POM_KIN_SING_SERIAL, 2u, sb, sizeof sb), "serial (limb 2)"));
  check_true(
      !strcmp(pom_kin_singular_text(POM_KIN_SING_SERIAL | POM_KIN_SING_PARALLEL, 5u, sb, sizeof sb),
              "serial (limbs 1, 3), parallel"));
  check_true(!strcmp(
      pom_kin_singular_text(POM_KIN_SING_SERIAL | POM_KIN_SING_CONSTRAINT, 0u, sb, sizeof sb),
      "serial, constraint"));
  check_true(!strcmp(pom_kin_singular_text(0, 0u, sb, sizeof sb), "none"));
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    pom_kin_arch a;
    if (!check_true(load_config_arch(cases[c].cfg, cases[c].arch, &a))) continue;
    if (cases[c].short_link && !check_true(with_param(&a, "limb_length", 1.5))) continue;
    edges(cases[c].label, &a, cases[c].min_edges);
    generic(cases[c].label, &a, cases[c].pss);
  }
  return check_summary("test_serial_sing");
}
