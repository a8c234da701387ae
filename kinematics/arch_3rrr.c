/* arch_3rrr.c - the 3-RRR spherical parallel wrist (Gosselin's Agile Eye
 * family) driven by three rotary voice coils: every one of the nine revolute
 * axes passes through O. Leg i: base (actuated) axis u_i fixed in the
 * ground, intermediate (elbow) axis w_i, platform axis v_i fixed in the
 * platform; the proximal link keeps the angle alpha1 between u_i and w_i,
 * the distal link alpha2 between w_i and v_i (derivation:
 * docs/kinematics-3rrr.md). One implementation of pom_kin_arch_type. */
#include "pom_arch.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* Private geometry: unit axes at home (fixed frame = platform frame). */
typedef struct {
  double base_axis[3][3];     /* u_i, actuated, fixed in the ground */
  double elbow_axis[3][3];    /* w_i at home (theta_i = 0) */
  double platform_axis[3][3]; /* v_i in the platform frame */
  double cos_distal[3];       /* cos alpha2 = w_i . v_i */
  double branch[3];           /* +1 or -1: the IK root (working mode) that is 0 at home */
} rrr;

enum { P_FIRST_AZ, P_ALPHA1, P_ALPHA2, P_BETA, P_GAMMA, P_TWIST, P_ELBOW, P_COUNT };

static const pom_kin_param_desc params[P_COUNT] = {
    {.key = "first_azimuth_deg",
     .meaning = "azimuth of base axis u_1 (leg i at + (i - 1) 120 deg)",
     .to_si = POM_DEG,
     .lo = -360.0,
     .hi = 360.0,
     .optional = 1,
     .def = 90.0,
     .synth = 0,
     .integer = 0},
    {.key = "proximal_angle_deg",
     .meaning = "alpha1: angle of the proximal link, u_i to w_i",
     .to_si = POM_DEG,
     .lo = 1.0,
     .hi = 179.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "distal_angle_deg",
     .meaning = "alpha2: angle of the distal link, w_i to v_i",
     .to_si = POM_DEG,
     .lo = 1.0,
     .hi = 179.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "base_cone_deg",
     .meaning = "beta: angle of the base axes u_i from -z",
     .to_si = POM_DEG,
     .lo = 0.0,
     .hi = 180.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "platform_cone_deg",
     .meaning = "gamma: angle of the platform axes v_i from +z",
     .to_si = POM_DEG,
     .lo = 0.0,
     .hi = 180.0,
     .optional = 0,
     .def = 0.0,
     .synth = 1,
     .integer = 0},
    {.key = "platform_twist_deg",
     .meaning = "azimuth of v_i minus that of u_i at home",
     .to_si = POM_DEG,
     .lo = -360.0,
     .hi = 360.0,
     .optional = 1,
     .def = 60.0,
     .synth = 1,
     .integer = 0},
    {.key = "elbow",
     .meaning = "+1 or -1: elbow w_i on the side of u_i x v_i (+1) or the other",
     .to_si = 1.0,
     .lo = -1.0,
     .hi = 1.0,
     .optional = 1,
     .def = 1.0,
     .synth = 0,
     .integer = 1},
};

static const pom_kin_points_desc points[] = {
    {.key = "base_axes",
     .meaning = "u_i, actuated base axes (unit, through O)",
     .offset = offsetof(rrr, base_axis),
     .optional = 0},
    {.key = "elbow_axes",
     .meaning = "w_i, intermediate axes at home (unit, through O)",
     .offset = offsetof(rrr, elbow_axis),
     .optional = 0},
    {.key = "platform_axes",
     .meaning = "v_i, platform axes at home (unit, through O)",
     .offset = offsetof(rrr, platform_axis),
     .optional = 0},
};

