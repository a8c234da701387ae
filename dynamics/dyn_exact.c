/* dyn_exact.c - the exact-constraint (rigid-joint) formulation
 * (pom_dyn_form_exact) in minimal coordinates: the state is the platform orientation and angular
 * velocity (plus the coils, PID integrals and energy accumulators); every body's pose and twist
 * follow from pom_kin_body_twists; the equations of motion are Kane's M(R) omega_dot = f(R, omega,
 * i) (docs/dynamics-exact.md). Model set-up, the right-hand side, the Jacobian (dense mechanical
 * and electrical columns, analytic from the second-order kinematics where the architecture has
 * them, else the mechanical ones differenced by dyn_fdjac.c), the block linear solver and the
 * state queries of the shared driver (dyn_simulate.c). */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_dense.h>

/* Characteristic scales of the states (docs/dynamics-exact.md section 5; the
 * same kinds and values as the parasitic path, docs/dynamics.md section 7). */
#define EXACT_SCALE_ANGLE   1e-4 /* rad, orientation angles and quaternion components */
#define EXACT_SCALE_RATE    1e-2 /* rad/s, platform angular velocity */
#define EXACT_SCALE_LENGTH  1e-6 /* m, for the PID integral (x horizon) */
#define EXACT_SCALE_CURRENT 1e-2 /* A, coil flux = L x this */
#define EXACT_SCALE_ENERGY  1e-3 /* J, energy accumulators */

/* Natural sizes (solver.atol_scale = 0, the default; docs/dynamics-exact.md
 * section 5): atol = rtol x size. The orientation and omega are tested on
 * their absolute error alone (no rtol |y| term): the controller turns errors
 * dq, dq_dot into a voltage error K_S K_P (dq + tau_D dq_dot) (1e7 V/m and
 * 3e4 V s/m with the paper's gains: a 2.4 um linear band), so an error
 * relative to a 0.2 rad tilt or a 10 rad/s rate lets the voltage chatter
 * across its range at rtol >= 1e-4 (measured: 0.4 % energy error at rtol
 * 1e-4, 33 % at 1e-3). 1e-3 rad is ~15 um of actuator travel at the
 * platform's 15-30 mm lever; 0.1 rad/s ~2 mm/s. */
#define EXACT_NATURAL_ANGLE   1e-3 /* rad, orientation angles and quaternion components */
#define EXACT_NATURAL_RATE    0.1  /* rad/s, platform angular velocity */
#define EXACT_NATURAL_LENGTH  1e-3 /* m, PID integral of a linear actuator (x settle) */
#define EXACT_NATURAL_TURN    0.1  /* rad, PID integral of a rotary actuator (x settle) */
#define EXACT_NATURAL_SETTLE  1e-2 /* s, the integral's time scale */
#define EXACT_NATURAL_CURRENT 1.0  /* A, coil flux = L x this */
#define EXACT_NATURAL_ENERGY  0.1  /* J, energy accumulators */

/* Test rotation of the consistency check between mechanism and kinematics:
 * a generic pose ~2 deg from home (no symmetry can hide a mismatch). */
static const double exact_check_euler[3] = {0.031, -0.022, 0.017};
/* Largest mismatch (m) of a joint between the mechanism and the kinematic
 * body poses: both are exact geometry, so any real mismatch is ~mm while
 * rounding is ~1e-17 m. */
#define EXACT_MATCH_TOL 1e-9

/* ---- private model and scratch ------------------------------------------ */
/* The exact formulation's model (m->form_model). Bodies use the shared
 * model's body[] slots (mass, principal moments, cm_home, mech_index);
 * offsets are unused. */
typedef struct {
  pom_kin_arch arch;                      /* geometry the body poses come from */
  int platform_mech;                      /* mechanism index of the platform */
  int n_ori;                              /* orientation states: 3 (ZYX Euler) or 4 (quaternion) */
  int ori;                                /* first orientation state */
  int omega;                              /* first state of omega (platform, fixed frame, rad/s) */
  int n_jac;                              /* leading states with Jacobian columns */
  int act_limb[POM_MECH_MAX_ACTUATORS];   /* kinematic limb (q index) of each actuator */
  double inertia[POM_MECH_MAX_BODIES][9]; /* [slot] inertia about the CM, fixed axes at home */
  int spin_free[POM_MECH_MAX_BODIES];     /* [slot] 1: idle spin, axisymmetric equivalent */
  double transverse[POM_MECH_MAX_BODIES]; /* [slot] its transverse moment (kg m^2) */
} dyn_exact;

/* Per-worker scratch of the exact formulation (d->form_data). */
typedef struct {
  pom_kin_twists tw;       /* body poses and twists of the last evaluation */
  pom_kin_twists_diff dtw; /* their derivatives at the last analytic Jacobian */
  double M[9];             /* mass matrix of the last evaluation (kg m^2) */
  double kinetic;          /* 1/2 omega^T M omega of the last evaluation (J) */
  double potential;        /* gravitational energy relative to home (J) */
} dyn_exact_work;

static inline const dyn_exact *exact_of(const pom_dyn_model *m) {
  return (const dyn_exact *)m->form_model;
}
static inline dyn_exact_work *work_of(pom_dyn_data *d) {
  return (dyn_exact_work *)d->form_data;
}

/* ---- small linear algebra ------------------------------------------------ */
/* out = A v and out = A^T v (row-major 3x3), inlined in the RHS */
static inline void mv(double out[3], const double A[9], const double v[3]) {
  out[0] = A[0] * v[0] + A[1] * v[1] + A[2] * v[2];
  out[1] = A[3] * v[0] + A[4] * v[1] + A[5] * v[2];
  out[2] = A[6] * v[0] + A[7] * v[1] + A[8] * v[2];
}
static inline void mtv(double out[3], const double A[9], const double v[3]) {
  out[0] = A[0] * v[0] + A[3] * v[1] + A[6] * v[2];
  out[1] = A[1] * v[0] + A[4] * v[1] + A[7] * v[2];
  out[2] = A[2] * v[0] + A[5] * v[1] + A[8] * v[2];
}
/* out = A^T B and out = A B (3x3) */
static inline void mtm(double out[9], const double A[9], const double B[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] = A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c];
}
static inline void mm(double out[9], const double A[9], const double B[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}
/* out += s * A^T B (3x3) */
static void add_tmul(double out[9], double s, const double A[9], const double B[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] += s * (A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c]);
}

/* Solves the symmetric positive definite M x = f by Cholesky; returns 0 when
 * M is not positive definite (or not finite). */
static int spd_solve(double x[3], const double M[9], const double f[3]) {
  double l00 = M[0];
  if (!(l00 > 0)) return 0;
  l00 = sqrt(l00);
  double l10 = M[3] / l00, l20 = M[6] / l00;
  double d1 = M[4] - l10 * l10;
  if (!(d1 > 0)) return 0;
  double l11 = sqrt(d1);
  double l21 = (M[7] - l20 * l10) / l11;
  double d2 = M[8] - l20 * l20 - l21 * l21;
  if (!(d2 > 0)) return 0;
  double l22 = sqrt(d2);
  double y0 = f[0] / l00, y1 = (f[1] - l10 * y0) / l11, y2 = (f[2] - l20 * y0 - l21 * y1) / l22;
  x[2] = y2 / l22;
  x[1] = (y1 - l21 * x[2]) / l11;
  x[0] = (y0 - l10 * x[1] - l20 * x[2]) / l00;
  return 1;
}

/* Platform rotation of state y; Euler path keeps the trig for the rate matrix. */
static void state_rotation(const pom_dyn_model *m, const double *y, double R[9], double trig[4]) {
  const dyn_exact *ex = exact_of(m);
  const double *o = y + ex->ori;
  if (ex->n_ori == 4) {
    double q[4] = {o[0], o[1], o[2], o[3]};
    pom_quat_normalize(q);
    pom_quat_to_matrix(R, q);
    return;
  }
  pom_euler_zyx_to_matrix_trig(R, trig, o);
}

static void exact_platform_rotation(const pom_dyn_model *m, const double *y, double R[9]) {
  state_rotation(m, y, R, NULL);
}

/* ---- model --------------------------------------------------------------- */
/* Pose of home point p of a body. */
static void body_point(double out[3], const pom_kin_body_twist *b, const double p[3]) {
  double d[3], r[3];
  pom_v3_sub(d, p, b->ref_home);
  pom_m3_apply(r, b->R, d);
  pom_v3_add(out, b->ref, r);
}

/* Checks that the kinematic body poses realise every joint of the mechanism
 * at a generic pose and finds the kinematic limb of each actuator. */
