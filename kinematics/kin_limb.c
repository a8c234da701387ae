/* kin_limb.c - the generic operations of an architecture given as a numeric
 * limb table (pom_limb.h): a closed-form IK kernel chosen from each limb's
 * joint sequence, the Jacobian row from the limb's actuation wrench, and
 * every body pose, twist map and bias (and their first derivatives) by
 * forward-mode automatic differentiation through the same kernel
 * (kin_jet.h). Derivations: docs/kinematics-tables.md. */
#include "pom_limb.h"

#include "kin_internal.h"
#include "kin_jet.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- kernels ---------------------------------------------------------------- */
pom_limb_kernel pom_limb_kernel_of(const int t[POM_LIMB_JOINTS], int actuated) {
  enum { R = POM_LIMB_JOINT_R, P = POM_LIMB_JOINT_P, U = POM_LIMB_JOINT_U, S = POM_LIMB_JOINT_S };
  if (t[0] == R && t[1] == R && t[2] == R && actuated == 0) return POM_LIMB_KERNEL_RRR;
  if (t[0] == P && t[1] == S && t[2] == S && actuated == 0) return POM_LIMB_KERNEL_PSS;
  if (t[0] == R && t[1] == S && t[2] == S && actuated == 0) return POM_LIMB_KERNEL_RSS;
  if (t[0] == S && t[1] == P && t[2] == S && actuated == 1) return POM_LIMB_KERNEL_SPS;
  if (t[0] == U && t[1] == P && t[2] == S && actuated == 1) return POM_LIMB_KERNEL_UPS;
  if (t[0] == R && t[1] == U && t[2] == U && actuated == 0) return POM_LIMB_KERNEL_RUU;
  if (t[0] == U && t[1] == P && t[2] == U && actuated == 1) return POM_LIMB_KERNEL_UPU;
  return POM_LIMB_KERNEL_NONE;
}

const char *pom_limb_kernel_name(pom_limb_kernel k) {
  switch (k) {
  case POM_LIMB_KERNEL_RRR:
    return "R-R-R";
  case POM_LIMB_KERNEL_PSS:
    return "P-S-S";
  case POM_LIMB_KERNEL_RSS:
    return "R-S-S";
  case POM_LIMB_KERNEL_SPS:
    return "S-P-S";
  case POM_LIMB_KERNEL_UPS:
    return "U-P-S";
  case POM_LIMB_KERNEL_RUU:
    return "R-U-U";
  case POM_LIMB_KERNEL_UPU:
    return "U-P-U";
  default:
    return "none";
  }
}

/* ---- plain evaluation (the IK op and the limits) ------------------------------ */
/* A limb at one platform rotation: q, the Jacobian row, the joints' current
 * centres (carried by the body after the joint), first axes (carried by
 * the body before it) and a U's second axis (carried by the body after). */
typedef struct {
  double q, row[3];
  double act;    /* the actuator side B_ii of the row's wrench (section 3): R-R-R, R-U-U
                    (u x w) . v, P-S-S l . a, R-S-S l . (a x arm); unset otherwise */
  double cq, sq; /* R-R-R, R-S-S: cos q and sin q (the jets reuse them) */
  double p[POM_LIMB_JOINTS][3];
  double ax[POM_LIMB_JOINTS][3];
  double ax2[POM_LIMB_JOINTS][3];
} limb_state;

/* The platform-side axis of an R-R-R or R-U-U limb at home: the last R's
 * axis, or the platform U's second axis (through O). */
static const double *platform_axis(const pom_limb *L) {
  return L->kernel == POM_LIMB_KERNEL_RUU ? L->joint[2].axis2 : L->joint[2].axis;
}

/* The sign that makes the middle U axes of an R-U-U (d = sign unit(w x v))
 * or U-P-U (n = sign unit(p0 x p2)) limb their home direction: section 2.5. */
static double middle_sign(const pom_limb *L) {
  double c[3];
  if (L->kernel == POM_LIMB_KERNEL_RUU) {
    pom_v3_cross(c, L->joint[1].axis, L->joint[2].axis2);
    return pom_v3_dot(c, L->joint[1].axis2) < 0.0 ? -1.0 : 1.0;
  }
  pom_v3_cross(c, L->joint[0].point, L->joint[2].point);
  return pom_v3_dot(c, L->joint[0].axis2) < 0.0 ? -1.0 : 1.0;
}

/* The root of A cos t + B sin t + C = 0 on the branch: t = atan2(B, A) +
 * branch acos(-C / hypot(A, B)), in [-pi, pi] (docs/kinematics-tables.md 2.1). */
static int angle_root(double A, double B, double C, double branch, double *t) {
  double rho = hypot(A, B);
  if (!(rho > 0.0)) return 0;
  double c = -C / rho;
  if (!(c >= -1.0 && c <= 1.0)) return 0; /* also false for NaN */
  *t = remainder(atan2(B, A) + branch * acos(c), 2.0 * POM_PI);
  return 1;
}

/* R-R-R: w(theta) . v = cos alpha2 with w(theta) = Rot(u, theta) w0. */
static void rrr_coef(const pom_limb *L, const double v[3], double *A, double *B, double *C) {
  const double *u = L->joint[0].axis, *w0 = L->joint[1].axis;
  double uw = pom_v3_dot(u, w0), uv = pom_v3_dot(u, v), uxw[3];
  pom_v3_cross(uxw, u, w0);
  *A = pom_v3_dot(w0, v) - uw * uv;
  *B = pom_v3_dot(uxw, v);
  *C = uw * uv - L->cos_distal;
}

/* R-S-S crank: p1(theta) = p0 + r_par + cos r_perp + sin (a x r), r = p1h - p0h. */
typedef struct {
  double rpar[3], rperp[3], axr[3];
} rss_crank;

static void rss_crank_of(const pom_limb *L, rss_crank *k) {
  const double *a = L->joint[0].axis;
  double r[3];
  pom_v3_sub(r, L->joint[1].point, L->joint[0].point);
  pom_v3_scale(k->rpar, pom_v3_dot(a, r), a);
  pom_v3_sub(k->rperp, r, k->rpar);
  pom_v3_cross(k->axr, a, r);
}

/* |p2 - p1(theta)|^2 = L^2 as A cos + B sin + C = 0, d = p2 - p0h - r_par. */
static void rss_coef(const pom_limb *L, const rss_crank *k, const double p2[3], double *A,
                     double *B, double *C) {
  double d[3];
  pom_v3_sub(d, p2, L->joint[0].point);
  pom_v3_sub(d, d, k->rpar);
  *A = -2.0 * pom_v3_dot(d, k->rperp);
  *B = -2.0 * pom_v3_dot(d, k->axr);
  *C = pom_v3_dot(d, d) + pom_v3_dot(k->rperp, k->rperp) - L->length * L->length;
}

/* Limb at rotation R; need_row: fail (0) at a leg singularity too;
 * need_pose: also the joints' centres and axes (p, ax, ax2; an R-R-R limb
 * leaves them out otherwise, the IK and twist ops not reading them). */
