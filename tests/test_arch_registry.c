/* test_arch_registry.c - the registry of architectures is open: a program
 * defines its own architecture (here the "3PSS-radial", defined in this file
 * only) with its own pom_kin_arch_type table and private data, registers it
 * with pom_kin_arch_register, and then uses it through the public API alone:
 * config loading, IK, Jacobian against central differences, FK round trip,
 * mechanism, and both dynamics formulations. Also the registry's error
 * paths. The worked example of docs/extending.md.
 *
 * The 3PSS-radial: three linear actuators whose sliders move along the
 * horizontal radial direction e_r,i of their limb (d_i = e_r,i), each joined
 * to the platform point C_i = r e_r,i by an S-S link of length L. With
 * d = R C_i - B_i (B_i the slider joint at mid-stroke) and u = e_r,i, the
 * link closes when |d - q u| = L, whose root on the home branch (link
 * direction l with sign(l . u) = s) is
 *   q = (d . u) - s sqrt((d . u)^2 - |d|^2 + L^2),
 * and differentiating |R C - B - q u|^2 = L^2 gives the Jacobian row
 *   q_dot = (C x l) . omega / (l . u),  l = R C - B - q u, C = R C_i.
 * With the link leaning inward (l . e_r < 0) the sliders sit outside and
 * below the platform. */
#include "check.h"
#include "pom_view.h"
#include "pom_arch.h"
#include "pom_config.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_shape.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* ---- the architecture -------------------------------------------------------- */

/* Private geometry (fixed frame at home, m): 51 doubles of the 96 of
 * pom_kin_arch.data. */
typedef struct {
  double platform_pt[3][3]; /* C_i, platform joint centres */
  double slider_pt[3][3];   /* B_i, slider joint centres at mid-stroke */
  double slider_dir[3][3];  /* u_i = e_r,i, unit slider axes (positive = outward) */
  double rod_dir[3][3];     /* unit link direction B_i -> C_i at home */
  double radial[3][3];      /* unit e_r,i */
  double rod_length[3];     /* |B_i C_i| (m) */
  double branch[3];         /* sign of (l_i . u_i) at home: the IK root */
} radial_geom;

/* Design parameters, in the order of radial_params. */
enum { RP_LENGTH, RP_LEAN, RP_TWIST, RP_COUNT };

static const pom_kin_param_desc radial_params[RP_COUNT] = {
    {"rod_length", "link length |B_i C_i| / platform radius", 1.0, 0.2, 50.0, 0, 0.0, 1, 0},
    {"link_lean_deg", "angle of the home link direction B->C from +z", POM_DEG, 0.0, 180.0, 0, 0.0,
     1, 0},
    {"link_twist_deg", "azimuth of the home link direction, from e_r toward e_t", POM_DEG, -360.0,
     360.0, 0, 0.0, 1, 0},
};

static const pom_kin_points_desc radial_points[] = {
    {"platform_points_m", "C_i, platform joint centres at home (m)",
     offsetof(radial_geom, platform_pt), 0},
    {"slider_points_m", "B_i, slider joint centres at mid-stroke (m)",
     offsetof(radial_geom, slider_pt), 0},
};

static const pom_kin_inertia_body_desc radial_bodies[] = {{"slider", 1}, {"rod", 2}};

/* C_i = r e_r,i (limb i at azimuth 90 + 120 i deg), B_i = C_i - L l_i. */
static pom_status radial_from_design(pom_kin_arch *arch, const pom_kin_design *des,
                                     pom_error *err) {
  radial_geom *g = POM_KIN_DATA(radial_geom, arch);
  const double r = des->scale, *x = des->x;
  if (!(x[RP_LENGTH] > 0.0))
    POM_FAIL(err, POM_ERR_ARG, "design: rod_length (%g) must be positive", x[RP_LENGTH]);
  for (int i = 0; i < 3; ++i) {
    double phi = 0.5 * POM_PI + 2.0 * POM_PI * i / 3.0;
    double er[3] = {cos(phi), sin(phi), 0.0}, et[3] = {-sin(phi), cos(phi), 0.0}, l[3];
    pom_kin_local_direction(l, er, et, x[RP_LEAN], x[RP_TWIST]);
    pom_v3_scale(g->platform_pt[i], r, er);
    pom_v3_axpy(g->slider_pt[i], g->platform_pt[i], -r * x[RP_LENGTH], l);
  }
  return POM_OK;
}

