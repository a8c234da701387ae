/* test_sensitivity.c - Sobol indices against the analytic indices of the
 * Ishigami and Sobol g functions (inside their bootstrap intervals, which
 * must also be narrow), with QMC and random sampling; Morris effects of a
 * function with a linear, a nonlinear and an irrelevant input; bad
 * options refused. */
#include "check.h"
#include "pom_explore.h"
#include "pom_study.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define PI 3.14159265358979323846

/* Ishigami (a = 7, b = 0.1), inputs uniform in [-pi, pi] through pom_dist. */
static double ishigami(const double *u, void *user) {
  const pom_dist *d = user;
  double x1 = pom_dist_quantile(d, u[0]), x2 = pom_dist_quantile(d, u[1]);
  double x3 = pom_dist_quantile(d, u[2]);
  return sin(x1) + 7.0 * sin(x2) * sin(x2) + 0.1 * pow(x3, 4) * sin(x1);
}

/* Sobol g with a = (0, 1, 4.5, 9, 99), x uniform in (0, 1) = u. */
static const double g_a[5] = {0.0, 1.0, 4.5, 9.0, 99.0};
static double sobol_g(const double *u, void *user) {
  (void)user;
  double f = 1;
  for (int i = 0; i < 5; ++i)
    f *= (fabs(4 * u[i] - 2) + g_a[i]) / (1 + g_a[i]);
  return f;
}

/* Analytic value inside the interval, and the interval narrow. */
static void check_in(double lo, double hi, double want, double max_width, const char *what, int i) {
  int ok = lo <= want && want <= hi && hi - lo <= max_width;
  check_true(ok);
  if (!ok) printf("  %s[%d]: analytic %.4f, interval [%.4f, %.4f]\n", what, i, want, lo, hi);
}

static void test_ishigami(pom_sens_sampling sampling, long n) {
  pom_error err;
  pom_dist d;
  double p[4] = {-PI, PI, 0, 0};
  check_true(pom_dist_make(&d, "uniform", p, &err) == POM_OK);
  pom_sens_sobol_opts o;
  pom_sens_sobol_defaults(&o);
  o.dim = 3;
  o.n_base = n;
  o.sampling = sampling;
  o.seed = 2718;
  o.bootstrap = 500;
  pom_sens_sobol_result r;
  check_true(pom_sens_sobol_run(&r, ishigami, &d, &o, &err) == POM_OK);
  /* V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2 */
  double V = 49.0 / 8 + 0.1 * pow(PI, 4) / 5 + 0.01 * pow(PI, 8) / 18 + 0.5;
  double V1 = 0.5 * pow(1 + 0.1 * pow(PI, 4) / 5, 2), V2 = 49.0 / 8;
  double V13 = 0.01 * pow(PI, 8) * (1.0 / 18 - 1.0 / 50);
  double S1[3] = {V1 / V, V2 / V, 0}, ST[3] = {(V1 + V13) / V, V2 / V, V13 / V};
  check_rel(S1[0], 0.3139, 1e-3); /* the published values */
  check_rel(ST[2], 0.2437, 1e-3);
  check_rel(r.variance, V, 0.05);
  check_true(r.n_used == n && r.n_failed == 0);
  for (int i = 0; i < 3; ++i) {
    check_in(r.S1_low[i], r.S1_high[i], S1[i], 0.12, "ishigami S1", i);
    check_in(r.ST_low[i], r.ST_high[i], ST[i], 0.12, "ishigami ST", i);
  }
}

static void test_g(void) {
  pom_error err;
  pom_sens_sobol_opts o;
  pom_sens_sobol_defaults(&o);
  o.dim = 5;
  o.n_base = 4096;
  o.seed = 31;
  o.bootstrap = 500;
  pom_sens_sobol_result r;
  check_true(pom_sens_sobol_run(&r, sobol_g, NULL, &o, &err) == POM_OK);
  double Vi[5], prod = 1;
  for (int i = 0; i < 5; ++i) {
    Vi[i] = 1.0 / (3.0 * (1 + g_a[i]) * (1 + g_a[i]));
    prod *= 1 + Vi[i];
  }
  double V = prod - 1;
  check_rel(r.variance, V, 0.05);
  for (int i = 0; i < 5; ++i) {
    double st = Vi[i] * prod / (1 + Vi[i]) / V;
    check_in(r.S1_low[i], r.S1_high[i], Vi[i] / V, 0.1, "g S1", i);
    check_in(r.ST_low[i], r.ST_high[i], st, 0.1, "g ST", i);
  }
  /* the order of importance: a_i increasing */
  for (int i = 0; i + 1 < 5; ++i)
    check_true(r.ST[i] > r.ST[i + 1]);
}

