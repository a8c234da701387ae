/* dyn_parasitic.c - the parasitic formulation (pom_dyn_form_parasitic): one
 * pass through the bond graph: body flows from the I-element
 * states (momenta), articulation-point velocities, parasitic C/R elements of
 * the joints, voice-coil GY/I/R elements and the controller's MSe, efforts
 * summed back onto the Eulerian junction structures (docs/dynamics.md
 * sections 3-6), and the state queries of the shared driver. The RHS
 * allocates nothing. */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* ---- body flows ---------------------------------------------------------- */
/* Fills the kinematic quantities of every body from the state; returns 1 when
 * an Euler-angle body is too close to pitch = +-90 deg. */
static int bodies_eval(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  int singular = 0;
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    dyn_body_eval *e = &d->be[b];
    const double *yb = y + bd->offset;
    if (m->par.scene.orientation == POM_ORIENT_QUATERNION) {
      double q[4] = {yb[DYN_BODY_ORI], yb[DYN_BODY_ORI + 1], yb[DYN_BODY_ORI + 2],
                     yb[DYN_BODY_ORI + 3]};
      pom_quat_normalize(q); /* the rotation of the unit quaternion along q */
      pom_quat_to_matrix(e->R, q);
    } else {
      /* R = Rz(psi) Ry(theta) Rx(phi), keeping the sines and cosines for
       * the rate matrix of the same angles */
      pom_euler_zyx_to_matrix_trig(e->R, e->trig, yb + DYN_BODY_ORI);
      const double cth = e->trig[2];
      if (cth < m->par.scene.euler_cos_min) singular = 1;
    }
    pom_m3_mul(e->Rp, e->R, bd->V);
    pom_v3_add(e->x, bd->cm_home, yb + DYN_BODY_U);
    pom_v3_scale(e->v, 1.0 / bd->mass, yb + DYN_BODY_P);
    for (int k = 0; k < 3; ++k)
      e->wp[k] = yb[DYN_BODY_H + k] / bd->principal[k];
    pom_m3_apply(e->w, e->Rp, e->wp);
    pom_v3_scale(e->F, bd->mass, m->gravity); /* gravity: effort source on each EJS */
    pom_v3_set(e->T, 0.0, 0.0, 0.0);
    if (bd->pinned) {
      /* weight at the true CM, off the pivot (docs/dynamics.md section 13) */
      double arm[3];
      pom_m3_apply(arm, e->R, bd->grav_arm);
      pom_v3_cross(e->T, arm, e->F);
    }
  }
  return singular;
}

/* Articulation point of side s of joint jt: position p, velocity v and the
 * lever arm r = p - x (fixed frame). The ground is at rest with R = I. */
static void point_eval(const pom_dyn_model *m, const pom_dyn_data *d, const dyn_joint *jt, int s,
                       double p[3], double v[3], double r[3]) {
  int slot = jt->slot[s];
  (void)m;
  if (slot < 0) {
    /* ground: at rest, rho holds the fixed point itself (dyn_model.c) */
    pom_v3_set(r, 0.0, 0.0, 0.0);
    pom_v3_set(v, 0.0, 0.0, 0.0);
    pom_v3_copy(p, jt->rho[s]);
    return;
  }
  const dyn_body_eval *e = &d->be[slot];
  double wxr[3];
  pom_m3_apply(r, e->R, jt->rho[s]);
  pom_v3_add(p, e->x, r);
  pom_v3_cross(wxr, e->w, r);
  pom_v3_add(v, e->v, wxr);
}

/* Applies force F at lever arm r to side s (no-op for the ground). */
static void apply_force(pom_dyn_data *d, const dyn_joint *jt, int s, const double F[3],
                        const double r[3]) {
  int slot = jt->slot[s];
  if (slot < 0) return;
  dyn_body_eval *e = &d->be[slot];
  double t[3];
  pom_v3_add(e->F, e->F, F);
  pom_v3_cross(t, r, F);
  pom_v3_add(e->T, e->T, t);
}

static void apply_torque(pom_dyn_data *d, const dyn_joint *jt, int s, double scale,
                         const double T[3]) {
  int slot = jt->slot[s];
  if (slot < 0) return;
  pom_v3_axpy(d->be[slot].T, d->be[slot].T, scale, T);
}

