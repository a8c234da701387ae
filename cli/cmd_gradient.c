/* cmd_gradient.c - `pomlab gradient CFG --params KEY,KEY,...`: the metrics
 * of the config's Monte-Carlo maneuvers with their design gradients by
 * forward sensitivities (study/pom_grad.h, docs/optimize.md "Design
 * gradients"), per maneuver and of the means; --check beside them the
 * central differences of whole simulations. */
#include "cli_opts.h"
#include "pom_cli.h"
#include "pom_study.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Relative step of the whole-run differences of --check: the runs'
 * integration error over 2 dh against the O(dh^2) truncation
 * (docs/optimize.md 12.6). */
#define CHECK_REL_STEP 1e-3
/* The check's default solver.rtol, when the config's is looser: a run's
 * integration error, about rtol of a metric and not smooth in the design,
 * divided by the step dh = 1e-3 |p| must stay below what the check is to
 * show. At the shipped rtol 1e-6 that noise (1e-3 of the derivative's
 * scale, measured up to 4x the derivative itself) buries the comparison;
 * at 1e-10 it is 1e-7 (docs/optimize.md 12.6). */
#define CHECK_RTOL_DEFAULT 1e-10

static const char *unit_of(pom_grad_metric k) {
  if (k <= POM_GRAD_ENERGY_3) return "J";
  if (k <= POM_GRAD_FINAL_POINTING_ERROR) return "rad";
  if (k == POM_GRAD_PEAK_CURRENT) return "A";
  return "s";
}

static void print_text(FILE *out, const pom_grad *g, const pom_dyn_metrics *mt,
                       const pom_dyn_grad *gr, const pom_dyn_grad *fd) {
  const int n = pom_grad_n_params(g);
  fprintf(out, "  %-24s %-16s", "metric", "value");
  for (int j = 0; j < n; ++j)
    fprintf(out, " d/d %-18.18s", pom_grad_key(g, j));
  fprintf(out, "\n");
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    double v = pom_grad_metric_value(mt, (pom_grad_metric)k);
    const pom_dyn_dmetric *d = pom_grad_metric_grad(gr, (pom_grad_metric)k);
    if (!isfinite(v) && !d->defined && d->why == POM_DYN_GRAD_UNKNOWN) continue;
    char val[32];
    snprintf(val, sizeof val, "%.6g %s", v, unit_of((pom_grad_metric)k));
    fprintf(out, "  %-24s %-16s", pom_grad_metric_name((pom_grad_metric)k), val);
    if (d->defined)
      for (int j = 0; j < n; ++j)
        fprintf(out, " %+-22.9e", d->d[j]);
    else
      fprintf(out, " undefined: %s", pom_dyn_grad_why_text(d->why));
    fprintf(out, "\n");
    if (!fd) continue;
    const pom_dyn_dmetric *c = pom_grad_metric_grad(fd, (pom_grad_metric)k);
    fprintf(out, "  %-24s %-16s", "  (whole-run diff.)", "");
    for (int j = 0; j < n && c->defined; ++j)
      fprintf(out, " %+-22.9e", c->d[j]);
    if (!c->defined) fprintf(out, " undefined");
    fprintf(out, "\n");
  }
}

/* One row per metric of a set's statistics (values v, gradients d; fd the
 * check's, or NULL): a metric whose value is NaN and gradient unknown is
 * left out. */
static void print_set(const pom_grad *g, int n, const double *v, const pom_dyn_dmetric *d,
                      const pom_dyn_dmetric *fd) {
  pom_dyn_metrics mm;
  pom_dyn_grad gm, gf;
  memset(&mm, 0, sizeof mm);
  memset(&gm, 0, sizeof gm);
  memset(&gf, 0, sizeof gf);
  gm.n_params = gf.n_params = n;
  mm.energy_total = v[POM_GRAD_ENERGY_TOTAL];
  for (int a = 0; a < 3; ++a) {
    mm.energy[a] = v[POM_GRAD_ENERGY_1 + a];
    mm.settling_time[a] = v[POM_GRAD_SETTLING_TIME_1 + a];
  }
  mm.tracking_rms_error = v[POM_GRAD_TRACKING_RMS_ERROR];
  mm.final_pointing_error = v[POM_GRAD_FINAL_POINTING_ERROR];
  mm.execution_time = v[POM_GRAD_EXECUTION_TIME];
  mm.pointing_settling_time = v[POM_GRAD_POINTING_SETTLING_TIME];
  mm.peak_current = v[POM_GRAD_PEAK_CURRENT];
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    *(pom_dyn_dmetric *)pom_grad_metric_grad(&gm, (pom_grad_metric)k) = d[k];
    if (fd) *(pom_dyn_dmetric *)pom_grad_metric_grad(&gf, (pom_grad_metric)k) = fd[k];
  }
  print_text(stdout, g, &mm, &gm, fd ? &gf : NULL);
}

