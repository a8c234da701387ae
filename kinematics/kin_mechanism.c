/* kin_mechanism.c - bodies, joints and actuators of both architectures at
 * the home pose, from the geometry and the `inertia` group
 * (docs/kinematics.md section 7). */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- actuator units -------------------------------------------------------- */
const pom_act_units *pom_act_units_of(pom_actuator_kind k) {
  static const pom_act_units units[2] = {
      {"m", "mm", 1e3, "N", "m/s", "prismatic", "displacement"},
      {"rad", "deg", 180.0 / POM_PI, "N m", "rad/s", "revolute", "angle"}};
  return k == POM_ACT_REVOLUTE ? &units[1] : &units[0];
}

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
  if (kind == 0) {
    snprintf(key, sizeof key, "inertia.%s.cm_mm", group);
    if (pom_cfg_has(cfg, key)) POM_TRY(pom_cfg_reals(cfg, key, 3, 1e-3, -1e4, 1e4, b->cm, err));
  } else if (kind == 1) {
    snprintf(key, sizeof key, "inertia.%s.cm_offset_mm", group);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1e-3, -1e4, 1e4, 0.0, &b->cm_offset, err));
  } else {
    snprintf(key, sizeof key, "inertia.%s.cm_fraction", group);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, 0.0, 1.0, 0.5, &b->cm_fraction, err));
  }
  return POM_OK;
}

pom_status pom_kin_inertia_load(pom_kin_inertia *in, const pom_kin_arch *arch, const pom_cfg *cfg,
                                pom_error *err) {
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
  POM_TRY(load_body(&in->piston, "piston", 1, cfg, err));
  if (arch->type == POM_ARCH_3PSS) {
    POM_TRY(load_body(&in->link, "link", 2, cfg, err));
  } else {
    POM_TRY(load_body(&in->cylinder, "cylinder", 1, cfg, err));
  }
  return POM_OK;
}

/* ---- builder --------------------------------------------------------------- */
/* Principal axes of a limb body: z = the limb axis a; x = x_given (3SPS: the
 * U-joint axis, perpendicular to a) or unit(e_z x a), or the limb's
 * tangential direction e_z x e_r when a is vertical; y = z x x. */
static void limb_axes(double Q[9], const double a[3], const double er[3], const double *x_given) {
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
static void rotate_inertia(double I[9], const double Q[9], const double m[3]) {
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += Q[3 * r + k] * m[k] * Q[3 * c + k];
      I[3 * r + c] = I[3 * c + r] = s; /* exactly symmetric */
    }
}

static int add_body(pom_mechanism *m, const char *name, int limb, const pom_kin_body_inertia *b,
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
    rotate_inertia(body->inertia, Q, b->moments);
    pom_v3_copy(body->cm, cm);
  }
  return k;
}

static int add_joint(pom_mechanism *m, const char *name, int limb, pom_joint_type type, int b0,
                     int b1, const double point[3], const double axis[3], const double axis2[3]) {
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

static void add_actuator(pom_mechanism *m, int joint, int moving_body, double stroke) {
  int k = m->n_actuators++;
  m->actuator[k].joint = joint;
  m->actuator[k].moving_body = moving_body;
  m->actuator[k].stroke = stroke;
  m->actuator[k].kind =
      m->joint[joint].type == POM_JOINT_REVOLUTE ? POM_ACT_REVOLUTE : POM_ACT_PRISMATIC;
  m->joint[joint].actuator = k;
}

pom_status pom_kin_mechanism_from(pom_mechanism *mech, const pom_kin_arch *arch,
                                  const pom_kin_inertia *in, pom_error *err) {
  if (arch->type != POM_ARCH_3PSS && arch->type != POM_ARCH_3SPS)
    POM_FAIL(err, POM_ERR_ARG, "unknown architecture type %d", (int)arch->type);
  memset(mech, 0, sizeof *mech);
  pom_v3_copy(mech->gravity, in->gravity);
  double I3[9], origin[3] = {0.0, 0.0, 0.0};
  pom_m3_identity(I3);
  add_body(mech, "ground", 0, NULL, I3, origin);
  mech->platform = add_body(mech, "platform", 0, &in->platform, I3, in->platform.cm);
  add_joint(mech, "O", 0, POM_JOINT_SPHERICAL, 0, mech->platform, origin, NULL, NULL);

  for (int i = 0; i < 3; ++i) {
    const double *s = arch->limb_dir_home[i], *er = arch->radial_dir[i];
    const double *P = arch->platform_point[i];
    double Q[9], cm[3];
    if (arch->type == POM_ARCH_3PSS) {
      const double *B = arch->slider_mid[i], *d = arch->slider_axis[i];
      /* piston: translates along d; CM on the axis */
      limb_axes(Q, d, er, NULL);
      pom_v3_axpy(cm, B, in->piston.cm_offset, d);
      int piston = add_body(mech, "piston", i + 1, &in->piston, Q, cm);
      /* link B -> C */
      limb_axes(Q, s, er, NULL);
      for (int k = 0; k < 3; ++k)
        cm[k] = B[k] + in->link.cm_fraction * (P[k] - B[k]);
      int link = add_body(mech, "link", i + 1, &in->link, Q, cm);
      int jp = add_joint(mech, "P", i + 1, POM_JOINT_PRISMATIC, 0, piston, B, d, NULL);
      add_actuator(mech, jp, piston, arch->stroke);
      add_joint(mech, "B", i + 1, POM_JOINT_SPHERICAL, piston, link, B, NULL, NULL);
      add_joint(mech, "C", i + 1, POM_JOINT_SPHERICAL, link, mech->platform, P, NULL, NULL);
    } else {
      const double *A = arch->base_point[i], *a1 = arch->ujoint_axis[i];
      double L0 = arch->limb_length_mid[i], a2[3], mid[3];
      /* cylinder: x = U-joint axis 1 (horizontal), z = limb */
      limb_axes(Q, s, er, a1);
      pom_v3_axpy(cm, A, in->cylinder.cm_offset, s);
      int cyl = add_body(mech, "cylinder", i + 1, &in->cylinder, Q, cm);
      pom_v3_axpy(cm, P, -in->piston.cm_offset, s);
      int piston = add_body(mech, "piston", i + 1, &in->piston, Q, cm);
      pom_v3_cross(a2, s, a1);
      pom_v3_normalize(a2, a2);
      add_joint(mech, "A", i + 1, POM_JOINT_UNIVERSAL, 0, cyl, A, a1, a2);
      /* prismatic cylinder -> piston, centred half-way along the limb */
      pom_v3_axpy(mid, A, 0.5 * L0, s);
      int jp = add_joint(mech, "P", i + 1, POM_JOINT_PRISMATIC, cyl, piston, mid, s, NULL);
      add_actuator(mech, jp, piston, arch->stroke);
      add_joint(mech, "B", i + 1, POM_JOINT_SPHERICAL, piston, mech->platform, P, NULL, NULL);
    }
  }
  return POM_OK;
}

pom_status pom_kin_mechanism_build(pom_mechanism *mech, const pom_kin_arch *arch,
                                   const pom_cfg *cfg, pom_error *err) {
  pom_kin_inertia in;
  POM_TRY(pom_kin_inertia_load(&in, arch, cfg, err));
  return pom_kin_mechanism_from(mech, arch, &in, err);
}