static pom_status consistency_check(dyn_exact *ex, const pom_mechanism *mech, pom_error *err) {
  double R[9];
  pom_kin_twists tw;
  pom_euler_zyx_to_matrix(R, exact_check_euler);
  POM_TRY(pom_kin_body_twists(&ex->arch, R, NULL, &tw, err));
  if (tw.n_bodies != mech->n_bodies)
    POM_FAIL(err, POM_ERR_ARG,
             "joints.model = \"rigid\": the architecture's kinematics has %d bodies, the "
             "mechanism %d (build the mechanism with pom_kin_mechanism_from of the same arch)",
             tw.n_bodies, mech->n_bodies);
  for (int a = 0; a < POM_MECH_MAX_ACTUATORS; ++a)
    ex->act_limb[a] = -1;
  for (int j = 0; j < mech->n_joints; ++j) {
    const pom_mech_joint *jt = &mech->joint[j];
    const pom_kin_body_twist *b0 = &tw.body[jt->body[0]], *b1 = &tw.body[jt->body[1]];
    double p0[3], p1[3], dd[3], Rrel[9];
    body_point(p0, b0, jt->point);
    body_point(p1, b1, jt->point);
    pom_v3_sub(dd, p1, p0);
    pom_m3_tmul(Rrel, b0->R, b1->R);
    double mismatch = 0.0, q = NAN;
    if (jt->type == POM_JOINT_PRISMATIC) {
      /* slides along the axis carried by side 0, no relative rotation */
      double ax[3], lat[3];
      pom_m3_apply(ax, b0->R, jt->axis);
      q = pom_v3_dot(ax, dd);
      pom_v3_axpy(lat, dd, -q, ax);
      mismatch = pom_v3_norm(lat);
      double rot = fabs(Rrel[1]) + fabs(Rrel[2]) + fabs(Rrel[5]);
      mismatch = fmax(mismatch, rot * pom_v3_norm(jt->point));
    } else {
      mismatch = pom_v3_norm(dd);
      if (jt->type == POM_JOINT_REVOLUTE) {
        /* turns about the axis only: the relative rotation leaves it fixed;
         * q is the angle about it (the parasitic path's definition) */
        double ax_rel[3], e1[3], e2[3], r1[3];
        pom_m3_apply(ax_rel, Rrel, jt->axis);
        pom_v3_sub(ax_rel, ax_rel, jt->axis);
        mismatch = fmax(mismatch, pom_v3_norm(ax_rel) * pom_v3_norm(jt->point));
        pom_dyn_perp_basis(e1, e2, jt->axis);
        pom_m3_apply(r1, Rrel, e1);
        q = pom_dyn_revolute_angle(jt->axis, e1, r1);
      }
    }
    int a = jt->actuator;
    if (a >= 0 && a < mech->n_actuators) {
      /* the limb whose q (m or rad, by the actuator's kind) matches; limb a
       * itself when several do */
      const pom_act_desc *u = pom_act_kind_desc(mech->actuator[a].kind);
      for (int i = 0; i < 3; ++i)
        if (fabs(tw.q[i] - q) <= EXACT_MATCH_TOL && (ex->act_limb[a] < 0 || i == a))
          ex->act_limb[a] = i;
      if (ex->act_limb[a] < 0)
        POM_FAIL(err, POM_ERR_ARG,
                 "joints.model = \"rigid\": actuator %d (%s joint '%s', q = %.6g %s at the check "
                 "pose) matches no limb of the kinematics",
                 a + 1, u->kind_name, jt->name, q, u->si);
    }
    if (!(mismatch <= EXACT_MATCH_TOL))
      POM_FAIL(err, POM_ERR_ARG,
               "joints.model = \"rigid\": joint '%s' is violated by %.3g m by the kinematic body "
               "poses (mechanism and architecture differ)",
               jt->name, mismatch);
  }
  for (int a = 0; a < mech->n_actuators; ++a)
    if (ex->act_limb[a] < 0)
      POM_FAIL(err, POM_ERR_ARG, "joints.model = \"rigid\": actuator %d has no joint", a + 1);
  return POM_OK;
}

static int home_terms(const pom_dyn_model *m, double M[9], double J[9]);

