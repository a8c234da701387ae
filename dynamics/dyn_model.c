/* dyn_model.c - assembly of the bond-graph model from a mechanism: bodies in
 * principal axes, joints as parasitic pseudo-constraints, actuators with
 * coil and controller, the state layout and tolerances (docs/dynamics.md
 * sections 2-5). */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Largest |axis . axis2| accepted for a universal joint (the two axes must
 * be perpendicular for g = (R0 a).(R1 b) to vanish at home). */
#define DYN_UJOINT_PERP_TOL 1e-6
/* Largest deviation of a joint axis from unit length accepted. */
#define DYN_AXIS_UNIT_TOL 1e-6

/* ---- helpers ------------------------------------------------------------- */
/* Two unit vectors completing n to a right-handed orthonormal basis. */
static void perp_basis(double e1[3], double e2[3], const double n[3]) {
  double t[3] = {1.0, 0.0, 0.0};
  if (fabs(n[0]) > 0.6) pom_v3_set(t, 0.0, 1.0, 0.0);
  double c[3];
  pom_v3_cross(c, n, t);
  pom_v3_normalize(e1, c);
  pom_v3_cross(e2, n, e1);
}

static pom_status check_axis(const pom_mech_joint *j, const double a[3], const char *which,
                             pom_error *err) {
  double n = pom_v3_norm(a);
  if (!(fabs(n - 1.0) <= DYN_AXIS_UNIT_TOL))
    POM_FAIL(err, POM_ERR_ARG, "joint '%s': %s has length %.9g, expected a unit vector", j->name,
             which, n);
  return POM_OK;
}

/* ---- joints -------------------------------------------------------------- */
static pom_status joint_setup(dyn_joint *jt, const pom_mech_joint *j, const pom_mechanism *mech,
                              const int *slot_of_mech, pom_error *err) {
  memset(jt, 0, sizeof *jt);
  jt->type = j->type;
  jt->actuator = -1;
  for (int s = 0; s < 2; ++s) {
    int b = j->body[s];
    if (b < 0 || b >= mech->n_bodies)
      POM_FAIL(err, POM_ERR_ARG, "joint '%s': body index %d outside [0, %d)", j->name, b,
               mech->n_bodies);
    jt->slot[s] = slot_of_mech[b];
    if (jt->slot[s] < 0)
      pom_v3_copy(jt->rho[s], j->point); /* ground: the point itself, fixed */
    else
      pom_v3_sub(jt->rho[s], j->point, mech->body[b].cm);
  }
  if (j->body[0] == j->body[1])
    POM_FAIL(err, POM_ERR_ARG, "joint '%s' connects body %d to itself", j->name, j->body[0]);
  if (jt->slot[0] < 0 && jt->slot[1] < 0)
    POM_FAIL(err, POM_ERR_ARG, "joint '%s' connects the ground to the ground", j->name);

  switch (j->type) {
  case POM_JOINT_SPHERICAL:
  case POM_JOINT_UNIVERSAL:
  case POM_JOINT_REVOLUTE:
    /* coincident points: three linear constraints along the fixed axes */
    jt->n_lin = 3;
    jt->lin_rotates = 0;
    for (int k = 0; k < 3; ++k) {
      pom_v3_set(jt->lin_dir[k], 0.0, 0.0, 0.0);
      jt->lin_dir[k][k] = 1.0;
    }
    if (j->type == POM_JOINT_UNIVERSAL) {
      POM_TRY(check_axis(j, j->axis, "axis", err));
      POM_TRY(check_axis(j, j->axis2, "axis2", err));
      double c = pom_v3_dot(j->axis, j->axis2);
      if (!(fabs(c) <= DYN_UJOINT_PERP_TOL))
        POM_FAIL(err, POM_ERR_ARG, "universal joint '%s': axis . axis2 = %.3g, must be 0", j->name,
                 c);
      jt->n_ang = 1; /* no relative spin about axis x axis2 */
      pom_v3_copy(jt->ang_e[0], j->axis);
      pom_v3_copy(jt->ang_h[0], j->axis2);
    } else if (j->type == POM_JOINT_REVOLUTE) {
      POM_TRY(check_axis(j, j->axis, "axis", err));
      double e1[3], e2[3];
      perp_basis(e1, e2, j->axis);
      jt->n_ang = 2; /* hinge axis of side 1 stays perpendicular to e1, e2 of side 0 */
      pom_v3_copy(jt->ang_e[0], e1);
      pom_v3_copy(jt->ang_e[1], e2);
      pom_v3_copy(jt->ang_h[0], j->axis);
      pom_v3_copy(jt->ang_h[1], j->axis);
      pom_v3_copy(jt->axis, j->axis);
    }
    break;
  case POM_JOINT_PRISMATIC: {
    POM_TRY(check_axis(j, j->axis, "axis", err));
    double e1[3], e2[3];
    perp_basis(e1, e2, j->axis);
    pom_v3_copy(jt->axis, j->axis);
    jt->n_lin = 2; /* no relative motion across the axis, measured in side 0 */
    jt->lin_rotates = 1;
    pom_v3_copy(jt->lin_dir[0], e1);
    pom_v3_copy(jt->lin_dir[1], e2);
    jt->n_ang = 3; /* no relative rotation at all */
    pom_v3_copy(jt->ang_e[0], e1);
    pom_v3_copy(jt->ang_h[0], e2);
    pom_v3_copy(jt->ang_e[1], e2);
    pom_v3_copy(jt->ang_h[1], j->axis);
    pom_v3_copy(jt->ang_e[2], j->axis);
    pom_v3_copy(jt->ang_h[2], e1);
    break;
  }
  default:
    POM_FAIL(err, POM_ERR_ARG, "joint '%s': unknown joint type %d", j->name, (int)j->type);
  }
  return POM_OK;
}