/* Link model (docs/kinematics-3rrr.md section 6), SI after loading. */
enum { V_DENSITY, V_SECTION, V_ELBOW_MASS, V_ROTOR_MASS, V_ROTOR_INERTIA, V_COUNT };
static const pom_kin_value_desc values[V_COUNT] = {
    {.key = "link_density_kg_m3",
     .meaning = "density of the arc links",
     .to_si = 1.0,
     .lo = 1.0,
     .hi = 1e5,
     .optional = 0,
     .def = 0.0},
    {.key = "link_section_mm2",
     .meaning = "cross-section area of the arc links",
     .to_si = 1e-6,
     .lo = 1e-3,
     .hi = 1e4,
     .optional = 0,
     .def = 0.0},
    {.key = "elbow_mass_kg",
     .meaning = "point mass of each elbow joint housing, on the distal link at r w_i",
     .to_si = 1.0,
     .lo = 0.0,
     .hi = 10.0,
     .optional = 1,
     .def = 0.0},
    {.key = "rotor_mass_kg",
     .meaning = "mass of each rotary voice coil rotor, on u_i at r",
     .to_si = 1.0,
     .lo = 0.0,
     .hi = 10.0,
     .optional = 1,
     .def = 0.0},
    {.key = "rotor_inertia_kgm2",
     .meaning = "rotor moment about its axis u_i",
     .to_si = 1.0,
     .lo = 0.0,
     .hi = 1.0,
     .optional = 1,
     .def = 0.0},
};

/* ---- geometry --------------------------------------------------------------- */
static void axis_at(double out[3], double azimuth, double polar_from_z, double zsign) {
  out[0] = sin(polar_from_z) * cos(azimuth);
  out[1] = sin(polar_from_z) * sin(azimuth);
  out[2] = zsign * cos(polar_from_z);
}

static pom_status from_design(pom_kin_arch *arch, const pom_kin_design *d, pom_error *err) {
  rrr *g = POM_KIN_DATA(rrr, arch);
  const double *x = d->x;
  double c1 = cos(x[P_ALPHA1]), c2 = cos(x[P_ALPHA2]);
  double elbow = x[P_ELBOW] >= 0.0 ? 1.0 : -1.0;
  if (x[P_ELBOW] == 0.0) POM_FAIL(err, POM_ERR_ARG, "design: elbow must be +1 or -1, not 0");
  for (int i = 0; i < 3; ++i) {
    double phi = x[P_FIRST_AZ] + 2.0 * POM_PI * i / 3.0;
    double *u = g->base_axis[i], *v = g->platform_axis[i], *w = g->elbow_axis[i], uxv[3];
    axis_at(u, phi, x[P_BETA], -1.0);
    axis_at(v, phi + x[P_TWIST], x[P_GAMMA], 1.0);
    /* w = a u + b v + c (u x v) with u.w = cos alpha1, v.w = cos alpha2, |w| = 1 */
    double cuv = pom_v3_dot(u, v), s2 = 1.0 - cuv * cuv;
    if (!(s2 > POM_KIN_HOME_MIN_COS))
      POM_FAIL(err, POM_ERR_ARG, "leg %d: base and platform axes are parallel at home", i + 1);
    double a = (c1 - c2 * cuv) / s2, b = (c2 - c1 * cuv) / s2;
    double rest = 1.0 - (a * a + b * b + 2.0 * a * b * cuv);
    if (!(rest >= 0.0)) {
      /* the spherical triangle u, w, v with sides alpha1, alpha2 and the
       * angle u-v exists when |alpha1 - alpha2| <= u-v <= alpha1 + alpha2 and
       * alpha1 + alpha2 + u-v <= 360 deg (docs/kinematics-3rrr.md section 1) */
      double uv = acos(cuv), lo = fabs(x[P_ALPHA1] - x[P_ALPHA2]);
      double hi = fmin(x[P_ALPHA1] + x[P_ALPHA2], 2.0 * POM_PI - x[P_ALPHA1] - x[P_ALPHA2]);
      const char *why = uv < lo   ? "shorter than |alpha1 - alpha2|: the leg would have to fold"
                        : uv > hi ? (x[P_ALPHA1] + x[P_ALPHA2] <= POM_PI
                                         ? "longer than alpha1 + alpha2: the links cannot reach"
                                         : "longer than 360 deg - alpha1 - alpha2")
                                  : "at a bound (a folded or stretched leg: singular)";
      POM_FAIL(err, POM_ERR_ARG,
               "leg %d: the links cannot join u and v at home: the angle u-v = %.6g deg (set by "
               "geometry.base_cone_deg, platform_cone_deg and platform_twist_deg) is %s; it must "
               "lie in [|alpha1 - alpha2|, min(alpha1 + alpha2, 360 deg - alpha1 - alpha2)] = "
               "[%.6g, %.6g] deg (alpha1 = geometry.proximal_angle_deg = %.6g, alpha2 = "
               "geometry.distal_angle_deg = %.6g)",
               i + 1, uv / POM_DEG, why, lo / POM_DEG, hi / POM_DEG, x[P_ALPHA1] / POM_DEG,
               x[P_ALPHA2] / POM_DEG);
    }
    double c = elbow * sqrt(rest / s2);
    pom_v3_cross(uxv, u, v);
    for (int k = 0; k < 3; ++k)
      w[k] = a * u[k] + b * v[k] + c * uxv[k];
  }
  return POM_OK;
}