static pom_status exact_init(pom_dyn_model *m, const pom_mechanism *mech, const pom_kin_arch *arch,
                             pom_error *err) {
  const pom_dyn_params *p = &m->par;
  if (!arch)
    POM_FAIL(err, POM_ERR_ARG,
             "joints.model = \"rigid\" needs the architecture the mechanism was built from "
             "(pom_dyn_model_create with arch NULL)");
  if (p->scene.limb_inertia != POM_INERTIA_FULL || !p->scene.universal_joint)
    POM_FAIL(err, POM_ERR_ARG,
             "joints.model = \"rigid\" supports scene.limb_inertia = \"full\" and "
             "scene.universal_joint = true only");
  if (mech->n_actuators < 1)
    POM_FAIL(err, POM_ERR_ARG, "mechanism sizes: %d bodies, %d actuators", mech->n_bodies,
             mech->n_actuators);
  dyn_exact *ex = calloc(1, sizeof *ex);
  if (!ex) POM_FAIL(err, POM_ERR_NOMEM, "allocating the exact-constraint model");
  m->form_model = ex;
  ex->arch = *arch;
  ex->platform_mech = mech->platform;
  if (mech->platform < 1 || mech->platform >= mech->n_bodies)
    POM_FAIL(err, POM_ERR_ARG, "joints.model = \"rigid\": the mechanism has no platform body");
  POM_TRY(consistency_check(ex, mech, err));

  /* bodies: mass, inertia about the CM (fixed axes at home); idle-spin bodies
   * get the transverse moment of their axisymmetric equivalent */
  pom_kin_twists tw;
  double I3[9];
  pom_m3_identity(I3);
  POM_TRY(pom_kin_body_twists(arch, I3, NULL, &tw, err));
  m->n_bodies = 0;
  for (int k = 1; k < mech->n_bodies; ++k) {
    const pom_mech_body *mb = &mech->body[k];
    dyn_body *bd = &m->body[m->n_bodies];
    if (!(mb->mass > 0) || !isfinite(mb->mass))
      POM_FAIL(err, POM_ERR_ARG, "body '%s': mass %g kg must be > 0", mb->name, mb->mass);
    pom_m3_sym_eig(bd->principal, bd->V, mb->inertia);
    if (!(bd->principal[2] > 0))
      POM_FAIL(err, POM_ERR_ARG, "body '%s': principal moments (%g, %g, %g) kg m^2 must be > 0",
               mb->name, bd->principal[0], bd->principal[1], bd->principal[2]);
    bd->mech_index = k;
    bd->mass = mb->mass;
    pom_v3_copy(bd->cm_home, mb->cm);
    memcpy(ex->inertia[m->n_bodies], mb->inertia, sizeof ex->inertia[0]);
    const pom_kin_body_twist *t = &tw.body[k];
    ex->spin_free[m->n_bodies] = t->spin_free;
    if (t->spin_free) {
      double Is[3], axial;
      pom_m3_apply(Is, mb->inertia, t->spin_axis);
      axial = pom_v3_dot(t->spin_axis, Is);
      ex->transverse[m->n_bodies] =
          0.5 * (mb->inertia[0] + mb->inertia[4] + mb->inertia[8] - axial);
    }
    m->slot_of_mech[k] = m->n_bodies;
    if (k == mech->platform) m->platform_slot = m->n_bodies;
    ++m->n_bodies;
  }

  /* state layout: orientation, omega, per actuator [flux] integral, accumulators */
  ex->n_ori = p->scene.orientation == POM_ORIENT_QUATERNION ? 4 : 3;
  ex->ori = 0;
  ex->omega = ex->n_ori;
  int next = ex->n_ori + 3;
  m->n_actuators = mech->n_actuators;
  for (int a = 0; a < m->n_actuators; ++a) {
    dyn_actuator *ac = &m->act[a];
    ac->joint = mech->actuator[a].joint;
    ac->flux_state = p->scene.coil_inductance ? next++ : -1;
    ac->ctrl_state = m->ctrl->n_states > 0 ? next : -1;
    next += m->ctrl->n_states;
  }
  ex->n_jac = next;
  for (int a = 0; a < m->n_actuators; ++a) {
    m->act[a].acc_state = next;
    next += DYN_ACC_PER_ACT;
  }
  m->acc_parasitic = next++;
  m->n_states = next;

  /* Jacobian pattern: the mechanical and electrical columns are dense (every
   * state feeds M(R) omega_dot = f); the accumulator columns are zero. The
   * mechanical columns (orientation, then omega) are analytic when the
   * architecture has second-order kinematics and the controller analytic
   * partials (pom_dyn_exact_jacobian; the colours below then go unused);
   * otherwise they are differenced (the last differenced column is an omega
   * one, exact_jacobian relies on it), each its own colour; the electrical
   * ones are analytic (colour -1 for both kinds: never differenced), unless
   * the controller has no analytic partials (m->ctrl_analytic 0): then they
   * are differenced too, after the mechanical ones (docs/dynamics-exact.md
   * section 5) */
  const size_t n = (size_t)m->n_states;
  m->atol = calloc(n, sizeof *m->atol);
  m->scale = calloc(n, sizeof *m->scale);
  m->dep = calloc(n * n, 1);
  m->color = calloc(n, sizeof *m->color);
  if (!m->atol || !m->scale || !m->dep || !m->color)
    POM_FAIL(err, POM_ERR_NOMEM, "allocating tolerances and the Jacobian pattern");
  for (size_t j = 0; j < n; ++j) {
    int in = (int)j < ex->n_jac;
    int n_fd = m->ctrl_analytic ? ex->n_ori + 3 : ex->n_jac;
    m->color[j] = (int)j < n_fd ? (int)j : -1;
    for (size_t i = 0; i < n; ++i)
      m->dep[i * n + j] = (unsigned char)in;
  }
  m->n_colors = m->ctrl_analytic ? ex->n_ori + 3 : ex->n_jac;
  POM_TRY(pom_dyn_pattern_build(m, err));
  const int angular = pom_act_kind_desc(p->actuator.kind)->angular; /* q in rad, else m */
  for (int i = 0; i < ex->n_ori; ++i)
    m->scale[ex->ori + i] = EXACT_SCALE_ANGLE;
  for (int i = 0; i < 3; ++i)
    m->scale[ex->omega + i] = EXACT_SCALE_RATE;
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_actuator *ac = &m->act[a];
    if (ac->flux_state >= 0)
      m->scale[ac->flux_state] = p->actuator.inductance * EXACT_SCALE_CURRENT;
    /* controller states by their kind; the PID integral of the error is m s
     * (linear) or rad s (rotary) */
    for (int k = 0; k < m->ctrl->n_states; ++k) {
      const double sq = angular ? EXACT_SCALE_ANGLE : EXACT_SCALE_LENGTH;
      const pom_dyn_ctrl_state_kind kind = m->ctrl->states[k].kind;
      m->scale[ac->ctrl_state + k] = kind == POM_DYN_CTRL_STATE_Q_TIME ? sq * p->maneuver.horizon
                                     : kind == POM_DYN_CTRL_STATE_Q    ? sq
                                                                       : sq / EXACT_NATURAL_SETTLE;
    }
    for (int k = 0; k < DYN_ACC_PER_ACT; ++k)
      m->scale[ac->acc_state + k] = EXACT_SCALE_ENERGY;
    m->scale[ac->acc_state + DYN_ACC_SATURATED] = p->maneuver.horizon;
  }
  m->scale[m->acc_parasitic] = EXACT_SCALE_ENERGY;
  if (p->solver.atol_scale > 0) {
    for (int i = 0; i < m->n_states; ++i)
      m->atol[i] = p->solver.atol_scale * m->scale[i];
  } else {
    /* natural sizes; the mechanical states without the relative term */
    m->relative = malloc(n);
    if (!m->relative) POM_FAIL(err, POM_ERR_NOMEM, "allocating tolerances");
    const double r = p->solver.rtol;
    for (int i = 0; i < m->n_states; ++i) {
      m->atol[i] = r * EXACT_NATURAL_ENERGY; /* accumulators */
      m->relative[i] = 1;
    }
    for (int i = 0; i < ex->n_ori; ++i) {
      m->atol[ex->ori + i] = r * EXACT_NATURAL_ANGLE;
      m->relative[ex->ori + i] = 0;
    }
    for (int i = 0; i < 3; ++i) {
      m->atol[ex->omega + i] = r * EXACT_NATURAL_RATE;
      m->relative[ex->omega + i] = 0;
    }
    for (int a = 0; a < m->n_actuators; ++a) {
      const dyn_actuator *ac = &m->act[a];
      if (ac->flux_state >= 0)
        m->atol[ac->flux_state] = r * p->actuator.inductance * EXACT_NATURAL_CURRENT;
      for (int k = 0; k < m->ctrl->n_states; ++k) {
        const double nq = angular ? EXACT_NATURAL_TURN : EXACT_NATURAL_LENGTH;
        const pom_dyn_ctrl_state_kind kind = m->ctrl->states[k].kind;
        m->atol[ac->ctrl_state + k] =
            kind == POM_DYN_CTRL_STATE_Q_TIME ? r * nq * EXACT_NATURAL_SETTLE
            : kind == POM_DYN_CTRL_STATE_Q    ? r * nq
                                              : r * nq / EXACT_NATURAL_SETTLE;
      }
    }
  }
  for (int a = 0; a < m->n_actuators; ++a) /* discontinuous indicator: no error test */
    m->atol[m->act[a].acc_state + DYN_ACC_SATURATED] = 1e30;
  /* the BDF order the drive mode allows (dyn_exact_order.c), from M and J
   * at home */
  double M_home[9], J_home[9];
  if (home_terms(m, M_home, J_home) == 0) {
    pom_dyn_order_cap(m, M_home, J_home);
    /* the Newton accuracy the drive voltage needs (dyn_exact_order.c): the
     * largest tolerances of a rotation, an omega component and the
     * controller state */
    double a_angle = 0.0, a_rate = 0.0, a_ctrl = 0.0;
    for (int i = 0; i < ex->n_ori; ++i)
      a_angle = fmax(a_angle, (ex->n_ori == 4 ? 2.0 : 1.0) * m->atol[ex->ori + i]);
    for (int i = 0; i < 3; ++i)
      a_rate = fmax(a_rate, m->atol[ex->omega + i]);
    for (int a = 0; a < m->n_actuators; ++a)
      if (m->act[a].ctrl_state >= 0) a_ctrl = fmax(a_ctrl, m->atol[m->act[a].ctrl_state]);
    pom_dyn_newton_coef(m, J_home, a_angle, a_rate, a_ctrl);
  }
  return POM_OK;
}

/* ---- mass matrix and generalized forces ------------------------------------ */
/* Kane's equations over the moving bodies at the twists tw and angular
 * velocity w: adds to M the mass matrix, to f the generalized force of
 * gravity and the velocity terms, to *pe the gravitational energy relative
 * to home (docs/dynamics-exact.md section 3). */
static void body_terms(const pom_dyn_model *m, const pom_kin_twists *tw, const double *w,
                       double M[9], double f[3], double *pe) {
  const dyn_exact *ex = exact_of(m);
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    const pom_kin_body_twist *t = &tw->body[bd->mech_index];
    double d0[3], rho[3], Acm[9], wb[3], a0[3], tmp[3], x[3];
    const double *Bm = t->B;
    int moving_rot = 0; /* 0 for bodies that only translate (B = 0) */
    for (int k = 0; k < 9; ++k)
      moving_rot |= Bm[k] != 0.0;
    pom_v3_sub(d0, bd->cm_home, t->ref_home);
    mv(rho, t->R, d0);
    /* Acm = A - [rho]x B, column by column */
    for (int c = 0; c < 3; ++c) {
      const double b0 = Bm[c], b1 = Bm[3 + c], b2 = Bm[6 + c];
      Acm[c] = t->A[c] - (rho[1] * b2 - rho[2] * b1);
      Acm[3 + c] = t->A[3 + c] - (rho[2] * b0 - rho[0] * b2);
      Acm[6 + c] = t->A[6 + c] - (rho[0] * b1 - rho[1] * b0);
    }
    mv(wb, Bm, w);
    /* CM acceleration at omega_dot = 0 */
    pom_v3_cross(a0, t->alpha_bias, rho);
    pom_v3_add(a0, a0, t->a_bias);
    pom_v3_cross(tmp, wb, rho);
    pom_v3_cross(x, wb, tmp);
    pom_v3_add(a0, a0, x);
    double F[3];
    for (int k = 0; k < 3; ++k)
      F[k] = bd->mass * (m->gravity[k] - a0[k]);
    add_tmul(M, bd->mass, Acm, Acm);
    mtv(tmp, Acm, F);
    pom_v3_add(f, f, tmp);
    /* rotation */
    if (moving_rot) {
      double Iw[3], Ia[3], gyro[3], Tq[3];
      if (ex->spin_free[b]) {
        /* axisymmetric about the spin axis, w across it: I w = I_t w, w x I w = 0 */
        add_tmul(M, ex->transverse[b], Bm, Bm);
        pom_v3_scale(Tq, -ex->transverse[b], t->alpha_bias);
      } else {
        /* in home axes: B_h = R^T B, M += B_h^T I_home B_h, torques likewise */
        double Bh[9], IBh[9], wh[3], ah[3];
        mtm(Bh, t->R, Bm);
        mm(IBh, ex->inertia[b], Bh);
        add_tmul(M, 1.0, Bh, IBh);
        mtv(wh, t->R, wb);
        mtv(ah, t->R, t->alpha_bias);
        mv(Iw, ex->inertia[b], wh);
        mv(Ia, ex->inertia[b], ah);
        pom_v3_cross(gyro, wh, Iw);
        for (int k = 0; k < 3; ++k)
          Tq[k] = -Ia[k] - gyro[k];
        mv(tmp, t->R, Tq); /* back to the fixed frame */
        pom_v3_copy(Tq, tmp);
      }
      mtv(tmp, Bm, Tq);
      pom_v3_add(f, f, tmp);
    }
    /* gravitational potential relative to home */
    pom_v3_add(x, t->ref, rho);
    pom_v3_sub(x, x, bd->cm_home);
    *pe -= bd->mass * pom_v3_dot(m->gravity, x);
  }
}

