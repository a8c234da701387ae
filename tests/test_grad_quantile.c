/* test_grad_quantile.c - the gradient of the smooth robust statistic of a
 * Monte-Carlo set (study/pom_grad.h pom_grad_montecarlo: the kernel-smoothed
 * p-quantile of each time metric over the maneuvers, docs/optimize.md 11.3,
 * 12.3), dq/dp = sum_i w_i dt_i/dp with w_i = dq/dt_i by the
 * implicit-function theorem, checked against central differences of the
 * quantile itself over whole Monte-Carlo sets at p +- h (the same maneuvers
 * and draws: the set is a function of p alone):
 *   D(h) = (q(p + h) - q(p - h)) / 2h, h = H and H/2 (H = 2e-2 |p|),
 *   R = D(H/2) + (D(H/2) - D(H)) / 3 (Richardson), its error estimate
 *   E = |D(H/2) - D(H)| / 3 + 1.5 eps_M |q| / (H/2),
 * eps_M the runs' non-smooth integration error relative to a time, at the
 * test's rtol 1e-10: measured as D(H/2) at rtol 1e-10 against 2e-10, whose
 * relative differences were at most 1.4e-4 (the pointing time against
 * R_c), 7e-6 in elasticity, i.e. eps_M = 5e-8; taken three times that, as
 * docs/optimize.md 12.4 does. H is 5x test_grad_random's to keep that noise
 * at a fifth; the Richardson term shows any curvature or kink it brings.
 * In elasticity (p/q) every defined quantile derivative must be within the
 * settling times' bound 1e-4 + E, E itself at most half the bound (the
 * reference resolves it). The check can fail: the mean's weights 1/n in place of
 * w_i must miss it on at least one metric (the quantile weighs the slow
 * maneuvers, the mean all alike), and the quantile's value must equal
 * pom_smooth_quantile of the maneuvers' times. */
#include "check.h"
#include "grad_test_util.h"
#include "pom_grad.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_MAN 6
#define REL_H 2e-2
#define EPS_M 1.5e-7

/* configs/3pss.cfg at rtol 1e-10 with N_MAN maneuvers. */
static pom_cfg *config(void) {
  pom_cfg *cfg = shipped_with_rtol("3pss.cfg", "1e-10");
  pom_error err;
  if (cfg && pom_cfg_set_number(cfg, "montecarlo.maneuvers", "6", "test", &err) != POM_OK) {
    printf("config: %s\n", err.message);
    pom_cfg_destroy(cfg);
    return NULL;
  }
  return cfg;
}

static const pom_grad_metric times[] = {POM_GRAD_SETTLING_TIME_1, POM_GRAD_SETTLING_TIME_2,
                                        POM_GRAD_SETTLING_TIME_3, POM_GRAD_EXECUTION_TIME,
                                        POM_GRAD_POINTING_SETTLING_TIME};
#define N_T ((int)(sizeof times / sizeof times[0]))
#define NK  2
static const char *const keys[NK] = {"controller.kd_s", "actuator.resistance_ohm"};

/* The quantiles of the set at the design v (no gradients needed, but the
 * set is run as the test's: the same maneuvers and draws). */
static int quantiles_at(pom_grad *g, const double *v, double q[N_T]) {
  pom_error err;
  if (pom_grad_set_values(g, v, &err) != POM_OK) {
    printf("design refused: %s\n", err.message);
    return 0;
  }
  pom_grad_mc_result r;
  if (pom_grad_montecarlo(g, NULL, &r, &err) != POM_OK) {
    printf("montecarlo: %s\n", err.message);
    return 0;
  }
  for (int i = 0; i < N_T; ++i)
    q[i] = r.quantile[times[i]];
  pom_grad_mc_free(&r);
  return 1;
}