static int limb_eval(const pom_limb *L, const double R[9], int need_row, int need_pose,
                     limb_state *s) {
  const pom_limb_joint *J = L->joint;
  if (need_pose) {
    memset(s->ax, 0, sizeof s->ax);
    memset(s->ax2, 0, sizeof s->ax2);
  }
  switch (L->kernel) {
  case POM_LIMB_KERNEL_RRR:
  case POM_LIMB_KERNEL_RUU: {
    const double *u = J[0].axis, *w0 = J[1].axis;
    double v[3], w[3], A, B, C, t, uxw[3], wxv[3], uxw0[3];
    pom_m3_apply(v, R, platform_axis(L));
    rrr_coef(L, v, &A, &B, &C);
    if (!angle_root(A, B, C, L->branch, &t)) return 0;
    double ct = cos(t), st = sin(t), uw = pom_v3_dot(u, w0);
    s->cq = ct;
    s->sq = st;
    pom_v3_cross(uxw0, u, w0);
    for (int k = 0; k < 3; ++k)
      w[k] = ct * w0[k] + st * uxw0[k] + (1.0 - ct) * uw * u[k];
    s->q = t;
    pom_v3_cross(uxw, u, w);
    double den = pom_v3_dot(uxw, v);
    s->act = den;
    if (den == 0.0) {
      if (need_row) return 0;
      pom_v3_set(s->row, 0.0, 0.0, 0.0);
    } else {
      pom_v3_cross(wxv, w, v);
      pom_v3_scale(s->row, 1.0 / den, wxv);
    }
    if (L->kernel == POM_LIMB_KERNEL_RRR && !need_pose) return 1;
    pom_v3_copy(s->ax[0], u);
    pom_v3_copy(s->ax[1], w);
    pom_v3_copy(s->ax[2], v);
    if (L->kernel == POM_LIMB_KERNEL_RUU) {
      /* the link's axis d = sign unit(w x v) (section 2.5); the centres on
       * the axes through O: the crank's on u, B on w, C on v */
      double d[3];
      pom_v3_cross(d, w, v);
      if (!(pom_v3_normalize(d, d) > 0.0)) return 0;
      pom_v3_scale(d, middle_sign(L), d);
      pom_v3_copy(s->ax[2], d);
      pom_v3_copy(s->ax2[1], d);
      pom_v3_copy(s->ax2[2], v);
      pom_v3_copy(s->p[0], J[0].point);
      pom_v3_scale(s->p[1], pom_v3_dot(J[1].point, w0), w);
      pom_m3_apply(s->p[2], R, J[2].point);
      return 1;
    }
    for (int j = 0; j < 3; ++j) /* centres on their axes through O */
      pom_v3_scale(s->p[j], pom_v3_dot(J[j].point, J[j].axis), s->ax[j]);
    return 1;
  }
  case POM_LIMB_KERNEL_PSS: {
    const double *u = J[0].axis, *Bm = J[1].point;
    double c[3], d[3], l[3], cl[3];
    pom_m3_apply(c, R, J[2].point);
    pom_v3_sub(d, c, Bm);
    double Lk = L->length, du = pom_v3_dot(d, u);
    double disc = du * du - pom_v3_dot(d, d) + Lk * Lk;
    if (!(disc >= 0.0)) return 0;
    double root = sqrt(disc), q = du - L->branch * root, lu = L->branch * root;
    s->q = q;
    s->act = lu;
    if (lu == 0.0) {
      if (need_row) return 0;
      pom_v3_set(s->row, 0.0, 0.0, 0.0);
    } else {
      pom_v3_axpy(l, d, -q, u);
      pom_v3_cross(cl, c, l);
      pom_v3_scale(s->row, 1.0 / lu, cl);
    }
    pom_v3_axpy(s->p[0], J[0].point, q, u);
    pom_v3_axpy(s->p[1], Bm, q, u);
    pom_v3_copy(s->p[2], c);
    pom_v3_copy(s->ax[0], u);
    return 1;
  }
  case POM_LIMB_KERNEL_RSS: {
    rss_crank k;
    double p2[3], A, B, C, t, l[3], arm[3], axarm[3], pl[3];
    rss_crank_of(L, &k);
    pom_m3_apply(p2, R, J[2].point);
    rss_coef(L, &k, p2, &A, &B, &C);
    if (!angle_root(A, B, C, L->branch, &t)) return 0;
    double ct = cos(t), st = sin(t);
    s->cq = ct;
    s->sq = st;
    for (int c = 0; c < 3; ++c) {
      arm[c] = k.rpar[c] + ct * k.rperp[c] + st * k.axr[c];
      s->p[1][c] = J[0].point[c] + arm[c];
    }
    s->q = t;
    pom_v3_sub(l, p2, s->p[1]);
    pom_v3_cross(axarm, J[0].axis, arm);
    double den = pom_v3_dot(l, axarm);
    s->act = den;
    if (den == 0.0) {
      if (need_row) return 0;
      pom_v3_set(s->row, 0.0, 0.0, 0.0);
    } else {
      pom_v3_cross(pl, p2, l);
      pom_v3_scale(s->row, 1.0 / den, pl);
    }
    pom_v3_copy(s->p[0], J[0].point);
    pom_v3_copy(s->p[2], p2);
    pom_v3_copy(s->ax[0], J[0].axis);
    return 1;
  }
  case POM_LIMB_KERNEL_SPS:
  case POM_LIMB_KERNEL_UPS:
  case POM_LIMB_KERNEL_UPU: {
    double b[3], v[3], sdir[3], h[3];
    pom_m3_apply(b, R, J[2].point);
    pom_v3_sub(v, b, J[0].point);
    double n = pom_v3_norm(v);
    if (!(n > 0.0 && n < INFINITY)) return 0;
    s->q = n - L->length;
    pom_v3_scale(sdir, 1.0 / n, v);
    pom_v3_cross(s->row, b, sdir);
    pom_v3_copy(s->p[0], J[0].point);
    pom_v3_sub(h, J[2].point, J[1].point);
    pom_v3_axpy(s->p[1], b, -pom_v3_dot(h, L->dir_home), sdir);
    pom_v3_copy(s->p[2], b);
    if (L->kernel != POM_LIMB_KERNEL_SPS) pom_v3_copy(s->ax[0], J[0].axis);
    pom_v3_copy(s->ax[1], sdir);
    if (L->kernel == POM_LIMB_KERNEL_UPU) {
      /* the middle axes n = sign unit(p0 x R p2) (section 2.5) */
      double nm[3];
      pom_v3_cross(nm, J[0].point, b);
      if (!(pom_v3_normalize(nm, nm) > 0.0)) return 0;
      pom_v3_scale(nm, middle_sign(L), nm);
      pom_v3_copy(s->ax2[0], nm);
      pom_v3_copy(s->ax[2], nm);
      pom_m3_apply(s->ax2[2], R, J[2].axis2);
    }
    return 1;
  }
  default:
    return 0;
  }
}

/* The transmission index of a limb evaluated with its row (section 3.2):
 * the actuator side over the norms that make it the cosine between the unit
 * actuation wrench and the actuated joint's unit twist. */
static double limb_transmission(const pom_limb *L, const limb_state *s) {
  switch (L->kernel) {
  case POM_LIMB_KERNEL_RRR:
  case POM_LIMB_KERNEL_RUU: {
    /* |(u x w) . v| / |w x v|, |w x v| = sin alpha2 (w, v unit, w . v = cos alpha2) */
    const double c = L->cos_distal;
    return fabs(s->act) / sqrt((1.0 - c) * (1.0 + c));
  }
  case POM_LIMB_KERNEL_PSS: /* |l . a| / |l|, |l| = L */
    return fabs(s->act) / L->length;
  case POM_LIMB_KERNEL_RSS: {
    /* |l . (a x arm)| / (|l| |a x arm|), |a x arm| = |r_perp| the crank radius */
    rss_crank k;
    rss_crank_of(L, &k);
    return fabs(s->act) / (L->length * pom_v3_norm(k.rperp));
  }
  default: /* S-P-S, U-P-S, U-P-U: the force along the limb drives the piston along it */
    return 1.0;
  }
}

int pom_limb_ik(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
                double *tr) {
  const pom_limb_table *tb = POM_LIMB_CTABLE(arch);
  limb_state s;
  if (!limb_eval(&tb->limb[i], R, row != NULL, 0, &s)) return 0;
  *q = s.q;
  if (row) {
    pom_v3_copy(row, s.row);
    if (tr) *tr = limb_transmission(&tb->limb[i], &s);
  }
  return 1;
}

/* ---- jets: the limb along a platform motion (docs/kinematics-tables.md 5) ----- */
/* The platform motion a jet algebra sees: R(t, ...) = the rotation R moved
 * along the algebra's directions (below); JP(platform) gives R(t, ...) x0
 * for a platform-fixed x0. With x = R x0 and a x b the cross product:
 *   V: R(t, s) = exp(t [w]) exp(sum s_k [e_k]) R:
 *      x, t: w x x, t^2: w x (w x x) / 2, s_k: e_k x x.
 *   D: R = exp(t [w + sum sigma_k e_k] + sum u_j [e_j]) exp(sum s_k [e_k]) R:
 *      the above, t s_k: w x (e_k x x), t^2 s_k: w x (w x (e_k x x)) / 2,
 *      sigma_k: 0, t sigma_k: e_k x x, t^2 sigma_k: (w x (e_k x x) +
 *      e_k x (w x x)) / 2, u_j: e_j x x, u_j s_k: e_j x (e_k x x). */
typedef struct {
  const double *R;
  double w[3];
} vj_motion;
typedef vj_motion dj_motion;

/* e_k x x */
static void ecross(double out[3], int k, const double x[3]) {
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  out[k] = 0.0;
  out[a] = -x[b];
  out[b] = x[a];
}