static const double identity3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
static const double zero3[3] = {0, 0, 0};

/* ---- one joint's two sides -------------------------------------------------- */
/* The two points of joint jt at the current evaluation: lever arms r0, r1
 * (fixed frame), relative position dd = p1 - p0 and velocity dv = v1 - v0,
 * and each side's rotation and angular velocity (the ground: I and 0). */
typedef struct {
  double r0[3], r1[3], dd[3], dv[3];
  const double *R0, *R1, *w0, *w1;
} joint_state;

static void joint_state_eval(const pom_dyn_model *m, const pom_dyn_data *d, const dyn_joint *jt,
                             joint_state *js) {
  double p0[3], v0[3], p1[3], v1[3];
  point_eval(m, d, jt, 0, p0, v0, js->r0);
  point_eval(m, d, jt, 1, p1, v1, js->r1);
  pom_v3_sub(js->dd, p1, p0);
  pom_v3_sub(js->dv, v1, v0);
  js->R0 = jt->slot[0] >= 0 ? d->be[jt->slot[0]].R : identity3;
  js->R1 = jt->slot[1] >= 0 ? d->be[jt->slot[1]].R : identity3;
  js->w0 = jt->slot[0] >= 0 ? d->be[jt->slot[0]].w : zero3;
  js->w1 = jt->slot[1] >= 0 ? d->be[jt->slot[1]].w : zero3;
}

/* ---- actuator sensors ------------------------------------------------------ */
/* The coordinate q and rate qd of joint jt's actuator from its sides'
 * rotations, angular velocities and the relative point position dd and
 * velocity dv (docs 4): about the revolute axis n (nxd unused), or along the
 * prismatic axis n (nxd = n x dd, the lever of its reaction torque). */
static void actuator_coordinate(const dyn_joint *jt, const double *R0, const double *R1,
                                const double *w0, const double *w1, const double dd[3],
                                const double dv[3], double n[3], double nxd[3], double *q,
                                double *qd) {
  pom_m3_apply(n, R0, jt->axis);
  if (jt->type == POM_JOINT_REVOLUTE) {
    double ref0[3], ref1[3];
    pom_m3_apply(ref0, R0, jt->ref);
    pom_m3_apply(ref1, R1, jt->ref);
    *q = pom_dyn_revolute_angle(n, ref0, ref1);
    *qd = pom_v3_dot(w1, n) - pom_v3_dot(w0, n);
    pom_v3_set(nxd, 0.0, 0.0, 0.0);
  } else {
    pom_v3_cross(nxd, n, dd);
    *q = pom_v3_dot(n, dd);
    *qd = pom_v3_dot(n, dv) + pom_v3_dot(w0, nxd);
  }
}

/* A coupled controller (law_all) reads every actuator's sensors before any
 * actuator law runs: q and qd of each actuated joint, then the pass. */
static void controller_pass(const pom_dyn_model *m, pom_dyn_data *d, const double *y,
                            double *ydot) {
  double q[POM_MECH_MAX_ACTUATORS] = {0}, qd[POM_MECH_MAX_ACTUATORS] = {0};
  for (int j = 0; j < m->n_joints; ++j) {
    const dyn_joint *jt = &m->joint[j];
    if (jt->actuator < 0) continue;
    joint_state js;
    double n[3], nxd[3];
    joint_state_eval(m, d, jt, &js);
    actuator_coordinate(jt, js.R0, js.R1, js.w0, js.w1, js.dd, js.dv, n, nxd, &q[jt->actuator],
                        &qd[jt->actuator]);
  }
  pom_dyn_controller_pass(m, d, q, qd, y, ydot);
}

