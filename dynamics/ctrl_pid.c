/* ctrl_pid.c - the PID of the paper, ideal or parallel form
 * (docs/dynamics.md section 4), as a controller type: one state per actuator
 * (the integral of the error), the derivative on the measured rate.
 *   ideal:    u = K_S K_P (e + K_I z - tau_D q_dot)
 *   parallel: u = K_S (K_P e + K_I z - K_D q_dot)
 * with e = q_set - q and z_dot = e; the engine saturates u. */
#include "pom_dyn_ctrl.h"

#include <stdio.h>

/* indexed by pom_pid_form */
static const char *const pid_forms[] = {"ideal", "parallel", NULL};
_Static_assert(POM_PID_IDEAL == 0 && POM_PID_PARALLEL == 1, "pid_forms follows pom_pid_form");

static const pom_dyn_ctrl_state_desc pid_states[] = {
    {.name = "integral",
     .meaning = "integral of the error e = q_set - q (m s or rad s)",
     .kind = POM_DYN_CTRL_STATE_Q_TIME},
};

static const pom_dyn_gain_desc pid_gains[] = {
    {.key = "kp",
     .symbol = "K_P",
     .unit = "V/V",
     .meaning = "proportional gain (on K_S e)",
     .lo = 0.0,
     .hi = 1e12,
     .def = 1.2e4,
     .tunable = 1,
     .log_search = 1,
     .offset = offsetof(pom_dyn_controller, kp),
     .search_default = 1,
     .search_lo = 1e2,
     .search_hi = 1e5},
    {.key = "ki_per_s",
     .symbol = "K_I",
     .unit = "1/s",
     .meaning = "integral gain: ideal, factor of int e; parallel, K_I",
     .lo = 0.0,
     .hi = 1e9,
     .def = 1.0e-3,
     .tunable = 1,
     .log_search = 1,
     .offset = offsetof(pom_dyn_controller, ki),
     .search_default = 0,
     .search_lo = 1e-4,
     .search_hi = 1e2},
    {.key = "kd_s",
     .symbol = "tau_D",
     .unit = "s",
     .meaning = "derivative time: ideal, tau_D; parallel, K_D",
     .lo = 0.0,
     .hi = 1e3,
     .def = 3.0e-3,
     .tunable = 1,
     .log_search = 1,
     .offset = offsetof(pom_dyn_controller, kd),
     .search_default = 1,
     .search_lo = 5e-4,
     .search_hi = 2e-2},
};

static const pom_dyn_ctrl_option_desc pid_options[] = {
    {.key = "form",
     .meaning =
         "ideal: K_S K_P (e + K_I z - tau_D q_dot); parallel: K_S (K_P e + K_I z - K_D q_dot)",
     .names = pid_forms,
     .offset = offsetof(pom_dyn_controller, form)},
};

/* ---- the law ------------------------------------------------------------------ */
static double pid_law(const pom_dyn_controller *c, const pom_dyn_ctrl_input *in, const double *z,
                      double *zdot) {
  double e = in->target - in->q;
  double u_raw;
  if (c->form == POM_PID_IDEAL)
    u_raw = in->sensor_gain * c->kp * (e + c->ki * z[0] - c->kd * in->q_dot);
  else
    u_raw = in->sensor_gain * (c->kp * e + c->ki * z[0] - c->kd * in->q_dot);
  if (zdot) zdot[0] = e;
  return u_raw;
}

/* ---- its derivatives ------------------------------------------------------------ */
/* u is linear in e (hence q), z and q_dot; z_dot = e reads q alone. */
static void pid_partials(const pom_dyn_controller *c, const pom_dyn_ctrl_input *in, const double *z,
                         pom_dyn_ctrl_partials *out) {
  (void)z;
  const double S = in->sensor_gain;
  *out = (pom_dyn_ctrl_partials){0};
  if (c->form == POM_PID_IDEAL) {
    out->du_dq = -S * c->kp;
    out->du_dz[0] = S * c->kp * c->ki;
    out->du_dqd = -S * c->kp * c->kd;
  } else {
    out->du_dq = -S * c->kp;
    out->du_dz[0] = S * c->ki;
    out->du_dqd = -S * c->kd;
  }
  out->dzd_dq[0] = -1.0;
}

static int pid_describe(const pom_dyn_controller *c, char *buf, size_t cap) {
  if (c->form == POM_PID_IDEAL)
    return snprintf(buf, cap,
                    "ideal PID u = sat(K_S K_P (e + K_I int e - tau_D q_dot)), K_P %g, K_I %g 1/s, "
                    "tau_D %g s",
                    c->kp, c->ki, c->kd);
  return snprintf(buf, cap,
                  "parallel PID u = sat(K_S (K_P e + K_I int e - K_D q_dot)), K_P %g, K_I %g 1/s, "
                  "K_D %g s",
                  c->kp, c->ki, c->kd);
}

const pom_dyn_ctrl_type pom_dyn_ctrl_pid = {
    .name = "pid",
    .label = "PID",
    .description = "the paper's PID on each actuator, derivative on the measured rate",
    .n_states = 1,
    .states = pid_states,
    .rate_deps = 0,
    .n_gains = 3,
    .gains = pid_gains,
    .n_options = 1,
    .options = pid_options,
    .law = pid_law,
    .partials = pid_partials,
    .describe = pid_describe,
};
