/* test_dyn_stepinfo_crossing.c - a stepinfo settling time is right within
 * its stated error or flagged (docs/results.md section 1c, issue 30 items 1
 * and 9): a slow crossing, whose position resolution over the slope there
 * exceeds the stated error max(rtol x 10 s, 1 ns), is located again with
 * tightened tolerances, or reported NaN with stepinfo_unresolved when the
 * needed tightening is beyond the cap. Before, the tiny maneuvers below gave
 * times 0.10-0.18 ms off with a stated error of 10 us. */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* configs/<file> on the rigid path to target (SI), with rtol and
 * atol_scale (atol_scale < 0 keeps the file's) */
static pom_status run_rigid(run_t *r, const char *file, const double target[3], double rtol,
                            double atol_scale) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  memset(r, 0, sizeof *r);
  if (!load_shipped(file, &arch, &mech, &p)) return POM_ERR_ARG;
  p.joints.model = POM_JOINTS_RIGID;
  if (rtol > 0) p.solver.rtol = rtol;
  if (atol_scale >= 0) p.solver.atol_scale = atol_scale;
  return run_arch(r, &mech, &arch, &p, target, NULL);
}

/* CVODE's step count of the last integration of r (a re-run's when there
 * was one); mt.steps counts both */
static long last_steps(const run_t *r) {
  long v = -1;
  return CVodeGetNumSteps(r->d->cvode, &v) == CV_SUCCESS ? v : -1;
}

/* A tiny maneuver on the shipped tolerances (rtol 1e-6: stated error 10 us)
 * against the converged reference (natural tolerances, rtol 1e-10: stated
 * 1 ns): each stepinfo time resolved, by a re-run, and within 10 us + 1 ns. */
static void check_tiny(const char *file, const double target[3], const char *what) {
  run_t r, ref;
  check_true(run_rigid(&ref, file, target, 1e-10, 0.0) == POM_OK);
  check_true(run_rigid(&r, file, target, -1, -1) == POM_OK);
  const double stated = pom_dyn_stepinfo_time_tol(1e-6) + pom_dyn_stepinfo_time_tol(1e-10);
  check_abs(stated, 10.001e-6, 1e-15);
  for (int a = 0; a < 3; ++a) {
    printf("%s actuator %d: %.10g ms (reference %.10g ms), %ld steps (%ld in the re-run)\n", what,
           a + 1, 1e3 * r.mt.settling_time_final[a], 1e3 * ref.mt.settling_time_final[a],
           r.mt.steps, last_steps(&r));
    check_true(ref.mt.stepinfo_unresolved[a] == 0 && isfinite(ref.mt.settling_time_final[a]));
    check_true(r.mt.stepinfo_unresolved[a] == 0);
    check_abs(r.mt.settling_time_final[a], ref.mt.settling_time_final[a], stated);
  }
  /* the re-run happened and its work is counted */
  check_true(r.mt.steps > last_steps(&r) && last_steps(&r) > 0);
  run_free(&r);
  run_free(&ref);
}

static void test_tiny_resolved(void) {
  /* 1 um per slider (the extremes table's micro rows; before: 0.12 and
   * 0.18 ms off) */
  const double um[3] = {1e-6, -1e-6, 1e-6};
  check_tiny("3pss.cfg", um, "3P-S-S/S (1, -1, 1) um");
  check_tiny("3sps.cfg", um, "3S-P-S/S (1, -1, 1) um");
  /* 1 mdeg per crank (before: 0.11 ms off) */
  const double mdeg = 1e-3 * 3.14159265358979323846 / 180.0;
  const double rrr[3] = {mdeg, -mdeg, mdeg};
  check_tiny("3rrr.cfg", rrr, "3-RRR (1, -1, 1) mdeg");
}

/* The 3S-P-S/S at zero (a 0.18 um gravity sag): the crossing needs the
 * tolerances some 1.7e3 x tighter than shipped (1.7e4 against the stated
 * 1 us of rtol x 1 s), within the cap of 1e4 once the safety factor is
 * applied: re-run, and each time right within its stated error against the
 * converged reference or flagged (before the re-run: 0.10 ms off,
 * unflagged). */
static void test_zero_right_or_flagged(void) {
  const double zero[3] = {0, 0, 0};
  run_t r, ref;
  check_true(run_rigid(&ref, "3sps.cfg", zero, 1e-10, 0.0) == POM_OK);
  check_true(run_rigid(&r, "3sps.cfg", zero, -1, -1) == POM_OK);
  const double stated = pom_dyn_stepinfo_time_tol(1e-6) + pom_dyn_stepinfo_time_tol(1e-10);
  for (int a = 0; a < 3; ++a) {
    printf("3S-P-S/S (0, 0, 0) actuator %d: %.10g ms (reference %.10g ms), flag %d\n", a + 1,
           1e3 * r.mt.settling_time_final[a], 1e3 * ref.mt.settling_time_final[a],
           (int)r.mt.stepinfo_unresolved[a]);
    if (r.mt.stepinfo_unresolved[a]) {
      check_true(isnan(r.mt.settling_time_final[a]));
    } else {
      check_true(ref.mt.stepinfo_unresolved[a] == 0);
      check_abs(r.mt.settling_time_final[a], ref.mt.settling_time_final[a], stated);
    }
  }
  /* the re-run happened (it was flagged without one before) */
  check_true(r.mt.steps > last_steps(&r) && last_steps(&r) > 0);
  run_free(&r);
  run_free(&ref);
}

/* The shipped maneuver (3, -3, 3) mm: every crossing fast enough (res /
 * slope 0.3-0.6 us under 10 us), no re-run, the times unchanged. */
static void test_shipped_untouched(void) {
  const double step[3] = {3e-3, -3e-3, 3e-3};
  const char *files[2] = {"3pss.cfg", "3sps.cfg"};
  for (int f = 0; f < 2; ++f) {
    run_t r;
    check_true(run_rigid(&r, files[f], step, -1, -1) == POM_OK);
    check_true(r.mt.steps == last_steps(&r));
    for (int a = 0; a < 3; ++a) {
      check_true(r.mt.stepinfo_unresolved[a] == 0 && isfinite(r.mt.settling_time_final[a]));
      check_true(r.d->settle.stepinfo_need[a] == 0.0);
    }
    run_free(&r);
  }
}

int main(void) {
  test_tiny_resolved();
  test_zero_right_or_flagged();
  test_shipped_untouched();
  return check_summary("test_dyn_stepinfo_crossing");
}