/* Derived fields; the slider axis is the radial direction of C_i. */
static pom_status radial_finish(pom_kin_arch *arch, pom_error *err) {
  radial_geom *g = POM_KIN_DATA(radial_geom, arch);
  for (int i = 0; i < 3; ++i) {
    const double *C = g->platform_pt[i];
    double h = hypot(C[0], C[1]), l[3];
    if (!(h > 0.0)) POM_FAIL(err, POM_ERR_ARG, "limb %d: platform point on the z axis", i + 1);
    pom_v3_set(g->radial[i], C[0] / h, C[1] / h, 0.0);
    pom_v3_copy(g->slider_dir[i], g->radial[i]);
    pom_v3_sub(l, C, g->slider_pt[i]);
    g->rod_length[i] = pom_v3_normalize(g->rod_dir[i], l);
    if (!(g->rod_length[i] > 0.0)) POM_FAIL(err, POM_ERR_ARG, "limb %d: B and C coincide", i + 1);
    double c = pom_v3_dot(g->rod_dir[i], g->slider_dir[i]);
    /* l . u = 0: the two IK roots meet, no home branch to follow */
    if (fabs(c) < 1e-3)
      POM_FAIL(err, POM_ERR_ARG, "limb %d: link perpendicular to its slider at home", i + 1);
    g->branch[i] = c > 0.0 ? 1.0 : -1.0;
  }
  return POM_OK;
}

/* Shared by limb and limb_twist: C = R C_i, l = C - B(q), q, l . u; 0 when
 * the link cannot reach the slider axis or is perpendicular to it. */
static int radial_close(const radial_geom *g, int i, const double R[9], double C[3], double l[3],
                        double *q, double *lu) {
  double d[3];
  const double *u = g->slider_dir[i];
  pom_m3_apply(C, R, g->platform_pt[i]);
  pom_v3_sub(d, C, g->slider_pt[i]);
  double du = pom_v3_dot(d, u), L = g->rod_length[i];
  double disc = du * du - pom_v3_dot(d, d) + L * L;
  if (!(disc >= 0.0)) return 0;
  *lu = g->branch[i] * sqrt(disc);
  *q = du - *lu;
  pom_v3_axpy(l, d, -*q, u);
  return *lu != 0.0;
}

static int radial_limb(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
                       double *tr) {
  const radial_geom *g = POM_KIN_CDATA(radial_geom, arch);
  double C[3], l[3], lu, qi, Cxl[3];
  if (!radial_close(g, i, R, C, l, &qi, &lu)) return 0;
  *q = qi;
  if (row) {
    pom_v3_cross(Cxl, C, l);
    pom_v3_scale(row, 1.0 / lu, Cxl);
    if (tr) *tr = fabs(lu) / g->rod_length[i]; /* |l^ . u| */
  }
  return 1;
}

/* Slider (translation along u) and rod (spherical at both ends; its spin
 * about B->C is idle and set to zero). Velocity products at omega_dot = 0:
 * C_ddot = w x (w x C), q_bias = (l . C_ddot + |l_dot|^2) / (l . u); rod
 * angular velocity without spin w_r = l x l_dot / L^2. */