static void vj_platform(pom_vjet out[3], const vj_motion *pf, const double x0[3]) {
  double x[3], wx[3], wwx[3], ex[3][3];
  pom_m3_apply(x, pf->R, x0);
  pom_v3_cross(wx, pf->w, x);
  pom_v3_cross(wwx, pf->w, wx);
  for (int k = 0; k < 3; ++k)
    ecross(ex[k], k, x);
  for (int r = 0; r < 3; ++r) {
    pom_vjet *o = &out[r];
    o->c[VJ_1] = x[r];
    o->c[VJ_T] = wx[r];
    o->c[VJ_T2] = 0.5 * wwx[r];
    for (int k = 0; k < 3; ++k)
      o->c[VJ_S + k] = ex[k][r];
  }
}

static void dj_platform(pom_djet out[3], const dj_motion *pf, const double x0[3]) {
  double x[3], wx[3], wwx[3], ex[3][3], wex[3][3], wwex[3][3], exw[3][3], eex[3][3][3];
  pom_m3_apply(x, pf->R, x0);
  pom_v3_cross(wx, pf->w, x);
  pom_v3_cross(wwx, pf->w, wx);
  for (int k = 0; k < 3; ++k) {
    ecross(ex[k], k, x);
    pom_v3_cross(wex[k], pf->w, ex[k]);
    pom_v3_cross(wwex[k], pf->w, wex[k]);
    ecross(exw[k], k, wx);
  }
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k)
      ecross(eex[j][k], j, ex[k]);
  for (int r = 0; r < 3; ++r) {
    pom_djet *o = &out[r];
    o->c[DJ_1] = x[r];
    o->c[DJ_T] = wx[r];
    o->c[DJ_T2] = 0.5 * wwx[r];
    for (int k = 0; k < 3; ++k) {
      o->c[DJ_D(k)] = ex[k][r];
      o->c[DJ_TD(k)] = wex[k][r];
      o->c[DJ_T2D(k)] = 0.5 * wwex[k][r];
      o->c[DJ_D(3 + k)] = 0.0;
      o->c[DJ_TD(3 + k)] = ex[k][r];
      o->c[DJ_T2D(3 + k)] = 0.5 * (wex[k][r] + exw[k][r]);
      o->c[DJ_U + k] = ex[k][r];
      for (int j = 0; j < 3; ++j)
        o->c[DJ_US + 3 * j + k] = eex[j][k][r];
    }
  }
}

/* the kernels over each algebra */
#define JT     pom_vjet
#define JP(n_) vj_##n_
#define JORDER 2 /* t^2 */
#include "kin_limb_jet.inc"
#undef JT
#undef JP
#undef JORDER

#define JT     pom_djet
#define JP(n_) dj_##n_
#define JORDER 3 /* t^2 d_m */
#include "kin_limb_jet.inc"
#undef JT
#undef JP
#undef JORDER

/* A body's angular velocity along a first-order direction whose coefficient
 * index is d, at the constant terms: vee(R_d R^T), or dir x dir_d for an
 * idle spin. R1, Rd: the rotation's constant and d coefficients (row-major);
 * dir0, dird likewise. */
static void omega_dir(double w[3], int spin_free, const double R1[9], const double Rd[9],
                      const double dir0[3], const double dird[3]) {
  if (spin_free) {
    pom_v3_cross(w, dir0, dird);
    return;
  }
  /* X = Rd R1^T; w = (X32 - X23, X13 - X31, X21 - X12) / 2 */
  static const int rc[3][2] = {{2, 1}, {0, 2}, {1, 0}};
  for (int a = 0; a < 3; ++a) {
    const int r = rc[a][0], c = rc[a][1];
    double x = 0.0;
    for (int k = 0; k < 3; ++k)
      x += Rd[3 * r + k] * R1[3 * c + k] - Rd[3 * c + k] * R1[3 * r + k];
    w[a] = 0.5 * x;
  }
}

/* A turning body's angular velocity along a first-order direction d,
 * vee(M_d M^T) (skew: M_d = [w_d] M): m0 x m0_d + (m2 . m1_d) m0 with m_k
 * the columns of M (the constant term) and m_k_d of M_d. */
static inline void omega_col(double w[3], const double M[9], const double Md[9]) {
  double m0[3] = {M[0], M[3], M[6]}, d0[3] = {Md[0], Md[3], Md[6]};
  const double along = M[2] * Md[1] + M[5] * Md[4] + M[8] * Md[7];
  pom_v3_cross(w, m0, d0);
  pom_v3_axpy(w, w, along, m0);
}

/* A framed body's rotation G M H^T (G NULL: the identity), M its jets'
 * constant term (kin_limb_jet.inc). */
