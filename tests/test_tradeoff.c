/* test_tradeoff.c - the speed/accuracy sweep (docs/tradeoff.md): a small
 * sweep on the shipped 3P-S-S/S; the errors it reports behave as the
 * numerics say they must (zero for the reference, shrinking with rtol on the
 * rigid path, the k_p error of the parasitic path above the rigid path's),
 * the recommendation obeys its definition, and the config keys are checked. */
#include "check.h"
#include "pom_kinematics.h"
#include "pom_tradeoff.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static pom_cfg *load_cfg(const char *text, pom_error *err) {
  pom_cfg *cfg = NULL;
  if (pom_cfg_load_string(&cfg, text, "<tradeoff>", err) != POM_OK) return NULL;
  return cfg;
}

static const pom_tradeoff_row *find(const pom_tradeoff_result *res, const char *label) {
  for (int r = 0; r < res->n_rows; ++r)
    if (strcmp(res->row[r].label, label) == 0) return &res->row[r];
  return NULL;
}

static void test_sweep(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/3pss.cfg", POM_SOURCE_DIR);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  pom_dyn_params_defaults(&p);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_kin_arch_load(&arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_build(&mech, &arch, cfg, &err) == POM_OK &&
           pom_dyn_params_load(&p, cfg, &err) == POM_OK;
  pom_cfg_destroy(cfg);
  if (!check_true(ok)) {
    printf("  %s\n", err.message);
    return;
  }
  p.maneuver.horizon = 0.03; /* the maneuvers settle in ~13 ms */
  pom_doe_maneuvers mv;
  pom_doe_maneuvers_defaults(&mv);
  pom_tradeoff_opts o;
  pom_tradeoff_defaults(&o);
  o.maneuvers = 1;
  o.repeats = 1;
  o.n_rtol = 1;
  o.rtol[0] = 1e-4;
  o.n_stiffness = 2;
  o.stiffness[0] = 1e5;
  o.stiffness[1] = 1e7;
  o.linear_solvers = 0;
  o.scenes = 0;
  o.reference_rtol = 1e-9;
  pom_tradeoff_result *res = calloc(1, sizeof *res);
  if (!check_true(res != NULL)) return;
  pom_status st = pom_tradeoff_run(&arch, &mech, &p, &mv, &o, res, NULL, NULL, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) printf("  %s\n", err.message);
  /* reference + config + 1 rtol + 2 stiffness + 7 rigid rows */
  check_true(res->n_rows == 12);
  check_abs(res->row[0].err_max, 0.0, 0.0);
  check_true(strcmp(res->row[0].family, "reference") == 0);
  for (int r = 0; r < res->n_rows; ++r) {
    check_true(res->row[r].failures == 0);
    check_true(isfinite(res->row[r].time) && res->row[r].time > 0);
    check_true(res->row[r].err_max ==
               fmax(res->row[r].err_settle, fmax(res->row[r].err_energy, res->row[r].err_traj)));
  }
  const pom_tradeoff_row *r3 = find(res, "rigid rtol 1e-03"), *r8 = find(res, "rigid rtol 1e-08");
  const pom_tradeoff_row *k5 = find(res, "k_p 1e+05"), *k7 = find(res, "k_p 1e+07");
  if (check_true(r3 && r8 && k5 && k7)) {
    /* the rigid path converges to its own rtol 1e-9 reference: rtol 1e-8
     * within 1e-5 (measured 3e-7), and far better than rtol 1e-3 */
    check_true(r8->err_traj < 1e-5 && r8->err_traj < r3->err_traj / 10.0);
    /* the parasitic path's model error shrinks with k_p (first order:
     * deflection ~1/k_p; measured 1.8e-2 -> 5.8e-4 of the step) */
    check_true(k7->err_traj < k5->err_traj / 5.0);
    check_true(k5->err_traj > r8->err_traj);
    check_true(r8->n_states < k5->n_states); /* minimal coordinates */
  }
  /* the rtol rows set rtol alone: natural absolute tolerances on the
   * parasitic path, the exact path's rule min(1e-3, 1e3 rtol) on the rigid
   * rows (docs/tradeoff.md section 1) */
  const pom_tradeoff_row *t4 = find(res, "rtol 1e-04");
  if (check_true(t4 != NULL)) check_true(t4->params.solver.atol_scale == 0.0);
  if (r8) check_true(r8->params.solver.atol_scale == 0.0);
  /* the recommendation is the cheapest row within the accuracy */
  int best = pom_tradeoff_recommend(res, o.accuracy);
  check_true(best == res->recommended);
  if (check_true(best > 0)) {
    check_true(res->row[best].err_max <= o.accuracy);
    for (int r = 1; r < res->n_rows; ++r)
      if (res->row[r].err_max <= o.accuracy) check_true(res->row[best].time <= res->row[r].time);
  }
  check_true(pom_tradeoff_recommend(res, 1e-12) == -1); /* nothing that accurate */
  free(res);
}

static void test_keys(void) {
  pom_error err;
  pom_error_clear(&err);
  pom_tradeoff_opts o;
  pom_tradeoff_defaults(&o);
  pom_cfg *cfg = load_cfg("tradeoff = { maneuvers = 2; rtol = [1e-3, 1e-5]; "
                          "stiffness_N_per_m = [1e6]; accuracy_percent = 0.5; "
                          "reference = \"parasitic\"; rigid = false; };",
                          &err);
  check_true(cfg != NULL);
  check_true(pom_tradeoff_load(&o, cfg, &err) == POM_OK);
  check_true(o.maneuvers == 2 && o.n_rtol == 2 && o.n_stiffness == 1);
  check_abs(o.accuracy, 0.005, 1e-15);
  check_true(o.reference_rigid == 0 && o.rigid == 0);
  pom_cfg_destroy(cfg);
  static const char *const bad[] = {
      "tradeoff = { maneuvers = 0; };",
      "tradeoff = { rtol = [1.0]; };",
      "tradeoff = { reference = \"exact\"; };",
      "tradeoff = { accuracy_percent = -1; };",
  };
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
    pom_tradeoff_defaults(&o);
    cfg = load_cfg(bad[k], &err);
    check_true(cfg != NULL);
    check_true(pom_tradeoff_load(&o, cfg, &err) == POM_ERR_CONFIG);
    check_true(strstr(err.message, "tradeoff.") != NULL);
    pom_cfg_destroy(cfg);
  }
}

int main(void) {
  test_keys();
  test_sweep();
  return check_summary("test_tradeoff");
}
