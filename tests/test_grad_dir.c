/* test_grad_dir.c - design gradients along a direction in the keys' space
 * (study/pom_grad.h pom_grad_create_dirs, docs/optimize.md 12.1): the
 * actuator size law's tangent over its four keys (coil force constant,
 * resistance, inductance, moving mass; docs/optimize.md 11.2) taken as ONE
 * sensitivity parameter, checked
 *   1. against the four single-key sensitivities combined by the chain
 *      rule, sum_m c_m dM/dkey_m: both are sensitivities of the same
 *      maneuver at rtol 1e-12, each within its class bound of the true
 *      derivative (test_grad_random: elasticities 4e-5 energies, 1e-4
 *      settling times, 1e-3 final pointing error, 1e-4 peak current), so
 *      they agree within twice that bound;
 *   2. against the honest whole-run reference along the direction
 *      (pom_grad_reference: central differences of whole simulations at
 *      v +- h c, Richardson with its own error estimate E): within the
 *      class bound + E, as test_grad_random compares single keys;
 *   3. identity directions given explicitly reproduce pom_grad_create bit
 *      for bit (same steps, same models), and a zero direction has
 *      derivative 0 while the others are unchanged;
 *   4. the step and scale of a direction: pbar = min_m |v_m| / |c_m|,
 *      h = rel_step pbar; a refused direction leaves the previous ones.
 * Elasticities are taken with the direction's scale pbar (the move of s
 * that changes some key by its own magnitude). */
#include "check.h"
#include "grad_test_util.h"
#include "pom_grad.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* configs/3pss.cfg with the solver's rtol at 1e-12 (the tolerance the
 * class bounds were measured at, docs/optimize.md 12.4). */
static pom_cfg *tight_config(void) {
  return shipped_with_rtol("3pss.cfg", "1e-12");
}

#define NK 4
static const char *const keys[NK] = {"actuator.force_constant_N_per_A", "actuator.resistance_ohm",
                                     "actuator.inductance_H", "inertia.piston.mass_kg"};
static const double expo[NK] = {1.0, -1.0, 1.0, 3.0}; /* the size law's exponents */

static int metric_class(int k) {
  if (k <= POM_GRAD_ENERGY_3) return 0;
  if (k == POM_GRAD_FINAL_POINTING_ERROR) return 2;
  if (k == POM_GRAD_PEAK_CURRENT) return 3;
  return 1;
}
static const double class_bound[4] = {4e-5, 1e-4, 1e-3, 1e-4};
/* the runs' relative integration error (test_grad_random, docs 12.4) */
static const double class_run_error[4] = {1e-9, 3e-9, 5e-8, 5e-10};

