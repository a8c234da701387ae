/* test_uncertain.c - distributions by inverse CDF (quantiles and moments
 * against closed forms), the `uncertain` group's validation, and draws that
 * depend on (seed, k) only. */
#include "check.h"
#include "pom_run.h"
#include "pom_study.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* Mean and variance of n draws at the centres u = (i + 1/2)/n: a midpoint
 * rule for the integrals of Q(u) and Q(u)^2 over (0, 1). */
static void moments(const pom_dist *d, int n, double *mean, double *var) {
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    double x = pom_dist_quantile(d, (i + 0.5) / n);
    s += x;
    s2 += x * x;
  }
  *mean = s / n;
  *var = s2 / n - *mean * *mean;
}

static void test_quantiles(void) {
  pom_error err;
  pom_dist d;
  double p[4] = {2.5, 7.25, NAN, NAN};
  check_true(pom_dist_make(&d, "uniform", p, &err) == POM_OK);
  check_rel(pom_dist_quantile(&d, 0.3), 2.5 + 0.3 * 4.75, 1e-15);
  check_true(d.lo == 2.5 && d.hi == 7.25);

  double pn[4] = {10.0, 0.5, NAN, NAN};
  check_true(pom_dist_make(&d, "normal", pn, &err) == POM_OK);
  /* Q(Phi(1.3)) = mean + 1.3 sd */
  check_rel(pom_dist_quantile(&d, gsl_cdf_ugaussian_P(1.3)), 10.65, 1e-12);
  check_rel(pom_dist_quantile(&d, 0.5), 10.0, 1e-15);
  /* a draw never reaches u = 0 or 1: the support is finite, about 8.1 sd */
  check_true(isfinite(d.lo) && isfinite(d.hi) && d.hi > 10.0 + 8 * 0.5 && d.hi < 10.0 + 9 * 0.5);
  check_rel(d.lo - 10.0, -(d.hi - 10.0), 1e-6);

  /* truncated normal: inside its bounds; mean mu + s (phi(a) - phi(b)) / Z */
  double pt[4] = {1.0, 0.1, 0.93, 1.2};
  check_true(pom_dist_make(&d, "truncated_normal", pt, &err) == POM_OK);
  check_true(d.lo >= 0.93 && d.hi <= 1.2);
  double a = -0.7, b = 2.0, Z = gsl_cdf_ugaussian_P(b) - gsl_cdf_ugaussian_P(a);
  double phia = exp(-0.5 * a * a) / sqrt(2 * 3.14159265358979323846),
         phib = exp(-0.5 * b * b) / sqrt(2 * 3.14159265358979323846);
  double mean, var;
  moments(&d, 200000, &mean, &var);
  check_rel(mean, 1.0 + 0.1 * (phia - phib) / Z, 1e-6);
  double v_want = 0.01 * (1 + (a * phia - b * phib) / Z - pow((phia - phib) / Z, 2));
  check_rel(var, v_want, 1e-4);
  /* CDF at the quantile: (Phi(z) - Phi(a)) / Z = u */
  double x = pom_dist_quantile(&d, 0.37);
  check_rel((gsl_cdf_ugaussian_P((x - 1.0) / 0.1) - gsl_cdf_ugaussian_P(a)) / Z, 0.37, 1e-12);

  /* far upper tail: computed with Q = 1 - P, still inside [min, max] and
   * monotonic */
  double pf[4] = {0.0, 1.0, 6.0, 6.5};
  check_true(pom_dist_make(&d, "truncated_normal", pf, &err) == POM_OK);
  double x1 = pom_dist_quantile(&d, 0.2), x2 = pom_dist_quantile(&d, 0.8);
  check_true(x1 > 6.0 && x1 < x2 && x2 < 6.5);
  double qa = gsl_cdf_ugaussian_Q(6.0), qb = gsl_cdf_ugaussian_Q(6.5);
  check_rel(gsl_cdf_ugaussian_Q(x1), qa - 0.2 * (qa - qb), 1e-9);
  /* an interval with no probability (1e-19) is refused */
  double pz[4] = {0.0, 1.0, 9.0, 9.5};
  check_true(pom_dist_make(&d, "truncated_normal", pz, &err) == POM_ERR_ARG);

  /* lognormal: median, and mean median exp(s^2/2) */
  double pl[4] = {3.8, 0.2, NAN, NAN};
  check_true(pom_dist_make(&d, "lognormal", pl, &err) == POM_OK);
  check_rel(pom_dist_quantile(&d, 0.5), 3.8, 1e-14);
  moments(&d, 200000, &mean, &var);
  check_rel(mean, 3.8 * exp(0.02), 1e-6);
  check_rel(var, 3.8 * 3.8 * exp(0.04) * (exp(0.04) - 1), 1e-3);
  check_true(d.lo > 0);
  /* truncated lognormal stays inside */
  double plt[4] = {1.0, 0.3, 0.8, 1.1};
  check_true(pom_dist_make(&d, "lognormal", plt, &err) == POM_OK);
  check_true(d.lo >= 0.8 && d.hi <= 1.1 && d.lo < 0.8001 && d.hi > 1.0999);

  /* inconsistent parameters */
  double bad1[4] = {3.0, 3.0, NAN, NAN};
  check_true(pom_dist_make(&d, "uniform", bad1, &err) == POM_ERR_ARG);
  double bad2[4] = {1.0, 0.0, NAN, NAN};
  check_true(pom_dist_make(&d, "normal", bad2, &err) == POM_ERR_ARG);
  double bad3[4] = {0.0, 1.0, 40.0, 41.0}; /* no mass */
  check_true(pom_dist_make(&d, "truncated_normal", bad3, &err) == POM_ERR_ARG);
  double bad4[4] = {-1.0, 0.1, NAN, NAN};
  check_true(pom_dist_make(&d, "lognormal", bad4, &err) == POM_ERR_ARG);
  check_true(pom_dist_make(&d, "cauchy", pn, &err) == POM_ERR_ARG);
  /* u from bits: never 0 or 1 */
  check_true(pom_dist_u_from_bits(0) == POM_DIST_U_MIN);
  check_true(pom_dist_u_from_bits(~0ULL) == POM_DIST_U_MAX && POM_DIST_U_MAX < 1.0);
}

