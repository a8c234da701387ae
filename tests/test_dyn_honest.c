/* test_dyn_honest.c - what a maneuver did not resolve or did not compute is
 * reported as NaN, never as a number (docs/results.md sections 1c and 1d):
 * the stepinfo settling time of a motion whose band lies below the
 * integration's resolution, and the end-of-run metrics of a failed
 * maneuver. */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Runs configs/<file> to target (SI) with the joints model and tolerances
 * given (atol_scale < 0 keeps the file's). */
static pom_status run_cfg(run_t *r, const char *file, pom_joint_model joints,
                          const double target[3], double rtol, double atol_scale) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  memset(r, 0, sizeof *r);
  if (!load_shipped(file, &arch, &mech, &p)) return POM_ERR_ARG;
  p.joints.model = joints;
  if (rtol > 0) p.solver.rtol = rtol;
  if (atol_scale >= 0) p.solver.atol_scale = atol_scale;
  return run_arch(r, &mech, &arch, &p, target, NULL);
}

/* Item 1 with the re-run (section 1c): a stepinfo time of r is right
 * within its stated error against the converged run (natural tolerances,
 * rtol 1e-10, or 1e-8 where 1e-10 leaves the band unresolved, as
 * bench/extremes.py) or flagged NaN. */
static void check_right_or_flagged(const run_t *r, const char *file, pom_joint_model joints,
                                   const double target[3], int a) {
  run_t ref;
  double ref_rtol = 1e-10;
  check_true(run_cfg(&ref, file, joints, target, ref_rtol, 0.0) == POM_OK);
  if (ref.mt.stepinfo_unresolved[a]) { /* a band 1e-10 does not resolve: 1e-8's */
    run_free(&ref);
    ref_rtol = 1e-8;
    check_true(run_cfg(&ref, file, joints, target, ref_rtol, 0.0) == POM_OK);
  }
  const double stated = pom_dyn_stepinfo_time_tol(1e-6) + pom_dyn_stepinfo_time_tol(ref_rtol);
  printf("%s actuator %d: %.10g ms (converged %.10g ms), flag %d\n", file, a + 1,
         1e3 * r->mt.settling_time_final[a], 1e3 * ref.mt.settling_time_final[a],
         (int)r->mt.stepinfo_unresolved[a]);
  if (r->mt.stepinfo_unresolved[a]) {
    check_true(isnan(r->mt.settling_time_final[a]));
  } else {
    check_true(ref.mt.stepinfo_unresolved[a] == 0);
    check_abs(r->mt.settling_time_final[a], ref.mt.settling_time_final[a], stated);
  }
  run_free(&ref);
}

/* Item 1: a band below the resolution gives NaN and the flag; a resolved one
 * a time that agrees with the converged one. */
static void test_unresolved_stepinfo(void) {
  const double zero[3] = {0, 0, 0}, mixed[3] = {3e-3, 0, -3e-3};
  run_t r;
  /* 3P-S-S/S, rigid, shipped tolerances: the whole motion is a 38 nm gravity
   * sag, its 0.8 nm band under the 1 nm absolute tolerance of the
   * orientation carried to q (it printed 67.92 ms; converged: 11.70 ms) */
  check_true(run_cfg(&r, "3pss.cfg", POM_JOINTS_RIGID, zero, -1, -1) == POM_OK);
  for (int a = 0; a < 3; ++a) {
    check_true(isnan(r.mt.settling_time_final[a]));
    check_true(r.mt.stepinfo_unresolved[a] == 1);
  }
  double res[3];
  pom_dyn_position_resolution(r.m, r.d->yfinal, N_VGetArrayPointer(r.d->ytmp), res);
  for (int a = 0; a < 3; ++a)
    check_true(res[a] > 1e-9 && res[a] < 1e-8);
  run_free(&r);
  /* the same with natural tolerances at rtol 1e-8: resolved, the converged
   * time (rtol 1e-6 ... 1e-10 give 11.67-11.70 ms) */
  check_true(run_cfg(&r, "3pss.cfg", POM_JOINTS_RIGID, zero, 1e-8, 0.0) == POM_OK);
  for (int a = 0; a < 3; ++a) {
    check_true(r.mt.stepinfo_unresolved[a] == 0);
    check_abs(r.mt.settling_time_final[a], 11.703e-3, 0.01e-3);
  }
  run_free(&r);
  /* (3, 0, -3) mm: the zero actuator (6.63 ms printed, 5.06 ms converged)
   * re-run (stated 10 us) and right, or flagged; the moving ones resolved
   * and unchanged */
  check_true(run_cfg(&r, "3pss.cfg", POM_JOINTS_RIGID, mixed, -1, -1) == POM_OK);
  check_right_or_flagged(&r, "3pss.cfg", POM_JOINTS_RIGID, mixed, 1);
  check_true(r.mt.stepinfo_unresolved[0] == 0 && r.mt.stepinfo_unresolved[2] == 0);
  check_abs(r.mt.settling_time_final[0], 12.8236e-3, 0.001e-3);
  check_abs(r.mt.settling_time_final[2], 12.7865e-3, 0.001e-3);
  run_free(&r);
  /* 3-RRR at zero on the parasitic path (printed 5 % off before the
   * re-run; flagged beyond the cap while the stated error was rtol x 1 s).
   * OPEN (issue 30 item 1, stated error 10 us): the re-run now resolves it
   * by its own test and reports 11.597 ms unflagged, but neither converged
   * run (rtol 1e-10 nor 1e-8, natural tolerances) resolves its band, so
   * the time is not verified; the run carries the rigid-limit warning
   * (docs/extremes.md, zero-3rrr-parasitic). Checked: the references stay
   * unresolved (when one resolves, this must become right-or-flagged). */
  check_true(run_cfg(&r, "3rrr.cfg", POM_JOINTS_PARASITIC, zero, -1, -1) == POM_OK);
  for (int a = 0; a < 3; ++a) {
    run_t ref;
    printf("3rrr.cfg parasitic zero actuator %d: %.10g ms, flag %d (unverified)\n", a + 1,
           1e3 * r.mt.settling_time_final[a], (int)r.mt.stepinfo_unresolved[a]);
    check_true(isnan(r.mt.settling_time_final[a]) == (r.mt.stepinfo_unresolved[a] == 1));
    for (double rt = 1e-10; rt < 2e-8; rt *= 100) {
      check_true(run_cfg(&ref, "3rrr.cfg", POM_JOINTS_PARASITIC, zero, rt, 0.0) == POM_OK);
      check_true(ref.mt.stepinfo_unresolved[a] == 1);
      run_free(&ref);
    }
  }
  run_free(&r);
  /* an ordinary maneuver: every band resolved */
  const double step[3] = {3e-3, -3e-3, 3e-3};
  check_true(run_cfg(&r, "3pss.cfg", POM_JOINTS_PARASITIC, step, -1, -1) == POM_OK);
  for (int a = 0; a < 3; ++a)
    check_true(isfinite(r.mt.settling_time_final[a]) && r.mt.stepinfo_unresolved[a] == 0);
  run_free(&r);
}