static inline void framed_rotation(double R[9], const double M[9], const double *G,
                                   const double H[9]) {
  double MH[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      MH[3 * r + c] =
          M[3 * r] * H[3 * c] + M[3 * r + 1] * H[3 * c + 1] + M[3 * r + 2] * H[3 * c + 2];
  if (!G) {
    memcpy(R, MH, sizeof MH);
    return;
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      R[3 * r + c] = G[3 * r] * MH[c] + G[3 * r + 1] * MH[3 + c] + G[3 * r + 2] * MH[6 + c];
}

/* v = G v (an angular velocity of a framed body with has_G). */
static inline void turn_by(double v[3], const double G[9]) {
  const double x[3] = {v[0], v[1], v[2]};
  for (int r = 0; r < 3; ++r)
    v[r] = G[3 * r] * x[0] + G[3 * r + 1] * x[1] + G[3 * r + 2] * x[2];
}

/* Coefficient k of a body's jets: its rotation (9, spin fixed) or its
 * direction (3, idle spin); the other is left alone. */
#define BODY_COEFS(lj_, b_, k_, R_, d_)                                                            \
  do {                                                                                             \
    if ((lj_)->spin_free[b_])                                                                      \
      for (int e_ = 0; e_ < 3; ++e_)                                                               \
        (d_)[e_] = (lj_)->dir[b_][e_].c[k_];                                                       \
    else                                                                                           \
      for (int e_ = 0; e_ < 9; ++e_)                                                               \
        (R_)[e_] = (lj_)->Rb[b_][e_].c[k_];                                                        \
  } while (0)

/* The fields of limb_twist for limb i from its jets: q, J and the poses
 * from the plain evaluation st and the constant terms, A e_k and B e_k from
 * the s_k terms (coefficient sk + ss k), q_bias and a_bias = 2 c_t2, alpha_bias
 * = the t term of the angular-velocity jet wt[b] (computed by the caller in
 * its algebra). c(x, k): coefficient k of jet x. Written as a macro over
 * the two algebras (their jets differ in type only). */
#define TWIST_FILL(lj_, wt_, sk_, ss_, t_, t2_)                                                    \
  do {                                                                                             \
    out->q[i] = st.q;                                                                              \
    pom_v3_copy(out->J + 3 * i, st.row);                                                           \
    out->q_bias[i] = 2.0 * (lj_).q.c[t2_];                                                         \
    for (int b = 0; b < POM_LIMB_BODIES; ++b) {                                                    \
      pom_kin_body_twist *bt = &out->body[2 + 2 * i + b];                                          \
      double R1[9] = {0}, d1[3] = {0}, Rd[9] = {0}, dd[3] = {0};                                   \
      /* every other field is written below */                                                     \
      bt->spin_free = 0;                                                                           \
      pom_v3_set(bt->spin_axis, 0.0, 0.0, 0.0);                                                    \
      pom_v3_copy(bt->ref_home, L->joint[L->ref_joint[b]].point);                                  \
      for (int r = 0; r < 3; ++r)                                                                  \
        bt->ref[r] = (lj_).ref[b][r].c[0];                                                         \
      if ((lj_).axis[b])                                                                           \
        pom_m3_copy(R1, (lj_).Rfix[b]);                                                            \
      else                                                                                         \
        BODY_COEFS(&(lj_), b, 0, R1, d1);                                                          \
      for (int k = 0; k < 3; ++k) {                                                                \
        double col[3];                                                                             \
        if (b > 0 && (lj_).same_turn[b]) { /* turns with body b - 1 */                             \
          for (int r = 0; r < 3; ++r)                                                              \
            col[r] = bt[-1].B[3 * r + k];                                                          \
        } else if ((lj_).axis[b]) {                                                                \
          pom_v3_scale(col, (lj_).q.c[(sk_) + (ss_)*k], (lj_).axis[b]);                            \
        } else {                                                                                   \
          BODY_COEFS(&(lj_), b, (sk_) + (ss_)*k, Rd, dd);                                          \
          if ((lj_).spin_free[b])                                                                  \
            pom_v3_cross(col, d1, dd);                                                             \
          else                                                                                     \
            omega_col(col, R1, Rd);                                                                \
          if ((lj_).has_G[b]) turn_by(col, (lj_).G[b]);                                            \
        }                                                                                          \
        for (int r = 0; r < 3; ++r) {                                                              \
          bt->A[3 * r + k] = (lj_).ref[b][r].c[(sk_) + (ss_)*k];                                   \
          bt->B[3 * r + k] = col[r];                                                               \
        }                                                                                          \
      }                                                                                            \
      for (int r = 0; r < 3; ++r) {                                                                \
        bt->a_bias[r] = 2.0 * (lj_).ref[b][r].c[t2_];                                              \
        bt->alpha_bias[r] = (wt_)[b][r].c[t_];                                                     \
      }                                                                                            \
      if ((lj_).spin_free[b]) {                                                                    \
        pom_kin_min_rotation(bt->R, L->dir_home, d1);                                              \
        bt->spin_free = 1;                                                                         \
        pom_v3_copy(bt->spin_axis, d1);                                                            \
      } else if ((lj_).framed[b] && b > 0 && (lj_).same_turn[b]) {                                 \
        pom_m3_copy(bt->R, bt[-1].R);                                                              \
      } else if ((lj_).framed[b]) {                                                                \
        framed_rotation(bt->R, R1, (lj_).has_G[b] ? (lj_).G[b] : NULL, (lj_).H[b]);                \
      } else {                                                                                     \
        pom_m3_copy(bt->R, R1);                                                                    \
      }                                                                                            \
      /* a body map that does not exist here (a U-P-S limb along its U-joint                       \
       * axis, an R-R-R distal link with w parallel to v): not assembled */                        \
      double sum = 0.0;                                                                            \
      for (int k = 0; k < 9; ++k)                                                                  \
        sum += bt->A[k] + bt->B[k] + bt->R[k];                                                     \
      for (int k = 0; k < 3; ++k)                                                                  \
        sum += bt->a_bias[k] + bt->alpha_bias[k];                                                  \
      if (!isfinite(sum + out->q_bias[i])) return 0;                                               \
    }                                                                                              \
  } while (0)

/* limb_twist: one jet evaluation in algebra V (T = w; s_0..2 = e_0..2). */
int pom_limb_twist(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                   pom_kin_twists *out) {
  const pom_limb *L = &POM_LIMB_CTABLE(arch)->limb[i];
  limb_state st;
  if (!limb_eval(L, R, 1, 0, &st)) return 0;
  vj_motion pf = {R, {w[0], w[1], w[2]}};
  vj_limb lj;
  pom_vjet wt[POM_LIMB_BODIES][3];
  vj_limb_eval(L, &pf, &st, &lj);
  vj_omegas(wt, &lj);
  TWIST_FILL(lj, wt, VJ_S, 1, VJ_T, VJ_T2);
  return 1;
}

/* limb_twist_diff: one jet evaluation in algebra D (T = w; s_k, sigma_k,
 * u_j = e_k, e_k, e_j), read as the table of docs/kinematics-tables.md 5. */
int pom_limb_twist_diff(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                        pom_kin_twists *out, pom_kin_twists_diff *dout) {
  const pom_limb *L = &POM_LIMB_CTABLE(arch)->limb[i];
  limb_state st;
  if (!limb_eval(L, R, 1, 0, &st)) return 0;
  dj_motion pf = {R, {w[0], w[1], w[2]}};
  dj_limb lj;
  pom_djet wt[POM_LIMB_BODIES][3];
  dj_limb_eval(L, &pf, &st, &lj);
  dj_omegas(wt, &lj);
  TWIST_FILL(lj, wt, DJ_D(0), 3, DJ_T, DJ_T2);
  for (int k = 0; k < 3; ++k) {
    pom_kin_twists *dt = &dout->d_theta[k], *dw = &dout->d_omega[k];
    dt->q[i] = lj.q.c[DJ_D(k)];
    for (int j = 0; j < 3; ++j)
      dt->J[3 * i + j] = lj.q.c[DJ_US + 3 * j + k];
    dt->q_bias[i] = 2.0 * lj.q.c[DJ_T2D(k)];
    dw->q[i] = 0.0;
    pom_v3_set(dw->J + 3 * i, 0.0, 0.0, 0.0);
    dw->q_bias[i] = 2.0 * lj.q.c[DJ_T2D(3 + k)];
    for (int b = 0; b < POM_LIMB_BODIES; ++b) {
      pom_kin_body_twist *tb = &dt->body[2 + 2 * i + b], *wb = &dw->body[2 + 2 * i + b];
      double R1[9] = {0}, d1[3] = {0}, Rs[9] = {0}, ds[3] = {0};
      if (!lj.axis[b]) {
        BODY_COEFS(&lj, b, 0, R1, d1);
        BODY_COEFS(&lj, b, DJ_D(k), Rs, ds);
      }
      for (int j = 0; j < 3; ++j) {
        /* B e_j = omega along u_j; its s_k term: vee(R_us R^T + R_u R_s^T),
         * or d_s x d_u + d x d_us for an idle spin */
        double Ru[9] = {0}, du[3] = {0}, Rus[9] = {0}, dus[3] = {0}, a[3], c[3];
        if (!lj.axis[b]) {
          BODY_COEFS(&lj, b, DJ_U + j, Ru, du);
          BODY_COEFS(&lj, b, DJ_US + 3 * j + k, Rus, dus);
        }
        for (int r = 0; r < 3; ++r)
          tb->A[3 * r + j] = lj.ref[b][r].c[DJ_US + 3 * j + k];
        if (b > 0 && lj.same_turn[b]) { /* turns with body b - 1 */
          for (int r = 0; r < 3; ++r)
            tb->B[3 * r + j] = tb[-1].B[3 * r + j];
          continue;
        }
        if (lj.axis[b]) { /* d/ds_k of (dq/du_j) axis */
          pom_v3_scale(a, lj.q.c[DJ_US + 3 * j + k], lj.axis[b]);
          pom_v3_set(c, 0.0, 0.0, 0.0);
        } else if (lj.spin_free[b]) {
          pom_v3_cross(a, ds, du);
          pom_v3_cross(c, d1, dus);
        } else {
          omega_dir(a, 0, R1, Rus, d1, dus);
          omega_dir(c, 0, Rs, Ru, d1, du);
        }
        for (int r = 0; r < 3; ++r)
          a[r] += c[r];
        if (lj.has_G[b]) turn_by(a, lj.G[b]);
        for (int r = 0; r < 3; ++r)
          tb->B[3 * r + j] = a[r];
      }
      for (int r = 0; r < 3; ++r) {
        tb->a_bias[r] = 2.0 * lj.ref[b][r].c[DJ_T2D(k)];
        tb->alpha_bias[r] = wt[b][r].c[DJ_TD(k)];
        wb->a_bias[r] = 2.0 * lj.ref[b][r].c[DJ_T2D(3 + k)];
        wb->alpha_bias[r] = wt[b][r].c[DJ_TD(3 + k)];
      }
      memset(wb->A, 0, sizeof wb->A);
      memset(wb->B, 0, sizeof wb->B);
    }
  }
  return 1;
}

/* ---- limits, footprint ------------------------------------------------------- */
void pom_limb_limit_values(const pom_kin_arch *arch, const double R[9], const double q[3],
                           double value[9]) {
  const pom_limb_table *tb = POM_LIMB_CTABLE(arch);
  limb_state s[3];
  (void)q; /* the kernels recompute q (the same closed form) with the joint centres */
  for (int i = 0; i < 3; ++i)
    if (!limb_eval(&tb->limb[i], R, 0, 1, &s[i])) {
      for (int j = 0; j < 3; ++j) {
        pom_v3_set(s[i].p[j], NAN, NAN, NAN);
        pom_v3_set(s[i].ax[j], NAN, NAN, NAN);
      }
    }
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_limb_measure *m = &tb->measure[kind];
    double *val = value + 3 * (kind - 1);
    for (int k = 0; k < 3; ++k) {
      int i = k, j = (k + 1) % 3;
      double l[3], lp[3], home[3];
      switch (m->kind) {
      case POM_LIMB_MEASURE_CONE_FIXED:
      case POM_LIMB_MEASURE_CONE_PLATFORM:
        pom_v3_sub(l, s[i].p[m->b], s[i].p[m->a]);
        pom_v3_sub(home, tb->limb[i].joint[m->b].point, tb->limb[i].joint[m->a].point);
        pom_v3_normalize(home, home);
        if (m->kind == POM_LIMB_MEASURE_CONE_PLATFORM) {
          pom_m3_tapply(lp, R, l);
          val[k] = pom_kin_angle_between(lp, home);
        } else {
          val[k] = pom_kin_angle_between(l, home);
        }
        break;
      case POM_LIMB_MEASURE_DISTANCE:
        val[k] = pom_kin_segment_distance(s[i].p[m->a], s[i].p[m->b], s[j].p[m->a], s[j].p[m->b]);
        break;
      case POM_LIMB_MEASURE_AXIS_ANGLE:
        val[k] = pom_kin_angle_between(s[i].ax[m->a], s[j].ax[m->a]);
        break;
      case POM_LIMB_MEASURE_ARM_ANGLE: {
        /* docs/architecture-files.md 2.6: counterclockwise about +z, [0, 2 pi) */
        double d =
            atan2(s[j].ax[m->a][1], s[j].ax[m->a][0]) - atan2(s[i].ax[m->a][1], s[i].ax[m->a][0]);
        d -= 2.0 * POM_PI * floor(d / (2.0 * POM_PI));
        val[k] = d < 2.0 * POM_PI ? d : 0.0;
        break;
      }
      default:
        val[k] = 0.0;
        break;
      }
    }
  }
}

double pom_limb_footprint(const pom_kin_arch *arch) {
  const pom_limb_table *tb = POM_LIMB_CTABLE(arch);
  double r = 0.0;
  for (int i = 0; i < 3; ++i) {
    const pom_limb *L = &tb->limb[i];
    if (L->actuated == 0 && L->joint[0].type == POM_LIMB_JOINT_P) {
      for (int s = -1; s <= 1; s += 2) {
        double p[3];
        pom_v3_axpy(p, L->motor, 0.5 * s * arch->stroke, L->joint[0].axis);
        r = fmax(r, hypot(p[0], p[1]));
      }
    } else {
      r = fmax(r, hypot(L->motor[0], L->motor[1]));
    }
  }
  return r;
}

/* ---- constraint wrenches (docs/kinematics-tables.md 3.1) ------------------------- */
/* Determinant of the n x n matrix a (row-major, stride 6, overwritten) by
 * Gaussian elimination with partial pivoting. */
static double det_small(double a[5][6], int n) {
  double det = 1.0;
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (fabs(a[r][c]) > fabs(a[piv][c])) piv = r;
    if (a[piv][c] == 0.0) return 0.0;
    if (piv != c) {
      for (int k = 0; k < n; ++k) {
        double t = a[c][k];
        a[c][k] = a[piv][k];
        a[piv][k] = t;
      }
      det = -det;
    }
    det *= a[c][c];
    for (int r = c + 1; r < n; ++r) {
      double f = a[r][c] / a[c][c];
      for (int k = c; k < n; ++k)
        a[r][k] -= f * a[c][k];
    }
  }
  return det;
}

