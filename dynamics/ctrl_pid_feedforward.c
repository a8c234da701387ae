/* ctrl_pid_feedforward.c - the PID on the tracking error of a reference
 * trajectory, plus the inverse-dynamics feedforward along it
 * (docs/control.md section 3). Coupled (the reference lives in platform
 * space) and model-based; one state per actuator, the integral of the
 * tracking error.
 *
 * Reference, from home at rest to R_set = FK(q_set) about the fixed axis of
 * r = rotvec(R_set), with s(t) the profile (step: s = 1; minimum jerk over
 * T: s = 10 x^3 - 15 x^4 + 6 x^5, x = t / T clipped to [0, 1]):
 *   R_ref = exp([s r]x), w_ref = s' r, alpha_ref = s'' r   (exact: a fixed axis)
 *   q_ref = IK(R_ref), q_dot_ref = J(R_ref) w_ref
 * Feedforward through the controller's model: F = J^-T (M alpha_ref - f),
 * u_ff = R_c i + K q_dot_ref with i = (F + b q_dot_ref) / K (+ L di/dt for
 * an inductive coil, by a central difference of the reference's current).
 * Feedback, per actuator, the ideal PID on e = q_ref - q:
 *   u = u_ff + K_S K_P (e + K_I z - tau_D (q_dot - q_dot_ref)),  z_dot = e. */
#include "dyn_ctrl_model.h"
#include "pom_dyn_ctrl.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const profiles[] = {"min_jerk", "step", NULL};
static const char *const switches[] = {"on", "off", NULL};

static const pom_dyn_ctrl_state_desc ff_states[] = {
    {.name = "integral",
     .meaning = "integral of the tracking error q_ref - q (m s or rad s)",
     .kind = POM_DYN_CTRL_STATE_Q_TIME},
};

static const pom_dyn_gain_desc ff_gains[] = {
    {.key = "kp",
     .symbol = "K_P",
     .unit = "V/V",
     .meaning = "proportional gain on K_S (q_ref - q)",
     .lo = 0.0,
     .hi = 1e12,
     .def = 1.2e4,
     .tunable = 1,
     .log_search = 1,
     .offset = POM_DYN_CTRL_GAIN_SLOT(0),
     .search_default = 1,
     .search_lo = 1e2,
     .search_hi = 1e5},
    {.key = "ki_per_s",
     .symbol = "K_I",
     .unit = "1/s",
     .meaning = "integral factor of the tracking error",
     .lo = 0.0,
     .hi = 1e9,
     .def = 1.0e-3,
     .tunable = 1,
     .log_search = 1,
     .offset = POM_DYN_CTRL_GAIN_SLOT(1),
     .search_default = 0,
     .search_lo = 1e-4,
     .search_hi = 1e2},
    {.key = "kd_s",
     .symbol = "tau_D",
     .unit = "s",
     .meaning = "derivative time on the rate error",
     .lo = 0.0,
     .hi = 1e3,
     .def = 3.0e-3,
     .tunable = 1,
     .log_search = 1,
     .offset = POM_DYN_CTRL_GAIN_SLOT(2),
     .search_default = 1,
     .search_lo = 5e-4,
     .search_hi = 2e-2},
    {.key = "trajectory_duration_s",
     .symbol = "T",
     .unit = "s",
     .meaning = "duration of the minimum-jerk reference",
     .lo = 1e-5,
     .hi = 1.0,
     .def = 0.01,
     .tunable = 1,
     .log_search = 1,
     .offset = POM_DYN_CTRL_GAIN_SLOT(3),
     .search_default = 1,
     .search_lo = 2e-3,
     .search_hi = 4e-2},
};

static const pom_dyn_ctrl_option_desc ff_options[] = {
    {.key = "reference",
     .meaning = "min_jerk: minimum-jerk rotation over T about a fixed axis; step: the setpoint",
     .names = profiles,
     .offset = POM_DYN_CTRL_OPTION_SLOT(0)},
    {.key = "feedforward",
     .meaning = "on: the inverse dynamics along the reference; off: the PID alone",
     .names = switches,
     .offset = POM_DYN_CTRL_OPTION_SLOT(1)},
};

/* ---- the reference -------------------------------------------------------------- */
/* Profile s and its first two time derivatives at t. */
static void profile(double out[3], int step, double t, double T) {
  if (step || t >= T) {
    out[0] = 1.0, out[1] = 0.0, out[2] = 0.0;
    return;
  }
  if (t <= 0.0) {
    out[0] = out[1] = out[2] = 0.0;
    return;
  }
  double x = t / T, x2 = x * x, x3 = x2 * x;
  out[0] = x3 * (10.0 - 15.0 * x + 6.0 * x2);
  out[1] = 30.0 * x2 * (1.0 - 2.0 * x + x2) / T;
  out[2] = 60.0 * x * (1.0 - 3.0 * x + 2.0 * x2) / (T * T);
}

/* The reference's rotation R at t (w->R_set, r_set set); r = rotvec(R_set) and the
 * profile s into r, s. */
static void reference_rotation_at(const dyn_ctrl_work *w, const pom_dyn_controller *c, double t,
                                  double R[9], double r[3], double s[3]) {
  double axis[3];
  pom_v3_copy(r, w->r_set); /* rotvec(R_set), computed once per maneuver */
  double angle = pom_v3_normalize(axis, r);
  profile(s, c->option[0] == 1, t, c->gain[3]);
  if (angle > 0.0)
    pom_m3_axis_angle(R, axis, s[0] * angle);
  else
    pom_m3_identity(R);
}

