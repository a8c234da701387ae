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
#include "pom_dyn_ctrl.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- descriptors ------------------------------------------------------------- */
static const pom_dyn_gain_desc ct_gains[] = {
    {"omega_n_rad_per_s", "omega_n", "rad/s",
     "natural frequency of the orientation error's closed loop", 1e-3, 1e6, 300.0, 1, 1,
     POM_DYN_CTRL_GAIN_SLOT(0), 1, 50.0, 3000.0},
    {"zeta", "zeta", "1", "damping ratio of the orientation error's closed loop", 0.0, 10.0, 0.9, 1,
     0, POM_DYN_CTRL_GAIN_SLOT(1), 1, 0.3, 1.5},
    {"current_loop_tau_s", "tau_i", "s",
     "inductive coil: time constant of the current loop that replaces L di/dt", 1e-9, 1.0, 2e-5, 0,
     1, POM_DYN_CTRL_GAIN_SLOT(2), 0, 0.0, 0.0},
};

/* ---- the controller's model and scratch -------------------------------------------- */
typedef struct {
  const pom_dyn_ctrl_engine *eng; /* the engine's services */
  pom_dyn_model *dyn;             /* exact (rigid) model of the nominal mechanism: M and f */
  pom_kin_arch arch;              /* nominal architecture: forward kinematics and J */
  pom_dyn_actuator act;           /* nominal actuator: the coil's inverse */
  int bearing;                    /* 1: the nominal scene has bearing friction */
} ct_model;

typedef struct {
  const pom_dyn_ctrl_engine *eng; /* the engine's services */
  pom_dyn_data *dd;               /* scratch of the controller's model */
  double target[3];               /* setpoints R_ref was computed for */
  double R_ref[9];                /* reference rotation (FK of the setpoints) */
  double R_last[9];               /* last measured rotation: the next forward kinematics' start */
  int have_ref;                   /* 1 once R_ref belongs to target */
  pom_kin_fk_opts fk;             /* forward-kinematics options */
} ct_work;

static pom_status ct_model_create(void **out, const pom_dyn_ctrl_engine *eng,
                                  const pom_dyn_controller *c, const pom_mechanism *mech,
                                  const pom_kin_arch *arch, const pom_dyn_params *p,
                                  pom_error *err) {
  (void)c;
  *out = NULL;
  if (!arch)
    POM_FAIL(err, POM_ERR_ARG,
             "controller computed_torque: needs the architecture (its forward kinematics and "
             "the exact model)");
  ct_model *cm = calloc(1, sizeof *cm);
  if (!cm) POM_FAIL(err, POM_ERR_NOMEM, "allocating the computed-torque model");
  cm->eng = eng;
  cm->arch = *arch;
  cm->act = p->actuator;
  cm->bearing = p->scene.bearing_friction;
  /* the rigid model of the same scene; its own controller is never run */
  pom_dyn_params mp = *p;
  mp.joints.model = POM_JOINTS_RIGID;
  mp.scene.orientation = POM_ORIENT_QUATERNION;
  mp.scene.coil_inductance = 0;
  pom_dyn_ctrl_set_defaults(&mp.controller, &pom_dyn_ctrl_pid);
  pom_status st = eng->model_create(&cm->dyn, mech, arch, &mp, err);
  if (st != POM_OK) {
    free(cm);
    return pom_error_prefix(err, "controller computed_torque: its model");
  }
  *out = cm;
  return POM_OK;
}

static void ct_model_destroy(void *model) {
  ct_model *cm = model;
  if (!cm) return;
  cm->eng->model_destroy(cm->dyn);
  free(cm);
}

static pom_status ct_work_create(void **out, const void *model, pom_error *err) {
  const ct_model *cm = model;
  ct_work *w = calloc(1, sizeof *w);
  if (!w) POM_FAIL(err, POM_ERR_NOMEM, "allocating the computed-torque scratch");
  w->eng = cm->eng;
  pom_status st = cm->eng->data_create(&w->dd, cm->dyn, err);
  if (st != POM_OK) {
    free(w);
    return st;
  }
  pom_kin_fk_defaults(&w->fk);
  *out = w;
  return POM_OK;
}

static void ct_work_destroy(void *work) {
  ct_work *w = work;
  if (!w) return;
  w->eng->data_destroy(w->dd);
  free(w);
}

