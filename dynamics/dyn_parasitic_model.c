/* dyn_parasitic_model.c - assembly of the parasitic formulation's model from
 * a mechanism (its init op): bodies in principal axes, joints as parasitic
 * pseudo-constraints, actuators (linear on prismatic, rotary on revolute
 * joints) with coil and controller, the state layout and tolerances
 * (docs/dynamics.md sections 2-5). */
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
                              const int *slot_of_mech, int universal_constraint, pom_error *err) {
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
      /* no relative spin about axis x axis2; scene.universal_joint = false
       * leaves a spherical joint (docs/dynamics.md section 13) */
      jt->n_ang = universal_constraint ? 1 : 0;
      pom_v3_copy(jt->ang_e[0], j->axis);
      pom_v3_copy(jt->ang_h[0], j->axis2);
    } else if (j->type == POM_JOINT_REVOLUTE) {
      POM_TRY(check_axis(j, j->axis, "axis", err));
      double e1[3], e2[3];
      pom_dyn_perp_basis(e1, e2, j->axis);
      jt->n_ang = 2; /* hinge axis of side 1 stays perpendicular to e1, e2 of side 0 */
      pom_v3_copy(jt->ang_e[0], e1);
      pom_v3_copy(jt->ang_e[1], e2);
      pom_v3_copy(jt->ang_h[0], j->axis);
      pom_v3_copy(jt->ang_h[1], j->axis);
      pom_v3_copy(jt->axis, j->axis);
      pom_v3_copy(jt->ref, e1); /* zero of the joint angle (docs 4) */
    }
    break;
  case POM_JOINT_PRISMATIC: {
    POM_TRY(check_axis(j, j->axis, "axis", err));
    double e1[3], e2[3];
    pom_dyn_perp_basis(e1, e2, j->axis);
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

/* ---- lumped limb inertia (docs/dynamics.md section 13) ------------------- */
/* What scene.limb_inertia = lumped changed in a copy of the mechanism. */
typedef struct {
  int removed[POM_MECH_MAX_BODIES];     /* 1: binary link replaced by a rod */
  int pinned[POM_MECH_MAX_BODIES];      /* 1: turns about its ground pivot */
  double arm[POM_MECH_MAX_BODIES][3];   /* true CM minus pivot (m) */
  int skip_joint[POM_MECH_MAX_JOINTS];  /* 1: joint of a removed link */
  int pivot_joint[POM_MECH_MAX_JOINTS]; /* 1: ground pivot of a pinned body (no linear part) */
  int n_rods;
  int rod_body[POM_MECH_MAX_JOINTS][2];        /* the two neighbours */
  double rod_point[POM_MECH_MAX_JOINTS][2][3]; /* their joint points at home (m) */
} dyn_lump;

/* Adds a point mass mu (kg) at P to body b: mass, CM and inertia about the
 * new CM by the parallel-axis theorem. */
static void add_point_mass(pom_mech_body *b, double mu, const double P[3]) {
  double M = b->mass, Mn = M + mu, c[3], dc[3], dp[3];
  for (int k = 0; k < 3; ++k)
    c[k] = (M * b->cm[k] + mu * P[k]) / Mn;
  pom_v3_sub(dc, b->cm, c);
  pom_v3_sub(dp, P, c);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      double e = (r == k) ? 1.0 : 0.0;
      b->inertia[3 * r + k] += M * (pom_v3_dot(dc, dc) * e - dc[r] * dc[k]) +
                               mu * (pom_v3_dot(dp, dp) * e - dp[r] * dp[k]);
    }
  b->mass = Mn;
  pom_v3_copy(b->cm, c);
}

/* A limb body: moving, not the platform, not carrying an actuator's coil. */
static int is_limb_body(const pom_mechanism *mech, int b) {
  if (b <= 0 || b == mech->platform) return 0;
  for (int a = 0; a < mech->n_actuators; ++a)
    if (mech->actuator[a].moving_body == b) return 0;
  return 1;
}

/* Rewrites lm (a copy of the mechanism) for lumped limb inertia:
 * - a binary link (a limb body with exactly two joints, both spherical, to
 *   two other bodies) is removed; its mass goes to the two joint points in
 *   the ratio that keeps the CM's position along the link, each part added to
 *   the neighbour there; a massless rod (distance constraint) replaces it;
 * - a limb body with exactly one joint to the ground, of a point kind
 *   (spherical, universal, revolute), is pinned at that point: it keeps its
 *   mass and weight but turns about the pivot with the inertia about it. */
