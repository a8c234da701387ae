/* arch_3pss.c - the 3P-S-S/S: three fixed prismatic actuators (sliders
 * along d_i) joined to the platform by S-S links (docs/kinematics.md 2-7;
 * twists: docs/dynamics-exact.md section 2). One implementation of
 * pom_kin_arch_type (pom_arch.h). */
#include "pom_arch.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* Private geometry (fixed frame at home, m). */
typedef struct {
  double platform_point[3][3]; /* C_i in the platform frame = fixed at home */
  double slider_mid[3][3];     /* B_i at mid-stroke */
  double slider_axis[3][3];    /* unit actuator axis d_i (positive = extension) */
  double link_length[3];       /* |B_i C_i| */
  double limb_dir_home[3][3];  /* unit link direction B_i -> C_i at home */
  double radial_dir[3][3];     /* unit horizontal direction e_r,i toward C_i */
  double branch_sign[3];       /* sign of (l_i . d_i) at home: selects the IK root */
} pss;

/* Design parameters, in the order of `params` below. */
enum { P_FIRST_AZ, P_HEIGHT, P_LENGTH, P_LEAN, P_AZ, P_TILT, P_TILT_AZ, P_COUNT };

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
     .meaning = "link length |B_i C_i| / platform radius",
     .to_si = 1.0,
     .lo = 0.1,
     .hi = 100.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "limb_lean_deg",
     .meaning = "angle of the home link direction from +z",
     .to_si = POM_DEG,
     .lo = 0.0,
     .hi = 180.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "limb_azimuth_deg",
     .meaning = "azimuth of the home link direction, from e_r toward e_t",
     .to_si = POM_DEG,
     .lo = -360.0,
     .hi = 360.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "actuator_tilt_deg",
     .meaning = "angle of the slider axis d_i from +z",
     .to_si = POM_DEG,
     .lo = 0.0,
     .hi = 180.0,
     .optional = 1,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "actuator_azimuth_deg",
     .meaning = "azimuth of the slider axis, from e_r toward e_t",
     .to_si = POM_DEG,
     .lo = -360.0,
     .hi = 360.0,
     .optional = 1,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
};

static const pom_kin_points_desc points[] = {
    {.key = "platform_points_m",
     .meaning = "C_i, platform joint centres at home (m)",
     .offset = offsetof(pss, platform_point),
     .optional = 0},
    {.key = "slider_points_m",
     .meaning = "B_i, slider joint centres at mid-stroke (m)",
     .offset = offsetof(pss, slider_mid),
     .optional = 0},
    {.key = "slider_axes",
     .meaning = "d_i, slider axes (unit, positive = extension)",
     .offset = offsetof(pss, slider_axis),
     .optional = 0},
};

static const pom_kin_inertia_body_desc bodies[] = {{.group = "piston", .place = 1},
                                                   {.group = "link", .place = 2}};

/* ---- geometry --------------------------------------------------------------- */
static pom_status from_design(pom_kin_arch *arch, const pom_kin_design *d, pom_error *err) {
  pss *g = POM_KIN_DATA(pss, arch);
  const double r = d->scale, *x = d->x;
  if (!(x[P_LENGTH] > 0.0))
    POM_FAIL(err, POM_ERR_ARG, "design: limb_length (%g) must be positive", x[P_LENGTH]);
  for (int i = 0; i < 3; ++i) {
    double phi = x[P_FIRST_AZ] + 2.0 * POM_PI * i / 3.0;
    double er[3] = {cos(phi), sin(phi), 0.0}, et[3] = {-sin(phi), cos(phi), 0.0};
    double P[3] = {r * er[0], r * er[1], r * x[P_HEIGHT]}, u[3];
    pom_kin_local_direction(u, er, et, x[P_LEAN], x[P_AZ]);
    pom_v3_copy(g->platform_point[i], P);
    pom_v3_axpy(g->slider_mid[i], P, -r * x[P_LENGTH], u); /* B = C - L l */
    pom_kin_local_direction(g->slider_axis[i], er, et, x[P_TILT], x[P_TILT_AZ]);
  }
  return POM_OK;
}