/* ---- the pass ------------------------------------------------------------ */
static int parasitic_eval(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot) {
  const pom_dyn_params *par = &m->par;
  const double kl = par->joints.stiffness, cl = par->joints.damping;
  const double ka = par->joints.angular_stiffness, ca = par->joints.angular_damping;
  dyn_outputs *o = &d->out;
  o->euler_singular = bodies_eval(m, d, y);
  o->platform_rate = m->platform_slot >= 0 ? pom_v3_norm(d->be[m->platform_slot].w) : 0.0;
  o->nonfinite = 0;
  o->max_lin_deflection = 0.0;
  o->max_ang_deflection = 0.0;
  o->spring_energy = 0.0;
  o->parasitic_power = 0.0;
  o->dexterity_bound = NAN; /* springs stretch instead: no floor */
  if (m->ctrl->law_all) controller_pass(m, d, y, ydot);

  for (int j = 0; j < m->n_joints; ++j) {
    const dyn_joint *jt = &m->joint[j];
    joint_state js;
    joint_state_eval(m, d, jt, &js);
    const double *r0 = js.r0, *r1 = js.r1, *dd = js.dd, *dv = js.dv;
    const double *R0 = js.R0, *R1 = js.R1, *w0 = js.w0, *w1 = js.w1;

    /* massless rod of a lumped link: C and R on the rate of its length */
    if (jt->distance) {
      double len = pom_v3_norm(dd), nv[3];
      pom_v3_scale(nv, len > 0 ? 1.0 / len : 0.0, dd);
      double delta = len - jt->length, rate = pom_v3_dot(nv, dv);
      double f = kl * delta + cl * rate, F[3];
      o->spring_energy += 0.5 * kl * delta * delta;
      o->parasitic_power += cl * rate * rate;
      o->max_lin_deflection = fmax(o->max_lin_deflection, fabs(delta));
      pom_v3_scale(F, -f, nv);
      apply_force(d, jt, 1, F, r1);
      pom_v3_scale(F, f, nv);
      apply_force(d, jt, 0, F, r0);
      continue;
    }

    /* linear pseudo-constraints: C (k_p) and R (R_p) on a 1-junction with the
     * forbidden relative velocity; directions fixed in side 0 when they rotate.
     * The forces of one joint act at its two points: summed, applied once. */
    double F0[3] = {0.0, 0.0, 0.0}, F1[3] = {0.0, 0.0, 0.0};
    double lin2 = 0.0;
    for (int k = 0; k < jt->n_lin; ++k) {
      double mk[3], mxd[3] = {0.0, 0.0, 0.0};
      if (jt->lin_rotates)
        pom_m3_apply(mk, R0, jt->lin_dir[k]);
      else
        pom_v3_copy(mk, jt->lin_dir[k]);
      double delta = pom_v3_dot(mk, dd);
      double rate = pom_v3_dot(mk, dv);
      if (jt->lin_rotates) {
        pom_v3_cross(mxd, mk, dd);
        rate += pom_v3_dot(w0, mxd);
      }
      double f = kl * delta + cl * rate;
      o->spring_energy += 0.5 * kl * delta * delta;
      o->parasitic_power += cl * rate * rate;
      lin2 += delta * delta;
      pom_v3_axpy(F1, F1, -f, mk);
      pom_v3_axpy(F0, F0, f, mk);
      if (jt->lin_rotates) apply_torque(d, jt, 0, -f, mxd);
    }
    o->max_lin_deflection = fmax(o->max_lin_deflection, sqrt(lin2));

    /* angular pseudo-constraints g = (R0 e).(R1 h) */
    for (int k = 0; k < jt->n_ang; ++k) {
      double ea[3], hb[3], n[3], dw[3];
      pom_m3_apply(ea, R0, jt->ang_e[k]);
      pom_m3_apply(hb, R1, jt->ang_h[k]);
      pom_v3_cross(n, ea, hb);
      pom_v3_sub(dw, w0, w1);
      double g = pom_v3_dot(ea, hb);
      double rate = pom_v3_dot(dw, n);
      double f = ka * g + ca * rate;
      o->spring_energy += 0.5 * ka * g * g;
      o->parasitic_power += ca * rate * rate;
      o->max_ang_deflection = fmax(o->max_ang_deflection, fabs(g));
      apply_torque(d, jt, 0, -f, n);
      apply_torque(d, jt, 1, f, n);
    }

    /* actuator: MSe (controller) -> coil I, R -> GY (K_m) -> force on the
     * prismatic joint's relative motion, with bearing friction; or GY (K_t)
     * -> torque on the revolute joint's relative rotation (docs 4) */
    int a = jt->actuator;
    if (a >= 0 && jt->type == POM_JOINT_REVOLUTE) {
      double n[3], nxd[3], q, qd;
      actuator_coordinate(jt, R0, R1, w0, w1, dd, dv, n, nxd, &q, &qd);
      double torque = pom_dyn_actuator_law(m, d, a, q, qd, y, ydot);
      apply_torque(d, jt, 1, torque, n);
      apply_torque(d, jt, 0, -torque, n);
    } else if (a >= 0) {
      double n[3], nxd[3], q, qd;
      actuator_coordinate(jt, R0, R1, w0, w1, dd, dv, n, nxd, &q, &qd);
      double force = pom_dyn_actuator_law(m, d, a, q, qd, y, ydot);
      pom_v3_axpy(F1, F1, force, n);
      pom_v3_axpy(F0, F0, -force, n);
      apply_torque(d, jt, 0, force, nxd);
    }
    apply_force(d, jt, 0, F0, r0);
    apply_force(d, jt, 1, F1, r1);
  }
  if (!ydot) return 0;
  ydot[m->acc_parasitic] = o->parasitic_power;

  /* Eulerian junction structures: p_dot = F, h'_dot = T' - w' x h' */
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    const dyn_body_eval *e = &d->be[b];
    const double *yb = y + bd->offset;
    double *fb = ydot + bd->offset;
    double Tp[3], gyro[3];
    if (bd->pinned) {
      /* the pivot reacts every force: no translation (docs 13) */
      memset(fb + DYN_BODY_U, 0, 6 * sizeof(double));
    } else {
      pom_v3_copy(fb + DYN_BODY_U, e->v);
      pom_v3_copy(fb + DYN_BODY_P, e->F);
    }
    pom_m3_tapply(Tp, e->Rp, e->T);
    pom_v3_cross(gyro, e->wp, yb + DYN_BODY_H);
    pom_v3_sub(fb + DYN_BODY_H, Tp, gyro);
    if (m->par.scene.orientation == POM_ORIENT_QUATERNION) {
      pom_quat_rate(fb + DYN_BODY_ORI, yb + DYN_BODY_ORI, e->w);
    } else {
      /* e_dot = E(e) omega, E as pom_euler_zyx_rate_matrix (docs 3) */
      double cps = e->trig[0], sps = e->trig[1], cth = e->trig[2], sth = e->trig[3];
      if (fabs(cth) < m->par.scene.euler_cos_min) {
        o->euler_singular = 1;
        memset(fb + DYN_BODY_ORI, 0, 3 * sizeof(double));
      } else {
        double tth = sth / cth;
        const double *w = e->w;
        fb[DYN_BODY_ORI] = cps * tth * w[0] + sps * tth * w[1] + w[2];
        fb[DYN_BODY_ORI + 1] = -sps * w[0] + cps * w[1];
        fb[DYN_BODY_ORI + 2] = cps / cth * w[0] + sps / cth * w[1];
      }
    }
  }
  for (int i = 0; i < m->n_states; ++i)
    if (!isfinite(ydot[i])) {
      o->nonfinite = 1;
      break;
    }
  return (o->euler_singular || o->nonfinite) ? 1 : 0;
}