static int radial_limb_twist(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                             pom_kin_twists *out) {
  const radial_geom *g = POM_KIN_CDATA(radial_geom, arch);
  const double *u = g->slider_dir[i], *B = g->slider_pt[i];
  double C[3], l[3], q, lu, row[3], Cxl[3];
  if (!radial_close(g, i, R, C, l, &q, &lu)) return 0;
  pom_v3_cross(Cxl, C, l);
  pom_v3_scale(row, 1.0 / lu, Cxl);
  double wC[3], Cdd[3], ldot[3];
  pom_v3_cross(wC, w, C);
  pom_v3_cross(Cdd, w, wC);
  pom_v3_axpy(ldot, wC, -pom_v3_dot(row, w), u);
  double qb = (pom_v3_dot(l, Cdd) + pom_v3_dot(ldot, ldot)) / lu;
  out->q[i] = q;
  pom_v3_copy(out->J + 3 * i, row);
  out->q_bias[i] = qb;

  pom_kin_body_twist *sl = &out->body[2 + 2 * i], *rod = &out->body[3 + 2 * i];
  pom_kin_twist_rest(sl);
  pom_v3_copy(sl->ref_home, B);
  pom_v3_axpy(sl->ref, B, q, u);
  pom_kin_outer(sl->A, u, row);
  pom_v3_scale(sl->a_bias, qb, u);

  *rod = *sl; /* reference point B(q) as well */
  const double L = g->rod_length[i], iL2 = 1.0 / (L * L);
  double s[3], lxu[3], lC = pom_v3_dot(l, C), ldd[3];
  pom_v3_scale(s, 1.0 / L, l);
  pom_kin_min_rotation(rod->R, g->rod_dir[i], s);
  /* l_dot = -[C]x omega - u (row . omega): B = ([l]x [C]x^T - (l x u) row^T) / L^2 */
  pom_v3_cross(lxu, l, u);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      rod->B[3 * a + b] = ((a == b ? lC : 0.0) - C[a] * l[b] - lxu[a] * row[b]) * iL2;
  pom_v3_axpy(ldd, Cdd, -qb, u);
  pom_v3_cross(rod->alpha_bias, l, ldd);
  pom_v3_scale(rod->alpha_bias, iL2, rod->alpha_bias);
  rod->spin_free = 1;
  pom_v3_copy(rod->spin_axis, s);
  return 1;
}

/* One limit kind: the swing of each link from its home direction (the cone
 * its two ball joints must allow). */
static void radial_limit_values(const pom_kin_arch *arch, const double R[9], const double q[3],
                                double value[9]) {
  const radial_geom *g = POM_KIN_CDATA(radial_geom, arch);
  for (int i = 0; i < 3; ++i) {
    double C[3], B[3], l[3];
    pom_m3_apply(C, R, g->platform_pt[i]);
    pom_v3_axpy(B, g->slider_pt[i], q[i], g->slider_dir[i]);
    pom_v3_sub(l, C, B);
    value[i] = pom_kin_angle_between(l, g->rod_dir[i]);
    value[3 + i] = value[6 + i] = 0.0;
  }
}

/* Radius of the slider joints about z over the stroke: the outer end. */
static double radial_footprint(const pom_kin_arch *arch) {
  const radial_geom *g = POM_KIN_CDATA(radial_geom, arch);
  double r = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int s = -1; s <= 1; s += 2) {
      double p[3];
      pom_v3_axpy(p, g->slider_pt[i], 0.5 * s * arch->stroke, g->slider_dir[i]);
      r = fmax(r, hypot(p[0], p[1]));
    }
  return r;
}

static pom_status radial_mechanism(pom_mechanism *mech, const pom_kin_arch *arch,
                                   const pom_kin_inertia *in, pom_error *err) {
  const radial_geom *g = POM_KIN_CDATA(radial_geom, arch);
  const pom_kin_body_inertia *sl_in = &in->body[0], *rod_in = &in->body[1];
  (void)err;
  for (int i = 0; i < 3; ++i) {
    const double *B = g->slider_pt[i], *C = g->platform_pt[i], *u = g->slider_dir[i];
    double Q[9], cm[3];
    pom_kin_limb_axes(Q, u, g->radial[i], NULL);
    pom_v3_axpy(cm, B, sl_in->cm_offset, u);
    int slider = pom_kin_build_body(mech, "slider", i + 1, sl_in, Q, cm);
    pom_kin_limb_axes(Q, g->rod_dir[i], g->radial[i], NULL);
    for (int k = 0; k < 3; ++k)
      cm[k] = B[k] + rod_in->cm_fraction * (C[k] - B[k]);
    int rod = pom_kin_build_body(mech, "rod", i + 1, rod_in, Q, cm);
    int jp = pom_kin_build_joint(mech, "P", i + 1, POM_JOINT_PRISMATIC, 0, slider, B, u, NULL);
    pom_kin_build_actuator(mech, jp, slider, arch->stroke);
    pom_kin_build_joint(mech, "B", i + 1, POM_JOINT_SPHERICAL, slider, rod, B, NULL, NULL);
    pom_kin_build_joint(mech, "C", i + 1, POM_JOINT_SPHERICAL, rod, mech->platform, C, NULL, NULL);
  }
  return POM_OK;
}

