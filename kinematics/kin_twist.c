/* kin_twist.c - pose of every body of the rigid mechanism as a function of
 * the platform rotation, with the maps from the platform angular velocity to
 * each body's twist and the velocity-product (bias) accelerations
 * (docs/dynamics-exact.md section 2). */
#include "pom_kinematics.h"

#include "pom_math.h"

#include <math.h>
#include <string.h>

/* ---- small helpers --------------------------------------------------------- */
/* out = u v^T (outer product) */
static void outer(double out[9], const double u[3], const double v[3]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] = u[r] * v[c];
}

/* Rotation taking unit a to unit b by the smallest angle (a . b > -1):
 * R = I + [k]x + [k]x^2 / (1 + c), k = a x b, c = a . b, with
 * [k]x^2 = k k^T - |k|^2 I. */
static void min_rotation(double R[9], const double a[3], const double b[3]) {
  double k[3];
  pom_v3_cross(k, a, b);
  double f = 1.0 / (1.0 + pom_v3_dot(a, b)), d = 1.0 - f * pom_v3_dot(k, k);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      R[3 * r + c] = (r == c ? d : 0.0) + f * k[r] * k[c];
  R[1] -= k[2];
  R[2] += k[1];
  R[3] += k[2];
  R[5] -= k[0];
  R[6] -= k[1];
  R[7] += k[0];
}

static void body_rest(pom_kin_body_twist *b) {
  memset(b, 0, sizeof *b);
  pom_m3_identity(b->R);
}

/* ---- 3P-S-S/S limb --------------------------------------------------------- */
/* Piston (translation along the slider axis u) and link (B -> C, spherical
 * joints at both ends; its spin about B->C is the idle freedom, set to zero).
 * Returns 0 when the link cannot be assembled or is perpendicular to u. */
static int limb_3pss(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                     pom_kin_twists *out) {
  const double *u = arch->slider_axis[i], *Bm = arch->slider_mid[i];
  double L = arch->link_length[i];
  double C[3], d[3], l[3];
  pom_m3_apply(C, R, arch->platform_point[i]);
  pom_v3_sub(d, C, Bm);
  double du = pom_v3_dot(d, u);
  double disc = du * du - pom_v3_dot(d, d) + L * L;
  if (!(disc >= 0.0)) return 0;
  double root = sqrt(disc);
  double q = du - arch->branch_sign[i] * root;
  double lu = arch->branch_sign[i] * root; /* l . u */
  if (lu == 0.0) return 0;
  pom_v3_axpy(l, d, -q, u);
  /* q_dot = J omega, J = (C x l) / (l . u) */
  double Jr[3], Cxl[3];
  pom_v3_cross(Cxl, C, l);
  pom_v3_scale(Jr, 1.0 / lu, Cxl);
  /* velocity products at omega_dot = 0: C_ddot0 = w x (w x C),
   * q_bias = (l . C_ddot0 + |l_dot|^2) / (l . u) */
  double wC[3], wwC[3], ldot[3];
  pom_v3_cross(wC, w, C);
  pom_v3_cross(wwC, w, wC);
  double qd = pom_v3_dot(Jr, w);
  pom_v3_axpy(ldot, wC, -qd, u);
  double qb = (pom_v3_dot(l, wwC) + pom_v3_dot(ldot, ldot)) / lu;
  out->q[i] = q;
  pom_v3_copy(out->J + 3 * i, Jr);
  out->q_bias[i] = qb;

  pom_kin_body_twist *pis = &out->body[2 + 2 * i], *lnk = &out->body[3 + 2 * i];
  body_rest(pis);
  pom_v3_copy(pis->ref_home, Bm);
  pom_v3_axpy(pis->ref, Bm, q, u);
  outer(pis->A, u, Jr);
  pom_v3_scale(pis->a_bias, qb, u);

  *lnk = *pis; /* the link's reference point is B as well */
  double s[3];
  pom_v3_scale(s, 1.0 / L, l);
  min_rotation(lnk->R, arch->limb_dir_home[i], s);
  /* link angular velocity with zero spin: w_l = l x l_dot / L^2,
   * l_dot = (-[C]x - u J) omega, so B = ([l]x[C]x^T - (l x u) J^T) / L^2
   * with [l]x[C]x = C l^T - (l . C) I */
  double lxu[3], lC = pom_v3_dot(l, C), iL2 = 1.0 / (L * L);
  pom_v3_cross(lxu, l, u);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      lnk->B[3 * r + c] = ((r == c ? lC : 0.0) - C[r] * l[c] - lxu[r] * Jr[c]) * iL2;
  double lb[3];
  pom_v3_axpy(lb, wwC, -qb, u); /* l_ddot at omega_dot = 0 */
  pom_v3_cross(lnk->alpha_bias, l, lb);
  pom_v3_scale(lnk->alpha_bias, 1.0 / (L * L), lnk->alpha_bias);
  lnk->spin_free = 1;
  pom_v3_copy(lnk->spin_axis, s);
  return 1;
}