/* theta = atan2(B, A) + branch acos(-C / rho) solves A cos + B sin + C = 0
 * (docs/kinematics-3rrr.md section 2); coefficients at platform axis v. */
static void leg_coefficients(const rrr *g, int i, const double v[3], double *A, double *B,
                             double *C) {
  const double *u = g->base_axis[i], *w0 = g->elbow_axis[i];
  double uw = pom_v3_dot(u, w0), uv = pom_v3_dot(u, v), uxw[3];
  pom_v3_cross(uxw, u, w0);
  *A = pom_v3_dot(w0, v) - uw * uv;
  *B = pom_v3_dot(uxw, v);
  *C = uw * uv - g->cos_distal[i];
}

static pom_status finish(pom_kin_arch *arch, pom_error *err) {
  rrr *g = POM_KIN_DATA(rrr, arch);
  if (!(arch->design.scale > 0.0))
    POM_FAIL(err, POM_ERR_ARG,
             "the link radius (geometry.link_radius_mm) is needed: it sizes the links");
  for (int i = 0; i < 3; ++i) {
    double *u = g->base_axis[i], *w = g->elbow_axis[i], *v = g->platform_axis[i];
    if (!(pom_v3_normalize(u, u) > 0.0) || !(pom_v3_normalize(w, w) > 0.0) ||
        !(pom_v3_normalize(v, v) > 0.0))
      POM_FAIL(err, POM_ERR_ARG, "leg %d: an axis has zero length", i + 1);
    g->cos_distal[i] = pom_v3_dot(w, v);
    double A, B, C;
    leg_coefficients(g, i, v, &A, &B, &C);
    /* theta = 0 is a root at home: the branch whose root it is */
    double phi = atan2(B, A);
    /* the two roots meet (a leg singularity) where sin(phi) = 0: phi near 0
     * or near +-pi (a folded leg) */
    if (fabs(B) < POM_KIN_HOME_MIN_COS * hypot(A, B))
      POM_FAIL(err, POM_ERR_ARG,
               "leg %d: u, w and v are coplanar at home (a leg singularity: the two working "
               "modes meet)",
               i + 1);
    g->branch[i] = phi > 0.0 ? -1.0 : 1.0;
  }
  return POM_OK;
}

/* ---- inverse kinematics ------------------------------------------------------ */
/* theta_i at platform axis v (unit, fixed frame) and w(theta_i); 0 when the
 * leg cannot be assembled. */
static int leg_angle(const rrr *g, int i, const double v[3], double *theta, double w[3]) {
  double A, B, C;
  leg_coefficients(g, i, v, &A, &B, &C);
  double rho = hypot(A, B);
  if (!(rho > 0.0)) return 0;
  double c = -C / rho;
  if (!(c >= -1.0 && c <= 1.0)) return 0; /* also false for NaN */
  double t = atan2(B, A) + g->branch[i] * acos(c);
  t = remainder(t, 2.0 * POM_PI); /* in [-pi, pi] */
  *theta = t;
  const double *u = g->base_axis[i], *w0 = g->elbow_axis[i];
  double uxw[3], ct = cos(t), st = sin(t), uw = pom_v3_dot(u, w0);
  pom_v3_cross(uxw, u, w0);
  for (int k = 0; k < 3; ++k)
    w[k] = ct * w0[k] + st * uxw[k] + (1.0 - ct) * uw * u[k];
  return 1;
}

