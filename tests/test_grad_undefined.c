/* test_grad_undefined.c - settling times whose derivative does not exist
 * are reported undefined with their reason, never as a number (issue 29
 * item 1; docs/optimize.md 12.2 "Where a settling time's derivative is
 * undefined"; dynamics/dyn_sens.c settling_grad).
 *
 * 1. Grazing. configs/3pss.cfg with rigid joints, rtol 1e-10 and a small
 *    derivative time (tau_D = 2e-4 s: the PID rings, |q_a - q_set| has a
 *    train of decaying peaks), one Monte-Carlo maneuver (seed SEED, the
 *    target the CLI draws too). How the case is found (at run time, not
 *    hard-coded): a plain run of the nominal model traced every 1 us gives
 *    e_a(t) = |q_a - q_set,a| / |q_set,a|; its local maxima, each refined by
 *    the parabola through the three samples about it, are the peaks. For the
 *    actuator with the largest steps the test takes the last peak P at or
 *    above 0.5 % whose every earlier peak is above 1.1 P and after which e
 *    stays below 0.9 P. With the settling band at P (1 + delta) (the band
 *    does not move the dynamics: maneuver.settle_band_percent only places
 *    the band) the last crossing into the band is before that peak and the
 *    peak is the band function's later local maximum, g = P - b = -delta/(1
 *    + delta) b below the edge:
 *    - delta = 5e-4 (within the engine's margin POM_DYN_GRAD_GRAZE_MARGIN =
 *      1e-3 of the band): the settling time's derivative must be undefined,
 *      POM_DYN_GRAD_GRAZING; `pomlab gradient` must print "undefined:
 *      grazing band crossing" on its row, and --json null with the reason;
 *    - delta = 3e-3 (three margins below the edge): it must be defined (the
 *      rule is not "always undefined");
 *    - that undefined is right: whole-run differences of the settling time
 *      at +-DH |K_P| jump by a sizeable part of the ringing's half period at
 *      delta = 5e-4 (a perturbation lifts the peak over the edge and the last
 *      crossing moves behind it), and at delta = 3e-3 they do not.
 * 2. Settled from the start: a target component of 0 (that actuator at home:
 *    no band) must give POM_DYN_GRAD_SETTLED_AT_START for that actuator's
 *    settling time while the others are defined; the zero target for every
 *    actuator and for the execution time; and the JSON writes null with the
 *    reason "settled from the start". The band at its widest, 100 % of the
 *    step (every actuator starts on the band's edge): no settling time has
 *    a derivative (settled from the start, or grazing: a crossing at t ~ 0
 *    from rest where rounding put the home pose a hair outside).
 *
 * argv[1]: the pomlab executable; argv[2]: a folder for the config file the
 * CLI reads. */
#define _POSIX_C_SOURCE 200809L /* popen */
#include "check.h"
#include "grad_test_util.h"
#include "pom_grad.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SEED 29

#define NK 2
static const char *const keys[NK] = {"controller.kp", "actuator.resistance_ohm"};

/* the relative steps of the whole-run differences that probe the jump (at
 * the grazing band) and the smooth change (at the other) */
static const double DH[4] = {1e-3, 1e-4, 1e-4, 1e-5};

/* configs/3pss.cfg with rigid joints, rtol 1e-10, no wall-clock budget,
 * tau_D = 2e-4 s, the settling band (percent) and the trace every 1 us, and
 * one Monte-Carlo maneuver, as text into out. */
