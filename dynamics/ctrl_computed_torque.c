/* ctrl_computed_torque.c - computed torque in orientation space
 * (docs/control.md section 2), a coupled, model-based controller type.
 *
 * From the sensors alone: the platform rotation R_m by the architecture's
 * forward kinematics of the measured actuator coordinates q, and its angular
 * velocity w_m = J(R_m)^-1 q_dot. The reference R_ref is the forward
 * kinematics of the actuator setpoints (a step: w_ref = 0, alpha_ref = 0).
 *   e       = rotvec(R_ref R_m^T)                (fixed frame, rad)
 *   alpha   = omega_n^2 e - 2 zeta omega_n w_m   (rad/s^2)
 *   tau     = M(R_m) alpha - f(R_m, w_m)         (N m: the controller's model)
 *   F       = J^-T tau                           (actuator efforts, N or N m)
 *   i       = (F + b q_dot) / K                  (coil current, A)
 *   u       = R_c i + K q_dot [+ (L / tau_i)(i - i_measured)]   (V)
 * M and f (gravity and velocity terms) come from the exact formulation of
 * the controller's own model (pom_dyn_exact_terms), built from the nominal
 * candidate; the engine saturates u like the PID's. With a perfect model, a
 * quasi-static coil and no saturation, w_dot = alpha exactly, so the error
 * obeys e'' + 2 zeta omega_n e' + omega_n^2 e = 0 to first order in |e|. */
#include "dyn_ctrl_model.h"
#include "pom_dyn_ctrl.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- descriptors ------------------------------------------------------------- */
static const pom_dyn_gain_desc ct_gains[] = {
    {.key = "omega_n_rad_per_s",
     .symbol = "omega_n",
     .unit = "rad/s",
     .meaning = "natural frequency of the orientation error's closed loop",
     .lo = 1e-3,
     .hi = 1e6,
     .def = 300.0,
     .tunable = 1,
     .log_search = 1,
     .offset = POM_DYN_CTRL_GAIN_SLOT(0),
     .search_default = 1,
     .search_lo = 50.0,
     .search_hi = 3000.0},
    {.key = "zeta",
     .symbol = "zeta",
     .unit = "1",
     .meaning = "damping ratio of the orientation error's closed loop",
     .lo = 0.0,
     .hi = 10.0,
     .def = 0.9,
     .tunable = 1,
     .log_search = 0,
     .offset = POM_DYN_CTRL_GAIN_SLOT(1),
     .search_default = 1,
     .search_lo = 0.3,
     .search_hi = 1.5},
    {.key = "current_loop_tau_s",
     .symbol = "tau_i",
     .unit = "s",
     .meaning = "inductive coil: time constant of the current loop that replaces L di/dt",
     .lo = 1e-9,
     .hi = 1.0,
     .def = 2e-5,
     .tunable = 0,
     .log_search = 1,
     .offset = POM_DYN_CTRL_GAIN_SLOT(2),
     .search_default = 0,
     .search_lo = 0.0,
     .search_hi = 0.0},
};

/* ---- the law --------------------------------------------------------------------- */
static void ct_fail(int n, double *u_raw) {
  for (int a = 0; a < n; ++a)
    u_raw[a] = NAN; /* a recoverable step failure (the engine's non-finite check) */
}

static pom_status ct_model_create(void **out, const pom_dyn_ctrl_engine *eng,
                                  const pom_dyn_controller *c, const pom_mechanism *mech,
                                  const pom_kin_arch *arch, const pom_dyn_params *p,
                                  pom_error *err) {
  (void)c;
  return pom_dyn_ctrl_model_create(out, eng, "computed_torque", mech, arch, p, err);
}

static void ct_law_all(const pom_dyn_controller *c, const void *model, void *work,
                       const pom_dyn_ctrl_sensed *s, double sensor_gain, const double *z,
                       double *u_raw, double *zdot) {
  (void)sensor_gain; /* the sensors give q in SI; K_S is the PID's scale */
  (void)z;
  (void)zdot;
  const dyn_ctrl_model *cm = model;
  dyn_ctrl_work *w = work;
  const double omega_n = c->gain[0], zeta = c->gain[1], tau_i = c->gain[2];
  if (s->n != 3 || !pom_dyn_ctrl_reference(cm, w, s->target)) {
    ct_fail(s->n, u_raw);
    return;
  }
  /* the measured rotation and angular velocity, from q and q_dot alone */
  double Rm[9], qm[3], J[9], wm[3];
  if (pom_kin_forward(&cm->arch, s->q, w->R_last, &w->fk, Rm, NULL, NULL) != POM_OK) {
    ct_fail(s->n, u_raw);
    return;
  }
  memcpy(w->R_last, Rm, sizeof Rm);
  if (pom_kin_inverse_jacobian(&cm->arch, Rm, qm, J, NULL) != POM_OK ||
      !pom_dyn_ctrl_solve3(wm, J, s->q_dot)) {
    ct_fail(s->n, u_raw);
    return;
  }
  /* error rotation vector (fixed frame) and the desired angular acceleration */
  double Re[9], e[3], alpha[3], F[3];
  pom_m3_mult(Re, w->R_set, Rm);
  pom_m3_rotvec(e, Re);
  for (int k = 0; k < 3; ++k)
    alpha[k] = omega_n * omega_n * e[k] - 2.0 * zeta * omega_n * wm[k];
  if (!pom_dyn_ctrl_inverse_dynamics(cm, w, Rm, wm, alpha, F, qm, J)) {
    ct_fail(s->n, u_raw);
    return;
  }
  /* the coil's inverse; a current loop in place of L di/dt when inductive */
  for (int a = 0; a < 3; ++a) {
    double i = 0.0;
    u_raw[a] = pom_dyn_ctrl_coil_voltage(cm, F[a], s->q_dot[a], &i);
    if (s->current) u_raw[a] += cm->act.inductance / tau_i * (i - s->current[a]);
  }
}

static int ct_describe(const pom_dyn_controller *c, char *buf, size_t cap) {
  return snprintf(buf, cap,
                  "computed torque, alpha = omega_n^2 rotvec(R_ref R^T) - 2 zeta omega_n omega "
                  "through the model's M, f and J, omega_n %g rad/s, zeta %g, current loop %g s",
                  c->gain[0], c->gain[1], c->gain[2]);
}

const pom_dyn_ctrl_type pom_dyn_ctrl_computed_torque = {
    .name = "computed_torque",
    .label = "computed torque",
    .description = "orientation-space computed torque through the candidate's nominal model, "
                   "from the actuator sensors by forward kinematics",
    .n_states = 0,
    .states = NULL,
    .rate_deps = 0,
    .n_gains = 3,
    .gains = ct_gains,
    .n_options = 0,
    .options = NULL,
    .law = NULL,
    .partials = NULL,
    .describe = ct_describe,
    .model_create = ct_model_create,
    .model_destroy = pom_dyn_ctrl_model_destroy,
    .work_create = pom_dyn_ctrl_work_create,
    .work_destroy = pom_dyn_ctrl_work_destroy,
    .law_all = ct_law_all,
};