/* ---- right-hand side ------------------------------------------------------ */
/* One evaluation. ydot NULL and !energy: the outputs (q, q_dot, current,
 * voltage) only, from the IK and J (the driver's per-step extremes); energy:
 * also M, the kinetic and the potential energy. */
static int exact_eval(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot,
                      int energy) {
  const dyn_exact *ex = exact_of(m);
  dyn_exact_work *xw = work_of(d);
  const pom_dyn_params *par = &m->par;
  dyn_outputs *o = &d->out;
  memset(o, 0, sizeof *o);
  o->dexterity_bound = NAN;
  double R[9], trig[4] = {1.0, 0.0, 1.0, 0.0};
  state_rotation(m, y, R, trig);
  if (ex->n_ori == 3 && trig[2] < par->scene.euler_cos_min) o->euler_singular = 1;
  const double *w = y + ex->omega;
  o->platform_rate = pom_v3_norm(w);
  pom_kin_twists *tw = &xw->tw;
  const int outputs_only = !ydot && !energy;
  if (outputs_only ? pom_kin_inverse_jacobian(&ex->arch, R, tw->q, tw->J, NULL) != POM_OK
                   : pom_kin_body_twists(&ex->arch, R, w, tw, NULL) != POM_OK) {
    o->kin_fail = 1;
    return 1;
  }
  /* the dexterity floor's measure from the J at hand, on the outputs
   * evaluations only (the driver's per step): docs/dynamics-exact.md section 3 */
  if (!ydot) o->dexterity_bound = pom_kin_dexterity_bound(tw->J);

  /* Kane: M = sum m Acm^T Acm + B^T I B; f = sum Acm^T (F - m a0) - B^T (I al0 + w x I w) */
  double M[9] = {0}, f[3] = {0}, pe = 0.0;
  if (!outputs_only) body_terms(m, tw, w, M, f, &pe);

  /* actuators: the same coil and controller laws as the parasitic path
   * (dyn_rhs.c), the force entering as J^T F */
  if (m->ctrl->law_all) { /* a coupled controller sees every actuator's sensors first */
    double qa[POM_MECH_MAX_ACTUATORS], qda[POM_MECH_MAX_ACTUATORS];
    for (int a = 0; a < m->n_actuators; ++a) {
      qa[a] = tw->q[ex->act_limb[a]];
      qda[a] = pom_v3_dot(tw->J + 3 * ex->act_limb[a], w);
    }
    pom_dyn_controller_pass(m, d, qa, qda, y, ydot);
  }
  for (int a = 0; a < m->n_actuators; ++a) {
    int limb = ex->act_limb[a];
    const double *Jr = tw->J + 3 * limb;
    double q = tw->q[limb];
    double qd = pom_v3_dot(Jr, w);
    double force = pom_dyn_actuator_law(m, d, a, q, qd, y, ydot);
    pom_v3_axpy(f, f, force, Jr);
  }
  if (outputs_only) return o->euler_singular ? 1 : 0;
  double Mw[3];
  mv(Mw, M, w);
  xw->kinetic = 0.5 * pom_v3_dot(w, Mw);
  xw->potential = pe;
  memcpy(xw->M, M, sizeof M);
  if (!ydot) return o->euler_singular ? 1 : 0;

  double wd[3];
  if (!spd_solve(wd, M, f)) {
    o->nonfinite = 1;
    return 1;
  }
  memcpy(ydot + ex->omega, wd, sizeof wd);
  ydot[m->acc_parasitic] = 0.0;
  double *od = ydot + ex->ori;
  if (ex->n_ori == 4) {
    pom_quat_rate(od, y + ex->ori, w);
  } else if (fabs(trig[2]) < par->scene.euler_cos_min) {
    o->euler_singular = 1;
    od[0] = od[1] = od[2] = 0.0;
  } else {
    double cps = trig[0], sps = trig[1], cth = trig[2], sth = trig[3], tth = sth / cth;
    od[0] = cps * tth * w[0] + sps * tth * w[1] + w[2];
    od[1] = -sps * w[0] + cps * w[1];
    od[2] = cps / cth * w[0] + sps / cth * w[1];
  }
  for (int i = 0; i < m->n_states; ++i)
    if (!isfinite(ydot[i])) {
      o->nonfinite = 1;
      break;
    }
  return (o->euler_singular || o->nonfinite) ? 1 : 0;
}

static int exact_rhs(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot) {
  return exact_eval(m, d, y, ydot, 0);
}

/* ---- Jacobian ------------------------------------------------------------------ */
/* Columns of the coil flux and PID integral of actuator a (docs/dynamics-exact.md
 * section 5): they enter only a's law, so omega_dot moves by M^-1 J_a^T dF, the
 * coil row by the coil equation's partials, the integral row not at all (e does
 * not depend on them) and a's energy accumulators by the product rule. M, q_a
 * and J_a are those of the last evaluation, at the platform rotation of y. */
static void electrical_columns(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  const dyn_exact *ex = exact_of(m);
  const dyn_exact_work *xw = work_of(d);
  const double *w = y + ex->omega;
  const double Rc = m->par.actuator.resistance;
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_actuator *ac = &m->act[a];
    int limb = ex->act_limb[a];
    const double *Jr = xw->tw.J + 3 * limb;
    double v[3] = {0.0, 0.0, 0.0}, lp_col[2][4];
    dyn_law_partials lp;
    pom_dyn_actuator_law_partials(m, d, a, xw->tw.q[limb], pom_v3_dot(Jr, w), y, &lp);
    (void)spd_solve(v, xw->M, Jr); /* M is positive definite: the evaluation solved with it */
    /* per column (z, flux): dF, d(flux_dot), du, di */
    lp_col[0][0] = lp.dF_dz, lp_col[0][1] = lp.dflux_dz, lp_col[0][2] = lp.du_dz;
    lp_col[0][3] = lp.di_dz;
    lp_col[1][0] = lp.dF_dflux, lp_col[1][1] = lp.dflux_dflux, lp_col[1][2] = 0.0;
    lp_col[1][3] = lp.di_dflux;
    const int cols[2] = {ac->ctrl_state, ac->flux_state}; /* ctrl_analytic: at most one state */
    const double pw = lp.u * lp.i;
    for (int c = 0; c < 2; ++c) {
      int j = cols[c];
      if (j < 0) continue;
      const double *g = lp_col[c];
      double dpw = g[2] * lp.i + lp.u * g[3];
      for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
        int i = m->rowind[k], r = i - ac->acc_state;
        double val = 0.0;
        if (i >= ex->omega && i < ex->omega + 3)
          val = v[i - ex->omega] * g[0];
        else if (i == ac->flux_state)
          val = g[1];
        else if (i == ac->ctrl_state)
          val = c == 0 ? lp.dzd_dz : 0.0; /* the law never reads the current */
        else if (r == DYN_ACC_SOURCE)
          val = dpw;
        else if (r == DYN_ACC_SOURCE_POS)
          val = pw > 0 ? dpw : 0.0;
        else if (r == DYN_ACC_COIL)
          val = 2.0 * Rc * lp.i * g[3];
        d->jac[k] = val;
      }
    }
  }
}

/* ---- analytic mechanical columns ----------------------------------------------- */
/* Per body, what every direction's derivative reuses (docs/dynamics-exact.md
 * section 5): with the angular acceleration omega_dot of the evaluation,
 * G = F - m Acm omega_dot and H = T - I B omega_dot (the residual of each
 * body's share of M omega_dot = f), so that f' - M' omega_dot groups into
 * matrix-vector products and no 3x3 product is formed per direction. */