static int config_text(char *out, size_t cap, double band_percent) {
  char path[512];
  static char text[1 << 16];
  if (!shipped_text("3pss.cfg", text, sizeof text, path)) return 0;
  out[0] = '\0';
  size_t used = 0;
  for (const char *p = text; *p;) {
    char line[1024];
    const char *t = next_line(&p, line, sizeof line);
    char rep[256];
    if (strncmp(t, "rtol", 4) == 0 && strchr(t, '='))
      snprintf(rep, sizeof rep, "  rtol = 1e-10;\n  max_wall_s = 0.0;\n");
    else if (strncmp(t, "kd_s", 4) == 0 && strchr(t, '='))
      snprintf(rep, sizeof rep, "  kd_s = 2.0e-4;\n");
    else if (strncmp(t, "settle_band_percent", 19) == 0)
      snprintf(rep, sizeof rep, "  settle_band_percent = %.17g;\n", band_percent);
    else if (strncmp(t, "output_dt_ms", 12) == 0)
      snprintf(rep, sizeof rep, "  output_dt_ms = 0.001;\n");
    else if (strncmp(t, "joints = {", 10) == 0)
      snprintf(rep, sizeof rep, "%s  model = \"rigid\";\n", line);
    else
      snprintf(rep, sizeof rep, "%s", line);
    size_t l = strlen(rep);
    if (used + l + 1 >= cap) return 0;
    memcpy(out + used, rep, l + 1);
    used += l;
  }
  const char *mc =
      "montecarlo = {\n  maneuvers = 1;\n  seed = "
      "29"
      ";\n  space = \"joint\";\n  distribution = \"uniform\";\n  range_mm = 3.0;\n};\n";
  if (used + strlen(mc) + 1 >= cap) return 0;
  strcat(out, mc);
  return 1;
}

static pom_grad *make_grad(double band_percent) {
  static char text[(1 << 16) + 1024];
  if (!config_text(text, sizeof text, band_percent)) return NULL;
  char path[512];
  snprintf(path, sizeof path, "%s/configs/3pss.cfg", POM_SOURCE_DIR);
  pom_cfg *cfg = NULL;
  pom_error err;
  if (pom_cfg_load_string(&cfg, text, path, &err) != POM_OK) {
    printf("config: %s\n", err.message);
    return NULL;
  }
  pom_grad *g = NULL;
  pom_status st = pom_grad_create(&g, cfg, keys, NK, NULL, &err);
  if (st != POM_OK) printf("create: %s\n", err.message);
  pom_cfg_destroy(cfg);
  return st == POM_OK ? g : NULL;
}

/* The config's one Monte-Carlo maneuver with gradients; 0 on failure. */
static int one_maneuver(pom_grad *g, pom_dyn_metrics *mt, pom_dyn_grad *gr) {
  pom_grad_mc_result r;
  pom_error err;
  if (pom_grad_montecarlo(g, NULL, &r, &err) != POM_OK) {
    printf("montecarlo: %s\n", err.message);
    return 0;
  }
  int ok = r.n == 1 && r.metrics[0].status == POM_OK;
  if (ok) {
    *mt = r.metrics[0];
    *gr = r.grads[0];
  }
  pom_grad_mc_free(&r);
  return ok;
}

/* The grazing peak of a traced run: actuator *act, peak P (fraction of the
 * step) and its time; 0 when no actuator has one. */
static int grazing_peak(pom_grad *g, const double q[3], int *act, double *P, double *tp) {
  const pom_dyn_model *m = pom_grad_model(g);
  pom_dyn_data *d = NULL;
  pom_dyn_trace *tr = NULL;
  pom_error err;
  pom_dyn_metrics mt;
  int found = 0;
  if (pom_dyn_data_create(&d, m, &err) != POM_OK || pom_dyn_trace_create(&tr, m, &err) != POM_OK ||
      pom_dyn_simulate(m, d, q, &mt, tr, &err) != POM_OK) {
    printf("traced run: %s\n", err.message);
    goto done;
  }
  /* the actuators by the size of their step, largest first */
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 3; ++i)
    for (int k = i + 1; k < 3; ++k)
      if (fabs(q[order[k]]) > fabs(q[order[i]])) {
        int x = order[i];
        order[i] = order[k];
        order[k] = x;
      }
  for (int oi = 0; oi < 3 && !found; ++oi) {
    const int a = order[oi];
    if (fabs(q[a]) < 5e-4) continue;
    double pk[256], pt[256];
    int np = 0;
    for (int i = 1; i + 1 < tr->n && np < 256; ++i) {
      double e0 = fabs(tr->q[3 * (i - 1) + a] - q[a]), e1 = fabs(tr->q[3 * i + a] - q[a]),
             e2 = fabs(tr->q[3 * (i + 1) + a] - q[a]);
      if (!(e1 > e0 && e1 >= e2)) continue;
      /* the parabola through the three samples: its vertex */
      double den = e0 - 2.0 * e1 + e2, x = den < 0.0 ? 0.5 * (e0 - e2) / den : 0.0;
      pk[np] = (e1 - 0.25 * (e0 - e2) * x) / fabs(q[a]);
      pt[np++] = tr->t[i] + x * (tr->t[i + 1] - tr->t[i]);
    }
    printf("actuator %d, %d peaks:", a + 1, np);
    for (int i = 0; i < np && i < 12; ++i)
      printf(" %.3f ms %.6f", pt[i] * 1e3, pk[i]);
    printf("\n");
    for (int k = np - 1; k >= 0 && !found; --k) {
      if (pk[k] < 5e-3) continue;
      int ok = 1;
      for (int i = 0; i < k; ++i)
        ok &= pk[i] > 1.1 * pk[k];
      for (int i = k + 1; i < np; ++i)
        ok &= pk[i] < 0.9 * pk[k];
      ok &= fabs(tr->q[3 * (tr->n - 1) + a] - q[a]) < 0.9 * pk[k] * fabs(q[a]);
      if (!ok) break; /* the last peak above 0.5 % must be the one */
      *act = a;
      *P = pk[k];
      *tp = pt[k];
      found = 1;
      printf("actuator %d: peaks of |q - q_set| / |q_set| at", a + 1);
      for (int i = 0; i <= k; ++i)
        printf(" %.3f ms %.6f%s", pt[i] * 1e3, pk[i], i < k ? "," : "");
      printf(" (the grazing peak: the last)\n");
    }
  }
