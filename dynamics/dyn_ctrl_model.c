/* dyn_ctrl_model.c - the model-based controllers' shared model, scratch and
 * inverse dynamics (dyn_ctrl_model.h, docs/control.md). Calls the engine
 * only through pom_dyn_ctrl_engine. */
#include "dyn_ctrl_model.h"

#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

pom_status pom_dyn_ctrl_model_create(void **out, const pom_dyn_ctrl_engine *eng, const char *who,
                                     const pom_mechanism *mech, const pom_kin_arch *arch,
                                     const pom_dyn_params *p, pom_error *err) {
  *out = NULL;
  if (!arch)
    POM_FAIL(err, POM_ERR_ARG,
             "controller %s: needs the architecture (its kinematics and the exact model)", who);
  dyn_ctrl_model *cm = calloc(1, sizeof *cm);
  if (!cm) POM_FAIL(err, POM_ERR_NOMEM, "allocating the model of controller %s", who);
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
    return pom_error_prefix(err, "controller %s: its model", who);
  }
  *out = cm;
  return POM_OK;
}

void pom_dyn_ctrl_model_destroy(void *model) {
  dyn_ctrl_model *cm = model;
  if (!cm) return;
  cm->eng->model_destroy(cm->dyn);
  free(cm);
}

pom_status pom_dyn_ctrl_work_create(void **out, const void *model, pom_error *err) {
  const dyn_ctrl_model *cm = model;
  dyn_ctrl_work *w = calloc(1, sizeof *w);
  if (!w) POM_FAIL(err, POM_ERR_NOMEM, "allocating a controller's scratch");
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

void pom_dyn_ctrl_work_destroy(void *work) {
  dyn_ctrl_work *w = work;
  if (!w) return;
  w->eng->data_destroy(w->dd);
  free(w);
}

int pom_dyn_ctrl_reference(const dyn_ctrl_model *cm, dyn_ctrl_work *w, const double target[3]) {
  if (w->have_ref && memcmp(w->target, target, sizeof w->target) == 0) return 1;
  if (pom_kin_forward(&cm->arch, target, NULL, &w->fk, w->R_set, NULL, NULL) != POM_OK) return 0;
  pom_m3_rotvec(w->r_set, w->R_set);
  memcpy(w->target, target, sizeof w->target);
  pom_m3_identity(w->R_last); /* every maneuver starts at home */
  w->have_ref = 1;
  return 1;
}

int pom_dyn_ctrl_solve3(double x[3], const double A[9], const double b[3]) {
  double det = pom_m3_det(A);
  if (!(fabs(det) > 0.0) || !isfinite(det)) return 0;
  for (int k = 0; k < 3; ++k) { /* Cramer's rule */
    double Ak[9];
    memcpy(Ak, A, sizeof Ak);
    for (int r = 0; r < 3; ++r)
      Ak[3 * r + k] = b[r];
    x[k] = pom_m3_det(Ak) / det;
  }
  return 1;
}

int pom_dyn_ctrl_inverse_dynamics(const dyn_ctrl_model *cm, dyn_ctrl_work *w, const double R[9],
                                  const double omega[3], const double alpha[3], double F[3],
                                  double q[3], double J[9]) {
  double M[9], f[3], tau[3], Jt[9];
  if (cm->eng->exact_terms(cm->dyn, w->dd, R, omega, M, f, q, J) != 0) return 0;
  pom_m3_apply(tau, M, alpha); /* M alpha = f + J^T F */
  pom_v3_sub(tau, tau, f);
  pom_m3_transpose(Jt, J);
  return pom_dyn_ctrl_solve3(F, Jt, tau);
}

double pom_dyn_ctrl_coil_voltage(const dyn_ctrl_model *cm, double F, double q_dot,
                                 double *current) {
  const pom_dyn_actuator *ap = &cm->act;
  const double b = cm->bearing ? ap->bearing_friction : 0.0;
  double i = (F + b * q_dot) / ap->force_constant; /* F = K i - b q_dot */
  if (current) *current = i;
  return ap->resistance * i + ap->force_constant * q_dot;
}