int pom_cmd_gradient(int argc, char **argv) {
  const char *cfg_path = NULL, *params = NULL;
  const char *n_text = NULL, *seed_text = NULL, *margin_text = NULL, *q_text = NULL,
             *bw_text = NULL, *check_rtol_text = NULL, *errtest_text = NULL;
  int json = 0, check = 0;
  const pom_opt opts[] = {
      {.name = "--params",
       .kind = POM_OPT_TEXT,
       .arg = "KEY,KEY,...",
       .help = "the design keys (dotted numeric config keys present in the file, an array "
               "element as key[i]; at most 16); derivatives are per unit of the key as written",
       .text = &params},
      {.name = "--maneuvers",
       .kind = POM_OPT_NUMBER,
       .arg = "N",
       .key = "montecarlo.maneuvers",
       .help = "number of maneuvers (default: the config's montecarlo.maneuvers)",
       .text = &n_text},
      {.name = "--seed",
       .kind = POM_OPT_NUMBER,
       .arg = "S",
       .key = "montecarlo.seed",
       .help = "study seed",
       .text = &seed_text},
      {.name = "--sens-margin",
       .kind = POM_OPT_NUMBER,
       .arg = "M",
       .key = POM_GRAD_KEY_NOISE_MARGIN,
       .help = "the sensitivities' accuracy, in [1, 1e6]: their relative tolerance is "
               "max(solver.rtol, M eps / 3e-6) (default 3e2; smaller = more accurate at more "
               "steps, acting only below solver.rtol = M x 7.4e-11; docs/optimize.md 12.4)",
       .text = &margin_text},
      {.name = "--sens-error-test",
       .kind = POM_OPT_CHOICE,
       .arg = "on|off",
       .key = POM_GRAD_KEY_ERROR_TEST,
       .help = "whether the sensitivities enter the integrator's error test (default on; off: "
               "the state's steps carry them, as accurate at a tight solver.rtol such as 1e-10 "
               "for far fewer steps, 10-20x less accurate at the shipped 1e-6; docs/optimize.md "
               "12.5)",
       .text = &errtest_text},
      {.name = "--quantile",
       .kind = POM_OPT_NUMBER,
       .arg = "P",
       .key = POM_GRAD_KEY_QUANTILE,
       .help = "the smooth robust statistic of the times over the maneuvers: the kernel-smoothed "
               "P-quantile, in [0.01, 0.99] (default 0.95; docs/optimize.md 11.3, 12.3)",
       .text = &q_text},
      {.name = "--bandwidth-ms",
       .kind = POM_OPT_NUMBER,
       .arg = "H",
       .key = POM_GRAD_KEY_BANDWIDTH,
       .help = "its Gaussian kernel's bandwidth, ms, in [1e-3, 1e3] (default 1, as the "
               "co-design's)",
       .text = &bw_text},
      {.name = "--check",
       .kind = POM_OPT_FLAG,
       .help = "also the central differences of whole simulations (step 1e-3 x |value|) beside "
               "each gradient, run at a tight solver.rtol (--check-rtol)",
       .flag = &check,
       .set = 1},
      {.name = "--check-rtol",
       .kind = POM_OPT_TEXT,
       .arg = "R",
       .help = "solver.rtol of --check's runs, checked as solver.rtol in a file (default: the "
               "config's, or 1e-10 where the config's is looser: at 1e-6 the runs' integration "
               "noise over the step buries the comparison; docs/optimize.md 12.6); the "
               "gradients keep the config's",
       .text = &check_rtol_text},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "JSON on stdout (SI units)",
       .flag = &json,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "gradient",
      .usage = "CONFIG --params KEY,KEY,... [options]",
      .about = "The metrics of the config's Monte-Carlo maneuvers and their derivatives with\n"
               "respect to design keys, by forward sensitivities through the exact (rigid-joint)\n"
               "formulation (docs/optimize.md, \"Design gradients\"): per maneuver and of the\n"
               "means: the energies, the tracking and final pointing errors, the settling and\n"
               "execution times and the peak coil current (its time and coil in the JSON). A\n"
               "settling time's derivative is undefined where the time is censored, zero from\n"
               "the start or its last band crossing grazes the band; the peak current's where\n"
               "its maximum is at the start or the horizon, on a kink or near a saturated\n"
               "voltage's corner of i(t), or ties with another coil or time (section 12.2). Of\n"
               "the set: the means and the smooth quantiles of the times (--quantile). An\n"
               "undefined derivative is printed as such, with its reason, never as a number.",
      .notes = "Needs joints.model = \"rigid\". Exit status: 0 done (failed maneuvers are\n"
               "reported); 1 runtime failure; 2 usage or config error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &cfg_path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!cfg_path || !params) {
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  if (check_rtol_text && !check) {
    fprintf(stderr, "pomlab gradient: --check-rtol %s: only with --check\n", check_rtol_text);
    return 2;
  }
  char list[4096];
  const char *keys[POM_GRAD_MAX_PARAMS];
  int n = 0;
  if (strlen(params) >= sizeof list) {
    fprintf(stderr, "pomlab gradient: --params: list too long\n");
    return 2;
  }
  snprintf(list, sizeof list, "%s", params);
  for (char *tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
    if (n == POM_GRAD_MAX_PARAMS) {
      fprintf(stderr, "pomlab gradient: --params: more than %d keys\n", POM_GRAD_MAX_PARAMS);
      return 2;
    }
    keys[n++] = tok;
  }
  if (n == 0) {
    fprintf(stderr, "pomlab gradient: --params: no key given\n");
    return 2;
  }
  pom_cfg *cfg = pom_cli_load_config(cfg_path);
  if (!cfg) return 2;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = pom_cli_opts_apply(&spec, cfg, &err);
  pom_grad *g = NULL;
  if (st == POM_OK) st = pom_grad_create(&g, cfg, keys, n, NULL, &err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    return pom_cli_exit_code(st);
  }
  pom_grad_mc_result r;
  st = pom_grad_montecarlo(g, NULL, &r, &err);
  pom_grad_mc_result c;
  memset(&c, 0, sizeof c);
  double check_rtol = 0.0;
  if (st == POM_OK && check) {
    /* the same maneuvers by whole-run differences at CHECK_REL_STEP */
    pom_grad_destroy(g);
    g = NULL;
    pom_grad_options o;
    pom_grad_options_defaults(&o);
    o.rel_step = CHECK_REL_STEP;
    cfg = pom_cli_load_config(cfg_path);
    if (!cfg) {
      pom_grad_mc_free(&r);
      return 2;
    }
    st = pom_cli_opts_apply(&spec, cfg, &err);
    /* the check's rtol: --check-rtol (checked by the solver's reader, the
     * message naming the flag), else the config's or CHECK_RTOL_DEFAULT */
    if (st == POM_OK && check_rtol_text)
      st = pom_cfg_set_number(cfg, "solver.rtol", check_rtol_text, "--check-rtol", &err);
    /* the range of the file's solver.rtol (pom_dyn_params_schema.h) */
    if (st == POM_OK)
      st =
          pom_cfg_real_opt(cfg, "solver.rtol", 1.0, POM_DYN_RTOL_MIN, 0.1, 1e-6, &check_rtol, &err);
    if (st == POM_OK && !check_rtol_text && check_rtol > CHECK_RTOL_DEFAULT)
      check_rtol = CHECK_RTOL_DEFAULT;
    o.solver_rtol = check_rtol;
    if (st == POM_OK) st = pom_grad_create(&g, cfg, keys, n, &o, &err);
    pom_cfg_destroy(cfg);
    pom_grad_mc_options mo;
    pom_grad_mc_options_defaults(&mo);
    mo.plain_fd = 1;
    if (st == POM_OK) st = pom_grad_montecarlo(g, &mo, &c, &err);
  }
  if (st != POM_OK) {
    pom_cli_report("gradient", &err);
    pom_grad_mc_free(&r);
    pom_grad_mc_free(&c);
    pom_grad_destroy(g);
    return pom_cli_exit_code(st);
  }
  if (json) {
    pom_grad_mc_json(stdout, cfg_path, g, &r, check ? &c : NULL);
  } else {
    printf("pomlab gradient %s: %ld maneuvers, keys:", cfg_path, r.n);
    for (int j = 0; j < n; ++j)
      printf(" %s = %.10g", pom_grad_key(g, j), pom_grad_value(g, j));
    printf("\n(derivatives per unit of each key as written in the config; SI metrics)\n");
    if (check)
      printf("(whole-run diff.: central differences of whole simulations at step %g |value|, "
             "solver.rtol %g; the gradients at the config's)\n",
             CHECK_REL_STEP, check_rtol);
    for (long i = 0; i < r.n; ++i) {
      const pom_dyn_metrics *mt = &r.metrics[i];
      printf("\nmaneuver %ld: target (%.6g, %.6g, %.6g) SI: %s%s%s\n", i + 1, mt->target[0],
             mt->target[1], mt->target[2], mt->status == POM_OK ? "finished" : "FAILED",
             mt->status == POM_OK ? "" : ": ", mt->status == POM_OK ? "" : mt->reason);
      if (mt->status == POM_OK) print_text(stdout, g, mt, &r.grads[i], check ? &c.grads[i] : NULL);
    }
    printf("\nmeans over the %ld finished of %ld maneuvers (a mean's derivative needs every "
           "maneuver's):\n",
           r.n_finished, r.n);
    print_set(g, n, r.mean, r.dmean, check ? c.dmean : NULL);
    printf("\nsmooth %g-quantiles of the times over the %ld maneuvers (Gaussian kernel, bandwidth "
           "%g ms; d/dp = sum_i w_i dt_i/dp, defined as the means'; docs/optimize.md 11.3, "
           "12.3):\n",
           r.quantile_p, r.n, 1e3 * r.quantile_bandwidth);
    print_set(g, n, r.quantile, r.dquantile, check ? c.dquantile : NULL);
  }
  pom_grad_mc_free(&r);
  pom_grad_mc_free(&c);
  pom_grad_destroy(g);
  return 0;
}