static pom_status finish(pom_kin_arch *arch, pom_error *err) {
  pss *g = POM_KIN_DATA(pss, arch);
  for (int i = 0; i < 3; ++i) {
    const double *P = g->platform_point[i];
    double h = hypot(P[0], P[1]), l[3];
    if (!(h > 0.0)) POM_FAIL(err, POM_ERR_ARG, "limb %d: platform point lies on the z axis", i + 1);
    pom_v3_set(g->radial_dir[i], P[0] / h, P[1] / h, 0.0);
    double n = pom_v3_normalize(g->slider_axis[i], g->slider_axis[i]);
    if (!(n > 0.0)) POM_FAIL(err, POM_ERR_ARG, "limb %d: slider axis has zero length", i + 1);
    pom_v3_sub(l, P, g->slider_mid[i]);
    double L = pom_v3_normalize(g->limb_dir_home[i], l);
    if (!(L > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "limb %d: slider point B coincides with platform point C", i + 1);
    g->link_length[i] = L;
    double c = pom_v3_dot(g->limb_dir_home[i], g->slider_axis[i]);
    /* l.d = 0 is the IK singularity (the two IK roots meet): no home branch. */
    if (fabs(c) < POM_KIN_HOME_MIN_COS)
      POM_FAIL(err, POM_ERR_ARG,
               "limb %d: link is perpendicular to its slider axis at home (cos = %.3g): "
               "the home pose is singular",
               i + 1, c);
    g->branch_sign[i] = c > 0.0 ? 1.0 : -1.0;
  }
  return POM_OK;
}

/* ---- inverse kinematics ------------------------------------------------------ */
/* q and Jacobian row of limb i (docs/kinematics.md 3.1). Returns 0 when the
 * link cannot reach the slider axis. */
static int limb(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
                double *tr) {
  const pss *g = POM_KIN_CDATA(pss, arch);
  double c[3], d[3];
  pom_m3_apply(c, R, g->platform_point[i]);
  pom_v3_sub(d, c, g->slider_mid[i]);
  const double *u = g->slider_axis[i];
  double L = g->link_length[i];
  double du = pom_v3_dot(d, u);
  double disc = du * du - pom_v3_dot(d, d) + L * L;
  if (!(disc >= 0.0)) return 0;
  double root = sqrt(disc);
  double qi = du - g->branch_sign[i] * root;
  *q = qi;
  if (row) {
    /* l = R c - B(q); l.u = branch_sign * root */
    double l[3], cl[3];
    pom_v3_axpy(l, d, -qi, u);
    pom_v3_cross(cl, c, l);
    double lu = g->branch_sign[i] * root;
    if (lu == 0.0) return 0;
    pom_v3_scale(row, 1.0 / lu, cl);
    /* transmission |l^ . u|, |l| = L (docs/kinematics-tables.md 3.2) */
    if (tr) *tr = fabs(lu) / L;
  }
  return 1;
}

/* ---- body twists ---------------------------------------------------------------- */
/* Piston (translation along the slider axis u) and link (B -> C, spherical
 * joints at both ends; its spin about B->C is the idle freedom, set to zero).
 * Returns 0 when the link cannot be assembled or is perpendicular to u. */
static int limb_twist(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                      pom_kin_twists *out) {
  const pss *g = POM_KIN_CDATA(pss, arch);
  const double *u = g->slider_axis[i], *Bm = g->slider_mid[i];
  double L = g->link_length[i];
  double C[3], d[3], l[3];
  pom_m3_apply(C, R, g->platform_point[i]);
  pom_v3_sub(d, C, Bm);
  double du = pom_v3_dot(d, u);
  double disc = du * du - pom_v3_dot(d, d) + L * L;
  if (!(disc >= 0.0)) return 0;
  double root = sqrt(disc);
  double q = du - g->branch_sign[i] * root;
  double lu = g->branch_sign[i] * root; /* l . u */
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
  pom_kin_twist_rest(pis);
  pom_v3_copy(pis->ref_home, Bm);
  pom_v3_axpy(pis->ref, Bm, q, u);
  pom_kin_outer(pis->A, u, Jr);
  pom_v3_scale(pis->a_bias, qb, u);

  *lnk = *pis; /* the link's reference point is B as well */
  double s[3];
  pom_v3_scale(s, 1.0 / L, l);
  pom_kin_min_rotation(lnk->R, g->limb_dir_home[i], s);
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

/* Second-order kinematics of limb i (docs/dynamics-exact.md section 2.1):
 * limb_twist, then its closed forms differentiated along a platform rotation
 * increment about e_k (C' = e_k x C, the slider point fixed) and along
 * omega_k (C fixed). */
static int limb_twist_diff(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                           pom_kin_twists *out, pom_kin_twists_diff *dout) {
  if (!limb_twist(arch, i, R, w, out)) return 0;
  const pss *g = POM_KIN_CDATA(pss, arch);
  const double *u = g->slider_axis[i], *Jr = out->J + 3 * i;
  const double iL2 = 1.0 / (g->link_length[i] * g->link_length[i]);
  const double q = out->q[i], qb = out->q_bias[i];
  double C[3], l[3], wC[3], wwC[3], ldot[3], lb[3], lxu[3];
  pom_m3_apply(C, R, g->platform_point[i]);
  pom_v3_sub(l, C, g->slider_mid[i]);
  pom_v3_axpy(l, l, -q, u);
  const double lu = pom_v3_dot(l, u);
  pom_v3_cross(wC, w, C);
  pom_v3_cross(wwC, w, wC);
  pom_v3_axpy(ldot, wC, -pom_v3_dot(Jr, w), u);
  pom_v3_axpy(lb, wwC, -qb, u);
  pom_v3_cross(lxu, l, u);
  for (int k = 0; k < 3; ++k) {
    double e[3] = {0.0, 0.0, 0.0};
    e[k] = 1.0;
    /* rotation increment: q' = J_k, l' = C' - q' u, (l.u)' = l'.u,
     * J' = (C' x l + C x l' - J (l.u)') / (l.u) */
    double Cp[3], lp[3], Jp[3], a[3], b[3];
    pom_v3_cross(Cp, e, C);
    const double qp = Jr[k];
    pom_v3_axpy(lp, Cp, -qp, u);
    const double lup = pom_v3_dot(lp, u);
    pom_v3_cross(a, Cp, l);
    pom_v3_cross(b, C, lp);
    for (int r = 0; r < 3; ++r)
      Jp[r] = (a[r] + b[r] - Jr[r] * lup) / lu;
    /* q_bias' = (l'.wwC + l.wwC' + 2 l_dot.l_dot' - q_bias (l.u)') / (l.u),
     * wwC' = w x (w x C'), l_dot' = w x C' - (J'.w) u */
    double wCp[3], wwCp[3], ldp[3], lbp[3], lxup[3];
    pom_v3_cross(wCp, w, Cp);
    pom_v3_cross(wwCp, w, wCp);
    pom_v3_axpy(ldp, wCp, -pom_v3_dot(Jp, w), u);
    const double qbp =
        (pom_v3_dot(lp, wwC) + pom_v3_dot(l, wwCp) + 2.0 * pom_v3_dot(ldot, ldp) - qb * lup) / lu;
    pom_kin_twists *dt = &dout->d_theta[k];
    pom_kin_body_twist *pis = &dt->body[2 + 2 * i], *lnk = &dt->body[3 + 2 * i];
    dt->q[i] = qp;
    pom_v3_copy(dt->J + 3 * i, Jp);
    dt->q_bias[i] = qbp;
    pom_kin_outer(pis->A, u, Jp);
    pom_v3_scale(pis->a_bias, qbp, u);
    pom_m3_copy(lnk->A, pis->A);
    pom_v3_copy(lnk->a_bias, pis->a_bias);
    /* B = ((l.C) I - C l^T - (l x u) J^T) / L^2, term by term */
    const double lCp = pom_v3_dot(lp, C) + pom_v3_dot(l, Cp);
    pom_v3_cross(lxup, lp, u);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        lnk->B[3 * r + c] = ((r == c ? lCp : 0.0) - Cp[r] * l[c] - C[r] * lp[c] - lxup[r] * Jr[c] -
                             lxu[r] * Jp[c]) *
                            iL2;
    /* alpha_bias = l x l_b / L^2, l_b = wwC - q_bias u */
    pom_v3_axpy(lbp, wwCp, -qbp, u);
    pom_v3_cross(a, lp, lb);
    pom_v3_cross(b, l, lbp);
    for (int r = 0; r < 3; ++r)
      lnk->alpha_bias[r] = (a[r] + b[r]) * iL2;

    /* omega_k: (w x C)_k = e x C, wwC_k = e x (w x C) + w x (e x C),
     * l_dot_k = e x C - J_k u; only the biases move */
    double eC[3], wwCw[3], ldw[3], lbw[3];
    pom_v3_cross(eC, e, C);
    pom_v3_cross(a, e, wC);
    pom_v3_cross(b, w, eC);
    pom_v3_add(wwCw, a, b);
    pom_v3_axpy(ldw, eC, -Jr[k], u);
    const double qbw = (pom_v3_dot(l, wwCw) + 2.0 * pom_v3_dot(ldot, ldw)) / lu;
    pom_kin_twists *dw = &dout->d_omega[k];
    pis = &dw->body[2 + 2 * i];
    lnk = &dw->body[3 + 2 * i];
    dw->q_bias[i] = qbw;
    pom_v3_scale(pis->a_bias, qbw, u);
    pom_v3_copy(lnk->a_bias, pis->a_bias);
    pom_v3_axpy(lbw, wwCw, -qbw, u);
    pom_v3_cross(a, l, lbw);
    pom_v3_scale(lnk->alpha_bias, iL2, a);
  }
  return 1;
}

/* ---- limits, footprint, mechanism --------------------------------------------- */
static void limit_values(const pom_kin_arch *arch, const double R[9], const double q[3],
                         double value[9]) {
  const pss *g = POM_KIN_CDATA(pss, arch);
  double from[3][3], to[3][3];
  for (int i = 0; i < 3; ++i) {
    pom_m3_apply(to[i], R, g->platform_point[i]);
    pom_v3_axpy(from[i], g->slider_mid[i], q[i], g->slider_axis[i]);
  }
  pom_kin_segment_limits(R, &from[0][0], &to[0][0], &g->limb_dir_home[0][0], value);
}

/* Radius of the slider joints about z over the whole stroke (m). */
/* The other IK root of limb i: the link on the other side of the normal to
 * the slider axis through C_i (branch_sign -> -branch_sign). */
static int flip_branch(pom_kin_arch *arch, int i) {
  pss *g = POM_KIN_DATA(pss, arch);
  g->branch_sign[i] = -g->branch_sign[i];
  return 1;
}

static double footprint(const pom_kin_arch *arch) {
  const pss *g = POM_KIN_CDATA(pss, arch);
  double r = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int s = -1; s <= 1; s += 2) {
      double p[3];
      pom_v3_axpy(p, g->slider_mid[i], 0.5 * s * arch->stroke, g->slider_axis[i]);
      r = fmax(r, hypot(p[0], p[1]));
    }
  return r;
}

static pom_status mechanism(pom_mechanism *mech, const pom_kin_arch *arch,
                            const pom_kin_inertia *in, pom_error *err) {
  const pss *g = POM_KIN_CDATA(pss, arch);
  const pom_kin_body_inertia *piston_in = &in->body[0], *link_in = &in->body[1];
  (void)err;
  for (int i = 0; i < 3; ++i) {
    const double *s = g->limb_dir_home[i], *er = g->radial_dir[i];
    const double *P = g->platform_point[i], *B = g->slider_mid[i], *d = g->slider_axis[i];
    double Q[9], cm[3];
    /* piston: translates along d; CM on the axis */
    pom_kin_limb_axes(Q, d, er, NULL);
    pom_v3_axpy(cm, B, piston_in->cm_offset, d);
    int piston = pom_kin_build_body(mech, "piston", i + 1, piston_in, Q, cm);
    /* link B -> C */
    pom_kin_limb_axes(Q, s, er, NULL);
    for (int k = 0; k < 3; ++k)
      cm[k] = B[k] + link_in->cm_fraction * (P[k] - B[k]);
    int link = pom_kin_build_body(mech, "link", i + 1, link_in, Q, cm);
    int jp = pom_kin_build_joint(mech, "P", i + 1, POM_JOINT_PRISMATIC, 0, piston, B, d, NULL);
    pom_kin_build_actuator(mech, jp, piston, arch->stroke);
    pom_kin_build_joint(mech, "B", i + 1, POM_JOINT_SPHERICAL, piston, link, B, NULL, NULL);
    pom_kin_build_joint(mech, "C", i + 1, POM_JOINT_SPHERICAL, link, mech->platform, P, NULL, NULL);
  }
  return POM_OK;
}

/* ---- shapes (docs/view.md section 3) ------------------------------------------------ */
/* The piston a square bar along its slider axis ending at B_i (the linear
 * voice coil's moving part), the link a rod B_i -> C_i; the platform is the
 * derived disc through the C_i. */
static int shapes(const pom_kin_arch *arch, const pom_mechanism *mech, pom_kin_shape *shape,
                  int cap) {
  const pss *g = POM_KIN_CDATA(pss, arch);
  const double r = arch->design.scale > 0.0 ? arch->design.scale : g->link_length[0];
  if (cap < 6 || mech->n_bodies < 8) return -1;
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const double *B = g->slider_mid[i], *d = g->slider_axis[i];
    double bar = 0.45 * r + 0.5 * arch->stroke;
    pom_kin_shape *s = &shape[n++];
    memset(s, 0, sizeof *s);
    s->kind = POM_SHAPE_BOX;
    s->body = 2 + 2 * i;
    pom_v3_axpy(s->center, B, -0.5 * bar, d);
    pom_v3_copy(s->axis, d);
    pom_v3_cross(s->axis2, d, g->radial_dir[i]);
    if (!(pom_v3_normalize(s->axis2, s->axis2) > 0.0)) pom_v3_set(s->axis2, 0.0, 0.0, 1.0);
    pom_v3_set(s->size, bar, 0.14 * r, 0.14 * r);
    s = &shape[n++];
    memset(s, 0, sizeof *s);
    s->kind = POM_SHAPE_SEGMENT;
    s->body = 3 + 2 * i;
    pom_v3_copy(s->from, B);
    pom_v3_copy(s->to, g->platform_point[i]);
    s->radius = 0.04 * r;
  }
  return n;
}

const pom_kin_arch_type pom_kin_arch_3pss = {
    .name = "3PSS",
    .label = "3P-S-S/S",
    .description = "three fixed linear voice coils (prismatic) driving S-S links to a platform on "
                   "a spherical joint",
    .actuator = POM_ACT_PRISMATIC,
    .data_size = sizeof(pss),
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
    .unreachable = "the link cannot reach the slider axis (no real IK root)",
    .from_design = from_design,
    .finish = finish,
    .limb = limb,
    .limb_twist = limb_twist,
    .limb_twist_diff = limb_twist_diff,
    .limit_values = limit_values,
    .footprint = footprint,
    .mechanism = mechanism,
    .shapes = shapes,
    .flip_branch = flip_branch,
};