int main(void) {
  pom_cfg *cfg = config();
  check_true(cfg != NULL);
  if (!cfg) return check_summary("test_grad_quantile");
  pom_grad_options o;
  pom_grad_options_defaults(&o);
  o.rigid_joints = 1;
  pom_grad *g = NULL;
  pom_error err;
  pom_status st = pom_grad_create(&g, cfg, keys, NK, &o, &err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) printf("create: %s\n", err.message);
  check_true(st == POM_OK);
  if (st != POM_OK) return check_summary("test_grad_quantile");
  double v0[NK];
  for (int j = 0; j < NK; ++j)
    v0[j] = pom_grad_value(g, j);

  pom_grad_mc_result r;
  check_true(pom_grad_montecarlo(g, NULL, &r, &err) == POM_OK);
  check_true(r.n == N_MAN && r.n_finished == N_MAN);
  check_abs(r.quantile_p, 0.95, 0.0);
  check_abs(r.quantile_bandwidth, 1e-3, 0.0);
  /* the value: pom_smooth_quantile of the maneuvers' times; the other
   * metrics have none */
  for (int i = 0; i < N_T; ++i) {
    double t[N_MAN];
    for (int m = 0; m < N_MAN; ++m)
      t[m] = pom_grad_metric_value(&r.metrics[m], times[i]);
    check_abs(r.quantile[times[i]], pom_smooth_quantile(t, N_MAN, 0.95, 1e-3, NULL), 0.0);
  }
  check_true(isnan(r.quantile[POM_GRAD_ENERGY_TOTAL]) &&
             !r.dquantile[POM_GRAD_ENERGY_TOTAL].defined);

  int compared = 0, mean_misses = 0;
  for (int j = 0; j < NK; ++j) {
    double D[2][N_T];
    int ok = 1;
    for (int s = 0; s < 2 && ok; ++s) {
      const double h = REL_H * fabs(v0[j]) / (s ? 2.0 : 1.0);
      double v[NK], qp[N_T], qm[N_T];
      memcpy(v, v0, sizeof v);
      v[j] = v0[j] + h;
      ok = quantiles_at(g, v, qp);
      v[j] = v0[j] - h;
      ok = ok && quantiles_at(g, v, qm);
      for (int i = 0; i < N_T; ++i)
        D[s][i] = (qp[i] - qm[i]) / (2.0 * h);
    }
    check_true(ok);
    if (!ok) break;
    for (int i = 0; i < N_T; ++i) {
      const pom_grad_metric k = times[i];
      const pom_dyn_dmetric *dq = &r.dquantile[k];
      const double q = r.quantile[k];
      if (!dq->defined) {
        printf("%s / %s: undefined (%s), not compared\n", pom_grad_metric_name(k), keys[j],
               pom_dyn_grad_why_text(dq->why));
        continue;
      }
      const double ref = D[1][i] + (D[1][i] - D[0][i]) / 3.0;
      const double el = fabs(v0[j]) / fabs(q);
      const double E =
          (fabs(D[1][i] - D[0][i]) / 3.0 + 1.5 * EPS_M * fabs(q) / (0.5 * REL_H * fabs(v0[j]))) *
          el;
      const double e = fabs(dq->d[j] - ref) * el, em = fabs(r.dmean[k].d[j] - ref) * el;
      printf("%-22s / %-24s dq/dp %+.9e  ref %+.9e  elasticity error %.2e (ref. error %.1e)  "
             "with the mean's weights %.2e\n",
             pom_grad_metric_name(k), keys[j], dq->d[j], ref, e, E, em);
      check_true(e <= 1e-4 + E);
      check_true(E <= 5e-5); /* the reference resolves the bound (half of it) */
      ++compared;
      mean_misses += !(em <= 1e-4 + E);
    }
  }
  check_true(compared >= 8);
  printf("compared %d quantile derivatives; the mean's weights miss %d of them\n", compared,
         mean_misses);
  check_true(mean_misses >= 1);
  pom_grad_mc_free(&r);
  pom_grad_destroy(g);
  return check_summary("test_grad_quantile");
}