/* ---- actuator positions only --------------------------------------------- */
static void slot_pose(const pom_dyn_model *m, const double *y, int slot, double R[9], double x[3]) {
  if (slot < 0) {
    pom_m3_identity(R);
    pom_v3_set(x, 0.0, 0.0, 0.0);
    return;
  }
  const dyn_body *bd = &m->body[slot];
  const double *yb = y + bd->offset;
  if (m->par.scene.orientation == POM_ORIENT_QUATERNION) {
    double q[4] = {yb[DYN_BODY_ORI], yb[DYN_BODY_ORI + 1], yb[DYN_BODY_ORI + 2],
                   yb[DYN_BODY_ORI + 3]};
    pom_quat_normalize(q);
    pom_quat_to_matrix(R, q);
  } else {
    pom_euler_zyx_to_matrix(R, yb + DYN_BODY_ORI);
  }
  pom_v3_add(x, bd->cm_home, yb + DYN_BODY_U);
}

static void parasitic_positions(const pom_dyn_model *m, const double *y, double *q) {
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_joint *jt = &m->joint[m->act[a].joint];
    double R0[9], R1[9], x0[3], x1[3], p0[3], p1[3], r[3], n[3], dd[3];
    slot_pose(m, y, jt->slot[0], R0, x0);
    slot_pose(m, y, jt->slot[1], R1, x1);
    if (jt->type == POM_JOINT_REVOLUTE) {
      /* the signed angle of the reference vector about the axis (as the pass) */
      double r0[3], r1[3];
      pom_m3_apply(n, R0, jt->axis);
      pom_m3_apply(r0, R0, jt->ref);
      pom_m3_apply(r1, R1, jt->ref);
      q[a] = pom_dyn_revolute_angle(n, r0, r1);
      continue;
    }
    if (jt->slot[0] < 0) {
      pom_v3_copy(p0, jt->rho[0]);
    } else {
      pom_m3_apply(r, R0, jt->rho[0]);
      pom_v3_add(p0, x0, r);
    }
    if (jt->slot[1] < 0) {
      pom_v3_copy(p1, jt->rho[1]);
    } else {
      pom_m3_apply(r, R1, jt->rho[1]);
      pom_v3_add(p1, x1, r);
    }
    pom_v3_sub(dd, p1, p0);
    pom_m3_apply(n, R0, jt->axis);
    q[a] = pom_v3_dot(n, dd);
  }
}

