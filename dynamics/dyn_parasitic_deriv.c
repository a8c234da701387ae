/* dyn_parasitic_deriv.c - the analytic Jacobian of the parasitic formulation's
 * right-hand side over the model's CSC pattern (docs/dynamics.md section 7,
 * "Analytic Jacobian"). Every joint's efforts are differentiated with
 * respect to the twist variations xi = (dx, dtheta, dv, dw) of its two
 * bodies; the pair blocks are then mapped to state columns (u, p, h',
 * orientation) and to the rows of the Eulerian junction structures. The
 * scatter map from the blocks to the CSC entries is built once per model;
 * the evaluation allocates nothing. */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* twist variation of one body: position, rotation (fixed frame), CM
 * velocity, angular velocity (fixed frame) */
enum { XI_X = 0, XI_TH = 3, XI_V = 6, XI_W = 9, XI_N = 12 };
/* columns of a joint's local derivatives: xi of side 0, then of side 1 */
#define JC (2 * XI_N)

/* Layout of the analytic Jacobian's scratch values (the form_model of a
 * parasitic model): body-pair blocks, then per actuator and side the body
 * rows against its (flux, integral) columns and its rows against the body
 * columns, then its own 2 x 2 block. */
typedef struct {
  int pair[POM_MECH_MAX_BODIES][POM_MECH_MAX_BODIES]; /* block of (row body, column body), -1 */
  int n_pairs;
  long act_col; /* first value of the actuator-column blocks [a][side][body_states][2] */
  long act_row; /* first value of the actuator-row blocks [a][side][2][body_states] */
  long act_own; /* first value of the actuator blocks [a][2][2] */
  long n_vals;
  long *src; /* [nnz] value index of each CSC entry, -1: a structural zero */
} pjac_layout;

/* Per-worker scratch (d->form_data of a parasitic model). */
typedef struct {
  double *vals;                        /* [n_vals] the blocks of the layout */
  double (*dw)[6][XI_N];               /* [n_pairs] d(F, T of row body) / d(xi of column body) */
  double G[POM_MECH_MAX_BODIES][3][4]; /* dtheta / d(orientation states) per body */
} pjac_data;

/* ---- small linear algebra ------------------------------------------------ */
/* D[r][c0 + c] += s A[r][c] for a 3x3 A */
static void add_block(double D[3][JC], int c0, double s, const double A[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      D[r][c0 + c] += s * A[3 * r + c];
}

/* D[r][c0 + c] += s delta_rc */
static void add_identity(double D[3][JC], int c0, double s) {
  for (int r = 0; r < 3; ++r)
    D[r][c0 + r] += s;
}

/* out += s A B (A 3x3, B 3 x JC) */
static void add_mul(double out[3][JC], double s, const double A[9], double B[3][JC]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < JC; ++c)
      out[r][c] += s * (A[3 * r] * B[0][c] + A[3 * r + 1] * B[1][c] + A[3 * r + 2] * B[2][c]);
}

/* out = v^T B (a row of JC) */
static void row_of(double out[JC], const double v[3], double B[3][JC]) {
  for (int c = 0; c < JC; ++c)
    out[c] = v[0] * B[0][c] + v[1] * B[1][c] + v[2] * B[2][c];
}

/* out += v w^T (outer product of a column and a row) */
static void add_outer(double out[3][JC], double s, const double v[3], const double w[JC]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < JC; ++c)
      out[r][c] += s * v[r] * w[c];
}

/* row[c0 + c] += s v[c] */
static void add_row3(double row[JC], int c0, double s, const double v[3]) {
  for (int c = 0; c < 3; ++c)
    row[c0 + c] += s * v[c];
}

/* [a]x [b]x */
static void skew2(double S[9], const double a[3], const double b[3]) {
  double A[9], B[9];
  pom_m3_skew(A, a);
  pom_m3_skew(B, b);
  pom_m3_mul(S, A, B);
}

/* ---- the actuator law's partial derivatives ------------------------------ */
/* Derivatives of the effort (force or torque) and of the coil flux rate of
 * actuator a with respect to q, q_dot, the flux and the integral (docs 7):
 * the saturated law's gain is 0 in saturation. */
typedef struct {
  double f_q, f_qd, f_lam, f_z; /* effort */
  double l_q, l_qd, l_lam, l_z; /* flux rate */
  double z_q, z_qd, z_z;        /* controller state rate (the controller's own partials) */
} act_partials;