static int limb(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
                double *tr) {
  const rrr *g = POM_KIN_CDATA(rrr, arch);
  double v[3], w[3];
  pom_m3_apply(v, R, g->platform_axis[i]);
  if (!leg_angle(g, i, v, q, w)) return 0;
  if (row) {
    /* theta_dot = (w x v) . omega / ((u x w) . v) */
    double uxw[3], wxv[3];
    pom_v3_cross(uxw, g->base_axis[i], w);
    double den = pom_v3_dot(uxw, v);
    if (den == 0.0) return 0; /* leg (type-1) singularity */
    pom_v3_cross(wxv, w, v);
    pom_v3_scale(row, 1.0 / den, wxv);
    /* transmission |n^ . u|, n^ = unit(w x v) (docs/kinematics-tables.md 3.2) */
    if (tr) *tr = fabs(den) / pom_v3_norm(wxv);
  }
  return 1;
}

/* ---- body twists (docs/kinematics-3rrr.md section 4) ---------------------------- */
/* Rotation about unit axis u by angle t (Rodrigues). */
static void axis_rotation(double R[9], const double u[3], double t) {
  double c = cos(t), s = sin(t), C = 1.0 - c;
  R[0] = c + C * u[0] * u[0];
  R[1] = C * u[0] * u[1] - s * u[2];
  R[2] = C * u[0] * u[2] + s * u[1];
  R[3] = C * u[1] * u[0] + s * u[2];
  R[4] = c + C * u[1] * u[1];
  R[5] = C * u[1] * u[2] - s * u[0];
  R[6] = C * u[2] * u[0] - s * u[1];
  R[7] = C * u[2] * u[1] + s * u[0];
  R[8] = c + C * u[2] * u[2];
}

/* The quantities of limb_twist that limb_twist_diff differentiates (names as
 * in docs/kinematics-3rrr.md section 4). */
typedef struct {
  const double *u;                 /* base axis */
  double v[3], w[3], n[3], nv;     /* platform and elbow axes, n = u x w, n . v */
  double Jr[3];                    /* Jacobian row (w x v) / (n . v) */
  double om[3], td, tb;            /* platform angular velocity, theta_dot, theta_ddot bias */
  double uxn[3], omv[3], omomv[3]; /* u x n, om x v, om x (om x v) */
  double beta, ndot[3], betad;     /* distal: omega_d = omega + beta v; n_dot; beta_dot */
} rrr_twist;

/* Fills limb i of *out and the intermediate quantities *k; 0 when the leg
 * cannot be assembled or is at a leg singularity. */