static pom_status lump_mechanism(pom_mechanism *lm, dyn_lump *lu, pom_error *err) {
  memset(lu, 0, sizeof *lu);
  for (int b = 1; b < lm->n_bodies; ++b) {
    if (!is_limb_body(lm, b)) continue;
    int js[POM_MECH_MAX_JOINTS], nj = 0, n_sph = 0, n_ground_point = 0, ground_joint = -1;
    for (int j = 0; j < lm->n_joints; ++j) {
      const pom_mech_joint *jt = &lm->joint[j];
      if (lu->skip_joint[j] || (jt->body[0] != b && jt->body[1] != b)) continue;
      js[nj++] = j;
      if (jt->type == POM_JOINT_SPHERICAL) ++n_sph;
      int other = jt->body[0] == b ? jt->body[1] : jt->body[0];
      if (other == 0 && jt->type != POM_JOINT_PRISMATIC) {
        ++n_ground_point;
        ground_joint = j;
      }
    }
    if (nj == 2 && n_sph == 2) {
      const pom_mech_joint *j0 = &lm->joint[js[0]], *j1 = &lm->joint[js[1]];
      int n0 = j0->body[0] == b ? j0->body[1] : j0->body[0];
      int n1 = j1->body[0] == b ? j1->body[1] : j1->body[0];
      if (n0 == n1 || lu->removed[n0] || lu->removed[n1]) continue; /* not a simple link */
      double axis[3], rel[3];
      pom_v3_sub(axis, j1->point, j0->point);
      double L2 = pom_v3_dot(axis, axis);
      if (!(L2 > 0))
        POM_FAIL(err, POM_ERR_ARG, "lumping body '%s': its two joints coincide", lm->body[b].name);
      pom_v3_sub(rel, lm->body[b].cm, j0->point);
      double t = pom_v3_dot(rel, axis) / L2;
      if (!(t >= 0.0 && t <= 1.0))
        POM_FAIL(err, POM_ERR_ARG,
                 "lumping body '%s': its CM lies outside the segment between its joints "
                 "(fraction %g); use scene.limb_inertia = \"full\"",
                 lm->body[b].name, t);
      double mu = lm->body[b].mass;
      if (n0 > 0) add_point_mass(&lm->body[n0], mu * (1.0 - t), j0->point);
      if (n1 > 0) add_point_mass(&lm->body[n1], mu * t, j1->point);
      lu->removed[b] = 1;
      lu->skip_joint[js[0]] = lu->skip_joint[js[1]] = 1;
      int r = lu->n_rods++;
      lu->rod_body[r][0] = n0;
      lu->rod_body[r][1] = n1;
      pom_v3_copy(lu->rod_point[r][0], j0->point);
      pom_v3_copy(lu->rod_point[r][1], j1->point);
    } else if (n_ground_point == 1) {
      pom_mech_body *bd = &lm->body[b];
      const double *A = lm->joint[ground_joint].point;
      pom_v3_sub(lu->arm[b], bd->cm, A);
      const double *d = lu->arm[b];
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k)
          bd->inertia[3 * r + k] +=
              bd->mass * (pom_v3_dot(d, d) * (r == k ? 1.0 : 0.0) - d[r] * d[k]);
      pom_v3_copy(bd->cm, A);
      lu->pinned[b] = 1;
      lu->pivot_joint[ground_joint] = 1;
    }
  }
  return POM_OK;
}

/* ---- characteristic scales and tolerances -------------------------------- */
/* Characteristic scales of each state kind (docs/dynamics.md section 7):
 * the smallest magnitude that still matters in a 3 mm maneuver. They size
 * the finite-difference increments, and the absolute tolerances atol =
 * atol_scale * scale when solver.atol_scale > 0. */
#define DYN_SCALE_LENGTH  1e-6 /* m: parasitic deflections are 1-30 um */
#define DYN_SCALE_SPEED   1e-3 /* m/s: actuator speeds reach ~0.5 m/s */
#define DYN_SCALE_RATE    1e-2 /* rad/s */
#define DYN_SCALE_ANGLE   1e-4 /* rad (and quaternion components): 1e-4 rad ~ 3 um at 30 mm */
#define DYN_SCALE_CURRENT 1e-2 /* A: currents reach V/R = 2.4 A */
#define DYN_SCALE_ENERGY  1e-3 /* J: a 3 mm move costs ~0.1-1 J */

/* Natural sizes: the magnitude each state kind reaches in a maneuver
 * (docs/dynamics.md section 7). With solver.atol_scale = 0 (the default)
 * atol = rtol * natural size, so that the error test is relative to
 * max(|y|, natural size) in every component and rtol alone sets the
 * accuracy. */
