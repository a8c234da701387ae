/* arch_3sps.c - the 3S-P-S/S (3-UPS/S): three extensible limbs (linear voice
 * coils), each a cylinder on a universal joint at the ground point A_i and a
 * piston ending in a spherical joint at the platform point B_i
 * (docs/kinematics.md 2-7; twists: docs/dynamics-exact.md section 2). One
 * implementation of pom_kin_arch_type (pom_arch.h). */
#include "pom_arch.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* Private geometry (fixed frame at home, m). */
typedef struct {
  double platform_point[3][3]; /* B_i in the platform frame = fixed at home */
  double base_point[3][3];     /* A_i, U-joint centre on the ground */
  double ujoint_axis[3][3];    /* U-joint axis fixed in the ground, unit, normal to the limb */
  double limb_length_mid[3];   /* |B_i - A_i| at mid-stroke */
  double limb_dir_home[3][3];  /* unit limb direction A_i -> B_i at home */
  double radial_dir[3][3];     /* unit horizontal direction e_r,i toward B_i */
} sps;

enum { P_FIRST_AZ, P_HEIGHT, P_LENGTH, P_LEAN, P_AZ, P_COUNT };

static const pom_kin_param_desc params[P_COUNT] = {
    {.key = "first_azimuth_deg",
     .meaning = "azimuth phi_1 of limb 1 (limb i at phi_1 + (i - 1) 120 deg)",
     .to_si = POM_DEG,
     .lo = -360.0,
     .hi = 360.0,
     .optional = 1,
     .def = 90.0,
     .synth = 0,
     .integer = 0},
    {.key = "platform_height",
     .meaning = "height of the platform points above O / platform radius",
     .to_si = 1.0,
     .lo = -10.0,
     .hi = 10.0,
     .optional = 1,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "limb_length",
     .meaning = "mid-stroke limb length |A_i B_i| / platform radius",
     .to_si = 1.0,
     .lo = 0.1,
     .hi = 100.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "limb_lean_deg",
     .meaning = "angle of the home limb direction from +z",
     .to_si = POM_DEG,
     .lo = 0.0,
     .hi = 180.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "limb_azimuth_deg",
     .meaning = "azimuth of the home limb direction, from e_r toward e_t",
     .to_si = POM_DEG,
     .lo = -360.0,
     .hi = 360.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
};

static const pom_kin_points_desc points[] = {
    {.key = "platform_points_m",
     .meaning = "B_i, platform joint centres at home (m)",
     .offset = offsetof(sps, platform_point),
     .optional = 0},
    {.key = "base_points_m",
     .meaning = "A_i, U-joint centres on the ground (m)",
     .offset = offsetof(sps, base_point),
     .optional = 0},
    {.key = "ujoint_axes",
     .meaning = "U-joint axes fixed in the ground (default unit(e_z x limb))",
     .offset = offsetof(sps, ujoint_axis),
     .optional = 1},
};

static const pom_kin_inertia_body_desc bodies[] = {{.group = "cylinder", .place = 1},
                                                   {.group = "piston", .place = 1}};

/* ---- geometry --------------------------------------------------------------- */
static pom_status from_design(pom_kin_arch *arch, const pom_kin_design *d, pom_error *err) {
  sps *g = POM_KIN_DATA(sps, arch);
  const double r = d->scale, *x = d->x;
  if (!(x[P_LENGTH] > 0.0))
    POM_FAIL(err, POM_ERR_ARG, "design: limb_length (%g) must be positive", x[P_LENGTH]);
  for (int i = 0; i < 3; ++i) {
    double phi = x[P_FIRST_AZ] + 2.0 * POM_PI * i / 3.0;
    double er[3] = {cos(phi), sin(phi), 0.0}, et[3] = {-sin(phi), cos(phi), 0.0};
    double P[3] = {r * er[0], r * er[1], r * x[P_HEIGHT]}, u[3];
    pom_kin_local_direction(u, er, et, x[P_LEAN], x[P_AZ]);
    pom_v3_copy(g->platform_point[i], P);
    pom_v3_axpy(g->base_point[i], P, -r * x[P_LENGTH], u); /* A = B - L0 s */
    /* First U-joint axis: horizontal, perpendicular to the limb's horizontal
     * part, = unit(e_z x s) whenever the limb is not vertical. */
    for (int k = 0; k < 3; ++k)
      g->ujoint_axis[i][k] = cos(x[P_AZ]) * et[k] - sin(x[P_AZ]) * er[k];
  }
  return POM_OK;
}

static pom_status finish(pom_kin_arch *arch, pom_error *err) {
  sps *g = POM_KIN_DATA(sps, arch);
  for (int i = 0; i < 3; ++i) {
    const double *P = g->platform_point[i];
    double h = hypot(P[0], P[1]), l[3];
    if (!(h > 0.0)) POM_FAIL(err, POM_ERR_ARG, "limb %d: platform point lies on the z axis", i + 1);
    pom_v3_set(g->radial_dir[i], P[0] / h, P[1] / h, 0.0);
    pom_v3_sub(l, P, g->base_point[i]);
    double L0 = pom_v3_normalize(g->limb_dir_home[i], l);
    if (!(L0 > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: ground point A coincides with platform point B", i + 1);
    g->limb_length_mid[i] = L0;
    double *a = g->ujoint_axis[i];
    if (pom_v3_norm(a) == 0.0) {
      /* default (points mode without ujoint_axes): unit(e_z x s) */
      double ez[3] = {0, 0, 1};
      pom_v3_cross(a, ez, l);
    }
    /* U-joint axis: made perpendicular to the limb (Gram-Schmidt). */
    pom_v3_axpy(a, a, -pom_v3_dot(a, g->limb_dir_home[i]), g->limb_dir_home[i]);
    double n = pom_v3_normalize(a, a);
    if (!(n > POM_KIN_HOME_MIN_COS))
      POM_FAIL(err, POM_ERR_ARG,
               "limb %d: U-joint axis is zero or parallel to the limb (a vertical limb needs "
               "explicit geometry.ujoint_axes)",
               i + 1);
  }
  return POM_OK;
}

/* ---- inverse kinematics (docs/kinematics.md 3.2) ------------------------------ */
static int limb(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
                double *tr) {
  const sps *g = POM_KIN_CDATA(sps, arch);
  double b[3], v[3];
  pom_m3_apply(b, R, g->platform_point[i]);
  pom_v3_sub(v, b, g->base_point[i]);
  double n = pom_v3_norm(v);
  if (!(n > 0.0 && n < INFINITY)) return 0; /* zero length, or a non-finite R */
  *q = n - g->limb_length_mid[i];
  if (row) {
    double s[3];
    pom_v3_scale(s, 1.0 / n, v);
    pom_v3_cross(row, b, s);
    /* the force along s drives the piston along s: transmission 1 (docs/kinematics-tables.md
     * 3.2) */
    if (tr) *tr = 1.0;
  }
  return 1;
}

/* ---- body twists --------------------------------------------------------- */
/* The quantities of limb_twist that limb_twist_diff differentiates (names as
 * in docs/dynamics-exact.md section 2). */
typedef struct {
  const double *A, *s0, *a1;   /* ground point, home limb direction, U-joint axis 1 */
  double a2[3];                /* U-joint axis 2 at home, s0 x a1 */
  double B[3], s[3], n, Jr[3]; /* platform point, unit limb, length, Jacobian row */
  double w[3];                 /* platform angular velocity */
  double ldot[3], lddot[3];    /* l_dot = w x B, l_ddot = w x l_dot (omega_dot = 0) */
  double nd, ndd;              /* n_dot, n_ddot */
  double sdot[3], sddot[3];    /* s_dot, s_ddot */
  double x, y, z, rho2, rho;   /* U-joint coordinates of s; rho^2 = x^2 + y^2 */
  double ca, sa;               /* cos, sin of the U-joint angle alpha */
  double xd, yd, zd, xdd, ydd, zdd;
  double ald, bed, rhod, aldd, bedd; /* alpha_dot, beta_dot, rho_dot, alpha_ddot, beta_ddot */
  double a2p[3], a1xa2p[3];          /* a2' = Rot(a1, alpha) a2, a1 x a2' */
  double va[3], ga[3], gb[3];        /* v_alpha; alpha_dot = ga . w, beta_dot = gb . w */
} sps_twist;

/* Cylinder on the universal joint at A (first axis a1 fixed in the ground,
 * second a2 = s0 x a1 fixed in the cylinder): R_cyl = Rot(a1, al) Rot(a2, be)
 * with s = R_cyl s0; the piston turns with it and carries the platform point
 * B. Fills limb i of *out and the intermediate quantities *k. Returns 0 for a
 * zero-length limb or a limb along a1 (cos be = 0). */
static int twist_eval(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                      pom_kin_twists *out, sps_twist *k) {
  const sps *g = POM_KIN_CDATA(sps, arch);
  const double *A = g->base_point[i], *s0 = g->limb_dir_home[i], *a1 = g->ujoint_axis[i];
  double *a2 = k->a2, *B = k->B, *s = k->s, l[3];
  k->A = A;
  k->s0 = s0;
  k->a1 = a1;
  pom_v3_copy(k->w, w);
  pom_v3_cross(a2, s0, a1);
  pom_v3_normalize(a2, a2);
  pom_m3_apply(B, R, g->platform_point[i]);
  pom_v3_sub(l, B, A);
  double n = k->n = pom_v3_norm(l);
  if (!(n > 0.0 && n < INFINITY)) return 0;
  pom_v3_scale(s, 1.0 / n, l);
  pom_v3_cross(k->Jr, B, s);
  out->q[i] = n - g->limb_length_mid[i];
  pom_v3_copy(out->J + 3 * i, k->Jr);

  /* first and second derivatives of s at omega_dot = 0 */
  double *ldot = k->ldot, *lddot = k->lddot, *sdot = k->sdot, *sddot = k->sddot;
  pom_v3_cross(ldot, w, B);
  pom_v3_cross(lddot, w, ldot);
  double nd = k->nd = pom_v3_dot(s, ldot);
  pom_v3_axpy(sdot, ldot, -nd, s);
  pom_v3_scale(sdot, 1.0 / n, sdot);
  double ndd = k->ndd = pom_v3_dot(s, lddot) + n * pom_v3_dot(sdot, sdot);
  for (int c = 0; c < 3; ++c)
    sddot[c] = (lddot[c] - 2.0 * nd * sdot[c] - ndd * s[c]) / n;
  out->q_bias[i] = ndd;

  /* U-joint angles: x = s.s0 = cb ca, y = -s.a2 = cb sa, z = s.a1 = sb */
  double x = k->x = pom_v3_dot(s, s0), y = k->y = -pom_v3_dot(s, a2);
  double z = k->z = pom_v3_dot(s, a1);
  double rho2 = k->rho2 = x * x + y * y, rho = k->rho = sqrt(rho2);
  if (!(rho > 0.0)) return 0;
  /* cos/sin of the U-joint angles without trigonometry */
  double ca = k->ca = x / rho, sa = k->sa = y / rho, cb = rho, sb = z;
  double xd = k->xd = pom_v3_dot(s0, sdot), yd = k->yd = -pom_v3_dot(a2, sdot);
  double zd = k->zd = pom_v3_dot(a1, sdot);
  double xdd = k->xdd = pom_v3_dot(s0, sddot), ydd = k->ydd = -pom_v3_dot(a2, sddot);
  double zdd = k->zdd = pom_v3_dot(a1, sddot);
  double ald = k->ald = (x * yd - y * xd) / rho2, bed = k->bed = zd / rho;
  double rhod = k->rhod = (x * xd + y * yd) / rho;
  double aldd = k->aldd =
      (x * ydd - y * xdd) / rho2 - 2.0 * (x * yd - y * xd) * (x * xd + y * yd) / (rho2 * rho2);
  double bedd = k->bedd = zdd / rho - zd * rhod / rho2;

  pom_kin_body_twist *cyl = &out->body[2 + 2 * i], *pis = &out->body[3 + 2 * i];
  pom_kin_twist_rest(cyl);
  /* R_cyl = E Rx(al) Ry(be) E^T with E = [a1 a2 s0] (right-handed: a1 x a2 = s0) */
  double E[9], Rl[9], ERl[9], *a2p = k->a2p, *a1xa2p = k->a1xa2p;
  for (int c = 0; c < 3; ++c) {
    E[3 * c + 0] = a1[c];
    E[3 * c + 1] = a2[c];
    E[3 * c + 2] = s0[c];
  }
  const double RxRy[9] = {cb, 0.0, sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb};
  pom_m3_copy(Rl, RxRy);
  pom_m3_mul(ERl, E, Rl);
  pom_m3_mult(cyl->R, ERl, E);
  for (int c = 0; c < 3; ++c)
    a2p[c] = ca * a2[c] + sa * s0[c];
  pom_v3_copy(cyl->ref_home, A);
  pom_v3_copy(cyl->ref, A);
  /* s_dot = S1 omega, S1 = (I - s s^T)(-[B]x) / n; al_dot and be_dot rows */
  double SB[9], P[9], S1[9];
  pom_m3_skew(SB, B);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      P[3 * r + c] = ((r == c) ? 1.0 : 0.0) - s[r] * s[c];
  pom_m3_mul(S1, P, SB);
  for (int c = 0; c < 9; ++c)
    S1[c] = -S1[c] / n;
  double *ga = k->ga, *gb = k->gb, *va = k->va, ta[9], tb[9];
  for (int c = 0; c < 3; ++c)
    va[c] = (-x * a2[c] - y * s0[c]) / rho2;
  pom_m3_tapply(ga, S1, va);
  pom_m3_tapply(gb, S1, a1);
  pom_v3_scale(gb, 1.0 / rho, gb);
  pom_kin_outer(ta, a1, ga);
  pom_kin_outer(tb, a2p, gb);
  for (int c = 0; c < 9; ++c)
    cyl->B[c] = ta[c] + tb[c];
  /* w_cyl = al_dot a1 + be_dot a2', a2'_dot = al_dot a1 x a2' */
  pom_v3_cross(a1xa2p, a1, a2p);
  for (int c = 0; c < 3; ++c)
    cyl->alpha_bias[c] = aldd * a1[c] + bedd * a2p[c] + bed * ald * a1xa2p[c];

  *pis = *cyl;
  pom_v3_copy(pis->ref_home, g->platform_point[i]);
  pom_v3_copy(pis->ref, B);
  for (int c = 0; c < 9; ++c)
    pis->A[c] = -SB[c];
  pom_v3_cross(pis->a_bias, w, ldot);
  return 1;
}

static int limb_twist(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                      pom_kin_twists *out) {
  sps_twist k;
  return twist_eval(arch, i, R, w, out, &k);
}

/* ---- second-order kinematics (docs/dynamics-exact.md section 2) ------------ */
/* S1^T v = B x (I - s s^T) v / n (s_dot = S1 omega); s1t_diff: its
 * derivative at fixed v along (dB, ds, dn), given s1tv = S1^T v. */
static void s1t_apply(double out[3], const sps_twist *k, const double v[3]) {
  double pv[3];
  pom_v3_axpy(pv, v, -pom_v3_dot(k->s, v), k->s);
  pom_v3_cross(out, k->B, pv);
  pom_v3_scale(out, 1.0 / k->n, out);
}

static void s1t_diff(double out[3], const sps_twist *k, const double v[3], const double s1tv[3],
                     const double dB[3], const double ds[3], double dn) {
  double pv[3], dpv[3], t0[3], t1[3];
  double sv = pom_v3_dot(k->s, v), dsv = pom_v3_dot(ds, v);
  pom_v3_axpy(pv, v, -sv, k->s);
  for (int c = 0; c < 3; ++c)
    dpv[c] = -dsv * k->s[c] - sv * ds[c];
  pom_v3_cross(t0, dB, pv);
  pom_v3_cross(t1, k->B, dpv);
  for (int c = 0; c < 3; ++c)
    out[c] = (t0[c] + t1[c] - dn * s1tv[c]) / k->n;
}

/* Derivative of limb i's fields (forward mode) into *d along a platform
 * rotation increment th (dw = 0) or, th NULL, along an angular velocity
 * increment dw at fixed R (then the fields that depend on R alone have a
 * zero derivative and their terms are skipped). */
static void twist_tangent(const sps_twist *k, int i, const double *th, const double dw[3],
                          pom_kin_twists *d) {
  const double *s = k->s, *B = k->B, *w = k->w, *s0 = k->s0, *a1 = k->a1, *a2 = k->a2;
  const double n = k->n;
  /* limb vector, length, direction, q and the Jacobian row */
  double dB[3] = {0.0, 0.0, 0.0}, ds[3] = {0.0, 0.0, 0.0}, dn = 0.0, t0[3], t1[3];
  if (th) {
    pom_v3_cross(dB, th, B);
    dn = pom_v3_dot(s, dB);
    for (int c = 0; c < 3; ++c)
      ds[c] = (dB[c] - dn * s[c]) / n;
    pom_v3_cross(t0, dB, s);
    pom_v3_cross(t1, B, ds);
    pom_v3_add(d->J + 3 * i, t0, t1);
  } else {
    pom_v3_set(d->J + 3 * i, 0.0, 0.0, 0.0);
  }
  d->q[i] = dn;

  /* velocities and accelerations of the limb at omega_dot = 0 */
  double dldot[3], dlddot[3], dsdot[3], dsddot[3];
  pom_v3_cross(t0, dw, B);
  pom_v3_cross(t1, w, dB);
  pom_v3_add(dldot, t0, t1);
  pom_v3_cross(t0, dw, k->ldot);
  pom_v3_cross(t1, w, dldot);
  pom_v3_add(dlddot, t0, t1);
  double dnd = pom_v3_dot(ds, k->ldot) + pom_v3_dot(s, dldot);
  for (int c = 0; c < 3; ++c)
    dsdot[c] = (dldot[c] - dnd * s[c] - k->nd * ds[c] - dn * k->sdot[c]) / n;
  double dndd = pom_v3_dot(ds, k->lddot) + pom_v3_dot(s, dlddot) +
                dn * pom_v3_dot(k->sdot, k->sdot) + 2.0 * n * pom_v3_dot(k->sdot, dsdot);
  for (int c = 0; c < 3; ++c)
    dsddot[c] = (dlddot[c] - 2.0 * dnd * k->sdot[c] - 2.0 * k->nd * dsdot[c] - dndd * s[c] -
                 k->ndd * ds[c] - dn * k->sddot[c]) /
                n;
  d->q_bias[i] = dndd;

  /* U-joint coordinates, angle rates and accelerations */
  const double x = k->x, y = k->y, rho = k->rho, rho2 = k->rho2;
  const double xd = k->xd, yd = k->yd, zd = k->zd;
  double dx = pom_v3_dot(s0, ds), dy = -pom_v3_dot(a2, ds);
  double dxd = pom_v3_dot(s0, dsdot), dyd = -pom_v3_dot(a2, dsdot), dzd = pom_v3_dot(a1, dsdot);
  double dxdd = pom_v3_dot(s0, dsddot), dydd = -pom_v3_dot(a2, dsddot);
  double dzdd = pom_v3_dot(a1, dsddot);
  double drho2 = 2.0 * (x * dx + y * dy), drho = (x * dx + y * dy) / rho;
  double dca = (dx - k->ca * drho) / rho, dsa = (dy - k->sa * drho) / rho;
  double N = x * yd - y * xd, M = x * xd + y * yd, N2 = x * k->ydd - y * k->xdd;
  double dN = dx * yd + x * dyd - dy * xd - y * dxd;
  double dM = dx * xd + x * dxd + dy * yd + y * dyd;
  double dN2 = dx * k->ydd + x * dydd - dy * k->xdd - y * dxdd;
  double r4 = rho2 * rho2;
  double dald = (dN - k->ald * drho2) / rho2;
  double dbed = (dzd - k->bed * drho) / rho;
  double drhod = (dM - k->rhod * drho) / rho;
  double daldd = (dN2 - (N2 / rho2) * drho2) / rho2 - 2.0 * (dN * M + N * dM) / r4 +
                 4.0 * N * M * drho2 / (r4 * rho2);
  double dbedd = (dzdd - k->zdd * drho / rho) / rho - (dzd * k->rhod + zd * drhod) / rho2 +
                 zd * k->rhod * drho2 / r4;

  /* cylinder twist map B = a1 ga^T + a2' gb^T and its bias */
  double da2p[3] = {0.0, 0.0, 0.0}, a1xda2p[3] = {0.0, 0.0, 0.0};
  pom_kin_body_twist *cyl = &d->body[2 + 2 * i], *pis = &d->body[3 + 2 * i];
  if (th) {
    double dva[3], dga[3], dgb[3], s1ta1[3];
    for (int c = 0; c < 3; ++c)
      dva[c] = -(dx * a2[c] + dy * s0[c] + k->va[c] * drho2) / rho2;
    s1t_diff(dga, k, k->va, k->ga, dB, ds, dn);
    s1t_apply(t0, k, dva);
    pom_v3_add(dga, dga, t0);
    pom_v3_scale(s1ta1, rho, k->gb);
    s1t_diff(dgb, k, a1, s1ta1, dB, ds, dn);
    for (int c = 0; c < 3; ++c) {
      dgb[c] = (dgb[c] - k->gb[c] * drho) / rho;
      da2p[c] = dca * a2[c] + dsa * s0[c];
    }
    pom_v3_cross(a1xda2p, a1, da2p);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        cyl->B[3 * r + c] = a1[r] * dga[c] + da2p[r] * k->gb[c] + k->a2p[r] * dgb[c];
  } else {
    memset(cyl->B, 0, sizeof cyl->B);
  }
  double dbal = dbed * k->ald + k->bed * dald, bal = k->bed * k->ald;
  for (int c = 0; c < 3; ++c)
    cyl->alpha_bias[c] = daldd * a1[c] + dbedd * k->a2p[c] + k->bedd * da2p[c] +
                         dbal * k->a1xa2p[c] + bal * a1xda2p[c];
  memset(cyl->A, 0, sizeof cyl->A);
  memset(cyl->a_bias, 0, sizeof cyl->a_bias);

  /* piston: the cylinder's rotation, reference point B */
  pom_m3_copy(pis->B, cyl->B);
  pom_v3_copy(pis->alpha_bias, cyl->alpha_bias);
  pom_m3_skew(pis->A, dB);
  for (int c = 0; c < 9; ++c)
    pis->A[c] = -pis->A[c];
  pom_v3_copy(pis->a_bias, dlddot);
}

static int limb_twist_diff(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                           pom_kin_twists *out, pom_kin_twists_diff *dout) {
  static const double e[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  static const double zero[3] = {0.0, 0.0, 0.0};
  sps_twist k;
  if (!twist_eval(arch, i, R, w, out, &k)) return 0;
  for (int c = 0; c < 3; ++c) {
    twist_tangent(&k, i, e[c], zero, &dout->d_theta[c]);
    twist_tangent(&k, i, NULL, e[c], &dout->d_omega[c]);
  }
  return 1;
}

/* ---- limits, footprint, mechanism --------------------------------------------- */
static void limit_values(const pom_kin_arch *arch, const double R[9], const double q[3],
                         double value[9]) {
  const sps *g = POM_KIN_CDATA(sps, arch);
  double to[3][3];
  (void)q;
  for (int i = 0; i < 3; ++i)
    pom_m3_apply(to[i], R, g->platform_point[i]);
  pom_kin_segment_limits(R, &g->base_point[0][0], &to[0][0], &g->limb_dir_home[0][0], value);
}

/* Radius of the U-joints about z (m). */
static double footprint(const pom_kin_arch *arch) {
  const sps *g = POM_KIN_CDATA(sps, arch);
  double r = 0.0;
  for (int i = 0; i < 3; ++i)
    r = fmax(r, hypot(g->base_point[i][0], g->base_point[i][1]));
  return r;
}

static pom_status mechanism(pom_mechanism *mech, const pom_kin_arch *arch,
                            const pom_kin_inertia *in, pom_error *err) {
  const sps *g = POM_KIN_CDATA(sps, arch);
  const pom_kin_body_inertia *cyl_in = &in->body[0], *piston_in = &in->body[1];
  (void)err;
  for (int i = 0; i < 3; ++i) {
    const double *s = g->limb_dir_home[i], *er = g->radial_dir[i], *P = g->platform_point[i];
    const double *A = g->base_point[i], *a1 = g->ujoint_axis[i];
    double L0 = g->limb_length_mid[i], a2[3], mid[3], Q[9], cm[3];
    /* cylinder: x = U-joint axis 1 (horizontal), z = limb */
    pom_kin_limb_axes(Q, s, er, a1);
    pom_v3_axpy(cm, A, cyl_in->cm_offset, s);
    int cyl = pom_kin_build_body(mech, "cylinder", i + 1, cyl_in, Q, cm);
    pom_v3_axpy(cm, P, -piston_in->cm_offset, s);
    int piston = pom_kin_build_body(mech, "piston", i + 1, piston_in, Q, cm);
    pom_v3_cross(a2, s, a1);
    pom_v3_normalize(a2, a2);
    pom_kin_build_joint(mech, "A", i + 1, POM_JOINT_UNIVERSAL, 0, cyl, A, a1, a2);
    /* prismatic cylinder -> piston, centred half-way along the limb */
    pom_v3_axpy(mid, A, 0.5 * L0, s);
    int jp = pom_kin_build_joint(mech, "P", i + 1, POM_JOINT_PRISMATIC, cyl, piston, mid, s, NULL);
    pom_kin_build_actuator(mech, jp, piston, arch->stroke);
    pom_kin_build_joint(mech, "B", i + 1, POM_JOINT_SPHERICAL, piston, mech->platform, P, NULL,
                        NULL);
  }
  return POM_OK;
}

const pom_kin_arch_type pom_kin_arch_3sps = {
    .name = "3SPS",
    .label = "3S-P-S/S",
    .description = "three extensible limbs (linear voice coils) on universal joints at the ground "
                   "and spherical joints at a platform on a spherical joint",
    .actuator = POM_ACT_PRISMATIC,
    .data_size = sizeof(sps),
    .scale_key = "platform_radius_mm",
    .scale_meaning = "platform radius: distance of the platform points from the z axis",
    .scale_sets_kinematics = 1,
    .n_params = P_COUNT,
    .params = params,
    .n_points = 3,
    .points = points,
    .limits = POM_KIN_SEGMENT_LIMIT_KINDS,
    .default_stroke = 0.012,
    .n_inertia_bodies = 2,
    .inertia_bodies = bodies,
    .unreachable = "the limb has zero length or lies along its U-joint axis",
    .from_design = from_design,
    .finish = finish,
    .limb = limb,
    .limb_twist = limb_twist,
    .limb_twist_diff = limb_twist_diff,
    .limit_values = limit_values,
    .footprint = footprint,
    .mechanism = mechanism,
};