static const pom_kin_arch_type radial_type = {
    .name = "3PSS-radial",
    .label = "3P(radial)-S-S/S",
    .description = "three horizontal radial linear actuators driving S-S links (test example)",
    .actuator = POM_ACT_PRISMATIC,
    .data_size = sizeof(radial_geom),
    .scale_key = "platform_radius_mm",
    .scale_meaning = "platform radius: distance of the platform points from the z axis",
    .scale_sets_kinematics = 1,
    .n_params = RP_COUNT,
    .params = radial_params,
    .n_points = 2,
    .points = radial_points,
    .limits = {{0},
               {"link cone", 0, 0, "link_cone_max_deg", "link_cone_deg", "deg", 1.0 / POM_DEG, 0.0,
                180.0, 0.5 * POM_PI, POM_KIN_LIMCLASS_CONE},
               {0},
               {0}},
    .default_stroke = 0.012,
    .n_inertia_bodies = 2,
    .inertia_bodies = radial_bodies,
    .unreachable = "the rod cannot reach the radial slider axis (no real IK root)",
    .from_design = radial_from_design,
    .finish = radial_finish,
    .limb = radial_limb,
    .limb_twist = radial_limb_twist,
    .limit_values = radial_limit_values,
    .footprint = radial_footprint,
    .mechanism = radial_mechanism,
};

/* ---- configuration ------------------------------------------------------------ */
/* High-entropy design: r = 12.385 mm, L = 2.385 r, lean 57.3 deg, twist
 * 137.5 deg (link leaning inward: the sliders sit 2.4 r out and 2.0 r down).
 * Rod moments axisymmetric so that the rigid formulation, which fixes the
 * idle rod spin, models the same physics as the parasitic one
 * (docs/dynamics-exact.md section 3). */
static const char *radial_cfg =
    "name = \"radial test\";\n"
    "architecture = \"3PSS-radial\";\n"
    "geometry = { mode = \"parameters\"; platform_radius_mm = 12.385;\n"
    "  rod_length = 2.385; link_lean_deg = 57.3; link_twist_deg = 137.5; };\n"
    "limits = { stroke_mm = 12.0; link_cone_max_deg = 35.0; };\n"
    "inertia = { gravity_mps2 = [0.0, 0.0, -9.81];\n"
    "  platform = { mass_kg = 2.93e-2; moments_kgm2 = [1.0e-6, 1.1e-6, 2.0e-6];\n"
    "               cm_mm = [0.0, 0.0, 0.0]; };\n"
    "  slider = { mass_kg = 1.3e-2; moments_kgm2 = [5.1e-7, 5.1e-7, 1.6e-7];\n"
    "             cm_offset_mm = 1.5; };\n"
    "  rod = { mass_kg = 3.94e-3; moments_kgm2 = [1.05e-6, 1.05e-6, 2.0e-7];\n"
    "          cm_fraction = 0.45; }; };\n";