/* x = A^-1 b for a 3x3 A (row-major) by Cramer's rule; 0 when singular. */
static int solve3(double x[3], const double A[9], const double b[3]) {
  double det = pom_m3_det(A);
  if (!(fabs(det) > 0.0) || !isfinite(det)) return 0;
  for (int k = 0; k < 3; ++k) {
    double Ak[9];
    memcpy(Ak, A, sizeof Ak);
    for (int r = 0; r < 3; ++r)
      Ak[3 * r + k] = b[r];
    x[k] = pom_m3_det(Ak) / det;
  }
  return 1;
}

/* ---- the law --------------------------------------------------------------------- */
static void ct_fail(int n, double *u_raw) {
  for (int a = 0; a < n; ++a)
    u_raw[a] = NAN; /* a recoverable step failure (the engine's non-finite check) */
}

static void ct_law_all(const pom_dyn_controller *c, const void *model, void *work,
                       const pom_dyn_ctrl_sensed *s, double sensor_gain, const double *z,
                       double *u_raw, double *zdot) {
  (void)sensor_gain; /* the sensors give q in SI; K_S is the PID's scale */
  (void)z;
  (void)zdot;
  const ct_model *cm = model;
  ct_work *w = work;
  const double omega_n = c->gain[0], zeta = c->gain[1], tau_i = c->gain[2];
  if (s->n != 3) {
    ct_fail(s->n, u_raw);
    return;
  }
  /* the reference: forward kinematics of the setpoints, once per target */
  if (!w->have_ref || memcmp(w->target, s->target, sizeof w->target) != 0) {
    if (pom_kin_forward(&cm->arch, s->target, NULL, &w->fk, w->R_ref, NULL, NULL) != POM_OK) {
      ct_fail(s->n, u_raw);
      return;
    }
    memcpy(w->target, s->target, sizeof w->target);
    pom_m3_identity(w->R_last); /* every maneuver starts at home */
    w->have_ref = 1;
  }
  /* the measured rotation and angular velocity, from q and q_dot alone */
  double Rm[9], M[9], f[3], qm[3], J[9], wm[3];
  if (pom_kin_forward(&cm->arch, s->q, w->R_last, &w->fk, Rm, NULL, NULL) != POM_OK) {
    ct_fail(s->n, u_raw);
    return;
  }
  memcpy(w->R_last, Rm, sizeof Rm);
  if (pom_kin_inverse_jacobian(&cm->arch, Rm, qm, J, NULL) != POM_OK || !solve3(wm, J, s->q_dot)) {
    ct_fail(s->n, u_raw);
    return;
  }
  /* the model's mass matrix and passive generalized forces there */
  if (cm->eng->exact_terms(cm->dyn, w->dd, Rm, wm, M, f, qm, J) != 0) {
    ct_fail(s->n, u_raw);
    return;
  }
  /* error rotation vector (fixed frame) and the desired angular acceleration */
  double Re[9], e[3], alpha[3], tau[3], F[3], Jt[9];
  pom_m3_mult(Re, w->R_ref, Rm);
  pom_m3_rotvec(e, Re);
  for (int k = 0; k < 3; ++k)
    alpha[k] = omega_n * omega_n * e[k] - 2.0 * zeta * omega_n * wm[k];
  /* M alpha = f + J^T F */
  pom_m3_apply(tau, M, alpha);
  pom_v3_sub(tau, tau, f);
  pom_m3_transpose(Jt, J);
  if (!solve3(F, Jt, tau)) {
    ct_fail(s->n, u_raw);
    return;
  }
  /* the coil's inverse: the current that gives F against friction, then
   * the voltage (a current loop in place of L di/dt for an inductive coil) */
  const pom_dyn_actuator *ap = &cm->act;
  const double b = cm->bearing ? ap->bearing_friction : 0.0;
  for (int a = 0; a < 3; ++a) {
    double i = (F[a] + b * s->q_dot[a]) / ap->force_constant;
    double u = ap->resistance * i + ap->force_constant * s->q_dot[a];
    if (s->current) u += ap->inductance / tau_i * (i - s->current[a]);
    u_raw[a] = u;
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
    .model_destroy = ct_model_destroy,
    .work_create = ct_work_create,
    .work_destroy = ct_work_destroy,
    .law_all = ct_law_all,
};