typedef struct {
  double rho[3], Acm[9], wb[3]; /* as body_terms */
  double Bwd[3];                /* B omega_dot */
  double G[3], rG[3];           /* F - m Acm omega_dot, rho x G */
  double If[9];                 /* fixed-frame inertia R_b I_home R_b^T (not for idle spin) */
  double Iwb[3], Iat[3];        /* I w_b, I (alpha0 + B omega_dot) */
  double at[3];                 /* alpha0 + B omega_dot */
  double H[3];                  /* T - I B omega_dot = -(I at + w_b x I w_b) */
  int rot;                      /* 0: the body only translates (B = B' = 0) */
} body_pre;

static void body_pre_eval(const pom_dyn_model *m, const pom_kin_twists *tw,
                          const pom_kin_twists_diff *dtw, const double *w, const double *wd,
                          body_pre *bp) {
  const dyn_exact *ex = exact_of(m);
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    const int k = bd->mech_index;
    const pom_kin_body_twist *t = &tw->body[k];
    body_pre *p = &bp[b];
    double d0[3], a0[3], tmp[3], x[3], S[9], Aw[3];
    pom_v3_sub(d0, bd->cm_home, t->ref_home);
    mv(p->rho, t->R, d0);
    pom_m3_skew(S, p->rho);
    mm(p->Acm, S, t->B);
    for (int e = 0; e < 9; ++e)
      p->Acm[e] = t->A[e] - p->Acm[e];
    mv(p->wb, t->B, w);
    mv(p->Bwd, t->B, wd);
    pom_v3_cross(a0, t->alpha_bias, p->rho);
    pom_v3_add(a0, a0, t->a_bias);
    pom_v3_cross(tmp, p->wb, p->rho);
    pom_v3_cross(x, p->wb, tmp);
    pom_v3_add(a0, a0, x);
    mv(Aw, p->Acm, wd);
    for (int e = 0; e < 3; ++e)
      p->G[e] = bd->mass * (m->gravity[e] - a0[e] - Aw[e]);
    pom_v3_cross(p->rG, p->rho, p->G);
    p->rot = 0;
    for (int e = 0; e < 9; ++e)
      p->rot |= t->B[e] != 0.0 || dtw->d_theta[0].body[k].B[e] != 0.0 ||
                dtw->d_theta[1].body[k].B[e] != 0.0 || dtw->d_theta[2].body[k].B[e] != 0.0;
    if (!p->rot) continue;
    pom_v3_add(p->at, t->alpha_bias, p->Bwd);
    if (ex->spin_free[b]) {
      /* axisymmetric equivalent: I = I_t on every w_b, no gyroscopic term */
      const double It = ex->transverse[b];
      pom_v3_scale(p->Iwb, It, p->wb);
      pom_v3_scale(p->Iat, It, p->at);
      pom_v3_scale(p->H, -1.0, p->Iat);
    } else {
      double RI[9], g[3];
      mm(RI, t->R, ex->inertia[b]);
      for (int r = 0; r < 3; ++r) /* If = RI R^T */
        for (int c = 0; c < 3; ++c)
          p->If[3 * r + c] = RI[3 * r] * t->R[3 * c] + RI[3 * r + 1] * t->R[3 * c + 1] +
                             RI[3 * r + 2] * t->R[3 * c + 2];
      mv(p->Iwb, p->If, p->wb);
      mv(p->Iat, p->If, p->at);
      pom_v3_cross(g, p->wb, p->Iwb);
      for (int e = 0; e < 3; ++e)
        p->H[e] = -p->Iat[e] - g[e];
    }
  }
}

/* I' v = beta x (I v) - I (beta x v), the fixed-frame inertia turning by beta;
 * Iv = I v given. */
static void inertia_turn(double out[3], const body_pre *p, int spin_free, const double beta[3],
                         const double v[3], const double Iv[3]) {
  double bv[3], Ibv[3];
  pom_v3_cross(out, beta, Iv);
  if (spin_free) return; /* I = I_t on the body's angular velocities: I' v = 0 */
  pom_v3_cross(bv, beta, v);
  mv(Ibv, p->If, bv);
  pom_v3_sub(out, out, Ibv);
}

/* r = f' - M' omega_dot over the bodies along one direction: a platform
 * rotation increment t (fixed frame; wdir = 0) or omega's wdir (t = NULL),
 * with D the twists' derivatives in that direction (pom_kin_twists_diff). */
static void body_terms_diff(const pom_dyn_model *m, const pom_kin_twists *tw,
                            const pom_kin_twists *D, const body_pre *bp, const double *w,
                            const double *wd, const double *t, const double wdir[3], double r[3]) {
  const dyn_exact *ex = exact_of(m);
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    const pom_kin_body_twist *tb = &tw->body[bd->mech_index], *Db = &D->body[bd->mech_index];
    const body_pre *p = &bp[b];
    double tmp[3], tmp2[3], acc[3];
    /* translation: Acm'^T G + Acm^T (F' - m Acm' omega_dot), with
     * Acm'^T G = A'^T G + B^T (rho' x G) + B'^T (rho x G) and
     * -F'/m + Acm' omega_dot = a_cm0' + A' omega_dot - rho' x B omega_dot - rho x B' omega_dot */
    const int turn = t != NULL; /* along omega A' = B' = 0 and the body does not turn */
    if (turn) {
      mtv(tmp, Db->A, p->G);
      pom_v3_add(r, r, tmp);
      mv(acc, Db->A, wd);
      pom_v3_add(acc, acc, Db->a_bias);
    } else {
      pom_v3_copy(acc, Db->a_bias);
    }
    if (p->rot) {
      /* the body turns by beta = B t: rho' = beta x rho; w_b' = B' w + B wdir */
      double beta[3] = {0.0, 0.0, 0.0}, drho[3] = {0.0, 0.0, 0.0}, dwb[3], wr[3], x[3];
      double Bpwd[3] = {0.0, 0.0, 0.0};
      if (turn) {
        mv(beta, tb->B, t);
        pom_v3_cross(drho, beta, p->rho);
        pom_v3_cross(tmp, drho, p->G);
        mtv(tmp2, tb->B, tmp);
        pom_v3_add(r, r, tmp2);
        mtv(tmp, Db->B, p->rG);
        pom_v3_add(r, r, tmp);
        mv(dwb, Db->B, w);
        mv(Bpwd, Db->B, wd);
      } else {
        mv(dwb, tb->B, wdir);
      }
      /* a_cm0' = alpha0' x rho + alpha0 x rho' + a0' + w_b' x (w_b x rho)
       *          + w_b x (w_b' x rho + w_b x rho') (a0' added above) */
      pom_v3_cross(tmp, Db->alpha_bias, p->rho);
      pom_v3_add(acc, acc, tmp);
      pom_v3_cross(tmp, p->at, drho); /* alpha0 x rho' - rho' x B omega_dot */
      pom_v3_add(acc, acc, tmp);
      pom_v3_cross(tmp, p->rho, Bpwd);
      pom_v3_sub(acc, acc, tmp);
      pom_v3_cross(wr, p->wb, p->rho);
      pom_v3_cross(tmp, dwb, wr);
      pom_v3_add(acc, acc, tmp);
      pom_v3_cross(tmp, dwb, p->rho);
      pom_v3_cross(tmp2, p->wb, drho);
      pom_v3_add(tmp, tmp, tmp2);
      pom_v3_cross(x, p->wb, tmp);
      pom_v3_add(acc, acc, x);
      /* rotation: B'^T H + B^T (T' - I' B omega_dot - I B' omega_dot), that is
       * -B^T (I' at + I (alpha0' + B' omega_dot) + w_b' x I w_b
       *       + w_b x (I' w_b + I w_b')) */
      const int sf = ex->spin_free[b];
      double s[3], Iv[3];
      if (turn) {
        mtv(tmp, Db->B, p->H);
        pom_v3_add(r, r, tmp);
      }
      inertia_turn(s, p, sf, beta, p->at, p->Iat);
      pom_v3_add(x, Db->alpha_bias, Bpwd);
      if (sf)
        pom_v3_scale(Iv, ex->transverse[b], x);
      else
        mv(Iv, p->If, x);
      pom_v3_add(s, s, Iv);
      if (!sf) {
        pom_v3_cross(tmp, dwb, p->Iwb);
        pom_v3_add(s, s, tmp);
        inertia_turn(tmp, p, sf, beta, p->wb, p->Iwb);
        mv(Iv, p->If, dwb);
        pom_v3_add(tmp, tmp, Iv);
        pom_v3_cross(x, p->wb, tmp);
        pom_v3_add(s, s, x);
      }
      mtv(tmp, tb->B, s);
      pom_v3_sub(r, r, tmp);
    }
    mtv(tmp, p->Acm, acc);
    pom_v3_axpy(r, r, -bd->mass, tmp);
  }
}