static void actuator_partials(const pom_dyn_model *m, const pom_dyn_data *d, int a, double q,
                              double qd, const double *y, act_partials *ap) {
  const pom_dyn_actuator *p = &m->par.actuator;
  const dyn_actuator *ac = &m->act[a];
  pom_dyn_ctrl_partials cp;
  double u_raw = pom_dyn_controller_law(m, d, a, q, qd, y, NULL, &cp);
  double du_q = cp.du_dq, du_qd = cp.du_dqd, du_z = cp.du_dz[0];
  /* the clamp of pom_dyn_actuator_law: u = u_raw on [-limit, limit] */
  double gain = (u_raw <= p->voltage_limit && u_raw >= -p->voltage_limit) ? 1.0 : 0.0;
  double b = m->par.scene.bearing_friction ? p->bearing_friction : 0.0;
  double K = p->force_constant, R = p->resistance;
  memset(ap, 0, sizeof *ap);
  if (ac->flux_state >= 0) {
    /* i = lambda / L; lambda_dot = u - R i - K q_dot; effort K i - b q_dot */
    ap->f_lam = K / p->inductance;
    ap->f_qd = -b;
    ap->l_q = gain * du_q;
    ap->l_qd = gain * du_qd - K;
    ap->l_z = gain * du_z;
    ap->l_lam = -R / p->inductance;
  } else {
    /* quasi-static coil: i = (u - K q_dot) / R */
    ap->f_q = K * gain * du_q / R;
    ap->f_qd = K * (gain * du_qd - K) / R - b;
    ap->f_z = K * gain * du_z / R;
  }
  ap->z_q = cp.dzd_dq[0];
  ap->z_qd = cp.dzd_dqd[0];
  ap->z_z = cp.dzd_dz[0][0];
}

/* ---- one joint ------------------------------------------------------------- */
/* Derivatives of one joint's efforts with respect to the xi of its sides. */
typedef struct {
  double F1[3][JC]; /* force on side 1 (side 0 gets -F1) */
  double T0[3][JC]; /* torque on side 0 about its CM */
  double T1[3][JC]; /* torque on side 1 about its CM */
  double Fa1[3][2]; /* force on side 1 against (flux, integral) of the joint's actuator */
  double Ta0[3][2]; /* torques against (flux, integral) */
  double Ta1[3][2];
  double lam[JC]; /* flux rate of the actuator against xi */
  double zr[JC];  /* integral rate against xi */
  act_partials ap;
} joint_deriv;

/* Side s of joint jt at the current evaluation: the point's position p, its
 * lever arm r, the body's rotation, velocity and angular velocity; and the
 * derivatives of p and of the point velocity with respect to xi (columns of
 * side s only). The ground is at rest. */
typedef struct {
  double p[3], r[3], v[3], w[3];
  const double *R;
} side_eval;

static const double identity3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

static void side_setup(const pom_dyn_data *d, const dyn_joint *jt, int s, side_eval *se,
                       double Pp[3][JC], double Pv[3][JC], double sign) {
  int slot = jt->slot[s];
  if (slot < 0) {
    pom_v3_copy(se->p, jt->rho[s]);
    pom_v3_set(se->r, 0.0, 0.0, 0.0);
    pom_v3_set(se->v, 0.0, 0.0, 0.0);
    pom_v3_set(se->w, 0.0, 0.0, 0.0);
    se->R = identity3;
    return;
  }
  const dyn_body_eval *e = &d->be[slot];
  se->R = e->R;
  pom_m3_apply(se->r, e->R, jt->rho[s]);
  pom_v3_add(se->p, e->x, se->r);
  double wxr[3];
  pom_v3_cross(wxr, e->w, se->r);
  pom_v3_add(se->v, e->v, wxr);
  pom_v3_copy(se->w, e->w);
  /* dp = dx - [r]x dtheta; dv_p = dv - [r]x dw - [w]x [r]x dtheta */
  double Sr[9], Swr[9];
  pom_m3_skew(Sr, se->r);
  skew2(Swr, e->w, se->r);
  int c0 = s * XI_N;
  add_identity(Pp, c0 + XI_X, sign);
  add_block(Pp, c0 + XI_TH, -sign, Sr);
  add_identity(Pv, c0 + XI_V, sign);
  add_block(Pv, c0 + XI_W, -sign, Sr);
  add_block(Pv, c0 + XI_TH, -sign, Swr);
}

/* A scalar coordinate c = m . d with m = R0 m_home turning with side 0 and
 * its rate m . s_rel (s_rel = d_dot - w0 x d): their derivatives. */
static void rotating_coord(double dc[JC], double dcr[JC], const double mk[3], const double dd[3],
                           const double srel[3], double Dd[3][JC], double Ds[3][JC]) {
  double mxd[3], mxs[3];
  pom_v3_cross(mxd, mk, dd);
  pom_v3_cross(mxs, mk, srel);
  row_of(dc, mk, Dd);
  row_of(dcr, mk, Ds);
  add_row3(dc, XI_TH, 1.0, mxd);
  add_row3(dcr, XI_TH, 1.0, mxs);
}