/* The unit joint twists of limb state s as rows (v_O, omega), v_O the
 * velocity of the point at O: a revolute about (p, a) is (p x a, a), a
 * prismatic (a, 0), a U two revolutes, an S three. Returns how many (at
 * most 9). */
static int limb_screws(const pom_limb *L, const limb_state *s, double tw[9][6]) {
  static const double e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int n = 0;
  for (int j = 0; j < POM_LIMB_JOINTS; ++j) {
    const double *axes[3];
    int na = 0;
    switch (L->joint[j].type) {
    case POM_LIMB_JOINT_P:
      pom_v3_copy(tw[n], s->ax[j]);
      pom_v3_set(tw[n] + 3, 0.0, 0.0, 0.0);
      ++n;
      continue;
    case POM_LIMB_JOINT_R:
      axes[na++] = s->ax[j];
      break;
    case POM_LIMB_JOINT_U:
      axes[na++] = s->ax[j];
      axes[na++] = s->ax2[j];
      break;
    default:
      axes[na++] = e[0];
      axes[na++] = e[1];
      axes[na++] = e[2];
      break;
    }
    for (int k = 0; k < na; ++k, ++n) {
      pom_v3_cross(tw[n], s->p[j], axes[k]);
      pom_v3_copy(tw[n] + 3, axes[k]);
    }
  }
  return n;
}

int pom_limb_constraint(const pom_kin_arch *arch, const double R[9], double force[9],
                        double moment[9]) {
  const pom_limb_table *tb = POM_LIMB_CTABLE(arch);
  if (tb->central != 0) return 0;
  double F[9], M[9];
  for (int i = 0; i < 3; ++i) {
    const pom_limb *L = &tb->limb[i];
    limb_state s;
    double tw[9][6], a[5][6], z[6];
    if (!limb_eval(L, R, 0, 1, &s)) return 0;
    if (limb_screws(L, &s, tw) != 5) return 0; /* a spherical limb holds O itself */
    /* the wrench (f, m) with v_k . f + omega_k . m = 0 for the five twists:
     * the signed 5 x 5 minors of the 5 x 6 twist matrix (a 6-D cross product) */
    for (int c = 0; c < 6; ++c) {
      for (int r = 0; r < 5; ++r)
        for (int k = 0, kk = 0; k < 6; ++k)
          if (k != c) a[r][kk++] = tw[r][k];
      z[c] = ((c & 1) ? -1.0 : 1.0) * det_small(a, 5);
    }
    double fn = pom_v3_norm(z), zn = hypot(fn, pom_v3_norm(z + 3)), scale = 1.0;
    for (int r = 0; r < 5; ++r)
      scale *= hypot(pom_v3_norm(tw[r]), pom_v3_norm(tw[r] + 3));
    if (!(fn > 1e-12 * zn) || !(zn > 1e-12 * scale) || !isfinite(zn)) {
      /* a pure moment, or the five twists dependent (the limb at a
       * singularity of its own, e.g. the R axis on the platform U's axis: no
       * single wrench): no force of this limb blocks a translation */
      pom_v3_set(F + 3 * i, 0.0, 0.0, 0.0);
      pom_v3_set(M + 3 * i, 0.0, 0.0, 0.0);
      continue;
    }
    pom_v3_scale(F + 3 * i, 1.0 / fn, z);
    pom_v3_scale(M + 3 * i, 1.0 / fn, z + 3);
  }
  memcpy(force, F, sizeof F);
  memcpy(moment, M, sizeof M);
  return 3;
}

/* ---- mechanism ------------------------------------------------------------------- */
/* A direction of limb L at home (pom_limb_dir); 0 when it has zero length. */
static int limb_dir(double out[3], const pom_limb *L, pom_limb_dir d) {
  if (d.b < 0) {
    pom_v3_copy(out, L->joint[d.a].axis);
  } else {
    pom_v3_sub(out, L->joint[d.b].point, L->joint[d.a].point);
  }
  return pom_v3_normalize(out, out) > 0.0;
}

/* Thin circular arc of radius r from unit a to unit b, linear density lam:
 * mass, CM and inertia about O (arch_3rrr.c, docs/kinematics-3rrr.md 6). */

