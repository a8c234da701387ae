/* test_dyn_platform_metrics.c - the platform-level metrics of a maneuver
 * (docs/results.md section 1b) against what the trace shows, on the
 * 3P-S-S/S with both joint formulations:
 *
 * 1. the target orientation is the rotation the setpoints were computed
 *    from (IK of a known R_t): final_pointing_error = angle(R_t, R(horizon))
 *    of the trace's quaternion, to the FK's tolerance;
 * 2. pointing_settling_time lies between the last output sample outside the
 *    band and the next one (the metric interpolates linearly);
 * 3. peak_angular_rate is at least the largest rate the trace shows by
 *    central differences of its quaternions (less their O(dt^2) error) and
 *    at most 2 % above it;
 * 4. peak_effort is at least the largest |K_m i - b q_dot| of the trace (the
 *    metric also sees the internal steps between samples) and at most
 *    0.1 % above it;
 * 5. the RMS tracking error is NaN for the PID and for a step reference,
 *    and for the minimum-jerk reference equals the time-averaged RMS of the
 *    angle to that reference recomputed here on the trace (trapezoid rule,
 *    within its Richardson error estimate);
 * 6. without the architecture (parasitic joints) the pointing metrics are
 *    NaN and the platform counts as unsettled. */
#include "check.h"
#include "dyn_test_util.h"
#include "pom_dyn_ctrl.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double angle_between(const double A[9], const double B[9]) {
  double At[9], E[9], rv[3];
  pom_m3_transpose(At, A);
  pom_m3_mul(E, At, B);
  pom_m3_rotvec(rv, E);
  return pom_v3_norm(rv);
}

/* The 3P-S-S/S with a maneuver to R_t = rotation by 0.0937 rad about a
 * skew axis; q receives the setpoints. */
static int setup(pom_kin_arch *arch, pom_mechanism *mech, pom_dyn_params *p, double Rt[9],
                 double q[3], pom_joint_model joints) {
  if (!load_shipped("3pss.cfg", arch, mech, p)) return 0;
  double axis[3] = {0.43, -0.71, 0.27};
  pom_v3_normalize(axis, axis);
  pom_m3_axis_angle(Rt, axis, 0.0937);
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_inverse(arch, Rt, q, &err) != POM_OK) return 0;
  p->joints.model = joints;
  p->scene.orientation = POM_ORIENT_QUATERNION;
  p->maneuver.horizon = 0.05;
  p->maneuver.output_dt = 2e-5;
  return 1;
}

static void check_pointing_and_peaks(pom_joint_model joints) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  double Rt[9], q[3];
  check_true(setup(&arch, &mech, &p, Rt, q, joints));
  run_t r;
  check_true(run_arch(&r, &mech, &arch, &p, q, NULL) == POM_OK);
  if (r.st != POM_OK) {
    run_free(&r);
    return;
  }
  const pom_dyn_trace *tr = r.tr;
  const int n = tr->n;
  double R[9];
  /* 1 */
  pom_quat_to_matrix(R, tr->quat + 4 * (n - 1));
  double e_final = angle_between(Rt, R);
  printf("  %s: final pointing error %.6e rad (trace %.6e)\n",
         joints == POM_JOINTS_RIGID ? "rigid" : "parasitic", r.mt.final_pointing_error, e_final);
  check_abs(r.mt.final_pointing_error, e_final, 1e-9);
  check_abs(r.mt.horizon, p.maneuver.horizon, 0.0);
  /* 2 */
  int last_out = -1;
  for (int k = 0; k < n; ++k) {
    pom_quat_to_matrix(R, tr->quat + 4 * k);
    if (angle_between(Rt, R) > p.maneuver.pointing_band) last_out = k;
  }
  check_true(r.mt.pointing_settled == 1 && last_out >= 0 && last_out < n - 1);
  if (last_out >= 0 && last_out < n - 1) {
    printf("  pointing settling time %.6f ms, last sample outside %.6f ms\n",
           r.mt.pointing_settling_time * 1e3, tr->t[last_out] * 1e3);
    check_true(r.mt.pointing_settling_time >= tr->t[last_out] - 1e-12 &&
               r.mt.pointing_settling_time <= tr->t[last_out + 1] + 1e-12);
  }
  /* 3: |omega| = 2 |q_dot| for a unit quaternion (central differences) */
  double rate_max = 0.0;
  for (int k = 1; k + 1 < n; ++k) {
    double dq = 0.0, h = tr->t[k + 1] - tr->t[k - 1];
    for (int i = 0; i < 4; ++i) {
      double v = (tr->quat[4 * (k + 1) + i] - tr->quat[4 * (k - 1) + i]) / h;
      dq += v * v;
    }
    rate_max = fmax(rate_max, 2.0 * sqrt(dq));
  }
  printf("  peak angular rate %.6f rad/s, trace %.6f rad/s\n", r.mt.peak_angular_rate, rate_max);
  check_true(r.mt.peak_angular_rate >= 0.999 * rate_max);
  check_true(r.mt.peak_angular_rate <= 1.02 * rate_max);
  /* 4 */
  const pom_dyn_actuator *ap = &p.actuator;
  for (int a = 0; a < 3; ++a) {
    double worst = 0.0;
    for (int k = 0; k < n; ++k) {
      double F = ap->force_constant * tr->current[3 * k + a] -
                 (p.scene.bearing_friction ? ap->bearing_friction : 0.0) * tr->q_dot[3 * k + a];
      worst = fmax(worst, fabs(F));
    }
    printf("  actuator %d: peak effort %.6f N, trace %.6f N\n", a + 1, r.mt.peak_effort[a], worst);
    check_true(r.mt.peak_effort[a] >= worst * (1 - 1e-12));
    check_true(r.mt.peak_effort[a] <= worst * 1.001);
  }
  /* 5: the PID follows no trajectory */
  check_true(isnan(r.mt.tracking_rms_error));
  run_free(&r);
}