static void joint_derivative(const pom_dyn_model *m, pom_dyn_data *d, const dyn_joint *jt,
                             const double *y, joint_deriv *jd) {
  const pom_dyn_params *par = &m->par;
  const double kl = par->joints.stiffness, cl = par->joints.damping;
  const double ka = par->joints.angular_stiffness, ca = par->joints.angular_damping;
  side_eval s0, s1;
  double Dd[3][JC] = {{0}}, Ddd[3][JC] = {{0}}; /* d = p1 - p0 and its rate */
  memset(jd, 0, sizeof *jd);
  side_setup(d, jt, 0, &s0, Dd, Ddd, -1.0);
  side_setup(d, jt, 1, &s1, Dd, Ddd, 1.0);
  double dd[3], ddot[3];
  pom_v3_sub(dd, s1.p, s0.p);
  pom_v3_sub(ddot, s1.v, s0.v);

  /* linear part: the force F1 on side 1 at p1, its reaction on side 0 at
   * p0 (fixed directions, rods) or at p1 (directions turning with side 0) */
  double F1[3] = {0.0, 0.0, 0.0};
  int react_at_p1 = 0;
  double row[JC], row2[JC];
  if (jt->distance) {
    double len = pom_v3_norm(dd);
    if (len > 0) {
      double nv[3], Pn[9], PnDd[3][JC] = {{0}};
      pom_v3_scale(nv, 1.0 / len, dd);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          Pn[3 * r + c] = ((r == c ? 1.0 : 0.0) - nv[r] * nv[c]) / len;
      add_mul(PnDd, 1.0, Pn, Dd);
      double f = kl * (len - jt->length) + cl * pom_v3_dot(nv, ddot);
      /* df = kl n.dd + cl (d_dot . dn + n . dd_dot), dn = Pn dd */
      row_of(row, nv, Dd);
      row_of(row2, ddot, PnDd);
      double row3[JC];
      row_of(row3, nv, Ddd);
      for (int c = 0; c < JC; ++c)
        row[c] = kl * row[c] + cl * (row2[c] + row3[c]);
      add_outer(jd->F1, -1.0, nv, row);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < JC; ++c)
          jd->F1[r][c] -= f * PnDd[r][c];
      pom_v3_scale(F1, -f, nv);
    }
  } else if (!jt->lin_rotates) {
    for (int k = 0; k < jt->n_lin; ++k) {
      const double *ek = jt->lin_dir[k];
      double f = kl * pom_v3_dot(ek, dd) + cl * pom_v3_dot(ek, ddot);
      row_of(row, ek, Dd);
      row_of(row2, ek, Ddd);
      for (int c = 0; c < JC; ++c)
        row[c] = kl * row[c] + cl * row2[c];
      add_outer(jd->F1, -1.0, ek, row);
      pom_v3_axpy(F1, F1, -f, ek);
    }
  } else {
    /* s_rel = d_dot - w0 x d; ds_rel = dd_dot + [d]x dw0 - [w0]x dd */
    react_at_p1 = 1;
    double srel[3], w0xd[3], Ds[3][JC], S[9];
    pom_v3_cross(w0xd, s0.w, dd);
    pom_v3_sub(srel, ddot, w0xd);
    memcpy(Ds, Ddd, sizeof Ds);
    pom_m3_skew(S, s0.w);
    add_mul(Ds, -1.0, S, Dd);
    if (jt->slot[0] >= 0) {
      pom_m3_skew(S, dd);
      add_block(Ds, XI_W, 1.0, S);
    }
    for (int k = 0; k < jt->n_lin; ++k) {
      double mk[3];
      pom_m3_apply(mk, s0.R, jt->lin_dir[k]);
      double f = kl * pom_v3_dot(mk, dd) + cl * pom_v3_dot(mk, srel);
      rotating_coord(row, row2, mk, dd, srel, Dd, Ds);
      for (int c = 0; c < JC; ++c)
        row[c] = kl * row[c] + cl * row2[c];
      add_outer(jd->F1, -1.0, mk, row);
      pom_v3_axpy(F1, F1, -f, mk);
    }
    int a = jt->actuator;
    if (a >= 0 && jt->type != POM_JOINT_REVOLUTE) {
      double n[3];
      pom_m3_apply(n, s0.R, jt->axis);
      double q = pom_v3_dot(n, dd), qd = pom_v3_dot(n, srel);
      actuator_partials(m, d, a, q, qd, y, &jd->ap);
      double dq[JC], dqd[JC];
      rotating_coord(dq, dqd, n, dd, srel, Dd, Ds);
      for (int c = 0; c < JC; ++c) {
        row[c] = jd->ap.f_q * dq[c] + jd->ap.f_qd * dqd[c];
        jd->lam[c] = jd->ap.l_q * dq[c] + jd->ap.l_qd * dqd[c];
        jd->zr[c] = jd->ap.z_q * dq[c] + jd->ap.z_qd * dqd[c];
      }
      add_outer(jd->F1, 1.0, n, row);
      double fa = pom_dyn_actuator_law(m, d, a, q, qd, y, NULL);
      pom_v3_axpy(F1, F1, fa, n);
      for (int r = 0; r < 3; ++r) {
        jd->Fa1[r][0] = n[r] * jd->ap.f_lam;
        jd->Fa1[r][1] = n[r] * jd->ap.f_z;
      }
    }
    /* dm = dtheta0 x m for every direction: -[F1]x dtheta0 */
    if (jt->slot[0] >= 0) {
      pom_m3_skew(S, F1);
      add_block(jd->F1, XI_TH, -1.0, S);
    }
  }
  /* torques of the linear part: T1 = r1 x F1, T0 = -(p_react - x0) x F1 */
  {
    double SF[9], Se[9], e0[3];
    pom_m3_skew(SF, F1);
    if (jt->slot[1] >= 0) {
      /* dT1 = [F1]x [r1]x dtheta1 + [r1]x dF1 */
      double S2[9];
      skew2(S2, F1, s1.r);
      add_block(jd->T1, XI_N + XI_TH, 1.0, S2);
      pom_m3_skew(Se, s1.r);
      add_mul(jd->T1, 1.0, Se, jd->F1);
    }
    if (jt->slot[0] >= 0) {
      /* dT0 = [F1]x d(p_react - x0) - [e0]x dF1 */
      double De[3][JC] = {{0}};
      if (react_at_p1) {
        pom_v3_add(e0, s0.r, dd);
        double Sr1[9];
        if (jt->slot[1] >= 0) {
          add_identity(De, XI_N + XI_X, 1.0);
          pom_m3_skew(Sr1, s1.r);
          add_block(De, XI_N + XI_TH, -1.0, Sr1);
        }
        add_identity(De, XI_X, -1.0);
      } else {
        pom_v3_copy(e0, s0.r);
        double Sr0[9];
        pom_m3_skew(Sr0, s0.r);
        add_block(De, XI_TH, -1.0, Sr0);
      }
      add_mul(jd->T0, 1.0, SF, De);
      pom_m3_skew(Se, e0);
      add_mul(jd->T0, -1.0, Se, jd->F1);
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 2; ++k)
          jd->Ta0[r][k] -= Se[3 * r] * jd->Fa1[0][k] + Se[3 * r + 1] * jd->Fa1[1][k] +
                           Se[3 * r + 2] * jd->Fa1[2][k];
    }
    if (jt->slot[1] >= 0) {
      pom_m3_skew(Se, s1.r);
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 2; ++k)
          jd->Ta1[r][k] += Se[3 * r] * jd->Fa1[0][k] + Se[3 * r + 1] * jd->Fa1[1][k] +
                           Se[3 * r + 2] * jd->Fa1[2][k];
    }
  }

  /* pure torques: angular pseudo-constraints and a rotary actuator, +Tp on
   * side 1 and -Tp on side 0 */
  double DTp[3][JC] = {{0}}, DTpa[3][2] = {{0}};
  double dw01[3];
  pom_v3_sub(dw01, s0.w, s1.w);
  for (int k = 0; k < jt->n_ang; ++k) {
    double ea[3], hb[3], n[3], A[9], B[9], Dn[3][JC] = {{0}};
    pom_m3_apply(ea, s0.R, jt->ang_e[k]);
    pom_m3_apply(hb, s1.R, jt->ang_h[k]);
    pom_v3_cross(n, ea, hb);
    double f = ka * pom_v3_dot(ea, hb) + ca * pom_v3_dot(dw01, n);
    /* dn = [hb]x [ea]x dtheta0 - [ea]x [hb]x dtheta1; dg = n.(dtheta0 - dtheta1) */
    skew2(A, hb, ea);
    skew2(B, ea, hb);
    if (jt->slot[0] >= 0) add_block(Dn, XI_TH, 1.0, A);
    if (jt->slot[1] >= 0) add_block(Dn, XI_N + XI_TH, -1.0, B);
    row_of(row, dw01, Dn); /* (w0 - w1) . dn */
    for (int c = 0; c < JC; ++c)
      row[c] *= ca;
    if (jt->slot[0] >= 0) {
      add_row3(row, XI_TH, ka, n);
      add_row3(row, XI_W, ca, n);
    }
    if (jt->slot[1] >= 0) {
      add_row3(row, XI_N + XI_TH, -ka, n);
      add_row3(row, XI_N + XI_W, -ca, n);
    }
    add_outer(DTp, 1.0, n, row);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < JC; ++c)
        DTp[r][c] += f * Dn[r][c];
  }
  int a = jt->actuator;
  if (a >= 0 && jt->type == POM_JOINT_REVOLUTE) {
    double n[3], r0[3], r1[3], c01[3], w10[3], nxw[3];
    pom_m3_apply(n, s0.R, jt->axis);
    pom_m3_apply(r0, s0.R, jt->ref);
    pom_m3_apply(r1, s1.R, jt->ref);
    pom_v3_cross(c01, r0, r1);
    double X = pom_v3_dot(r0, r1), Y = pom_v3_dot(n, c01);
    double q = atan2(Y, X);
    pom_v3_sub(w10, s1.w, s0.w);
    double qd = pom_v3_dot(w10, n);
    /* dq = gq . (dtheta1 - dtheta0), gq = [X (X n - (n.r1) r0) + Y r0 x r1] / (X^2 + Y^2) */
    double gq[3], nr1 = pom_v3_dot(n, r1), den = X * X + Y * Y;
    for (int k = 0; k < 3; ++k)
      gq[k] = (X * (X * n[k] - nr1 * r0[k]) + Y * c01[k]) / den;
    double dq[JC] = {0}, dqd[JC] = {0};
    pom_v3_cross(nxw, n, w10);
    if (jt->slot[0] >= 0) {
      add_row3(dq, XI_TH, -1.0, gq);
      add_row3(dqd, XI_W, -1.0, n);
      add_row3(dqd, XI_TH, 1.0, nxw); /* (w1 - w0) . (dtheta0 x n) */
    }
    if (jt->slot[1] >= 0) {
      add_row3(dq, XI_N + XI_TH, 1.0, gq);
      add_row3(dqd, XI_N + XI_W, 1.0, n);
    }
    actuator_partials(m, d, a, q, qd, y, &jd->ap);
    double tau = pom_dyn_actuator_law(m, d, a, q, qd, y, NULL);
    for (int c = 0; c < JC; ++c) {
      row[c] = jd->ap.f_q * dq[c] + jd->ap.f_qd * dqd[c];
      jd->lam[c] = jd->ap.l_q * dq[c] + jd->ap.l_qd * dqd[c];
      jd->zr[c] = jd->ap.z_q * dq[c] + jd->ap.z_qd * dqd[c];
    }
    add_outer(DTp, 1.0, n, row);
    if (jt->slot[0] >= 0) {
      double Sn[9]; /* tau dn = -tau [n]x dtheta0 */
      pom_m3_skew(Sn, n);
      add_block(DTp, XI_TH, -tau, Sn);
    }
    for (int r = 0; r < 3; ++r) {
      DTpa[r][0] = n[r] * jd->ap.f_lam;
      DTpa[r][1] = n[r] * jd->ap.f_z;
    }
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < JC; ++c) {
      jd->T1[r][c] += DTp[r][c];
      jd->T0[r][c] -= DTp[r][c];
    }
    for (int k = 0; k < 2; ++k) {
      jd->Ta1[r][k] += DTpa[r][k];
      jd->Ta0[r][k] -= DTpa[r][k];
    }
  }
}