/* ---- stored energy ------------------------------------------------------- */
static double parasitic_stored(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  parasitic_eval(m, d, y, NULL);
  double E = d->out.spring_energy;
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    const double *yb = y + bd->offset;
    E += 0.5 * pom_v3_dot(yb + DYN_BODY_P, yb + DYN_BODY_P) / bd->mass;
    for (int k = 0; k < 3; ++k)
      E += 0.5 * yb[DYN_BODY_H + k] * yb[DYN_BODY_H + k] / bd->principal[k];
    E -= bd->mass * pom_v3_dot(m->gravity, yb + DYN_BODY_U);
    if (bd->pinned) {
      /* CM displacement R a - a of the weight's arm a (R from the pass above) */
      double ra[3];
      pom_m3_apply(ra, d->be[b].R, bd->grav_arm);
      pom_v3_sub(ra, ra, bd->grav_arm);
      E -= bd->mass * pom_v3_dot(m->gravity, ra);
    }
  }
  return pom_dyn_add_coil_energy(m, y, E);
}

/* ---- state queries of the shared driver ----------------------------------- */
/* Rotation of model body slot b in state y (identity for the ground). */
static void slot_rotation(const pom_dyn_model *m, const double *y, int b, double R[9]) {
  if (b < 0) {
    pom_m3_identity(R);
    return;
  }
  const double *o = y + m->body[b].offset + DYN_BODY_ORI;
  if (m->par.scene.orientation == POM_ORIENT_QUATERNION) {
    double q[4] = {o[0], o[1], o[2], o[3]};
    pom_quat_normalize(q);
    pom_quat_to_matrix(R, q);
  } else {
    pom_euler_zyx_to_matrix(R, o);
  }
}

static void parasitic_platform_rotation(const pom_dyn_model *m, const double *y, double R[9]) {
  slot_rotation(m, y, m->platform_slot, R);
}

static void parasitic_initial(const pom_dyn_model *m, double *y, const pom_dyn_initial *init) {
  memset(y, 0, (size_t)m->n_states * sizeof(double));
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    double *yb = y + bd->offset;
    if (m->par.scene.orientation == POM_ORIENT_QUATERNION) yb[DYN_BODY_ORI] = 1.0;
    if (!init) continue;
    int k = bd->mech_index;
    double wp[3];
    if (!bd->pinned) pom_v3_scale(yb + DYN_BODY_P, bd->mass, init->v[k]);
    pom_m3_tapply(wp, bd->V, init->omega[k]); /* R = I at home: principal = V^T fixed */
    for (int c = 0; c < 3; ++c)
      yb[DYN_BODY_H + c] = bd->principal[c] * wp[c];
  }
}

/* 1 when an Euler-angle body has cos(pitch) below the scene's limit (also
 * catches a step that jumped across pitch = 90 deg). */
static int parasitic_near_singular(const pom_dyn_model *m, const double *y) {
  if (m->par.scene.orientation != POM_ORIENT_EULER_ZYX) return 0;
  for (int b = 0; b < m->n_bodies; ++b)
    if (cos(y[m->body[b].offset + DYN_BODY_ORI + 1]) < m->par.scene.euler_cos_min) return 1;
  return 0;
}