static const char *good =
    "montecarlo = { seed = 77; };\n"
    "uncertain = (\n"
    "  { key = \"actuator.resistance_ohm\"; dist = \"normal\"; mean = 10.0; sd = 0.5; },\n"
    "  { key = \"controller.kp\"; dist = \"lognormal\"; median = 1.0; sigma_ln = 0.1;\n"
    "    relative = true; max = 1.3; },\n"
    "  { key = \"inertia.platform.mass_kg\"; dist = \"uniform\"; min = 0.9; max = 1.1;\n"
    "    relative = true; }\n"
    ");\n";

static void test_group(void) {
  pom_error err;
  pom_cfg *cfg = NULL;
  pom_unc unc;
  check_true(pom_cfg_load_string(&cfg, good, "<good>", &err) == POM_OK);
  check_true(pom_unc_load(&unc, cfg, 77, &err) == POM_OK);
  check_true(unc.n == 3 && unc.param[1].relative && !unc.param[0].relative);
  check_true(unc.param[1].dist.hi <= 1.3);
  pom_cfg_destroy(cfg);

  /* draws depend on (seed, k) only, lie inside each support, and differ
   * between maneuvers */
  double x[POM_UNC_MAX], y[POM_UNC_MAX], z[POM_UNC_MAX];
  pom_unc_draws(&unc, 12, x);
  pom_unc_draws(&unc, 13, z);
  pom_unc copy = unc;
  pom_unc_draws(&copy, 12, y);
  for (int j = 0; j < 3; ++j) {
    check_true(x[j] == y[j] && x[j] != z[j]);
    check_true(x[j] >= unc.param[j].dist.lo && x[j] <= unc.param[j].dist.hi);
  }
  copy.seed = 78;
  pom_unc_draws(&copy, 12, y);
  check_true(y[0] != x[0]);
  /* many draws of the normal: mean and sd within 4 standard errors */
  double s = 0, s2 = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    pom_unc_draws(&unc, k, x);
    s += x[0];
    s2 += x[0] * x[0];
  }
  double mean = s / n, sd = sqrt(s2 / n - mean * mean);
  check_abs(mean, 10.0, 4 * 0.5 / sqrt(n));
  check_abs(sd, 0.5, 4 * 0.5 / sqrt(2.0 * n));

  /* design mode: unit k uses row k / per_row and maneuver k % per_row */
  double design[6] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  unc.design = design;
  unc.design_rows = 2;
  unc.per_row = 3;
  long m = -1;
  double u[POM_UNC_MAX];
  pom_unc_unit(&unc, 4, &m, u);
  check_true(m == 1 && u[0] == 0.4 && u[2] == 0.6);

  /* bad groups name the key */
  static const char *const bad[] = {
      "uncertain = ( { key = \"actuator.resistance_ohm\"; dist = \"normal\"; mean = 1.0; }"
      " );",
      "uncertain = ( { key = \"resistance\"; dist = \"uniform\"; min = 1.0; max = 2.0; } );",
      "uncertain = ( { key = \"a.b\"; dist = \"uniform\"; min = 2.0; max = 1.0; } );",
      "uncertain = ( { key = \"a.b\"; dist = \"beta\"; min = 1.0; max = 2.0; } );",
      "uncertain = ( { key = \"a.b\"; dist = \"uniform\"; min = 1.0; max = 2.0; },"
      " { key = \"a.b\"; dist = \"uniform\"; min = 1.0; max = 2.0; } );",
      "uncertain = ();",
      "uncertain = { key = \"a.b\"; dist = \"uniform\"; min = 1.0; max = 2.0; };",
      NULL};
  /* the key of the parameter that breaks the rule (min > max: max) */
  static const char *const want[] = {"uncertain.[0].sd",
                                     "uncertain.[0].key",
                                     "uncertain.[0].max",
                                     "uncertain.[0].dist",
                                     "uncertain.[1].key",
                                     "'uncertain'",
                                     "expected a list in parentheses"};
  for (int b = 0; bad[b]; ++b) {
    check_true(pom_cfg_load_string(&cfg, bad[b], "<bad>", &err) == POM_OK);
    pom_status st = pom_unc_load(&unc, cfg, 1, &err);
    check_true(st == POM_ERR_CONFIG);
    if (!strstr(err.message, want[b])) {
      check_true(0);
      printf("bad %d: message '%s' lacks '%s'\n", b, err.message, want[b]);
    }
    pom_cfg_destroy(cfg);
  }
}

int main(void) {
  test_quantiles();
  test_group();
  return check_summary("test_uncertain");
}