/* ---- body columns and rows ------------------------------------------------ */
/* dtheta = G d(orientation): Euler ZYX, the fixed-frame axes of the three
 * angles; quaternion (R of q/|q|), 2/|q|^2 [-v | w I + [v]x]. */
static void orientation_G(const pom_dyn_model *m, const double *yb, const dyn_body_eval *e,
                          double G[3][4]) {
  memset(G, 0, 12 * sizeof(double));
  if (m->par.scene.orientation == POM_ORIENT_QUATERNION) {
    const double *q = yb + DYN_BODY_ORI;
    double s = 2.0 / (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int r = 0; r < 3; ++r) {
      G[r][0] = -s * q[1 + r];
      G[r][1 + r] = s * q[0];
    }
    G[0][2] = -s * q[3], G[0][3] = s * q[2];
    G[1][1] = s * q[3], G[1][3] = -s * q[1];
    G[2][1] = -s * q[2], G[2][2] = s * q[1];
  } else {
    double cps = e->trig[0], sps = e->trig[1], cth = e->trig[2], sth = e->trig[3];
    G[2][0] = 1.0;
    G[0][1] = -sps, G[1][1] = cps;
    G[0][2] = cps * cth, G[1][2] = sps * cth, G[2][2] = -sth;
  }
}

/* A row over the xi of body b mapped to the body's state columns
 * (out[body_states]): dx = du, dv = dp / m, dw = Rp diag(1/I') dh' and
 * dtheta = G de with dw = -[w]x dtheta, so the orientation columns see
 * (xi_theta + w x xi_w) . G. */