static int twist_eval(const pom_kin_arch *arch, int i, const double R[9], const double om[3],
                      pom_kin_twists *out, rrr_twist *k) {
  const rrr *g = POM_KIN_CDATA(rrr, arch);
  const double *u = k->u = g->base_axis[i];
  double *v = k->v, *w = k->w, theta;
  pom_m3_apply(v, R, g->platform_axis[i]);
  if (!leg_angle(g, i, v, &theta, w)) return 0;
  double *n = k->n, wxv[3];
  pom_v3_cross(n, u, w); /* n = u x w */
  double nv = k->nv = pom_v3_dot(n, v);
  if (nv == 0.0) return 0;
  pom_v3_cross(wxv, w, v);
  double *Jr = k->Jr;
  pom_v3_scale(Jr, 1.0 / nv, wxv);
  pom_v3_copy(k->om, om);
  double td = k->td = pom_v3_dot(Jr, om);
  /* theta_ddot at omega_dot = 0: from d2/dt2 (w . v) = 0 with
   * w_dot = theta_dot n, n_dot = theta_dot u x n, v_dot = om x v */
  double *uxn = k->uxn, *omv = k->omv, *omomv = k->omomv;
  pom_v3_cross(uxn, u, n);
  pom_v3_cross(omv, om, v);
  pom_v3_cross(omomv, om, omv);
  double tb = k->tb =
      -(td * td * pom_v3_dot(uxn, v) + 2.0 * td * pom_v3_dot(n, omv) + pom_v3_dot(w, omomv)) / nv;
  out->q[i] = theta;
  pom_v3_copy(out->J + 3 * i, Jr);
  out->q_bias[i] = tb;

  /* proximal: turns about u by theta; reference point O */
  pom_kin_body_twist *px = &out->body[2 + 2 * i], *ds = &out->body[3 + 2 * i];
  pom_kin_twist_rest(px);
  axis_rotation(px->R, u, theta);
  pom_kin_outer(px->B, u, Jr);
  pom_v3_scale(px->alpha_bias, tb, u);

  /* distal: keeps w and v; omega_d = omega + beta v, beta = -(omega . n) / (v . n) */
  pom_kin_twist_rest(ds);
  double F0[9], F[9];
  pom_kin_pair_frame(F0, g->elbow_axis[i], g->platform_axis[i]);
  pom_kin_pair_frame(F, w, v);
  pom_m3_mult(ds->R, F, F0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      ds->B[3 * r + c] = (r == c ? 1.0 : 0.0) - v[r] * n[c] / nv;
  double beta = k->beta = -pom_v3_dot(om, n) / nv, *ndot = k->ndot;
  pom_v3_scale(ndot, td, uxn);
  double betad = k->betad = -(pom_v3_dot(om, ndot) * nv -
                              pom_v3_dot(om, n) * (pom_v3_dot(omv, n) + pom_v3_dot(v, ndot))) /
                            (nv * nv);
  for (int c = 0; c < 3; ++c)
    ds->alpha_bias[c] = betad * v[c] + beta * omv[c];
  return 1;
}

static int limb_twist(const pom_kin_arch *arch, int i, const double R[9], const double om[3],
                      pom_kin_twists *out) {
  rrr_twist k;
  return twist_eval(arch, i, R, om, out, &k);
}

/* ---- second-order kinematics (docs/dynamics-exact.md section 2) ---------------- */
/* Derivative of limb i's fields (forward mode) into *d along a platform
 * rotation increment th (dom = 0) or, th NULL, along an angular velocity
 * increment dom at fixed R (then the fields that depend on R alone have a
 * zero derivative and their terms are skipped). */
static void twist_tangent(const rrr_twist *k, int i, const double *th, const double dom[3],
                          pom_kin_twists *d) {
  const double *u = k->u, *v = k->v, *w = k->w, *n = k->n, *om = k->om, *Jr = k->Jr;
  const double nv = k->nv, td = k->td;
  pom_kin_body_twist *px = &d->body[2 + 2 * i], *ds = &d->body[3 + 2 * i];
  /* axes, q and the Jacobian row: d(w . v) = 0 gives dtheta = Jr . th */
  double dv[3] = {0.0, 0.0, 0.0}, dw[3] = {0.0, 0.0, 0.0}, dn[3] = {0.0, 0.0, 0.0};
  double dJr[3] = {0.0, 0.0, 0.0}, duxn[3] = {0.0, 0.0, 0.0}, dnv = 0.0, t0[3], t1[3];
  if (th) {
    pom_v3_cross(dv, th, v);
    double dtheta = pom_v3_dot(Jr, th);
    d->q[i] = dtheta;
    pom_v3_scale(dw, dtheta, n);
    pom_v3_scale(dn, dtheta, k->uxn);
    dnv = pom_v3_dot(dn, v) + pom_v3_dot(n, dv);
    pom_v3_cross(t0, dw, v);
    pom_v3_cross(t1, w, dv);
    for (int c = 0; c < 3; ++c)
      dJr[c] = (t0[c] + t1[c] - Jr[c] * dnv) / nv;
    pom_v3_cross(duxn, u, dn);
  } else {
    d->q[i] = 0.0;
  }
  pom_v3_copy(d->J + 3 * i, dJr);

  /* theta_dot and the theta_ddot bias */
  double dtd = pom_v3_dot(dJr, om) + pom_v3_dot(Jr, dom);
  double domv[3], domomv[3];
  pom_v3_cross(t0, dom, v);
  pom_v3_cross(t1, om, dv);
  pom_v3_add(domv, t0, t1);
  pom_v3_cross(t0, dom, k->omv);
  pom_v3_cross(t1, om, domv);
  pom_v3_add(domomv, t0, t1);
  double dN = 2.0 * td * dtd * pom_v3_dot(k->uxn, v) +
              td * td * (pom_v3_dot(duxn, v) + pom_v3_dot(k->uxn, dv)) +
              2.0 * dtd * pom_v3_dot(n, k->omv) +
              2.0 * td * (pom_v3_dot(dn, k->omv) + pom_v3_dot(n, domv)) + pom_v3_dot(dw, k->omomv) +
              pom_v3_dot(w, domomv);
  double dtb = -(dN + k->tb * dnv) / nv;
  d->q_bias[i] = dtb;

  /* proximal: B = u Jr^T, alpha_bias = tb u */
  pom_kin_outer(px->B, u, dJr);
  pom_v3_scale(px->alpha_bias, dtb, u);
  memset(px->A, 0, sizeof px->A);
  memset(px->a_bias, 0, sizeof px->a_bias);

  /* distal: B = I - v n^T / nv, alpha_bias = beta_dot v + beta om x v */
  if (th) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        ds->B[3 * r + c] = -(dv[r] * n[c] + v[r] * dn[c]) / nv + v[r] * n[c] * dnv / (nv * nv);
  } else {
    memset(ds->B, 0, sizeof ds->B);
  }
  double dbeta = -(pom_v3_dot(dom, n) + pom_v3_dot(om, dn) + k->beta * dnv) / nv;
  double dndot[3];
  for (int c = 0; c < 3; ++c)
    dndot[c] = dtd * k->uxn[c] + td * duxn[c];
  double P1 = pom_v3_dot(om, k->ndot), P2 = pom_v3_dot(om, n);
  double P3 = pom_v3_dot(k->omv, n) + pom_v3_dot(v, k->ndot);
  double dP1 = pom_v3_dot(dom, k->ndot) + pom_v3_dot(om, dndot);
  double dP2 = pom_v3_dot(dom, n) + pom_v3_dot(om, dn);
  double dP3 =
      pom_v3_dot(domv, n) + pom_v3_dot(k->omv, dn) + pom_v3_dot(dv, k->ndot) + pom_v3_dot(v, dndot);
  double dbetad =
      -(dP1 * nv + P1 * dnv - dP2 * P3 - P2 * dP3) / (nv * nv) - 2.0 * k->betad * dnv / nv;
  for (int c = 0; c < 3; ++c)
    ds->alpha_bias[c] = dbetad * v[c] + k->betad * dv[c] + dbeta * k->omv[c] + k->beta * domv[c];
  memset(ds->A, 0, sizeof ds->A);
  memset(ds->a_bias, 0, sizeof ds->a_bias);
}