#define DYN_NATURAL_LENGTH  1e-3 /* m: CM displacements (strokes +-6 mm) */
#define DYN_NATURAL_SPEED   0.1  /* m/s: actuator speeds 0.1-0.5 m/s */
#define DYN_NATURAL_RATE    1.0  /* rad/s: platform rates ~1-10 rad/s */
#define DYN_NATURAL_ANGLE   0.1  /* rad: tilts up to ~0.2 rad; quaternion parts */
#define DYN_NATURAL_CURRENT 1.0  /* A: 0-2.4 A */
#define DYN_NATURAL_SETTLE  1e-2 /* s: the settling time, the integral's time scale */
#define DYN_NATURAL_ENERGY  0.1  /* J: 0.05-1 J per actuator and maneuver */

/* Fills m->scale and m->atol from the per-kind constants; a pair
 * (scale, natural) per state. */
static void tolerances_fill(pom_dyn_model *m) {
  const pom_dyn_params *p = &m->par;
  const int angular = pom_act_kind_desc(p->actuator.kind)->angular;
  const double L = p->actuator.inductance;
  const int natural = !(p->solver.atol_scale > 0);
  double *nat = m->atol; /* natural sizes first, scaled below */
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    for (int k = 0; k < 3; ++k) {
      m->scale[bd->offset + DYN_BODY_U + k] = DYN_SCALE_LENGTH;
      m->scale[bd->offset + DYN_BODY_P + k] = bd->mass * DYN_SCALE_SPEED;
      m->scale[bd->offset + DYN_BODY_H + k] = bd->principal[k] * DYN_SCALE_RATE;
      nat[bd->offset + DYN_BODY_U + k] = DYN_NATURAL_LENGTH;
      nat[bd->offset + DYN_BODY_P + k] = bd->mass * DYN_NATURAL_SPEED;
      nat[bd->offset + DYN_BODY_H + k] = bd->principal[k] * DYN_NATURAL_RATE;
    }
    for (int k = DYN_BODY_ORI; k < m->body_states; ++k) {
      m->scale[bd->offset + k] = DYN_SCALE_ANGLE;
      nat[bd->offset + k] = DYN_NATURAL_ANGLE;
    }
  }
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_actuator *ac = &m->act[a];
    if (ac->flux_state >= 0) {
      m->scale[ac->flux_state] = L * DYN_SCALE_CURRENT;
      nat[ac->flux_state] = L * DYN_NATURAL_CURRENT;
    }
    /* controller states by their kind; the PID integral of the error is
     * m s (linear) or rad s (rotary) */
    for (int k = 0; k < m->ctrl->n_states; ++k) {
      const int i = ac->ctrl_state + k;
      const double sq = angular ? DYN_SCALE_ANGLE : DYN_SCALE_LENGTH;
      const double nq = angular ? DYN_NATURAL_ANGLE : DYN_NATURAL_LENGTH;
      switch (m->ctrl->states[k].kind) {
      case POM_DYN_CTRL_STATE_Q_TIME:
        m->scale[i] = sq * p->maneuver.horizon;
        nat[i] = nq * DYN_NATURAL_SETTLE;
        break;
      case POM_DYN_CTRL_STATE_Q:
        m->scale[i] = sq;
        nat[i] = nq;
        break;
      case POM_DYN_CTRL_STATE_RATE:
        m->scale[i] = angular ? DYN_SCALE_RATE : DYN_SCALE_SPEED;
        nat[i] = angular ? DYN_NATURAL_RATE : DYN_NATURAL_SPEED;
        break;
      }
    }
    for (int k = 0; k < DYN_ACC_PER_ACT; ++k) {
      m->scale[ac->acc_state + k] = DYN_SCALE_ENERGY;
      nat[ac->acc_state + k] = DYN_NATURAL_ENERGY;
    }
    m->scale[ac->acc_state + DYN_ACC_SATURATED] = p->maneuver.horizon;
  }
  m->scale[m->acc_parasitic] = DYN_SCALE_ENERGY;
  nat[m->acc_parasitic] = DYN_NATURAL_ENERGY;
  for (int i = 0; i < m->n_states; ++i)
    m->atol[i] = natural ? p->solver.rtol * nat[i] : p->solver.atol_scale * m->scale[i];
  /* time in saturation integrates a discontinuous indicator: kept out of the
   * error test (as CVODES does with quadratures when errconQ is off) */
  for (int a = 0; a < m->n_actuators; ++a)
    m->atol[m->act[a].acc_state + DYN_ACC_SATURATED] = 1e30;
}