static void xi_to_states(double *out, const double xi[XI_N], const pom_dyn_model *m, int b,
                         const dyn_body_eval *e, double G[3][4]) {
  const dyn_body *bd = &m->body[b];
  for (int k = 0; k < 3; ++k) {
    out[DYN_BODY_U + k] = xi[XI_X + k];
    out[DYN_BODY_P + k] = xi[XI_V + k] / bd->mass;
    out[DYN_BODY_H + k] =
        (xi[XI_W] * e->Rp[k] + xi[XI_W + 1] * e->Rp[3 + k] + xi[XI_W + 2] * e->Rp[6 + k]) /
        bd->principal[k];
  }
  double t[3];
  pom_v3_cross(t, e->w, xi + XI_W);
  pom_v3_add(t, t, xi + XI_TH);
  for (int k = 0; k < m->body_states - DYN_BODY_ORI; ++k)
    out[DYN_BODY_ORI + k] = t[0] * G[0][k] + t[1] * G[1][k] + t[2] * G[2][k];
}

/* The rows of body bi (pinned: no u, p rows) against the states of body bj
 * from the force/torque block D = d(F, T of bi) / d(xi of bj): p_dot = F,
 * h'_dot = Rp^T T + ... (the body's own terms are added by body_own). */
static void pair_rows(double *blk, double D[6][XI_N], const pom_dyn_model *m, const pom_dyn_data *d,
                      pjac_data *pd, int bi, int bj) {
  const int bs = m->body_states;
  const dyn_body_eval *ei = &d->be[bi];
  double T[3][13];
  if (!m->body[bi].pinned)
    for (int r = 0; r < 3; ++r)
      xi_to_states(blk + (DYN_BODY_P + r) * bs, D[r], m, bj, &d->be[bj], pd->G[bj]);
  for (int r = 0; r < 3; ++r)
    xi_to_states(T[r], D[3 + r], m, bj, &d->be[bj], pd->G[bj]);
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < bs; ++c)
      blk[(DYN_BODY_H + k) * bs + c] +=
          ei->Rp[k] * T[0][c] + ei->Rp[3 + k] * T[1][c] + ei->Rp[6 + k] * T[2][c];
}