/* ---- validation of the parameters ---------------------------------------- */
static pom_status params_check(const pom_dyn_params *p, pom_error *err) {
  const pom_dyn_actuator *a = &p->actuator;
  if (!(a->force_constant > 0) || !(a->resistance > 0) || !(a->voltage_limit > 0) ||
      !(a->sensor_gain > 0) || !(a->bearing_friction >= 0))
    POM_FAIL(err, POM_ERR_ARG,
             "actuator parameters must be positive (K_m %g, R_c %g, limit %g, K_S %g) and "
             "friction >= 0 (%g)",
             a->force_constant, a->resistance, a->voltage_limit, a->sensor_gain,
             a->bearing_friction);
  if (p->scene.coil_inductance && !(a->inductance > 0))
    POM_FAIL(err, POM_ERR_ARG, "coil inductance %g H must be > 0 when scene.coil_inductance is on",
             a->inductance);
  const pom_dyn_controller *c = &p->controller;
  if (!(c->kp >= 0) || !(c->ki >= 0) || !(c->kd >= 0))
    POM_FAIL(err, POM_ERR_ARG, "controller gains must be >= 0 (kp %g, ki %g, kd %g)", c->kp, c->ki,
             c->kd);
  const pom_dyn_joints *j = &p->joints;
  if (!(j->stiffness > 0) || !(j->angular_stiffness > 0) || !(j->damping >= 0) ||
      !(j->angular_damping >= 0))
    POM_FAIL(err, POM_ERR_ARG, "joint stiffness must be > 0 and damping >= 0");
  const pom_dyn_solver *s = &p->solver;
  if (!(s->rtol > 0) || !(s->atol_scale > 0) || !(s->max_step >= 0) || s->max_steps < 1 ||
      s->max_order < 1 || s->max_order > 5)
    POM_FAIL(err, POM_ERR_ARG,
             "solver: rtol %g, atol_scale %g must be > 0, max_step %g >= 0, "
             "max_steps %ld >= 1, max_order %d in 1..5",
             s->rtol, s->atol_scale, s->max_step, s->max_steps, s->max_order);
  const pom_dyn_maneuver *m = &p->maneuver;
  if (!(m->horizon > 0) || !(m->output_dt > 0) || !(m->output_dt <= m->horizon) ||
      !(m->settle_band > 0) || !(m->horizon / m->output_dt <= 1e7))
    POM_FAIL(err, POM_ERR_ARG,
             "maneuver: horizon %g s, output_dt %g s (0 < dt <= horizon, <= 1e7 samples), band "
             "%g must be > 0",
             m->horizon, m->output_dt, m->settle_band);
  if (!(p->scene.euler_cos_min > 0 && p->scene.euler_cos_min < 1))
    POM_FAIL(err, POM_ERR_ARG, "scene.euler_cos_min %g outside (0, 1)", p->scene.euler_cos_min);
  return POM_OK;
}