static pom_status build_body(pom_mechanism *mech, int *index, const pom_limb_table *tb,
                             const pom_limb *L, int i, int b, const pom_kin_inertia *in,
                             pom_error *err) {
  const pom_limb_body *bd = &tb->body[b];
  double I3[9], O[3] = {0.0, 0.0, 0.0};
  pom_m3_identity(I3);
  switch (bd->model) {
  case POM_LIMB_MASS_GROUP: {
    const pom_kin_body_inertia *bi = &in->body[bd->group];
    double z[3], x[3], Q[9], cm[3], d[3];
    limb_dir(z, L, bd->z_dir);
    int has_x = bd->x_dir.a >= 0 && limb_dir(x, L, bd->x_dir);
    pom_kin_limb_axes(Q, z, L->radial, has_x ? x : NULL);
    if (bd->place == 1) {
      limb_dir(d, L, bd->cm_dir);
      pom_v3_axpy(cm, L->joint[bd->cm_from].point, bi->cm_offset, d);
    } else if (bd->place == 2) {
      const double *pa = L->joint[bd->cm_dir.a].point, *pb = L->joint[bd->cm_dir.b].point;
      for (int k = 0; k < 3; ++k)
        cm[k] = pa[k] + bi->cm_fraction * (pb[k] - pa[k]);
    } else {
      pom_v3_copy(cm, L->joint[L->ref_joint[b]].point);
    }
    *index = pom_kin_build_body(mech, bd->name, i + 1, bi, Q, cm);
    return POM_OK;
  }
  case POM_LIMB_MASS_ARC: {
    const double r = tb->arc_radius, lam = in->value[bd->v_density] * in->value[bd->v_section];
    double m, c[3], IO[9], s[3], p[3];
    pom_kin_arc_inertia(&m, c, IO, L->joint[bd->arc_a].axis, L->joint[bd->arc_b].axis, r, lam);
    pom_v3_scale(s, m, c);
    if (bd->v_point_mass >= 0) {
      pom_v3_scale(p, r, L->joint[bd->point_joint].axis);
      pom_kin_add_point_mass(&m, s, IO, in->value[bd->v_point_mass], p);
    }
    if (bd->v_rotor >= 0) {
      const double *u = L->joint[bd->rotor_joint].axis, Jr = in->value[bd->v_rotor];
      for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 3; ++k)
          IO[3 * a + k] += 0.5 * Jr * ((a == k ? 1.0 : 0.0) + u[a] * u[k]);
    }
    if (!(m > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: the %s has no mass (its arc model)", i + 1, bd->name);
    *index = pom_kin_body_from_O(mech, bd->name, i + 1, m, s, IO);
    return POM_OK;
  }
  default:
    *index = pom_kin_build_body(mech, bd->name, i + 1, NULL, I3, O);
    return POM_OK;
  }
}

static pom_joint_type joint_kind(int t) {
  switch (t) {
  case POM_LIMB_JOINT_R:
    return POM_JOINT_REVOLUTE;
  case POM_LIMB_JOINT_P:
    return POM_JOINT_PRISMATIC;
  case POM_LIMB_JOINT_U:
    return POM_JOINT_UNIVERSAL;
  default:
    return POM_JOINT_SPHERICAL;
  }
}

pom_status pom_limb_mechanism(pom_mechanism *mech, const pom_kin_arch *arch,
                              const pom_kin_inertia *in, pom_error *err) {
  const pom_limb_table *tb = POM_LIMB_CTABLE(arch);
  for (int i = 0; i < 3; ++i) {
    const pom_limb *L = &tb->limb[i];
    int body[POM_LIMB_BODIES + 2];
    body[0] = 0;
    for (int b = 0; b < POM_LIMB_BODIES; ++b)
      POM_TRY(build_body(mech, &body[1 + b], tb, L, i, b, in, err));
    body[3] = mech->platform;
    for (int j = 0; j < POM_LIMB_JOINTS; ++j) {
      const pom_limb_joint *jt = &L->joint[j];
      const double *axis = jt->type == POM_LIMB_JOINT_S ? NULL : jt->axis;
      const double *axis2 = jt->type == POM_LIMB_JOINT_U ? jt->axis2 : NULL;
      int k = pom_kin_build_joint(mech, tb->joint_name[j], i + 1, joint_kind(jt->type), body[j],
                                  body[j + 1], jt->point, axis, axis2);
      if (j == L->actuated) pom_kin_build_actuator(mech, k, body[j + 1], arch->stroke);
    }
  }
  return POM_OK;
}

/* ---- finish ---------------------------------------------------------------------- */
static int valid_joint(int j) {
  return j >= 0 && j < POM_LIMB_JOINTS;
}

static pom_status check_dir(pom_limb_dir d, const char *what, const char *body, pom_error *err) {
  if (!valid_joint(d.a) || d.b >= POM_LIMB_JOINTS)
    POM_FAIL(err, POM_ERR_ARG, "body %s: %s names joint %d/%d, not one of 0..2", body, what, d.a,
             d.b);
  return POM_OK;
}

/* The kernel's derived fields of limb L (number i + 1 in messages). */
/* Whether the line through p along the unit a misses O (relative tolerance tol). */
static int off_origin(const double p[3], const double a[3], double tol) {
  double c[3];
  pom_v3_cross(c, p, a);
  return pom_v3_norm(c) > tol * (1.0 + pom_v3_norm(p));
}

/* R-R-R and R-U-U at home: the distal cosine from the middle axis and the
 * platform-side axis v, the working mode through home (the branch the
 * caller checks), no limb direction or length; fails when the three axes
 * are coplanar (`axes` names them). */
static pom_status rrr_home(pom_limb *L, int i, const double v[3], const char *axes, double *derived,
                           pom_error *err) {
  L->cos_distal = pom_v3_dot(L->joint[1].axis, v);
  double A, B, C;
  rrr_coef(L, v, &A, &B, &C);
  if (fabs(B) < POM_KIN_HOME_MIN_COS * hypot(A, B))
    POM_FAIL(err, POM_ERR_ARG,
             "limb %d: %s coplanar at home (a leg singularity: the two working modes meet)", i + 1,
             axes);
  *derived = atan2(B, A) > 0.0 ? -1.0 : 1.0;
  pom_v3_set(L->dir_home, 0.0, 0.0, 0.0);
  L->length = 0.0;
  return POM_OK;
}

static pom_status finish_limb(pom_limb *L, int i, double scale, pom_error *err) {
  pom_limb_joint *J = L->joint;
  int types[POM_LIMB_JOINTS];
  for (int j = 0; j < POM_LIMB_JOINTS; ++j) {
    types[j] = J[j].type;
    if (J[j].type < POM_LIMB_JOINT_R || J[j].type > POM_LIMB_JOINT_S)
      POM_FAIL(err, POM_ERR_ARG, "limb %d: joint %d has no type (R, P, U or S)", i + 1, j + 1);
    /* a U-joint's zero axis is derived below (U-P-S) */
    if ((J[j].type == POM_LIMB_JOINT_R || J[j].type == POM_LIMB_JOINT_P) &&
        !(pom_v3_normalize(J[j].axis, J[j].axis) > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: joint %d's axis has zero length", i + 1, j + 1);
  }
  L->kernel = (int)pom_limb_kernel_of(types, L->actuated);
  if (L->kernel == POM_LIMB_KERNEL_NONE)
    POM_FAIL(err, POM_ERR_ARG,
             "limb %d: no IK kernel for this joint sequence with joint %d actuated (covered: "
             "R-R-R, R-U-U, P-S-S and R-S-S with joint 1 actuated, S-P-S, U-P-S and U-P-U with "
             "joint 2 actuated)",
             i + 1, L->actuated + 1);
  if (!(L->branch == 0.0 || L->branch == 1.0 || L->branch == -1.0))
    POM_FAIL(err, POM_ERR_ARG, "limb %d: branch %g must be +1, -1 or 0 (the root through home)",
             i + 1, L->branch);
  double derived = 1.0;
  switch (L->kernel) {
  case POM_LIMB_KERNEL_RRR: {
    for (int j = 0; j < 3; ++j)
      if (off_origin(J[j].point, J[j].axis, 1e-9))
        POM_FAIL(err, POM_ERR_ARG, "limb %d: R-R-R joint %d's axis does not pass through O", i + 1,
                 j + 1);
    POM_TRY(rrr_home(L, i, J[2].axis, "the three axes are", &derived, err));
    break;
  }
  case POM_LIMB_KERNEL_RUU: {
    /* the layout of section 2.5: u, w, v through O, B on w, C on v, the
     * link's two axes parallel and normal to w and v */
    double c[3];
    const double tol = 1e-9;
    for (int j = 0; j < 3; ++j)
      if (!(pom_v3_normalize(J[j].axis, J[j].axis) > 0.0) ||
          (J[j].type == POM_LIMB_JOINT_U && !(pom_v3_normalize(J[j].axis2, J[j].axis2) > 0.0)))
        POM_FAIL(err, POM_ERR_ARG, "limb %d: joint %d needs its axes (R-U-U)", i + 1, j + 1);
    const double *through[3][2] = {
        {J[0].point, J[0].axis}, {J[1].point, J[1].axis}, {J[2].point, J[2].axis2}};
    static const char *const what[3] = {"the crank's axis", "the first U's first axis",
                                        "the second U's second axis"};
    for (int j = 0; j < 3; ++j)
      if (off_origin(through[j][0], through[j][1], tol))
        POM_FAIL(err, POM_ERR_ARG,
                 "limb %d: R-U-U: %s does not pass through O and its joint centre (the limb "
                 "would not leave the platform a pure rotation: docs/kinematics-tables.md 2.5)",
                 i + 1, what[j]);
    pom_v3_cross(c, J[1].axis2, J[2].axis);
    if (pom_v3_norm(c) > tol)
      POM_FAIL(err, POM_ERR_ARG,
               "limb %d: R-U-U: the link's two U axes are not parallel (docs/kinematics-tables.md "
               "2.5)",
               i + 1);
    if (fabs(pom_v3_dot(J[1].axis2, J[1].axis)) > tol ||
        fabs(pom_v3_dot(J[2].axis, J[2].axis2)) > tol)
      POM_FAIL(err, POM_ERR_ARG, "limb %d: R-U-U: a U's two axes are not normal", i + 1);
    if (!(fabs(pom_v3_dot(J[1].point, J[1].axis)) > 0.0) ||
        !(fabs(pom_v3_dot(J[2].point, J[2].axis2)) > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: R-U-U: a U centre lies at O", i + 1);
    POM_TRY(rrr_home(L, i, J[2].axis2, "u, w and v are", &derived, err));
    break;
  }
  case POM_LIMB_KERNEL_UPU: {
    double l[3], c[3], h[3];
    const double tol = 1e-9;
    pom_v3_sub(l, J[2].point, J[0].point);
    L->length = pom_v3_normalize(L->dir_home, l);
    if (!(L->length > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: the base joint coincides with the platform joint",
               i + 1);
    pom_v3_cross(c, J[1].axis, L->dir_home);
    if (pom_v3_norm(c) > tol || pom_v3_dot(J[1].axis, L->dir_home) < 0.0)
      POM_FAIL(err, POM_ERR_ARG,
               "limb %d: the prismatic axis must point along the limb, from the base joint to the "
               "platform joint",
               i + 1);
    pom_v3_sub(h, J[1].point, J[0].point);
    pom_v3_cross(c, h, L->dir_home);
    if (pom_v3_norm(c) > tol * L->length)
      POM_FAIL(err, POM_ERR_ARG, "limb %d: the prismatic joint's point is off the limb's line",
               i + 1);
    for (int j = 0; j < 3; j += 2)
      if (!(pom_v3_normalize(J[j].axis, J[j].axis) > 0.0) ||
          !(pom_v3_normalize(J[j].axis2, J[j].axis2) > 0.0))
        POM_FAIL(err, POM_ERR_ARG, "limb %d: joint %d needs its two axes (U-P-U)", i + 1, j + 1);
    const double *through[2][2] = {{J[0].point, J[0].axis}, {J[2].point, J[2].axis2}};
    for (int j = 0; j < 2; ++j) {
      if (off_origin(through[j][0], through[j][1], tol))
        POM_FAIL(err, POM_ERR_ARG,
                 "limb %d: U-P-U: the %s U's %s axis does not pass through O and its centre "
                 "(docs/kinematics-tables.md 2.5)",
                 i + 1, j ? "platform" : "base", j ? "second" : "first");
    }
    pom_v3_cross(c, J[0].axis2, J[2].axis);
    if (pom_v3_norm(c) > tol || fabs(pom_v3_dot(J[0].axis2, L->dir_home)) > tol)
      POM_FAIL(err, POM_ERR_ARG,
               "limb %d: U-P-U: the middle U axes must be parallel and normal to the slide "
               "(docs/kinematics-tables.md 2.5)",
               i + 1);
    if (fabs(pom_v3_dot(J[0].axis2, J[0].axis)) > tol ||
        fabs(pom_v3_dot(J[2].axis, J[2].axis2)) > tol)
      POM_FAIL(err, POM_ERR_ARG, "limb %d: U-P-U: a U's two axes are not normal", i + 1);
    derived = 1.0;
    break;
  }
  case POM_LIMB_KERNEL_PSS:
  case POM_LIMB_KERNEL_RSS: {
    double l[3];
    pom_v3_sub(l, J[2].point, J[1].point);
    L->length = pom_v3_normalize(L->dir_home, l);
    if (!(L->length > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: the link's two spherical joints coincide", i + 1);
    if (L->kernel == POM_LIMB_KERNEL_PSS) {
      double c = pom_v3_dot(L->dir_home, J[0].axis);
      if (fabs(c) < POM_KIN_HOME_MIN_COS)
        POM_FAIL(err, POM_ERR_ARG,
                 "limb %d: link is perpendicular to its slider axis at home (cos = %.3g): the "
                 "home pose is singular",
                 i + 1, c);
      derived = c > 0.0 ? 1.0 : -1.0;
    } else {
      rss_crank k;
      double A, B, C;
      rss_crank_of(L, &k);
      if (!(pom_v3_norm(k.rperp) > 0.0))
        POM_FAIL(err, POM_ERR_ARG, "limb %d: the crank's spherical joint lies on its axis", i + 1);
      rss_coef(L, &k, J[2].point, &A, &B, &C);
      if (fabs(B) < POM_KIN_HOME_MIN_COS * hypot(A, B))
        POM_FAIL(err, POM_ERR_ARG,
                 "limb %d: the link lies in the plane of the crank's axis at home (a leg "
                 "singularity: the two IK roots meet)",
                 i + 1);
      derived = atan2(B, A) > 0.0 ? -1.0 : 1.0;
    }
    break;
  }
  case POM_LIMB_KERNEL_SPS:
  case POM_LIMB_KERNEL_UPS: {
    double l[3], c[3], h[3];
    pom_v3_sub(l, J[2].point, J[0].point);
    L->length = pom_v3_normalize(L->dir_home, l);
    if (!(L->length > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: the base joint coincides with the platform joint",
               i + 1);
    pom_v3_cross(c, J[1].axis, L->dir_home);
    if (pom_v3_norm(c) > 1e-9 || pom_v3_dot(J[1].axis, L->dir_home) < 0.0)
      POM_FAIL(err, POM_ERR_ARG,
               "limb %d: the prismatic axis must point along the limb, from the base joint to the "
               "platform joint",
               i + 1);
    pom_v3_sub(h, J[1].point, J[0].point);
    pom_v3_cross(c, h, L->dir_home);
    if (pom_v3_norm(c) > 1e-9 * L->length)
      POM_FAIL(err, POM_ERR_ARG, "limb %d: the prismatic joint's point is off the limb's line",
               i + 1);
    if (L->kernel == POM_LIMB_KERNEL_UPS) {
      double *a = J[0].axis, *a2 = J[0].axis2, d2[3];
      if (pom_v3_norm(a) == 0.0) {
        double ez[3] = {0.0, 0.0, 1.0};
        pom_v3_cross(a, ez, l);
      }
      pom_v3_axpy(a, a, -pom_v3_dot(a, L->dir_home), L->dir_home);
      if (!(pom_v3_normalize(a, a) > POM_KIN_HOME_MIN_COS))
        POM_FAIL(err, POM_ERR_ARG,
                 "limb %d: U-joint axis is zero or parallel to the limb (a vertical limb needs "
                 "an explicit axis)",
                 i + 1);
      pom_v3_cross(d2, L->dir_home, a);
      pom_v3_normalize(d2, d2);
      if (pom_v3_norm(a2) > 0.0) {
        pom_v3_cross(c, a2, d2);
        if (pom_v3_norm(c) > 1e-9 * pom_v3_norm(a2))
          POM_FAIL(err, POM_ERR_ARG,
                   "limb %d: the U-joint's second axis must be normal to its first axis and to "
                   "the limb",
                   i + 1);
      }
      pom_v3_copy(a2, d2);
    }
    derived = 1.0;
    break;
  }
  default:
    break;
  }
  if (L->kernel == POM_LIMB_KERNEL_RRR || L->kernel == POM_LIMB_KERNEL_PSS ||
      L->kernel == POM_LIMB_KERNEL_RSS || L->kernel == POM_LIMB_KERNEL_RUU) {
    if (L->branch != 0.0 && L->branch != derived)
      POM_FAIL(err, POM_ERR_ARG,
               "limb %d: branch %+g is not the IK root through the home configuration (%+g)", i + 1,
               L->branch, derived);
  }
  L->branch = derived;
  for (int b = 0; b < POM_LIMB_BODIES; ++b)
    L->ref_joint[b] = J[b].type == POM_LIMB_JOINT_P ? b + 1 : b;
  /* radial: toward the platform joint, else its axis, else e_x */
  const double *src = J[2].point;
  if (!(hypot(src[0], src[1]) > 0.0)) src = J[2].axis;
  double h = hypot(src[0], src[1]);
  if (h > 0.0)
    pom_v3_set(L->radial, src[0] / h, src[1] / h, 0.0);
  else
    pom_v3_set(L->radial, 1.0, 0.0, 0.0);
  if (pom_v3_norm(L->motor) == 0.0) {
    if (L->kernel == POM_LIMB_KERNEL_RRR && pom_v3_norm(J[0].point) == 0.0)
      pom_v3_scale(L->motor, scale, J[0].axis);
    else
      pom_v3_copy(L->motor, J[0].point);
  }
  return POM_OK;
}

pom_status pom_limb_finish(pom_kin_arch *arch, pom_error *err) {
  pom_limb_table *tb = POM_LIMB_TABLE(arch);
  const pom_kin_arch_type *type = arch->type;
  int holds_O = 1;
  for (int i = 0; i < 3; ++i) {
    tb->limb[i].kernel = 0;
    POM_TRY(finish_limb(&tb->limb[i], i, arch->design.scale, err));
    int k = tb->limb[i].kernel;
    if (k != POM_LIMB_KERNEL_RRR && k != POM_LIMB_KERNEL_RUU && k != POM_LIMB_KERNEL_UPU)
      holds_O = 0;
    if (i > 0 && tb->limb[i].kernel != tb->limb[0].kernel)
      POM_FAIL(err, POM_ERR_ARG, "limb %d is a %s limb, limb 1 a %s: the three must be alike",
               i + 1, pom_limb_kernel_name((pom_limb_kernel)tb->limb[i].kernel),
               pom_limb_kernel_name((pom_limb_kernel)tb->limb[0].kernel));
  }
  const int act = tb->limb[0].joint[tb->limb[0].actuated].type;
  const pom_actuator_kind kind = act == POM_LIMB_JOINT_P ? POM_ACT_PRISMATIC : POM_ACT_REVOLUTE;
  if (type && type->actuator != kind)
    POM_FAIL(err, POM_ERR_ARG, "the actuated joints are %s but the type's actuators are not",
             act == POM_LIMB_JOINT_P ? "prismatic" : "revolute");
  if (!(tb->central == 1 || tb->central == 0 || tb->central == -1))
    POM_FAIL(err, POM_ERR_ARG, "central joint: %d is not 1 (required), 0 (none) or -1 (optional)",
             tb->central);
  if (tb->central != 1 && !holds_O)
    POM_FAIL(err, POM_ERR_ARG,
             "the %s limbs do not hold the platform at O: the central spherical joint is needed",
             pom_limb_kernel_name((pom_limb_kernel)tb->limb[0].kernel));
  if (type && (tb->central == -1) != (type->optional_central_joint != 0))
    POM_FAIL(err, POM_ERR_ARG,
             "central joint: the table says %s, the type's optional_central_joint %d",
             tb->central == -1 ? "optional" : "fixed", type->optional_central_joint);
  if (tb->central == 0) {
    /* the limbs alone hold O through one wrench each: independent at home */
    double I[9], F[9], M[9];
    pom_m3_identity(I);
    if (pom_limb_constraint(arch, I, F, M) == 3) {
      double sv[3];
      pom_m3_singular_values(sv, F);
      if (!(sv[2] > POM_KIN_HOME_MIN_COS))
        POM_FAIL(err, POM_ERR_ARG,
                 "the limbs' constraint forces are dependent at home (a constraint singularity: "
                 "smallest singular value %.3g; the platform can translate)",
                 sv[2]);
    }
  }
  for (int b = 0; b < POM_LIMB_BODIES; ++b) {
    const pom_limb_body *bd = &tb->body[b];
    if (!memchr(bd->name, '\0', sizeof bd->name) || bd->name[0] == '\0')
      POM_FAIL(err, POM_ERR_ARG, "limb body %d has no name", b + 1);
    if (bd->model == POM_LIMB_MASS_GROUP) {
      if (type && (bd->group < 0 || bd->group >= type->n_inertia_bodies))
        POM_FAIL(err, POM_ERR_ARG, "body %s: inertia group %d is not one of the type's %d",
                 bd->name, bd->group, type->n_inertia_bodies);
      POM_TRY(check_dir(bd->z_dir, "z axis", bd->name, err));
      if (bd->x_dir.a >= 0) POM_TRY(check_dir(bd->x_dir, "x axis", bd->name, err));
      if (bd->place == 1 || bd->place == 2) POM_TRY(check_dir(bd->cm_dir, "CM", bd->name, err));
      if (bd->place == 1 && !valid_joint(bd->cm_from))
        POM_FAIL(err, POM_ERR_ARG, "body %s: CM offset from joint %d", bd->name, bd->cm_from);
      if (bd->place == 2 && bd->cm_dir.b < 0)
        POM_FAIL(err, POM_ERR_ARG, "body %s: cm_fraction needs two joints", bd->name);
    } else if (bd->model == POM_LIMB_MASS_ARC) {
      const int v[3] = {bd->v_point_mass, bd->v_rotor, -1};
      if (!valid_joint(bd->arc_a) || !valid_joint(bd->arc_b))
        POM_FAIL(err, POM_ERR_ARG, "body %s: the arc's joints %d, %d", bd->name, bd->arc_a,
                 bd->arc_b);
      if (type && (bd->v_density < 0 || bd->v_density >= type->n_inertia_values ||
                   bd->v_section < 0 || bd->v_section >= type->n_inertia_values ||
                   v[0] >= type->n_inertia_values || v[1] >= type->n_inertia_values))
        POM_FAIL(err, POM_ERR_ARG, "body %s: an inertia value index is out of the type's %d",
                 bd->name, type->n_inertia_values);
      if ((v[0] >= 0 && !valid_joint(bd->point_joint)) ||
          (v[1] >= 0 && !valid_joint(bd->rotor_joint)))
        POM_FAIL(err, POM_ERR_ARG, "body %s: a point mass or rotor on no joint", bd->name);
      if (!(tb->arc_radius > 0.0))
        POM_FAIL(err, POM_ERR_ARG, "body %s: the arc radius (%g m) must be positive", bd->name,
                 tb->arc_radius);
    } else if (bd->model != POM_LIMB_MASS_NONE) {
      POM_FAIL(err, POM_ERR_ARG, "body %s: mass model %d", bd->name, bd->model);
    }
  }
  for (int k = 1; k < POM_KIN_LIM_KINDS; ++k) {
    const pom_limb_measure *m = &tb->measure[k];
    if (m->kind == POM_LIMB_MEASURE_NONE) continue;
    if (m->kind < 0 || m->kind > POM_LIMB_MEASURE_ARM_ANGLE)
      POM_FAIL(err, POM_ERR_ARG, "limit kind %d: measure %d", k, m->kind);
    const int one_joint =
        m->kind == POM_LIMB_MEASURE_AXIS_ANGLE || m->kind == POM_LIMB_MEASURE_ARM_ANGLE;
    if (!valid_joint(m->a) || (!one_joint && !valid_joint(m->b)))
      POM_FAIL(err, POM_ERR_ARG, "limit kind %d: joints %d, %d are not among 0..2", k, m->a, m->b);
    if (m->kind == POM_LIMB_MEASURE_ARM_ANGLE)
      for (int i = 0; i < 3; ++i) {
        const pom_limb *L = &tb->limb[i];
        const pom_limb_joint *a = &L->joint[L->actuated];
        if (a->type != POM_LIMB_JOINT_R || hypot(a->axis[0], a->axis[1]) > 1e-9 * fabs(a->axis[2]))
          POM_FAIL(err, POM_ERR_ARG,
                   "limit kind %d (%s): an arm angle needs coaxial actuators, every actuated "
                   "joint revolute on the z axis; limb %d's is %s with axis (%.6g, %.6g, %.6g)",
                   k, type && type->limits[k].name ? type->limits[k].name : "arm angle", i + 1,
                   a->type == POM_LIMB_JOINT_R ? "revolute" : "not revolute", a->axis[0],
                   a->axis[1], a->axis[2]);
      }
    int pair = m->kind == POM_LIMB_MEASURE_DISTANCE || one_joint;
    if (type && type->limits[k].name && type->limits[k].per_pair != pair)
      POM_FAIL(err, POM_ERR_ARG, "limit kind %d (%s): its measure is %s, its descriptor not", k,
               type->limits[k].name, pair ? "per limb pair" : "per limb");
  }
  return POM_OK;
}

int pom_limb_flip_branch(pom_kin_arch *arch, int i) {
  pom_limb *L = &POM_LIMB_TABLE(arch)->limb[i];
  if (!(L->kernel == POM_LIMB_KERNEL_RRR || L->kernel == POM_LIMB_KERNEL_PSS ||
        L->kernel == POM_LIMB_KERNEL_RSS || L->kernel == POM_LIMB_KERNEL_RUU))
    return 0; /* S-P-S, U-P-S, U-P-U: q = |p2 - p0| - L0, one root */
  L->branch = -L->branch;
  return 1;
}

void pom_limb_type_ops(pom_kin_arch_type *type) {
  type->data_size = sizeof(pom_limb_table);
  type->finish = pom_limb_finish;
  type->limb = pom_limb_ik;
  type->limb_twist = pom_limb_twist;
  type->limb_twist_diff = pom_limb_twist_diff;
  type->limit_values = pom_limb_limit_values;
  type->footprint = pom_limb_footprint;
  type->mechanism = pom_limb_mechanism;
  type->shapes = NULL;
  type->flip_branch = pom_limb_flip_branch;
  type->constraint = pom_limb_constraint;
}