static int limb_twist_diff(const pom_kin_arch *arch, int i, const double R[9], const double om[3],
                           pom_kin_twists *out, pom_kin_twists_diff *dout) {
  static const double e[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  static const double zero[3] = {0.0, 0.0, 0.0};
  rrr_twist k;
  if (!twist_eval(arch, i, R, om, out, &k)) return 0;
  for (int c = 0; c < 3; ++c) {
    twist_tangent(&k, i, e[c], zero, &dout->d_theta[c]);
    twist_tangent(&k, i, NULL, e[c], &dout->d_omega[c]);
  }
  return 1;
}

/* ---- limits, footprint ----------------------------------------------------------- */
/* Kind 1: the angle between the elbow axes of each leg pair (the elbow
 * housings are the bulkiest parts; docs/kinematics-3rrr.md section 5). */
static void limit_values(const pom_kin_arch *arch, const double R[9], const double q[3],
                         double value[9]) {
  const rrr *g = POM_KIN_CDATA(rrr, arch);
  double w[3][3];
  for (int i = 0; i < 3; ++i) {
    double v[3], t;
    pom_m3_apply(v, R, g->platform_axis[i]);
    if (!leg_angle(g, i, v, &t, w[i])) pom_v3_set(w[i], NAN, NAN, NAN);
  }
  (void)q;
  for (int k = 0; k < 3; ++k) {
    value[k] = pom_kin_angle_between(w[k], w[(k + 1) % 3]);
    value[3 + k] = value[6 + k] = 0.0;
  }
}

/* The motors sit on u_i at the link radius. */
/* The other IK root of leg i: s -> -s in theta = phi + s acos(-C / rho)
 * (docs/kinematics-3rrr.md section 2). */
static int flip_branch(pom_kin_arch *arch, int i) {
  rrr *g = POM_KIN_DATA(rrr, arch);
  g->branch[i] = -g->branch[i];
  return 1;
}

static double footprint(const pom_kin_arch *arch) {
  const rrr *g = POM_KIN_CDATA(rrr, arch);
  double r = 0.0;
  for (int i = 0; i < 3; ++i)
    r = fmax(r, hypot(g->base_axis[i][0], g->base_axis[i][1]));
  return r * arch->design.scale;
}

/* ---- mechanism (link model: docs/kinematics-3rrr.md section 6) ------------------- */
static pom_status mechanism(pom_mechanism *mech, const pom_kin_arch *arch,
                            const pom_kin_inertia *in, pom_error *err) {
  const rrr *g = POM_KIN_CDATA(rrr, arch);
  const double r = arch->design.scale, lam = in->value[V_DENSITY] * in->value[V_SECTION];
  const double O[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 3; ++i) {
    const double *u = g->base_axis[i], *w = g->elbow_axis[i], *v = g->platform_axis[i];
    double m, c[3], IO[9], s[3], p[3];
    /* proximal: arc u -> w plus the rotor (mass on u at r, axisymmetric
     * about u: J_r axial, J_r / 2 transverse) */
    pom_kin_arc_inertia(&m, c, IO, u, w, r, lam);
    pom_v3_scale(s, m, c);
    pom_v3_scale(p, r, u);
    pom_kin_add_point_mass(&m, s, IO, in->value[V_ROTOR_MASS], p);
    double Jr = in->value[V_ROTOR_INERTIA];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        IO[3 * a + b] += 0.5 * Jr * ((a == b ? 1.0 : 0.0) + u[a] * u[b]);
    if (!(m > 0.0)) POM_FAIL(err, POM_ERR_ARG, "leg %d: the proximal link has no mass", i + 1);
    int prox = pom_kin_body_from_O(mech, "proximal", i + 1, m, s, IO);
    /* distal: arc w -> v plus the elbow housing at r w */
    pom_kin_arc_inertia(&m, c, IO, w, v, r, lam);
    pom_v3_scale(s, m, c);
    pom_v3_scale(p, r, w);
    pom_kin_add_point_mass(&m, s, IO, in->value[V_ELBOW_MASS], p);
    int dist = pom_kin_body_from_O(mech, "distal", i + 1, m, s, IO);
    int ju = pom_kin_build_joint(mech, "U", i + 1, POM_JOINT_REVOLUTE, 0, prox, O, u, NULL);
    pom_kin_build_actuator(mech, ju, prox, arch->stroke);
    pom_kin_build_joint(mech, "W", i + 1, POM_JOINT_REVOLUTE, prox, dist, O, w, NULL);
    pom_kin_build_joint(mech, "V", i + 1, POM_JOINT_REVOLUTE, dist, mech->platform, O, v, NULL);
  }
  return POM_OK;
}

/* ---- shapes (docs/view.md section 3) ------------------------------------------------ */
/* The arc links on the sphere of the link radius r, the rotor of each motor
 * on its base axis just outside it, and the platform: a disc through the
 * platform axes' points r v_i on a stem from O. */
static int shapes(const pom_kin_arch *arch, const pom_mechanism *mech, pom_kin_shape *shape,
                  int cap) {
  const rrr *g = POM_KIN_CDATA(rrr, arch);
  const double r = arch->design.scale;
  if (cap < 16 || mech->n_bodies < 8) return -1;
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const double *u = g->base_axis[i], *w = g->elbow_axis[i], *v = g->platform_axis[i];
    pom_kin_shape *s = &shape[n++];
    memset(s, 0, sizeof *s);
    s->kind = POM_SHAPE_ARC; /* proximal arc u -> w */
    s->body = 2 + 2 * i;
    pom_v3_scale(s->from, r, u);
    pom_v3_scale(s->to, r, w);
    s->radius = 0.05 * r;
    s = &shape[n++];
    memset(s, 0, sizeof *s);
    s->kind = POM_SHAPE_SEGMENT; /* its rotor */
    s->body = 2 + 2 * i;
    pom_v3_scale(s->from, 1.02 * r, u);
    pom_v3_scale(s->to, 1.3 * r, u);
    s->radius = 0.16 * r;
    s = &shape[n++];
    memset(s, 0, sizeof *s);
    s->kind = POM_SHAPE_ARC; /* distal arc w -> v */
    s->body = 3 + 2 * i;
    pom_v3_scale(s->from, r, w);
    pom_v3_scale(s->to, r, v);
    s->radius = 0.05 * r;
  }
  pom_kin_shape *d = &shape[n++];
  memset(d, 0, sizeof *d);
  d->kind = POM_SHAPE_DISC;
  d->body = mech->platform;
  for (int i = 0; i < 3; ++i)
    pom_v3_axpy(d->center, d->center, r / 3.0, g->platform_axis[i]);
  double nrm = pom_v3_normalize(d->axis, d->center);
  if (!(nrm > 0.0)) pom_v3_set(d->axis, 0.0, 0.0, 1.0);
  for (int i = 0; i < 3; ++i) {
    double p[3];
    pom_v3_scale(p, r, g->platform_axis[i]);
    pom_v3_sub(p, p, d->center);
    d->radius = fmax(d->radius, pom_v3_norm(p));
  }
  d->thickness = 0.06 * r;
  pom_kin_shape *stem = &shape[n++];
  memset(stem, 0, sizeof *stem);
  stem->kind = POM_SHAPE_SEGMENT;
  stem->body = mech->platform;
  pom_v3_copy(stem->to, d->center);
  stem->radius = 0.04 * r;
  return n;
}