/* The body's own terms: u_dot = p / m; h'_dot = Rp^T T - w' x h' (the
 * turning of Rp and the gyroscopic term); the orientation rates. */
static void body_own(double *blk, const pom_dyn_model *m, const pom_dyn_data *d, pjac_data *pd,
                     int b, const double *y) {
  const int bs = m->body_states;
  const dyn_body *bd = &m->body[b];
  const dyn_body_eval *e = &d->be[b];
  const double *yb = y + bd->offset;
  const double *h = yb + DYN_BODY_H;
  double(*G)[4] = pd->G[b];
  const int n_ori = bs - DYN_BODY_ORI;
  if (!bd->pinned)
    for (int k = 0; k < 3; ++k)
      blk[(DYN_BODY_U + k) * bs + DYN_BODY_P + k] += 1.0 / bd->mass;
  /* d(Rp^T T) / dtheta = Rp^T [T]x (T held) */
  double ST[9], RtS[9];
  pom_m3_skew(ST, e->T);
  pom_m3_tmul(RtS, e->Rp, ST);
  for (int k = 0; k < 3; ++k) {
    for (int c = 0; c < n_ori; ++c)
      blk[(DYN_BODY_H + k) * bs + DYN_BODY_ORI + c] +=
          RtS[3 * k] * G[0][c] + RtS[3 * k + 1] * G[1][c] + RtS[3 * k + 2] * G[2][c];
    /* -d(w' x h')/dh' = -[w']x + [h']x diag(1/I') */
    double Sw[9], Sh[9];
    pom_m3_skew(Sw, e->wp);
    pom_m3_skew(Sh, h);
    for (int c = 0; c < 3; ++c)
      blk[(DYN_BODY_H + k) * bs + DYN_BODY_H + c] +=
          -Sw[3 * k + c] + Sh[3 * k + c] / bd->principal[c];
  }
  /* orientation rows: rate(e, w) with dw = -[w]x G de and Rp diag(1/I') dh' */
  double Rh[9], SwG[3][4] = {{0}}; /* dw/dh' and dw/de */
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      Rh[3 * r + c] = e->Rp[3 * r + c] / bd->principal[c];
  for (int c = 0; c < n_ori; ++c) {
    double g[3] = {G[0][c], G[1][c], G[2][c]}, wg[3];
    pom_v3_cross(wg, g, e->w); /* -w x g */
    for (int r = 0; r < 3; ++r)
      SwG[r][c] = wg[r];
  }
  if (m->par.scene.orientation == POM_ORIENT_QUATERNION) {
    /* q_dot = 1/2 (0, w) q: d/dq = 1/2 L(w) + 1/2 Q dw/dq, Q = d/dw */
    const double *q = yb + DYN_BODY_ORI, *w = e->w;
    double Lw[4][4] = {{0, -w[0], -w[1], -w[2]},
                       {w[0], 0, -w[2], w[1]},
                       {w[1], w[2], 0, -w[0]},
                       {w[2], -w[1], w[0], 0}};
    double Q[4][3] = {
        {-q[1], -q[2], -q[3]}, {q[0], q[3], -q[2]}, {-q[3], q[0], q[1]}, {q[2], -q[1], q[0]}};
    for (int r = 0; r < 4; ++r) {
      double *row = blk + (DYN_BODY_ORI + r) * bs;
      for (int c = 0; c < 4; ++c)
        row[DYN_BODY_ORI + c] +=
            0.5 * (Lw[r][c] + Q[r][0] * SwG[0][c] + Q[r][1] * SwG[1][c] + Q[r][2] * SwG[2][c]);
      for (int c = 0; c < 3; ++c)
        row[DYN_BODY_H + c] += 0.5 * (Q[r][0] * Rh[c] + Q[r][1] * Rh[3 + c] + Q[r][2] * Rh[6 + c]);
    }
    return;
  }
  double cps = e->trig[0], sps = e->trig[1], cth = e->trig[2], sth = e->trig[3];
  if (fabs(cth) < m->par.scene.euler_cos_min) return; /* the pass zeroes these rates */
  const double *w = e->w;
  double tth = sth / cth;
  double E[3][3] = {{cps * tth, sps * tth, 1.0}, {-sps, cps, 0.0}, {cps / cth, sps / cth, 0.0}};
  /* the angles' explicit terms: d/dpsi and d/dtheta of E(e) w */
  double wa = cps * w[0] + sps * w[1], wb = -sps * w[0] + cps * w[1];
  double Ex[3][3] = {
      {wb * tth, wa / (cth * cth), 0.0}, {-wa, 0.0, 0.0}, {wb / cth, wa * sth / (cth * cth), 0.0}};
  for (int r = 0; r < 3; ++r) {
    double *row = blk + (DYN_BODY_ORI + r) * bs;
    for (int c = 0; c < 3; ++c) {
      row[DYN_BODY_ORI + c] +=
          Ex[r][c] + E[r][0] * SwG[0][c] + E[r][1] * SwG[1][c] + E[r][2] * SwG[2][c];
      row[DYN_BODY_H + c] += E[r][0] * Rh[c] + E[r][1] * Rh[3 + c] + E[r][2] * Rh[6 + c];
    }
  }
}