/* Loads radial_cfg: arch, mechanism and dynamics parameters. */
static int load_radial(pom_kin_arch *arch, pom_mechanism *mech, pom_dyn_params *p) {
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_dyn_params_defaults(p);
  int ok = pom_cfg_load_string(&cfg, radial_cfg, "<radial>", &err) == POM_OK &&
           pom_kin_arch_load(arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_build(mech, arch, cfg, &err) == POM_OK &&
           pom_dyn_params_load(p, cfg, &err) == POM_OK;
  if (!ok) printf("  loading: %s\n", err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

/* ---- 1. registry ---------------------------------------------------------------- */
/* Registering grows the count by one and makes the name findable; the same
 * name again, an incomplete table, oversized private data and an actuator
 * kind that is not one are refused. */
static void test_register(void) {
  pom_error err;
  int n0 = pom_kin_arch_type_count();
  check_true(pom_kin_arch_type_find("3PSS-radial") == NULL);
  check_true(pom_kin_arch_register(&radial_type, &err) == POM_OK);
  check_true(pom_kin_arch_type_count() == n0 + 1);
  check_true(pom_kin_arch_type_find("3PSS-radial") == &radial_type);
  check_true(pom_kin_arch_type_at(n0) == &radial_type);
  check_true(pom_kin_arch_register(&radial_type, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "3PSS-radial") != NULL);

  static pom_kin_arch_type incomplete, fat, clash, unknown_kind;
  incomplete = radial_type;
  incomplete.name = "3PSS-radial-no-twist";
  incomplete.limb_twist = NULL;
  check_true(pom_kin_arch_register(&incomplete, &err) == POM_ERR_ARG);
  fat = radial_type;
  fat.name = "3PSS-radial-fat";
  fat.data_size = sizeof(((pom_kin_arch *)0)->data) + sizeof(double);
  check_true(pom_kin_arch_register(&fat, &err) == POM_ERR_ARG);
  clash = radial_type; /* another table, a built-in's name */
  clash.name = "3PSS";
  check_true(pom_kin_arch_register(&clash, &err) == POM_ERR_ARG);
  unknown_kind = radial_type;
  unknown_kind.name = "3PSS-radial-unknown-kind";
  unknown_kind.actuator = (pom_actuator_kind)POM_ACT_KINDS;
  check_true(pom_kin_arch_register(&unknown_kind, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "not a known kind") != NULL);
  check_true(pom_kin_arch_type_count() == n0 + 1);
  printf("registry: %d built-in + user types, 3PSS-radial at %d\n", n0 + 1, n0);
}

/* ---- 2. kinematics ---------------------------------------------------------------- */
/* Home: q = 0 (mid-stroke) exactly up to rounding; J against central
 * differences of IK along rotations exp(h [e_k]) R (h = 1e-6 rad: truncation
 * ~h^2 |q'''| ~ 1e-14 m, rounding ~1e-16 m / h = 1e-10 m/rad; tolerance
 * 1e-8 m/rad ~ 1e-6 of |J| ~ 1.5e-2 m/rad); IK -> FK round trip to 1e-10
 * rad (FK's residual tolerance 1e-12 m / smallest singular value). */
static void test_kinematics(const pom_kin_arch *a) {
  pom_error err;
  const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double q0[3], J[9];
  check_true(a->type == &radial_type);
  check_true(pom_kin_inverse(a, I, q0, &err) == POM_OK);
  for (int i = 0; i < 3; ++i)
    check_abs(q0[i], 0.0, 1e-15);
  /* the sliders lie on their radial axes, outside the platform */
  const double *B = pom_kin_arch_points(a, "slider_points_m");
  check_true(B != NULL && pom_kin_arch_points(a, "slider_axes") == NULL);
  check_true(hypot(B[0], B[1]) > 0.012385);

  const double poses[3][3] = {{0.0713, -0.0482, 0.0291}, {-0.1127, 0.0385, 0.0944}, {0, 0, 0}};
  double worst_fd = 0.0, worst_rt = 0.0, jmax = 0.0;
  for (int c = 0; c < 3; ++c) {
    double R[9], q[3];
    pom_euler_zyx_to_matrix(R, poses[c]);
    if (!check_true(pom_kin_inverse_jacobian(a, R, q, J, &err) == POM_OK)) continue;
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-6;
      double e[3] = {0, 0, 0}, E[9], Rp[9], Rm[9], qp[3], qm[3];
      e[k] = 1.0;
      pom_m3_axis_angle(E, e, h);
      pom_m3_mul(Rp, E, R);
      pom_m3_axis_angle(E, e, -h);
      pom_m3_mul(Rm, E, R);
      check_true(pom_kin_inverse(a, Rp, qp, NULL) == POM_OK);
      check_true(pom_kin_inverse(a, Rm, qm, NULL) == POM_OK);
      for (int i = 0; i < 3; ++i) {
        worst_fd = fmax(worst_fd, fabs((qp[i] - qm[i]) / (2.0 * h) - J[3 * i + k]));
        jmax = fmax(jmax, fabs(J[3 * i + k]));
      }
    }
    double Rf[9], D[9], rv[3];
    check_true(pom_kin_forward(a, q, NULL, NULL, Rf, NULL, &err) == POM_OK);
    pom_m3_mult(D, Rf, R);
    pom_m3_rotvec(rv, D);
    worst_rt = fmax(worst_rt, pom_v3_norm(rv));
  }
  check_abs(worst_fd, 0.0, 1e-8);
  check_abs(worst_rt, 0.0, 1e-10);
  /* the one limit kind is named and evaluated; kinds 2 and 3 are unused */
  char name[64];
  check_true(strcmp(pom_kin_limit_name(a, POM_KIN_LIM_CONE_BASE + 1, name, sizeof name),
                    "link cone limb 2") == 0);
  check_true(strcmp(pom_kin_limit_name(a, POM_KIN_LIM_CONE_PLATFORM, name, sizeof name), "?") == 0);
  pom_kin_pose pose;
  double R[9];
  pom_euler_zyx_to_matrix(R, poses[1]);
  check_true(pom_kin_pose_evaluate(a, R, &pose, NULL) == POM_OK);
  check_true(pose.limit[POM_KIN_LIM_CONE_BASE] > 0.0 && pose.limit[POM_KIN_LIM_CONE_BASE] < 0.6);
  printf("kinematics: |J| %.4g m/rad, J vs FD %.2g, IK->FK %.2g rad, link cone %.2f deg\n", jmax,
         worst_fd, worst_rt, pose.limit[POM_KIN_LIM_CONE_BASE] / POM_DEG);
}

/* ---- 3. mechanism ----------------------------------------------------------------- */
static void test_mechanism(const pom_mechanism *m) {
  check_true(m->n_bodies == 8);    /* ground, platform, 3 x (slider, rod) */
  check_true(m->n_joints == 10);   /* O, 3 x (P, B, C) */
  check_true(m->n_actuators == 3); /* on the prismatic joints */
  check_true(m->platform == 1);
  double mass = 0.0;
  for (int b = 0; b < m->n_bodies; ++b)
    mass += m->body[b].mass;
  check_rel(mass, 2.93e-2 + 3.0 * (1.3e-2 + 3.94e-3), 1e-14);
  for (int k = 0; k < 3; ++k) {
    const pom_mech_joint *j = &m->joint[m->actuator[k].joint];
    check_true(j->type == POM_JOINT_PRISMATIC && j->body[0] == 0);
    check_true(m->actuator[k].moving_body == 2 + 2 * k);
    check_abs(j->axis[2], 0.0, 0.0); /* horizontal slider */
  }
}

/* ---- 4. dynamics: both formulations ------------------------------------------------ */
/* A 20 ms maneuver to (1.7, -1.3, 0.9) mm on the parasitic path (k_p from
 * the defaults, 1e6 N/m) and the rigid path: both finish with status OK and
 * settled, with an energy audit closing to 1e-4 (local error ~rtol 1e-6
 * over ~900 steps; measured 1.6e-5 and 8.4e-6), and agree on the settling
 * times to 2e-2 relative (measured 4.0e-3). The tolerance: the parasitic
 * joints perturb the motion by O(1/k_p); test_dynamics_exact (test 5)
 * requires the settling-time error to fall >= 10x from k_p = 1e6 to 1e8 and
 * be <= 2e-3 at 1e8, so O(1e-2) is the expected size at 1e6. */
static void test_dynamics(const pom_kin_arch *a, const pom_mechanism *mech, pom_dyn_params p) {
  const double target[3] = {1.7e-3, -1.3e-3, 0.9e-3};
  const pom_joint_model models[2] = {POM_JOINTS_PARASITIC, POM_JOINTS_RIGID};
  pom_dyn_metrics mt[2];
  p.maneuver.horizon = 0.020;
  for (int c = 0; c < 2; ++c) {
    pom_dyn_model *m = NULL;
    pom_dyn_data *d = NULL;
    pom_error err;
    pom_error_clear(&err);
    memset(&mt[c], 0, sizeof mt[c]);
    p.joints.model = models[c];
    pom_status st = pom_dyn_model_create(&m, mech, a, &p, &err);
    if (st == POM_OK) st = pom_dyn_data_create(&d, m, &err);
    if (st == POM_OK) st = pom_dyn_simulate(m, d, target, &mt[c], NULL, &err);
    if (st != POM_OK) printf("  %s: %s\n", c ? "rigid" : "parasitic", err.message);
    check_true(st == POM_OK && mt[c].status == POM_OK);
    check_abs(mt[c].energy_balance_error, 0.0, 1e-4);
    for (int k = 0; k < 3; ++k)
      check_true(mt[c].settled[k]);
    printf("dynamics %s: execution %.4f ms, energy %.4g J, audit %.2g, %ld steps\n",
           c ? "rigid" : "parasitic", mt[c].execution_time * 1e3, mt[c].energy_total,
           mt[c].energy_balance_error, mt[c].steps);
    pom_dyn_data_destroy(d);
    pom_dyn_model_destroy(m);
  }
  double worst = 0.0;
  for (int k = 0; k < 3; ++k)
    worst =
        fmax(worst, fabs(mt[0].settling_time[k] - mt[1].settling_time[k]) / mt[1].settling_time[k]);
  check_abs(worst, 0.0, 2e-2);
  printf("dynamics: parasitic vs rigid settling times %.3g relative\n", worst);
}

/* ---- 5. drawn without drawing code (docs/view.md section 3) ------------------------ */
/* The type has no `shapes`: every moving body gets one derived from its joint
 * points: the platform a disc through C_i, the rods B_i -> C_i, the sliders
 * rods along their axes ending at B_i. */
static void test_shapes(const pom_kin_arch *a, const pom_mechanism *m) {
  pom_kin_shape s[POM_KIN_MAX_SHAPES];
  int n = 0;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_kin_body_shapes(a, m, s, POM_KIN_MAX_SHAPES, &n, &err) == POM_OK);
  check_true(n == m->n_bodies - 1);
  for (int k = 0; k < n; ++k) {
    check_true(s[k].body == k + 1);
    if (s[k].body == m->platform) {
      check_true(s[k].kind == POM_SHAPE_DISC);
      check_rel(s[k].radius, 12.385e-3, 1e-12);
    } else {
      double d[3];
      pom_v3_sub(d, s[k].to, s[k].from);
      check_true(s[k].kind == POM_SHAPE_SEGMENT && pom_v3_norm(d) > 1e-3 && s[k].radius > 0.0);
    }
  }
  check_true(pom_kin_body_shapes(a, m, s, 3, &n, &err) == POM_ERR_ARG);
}

/* Writes the pomlab view page of the radial architecture (tests/
 * test_view_browser.py --radial opens it in Chromium). */
static int view_html(const pom_kin_arch *a, const pom_mechanism *m, const char *path) {
  pom_view_page page;
  memset(&page, 0, sizeof page);
  page.title = "3PSS-radial (test architecture)";
  page.n_mechs = 1;
  page.mech[0].label = "radial test";
  page.mech[0].arch = a;
  page.mech[0].mech = m;
  double e[3] = {4.0 * POM_DEG, -3.0 * POM_DEG, 5.0 * POM_DEG};
  pom_euler_zyx_to_matrix(page.R, e);
  FILE *f = fopen(path, "w");
  pom_error err;
  pom_error_clear(&err);
  pom_status st = f ? pom_view_write(f, &page, &err) : POM_ERR_IO;
  if (f && fclose(f) != 0) st = POM_ERR_IO;
  if (st != POM_OK) printf("view: %s\n", f ? err.message : path);
  return st == POM_OK ? 0 : 1;
}

int main(int argc, char **argv) {
  test_register();
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!check_true(load_radial(&arch, &mech, &p))) return check_summary("test_arch_registry");
  if (argc == 3 && strcmp(argv[1], "--view-html") == 0) return view_html(&arch, &mech, argv[2]);
  test_shapes(&arch, &mech);
  test_kinematics(&arch);
  test_mechanism(&mech);
  test_dynamics(&arch, &mech, p);
  return check_summary("test_arch_registry");
}