/* Rotation increment per orientation state (docs/dynamics-exact.md section
 * 5): column j of G is d theta / d o_j, with dR = [d theta]x R. ZYX Euler
 * (psi, theta, phi): z, Rz(psi) y, Rz(psi) Ry(theta) x; quaternion (the
 * state q, normalized inside): 2 (e_j (x) q^*)_vec / |q| with q^* the
 * normalized conjugate. G is 3 x n_ori, row-major with 4 columns. */
static void orientation_map(const dyn_exact *ex, const double *o, const double trig[4],
                            double G[12]) {
  memset(G, 0, 12 * sizeof *G);
  if (ex->n_ori == 4) {
    double n = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2] + o[3] * o[3]);
    double s = o[0] / n, v[3] = {o[1] / n, o[2] / n, o[3] / n}, f = 2.0 / n;
    for (int r = 0; r < 3; ++r)
      G[4 * r] = -f * v[r];
    for (int c = 0; c < 3; ++c) { /* s e_c - e_c x v */
      double e[3] = {0.0, 0.0, 0.0}, x[3];
      e[c] = 1.0;
      pom_v3_cross(x, e, v);
      for (int r = 0; r < 3; ++r)
        G[4 * r + 1 + c] = f * (s * e[r] - x[r]);
    }
    return;
  }
  const double cps = trig[0], sps = trig[1], cth = trig[2], sth = trig[3];
  G[4 * 2 + 0] = 1.0;
  G[4 * 0 + 1] = -sps;
  G[4 * 1 + 1] = cps;
  G[4 * 0 + 2] = cps * cth;
  G[4 * 1 + 2] = sps * cth;
  G[4 * 2 + 2] = -sth;
}

/* Partials of the orientation rates: dod[r][j] against o_j (j < n_ori) and
 * against omega_k (j = n_ori + k), row-major with 7 columns. */
static void orientation_rate_partials(const dyn_exact *ex, const double *o, const double *w,
                                      const double trig[4], double dod[28]) {
  memset(dod, 0, 28 * sizeof *dod);
  if (ex->n_ori == 4) {
    /* q_dot = 1/2 (0, w) (x) q: linear in q and in w */
    const double wq[4] = {0.0, w[0], w[1], w[2]};
    for (int j = 0; j < 4; ++j) {
      double e[4] = {0.0, 0.0, 0.0, 0.0}, r[4];
      e[j] = 1.0;
      pom_quat_mul(r, wq, e);
      for (int i = 0; i < 4; ++i)
        dod[7 * i + j] = 0.5 * r[i];
    }
    for (int k = 0; k < 3; ++k) {
      double ek[4] = {0.0, 0.0, 0.0, 0.0}, r[4];
      ek[1 + k] = 1.0;
      pom_quat_mul(r, ek, o);
      for (int i = 0; i < 4; ++i)
        dod[7 * i + 4 + k] = 0.5 * r[i];
    }
    return;
  }
  /* psi_dot = tan(theta) a + w_z, theta_dot = b, phi_dot = a / cos(theta) with
   * a = c_psi w_x + s_psi w_y, b = -s_psi w_x + c_psi w_y */
  const double cps = trig[0], sps = trig[1], cth = trig[2], sth = trig[3], tth = sth / cth;
  const double a = cps * w[0] + sps * w[1], b = -sps * w[0] + cps * w[1];
  dod[7 * 0 + 0] = tth * b;
  dod[7 * 0 + 1] = a / (cth * cth);
  dod[7 * 1 + 0] = -a;
  dod[7 * 2 + 0] = b / cth;
  dod[7 * 2 + 1] = a * sth / (cth * cth);
  const double E[9] = {cps * tth, sps * tth, 1.0, -sps, cps, 0.0, cps / cth, sps / cth, 0.0};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      dod[7 * r + 3 + k] = E[3 * r + k];
}

/* The orientation and omega columns (docs/dynamics-exact.md section 5), from
 * the second-order kinematics at y: omega_dot = M^-1 f moves by
 * M^-1 (f' - M' omega_dot) with f' and M' from body_terms_diff and the
 * actuators' J_a' F_a + J_a (F_q q_a' + F_qd qd_a'); the actuator and
 * accumulator rows by the law's partials against q_a, qd_a; the orientation
 * rows by the rate map's. Also leaves xw->tw and xw->M at y for
 * electrical_columns. f0 is the right-hand side at y. Returns 0, or 1
 * (recoverable) where the evaluation at y fails. */
