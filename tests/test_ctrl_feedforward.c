/* test_ctrl_feedforward.c - the PID with inverse-dynamics feedforward along a
 * minimum-jerk reference (dynamics/ctrl_pid_feedforward.c, docs/control.md
 * section 3) on the three shipped architectures.
 *
 * 1. Feedforward alone tracks. Plant = the controller's model (rigid joints,
 *    quasi-static coil), no saturation (a 5 mrad rotation in T = 20 ms),
 *    feedback gains zero (K_P = 0 silences the whole ideal PID). The
 *    reference starts where the plant starts (home, at rest, zero
 *    acceleration), and the feedforward makes w_dot = alpha_ref whenever the
 *    plant is on the reference: by uniqueness the plant stays on it, and the
 *    tracking error is what the integration leaves. Open loop, that error
 *    grows at worst like a double integrator of the acceleration error: with
 *    a relative acceleration error eps (the integrator's, rtol 1e-10 with
 *    natural tolerances: eps <= 1e-7 at most) the angle error after T is at
 *    most eps |r| (T^2/2 alpha_max / |r|) = eps |r| 5.8 (alpha_max = 5.77 |r|
 *    / T^2 for the minimum jerk), and it keeps that offset after T (no
 *    feedback): bound 1e-6 |r|, measured far below.
 * 2. The feedforward earns its keep: with the shipped PID gains, the largest
 *    tracking error over the maneuver is smaller with the feedforward than
 *    without (the PID alone on the same reference). */
#include "check.h"
#include "dyn_test_util.h"
#include "pom_dyn_ctrl.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define T_REF 0.02 /* s */

static const char *const files[] = {"3pss.cfg", "3sps.cfg", "3rrr.cfg"};

/* Minimum-jerk s(t). */
static double s_of(double t) {
  double x = t >= T_REF ? 1.0 : (t <= 0 ? 0.0 : t / T_REF);
  return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
}

/* Largest angle between the plant and the reference rotation over the
 * trace (rad). */
static double tracking_error(const pom_dyn_trace *tr, const double r[3]) {
  double axis[3], worst = 0.0;
  double angle = pom_v3_normalize(axis, r);
  for (int k = 0; k < tr->n; ++k) {
    double R[9], Rr[9], Re[9], e[3];
    pom_quat_to_matrix(R, tr->quat + 4 * k);
    pom_m3_axis_angle(Rr, axis, s_of(tr->t[k]) * angle);
    pom_m3_mult(Re, Rr, R);
    pom_m3_rotvec(e, Re);
    worst = fmax(worst, pom_v3_norm(e));
  }
  return worst;
}

/* One run of file with the feedforward controller; the largest tracking
 * error, or -1 on failure. */
static double run_ff(const char *file, double angle, int zero_gains, int feedforward,
                     double *saturation) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!load_shipped(file, &arch, &mech, &p)) return -1.0;
  pom_dyn_controller pid = p.controller; /* the shipped PID gains */
  pom_dyn_ctrl_set_defaults(&p.controller, &pom_dyn_ctrl_pid_feedforward);
  p.controller.gain[0] = zero_gains ? 0.0 : pid.kp;
  p.controller.gain[1] = pid.ki;
  p.controller.gain[2] = pid.kd;
  p.controller.gain[3] = T_REF;
  p.controller.option[1] = feedforward ? 0 : 1;
  p.joints.model = POM_JOINTS_RIGID;
  p.scene.coil_inductance = 0;
  p.scene.orientation = POM_ORIENT_QUATERNION;
  p.solver.rtol = 1e-10;
  p.solver.atol_scale = 0.0;
  p.maneuver.horizon = 0.04;
  p.maneuver.output_dt = 2e-5;
  double r[3] = {0.6, -0.5, 0.62}, axis[3], Rt[9], q[3];
  pom_v3_normalize(axis, r);
  pom_v3_scale(r, angle, axis);
  pom_m3_axis_angle(Rt, axis, angle);
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_inverse(&arch, Rt, q, &err) != POM_OK) return -1.0;
  run_t run;
  double worst = -1.0;
  if (run_arch(&run, &mech, &arch, &p, q, NULL) == POM_OK) {
    worst = tracking_error(run.tr, r);
    *saturation = run.mt.saturation_time[0] + run.mt.saturation_time[1] + run.mt.saturation_time[2];
  }
  run_free(&run);
  return worst;
}

int main(void) {
  for (int c = 0; c < 3; ++c) {
    const double angle = 5e-3;
    double sat = 0.0;
    double e_ff = run_ff(files[c], angle, 1, 1, &sat);
    printf("  %s: feedforward alone, largest tracking error %.3e rad = %.3e of the rotation, "
           "saturated %g s\n",
           files[c], e_ff, e_ff / angle, sat);
    check_true(e_ff >= 0.0);
    check_abs(sat, 0.0, 0.0);
    check_true(e_ff <= 1e-6 * angle);
    /* 2: with the PID's gains, on a larger rotation */
    double sat2 = 0.0, sat3 = 0.0;
    double with = run_ff(files[c], 0.05, 0, 1, &sat2);
    double without = run_ff(files[c], 0.05, 0, 0, &sat3);
    printf("  %s: 0.05 rad with the PID gains: tracking error %.3e rad with the feedforward, "
           "%.3e rad without\n",
           files[c], with, without);
    check_true(with >= 0.0 && without > 0.0 && with < without);
  }
  return check_summary("test_ctrl_feedforward");
}