/* ---- the Jacobian ---------------------------------------------------------- */
int pom_dyn_parasitic_jacobian(const pom_dyn_model *m, pom_dyn_data *d, const double *y,
                               double *jac) {
  const pjac_layout *L = m->form_model;
  pjac_data *pd = d->form_data;
  const int bs = m->body_states;
  ++d->jac_count;
  pom_dyn_eval(m, d, y, NULL); /* body flows and effort sums at y */
  memset(pd->vals, 0, (size_t)L->n_vals * sizeof *pd->vals);
  memset(pd->dw, 0, (size_t)L->n_pairs * sizeof *pd->dw);
  for (int b = 0; b < m->n_bodies; ++b) {
    orientation_G(m, y + m->body[b].offset, &d->be[b], pd->G[b]);
    if (m->body[b].pinned) {
      /* weight at R a: dT = [m g]x [R a]x dtheta */
      double mg[3], ra[3], S[9];
      pom_v3_scale(mg, m->body[b].mass, m->gravity);
      pom_m3_apply(ra, d->be[b].R, m->body[b].grav_arm);
      skew2(S, mg, ra);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          pd->dw[L->pair[b][b]][3 + r][XI_TH + c] += S[3 * r + c];
    }
  }
  joint_deriv jd;
  for (int j = 0; j < m->n_joints; ++j) {
    const dyn_joint *jt = &m->joint[j];
    joint_derivative(m, d, jt, y, &jd);
    for (int s = 0; s < 2; ++s) {
      int bi = jt->slot[s];
      if (bi < 0) continue;
      const double sg = s == 1 ? 1.0 : -1.0;
      double(*Ts)[JC] = s == 1 ? jd.T1 : jd.T0;
      for (int t = 0; t < 2; ++t) {
        int bj = jt->slot[t];
        if (bj < 0) continue;
        double(*D)[XI_N] = pd->dw[L->pair[bi][bj]];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < XI_N; ++c) {
            D[r][c] += sg * jd.F1[r][t * XI_N + c];
            D[3 + r][c] += Ts[r][t * XI_N + c];
          }
      }
    }
    int a = jt->actuator;
    if (a < 0) continue;
    for (int s = 0; s < 2; ++s) {
      int b = jt->slot[s];
      if (b < 0) continue;
      const double sg = s == 1 ? 1.0 : -1.0;
      double(*Ta)[2] = s == 1 ? jd.Ta1 : jd.Ta0;
      double *col = pd->vals + L->act_col + (long)(a * 2 + s) * bs * 2;
      const double *Rp = d->be[b].Rp;
      for (int k = 0; k < 2; ++k) {
        for (int r = 0; r < 3; ++r) {
          if (!m->body[b].pinned) col[(DYN_BODY_P + r) * 2 + k] = sg * jd.Fa1[r][k];
          col[(DYN_BODY_H + r) * 2 + k] =
              Rp[r] * Ta[0][k] + Rp[3 + r] * Ta[1][k] + Rp[6 + r] * Ta[2][k];
        }
      }
      double *row = pd->vals + L->act_row + (long)(a * 2 + s) * 2 * bs;
      xi_to_states(row, jd.lam + s * XI_N, m, b, &d->be[b], pd->G[b]);
      xi_to_states(row + bs, jd.zr + s * XI_N, m, b, &d->be[b], pd->G[b]);
    }
    double *own = pd->vals + L->act_own + 4L * a;
    own[0] = jd.ap.l_lam; /* flux row: flux, controller-state columns */
    own[1] = jd.ap.l_z;
    own[3] = jd.ap.z_z; /* controller-state row: its own column (the law never reads i) */
  }
  for (int bi = 0; bi < m->n_bodies; ++bi)
    for (int bj = 0; bj < m->n_bodies; ++bj) {
      int p = L->pair[bi][bj];
      if (p < 0) continue;
      double *blk = pd->vals + (long)p * bs * bs;
      pair_rows(blk, pd->dw[p], m, d, pd, bi, bj);
      if (bi == bj) body_own(blk, m, d, pd, bi, y);
    }
  int bad = 0;
  for (long k = 0; k < m->nnz; ++k) {
    jac[k] = L->src[k] >= 0 ? pd->vals[L->src[k]] : 0.0;
    if (!isfinite(jac[k])) bad = 1;
  }
  return bad;
}