/* The reference at t: rotation, angular velocity and acceleration, and the
 * feedforward efforts F with q_ref, J there. 0 on failure. */
static int reference_at(const dyn_ctrl_model *cm, dyn_ctrl_work *w, const pom_dyn_controller *c,
                        double t, double R[9], double wr[3], double F[3], double q[3],
                        double J[9]) {
  double r[3], s[3], alpha[3];
  reference_rotation_at(w, c, t, R, r, s);
  pom_v3_scale(wr, s[1], r);
  pom_v3_scale(alpha, s[2], r);
  return pom_dyn_ctrl_inverse_dynamics(cm, w, R, wr, alpha, F, q, J);
}

/* ---- the law ---------------------------------------------------------------------- */
static pom_status ff_model_create(void **out, const pom_dyn_ctrl_engine *eng,
                                  const pom_dyn_controller *c, const pom_mechanism *mech,
                                  const pom_kin_arch *arch, const pom_dyn_params *p,
                                  pom_error *err) {
  (void)c;
  return pom_dyn_ctrl_model_create(out, eng, "pid_feedforward", mech, arch, p, err);
}

static void ff_law_all(const pom_dyn_controller *c, const void *model, void *work,
                       const pom_dyn_ctrl_sensed *s, double sensor_gain, const double *z,
                       double *u_raw, double *zdot) {
  const dyn_ctrl_model *cm = model;
  dyn_ctrl_work *w = work;
  const double kp = c->gain[0], ki = c->gain[1], kd = c->gain[2];
  const int feedforward = c->option[1] == 0;
  double R[9], wr[3], F[3], qr[3], J[9], qdr[3];
  if (s->n != 3 || !pom_dyn_ctrl_reference(cm, w, s->target) ||
      !reference_at(cm, w, c, s->t, R, wr, F, qr, J)) {
    for (int a = 0; a < s->n; ++a)
      u_raw[a] = NAN; /* a recoverable step failure */
    return;
  }
  pom_m3_apply(qdr, J, wr);
  double di[3] = {0.0, 0.0, 0.0};
  if (feedforward && s->current) {
    /* L di/dt of the reference's current, by a central difference in t */
    const double h = 1e-3 * c->gain[3];
    double R2[9], w2[3], F2[3], q2[3], J2[9], qd2[3], sgn = 1.0;
    for (int side = 0; side < 2; ++side, sgn = -1.0) {
      if (!reference_at(cm, w, c, s->t + sgn * h, R2, w2, F2, q2, J2)) break;
      pom_m3_apply(qd2, J2, w2);
      for (int a = 0; a < 3; ++a) {
        double i = 0.0;
        (void)pom_dyn_ctrl_coil_voltage(cm, F2[a], qd2[a], &i);
        di[a] += sgn * i / (2.0 * h);
      }
    }
  }
  for (int a = 0; a < 3; ++a) {
    double e = qr[a] - s->q[a];
    double u_ff = feedforward ? pom_dyn_ctrl_coil_voltage(cm, F[a], qdr[a], NULL) +
                                    cm->act.inductance * (s->current ? di[a] : 0.0)
                              : 0.0;
    u_raw[a] = u_ff + sensor_gain * kp * (e + ki * z[a] - kd * (s->q_dot[a] - qdr[a]));
    if (zdot) zdot[a] = e;
  }
}

/* The minimum-jerk reference's rotation at t; 0 for the step reference
 * (no trajectory: its tracking error would be the pointing error). */
static int ff_reference_rotation(const pom_dyn_controller *c, const void *model, void *work,
                                 double t, const double target[3], double R[9]) {
  double r[3], s[3];
  if (c->option[0] == 1 || !pom_dyn_ctrl_reference(model, work, target)) return 0;
  reference_rotation_at(work, c, t, R, r, s);
  return 1;
}

static int ff_describe(const pom_dyn_controller *c, char *buf, size_t cap) {
  return snprintf(buf, cap,
                  "PID on the tracking error of a %s reference (T %g s), feedforward %s, K_P %g, "
                  "K_I %g 1/s, tau_D %g s",
                  pom_cfg_choice_name(profiles, c->option[0]), c->gain[3],
                  pom_cfg_choice_name(switches, c->option[1]), c->gain[0], c->gain[1], c->gain[2]);
}

const pom_dyn_ctrl_type pom_dyn_ctrl_pid_feedforward = {
    .name = "pid_feedforward",
    .label = "PID with feedforward",
    .description = "ideal PID on the tracking error of a minimum-jerk platform reference, plus "
                   "the inverse dynamics of the nominal model along it",
    .n_states = 1,
    .states = ff_states,
    .rate_deps = 0,
    .n_gains = 4,
    .gains = ff_gains,
    .n_options = 2,
    .options = ff_options,
    .law = NULL,
    .partials = NULL,
    .describe = ff_describe,
    .model_create = ff_model_create,
    .model_destroy = pom_dyn_ctrl_model_destroy,
    .work_create = pom_dyn_ctrl_work_create,
    .work_destroy = pom_dyn_ctrl_work_destroy,
    .law_all = ff_law_all,
    .reference_rotation = ff_reference_rotation,
};