static pom_status parasitic_body_pose(const pom_dyn_model *m, const double *y, int k, double R[9],
                                      double x[3], pom_error *err) {
  (void)err;
  int b = m->slot_of_mech[k];
  slot_rotation(m, y, b, R);
  pom_v3_add(x, m->body[b].cm_home, y + m->body[b].offset + DYN_BODY_U);
  double arm[3]; /* a pinned body's CM is off its reference point (docs 13) */
  pom_m3_apply(arm, R, m->body[b].grav_arm);
  pom_v3_add(x, x, arm);
  return POM_OK;
}

static pom_status parasitic_solver_failure(const pom_dyn_model *m, pom_dyn_data *d, double t,
                                           pom_error *err) {
  (void)m;
  return pom_error_set(err, POM_ERR_SOLVER, __FILE__, __LINE__, "CVODE failed at t = %.6g s: %s", t,
                       d->cvode_msg);
}

/* ---- per-worker data ------------------------------------------------------ */
static pom_status parasitic_data_init(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err) {
  const sunindextype n = m->n_states;
  POM_TRY(pom_dyn_parasitic_jac_data(m, d, err));
  if (m->par.solver.linear_solver == POM_LINSOL_STRUCTURED) {
    /* the block LU over the bond graph's groups (dyn_structured_ls.c) reads
     * the CSC matrix the linear-system callback fills */
    d->A = SUNSparseMatrix(n, n, (sunindextype)m->nnz, CSC_MAT, d->ctx);
    if (!d->A) POM_FAIL(err, POM_ERR_NOMEM, "allocating the Newton matrix");
    pom_dyn_pattern_to_matrix(m, d->A);
    POM_TRY(pom_dyn_structured_ls_create(&d->LS, m, d->ctx, err));
  } else if (m->par.solver.linear_solver == POM_LINSOL_KLU) {
    d->A = SUNSparseMatrix(n, n, (sunindextype)m->nnz, CSC_MAT, d->ctx);
    if (d->A) pom_dyn_pattern_to_matrix(m, d->A);
    if (d->A) d->LS = SUNLinSol_KLU(d->y, d->A, d->ctx);
    /* AMD ordering: half the fill of SUNDIALS' default COLAMD on these
     * matrices (3PSS: nnz(L+U) 1823 against 3535), 25 % faster maneuvers */
    if (d->LS && SUNLinSol_KLUSetOrdering(d->LS, 0) != 0)
      POM_FAIL(err, POM_ERR_SOLVER, "setting the KLU ordering");
    /* no row scaling, no input check: the pattern is written once, sorted,
     * and the scaling pass at each of the ~200 refactorizations of a
     * maneuver cost 11 % of the paper study's CPU with no gain in accuracy
     * (bench/README.md, issue 10; the solve's residual is tested) */
    if (d->LS) SUNLinSol_KLUGetCommon(d->LS)->scale = -1;
  } else {
    d->A = SUNDenseMatrix(n, n, d->ctx);
    if (d->A) d->LS = SUNLinSol_Dense(d->y, d->A, d->ctx);
  }
  return POM_OK;
}

static void parasitic_data_free(pom_dyn_data *d) {
  pom_dyn_parasitic_jac_data_free(d); /* the analytic Jacobian's scratch */
}

static void parasitic_model_free(pom_dyn_model *m) {
  pom_dyn_parasitic_jac_layout_free(m); /* the bond graph lives in the shared arrays */
}

/* ---- the table ------------------------------------------------------------ */
const dyn_formulation pom_dyn_form_parasitic = {
    .name = "parasitic",
    .natural_tolerances = 1,
    .parasitic_springs = 1,
    .init = pom_dyn_parasitic_init,
    .model_free = parasitic_model_free,
    .data_init = parasitic_data_init,
    .data_free = parasitic_data_free,
    .eval = parasitic_eval,
    .linsys = pom_dyn_cvode_linsys,
    .jacobian = pom_dyn_parasitic_jacobian,
    .initial = parasitic_initial,
    .positions = parasitic_positions,
    .stored = parasitic_stored,
    .near_singular = parasitic_near_singular,
    .platform_rotation = parasitic_platform_rotation,
    .body_pose = parasitic_body_pose,
    .solver_failure = parasitic_solver_failure,
};