/* ---- the init op --------------------------------------------------------- */
pom_status pom_dyn_parasitic_init(pom_dyn_model *m, const pom_mechanism *mech,
                                  const pom_kin_arch *arch, pom_error *err) {
  pom_status st = POM_OK;
  const pom_dyn_params *p = &m->par;
  pom_mechanism *lm = NULL; /* the mechanism after the scene's lumping */
  dyn_lump *lu = NULL;
  int joint_map[POM_MECH_MAX_JOINTS];
  (void)arch; /* the bond graph needs the mechanism only */
  lm = malloc(sizeof *lm);
  lu = calloc(1, sizeof *lu);
  if (!lm || !lu) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "allocating the dynamics model");
  *lm = *mech;
  if (p->scene.limb_inertia == POM_INERTIA_LUMPED) POM_TRY_GOTO(lump_mechanism(lm, lu, err), fail);
  mech = lm;
  m->body_states = (p->scene.orientation == POM_ORIENT_QUATERNION) ? 13 : 12;

  /* bodies: principal axes of the home inertia tensor (EJS in body axes) */
  for (int b = 1; b < mech->n_bodies; ++b) {
    const pom_mech_body *mb = &mech->body[b];
    if (lu->removed[b]) continue;
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
    bd->pinned = lu->pinned[b];
    pom_v3_copy(bd->grav_arm, lu->arm[b]);
    bd->offset = m->n_bodies * m->body_states;
    m->slot_of_mech[b] = m->n_bodies;
    if (b == mech->platform) m->platform_slot = m->n_bodies;
    ++m->n_bodies;
  }
  int next = m->n_bodies * m->body_states;

  for (int j = 0; j < mech->n_joints; ++j) {
    joint_map[j] = -1;
    if (lu->skip_joint[j]) continue;
    dyn_joint *jt = &m->joint[m->n_joints];
    POM_TRY_GOTO(
        joint_setup(jt, &mech->joint[j], mech, m->slot_of_mech, p->scene.universal_joint, err),
        fail);
    if (lu->pivot_joint[j]) jt->n_lin = 0; /* the pinned body cannot leave its pivot */
    joint_map[j] = m->n_joints++;
  }
  for (int r = 0; r < lu->n_rods; ++r) {
    /* massless rod of a lumped link: one distance pseudo-constraint */
    if (m->n_joints >= POM_MECH_MAX_JOINTS)
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "too many joints after lumping");
    dyn_joint *jt = &m->joint[m->n_joints++];
    memset(jt, 0, sizeof *jt);
    jt->type = POM_JOINT_SPHERICAL;
    jt->actuator = -1;
    jt->distance = 1;
    double dd[3];
    pom_v3_sub(dd, lu->rod_point[r][1], lu->rod_point[r][0]);
    jt->length = pom_v3_norm(dd);
    for (int s = 0; s < 2; ++s) {
      int b = lu->rod_body[r][s];
      jt->slot[s] = m->slot_of_mech[b];
      if (jt->slot[s] < 0)
        pom_v3_copy(jt->rho[s], lu->rod_point[r][s]);
      else
        pom_v3_sub(jt->rho[s], lu->rod_point[r][s], mech->body[b].cm);
    }
  }

  for (int a = 0; a < mech->n_actuators; ++a) {
    int jm = mech->actuator[a].joint;
    /* a linear actuator drives a prismatic joint, a rotary one a revolute joint */
    const pom_act_desc *kind = pom_act_kind_desc(p->actuator.kind);
    if (jm < 0 || jm >= mech->n_joints || mech->joint[jm].type != kind->joint || joint_map[jm] < 0)
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "actuator %d: joint %d is not a %s joint", a, jm,
                    kind->kind_name);
    int j = joint_map[jm];
    if (m->joint[j].actuator >= 0)
      POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "actuators %d and %d drive the same joint",
                    m->joint[j].actuator, a);
    m->joint[j].actuator = a;
    dyn_actuator *ac = &m->act[a];
    ac->joint = j;
    ac->flux_state = p->scene.coil_inductance ? next++ : -1;
    ac->ctrl_state = m->ctrl->n_states > 0 ? next : -1;
    next += m->ctrl->n_states;
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
  tolerances_fill(m);
  POM_TRY_GOTO(pom_dyn_structure_build(m, err), fail);
  POM_TRY_GOTO(pom_dyn_parasitic_jac_layout(m, err), fail);
fail:
  free(lm);
  free(lu);
  return st;
}
