/* test_fidelity.c - fidelity earned per candidate (docs/tradeoff.md section
 * 9): for each shipped architecture the rule picks a setting at 1 % on 20
 * selection maneuvers (seed A, margin 2) validated on 20 others (seed B);
 * its claimed accuracy must then hold on 50 unseen maneuvers (seed C)
 * against the tight reference. Also: the ladder is ordered, an impossible
 * accuracy falls back to the last rung with met = 0, bad arguments are
 * refused. The shipped 100 ms horizon; joint space, +-3 mm for the linear
 * designs and +-10 deg for the 3-RRR (its 15 mm/rad equivalent lever makes
 * +-3 mm about +-11 deg). */
#include "check.h"
#include "pom_run.h"
#include "pom_study.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SEED_SELECT   101u
#define SEED_VALIDATE 202u
#define SEED_UNSEEN   303u
#define N_UNSEEN      50

static int load(const char *file, pom_kin_arch *arch, pom_mechanism *mech, pom_dyn_params *p,
                pom_error *err) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, file);
  pom_cfg *cfg = NULL;
  pom_dyn_params_defaults(p);
  int ok = pom_cfg_load(&cfg, path, err) == POM_OK && pom_kin_arch_load(arch, cfg, err) == POM_OK &&
           pom_kin_mechanism_build(mech, arch, cfg, err) == POM_OK &&
           pom_dyn_params_load(p, cfg, err) == POM_OK;
  pom_cfg_destroy(cfg);
  if (!ok) printf("  %s\n", err->message);
  return ok;
}

static void test_architecture(const char *file) {
  pom_error err;
  pom_error_clear(&err);
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_params p;
  if (!check_true(mech != NULL) || !check_true(load(file, &arch, mech, &p, &err))) {
    free(mech);
    return;
  }
  pom_doe_maneuvers mv;
  pom_doe_maneuvers_defaults(&mv);
  if (pom_act_kind_desc(mech->actuator[0].kind)->angular) mv.range = 10.0 * POM_DEG;
  pom_fidelity_opts o;
  pom_fidelity_defaults(&o);
  double(*sel)[3] = calloc(20, sizeof *sel), (*val)[3] = calloc(20, sizeof *val);
  double(*unseen)[3] = calloc(N_UNSEEN, sizeof *unseen);
  int n_sel = 0, n_val = 0, n_unseen = 0;
  pom_doe_maneuver_targets(sel, &n_sel, &mv, SEED_SELECT, 20, &arch);
  pom_doe_maneuver_targets(val, &n_val, &mv, SEED_VALIDATE, 20, &arch);
  pom_doe_maneuver_targets(unseen, &n_unseen, &mv, SEED_UNSEEN, N_UNSEEN, &arch);
  check_true(n_sel == 20 && n_val == 20 && n_unseen == N_UNSEEN);
  pom_fidelity_result res;
  pom_status st = pom_fidelity_select(&res, &arch, mech, &p, (const double(*)[3])sel, n_sel,
                                      (const double(*)[3])val, n_val, &o, &err);
  if (!check_true(st == POM_OK)) {
    printf("  %s: %s\n", file, err.message);
    goto done;
  }
  check_true(res.met);
  check_true(res.rung >= 0);
  check_true(res.n_select == n_sel && res.n_validate == n_val);
  check_true(fmax(res.select_time, res.select_energy) <= o.accuracy / o.margin);
  check_true(fmax(res.bound_time, res.bound_energy) <= o.accuracy);
  /* the claim on maneuvers the rule never saw */
  pom_dyn_params chosen = p, ref = p;
  pom_fidelity_apply(&chosen, &res.setting);
  pom_fidelity_reference(&ref, o.reference_rtol);
  double e[2] = {NAN, NAN};
  int used = 0;
  st = pom_fidelity_measure(e, &used, &arch, mech, &chosen, &ref, (const double(*)[3])unseen,
                            n_unseen, &err);
  check_true(st == POM_OK);
  check_true(used == n_unseen);
  check_true(e[0] <= o.accuracy);
  check_true(e[1] <= o.accuracy);
  printf("  %s: %s (rung %d, %d tried); selection %.2e / %.2e, validated bound %.2e / %.2e "
         "(time / energy); %d unseen: %.2e / %.2e; %.0f steps against %.0f for the reference; "
         "%.2f s\n",
         file, res.setting.label, res.rung, res.tried, res.select_time, res.select_energy,
         res.bound_time, res.bound_energy, used, e[0], e[1], res.steps, res.reference_steps,
         res.wall);
done:
  free(sel);
  free(val);
  free(unseen);
  free(mech);
}

/* The ladder is ordered cheapest first (looser rtol first within a coil
 * model, the quasi-static coil before the inductive one); an accuracy no
 * rung meets ends on the last rung with met = 0; bad options are refused. */
static void test_rule(void) {
  int n = 0;
  const pom_fidelity_setting *lad = pom_fidelity_ladder(&n);
  check_true(n >= 4);
  for (int r = 1; r < n; ++r)
    check_true(
        lad[r].coil_inductance > lad[r - 1].coil_inductance ||
        (lad[r].coil_inductance == lad[r - 1].coil_inductance && lad[r].rtol < lad[r - 1].rtol));
  pom_error err;
  pom_error_clear(&err);
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_params p;
  if (!check_true(mech != NULL) || !check_true(load("3pss.cfg", &arch, mech, &p, &err))) {
    free(mech);
    return;
  }
  p.maneuver.horizon = 0.03;
  const double q[2][3] = {{2.385e-3, -1.27e-3, 0.61e-3}, {-0.93e-3, 2.71e-3, -1.88e-3}};
  pom_fidelity_opts o;
  pom_fidelity_defaults(&o);
  o.accuracy = 1e-12;
  pom_fidelity_result res;
  check_true(pom_fidelity_select(&res, &arch, mech, &p, q, 1, q + 1, 1, &o, &err) == POM_OK);
  check_true(!res.met && res.rung == n - 1 && res.tried == n);
  check_true(res.bound_time > 0 || res.bound_energy > 0);
  o.accuracy = 0.01;
  o.margin = 0.5;
  check_true(pom_fidelity_select(&res, &arch, mech, &p, q, 1, q + 1, 1, &o, &err) == POM_ERR_ARG);
  o.margin = 2.0;
  check_true(pom_fidelity_select(&res, &arch, mech, &p, q, 0, q + 1, 1, &o, &err) == POM_ERR_ARG);
  free(mech);
}

int main(void) {
  test_rule();
  test_architecture("3pss.cfg");
  test_architecture("3sps.cfg");
  test_architecture("3rrr.cfg");
  return check_summary("test_fidelity");
}
