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
    {"first_azimuth_deg", "azimuth phi_1 of limb 1 (limb i at phi_1 + (i - 1) 120 deg)", POM_DEG,
     -360.0, 360.0, 1, 90.0, 0, 0},
    {"platform_height", "height of the platform points above O / platform radius", 1.0, -10.0, 10.0,
     1, 0.0, 1, 0},
    {"limb_length", "mid-stroke limb length |A_i B_i| / platform radius", 1.0, 0.1, 100.0, 0, 0.0,
     1, 0},
    {"limb_lean_deg", "angle of the home limb direction from +z", POM_DEG, 0.0, 180.0, 0, 0.0, 1,
     0},
    {"limb_azimuth_deg", "azimuth of the home limb direction, from e_r toward e_t", POM_DEG, -360.0,
     360.0, 0, 0.0, 1, 0},
};

static const pom_kin_points_desc points[] = {
    {"platform_points_m", "B_i, platform joint centres at home (m)", offsetof(sps, platform_point),
     0},
    {"base_points_m", "A_i, U-joint centres on the ground (m)", offsetof(sps, base_point), 0},
    {"ujoint_axes", "U-joint axes fixed in the ground (default unit(e_z x limb))",
     offsetof(sps, ujoint_axis), 1},
};

static const pom_kin_inertia_body_desc bodies[] = {{"cylinder", 1}, {"piston", 1}};

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
static int limb(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3]) {
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
  }
  return 1;
}

/* ---- body twists --------------------------------------------------------- */
/* Cylinder on the universal joint at A (first axis a1 fixed in the ground,
 * second a2 = s0 x a1 fixed in the cylinder): R_cyl = Rot(a1, al) Rot(a2, be)
 * with s = R_cyl s0; the piston turns with it and carries the platform point
 * B. Returns 0 for a zero-length limb or a limb along a1 (cos be = 0). */
static int limb_twist(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                      pom_kin_twists *out) {
  const sps *g = POM_KIN_CDATA(sps, arch);
  const double *A = g->base_point[i], *s0 = g->limb_dir_home[i], *a1 = g->ujoint_axis[i];
  double a2[3], B[3], l[3], s[3];
  pom_v3_cross(a2, s0, a1);
  pom_v3_normalize(a2, a2);
  pom_m3_apply(B, R, g->platform_point[i]);
  pom_v3_sub(l, B, A);
  double n = pom_v3_norm(l);
  if (!(n > 0.0 && n < INFINITY)) return 0;
  pom_v3_scale(s, 1.0 / n, l);
  double Jr[3];
  pom_v3_cross(Jr, B, s);
  out->q[i] = n - g->limb_length_mid[i];
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
  pom_kin_twist_rest(cyl);
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
  pom_kin_outer(ta, a1, ga);
  pom_kin_outer(tb, a2p, gb);
  for (int k = 0; k < 9; ++k)
    cyl->B[k] = ta[k] + tb[k];
  /* w_cyl = al_dot a1 + be_dot a2', a2'_dot = al_dot a1 x a2' */
  pom_v3_cross(a1xa2p, a1, a2p);
  for (int k = 0; k < 3; ++k)
    cyl->alpha_bias[k] = aldd * a1[k] + bedd * a2p[k] + bed * ald * a1xa2p[k];

  *pis = *cyl;
  pom_v3_copy(pis->ref_home, g->platform_point[i]);
  pom_v3_copy(pis->ref, B);
  for (int k = 0; k < 9; ++k)
    pis->A[k] = -SB[k];
  pom_v3_cross(pis->a_bias, w, ldot);
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
    .limit_values = limit_values,
    .footprint = footprint,
    .mechanism = mechanism,
};