done:
  pom_dyn_trace_destroy(tr);
  pom_dyn_data_destroy(d);
  return found;
}

/* Runs the CLI on the config at band_percent; 1 when its text row of
 * settling_time_N says "undefined: grazing band crossing" and its JSON has
 * the gradient null with that reason. */
static int cli_grazing(const char *pomlab, const char *dir, double band_percent, int act) {
  static char text[(1 << 16) + 1024];
  char cfg[600], cmd[2048], name[64], want_null[96], want_why[128];
  snprintf(cfg, sizeof cfg, "%s/grazing.cfg", dir);
  FILE *f = fopen(cfg, "wb");
  if (!f || !config_text(text, sizeof text, band_percent)) {
    if (f) fclose(f);
    printf("cannot write %s\n", cfg);
    return 0;
  }
  int wrote = fputs(text, f) >= 0;
  if (fclose(f) != 0 || !wrote) {
    printf("cannot write %s\n", cfg);
    return 0;
  }
  snprintf(name, sizeof name, "settling_time_%d", act + 1);
  int text_ok = 0, null_ok = 0, why_ok = 0;
  for (int json = 0; json < 2; ++json) {
    snprintf(cmd, sizeof cmd, "'%s' gradient '%s' --params %s,%s%s", pomlab, cfg, keys[0], keys[1],
             json ? " --json" : "");
    FILE *p = popen(cmd, "r");
    if (!p) return 0;
    static char outbuf[1 << 16];
    size_t n = fread(outbuf, 1, sizeof outbuf - 1, p);
    outbuf[n] = '\0';
    int rc = pclose(p);
    check_true(rc == 0);
    if (!json) {
      /* the row of the maneuver's table: "  settling_time_N   value s   undefined: ..." */
      const char *row = strstr(outbuf, "\nmaneuver 1:");
      row = row ? strstr(row, name) : NULL;
      const char *eol = row ? strchr(row, '\n') : NULL;
      if (row && eol) {
        char line[512];
        snprintf(line, sizeof line, "%.*s", (int)(eol - row), row);
        printf("pomlab gradient: %s\n", line);
        text_ok = strstr(line, "undefined: grazing band crossing") != NULL;
      }
    } else {
      snprintf(want_null, sizeof want_null, "\"%s\": null", name);
      snprintf(want_why, sizeof want_why, "\"%s\": \"grazing band crossing\"", name);
      const char *grad = strstr(outbuf, "\"gradient\": {");
      const char *und = strstr(outbuf, "\"undefined\": {");
      null_ok = grad && und && strstr(grad, want_null) && strstr(grad, want_null) < und;
      why_ok = und && strstr(und, want_why) != NULL;
      printf("pomlab gradient --json: %s in the gradient: %s; reason: %s\n", want_null,
             null_ok ? "yes" : "no", why_ok ? "yes" : "no");
    }
  }
  return text_ok && null_ok && why_ok;
}