/* 2.385 x1 + x2^2 + 0 x3 on u: EE1 = 2.385 always; EE2 = 2 u_low + 1/2
 * with u_low in {1/8, 3/8} (4 levels), so mu*2 in [0.75, 1.25] and sigma2
 * > 0; EE3 = 0. */
static double morris_fn(const double *u, void *user) {
  (void)user;
  return 2.385 * u[0] + u[1] * u[1] + 0.0 * u[2];
}

static double fail_half(const double *u, void *user) {
  (void)user;
  return u[0] > 0.5 ? NAN : u[0] + u[1];
}

static void test_morris(void) {
  pom_error err;
  pom_sens_morris_opts o;
  pom_sens_morris_defaults(&o);
  o.dim = 3;
  o.trajectories = 40;
  o.seed = 99;
  pom_sens_morris_result r;
  check_true(pom_sens_morris_run(&r, morris_fn, NULL, &o, &err) == POM_OK);
  check_rel(r.mu_star[0], 2.385, 1e-12);
  check_rel(r.mu[0], 2.385, 1e-12);
  check_abs(r.sigma[0], 0.0, 1e-12);
  check_true(r.mu_star[1] >= 0.75 && r.mu_star[1] <= 1.25 && r.sigma[1] > 0.1);
  check_abs(r.mu_star[2], 0.0, 0.0);
  check_abs(r.sigma[2], 0.0, 0.0);
  check_true(r.n_effects[0] == 40 && r.n_effects[2] == 40);
  /* the design: consecutive rows differ in one input by 1/2 */
  long rows = pom_sens_morris_rows(&o);
  double *u = malloc((size_t)rows * 3 * sizeof *u);
  check_true(pom_sens_morris_design(u, &o, &err) == POM_OK);
  for (long t = 0; t < o.trajectories; ++t)
    for (int s = 1; s <= 3; ++s) {
      int moved = 0;
      for (int i = 0; i < 3; ++i) {
        double du = fabs(u[(t * 4 + s) * 3 + i] - u[(t * 4 + s - 1) * 3 + i]);
        if (du > 0) {
          ++moved;
          check_abs(du, 0.5, 1e-15);
        }
      }
      check_true(moved == 1);
    }
  free(u);
  /* failed runs drop their effects only */
  check_true(pom_sens_morris_run(&r, fail_half, NULL, &o, &err) == POM_OK);
  check_true(r.n_effects[0] == 0 && r.n_effects[1] > 0 && r.n_effects[1] < 40);
  check_rel(r.mu_star[1], 1.0, 1e-12);
}

static void test_errors(void) {
  pom_error err;
  pom_sens_sobol_opts o;
  pom_sens_sobol_result r;
  pom_sens_sobol_defaults(&o);
  o.dim = 21;
  check_true(pom_sens_sobol_run(&r, sobol_g, NULL, &o, &err) == POM_ERR_ARG);
  o.dim = 2;
  o.n_base = 16;
  /* a constant output has no indices */
  double y[64];
  for (int k = 0; k < 64; ++k)
    y[k] = 1.5;
  check_true(pom_sens_sobol_indices(&r, y, &o, &err) == POM_ERR_ARG);
  /* failed base samples are dropped and counted */
  for (int k = 0; k < 64; ++k)
    y[k] = k % 7 + 0.25 * (k % 3);
  y[5] = NAN;
  check_true(pom_sens_sobol_indices(&r, y, &o, &err) == POM_OK);
  check_true(r.n_used == 15 && r.n_failed == 1);
  pom_sens_morris_opts m;
  pom_sens_morris_defaults(&m);
  m.levels = 3;
  pom_sens_morris_result mr;
  check_true(pom_sens_morris_run(&mr, morris_fn, NULL, &m, &err) == POM_ERR_ARG);
}

int main(void) {
  test_ishigami(POM_SENS_QMC, 4096);
  test_ishigami(POM_SENS_RANDOM, 8192);
  test_g();
  test_morris();
  test_errors();
  return check_summary("test_sensitivity");
}
