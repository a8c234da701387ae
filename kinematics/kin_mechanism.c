/* kin_mechanism.c - the mechanism of an architecture at the home pose: the
 * `inertia` group read by the type's tables and the builders the types use
 * (docs/kinematics.md section 7). */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- config ---------------------------------------------------------------- */
static pom_status load_body(pom_kin_body_inertia *b, const char *group, int kind,
                            const pom_cfg *cfg, pom_error *err) {
  char key[128];
  memset(b, 0, sizeof *b);
  snprintf(key, sizeof key, "inertia.%s", group);
  if (!pom_cfg_has(cfg, key))
    return pom_cfg_error(cfg, key, NULL, err,
                         "missing: expected a group { mass_kg = ...; moments_kgm2 = [...]; }");
  snprintf(key, sizeof key, "inertia.%s.mass_kg", group);
  POM_TRY(pom_cfg_real(cfg, key, 1.0, 1e-9, 1e3, &b->mass, err));
  snprintf(key, sizeof key, "inertia.%s.moments_kgm2", group);
  POM_TRY(pom_cfg_reals(cfg, key, 3, 1.0, 1e-15, 1e2, b->moments, err));
  /* principal moments of a rigid body obey the triangle inequality */
  for (int k = 0; k < 3; ++k) {
    double a = b->moments[k], o = b->moments[(k + 1) % 3] + b->moments[(k + 2) % 3];
    if (a > o * (1.0 + 1e-12))
      return pom_cfg_error(cfg, key, NULL, err,
                           "not the principal moments of a rigid body: moment %d (%g) exceeds the "
                           "sum of the other two (%g)",
                           k + 1, a, o);
  }
  if (kind == 0 && strcmp(group, "platform") == 0) {
    snprintf(key, sizeof key, "inertia.%s.cm_mm", group);
    if (pom_cfg_has(cfg, key)) POM_TRY(pom_cfg_reals(cfg, key, 3, 1e-3, -1e4, 1e4, b->cm, err));
  } else if (kind == 1) {
    snprintf(key, sizeof key, "inertia.%s.cm_offset_mm", group);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1e-3, -1e4, 1e4, 0.0, &b->cm_offset, err));
  } else if (kind == 2) {
    snprintf(key, sizeof key, "inertia.%s.cm_fraction", group);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, 0.0, 1.0, 0.5, &b->cm_fraction, err));
  }
  return POM_OK;
}

pom_status pom_kin_inertia_load(pom_kin_inertia *in, const pom_kin_arch *arch, const pom_cfg *cfg,
                                pom_error *err) {
  const pom_kin_arch_type *t = arch->type;
  char key[128];
  memset(in, 0, sizeof *in);
  if (!pom_cfg_has(cfg, "inertia"))
    return pom_cfg_error(cfg, "inertia", NULL, err, "missing: expected the group of masses");
  double g_default[3] = {0.0, 0.0, -9.81};
  if (pom_cfg_has(cfg, "inertia.gravity_mps2")) {
    POM_TRY(pom_cfg_reals(cfg, "inertia.gravity_mps2", 3, 1.0, -100.0, 100.0, in->gravity, err));
  } else {
    memcpy(in->gravity, g_default, sizeof g_default);
  }
  POM_TRY(load_body(&in->platform, "platform", 0, cfg, err));
  for (int k = 0; k < t->n_inertia_bodies; ++k)
    POM_TRY(
        load_body(&in->body[k], t->inertia_bodies[k].group, t->inertia_bodies[k].place, cfg, err));
  for (int k = 0; k < t->n_inertia_values; ++k) {
    const pom_kin_value_desc *v = &t->inertia_values[k];
    snprintf(key, sizeof key, "inertia.%s", v->key);
    if (v->optional) {
      POM_TRY(pom_cfg_real_opt(cfg, key, v->to_si, v->lo, v->hi, v->def * v->to_si, &in->value[k],
                               err));
    } else {
      POM_TRY(pom_cfg_real(cfg, key, v->to_si, v->lo, v->hi, &in->value[k], err));
    }
  }
  return POM_OK;
}

/* ---- builder --------------------------------------------------------------- */
/* Principal axes of a limb body: z = the limb axis a; x = x_given (3SPS: the
 * U-joint axis, perpendicular to a) or unit(e_z x a), or the limb's
 * tangential direction e_z x e_r when a is vertical; y = z x x. */
void pom_kin_limb_axes(double Q[9], const double a[3], const double er[3], const double *x_given) {
  double ez[3] = {0.0, 0.0, 1.0}, x[3], y[3];
  if (x_given) {
    pom_v3_copy(x, x_given);
  } else {
    pom_v3_cross(x, ez, a);
    if (pom_v3_normalize(x, x) < POM_KIN_HOME_MIN_COS) pom_v3_cross(x, ez, er);
  }
  pom_v3_normalize(x, x);
  pom_v3_cross(y, a, x);
  for (int r = 0; r < 3; ++r) {
    Q[3 * r + 0] = x[r];
    Q[3 * r + 1] = y[r];
    Q[3 * r + 2] = a[r];
  }
}