/* ---- characteristic scales and tolerances -------------------------------- */
/* Characteristic scales of each state kind (docs/dynamics.md section 7):
 * the smallest magnitude that still matters in a 3 mm maneuver. atol =
 * atol_scale * scale; the finite-difference increments use the same scale. */
#define DYN_SCALE_LENGTH  1e-6 /* m: parasitic deflections are 1-30 um */
#define DYN_SCALE_SPEED   1e-3 /* m/s: actuator speeds reach ~0.5 m/s */
#define DYN_SCALE_RATE    1e-2 /* rad/s */
#define DYN_SCALE_ANGLE   1e-4 /* rad (and quaternion components): 1e-4 rad ~ 3 um at 30 mm */
#define DYN_SCALE_CURRENT 1e-2 /* A: currents reach V/R = 2.4 A */
#define DYN_SCALE_ENERGY  1e-3 /* J: a 3 mm move costs ~0.1-1 J */

static void scales_fill(pom_dyn_model *m) {
  const pom_dyn_params *p = &m->par;
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    for (int k = 0; k < 3; ++k) {
      m->scale[bd->offset + DYN_BODY_U + k] = DYN_SCALE_LENGTH;
      m->scale[bd->offset + DYN_BODY_P + k] = bd->mass * DYN_SCALE_SPEED;
      m->scale[bd->offset + DYN_BODY_H + k] = bd->principal[k] * DYN_SCALE_RATE;
    }
    for (int k = DYN_BODY_ORI; k < m->body_states; ++k)
      m->scale[bd->offset + k] = DYN_SCALE_ANGLE;
  }
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_actuator *ac = &m->act[a];
    if (ac->flux_state >= 0) m->scale[ac->flux_state] = p->actuator.inductance * DYN_SCALE_CURRENT;
    m->scale[ac->int_state] = DYN_SCALE_LENGTH * p->maneuver.horizon;
    for (int k = 0; k < DYN_ACC_PER_ACT; ++k)
      m->scale[ac->acc_state + k] = DYN_SCALE_ENERGY;
    m->scale[ac->acc_state + DYN_ACC_SATURATED] = p->maneuver.horizon;
  }
  m->scale[m->acc_parasitic] = DYN_SCALE_ENERGY;
  for (int i = 0; i < m->n_states; ++i)
    m->atol[i] = p->solver.atol_scale * m->scale[i];
  /* time in saturation integrates a discontinuous indicator: kept out of the
   * error test (as CVODES does with quadratures when errconQ is off) */
  for (int a = 0; a < m->n_actuators; ++a)
    m->atol[m->act[a].acc_state + DYN_ACC_SATURATED] = 1e30;
}