static int mechanical_columns(const pom_dyn_model *m, pom_dyn_data *d, const double *y,
                              const double *f0) {
  const dyn_exact *ex = exact_of(m);
  dyn_exact_work *xw = work_of(d);
  const pom_dyn_actuator *ap = &m->par.actuator;
  const double Rc = ap->resistance;
  double R[9], trig[4] = {1.0, 0.0, 1.0, 0.0};
  state_rotation(m, y, R, trig);
  if (ex->n_ori == 3 && trig[2] < m->par.scene.euler_cos_min) return 1;
  const double *w = y + ex->omega, *wd = f0 + ex->omega;
  if (pom_kin_body_twists_diff(&ex->arch, R, w, &xw->tw, &xw->dtw, NULL) != POM_OK) return 1;
  const pom_kin_twists *tw = &xw->tw;
  double M[9] = {0}, f[3] = {0}, pe = 0.0;
  body_terms(m, tw, w, M, f, &pe);
  memcpy(xw->M, M, sizeof M);
  body_pre bp[POM_MECH_MAX_BODIES];
  body_pre_eval(m, tw, &xw->dtw, w, wd, bp);

  /* per direction (theta_0..2, omega_0..2): omega_dot', q_a', qd_a' */
  dyn_law_partials lp[POM_MECH_MAX_ACTUATORS];
  double dwd[6][3], dq[POM_MECH_MAX_ACTUATORS][6], dqd[POM_MECH_MAX_ACTUATORS][6];
  for (int a = 0; a < m->n_actuators; ++a) {
    const int limb = ex->act_limb[a];
    pom_dyn_actuator_law_partials(m, d, a, tw->q[limb], pom_v3_dot(tw->J + 3 * limb, w), y, &lp[a]);
  }
  for (int dir = 0; dir < 6; ++dir) {
    const int k = dir % 3, rot = dir < 3;
    double t[3] = {0.0, 0.0, 0.0}, wdir[3] = {0.0, 0.0, 0.0}, df[3] = {0.0, 0.0, 0.0};
    const pom_kin_twists *D = rot ? &xw->dtw.d_theta[k] : &xw->dtw.d_omega[k];
    (rot ? t : wdir)[k] = 1.0;
    body_terms_diff(m, tw, D, bp, w, wd, rot ? t : NULL, wdir, df); /* f' - M' omega_dot */
    for (int a = 0; a < m->n_actuators; ++a) {
      const int limb = ex->act_limb[a];
      const double *Jr = tw->J + 3 * limb, *dJ = D->J + 3 * limb;
      dq[a][dir] = rot ? Jr[k] : 0.0;
      dqd[a][dir] = rot ? pom_v3_dot(dJ, w) : Jr[k];
      double dF = lp[a].dF_dq * dq[a][dir] + lp[a].dF_dqd * dqd[a][dir];
      for (int r = 0; r < 3; ++r)
        df[r] += dJ[r] * lp[a].effort + Jr[r] * dF;
    }
    if (!spd_solve(dwd[dir], M, df)) return 1;
  }

  /* the columns: orientation states through G, then omega */
  double G[12], dod[28];
  orientation_map(ex, y + ex->ori, trig, G);
  orientation_rate_partials(ex, y + ex->ori, w, trig, dod);
  const int n_mech = ex->n_ori + 3;
  for (int j = 0; j < n_mech; ++j) {
    const int col = ex->ori + j;
    double c[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; /* weights of the six directions */
    if (j < ex->n_ori)
      for (int r = 0; r < 3; ++r)
        c[r] = G[4 * r + j];
    else
      c[3 + j - ex->n_ori] = 1.0;
    double dw[3] = {0.0, 0.0, 0.0};
    for (int e = 0; e < 6; ++e)
      if (c[e] != 0.0)
        for (int r = 0; r < 3; ++r)
          dw[r] += c[e] * dwd[e][r];
    for (long kk = m->colptr[col]; kk < m->colptr[col + 1]; ++kk)
      d->jac[kk] = 0.0;
    for (long kk = m->colptr[col]; kk < m->colptr[col + 1]; ++kk) {
      const int i = m->rowind[kk];
      if (i >= ex->ori && i < ex->ori + ex->n_ori)
        d->jac[kk] = dod[7 * (i - ex->ori) + j];
      else if (i >= ex->omega && i < ex->omega + 3)
        d->jac[kk] = dw[i - ex->omega];
    }
    for (int a = 0; a < m->n_actuators; ++a) {
      const dyn_actuator *ac = &m->act[a];
      const dyn_law_partials *g = &lp[a];
      double sq = 0.0, sqd = 0.0;
      for (int e = 0; e < 6; ++e) {
        sq += c[e] * dq[a][e];
        sqd += c[e] * dqd[a][e];
      }
      const double du = g->du_dq * sq + g->du_dqd * sqd, di = g->di_dq * sq + g->di_dqd * sqd;
      const double dpw = du * g->i + g->u * di, pw = g->u * g->i;
      for (long kk = m->colptr[col]; kk < m->colptr[col + 1]; ++kk) {
        const int i = m->rowind[kk], r = i - ac->acc_state;
        if (i == ac->flux_state)
          d->jac[kk] = g->dflux_dq * sq + g->dflux_dqd * sqd;
        else if (i == ac->ctrl_state)
          d->jac[kk] = g->dzd_dq * sq + g->dzd_dqd * sqd;
        else if (r == DYN_ACC_SOURCE)
          d->jac[kk] = dpw;
        else if (r == DYN_ACC_SOURCE_POS)
          d->jac[kk] = pw > 0 ? dpw : 0.0;
        else if (r == DYN_ACC_COIL)
          d->jac[kk] = 2.0 * Rc * g->i * di;
        else if (r == DYN_ACC_BEARING)
          d->jac[kk] = g->dbearing_dqd * sqd;
      }
    }
  }
  return 0;
}

/* 1 when the orientation and omega columns go analytically: solver.jacobian
 * analytic (the default), a controller with analytic partials and an
 * architecture with second-order kinematics. */
static int analytic_mechanical(const pom_dyn_model *m) {
  return m->par.solver.jacobian == POM_JAC_ANALYTIC && m->ctrl_analytic &&
         pom_kin_has_twists_diff(&exact_of(m)->arch);
}

int pom_dyn_exact_jacobian(pom_dyn_data *d, const double *y, const double *f0, double *yp,
                           double *fp) {
  if (analytic_mechanical(d->m)) {
    ++d->jac_count;
    int r = mechanical_columns(d->m, d, y, f0);
    if (r != 0) return r;
    electrical_columns(d->m, d, y);
    return 0;
  }
  /* the mechanical columns by differences; the last one differenced is an
   * omega column, whose evaluation leaves M, q and J at the rotation of y
   * (they do not depend on omega) */
  int r = pom_dyn_fd_jacobian(d, y, f0, yp, fp);
  if (r != 0) return r;
  if (d->m->ctrl_analytic) electrical_columns(d->m, d, y);
  return 0;
}

/* CVODE's linear-system callback: A = I - gamma J into the dense matrix, J
 * re-evaluated unless CVODE says the stored one is still good (jok). Only
 * the leading n_jac columns are non-trivial (the accumulator columns of J
 * are zero); the block solver reads nothing else. */
static int exact_linsys(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, sunbooleantype jok,
                        sunbooleantype *jcur, sunrealtype gamma, void *user_data, N_Vector tmp1,
                        N_Vector tmp2, N_Vector tmp3) {
  (void)tmp3;
  pom_dyn_data *d = user_data;
  const pom_dyn_model *m = d->m;
  const int n = m->n_states, nb = exact_of(m)->n_jac;
  d->t = t; /* the differenced evaluations at the Jacobian's time */
  if (!jok || !d->jac_valid) {
    int rl = pom_dyn_rhs_if_lazy(d, t, y, fy); /* fy skipped by a sensitivity run */
    if (rl != 0) return rl;
    d->t = t;
    int r = pom_dyn_exact_jacobian(d, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                                   N_VGetArrayPointer(tmp1), N_VGetArrayPointer(tmp2));
    if (r != 0) return r;
    d->jac_valid = 1;
    *jcur = SUNTRUE;
  } else {
    *jcur = SUNFALSE;
  }
  for (int j = 0; j < n; ++j) {
    double *col = SUNDenseMatrix_Column(A, j);
    if (j < nb) {
      for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k)
        col[m->rowind[k]] = -gamma * d->jac[k];
    } else {
      memset(col, 0, (size_t)n * sizeof(double));
    }
    col[j] += 1.0;
  }
  return 0;
}

/* ---- block linear solver --------------------------------------------------- */
/* The Newton matrix I - gamma J of the exact path is block lower triangular:
 * the accumulator columns of J are zero (they feed nothing back), so
 * A = [A11 0; A21 I] with A11 of size n_jac (12-13); the shared linear-system
 * callback (dyn_fdjac.c) writes A into a dense matrix. Setup factors A11 by LU
 * with partial pivoting; solve does the small block and then x2 = b2 - A21 x1.
 * SUNDIALS' dense LU (built without optimization on this system) on the full
 * n = 28 matrix took a third of the run (bench/README.md). */
typedef struct {
  int n;       /* states */
  int nb;      /* leading block (n_jac) */
  double *lu;  /* [nb * nb] LU factors of A11, column-major */
  double *a21; /* [(n - nb) * nb] A21, column-major (copied at setup) */
  int *piv;    /* [nb] row pivots */
} exact_ls;

static SUNLinearSolver_Type exact_ls_gettype(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID exact_ls_getid(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_CUSTOM;
}

static int exact_ls_setup(SUNLinearSolver S, SUNMatrix A) {
  exact_ls *c = S->content;
  const int nb = c->nb;
  double *lu = c->lu;
  const int nr = c->n - nb;
  for (int j = 0; j < nb; ++j) {
    const double *col = SUNDenseMatrix_Column(A, j);
    memcpy(lu + (size_t)j * (size_t)nb, col, (size_t)nb * sizeof(double));
    memcpy(c->a21 + (size_t)j * (size_t)nr, col + nb, (size_t)nr * sizeof(double));
  }
  for (int k = 0; k < nb; ++k) {
    int p = k;
    double big = fabs(lu[k * nb + k]);
    for (int i = k + 1; i < nb; ++i)
      if (fabs(lu[k * nb + i]) > big) {
        big = fabs(lu[k * nb + i]);
        p = i;
      }
    c->piv[k] = p;
    if (!(big > 0)) return SUNLS_LUFACT_FAIL; /* recoverable: CVODE retries smaller */
    if (p != k)
      for (int j = 0; j < nb; ++j) {
        double t = lu[j * nb + k];
        lu[j * nb + k] = lu[j * nb + p];
        lu[j * nb + p] = t;
      }
    double inv = 1.0 / lu[k * nb + k];
    for (int i = k + 1; i < nb; ++i)
      lu[k * nb + i] *= inv;
    for (int j = k + 1; j < nb; ++j) {
      double a = lu[j * nb + k];
      if (a != 0.0)
        for (int i = k + 1; i < nb; ++i)
          lu[j * nb + i] -= a * lu[k * nb + i];
    }
  }
  return SUNLS_SUCCESS;
}

static int exact_ls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector xv, N_Vector bv,
                          sunrealtype tol) {
  (void)tol;
  exact_ls *c = S->content;
  const int nb = c->nb, n = c->n;
  const double *lu = c->lu;
  double *x = N_VGetArrayPointer(xv);
  const double *b = N_VGetArrayPointer(bv);
  if (x != b) memcpy(x, b, (size_t)n * sizeof(double));
  for (int k = 0; k < nb; ++k) { /* all row interchanges first (as LAPACK getrs) */
    int p = c->piv[k];
    if (p != k) {
      double t = x[k];
      x[k] = x[p];
      x[p] = t;
    }
  }
  /* x[k] held in a local: x may alias the factors for all the compiler knows */
  for (int k = 0; k < nb; ++k) {
    const double xk = x[k], *lk = lu + k * nb;
    for (int i = k + 1; i < nb; ++i)
      x[i] -= lk[i] * xk;
  }
  for (int k = nb - 1; k >= 0; --k) {
    const double xk = x[k] / lu[k * nb + k], *lk = lu + k * nb;
    x[k] = xk;
    for (int i = 0; i < k; ++i)
      x[i] -= lk[i] * xk;
  }
  (void)A;
  for (int j = 0; j < nb; ++j) {
    const double xj = x[j], *col = c->a21 + j * (n - nb) - nb;
    for (int i = nb; i < n; ++i)
      x[i] -= col[i] * xj;
  }
  return SUNLS_SUCCESS;
}