/* inertia = Q diag(m) Q^T */
void pom_kin_rotate_inertia(double I[9], const double Q[9], const double m[3]) {
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += Q[3 * r + k] * m[k] * Q[3 * c + k];
      I[3 * r + c] = I[3 * c + r] = s; /* exactly symmetric */
    }
}

int pom_kin_build_body(pom_mechanism *m, const char *name, int limb, const pom_kin_body_inertia *b,
                       const double Q[9], const double cm[3]) {
  int k = m->n_bodies++;
  pom_mech_body *body = &m->body[k];
  if (limb > 0) {
    snprintf(body->name, sizeof body->name, "%s%d", name, limb);
  } else {
    snprintf(body->name, sizeof body->name, "%s", name);
  }
  if (b) {
    body->mass = b->mass;
    pom_kin_rotate_inertia(body->inertia, Q, b->moments);
    pom_v3_copy(body->cm, cm);
  }
  return k;
}

int pom_kin_build_joint(pom_mechanism *m, const char *name, int limb, pom_joint_type type, int b0,
                        int b1, const double point[3], const double axis[3],
                        const double axis2[3]) {
  int k = m->n_joints++;
  pom_mech_joint *j = &m->joint[k];
  if (limb > 0) {
    snprintf(j->name, sizeof j->name, "%s%d", name, limb);
  } else {
    snprintf(j->name, sizeof j->name, "%s", name);
  }
  j->type = type;
  j->body[0] = b0;
  j->body[1] = b1;
  pom_v3_copy(j->point, point);
  if (axis) pom_v3_copy(j->axis, axis);
  if (axis2) pom_v3_copy(j->axis2, axis2);
  j->actuator = -1;
  return k;
}

void pom_kin_build_actuator(pom_mechanism *m, int joint, int moving_body, double stroke) {
  int k = m->n_actuators++;
  m->actuator[k].joint = joint;
  m->actuator[k].moving_body = moving_body;
  m->actuator[k].stroke = stroke;
  /* the kind whose joint type this is; kind 0 on another joint type, which the
   * dynamics refuses ("joint j is not a prismatic joint") */
  m->actuator[k].kind = (pom_actuator_kind)0;
  for (int a = 0; a < POM_ACT_KINDS; ++a)
    if (pom_act_kind_desc((pom_actuator_kind)a)->joint == m->joint[joint].type)
      m->actuator[k].kind = (pom_actuator_kind)a;
  m->joint[joint].actuator = k;
}

void pom_kin_build_base(pom_mechanism *mech, const pom_kin_inertia *in, int central_joint) {
  double I3[9], origin[3] = {0.0, 0.0, 0.0};
  pom_m3_identity(I3);
  pom_v3_copy(mech->gravity, in->gravity);
  pom_kin_build_body(mech, "ground", 0, NULL, I3, origin);
  mech->platform = pom_kin_build_body(mech, "platform", 0, &in->platform, I3, in->platform.cm);
  if (central_joint)
    pom_kin_build_joint(mech, "O", 0, POM_JOINT_SPHERICAL, 0, mech->platform, origin, NULL, NULL);
}

pom_status pom_kin_mechanism_from(pom_mechanism *mech, const pom_kin_arch *arch,
                                  const pom_kin_inertia *in, pom_error *err) {
  if (!arch->type) POM_FAIL(err, POM_ERR_ARG, "mechanism: architecture without a type");
  memset(mech, 0, sizeof *mech);
  pom_kin_build_base(mech, in, arch->central_joint);
  POM_TRY(arch->type->mechanism(mech, arch, in, err));
  if (mech->n_actuators != 3)
    POM_FAIL(err, POM_ERR_INTERNAL, "architecture %s built %d actuators, expected 3",
             arch->type->name, mech->n_actuators);
  for (int a = 0; a < mech->n_actuators; ++a)
    if (mech->actuator[a].kind != arch->type->actuator)
      POM_FAIL(err, POM_ERR_INTERNAL,
               "architecture %s: actuator %d drives a %s joint, the type declares %s actuators",
               arch->type->name, a + 1, pom_act_kind_desc(mech->actuator[a].kind)->kind_name,
               pom_act_kind_desc(arch->type->actuator)->kind_name);
  return POM_OK;
}

pom_status pom_kin_mechanism_build(pom_mechanism *mech, const pom_kin_arch *arch,
                                   const pom_cfg *cfg, pom_error *err) {
  pom_kin_inertia in;
  POM_TRY(pom_kin_inertia_load(&in, arch, cfg, err));
  return pom_kin_mechanism_from(mech, arch, &in, err);
}

/* ---- names -------------------------------------------------------------------- */
const char *pom_joint_type_name(pom_joint_type t) {
  switch (t) {
  case POM_JOINT_SPHERICAL:
    return "spherical";
  case POM_JOINT_PRISMATIC:
    return "prismatic";
  case POM_JOINT_UNIVERSAL:
    return "universal";
  case POM_JOINT_REVOLUTE:
    return "revolute";
  }
  return "?";
}