static void grazing(const char *pomlab, const char *dir) {
  pom_grad *g = make_grad(2.0);
  check_true(g != NULL);
  if (!g) return;
  pom_dyn_metrics mt;
  pom_dyn_grad gr;
  check_true(one_maneuver(g, &mt, &gr));
  const double *q = mt.target;
  printf("the maneuver (seed %d): target (%+.4f, %+.4f, %+.4f) mm\n", SEED, q[0] * 1e3, q[1] * 1e3,
         q[2] * 1e3);
  int a = -1;
  double P = 0.0, tp = 0.0;
  check_true(grazing_peak(g, q, &a, &P, &tp));
  pom_grad_destroy(g);
  if (a < 0) return;
  static const double deltas[4] = {5e-4, 3e-3, -5e-4, -3e-3};
  double jump[4] = {0.0, 0.0, 0.0, 0.0}, gap = 0.0;
  for (int c = 0; c < 4; ++c) {
    const double band = 100.0 * P * (1.0 + deltas[c]);
    g = make_grad(band);
    check_true(g != NULL);
    if (!g) return;
    check_true(one_maneuver(g, &mt, &gr));
    const pom_dyn_dmetric *d = &gr.settling_time[a];
    printf("band %.9f %% (the peak %+.0e of the band from its edge): settling time %d %.6f ms "
           "(the peak at %.6f ms), crossing rate %.4g /s: ",
           band, -deltas[c], a + 1, mt.settling_time[a] * 1e3, tp * 1e3, gr.crossing_rate[a]);
    if (d->defined)
      printf("d/d K_P %+.6e s, d/d R_c %+.6e s/ohm\n", d->d[0], d->d[1]);
    else
      printf("undefined: %s\n", pom_dyn_grad_why_text(d->why));
    /* the crossing is before the peak, or (the peak above the edge) just after it */
    check_true(mt.settled[a] && (c < 2 ? mt.settling_time[a] < tp : mt.settling_time[a] > tp));
    if (c == 0) gap = tp - mt.settling_time[a];
    if (c % 2 == 0) {
      check_true(!d->defined && d->why == POM_DYN_GRAD_GRAZING);
      check_true(isnan(d->d[0]) && isnan(d->d[1]));
    } else {
      check_true(d->defined && isfinite(d->d[0]) && isfinite(d->d[1]));
    }
    /* the whole-run differences of the settling time along K_P */
    double dh[NK] = {DH[c] * fabs(pom_grad_value(g, 0)), DH[c] * fabs(pom_grad_value(g, 1))};
    pom_dyn_metrics m0;
    pom_dyn_grad fd;
    pom_error err;
    check_true(pom_grad_fd_maneuver(g, q, NULL, dh, &m0, &fd, &err) == POM_OK);
    for (int j = 0; j < NK; ++j)
      printf("  whole-run t*(p + h) - t*(p - h) at h = %.0e |p|, p = %s: %.6f ms\n", DH[c], keys[j],
             fd.settling_time[a].defined ? fd.settling_time[a].d[j] * 2.0 * dh[j] * 1e3 : NAN);
    check_true(fd.settling_time[a].defined);
    jump[c] = fabs(fd.settling_time[a].d[1]) * 2.0 * dh[1];
    /* defined: the whole-run difference is the derivative (1 % for the
     * differences' integration error at rtol 1e-10 over 2e-4 |R_c|) */
    if (c % 2 == 1) check_rel(fd.settling_time[a].d[1], d->d[1], 1e-2);
    if (c == 0) check_true(cli_grazing(pomlab, dir, band, a));
    pom_grad_destroy(g);
  }
  /* at the grazing bands the time jumps across the peak within +-1e-3 |R_c|
   * below the edge and +-1e-4 |R_c| above it (by more than a tenth of the
   * time from the crossing to the peak) */
  printf("t*(R_c + h) - t*(R_c - h): %.6f ms grazing below (h = %.0e |R_c|), %.6f ms defined (h "
         "= %.0e |R_c|), %.6f ms grazing above (h = %.0e |R_c|); the crossing %.6f ms before the "
         "peak\n",
         jump[0] * 1e3, DH[0], jump[1] * 1e3, DH[1], jump[2] * 1e3, DH[2], gap * 1e3);
  check_true(jump[0] > 0.1 * gap && jump[2] > 0.1 * gap);
}