/* Minimum-jerk s(t) over T. */
static double s_of(double t, double T) {
  double x = t >= T ? 1.0 : (t <= 0 ? 0.0 : t / T);
  return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
}

static void check_tracking(void) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  double Rt[9], q[3];
  check_true(setup(&arch, &mech, &p, Rt, q, POM_JOINTS_RIGID));
  pom_dyn_controller pid = p.controller;
  pom_dyn_ctrl_set_defaults(&p.controller, &pom_dyn_ctrl_pid_feedforward);
  p.controller.gain[0] = pid.kp;
  p.controller.gain[1] = pid.ki;
  p.controller.gain[2] = pid.kd;
  const double T = 0.0137;
  p.controller.gain[3] = T;
  p.solver.rtol = 1e-8; /* the shipped 1e-5 does not close the energy audit on this path */
  p.solver.atol_scale = 0.0;
  run_t r;
  check_true(run_arch(&r, &mech, &arch, &p, q, NULL) == POM_OK);
  if (r.st == POM_OK) {
    /* the reference about the axis of R_set = FK(q) = R_t */
    double rv[3], axis[3], sum1 = 0.0, sum2 = 0.0;
    pom_m3_rotvec(rv, Rt);
    double angle = pom_v3_normalize(axis, rv);
    const int n = r.tr->n;
    for (int k = 0; k < n; ++k) {
      double R[9], Rr[9];
      pom_quat_to_matrix(R, r.tr->quat + 4 * k);
      pom_m3_axis_angle(Rr, axis, s_of(r.tr->t[k], T) * angle);
      double e = angle_between(Rr, R);
      /* trapezoid weights on the grid (1) and on every other sample (2) */
      double w1 = (k == 0 || k == n - 1) ? 0.5 : 1.0;
      double w2 = (k == 0 || k == n - 1) ? 1.0 : (k % 2 == 0 ? 2.0 : 0.0);
      sum1 += w1 * e * e;
      sum2 += w2 * e * e;
    }
    /* the metric is a time average (Gauss-Legendre on every step): against
     * the trapezoid rule on the trace, whose error Richardson's estimate
     * |I_dt - I_2dt| / 3 bounds (n - 1 even: both rules end at the horizon) */
    const double dt = p.maneuver.output_dt, Tend = p.maneuver.horizon;
    check_true((n - 1) % 2 == 0);
    double I1 = sum1 * dt, I2 = sum2 * dt;
    double rms = sqrt(I1 / Tend);
    double tol = fabs(I1 - I2) / 3.0 / I1; /* relative, of the mean square */
    printf("  minimum-jerk reference: RMS tracking error %.6e rad (trapezoid on the trace "
           "%.6e, its error estimate %.2e rel.), pointing settling %.3f ms\n",
           r.mt.tracking_rms_error, rms, tol, r.mt.pointing_settling_time * 1e3);
    /* the mean square within 2x the trapezoid's estimated error (+1e-9 for
     * the Gauss-Legendre rule's own, O(h^4) per step) */
    check_rel(r.mt.tracking_rms_error * r.mt.tracking_rms_error, rms * rms, 2.0 * tol + 1e-9);
    check_true(r.mt.pointing_settled == 1);
  }
  run_free(&r);
  p.controller.option[0] = 1; /* the step reference: no trajectory */
  check_true(run_arch(&r, &mech, &arch, &p, q, NULL) == POM_OK);
  check_true(isnan(r.mt.tracking_rms_error));
  run_free(&r);
}

static void check_without_arch(void) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  double Rt[9], q[3];
  check_true(setup(&arch, &mech, &p, Rt, q, POM_JOINTS_PARASITIC));
  run_t r;
  check_true(run(&r, &mech, &p, q, NULL) == POM_OK);
  check_true(isnan(r.mt.pointing_settling_time) && isnan(r.mt.final_pointing_error));
  check_true(r.mt.pointing_settled == 0);
  check_true(r.mt.peak_angular_rate > 0.0 && r.mt.peak_effort[0] > 0.0);
  check_true(r.mt.settled[0] && r.mt.settled[1] && r.mt.settled[2]);
  run_free(&r);
}

int main(void) {
  check_pointing_and_peaks(POM_JOINTS_PARASITIC);
  check_pointing_and_peaks(POM_JOINTS_RIGID);
  check_tracking();
  check_without_arch();
  return check_summary("test_dyn_platform_metrics");
}