/* ---- 3S-P-S/S limb --------------------------------------------------------- */
/* Cylinder on the universal joint at A (first axis a1 fixed in the ground,
 * second a2 = s0 x a1 fixed in the cylinder): R_cyl = Rot(a1, al) Rot(a2, be)
 * with s = R_cyl s0; the piston turns with it and carries the platform point
 * B. Returns 0 for a zero-length limb or a limb along a1 (cos be = 0). */
static int limb_3sps(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                     pom_kin_twists *out) {
  const double *A = arch->base_point[i], *s0 = arch->limb_dir_home[i], *a1 = arch->ujoint_axis[i];
  double a2[3], B[3], l[3], s[3];
  pom_v3_cross(a2, s0, a1);
  pom_v3_normalize(a2, a2);
  pom_m3_apply(B, R, arch->platform_point[i]);
  pom_v3_sub(l, B, A);
  double n = pom_v3_norm(l);
  if (!(n > 0.0 && n < INFINITY)) return 0;
  pom_v3_scale(s, 1.0 / n, l);
  double Jr[3];
  pom_v3_cross(Jr, B, s);
  out->q[i] = n - arch->limb_length_mid[i];
  pom_v3_copy(out->J + 3 * i, Jr);

  /* first and second derivatives of s at omega_dot = 0 */
  double ldot[3], lddot[3], sdot[3], sddot[3];
  pom_v3_cross(ldot, w, B);
  pom_v3_cross(lddot, w, ldot);
  double nd = pom_v3_dot(s, ldot);
  pom_v3_axpy(sdot, ldot, -nd, s);
  pom_v3_scale(sdot, 1.0 / n, sdot);
  double ndd = pom_v3_dot(s, lddot) + n * pom_v3_dot(sdot, sdot);
  for (int k = 0; k < 3; ++k)
    sddot[k] = (lddot[k] - 2.0 * nd * sdot[k] - ndd * s[k]) / n;
  out->q_bias[i] = ndd;

  /* U-joint angles: x = s.s0 = cb ca, y = -s.a2 = cb sa, z = s.a1 = sb */
  double x = pom_v3_dot(s, s0), y = -pom_v3_dot(s, a2), z = pom_v3_dot(s, a1);
  double rho2 = x * x + y * y, rho = sqrt(rho2);
  if (!(rho > 0.0)) return 0;
  /* cos/sin of the U-joint angles without trigonometry */
  double ca = x / rho, sa = y / rho, cb = rho, sb = z;
  double xd = pom_v3_dot(s0, sdot), yd = -pom_v3_dot(a2, sdot), zd = pom_v3_dot(a1, sdot);
  double xdd = pom_v3_dot(s0, sddot), ydd = -pom_v3_dot(a2, sddot), zdd = pom_v3_dot(a1, sddot);
  double ald = (x * yd - y * xd) / rho2, bed = zd / rho;
  double rhod = (x * xd + y * yd) / rho;
  double aldd =
      (x * ydd - y * xdd) / rho2 - 2.0 * (x * yd - y * xd) * (x * xd + y * yd) / (rho2 * rho2);
  double bedd = zdd / rho - zd * rhod / rho2;

  pom_kin_body_twist *cyl = &out->body[2 + 2 * i], *pis = &out->body[3 + 2 * i];
  body_rest(cyl);
  /* R_cyl = E Rx(al) Ry(be) E^T with E = [a1 a2 s0] (right-handed: a1 x a2 = s0) */
  double E[9], Rl[9], ERl[9], a2p[3], a1xa2p[3];
  for (int k = 0; k < 3; ++k) {
    E[3 * k + 0] = a1[k];
    E[3 * k + 1] = a2[k];
    E[3 * k + 2] = s0[k];
  }
  const double RxRy[9] = {cb, 0.0, sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb};
  pom_m3_copy(Rl, RxRy);
  pom_m3_mul(ERl, E, Rl);
  pom_m3_mult(cyl->R, ERl, E);
  for (int k = 0; k < 3; ++k)
    a2p[k] = ca * a2[k] + sa * s0[k];
  pom_v3_copy(cyl->ref_home, A);
  pom_v3_copy(cyl->ref, A);
  /* s_dot = S1 omega, S1 = (I - s s^T)(-[B]x) / n; al_dot and be_dot rows */
  double SB[9], P[9], S1[9];
  pom_m3_skew(SB, B);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      P[3 * r + c] = ((r == c) ? 1.0 : 0.0) - s[r] * s[c];
  pom_m3_mul(S1, P, SB);
  for (int k = 0; k < 9; ++k)
    S1[k] = -S1[k] / n;
  double ga[3], gb[3], va[3], ta[9], tb[9];
  for (int k = 0; k < 3; ++k)
    va[k] = (-x * a2[k] - y * s0[k]) / rho2;
  pom_m3_tapply(ga, S1, va);
  pom_m3_tapply(gb, S1, a1);
  pom_v3_scale(gb, 1.0 / rho, gb);
  outer(ta, a1, ga);
  outer(tb, a2p, gb);
  for (int k = 0; k < 9; ++k)
    cyl->B[k] = ta[k] + tb[k];
  /* w_cyl = al_dot a1 + be_dot a2', a2'_dot = al_dot a1 x a2' */
  pom_v3_cross(a1xa2p, a1, a2p);
  for (int k = 0; k < 3; ++k)
    cyl->alpha_bias[k] = aldd * a1[k] + bedd * a2p[k] + bed * ald * a1xa2p[k];

  *pis = *cyl;
  pom_v3_copy(pis->ref_home, arch->platform_point[i]);
  pom_v3_copy(pis->ref, B);
  for (int k = 0; k < 9; ++k)
    pis->A[k] = -SB[k];
  pom_v3_cross(pis->a_bias, w, ldot);
  return 1;
}