int main(int argc, char **argv) {
  pom_cfg *cfg = tight_config();
  check_true(cfg != NULL);
  if (!cfg) return check_summary("test_grad_dir");
  pom_grad_options o;
  pom_grad_options_defaults(&o);
  o.rigid_joints = 1;
  pom_error err;
  pom_error_clear(&err);
  /* the keys at size s = 1.23 of the config's coil, and the law's tangent
   * c_m = e_m v0_m s^(e_m - 1) = d value_m / ds */
  const double s = 1.23;
  pom_grad *single = NULL, *dir = NULL, *ident = NULL;
  pom_status st = pom_grad_create(&single, cfg, keys, NK, &o, &err);
  if (st != POM_OK) printf("create: %s\n", err.message);
  check_true(st == POM_OK);
  if (st != POM_OK) return check_summary("test_grad_dir");
  double v[NK], c[NK];
  for (int m = 0; m < NK; ++m) {
    double v0 = pom_grad_value(single, m);
    v[m] = v0 * pow(s, expo[m]);
    c[m] = expo[m] * v0 * pow(s, expo[m] - 1.0);
  }
  st = pom_grad_set_values(single, v, &err);
  check_true(st == POM_OK);
  /* two parameters: the size direction and a zero direction */
  double dirs[2 * NK];
  for (int m = 0; m < NK; ++m) {
    dirs[m] = c[m];
    dirs[NK + m] = 0.0;
  }
  st = pom_grad_create_dirs(&dir, cfg, keys, NK, dirs, 2, &o, &err);
  if (st == POM_OK) st = pom_grad_set_values(dir, v, &err);
  if (st != POM_OK) printf("create_dirs: %s\n", err.message);
  check_true(st == POM_OK);
  double eye[NK * NK];
  for (int j = 0; j < NK * NK; ++j)
    eye[j] = j % (NK + 1) == 0 ? 1.0 : 0.0;
  st = pom_grad_create_dirs(&ident, cfg, keys, NK, eye, NK, &o, &err);
  if (st == POM_OK) st = pom_grad_set_values(ident, v, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) return check_summary("test_grad_dir");

  /* 4. step and scale */
  double pbar = INFINITY;
  for (int m = 0; m < NK; ++m)
    pbar = fmin(pbar, fabs(v[m]) / fabs(c[m]));
  check_rel(pom_grad_scale(dir, 0), pbar, 1e-15); /* = s / 3, the mass's */
  check_rel(pbar, s / 3.0, 1e-14);
  check_rel(pom_grad_step(dir, 0), o.rel_step * pbar, 1e-15);
  check_abs(pom_grad_step(dir, 1), 0.0, 0.0);
  check_true(pom_grad_n_params(dir) == 2 && pom_grad_n_keys(dir) == NK);

  /* a joint-space target inside the stroke where every metric of the PID
   * but the tracking error has a derivative (the peak current's maximum
   * is smooth there; at (2.385, -1.7, 0.9) mm it sits on a kink); argv:
   * another target in mm */
  double q[3] = {1.2e-3, 0.4e-3, -0.3e-3};
  for (int i = 0; i < 3 && argc == 4; ++i)
    q[i] = 1e-3 * atof(argv[1 + i]);
  pom_dyn_metrics ms, md, mi;
  pom_dyn_grad gs, gd, gi;
  check_true(pom_grad_maneuver_joint(single, q, &ms, &gs, &err) == POM_OK);
  check_true(pom_grad_maneuver_joint(dir, q, &md, &gd, &err) == POM_OK);
  check_true(pom_grad_maneuver_joint(ident, q, &mi, &gi, &err) == POM_OK);

  /* 3. explicit identity = pom_grad_create, bit for bit */
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    const pom_dyn_dmetric *a = pom_grad_metric_grad(&gs, (pom_grad_metric)k);
    const pom_dyn_dmetric *b = pom_grad_metric_grad(&gi, (pom_grad_metric)k);
    check_true(a->defined == b->defined);
    for (int m = 0; m < NK && a->defined; ++m)
      check_true(a->d[m] == b->d[m]);
  }

  /* 2. the reference along the direction (H = 4e-3 pbar, as test_grad_random) */
  double H[2] = {4e-3 * pbar, 1.0};
  double run_error[POM_GRAD_N_METRICS];
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k)
    run_error[k] = class_run_error[metric_class(k)];
  pom_grad_ref ref[POM_GRAD_N_METRICS];
  pom_dyn_metrics mr;
  st = pom_grad_reference(dir, q, NULL, H, run_error, &mr, ref, &err);
  if (st != POM_OK) printf("reference: %s\n", err.message);
  check_true(st == POM_OK);

  int compared = 0;
  double worst_sum = 0, worst_ref = 0;
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    const pom_dyn_dmetric *a = pom_grad_metric_grad(&gs, (pom_grad_metric)k);
    const pom_dyn_dmetric *b = pom_grad_metric_grad(&gd, (pom_grad_metric)k);
    double M = pom_grad_metric_value(&md, (pom_grad_metric)k);
    /* the same maneuver's metric (the same nominal model and steps of the
     * state; the sensitivities' error test differs, so not bit for bit) */
    double Ms = pom_grad_metric_value(&ms, (pom_grad_metric)k);
    if (isfinite(M) && isfinite(Ms)) check_rel(M, Ms, 1e-6);
    if (a->defined != b->defined) {
      printf("%s: defined %d (single keys) against %d (direction)\n",
             pom_grad_metric_name((pom_grad_metric)k), a->defined, b->defined);
      check_true(0);
      continue;
    }
    if (!b->defined)
      printf("%s: undefined (%s)\n", pom_grad_metric_name((pom_grad_metric)k),
             pom_dyn_grad_why_text(b->why));
    if (!b->defined || !(fabs(M) > 0)) continue;
    /* the zero direction: exactly 0 */
    check_abs(b->d[1], 0.0, 0.0);
    double chain = 0;
    for (int m = 0; m < NK; ++m)
      chain += c[m] * a->d[m];
    const double bound = class_bound[metric_class(k)];
    const double el = pbar / fabs(M); /* elasticity per unit of the derivative */
    double e_sum = fabs(b->d[0] - chain) * el;
    printf("%-22s d/ds %.9e  chain %.9e  elasticity diff %.2e", pom_grad_metric_name(k), b->d[0],
           chain, e_sum);
    check_abs(e_sum, 0.0, 2.0 * bound);
    worst_sum = fmax(worst_sum, e_sum);
    if (ref[k].defined && !ref[k].kink[0] && ref[k].err[0] * el < 0.25 * bound) {
      double e_ref = fabs(b->d[0] - ref[k].d[0]) * el;
      printf("  reference %.9e (E %.1e)  diff %.2e", ref[k].d[0], ref[k].err[0] * el, e_ref);
      check_abs(e_ref, 0.0, bound + ref[k].err[0] * el);
      worst_ref = fmax(worst_ref, e_ref);
      ++compared;
    }
    printf("\n");
  }
  printf("worst elasticity differences: %.2e against the chain rule, %.2e against the "
         "reference (%d metrics)\n",
         worst_sum, worst_ref, compared);
  /* 4 energies, 5 settling times, the final pointing error, the peak current */
  check_true(argc == 4 || compared == 11);
  /* a refused direction (a non-finite coefficient) leaves the previous
   * design and directions in place */
  double bad[2 * NK];
  memcpy(bad, dirs, sizeof bad);
  bad[NK + 2] = NAN;
  check_true(pom_grad_set_point(dir, v, bad, &err) == POM_ERR_ARG);
  check_rel(pom_grad_dir(dir, 0, 3), c[3], 0.0);
  check_abs(pom_grad_dir(dir, 1, 2), 0.0, 0.0);
  check_rel(pom_grad_scale(dir, 0), pbar, 1e-15);
  pom_grad_destroy(single);
  pom_grad_destroy(dir);
  pom_grad_destroy(ident);
  pom_cfg_destroy(cfg);
  return check_summary("test_grad_dir");
}