static int exact_ls_free(SUNLinearSolver S) {
  if (!S) return 0;
  exact_ls *c = S->content;
  if (c) {
    free(c->lu);
    free(c->a21);
    free(c->piv);
    free(c);
  }
  S->content = NULL;
  SUNLinSolFreeEmpty(S);
  return 0;
}

static SUNLinearSolver exact_linear_solver(const pom_dyn_model *m, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (!S) return NULL;
  exact_ls *c = calloc(1, sizeof *c);
  S->content = c;
  S->ops->gettype = exact_ls_gettype;
  S->ops->getid = exact_ls_getid;
  S->ops->setup = exact_ls_setup;
  S->ops->solve = exact_ls_solve;
  S->ops->free = exact_ls_free;
  if (c) {
    c->n = m->n_states;
    c->nb = exact_of(m)->n_jac;
    c->lu = calloc((size_t)c->nb * (size_t)c->nb, sizeof *c->lu);
    c->piv = calloc((size_t)c->nb, sizeof *c->piv);
    c->a21 = calloc((size_t)(c->n - c->nb) * (size_t)c->nb, sizeof *c->a21);
  }
  if (!c || !c->lu || !c->piv || !c->a21) {
    exact_ls_free(S);
    return NULL;
  }
  return S;
}

/* ---- state queries for the shared driver ---------------------------------- */
static void exact_initial(const pom_dyn_model *m, double *y, const pom_dyn_initial *init) {
  const dyn_exact *ex = exact_of(m);
  memset(y, 0, (size_t)m->n_states * sizeof(double));
  if (ex->n_ori == 4) y[ex->ori] = 1.0;
  if (init) memcpy(y + ex->omega, init->omega[ex->platform_mech], 3 * sizeof(double));
}

static int exact_near_singular(const pom_dyn_model *m, const double *y) {
  const dyn_exact *ex = exact_of(m);
  return ex->n_ori == 3 && cos(y[ex->ori + 1]) < m->par.scene.euler_cos_min;
}

static void exact_positions(const pom_dyn_model *m, const double *y, double *q) {
  const dyn_exact *ex = exact_of(m);
  double R[9], qq[3] = {NAN, NAN, NAN};
  state_rotation(m, y, R, NULL);
  (void)pom_kin_inverse(&ex->arch, R, qq, NULL); /* NaN when unassemblable */
  for (int a = 0; a < m->n_actuators; ++a)
    q[a] = qq[ex->act_limb[a]];
}

/* Dexterity 1/kappa(J) of the kinematic Jacobian at the platform pose of
 * state y (NaN when the pose cannot be assembled): failure diagnostics. */
static double exact_dexterity(const pom_dyn_model *m, const double *y) {
  double R[9], q[3], J[9], dex = NAN;
  state_rotation(m, y, R, NULL);
  if (pom_kin_inverse_jacobian(&exact_of(m)->arch, R, q, J, NULL) == POM_OK)
    pom_kin_dexterity(J, NULL, NULL, &dex);
  return dex;
}

/* Rigid joints: say how close the pose is to a singularity, where a limb
 * locks and the integrator stalls (docs/dynamics-exact.md section 3). */
static pom_status exact_solver_failure(const pom_dyn_model *m, pom_dyn_data *d, double t,
                                       pom_error *err) {
  double dex = exact_dexterity(m, N_VGetArrayPointer(d->y));
  return pom_error_set(err, isnan(dex) ? POM_ERR_UNREACHABLE : POM_ERR_SOLVER, __FILE__, __LINE__,
                       "rigid joints: CVODE failed at t = %.6g s with the mechanism at 1/kappa(J) "
                       "= %.3g (1 isotropic, 0 singular%s): %s",
                       t, dex, isnan(dex) ? ", NaN: not assemblable" : "", d->cvode_msg);
}

static double exact_stored(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  if (exact_eval(m, d, y, NULL, 1) != 0 && d->out.kin_fail) return NAN;
  const dyn_exact_work *xw = work_of(d);
  return pom_dyn_add_coil_energy(m, y, xw->kinetic + xw->potential);
}

static pom_status exact_body_pose(const pom_dyn_model *m, const double *y, int k, double R[9],
                                  double x[3], pom_error *err) {
  double Rp[9], d0[3], r[3];
  pom_kin_twists tw;
  state_rotation(m, y, Rp, NULL);
  POM_TRY(pom_kin_body_twists(&exact_of(m)->arch, Rp, NULL, &tw, err));
  const pom_kin_body_twist *t = &tw.body[k];
  pom_m3_copy(R, t->R);
  pom_v3_sub(d0, m->body[m->slot_of_mech[k]].cm_home, t->ref_home);
  pom_m3_apply(r, t->R, d0);
  pom_v3_add(x, t->ref, r);
  return POM_OK;
}

/* ---- model and data ------------------------------------------------------- */
static void exact_model_free(pom_dyn_model *m) {
  free(m->form_model);
  m->form_model = NULL;
}

/* A few states: a dense Newton matrix and the block solver above. */
static pom_status exact_data_init(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err) {
  const sunindextype n = m->n_states;
  d->form_data = calloc(1, sizeof(dyn_exact_work));
  if (!d->form_data) POM_FAIL(err, POM_ERR_NOMEM, "allocating exact-path scratch");
  d->A = SUNDenseMatrix(n, n, d->ctx);
  if (d->A) d->LS = exact_linear_solver(m, d->ctx);
  return POM_OK;
}

static void exact_data_free(pom_dyn_data *d) {
  free(d->form_data);
  d->form_data = NULL;
}

/* ---- queries for tests ---------------------------------------------------- */
int pom_dyn_exact_layout(const pom_dyn_model *m, int *ori, int *n_ori, int *omega) {
  if (m->form != &pom_dyn_form_exact) return 0;
  const dyn_exact *ex = exact_of(m);
  *ori = ex->ori;
  *n_ori = ex->n_ori;
  *omega = ex->omega;
  return 1;
}

const double *pom_dyn_exact_mass_matrix(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  if (m->form != &pom_dyn_form_exact || !d->form_data) return NULL;
  (void)exact_eval(m, d, y, NULL, 1);
  return work_of(d)->M;
}

/* ---- the table ------------------------------------------------------------ */
const dyn_formulation pom_dyn_form_exact = {
    .name = "rigid",
    .natural_tolerances = 1,
    .init = exact_init,
    .model_free = exact_model_free,
    .data_init = exact_data_init,
    .data_free = exact_data_free,
    .eval = exact_rhs,
    .linsys = exact_linsys,
    .initial = exact_initial,
    .positions = exact_positions,
    .stored = exact_stored,
    .near_singular = exact_near_singular,
    .platform_rotation = exact_platform_rotation,
    .body_pose = exact_body_pose,
    .solver_failure = exact_solver_failure,
};

/* Mass matrix M (about omega) and actuator Jacobian J (rows in actuator
 * order) at home, at rest; 0, or 1 when the mechanism cannot be assembled. */
static int home_terms(const pom_dyn_model *m, double M[9], double J[9]) {
  const dyn_exact *ex = exact_of(m);
  pom_kin_twists tw;
  double I3[9], w[3] = {0.0, 0.0, 0.0}, f[3] = {0.0, 0.0, 0.0}, pe = 0.0;
  pom_m3_identity(I3);
  if (pom_kin_body_twists(&ex->arch, I3, w, &tw, NULL) != POM_OK) return 1;
  memset(M, 0, 9 * sizeof *M);
  body_terms(m, &tw, w, M, f, &pe);
  for (int a = 0; a < m->n_actuators; ++a)
    memcpy(J + 3 * a, tw.J + 3 * ex->act_limb[a], 3 * sizeof *J);
  return 0;
}

/* ---- the controller's view (model-based control) ----------------------------- */
int pom_dyn_exact_terms(const pom_dyn_model *m, pom_dyn_data *d, const double R[9],
                        const double w[3], double M[9], double f[3], double q[3], double J[9]) {
  const dyn_exact *ex = exact_of(m);
  pom_kin_twists *tw = &work_of(d)->tw;
  if (pom_kin_body_twists(&ex->arch, R, w, tw, NULL) != POM_OK) return 1;
  double pe = 0.0;
  memset(M, 0, 9 * sizeof *M);
  memset(f, 0, 3 * sizeof *f);
  body_terms(m, tw, w, M, f, &pe);
  for (int a = 0; a < m->n_actuators; ++a) { /* q and J in actuator order */
    int limb = ex->act_limb[a];
    q[a] = tw->q[limb];
    memcpy(J + 3 * a, tw->J + 3 * limb, 3 * sizeof *J);
  }
  return 0;
}