/* The not-computed metrics of a failed run are NaN; the extremes over the
 * steps taken stay finite. */
static void check_failed(const pom_dyn_metrics *mt, int watched) {
  for (int a = 0; a < 3; ++a) {
    check_true(isnan(mt->energy[a]) && isnan(mt->energy_positive[a]));
    check_true(isnan(mt->energy_coil[a]) && isnan(mt->energy_bearing[a]));
    check_true(isnan(mt->saturation_time[a]));
    check_true(isnan(mt->final_q[a]) && isnan(mt->max_abs_q[a]));
    check_true(isnan(mt->settling_time[a]) && isnan(mt->settling_time_final[a]));
    check_true(mt->settled[a] == 0 && mt->stepinfo_unresolved[a] == 0);
    check_true(watched ? isfinite(mt->peak_voltage[a]) : isnan(mt->peak_voltage[a]));
    check_true(watched ? isfinite(mt->peak_effort[a]) : isnan(mt->peak_effort[a]));
  }
  check_true(isnan(mt->energy_total) && isnan(mt->energy_supplied) &&
             isnan(mt->energy_dissipated) && isnan(mt->energy_stored_change) &&
             isnan(mt->energy_parasitic) && isnan(mt->energy_balance_scale));
  check_true(isnan(mt->energy_balance_error));
  check_true(isnan(mt->execution_time) && isnan(mt->final_pointing_error));
  check_true(watched ? isfinite(mt->peak_angular_rate) : isnan(mt->peak_angular_rate));
  check_true(watched ? isfinite(mt->max_deflection) : isnan(mt->max_deflection));
}

/* Item 6: the short-link 3P-S-S/S of tests/test_dynamics_exact.c (links 2.0
 * times the platform radius) driven to the stroke ends (6, -6, 6) mm stops at
 * the dexterity floor (POM_ERR_SINGULAR) after 4.4 ms. */
static void test_failed_maneuver(void) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  check_true(load_shipped("3pss.cfg", &arch, &mech, &p));
  char path[512];
  snprintf(path, sizeof path, "%s/configs/3pss.cfg", POM_SOURCE_DIR);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_kin_inertia in;
  check_true(pom_cfg_load(&cfg, path, &err) == POM_OK &&
             pom_kin_inertia_load(&in, &arch, cfg, &err) == POM_OK);
  pom_cfg_destroy(cfg);
  pom_kin_design dz = {0.012, {0.5 * POM_PI, 0.0, 2.0, 80.0 * POM_DEG, 60.0 * POM_DEG, 0.0, 0.0}};
  pom_kin_arch z;
  pom_mechanism zm;
  check_true(pom_kin_arch_from_design(&z, pom_kin_arch_type_find("3PSS"), &dz, &err) == POM_OK);
  check_true(pom_kin_mechanism_from(&zm, &z, &in, &err) == POM_OK);
  p.joints.model = POM_JOINTS_RIGID;
  p.maneuver.horizon = 0.03;
  const double corner[3] = {6e-3, -6e-3, 6e-3};
  run_t r;
  pom_status st = run_arch(&r, &zm, &z, &p, corner, NULL);
  printf("short links to (6, -6, 6) mm: %s (%ld steps)\n", r.mt.reason, r.mt.steps);
  check_true(st == POM_ERR_SINGULAR && r.mt.status == st && r.mt.steps > 0);
  check_failed(&r.mt, 1);
  check_true(r.mt.peak_voltage[0] > 0 && r.mt.peak_angular_rate > 0);
  run_free(&r);
  /* refused before any work (a target outside the stroke): nothing watched */
  const double out[3] = {7e-3, 0, 0};
  check_true(run_arch(&r, &mech, &arch, &p, out, NULL) == POM_ERR_LIMIT);
  check_failed(&r.mt, 0);
  check_true(r.mt.target[0] == 7e-3 && r.mt.horizon == p.maneuver.horizon);
  run_free(&r);
}

int main(void) {
  test_unresolved_stepinfo();
  test_failed_maneuver();
  return check_summary("test_dyn_honest");
}