/* ---- create / destroy ---------------------------------------------------- */
pom_status pom_dyn_model_create(pom_dyn_model **out, const pom_mechanism *mech,
                                const pom_dyn_params *p, pom_error *err) {
  pom_status st = POM_OK;
  pom_dyn_model *m = NULL;
  if (!out || !mech || !p) POM_FAIL(err, POM_ERR_ARG, "pom_dyn_model_create: NULL argument");
  *out = NULL;
  POM_TRY(params_check(p, err));
  if (mech->n_bodies < 2 || mech->n_bodies > POM_MECH_MAX_BODIES || mech->n_joints < 0 ||
      mech->n_joints > POM_MECH_MAX_JOINTS || mech->n_actuators < 0 || mech->n_actuators > 3)
    POM_FAIL(err, POM_ERR_ARG,
             "mechanism sizes: %d bodies (2..%d incl. ground), %d joints (0..%d), %d actuators "
             "(0..3)",
             mech->n_bodies, POM_MECH_MAX_BODIES, mech->n_joints, POM_MECH_MAX_JOINTS,
             mech->n_actuators);
  m = calloc(1, sizeof *m);
  if (!m) POM_FAIL(err, POM_ERR_NOMEM, "allocating the dynamics model");
  m->par = *p;
  if (p->scene.gravity) pom_v3_copy(m->gravity, mech->gravity);
  m->body_states = (p->scene.orientation == POM_ORIENT_QUATERNION) ? 13 : 12;

  /* bodies: principal axes of the home inertia tensor (EJS in body axes) */
  for (int b = 0; b < POM_MECH_MAX_BODIES; ++b)
    m->slot_of_mech[b] = -1;
  m->platform_slot = -1;
  for (int b = 1; b < mech->n_bodies; ++b) {
    const pom_mech_body *mb = &mech->body[b];
    dyn_body *bd = &m->body[m->n_bodies];
    if (!(mb->mass > 0) || !isfinite(mb->mass))
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "body '%s': mass %g kg must be > 0", mb->name,
                    mb->mass);
    double asym = 0, nrm = 0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        asym = fmax(asym, fabs(mb->inertia[3 * r + c] - mb->inertia[3 * c + r]));
        nrm = fmax(nrm, fabs(mb->inertia[3 * r + c]));
      }
    if (!(asym <= 1e-9 * nrm))
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "body '%s': inertia tensor not symmetric", mb->name);
    pom_m3_sym_eig(bd->principal, bd->V, mb->inertia);
    if (!(bd->principal[2] > 0))
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail,
                    "body '%s': principal moments (%g, %g, %g) kg m^2 must all be > 0", mb->name,
                    bd->principal[0], bd->principal[1], bd->principal[2]);
    bd->mech_index = b;
    bd->mass = mb->mass;
    pom_v3_copy(bd->cm_home, mb->cm);
    bd->offset = m->n_bodies * m->body_states;
    m->slot_of_mech[b] = m->n_bodies;
    if (b == mech->platform) m->platform_slot = m->n_bodies;
    ++m->n_bodies;
  }
  int next = m->n_bodies * m->body_states;

  for (int j = 0; j < mech->n_joints; ++j) {
    POM_TRY_GOTO(joint_setup(&m->joint[j], &mech->joint[j], mech, m->slot_of_mech, err), fail);
  }
  m->n_joints = mech->n_joints;

  for (int a = 0; a < mech->n_actuators; ++a) {
    int j = mech->actuator[a].joint;
    if (j < 0 || j >= mech->n_joints || mech->joint[j].type != POM_JOINT_PRISMATIC)
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "actuator %d: joint %d is not a prismatic joint", a, j);
    if (m->joint[j].actuator >= 0)
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "actuators %d and %d drive the same joint",
                    m->joint[j].actuator, a);
    m->joint[j].actuator = a;
    dyn_actuator *ac = &m->act[a];
    ac->joint = j;
    ac->flux_state = p->scene.coil_inductance ? next++ : -1;
    ac->int_state = next++;
  }
  m->n_actuators = mech->n_actuators;
  for (int a = 0; a < m->n_actuators; ++a) {
    m->act[a].acc_state = next;
    next += DYN_ACC_PER_ACT;
  }
  m->acc_parasitic = next++;
  m->n_states = next;

  m->atol = calloc((size_t)m->n_states, sizeof *m->atol);
  m->scale = calloc((size_t)m->n_states, sizeof *m->scale);
  if (!m->atol || !m->scale) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "allocating tolerances");
  scales_fill(m);
  POM_TRY_GOTO(pom_dyn_structure_build(m, err), fail);
  *out = m;
  return POM_OK;
fail:
  pom_dyn_model_destroy(m);
  return st;
}

void pom_dyn_model_destroy(pom_dyn_model *m) {
  if (!m) return;
  free(m->atol);
  free(m->scale);
  free(m->dep);
  free(m->color);
  free(m->colptr);
  free(m->rowind);
  free(m->diag);
  free(m);
}

const pom_dyn_params *pom_dyn_model_params(const pom_dyn_model *m) {
  return &m->par;
}
int pom_dyn_model_n_states(const pom_dyn_model *m) {
  return m->n_states;
}
int pom_dyn_model_n_colors(const pom_dyn_model *m) {
  return m->n_colors;
}