/* ---- public ---------------------------------------------------------------- */
pom_status pom_kin_body_twists(const pom_kin_arch *arch, const double R[9], const double omega[3],
                               pom_kin_twists *out, pom_error *err) {
  static const double zero[3] = {0.0, 0.0, 0.0};
  const double *w = omega ? omega : zero;
  if (arch->type != POM_ARCH_3PSS && arch->type != POM_ARCH_3SPS)
    POM_FAIL(err, POM_ERR_ARG, "pom_kin_body_twists: unknown architecture type %d",
             (int)arch->type);
  out->n_bodies = 8;
  body_rest(&out->body[0]);
  pom_kin_body_twist *pf = &out->body[1];
  body_rest(pf);
  pom_m3_copy(pf->R, R);
  pom_m3_identity(pf->B);
  for (int i = 0; i < 3; ++i) {
    int ok =
        arch->type == POM_ARCH_3PSS ? limb_3pss(arch, i, R, w, out) : limb_3sps(arch, i, R, w, out);
    if (!ok) {
      if (!err) return POM_ERR_UNREACHABLE; /* no formatting in the hot path */
      for (int k = 0; k < 9; ++k)
        if (!isfinite(R[k]))
          POM_FAIL(err, POM_ERR_NONFINITE, "body twists: rotation entry R[%d] = %g", k, R[k]);
      POM_FAIL(err, POM_ERR_UNREACHABLE,
               arch->type == POM_ARCH_3PSS
                   ? "limb %d: the link cannot reach the slider axis or is perpendicular to it"
                   : "limb %d: zero length, or the limb lies along its U-joint axis",
               i + 1);
    }
  }
  return POM_OK;
}