static void settled_at_start(void) {
  pom_grad *g = make_grad(2.0);
  check_true(g != NULL);
  if (!g) return;
  static const double targets[2][3] = {{2.0e-3, 0.0, -1.2e-3}, {0.0, 0.0, 0.0}};
  for (int c = 0; c < 2; ++c) {
    pom_dyn_metrics mt;
    pom_dyn_grad gr;
    pom_error err;
    check_true(pom_grad_maneuver_joint(g, targets[c], &mt, &gr, &err) == POM_OK);
    for (int a = 0; a < 3; ++a) {
      const pom_dyn_dmetric *d = &gr.settling_time[a];
      printf("target (%+.1f, %+.1f, %+.1f) mm: settling time %d %.6f ms, settled %d: %s\n",
             targets[c][0] * 1e3, targets[c][1] * 1e3, targets[c][2] * 1e3, a + 1,
             mt.settling_time[a] * 1e3, mt.settled[a],
             d->defined ? "defined" : pom_dyn_grad_why_text(d->why));
      if (targets[c][a] == 0.0) {
        check_true(mt.settled[a] && mt.settling_time[a] == 0.0);
        check_true(!d->defined && d->why == POM_DYN_GRAD_SETTLED_AT_START);
        check_true(isnan(d->d[0]) && isnan(d->d[1]));
      } else {
        check_true(d->defined);
      }
    }
    const pom_dyn_dmetric *x = &gr.execution_time;
    printf("  execution time %.6f ms: %s\n", mt.execution_time * 1e3,
           x->defined ? "defined" : pom_dyn_grad_why_text(x->why));
    if (c == 0) {
      check_true(x->defined);
      /* the JSON: null with the reason */
      pom_grad_mc_result r;
      memset(&r, 0, sizeof r);
      r.n_params = NK;
      r.n = r.n_finished = 1;
      r.metrics = &mt;
      r.grads = &gr;
      FILE *f = tmpfile();
      check_true(f != NULL);
      if (!f) continue;
      pom_grad_mc_json(f, "settled.cfg", g, &r, NULL);
      long len = ftell(f);
      static char buf[1 << 16];
      rewind(f);
      size_t n = fread(buf, 1, sizeof buf - 1, f);
      buf[n] = '\0';
      fclose(f);
      check_true(len > 0);
      const char *grad = strstr(buf, "\"gradient\": {"), *und = strstr(buf, "\"undefined\": {");
      const char *nul = grad ? strstr(grad, "\"settling_time_2\": null") : NULL;
      check_true(grad && und && nul && nul < und);
      check_true(und && strstr(und, "\"settling_time_2\": \"settled from the start\""));
    } else {
      check_true(!x->defined && x->why == POM_DYN_GRAD_SETTLED_AT_START);
    }
  }
  pom_grad_destroy(g);
  /* the widest band, 100 % of the step: every actuator starts on its edge
   * (|0 - q_set| = b; rounding of the home pose may put it a hair outside,
   * and the time is then a crossing at t ~ 0 from rest, dg/dt ~ 0): never
   * a number */
  g = make_grad(100.0);
  check_true(g != NULL);
  if (!g) return;
  pom_dyn_metrics mt;
  pom_dyn_grad gr;
  check_true(one_maneuver(g, &mt, &gr));
  for (int a = 0; a < 3; ++a) {
    const pom_dyn_dmetric *d = &gr.settling_time[a];
    printf("band 100 %%: settling time %d %.3g s: %s\n", a + 1, mt.settling_time[a],
           d->defined ? "defined" : pom_dyn_grad_why_text(d->why));
    check_true(!d->defined &&
               (d->why == POM_DYN_GRAD_SETTLED_AT_START || d->why == POM_DYN_GRAD_GRAZING));
  }
  check_true(!gr.execution_time.defined);
  pom_grad_destroy(g);
}

int main(int argc, char **argv) {
  if (argc < 3) {
    printf("usage: test_grad_undefined POMLAB DIR\n");
    return 2;
  }
  setvbuf(stdout, NULL, _IOLBF, 0);
  grazing(argv[1], argv[2]);
  settled_at_start();
  return check_summary("test_grad_undefined");
}