/* ---- layout and scratch ----------------------------------------------------- */
/* Which actuator state is i: 0 flux, 1 integral (actuator in *a), -1 none. */
static int actuator_state(const pom_dyn_model *m, int i, int *a) {
  for (int k = 0; k < m->n_actuators; ++k) {
    if (i == m->act[k].flux_state) return *a = k, 0;
    if (i == m->act[k].ctrl_state) return *a = k, 1;
  }
  return -1;
}

/* The side of actuator a's joint that is body b, -1 when neither. */
static int actuator_side(const pom_dyn_model *m, int a, int b) {
  const dyn_joint *jt = &m->joint[m->act[a].joint];
  return jt->slot[0] == b ? 0 : (jt->slot[1] == b ? 1 : -1);
}

/* Value index of entry (i, j), -1 when the analytic Jacobian has none. */
static long entry_source(const pom_dyn_model *m, const pjac_layout *L, int i, int j) {
  const int bs = m->body_states, nbs = m->n_bodies * bs;
  int ai = -1, aj = -1;
  int ki = i < nbs ? -1 : actuator_state(m, i, &ai);
  int kj = j < nbs ? -1 : actuator_state(m, j, &aj);
  if (i < nbs && j < nbs) {
    int p = L->pair[i / bs][j / bs];
    return p < 0 ? -1 : (long)p * bs * bs + (long)(i % bs) * bs + j % bs;
  }
  if (i < nbs && kj >= 0) {
    int s = actuator_side(m, aj, i / bs);
    return s < 0 ? -1 : L->act_col + ((long)(aj * 2 + s) * bs + i % bs) * 2 + kj;
  }
  if (ki >= 0 && j < nbs) {
    int s = actuator_side(m, ai, j / bs);
    return s < 0 ? -1 : L->act_row + ((long)(ai * 2 + s) * 2 + ki) * bs + j % bs;
  }
  if (ki >= 0 && kj >= 0 && ai == aj) return L->act_own + 4L * ai + 2 * ki + kj;
  return -1; /* accumulators, other actuators */
}

pom_status pom_dyn_parasitic_jac_layout(pom_dyn_model *m, pom_error *err) {
  pjac_layout *L = calloc(1, sizeof *L);
  if (!L) POM_FAIL(err, POM_ERR_NOMEM, "allocating the Jacobian layout");
  m->form_model = L;
  for (int bi = 0; bi < POM_MECH_MAX_BODIES; ++bi)
    for (int bj = 0; bj < POM_MECH_MAX_BODIES; ++bj)
      L->pair[bi][bj] = -1;
  for (int b = 0; b < m->n_bodies; ++b)
    L->pair[b][b] = L->n_pairs++;
  for (int j = 0; j < m->n_joints; ++j) {
    int s0 = m->joint[j].slot[0], s1 = m->joint[j].slot[1];
    if (s0 < 0 || s1 < 0 || L->pair[s0][s1] >= 0) continue;
    L->pair[s0][s1] = L->n_pairs++;
    L->pair[s1][s0] = L->n_pairs++;
  }
  const long bs = m->body_states;
  L->act_col = (long)L->n_pairs * bs * bs;
  L->act_row = L->act_col + (long)m->n_actuators * 2 * bs * 2;
  L->act_own = L->act_row + (long)m->n_actuators * 2 * 2 * bs;
  L->n_vals = L->act_own + 4L * m->n_actuators;
  L->src = calloc((size_t)m->nnz, sizeof *L->src);
  if (!L->src) POM_FAIL(err, POM_ERR_NOMEM, "allocating the Jacobian layout");
  for (int j = 0; j < m->n_states; ++j)
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k)
      L->src[k] = entry_source(m, L, m->rowind[k], j);
  return POM_OK;
}

void pom_dyn_parasitic_jac_layout_free(pom_dyn_model *m) {
  pjac_layout *L = m->form_model;
  if (!L) return;
  free(L->src);
  free(L);
  m->form_model = NULL;
}

pom_status pom_dyn_parasitic_jac_data(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err) {
  const pjac_layout *L = m->form_model;
  pjac_data *pd = calloc(1, sizeof *pd);
  if (!pd) POM_FAIL(err, POM_ERR_NOMEM, "allocating the Jacobian scratch");
  d->form_data = pd;
  pd->vals = calloc((size_t)L->n_vals, sizeof *pd->vals);
  pd->dw = calloc((size_t)L->n_pairs, sizeof *pd->dw);
  if (!pd->vals || !pd->dw) POM_FAIL(err, POM_ERR_NOMEM, "allocating the Jacobian scratch");
  return POM_OK;
}

void pom_dyn_parasitic_jac_data_free(pom_dyn_data *d) {
  pjac_data *pd = d->form_data;
  if (!pd) return;
  free(pd->vals);
  free(pd->dw);
  free(pd);
  d->form_data = NULL;
}