const pom_kin_arch_type pom_kin_arch_3rrr = {
    .name = "3RRR",
    .label = "3-RRR",
    .description = "spherical wrist (Agile Eye family): three rotary voice coils on base axes "
                   "through O, arc links, all nine revolute axes through O",
    .actuator = POM_ACT_REVOLUTE,
    .data_size = sizeof(rrr),
    .scale_key = "link_radius_mm",
    .scale_meaning = "link radius: distance of the arc links from O (angles alone fix the "
                     "kinematics; the radius sets masses, inertias and the torque needed)",
    .scale_sets_kinematics = 0,
    .n_params = P_COUNT,
    .params = params,
    .n_points = 3,
    .points = points,
    .limits = {[1] = {.name = "elbow angle",
                      .per_pair = 1,
                      .lower = 1,
                      .key = "min_elbow_angle_deg",
                      .json = "elbow_angle_deg",
                      .unit = "deg",
                      .to_display = 1.0 / POM_DEG,
                      .lo = 0.0,
                      .hi = 180.0,
                      .def = 0.0,
                      .cls = POM_KIN_LIMCLASS_INTERFERENCE}},
    .default_stroke = 60.0 * POM_DEG,
    .n_inertia_bodies = 0,
    .inertia_bodies = NULL,
    .n_inertia_values = V_COUNT,
    .inertia_values = values,
    .unreachable = "the distal link cannot reach the platform axis (no real IK root), or the leg "
                   "is at a leg singularity",
    .optional_central_joint = 1,
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
