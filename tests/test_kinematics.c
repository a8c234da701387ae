/* test_kinematics.c - geometry loading, IK/FK, Jacobian, limits, workspace and
 * mechanism of both architectures (docs/kinematics.md). */
#include "check.h"
#include "kin_internal.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- access to the classic types' geometry through the public tables ------- */
#define PT(a, key) ((const double(*)[3])pom_kin_arch_points((a), (key)))
static int is_3pss(const pom_kin_arch *a) {
  return a->type == pom_kin_arch_type_find("3PSS");
}
/* the ground-side end of limb i at mid-stroke: 3PSS slider point B_i, 3SPS A_i */
static const double *limb_base(const pom_kin_arch *a, int i) {
  return is_3pss(a) ? PT(a, "slider_points_m")[i] : PT(a, "base_points_m")[i];
}
/* |C_i - B_i| (3PSS link) or |B_i - A_i| (3SPS mid-stroke limb) (m) */
static double limb_len(const pom_kin_arch *a, int i) {
  double d[3];
  pom_v3_sub(d, PT(a, "platform_points_m")[i], limb_base(a, i));
  return pom_v3_norm(d);
}
/* unit home limb direction, ground side -> platform */
static void limb_dir(const pom_kin_arch *a, int i, double out[3]) {
  pom_v3_sub(out, PT(a, "platform_points_m")[i], limb_base(a, i));
  pom_v3_normalize(out, out);
}

static const char *const kin_scopes[] = {"name",      "architecture", "geometry", "limits",
                                         "workspace", "inertia",      NULL};

/* ---- helpers --------------------------------------------------------------- */
static int load_file(pom_kin_arch *arch, const char *rel) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK && pom_kin_arch_load(arch, cfg, &err) == POM_OK;
  if (!ok) printf("loading %s: %s\n", rel, err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

/* Loads arch from config text; returns the status and leaves the message. */
static pom_status load_text(pom_kin_arch *arch, const char *text, pom_error *err) {
  pom_cfg *cfg = NULL;
  pom_error_clear(err);
  pom_status st = pom_cfg_load_string(&cfg, text, "<test>", err);
  if (st == POM_OK) st = pom_kin_arch_load(arch, cfg, err);
  if (st == POM_OK) {
    pom_kin_ws_opts o;
    st = pom_kin_ws_load(&o, cfg, err);
  }
  if (st == POM_OK && pom_cfg_has(cfg, "inertia")) {
    pom_kin_inertia in;
    st = pom_kin_inertia_load(&in, arch, cfg, err);
  }
  if (st == POM_OK) st = pom_cfg_check_unknown(cfg, kin_scopes, NULL, err);
  pom_cfg_destroy(cfg);
  return st;
}

static double rotation_angle_between(const double A[9], const double B[9]) {
  double D[9], rv[3];
  pom_m3_mult(D, A, B); /* A B^T */
  pom_m3_rotvec(rv, D);
  return pom_v3_norm(rv);
}

static void random_pose(pom_rng *rng, double R[9], double half_width) {
  double e[3];
  for (int k = 0; k < 3; ++k)
    e[k] = pom_rng_range(rng, -half_width, half_width);
  pom_euler_zyx_to_matrix(R, e);
}

/* ---- reference geometry ---------------------------------------------------- */
static void test_isotropic_home(const pom_kin_arch *arch) {
  double I[9], q[3], J[9], sv[3], kappa, dex;
  pom_m3_identity(I);
  check_true(pom_kin_inverse_jacobian(arch, I, q, J, NULL) == POM_OK);
  /* home = mid-stroke: q = 0 up to the rounding of |A + ...| - L (~1e-17 m) */
  for (int i = 0; i < 3; ++i)
    check_abs(q[i], 0.0, 1e-15);
  pom_kin_dexterity(J, sv, &kappa, &dex);
  /* The design is isotropic by construction (PARAMETERS §b); its angles are
   * given to 16 digits, so sigma = 15 mm and kappa = 1 hold to ~1e-15. */
  for (int k = 0; k < 3; ++k)
    check_rel(sv[k], 0.015, 1e-12);
  check_abs(kappa, 1.0, 1e-12);
  check_abs(dex, 1.0, 1e-12);
  /* PARAMETERS §b: row 1 of J at home = (0.012247, 0, 0.008660) m */
  check_abs(J[0], 0.015 / sqrt(1.5), 1e-15);
  check_abs(J[1], 0.0, 1e-15);
  check_abs(J[2], 0.015 / sqrt(3.0), 1e-15);
}

/* The explicit-points form of PARAMETERS §b tables (6 decimals in m) must give
 * the arch of the parameter form. Rounding: points 5e-7 m, directions 5e-6
 * times a length <= 0.11 m, so 1e-6 m; axes 5e-6 -> 1e-5. */
static void test_points_equal_parameters(const pom_kin_arch *p3, const pom_kin_arch *s3) {
  const char *pss = "architecture = \"3PSS\";\n"
                    "geometry = { mode = \"points\";\n"
                    "  platform_points_m = ( [0.0, 0.012247, 0.0], [-0.010607, -0.006124, 0.0],\n"
                    "                        [0.010607, -0.006124, 0.0] );\n"
                    "  slider_points_m = ( [0.022120, 0.000754, -0.031282],\n"
                    "     [-0.011713, 0.018780, -0.031282], [-0.010407, -0.019533, -0.031282] );\n"
                    "  slider_axes = ( [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0] ); };\n";
  const char *sps =
      "architecture = \"3SPS\";\n"
      "geometry = { mode = \"points\";\n"
      "  platform_points_m = ( [0.0, 0.015, 0.0], [-0.012990, -0.0075, 0.0],\n"
      "                        [0.012990, -0.0075, 0.0] );\n"
      "  base_points_m = ( [0.063509, 0.015000, -0.089815],\n"
      "     [-0.044745, 0.047500, -0.089815], [-0.018764, -0.062500, -0.089815] );\n"
      "  ujoint_axes = ( [0.0, -1.0, 0.0], [0.86603, 0.5, 0.0], [-0.86603, 0.5, 0.0] );\n"
      "};\n";
  pom_kin_arch a;
  pom_error err;
  check_true(load_text(&a, pss, &err) == POM_OK);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      double da[3], dp[3];
      limb_dir(&a, i, da);
      limb_dir(p3, i, dp);
      check_abs(PT(&a, "platform_points_m")[i][k], PT(p3, "platform_points_m")[i][k], 1e-6);
      check_abs(PT(&a, "slider_points_m")[i][k], PT(p3, "slider_points_m")[i][k], 1e-6);
      check_abs(PT(&a, "slider_axes")[i][k], PT(p3, "slider_axes")[i][k], 1e-15);
      check_abs(da[k], dp[k], 1e-4);
    }
  for (int i = 0; i < 3; ++i)
    check_abs(limb_len(&a, i), limb_len(p3, i), 1e-6);
  check_true(load_text(&a, sps, &err) == POM_OK);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      check_abs(PT(&a, "platform_points_m")[i][k], PT(s3, "platform_points_m")[i][k], 1e-6);
      check_abs(PT(&a, "base_points_m")[i][k], PT(s3, "base_points_m")[i][k], 1e-6);
      check_abs(PT(&a, "ujoint_axes")[i][k], PT(s3, "ujoint_axes")[i][k], 1e-5);
    }
    check_abs(limb_len(&a, i), limb_len(s3, i), 1e-6);
  }
  /* without ujoint_axes the default is unit(e_z x s) = the table's axes */
  const char *sps_default =
      "architecture = \"3SPS\";\n"
      "geometry = { mode = \"points\";\n"
      "  platform_points_m = ( [0.0, 0.015, 0.0], [-0.012990, -0.0075, 0.0],\n"
      "                        [0.012990, -0.0075, 0.0] );\n"
      "  base_points_m = ( [0.063509, 0.015000, -0.089815],\n"
      "     [-0.044745, 0.047500, -0.089815], [-0.018764, -0.062500, -0.089815] ); };\n";
  check_true(load_text(&a, sps_default, &err) == POM_OK);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      check_abs(PT(&a, "ujoint_axes")[i][k], PT(s3, "ujoint_axes")[i][k], 1e-5);
}

/* ---- Jacobian against central differences of the IK ------------------------ */
/* q(exp(+-eps e_k) R): the truncation error of the central difference is
 * eps^2/6 |q'''| <= 1e-10 * 0.11 m / 6 ~ 2e-12 m/rad, the rounding error
 * ~1e-17 m / eps = 1e-12 m/rad; J entries are ~1e-2 m/rad, so 1e-10 m/rad
 * absolute is a 1e-8 relative check with a margin of ~30. */
static void test_jacobian_fd(const pom_kin_arch *arch, pom_rng *rng) {
  const double eps = 1e-5;
  double worst = 0.0;
  int fails = 0;
  for (int n = 0; n < 300; ++n) {
    double R[9], q[3], J[9];
    random_pose(rng, R, 13.0 * POM_DEG);
    if (pom_kin_inverse_jacobian(arch, R, q, J, NULL) != POM_OK) {
      ++fails;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      double axis[3] = {0, 0, 0}, E[9], Rp[9], Rm[9], qp[3], qm[3];
      axis[k] = 1.0;
      pom_m3_axis_angle(E, axis, eps);
      pom_m3_mul(Rp, E, R);
      pom_m3_axis_angle(E, axis, -eps);
      pom_m3_mul(Rm, E, R);
      if (pom_kin_inverse(arch, Rp, qp, NULL) != POM_OK ||
          pom_kin_inverse(arch, Rm, qm, NULL) != POM_OK) {
        ++fails;
        continue;
      }
      for (int i = 0; i < 3; ++i)
        worst = fmax(worst, fabs((qp[i] - qm[i]) / (2.0 * eps) - J[3 * i + k]));
    }
  }
  check_true(fails == 0);
  check_abs(worst, 0.0, 1e-10);
  /* pom_kin_jacobian alone equals the combined call */
  double R[9], J1[9], J2[9], q[3];
  random_pose(rng, R, 10.0 * POM_DEG);
  check_true(pom_kin_jacobian(arch, R, J1, NULL) == POM_OK);
  check_true(pom_kin_inverse_jacobian(arch, R, q, J2, NULL) == POM_OK);
  for (int k = 0; k < 9; ++k)
    check_abs(J1[k], J2[k], 0.0);
}

/* ---- closed-form dexterity against the Jacobi SVD of core ------------------ */
/* Generic matrices: both are backward stable, eigenvalues of J^T J to
 * ~1e-15 sv0^2, so sv to ~1e-15 sv0^2 / sv2; with sv2/sv0 >= 1e-2 here,
 * 1e-11 sv0 has a margin of ~100. A double singular value makes the cubic's
 * root ill-conditioned: error ~sqrt(1e-16) = 1e-8 sv0 (documented bound). */
static void test_dexterity_closed_form(pom_rng *rng) {
  double worst = 0.0, worst_double = 0.0;
  for (int n = 0; n < 2000; ++n) {
    double U[9], V[9], D[9] = {0}, T[9], J[9], sv[3], ref[3], e[3];
    for (int k = 0; k < 3; ++k)
      e[k] = pom_rng_range(rng, -POM_PI, POM_PI);
    pom_euler_zyx_to_matrix(U, e);
    for (int k = 0; k < 3; ++k)
      e[k] = pom_rng_range(rng, -POM_PI, POM_PI);
    pom_euler_zyx_to_matrix(V, e);
    double a = pom_rng_range(rng, 0.01, 0.02), b = a * pom_rng_range(rng, 0.01, 1.0);
    double c = pom_rng_range(rng, b, a);
    int doubled = n % 2;
    D[0] = a;
    D[4] = doubled ? a : c;
    D[8] = b;
    pom_m3_mul(T, U, D);
    pom_m3_mult(J, T, V); /* U D V^T */
    pom_kin_dexterity(J, sv, NULL, NULL);
    pom_m3_singular_values(ref, J);
    for (int k = 0; k < 3; ++k) {
      double d = fabs(sv[k] - ref[k]) / ref[0];
      if (doubled) {
        worst_double = fmax(worst_double, d);
      } else {
        worst = fmax(worst, d);
      }
    }
  }
  check_abs(worst, 0.0, 1e-11);
  check_abs(worst_double, 0.0, 1e-7);
  double Z[9] = {0}, sv[3], kappa, dex;
  pom_kin_dexterity(Z, sv, &kappa, &dex);
  check_true(isinf(kappa) && dex == 0.0);
}

/* The dexterity floor's bound 3/kappa_F (docs/dynamics-exact.md section 3)
 * on J = U D V^T with known singular values a >= c >= b: kappa_F^2 =
 * (a^2 + b^2 + c^2)(1/a^2 + 1/b^2 + 1/c^2) exactly, and b/a <= 3/kappa_F <=
 * 3 b/a. Rounding: det and the cofactors are differences of products of
 * O(a) entries, so the relative error is ~eps a^2 / (b c) <= eps kappa_2^2:
 * 2e-6 at the b = 1e-5 a drawn here (the floor is 1e-3 by default). Own
 * stream, so the other tests' draws are unchanged. */
static void test_dexterity_bound(void) {
  pom_rng r;
  pom_rng *rng = &r;
  pom_rng_seed(rng, 2385, 7);
  double worst = 0.0, lo_ratio = INFINITY, hi_ratio = 0.0;
  for (int n = 0; n < 2000; ++n) {
    double U[9], V[9], D[9] = {0}, T[9], J[9], e[3];
    for (int k = 0; k < 3; ++k)
      e[k] = pom_rng_range(rng, -POM_PI, POM_PI);
    pom_euler_zyx_to_matrix(U, e);
    for (int k = 0; k < 3; ++k)
      e[k] = pom_rng_range(rng, -POM_PI, POM_PI);
    pom_euler_zyx_to_matrix(V, e);
    double a = pom_rng_range(rng, 0.01, 0.02), b = a * pow(10.0, pom_rng_range(rng, -5.0, 0.0));
    double c = pom_rng_range(rng, b, a);
    D[0] = a;
    D[4] = c;
    D[8] = b;
    pom_m3_mul(T, U, D);
    pom_m3_mult(J, T, V);
    double kf = sqrt((a * a + b * b + c * c) * (1 / (a * a) + 1 / (b * b) + 1 / (c * c)));
    double bound = pom_kin_dexterity_bound(J);
    worst = fmax(worst, fabs(bound * kf / 3.0 - 1.0));
    lo_ratio = fmin(lo_ratio, bound / (b / a));
    hi_ratio = fmax(hi_ratio, bound / (b / a));
  }
  check_abs(worst, 0.0, 1e-5);
  check_true(lo_ratio >= 1.0 - 1e-5 && hi_ratio <= 3.0 + 1e-5);
  /* the factor is 3 a / sqrt(a^2 + c^2) >= 3/sqrt(2) near a singularity
   * (b << c), 1 at isotropy: the draws span most of [1, 3] */
  check_true(lo_ratio < 1.1 && hi_ratio > 2.9);
  /* isotropic (a multiple of a rotation): exactly 1 up to rounding */
  double R[9], J[9], e[3] = {0.3817, -0.2385, 1.1731};
  pom_euler_zyx_to_matrix(R, e);
  for (int k = 0; k < 9; ++k)
    J[k] = 0.015 * R[k];
  check_abs(pom_kin_dexterity_bound(J), 1.0, 1e-14);
  /* singular: rank 2, rank 1, zero */
  double S2[9] = {0.01, 0.002, 0.0, 0.003, 0.012, 0.0, 0.004, 0.005, 0.0};
  double S1[9] = {0.01, 0.02, 0.03, 0.02, 0.04, 0.06, -0.01, -0.02, -0.03}, Z[9] = {0};
  check_true(pom_kin_dexterity_bound(S2) == 0.0);
  check_true(pom_kin_dexterity_bound(S1) == 0.0);
  check_true(pom_kin_dexterity_bound(Z) == 0.0);
}

/* ---- random designs: the formulas hold beyond the reference ----------------- */
/* Designs drawn over the ranges synthesis explores, tilted sliders and raised
 * platform points included; at poses within 8 deg of home that are
 * assemblable and not near-singular (1/kappa > 0.05), J must match central
 * differences (bound as in test_jacobian_fd, lengths <= 0.16 m) and FK must
 * return the pose (1e-12 m / sv_min with sv_min >= 0.05 * ~5 mm: 5e-9 rad). */
static void test_random_designs(pom_rng *rng) {
  int designs = 0, poses = 0;
  double worst_fd = 0.0, worst_rt = 0.0;
  for (int n = 0; n < 40; ++n) {
    const pom_kin_arch_type *type = pom_kin_arch_type_find(n % 2 ? "3SPS" : "3PSS");
    pom_kin_design d = {pom_rng_range(rng, 0.008, 0.02),
                        {pom_rng_range(rng, -POM_PI, POM_PI), pom_rng_range(rng, -0.3, 0.3),
                         pom_rng_range(rng, 2.0, 8.0), pom_rng_range(rng, 15.0, 60.0) * POM_DEG,
                         pom_rng_range(rng, 20.0, 160.0) * POM_DEG,
                         pom_rng_range(rng, 0.0, 20.0) * POM_DEG,
                         pom_rng_range(rng, -POM_PI, POM_PI)}};
    pom_kin_arch a;
    if (pom_kin_arch_from_design(&a, type, &d, NULL) != POM_OK) continue;
    ++designs;
    for (int k = 0; k < 10; ++k) {
      double R[9], q[3], J[9], dex, Rf[9];
      random_pose(rng, R, 8.0 * POM_DEG);
      if (pom_kin_inverse_jacobian(&a, R, q, J, NULL) != POM_OK) continue;
      pom_kin_dexterity(J, NULL, NULL, &dex);
      if (dex < 0.05) continue;
      ++poses;
      for (int c = 0; c < 3; ++c) {
        double axis[3] = {0, 0, 0}, E[9], Rp[9], Rm[9], qp[3], qm[3], eps = 1e-5;
        axis[c] = 1.0;
        pom_m3_axis_angle(E, axis, eps);
        pom_m3_mul(Rp, E, R);
        pom_m3_axis_angle(E, axis, -eps);
        pom_m3_mul(Rm, E, R);
        check_true(pom_kin_inverse(&a, Rp, qp, NULL) == POM_OK &&
                   pom_kin_inverse(&a, Rm, qm, NULL) == POM_OK);
        for (int i = 0; i < 3; ++i)
          worst_fd = fmax(worst_fd, fabs((qp[i] - qm[i]) / (2.0 * eps) - J[3 * i + c]));
      }
      /* continue from the home pose of this design */
      pom_status st = pom_kin_forward(&a, q, NULL, NULL, Rf, NULL, NULL);
      check_true(st == POM_OK);
      if (st == POM_OK) worst_rt = fmax(worst_rt, rotation_angle_between(R, Rf));
    }
  }
  check_true(designs >= 20 && poses >= 100);
  check_abs(worst_fd, 0.0, 1e-10);
  check_abs(worst_rt, 0.0, 5e-9);
}

/* ---- IK -> FK round trips ------------------------------------------------- */
/* FK stops at max |q(R) - q| <= 1e-12 m; with sv_min >= 0.3 * 15 mm in the
 * workspace the rotation error is <= 1e-12 / 4.5e-3 ~ 2e-10 rad; 1e-9 rad. */
static void test_round_trips(const pom_kin_arch *arch, pom_rng *rng, int n) {
  double worst = 0.0, worst_res = 0.0;
  int failures = 0, max_iter = 0;
  for (int k = 0; k < n; ++k) {
    double R[9], q[3], Rf[9];
    random_pose(rng, R, 13.0 * POM_DEG);
    if (pom_kin_inverse(arch, R, q, NULL) != POM_OK) {
      ++failures;
      continue;
    }
    pom_kin_fk_info info;
    pom_error err;
    pom_error_clear(&err);
    if (pom_kin_forward(arch, q, NULL, NULL, Rf, &info, &err) != POM_OK) {
      if (failures++ == 0) printf("round trip: %s\n", err.message);
      continue;
    }
    worst = fmax(worst, rotation_angle_between(R, Rf));
    worst_res = fmax(worst_res, info.residual);
    if (info.iterations > max_iter) max_iter = info.iterations;
  }
  check_true(failures == 0);
  check_abs(worst, 0.0, 1e-9);
  check_abs(worst_res, 0.0, 1e-12);
  /* Newton converges quadratically from home: a handful of iterations */
  check_true(max_iter <= 10);
}

/* The continuation path: starve direct Newton (2 iterations) so that FK must
 * continue along q(t); it must still land on the pose IK came from. */
static void test_continuation(const pom_kin_arch *arch) {
  double e[3] = {12.0 * POM_DEG, -11.0 * POM_DEG, 12.5 * POM_DEG}, R[9], q[3], Rf[9];
  pom_euler_zyx_to_matrix(R, e);
  check_true(pom_kin_inverse(arch, R, q, NULL) == POM_OK);
  pom_kin_fk_opts o;
  pom_kin_fk_defaults(&o);
  o.max_iterations = 2;
  pom_kin_fk_info info;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = pom_kin_forward(arch, q, NULL, &o, Rf, &info, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) printf("continuation: %s\n", err.message);
  check_true(info.continuation_steps > 0);
  check_abs(rotation_angle_between(R, Rf), 0.0, 1e-9);
  /* a q far outside anything reachable: reported, R untouched */
  double qbad[3] = {0.5, -0.5, 0.5}, Rb[9] = {7, 7, 7, 7, 7, 7, 7, 7, 7};
  st = pom_kin_forward(arch, qbad, NULL, NULL, Rb, &info, &err);
  check_true(st == POM_ERR_NOCONVERGE);
  check_true(strstr(err.message, "continuation stalled") != NULL);
  check_abs(Rb[0], 7.0, 0.0);
}

/* A solution across a singular surface (det J of the other sign) is another
 * assembly mode, never returned: FK started right on such a pose (zero
 * residual) must refuse it. The pose is found by a seeded random search over
 * all rotations. */
static void test_other_branch_refused(const pom_kin_arch *arch, pom_rng *rng) {
  double R[9], q[3], J[9], Rf[9] = {7, 7, 7, 7, 7, 7, 7, 7, 7};
  int found = 0;
  for (int n = 0; n < 10000 && !found; ++n) {
    double e[3] = {pom_rng_range(rng, -POM_PI, POM_PI), pom_rng_range(rng, -1.5, 1.5),
                   pom_rng_range(rng, -POM_PI, POM_PI)},
           sv[3];
    pom_euler_zyx_to_matrix(R, e);
    if (pom_kin_inverse_jacobian(arch, R, q, J, NULL) != POM_OK) continue;
    pom_kin_dexterity(J, sv, NULL, NULL);
    found = pom_m3_det(J) * arch->home_det_sign < 0.0 && sv[2] > 0.05 * sv[0];
  }
  check_true(found);
  if (!found) return;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_kin_forward(arch, q, R, NULL, Rf, NULL, &err) == POM_ERR_NOCONVERGE);
  check_true(strstr(err.message, "det J changed sign") != NULL);
  check_abs(Rf[0], 7.0, 0.0); /* untouched */
}

/* FK over the full-stroke joint cube (9^3 grid, +-6 mm): every q is solved
 * on the home branch, and the largest rotation, the largest cone angles and
 * the smallest dexterity
 * agree with the independent computation of PARAMETERS §b (3PSS: 50.5 deg,
 * 0.36; 3SPS: 49.1 deg, 0.40, quoted to 3 and 2 digits; tolerances = half a
 * unit of the last quoted digit, plus the grid effect 4e-4 measured between
 * 5^3 and 33^3 grids). */
static void test_full_stroke_fk(const pom_kin_arch *arch, double want_rot_deg, double want_dex) {
  double maxrot = 0.0, mindex = 1.0, worst_res = 0.0, maxcone[2] = {0.0, 0.0};
  int fails = 0;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int k = -4; k <= 4; ++k) {
        double q[3] = {1.5e-3 * i, 1.5e-3 * j, 1.5e-3 * k}, R[9], rv[3], qb[3];
        pom_kin_fk_info info;
        if (pom_kin_forward(arch, q, NULL, NULL, R, &info, NULL) != POM_OK) {
          ++fails;
          continue;
        }
        pom_kin_inverse(arch, R, qb, NULL);
        for (int m = 0; m < 3; ++m)
          worst_res = fmax(worst_res, fabs(qb[m] - q[m]));
        pom_m3_rotvec(rv, R);
        maxrot = fmax(maxrot, pom_v3_norm(rv));
        pom_kin_pose p;
        pom_kin_pose_evaluate(arch, R, &p, NULL);
        mindex = fmin(mindex, p.dexterity);
        for (int m = 0; m < 3; ++m) {
          maxcone[0] = fmax(maxcone[0], p.limit[POM_KIN_LIM_CONE_BASE + m]);
          maxcone[1] = fmax(maxcone[1], p.limit[POM_KIN_LIM_CONE_PLATFORM + m]);
        }
      }
  check_true(fails == 0);
  check_abs(worst_res, 0.0, 1e-12);
  check_abs(maxrot / POM_DEG, want_rot_deg, 0.05);
  check_abs(mindex, want_dex, 0.0055);
  /* Largest joint-cone angles (the corners of the cube dominate: a 25^3 grid
   * gives the same to 1e-3 deg). PARAMETERS §b: 3PSS 17.3 deg at the slider
   * joint and 51.6 deg at the platform joint (to 3 digits: 0.05 deg); 3SPS
   * "<= 7.5 deg" at the U joint (we get 5.85 deg) and 44.5 deg at the
   * platform (we get 44.32 deg, also with an independent Python computation,
   * so the reference figure carries a ~0.2 deg error: 0.3 deg allowed). The
   * base cone is in the fixed frame, the platform cone in the platform frame:
   * swapping the frames moves each maximum by > 10 deg. */
  if (is_3pss(arch)) {
    check_abs(maxcone[0] / POM_DEG, 17.3, 0.05);
    check_abs(maxcone[1] / POM_DEG, 51.6, 0.05);
  } else {
    check_true(maxcone[0] / POM_DEG <= 7.5);
    check_abs(maxcone[1] / POM_DEG, 44.5, 0.3);
  }
}

/* ---- reachability and limits ---------------------------------------------- */
static void test_out_of_stroke(const pom_kin_arch *arch) {
  /* 35 deg of pitch is beyond the single-axis range about y (29-30 deg with
   * the +-6 mm stroke, PARAMETERS §b); each stroke bit must agree with
   * |q_i| > 6 mm */
  double e[3] = {0.0, 35.0 * POM_DEG, 0.0}, R[9];
  pom_euler_zyx_to_matrix(R, e);
  pom_kin_pose p;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = pom_kin_pose_evaluate(arch, R, &p, &err);
  check_true(st == POM_ERR_LIMIT);
  check_true(p.reachable == 1);
  int over = 0;
  char nm[64];
  for (int i = 0; i < 3; ++i) {
    int bit = (p.violations >> (POM_KIN_LIM_STROKE + i)) & 1u;
    int truth = fabs(p.q[i]) > 0.006;
    check_true(bit == truth);
    over += truth;
    if (truth)
      check_true(strstr(err.message,
                        pom_kin_limit_name(arch, POM_KIN_LIM_STROKE + i, nm, sizeof nm)) != NULL);
  }
  check_true(over > 0);
  /* home is inside every limit */
  double I[9];
  pom_m3_identity(I);
  check_true(pom_kin_pose_evaluate(arch, I, &p, &err) == POM_OK);
  check_true(p.violations == 0);
}

static void test_cone_and_distance_limits(const pom_kin_arch *ref) {
  pom_kin_arch a = *ref;
  double e[3] = {0.0, 0.0, 8.0 * POM_DEG}, R[9];
  pom_euler_zyx_to_matrix(R, e);
  pom_kin_pose p;
  check_true(pom_kin_pose_evaluate(&a, R, &p, NULL) == POM_OK);
  /* Tighten the platform cone just below the largest angle: only that limb trips. */
  int imax = 0;
  for (int i = 1; i < 3; ++i)
    if (p.limit[POM_KIN_LIM_CONE_PLATFORM + i] > p.limit[POM_KIN_LIM_CONE_PLATFORM + imax])
      imax = i;
  a.limit_bound[2] = 0.999 * p.limit[POM_KIN_LIM_CONE_PLATFORM + imax];
  check_true(pom_kin_pose_evaluate(&a, R, &p, NULL) == POM_ERR_LIMIT);
  check_true((p.violations & (1u << (POM_KIN_LIM_CONE_PLATFORM + imax))) != 0);
  /* at home every cone angle is zero */
  double I[9];
  pom_m3_identity(I);
  pom_kin_pose_evaluate(ref, I, &p, NULL);
  for (int i = 0; i < 3; ++i) {
    check_abs(p.limit[POM_KIN_LIM_CONE_BASE + i], 0.0, 1e-7);
    check_abs(p.limit[POM_KIN_LIM_CONE_PLATFORM + i], 0.0, 1e-7);
  }
  /* distance limit: require more clearance than home has */
  a = *ref;
  a.limit_bound[3] = p.limit[POM_KIN_LIM_DISTANCE] * 1.001;
  check_true(pom_kin_pose_evaluate(&a, I, &p, NULL) == POM_ERR_LIMIT);
  check_true((p.violations & (7u << POM_KIN_LIM_DISTANCE)) == (7u << POM_KIN_LIM_DISTANCE));
  char buf[256];
  pom_kin_violations_text(&a, p.violations, buf, sizeof buf);
  check_true(strcmp(buf, "distance limbs 1-2, distance limbs 2-3, distance limbs 3-1") == 0);
}

/* A 3PSS with long, nearly horizontal links: tilting moves C_i out of the
 * link's reach of the vertical slider axis. For a vertical slider the IK has a
 * real root iff the horizontal distance from the slider axis to C_i is <= L. */
static void test_unreachable(void) {
  pom_kin_design d = {0.012, {0.5 * POM_PI, 0.0, 2.0, 80.0 * POM_DEG, 60.0 * POM_DEG, 0.0, 0.0}};
  pom_kin_arch a;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_kin_arch_from_design(&a, pom_kin_arch_type_find("3PSS"), &d, &err) == POM_OK);
  int found = 0;
  for (int deg = 1; deg <= 60 && !found; ++deg) {
    for (int ax = 0; ax < 3 && !found; ++ax) {
      double e[3] = {0, 0, 0}, R[9];
      e[ax] = deg * POM_DEG;
      pom_euler_zyx_to_matrix(R, e);
      pom_kin_pose p;
      pom_status st = pom_kin_pose_evaluate(&a, R, &p, &err);
      if (st != POM_ERR_UNREACHABLE) continue;
      found = 1;
      check_true(p.reachable == 0);
      int i = p.unreachable_limb;
      check_true(i >= 0 && i < 3);
      if (i < 0 || i > 2) break;
      double c[3];
      pom_m3_apply(c, R, PT(&a, "platform_points_m")[i]);
      double h =
          hypot(c[0] - PT(&a, "slider_points_m")[i][0], c[1] - PT(&a, "slider_points_m")[i][1]);
      check_true(h > limb_len(&a, i));
      char want[32];
      snprintf(want, sizeof want, "limb %d", i + 1);
      check_true(strstr(err.message, want) != NULL);
      double q[3] = {9, 9, 9};
      check_true(pom_kin_inverse(&a, R, q, NULL) == POM_ERR_UNREACHABLE);
      check_abs(q[0], 9.0, 0.0); /* untouched */
    }
  }
  check_true(found);
}

/* A NaN or Inf rotation is a non-finite input, not an unreachable pose. */
static void test_nonfinite(const pom_kin_arch *arch) {
  double R[9], q[3] = {9, 9, 9};
  pom_m3_identity(R);
  R[4] = NAN;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_kin_inverse(arch, R, q, &err) == POM_ERR_NONFINITE);
  check_true(strstr(err.message, "R[4]") != NULL);
  check_abs(q[0], 9.0, 0.0); /* untouched */
  pom_kin_pose p;
  R[4] = 1.0;
  R[0] = INFINITY;
  check_true(pom_kin_pose_evaluate(arch, R, &p, &err) == POM_ERR_NONFINITE);
  check_true(p.reachable == 0 && p.unreachable_limb == -1);
}

static void test_segment_distance(void) {
  double a0[3] = {-1, 0, 0}, a1[3] = {1, 0, 0};
  double b0[3] = {0, -1, 0.37}, b1[3] = {0, 1, 0.37};
  check_abs(pom_kin_segment_distance(a0, a1, b0, b1), 0.37, 1e-15);
  double c0[3] = {2, 1, 0}, c1[3] = {3, 1, 0}; /* endpoint pair (1,0,0)-(2,1,0) */
  check_abs(pom_kin_segment_distance(a0, a1, c0, c1), sqrt(2.0), 1e-15);
  double d0[3] = {-0.5, 0.25, 0}, d1[3] = {0.5, 0.25, 0}; /* parallel, overlapping */
  check_abs(pom_kin_segment_distance(a0, a1, d0, d1), 0.25, 1e-15);
}

/* Distance from p0 + s (p1 - p0) to the segment [q0, q1], exact for one s. */
static double point_segment_distance(const double p0[3], const double p1[3], double s,
                                     const double q0[3], const double q1[3]) {
  double x[3], d[3], r[3], w[3];
  for (int k = 0; k < 3; ++k)
    x[k] = p0[k] + s * (p1[k] - p0[k]);
  pom_v3_sub(d, q1, q0);
  pom_v3_sub(r, x, q0);
  double t = pom_v3_dot(d, r) / pom_v3_dot(d, d);
  t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
  for (int k = 0; k < 3; ++k)
    w[k] = r[k] - t * d[k];
  return pom_v3_norm(w);
}

/* Random segment pairs (some nearly parallel, many with the closest points
 * at ends) against an independent minimisation: the distance from a point of
 * segment 1 to segment 2 is convex in its parameter s, so a golden-section
 * search (120 steps: bracket 1e-25) finds the minimum; the value is flat
 * there, so for generic pairs both agree to rounding, ~1e-15 for unit
 * lengths (1e-12 allowed). For pairs at an angle ~1e-9 rad the closed form's
 * s comes from a ~1e-18 denominator: still a pair of segment points, so never
 * below the minimum, but up to ~angle x length = 1e-9 above it (measured
 * 1.1e-9; 5e-9 allowed; irrelevant for a clearance in mm). */
static void test_segment_distance_random(pom_rng *rng) {
  const double g = 0.5 * (sqrt(5.0) - 1.0);
  double worst = 0.0, worst_parallel = 0.0;
  for (int n = 0; n < 2000; ++n) {
    double p0[3], p1[3], q0[3], q1[3];
    for (int k = 0; k < 3; ++k) {
      p0[k] = pom_rng_range(rng, -1.0, 1.0);
      p1[k] = pom_rng_range(rng, -1.0, 1.0);
      q0[k] = pom_rng_range(rng, -1.0, 1.0);
      q1[k] = pom_rng_range(rng, -1.0, 1.0);
    }
    if (n % 4 == 0) /* nearly parallel: q1 - q0 = 0.7 (p1 - p0) + 1e-9 noise */
      for (int k = 0; k < 3; ++k)
        q1[k] = q0[k] + 0.7 * (p1[k] - p0[k]) + 1e-9 * pom_rng_range(rng, -1.0, 1.0);
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 120; ++it) {
      double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
      if (point_segment_distance(p0, p1, m1, q0, q1) < point_segment_distance(p0, p1, m2, q0, q1))
        hi = m2;
      else
        lo = m1;
    }
    double ref = point_segment_distance(p0, p1, 0.5 * (lo + hi), q0, q1);
    ref = fmin(ref, fmin(point_segment_distance(p0, p1, 0.0, q0, q1),
                         point_segment_distance(p0, p1, 1.0, q0, q1)));
    double got = pom_kin_segment_distance(p0, p1, q0, q1);
    if (n % 4 == 0) {
      worst_parallel = fmax(worst_parallel, fabs(got - ref));
      check_true(got >= ref - 1e-15);
    } else {
      worst = fmax(worst, fabs(got - ref));
    }
  }
  check_abs(worst, 0.0, 1e-12);
  check_abs(worst_parallel, 0.0, 5e-9);
}

/* ---- workspace ------------------------------------------------------------- */
static void test_workspace(const pom_kin_arch *arch, double want_half_width_deg) {
  pom_kin_ws_opts o;
  pom_kin_ws_defaults(&o);
  o.max_half_width = 30.0 * POM_DEG;
  pom_kin_ws_result r;
  check_true(pom_kin_workspace(arch, &o, &r, NULL) == POM_OK);
  /* PARAMETERS §b (independent Python computation): Euler-cube regular
   * workspace with the +-6 mm stroke = 13.0 deg (3PSS) and 13.5 deg (3SPS);
   * on a 1 deg grid both are 13 deg. */
  check_abs(r.half_width / POM_DEG, want_half_width_deg, 1e-9);
  check_true(!r.capped);
  check_true(r.min_dexterity >= o.dexterity_min);
  /* the reported failing pose lies on the next shell and really fails */
  double m = fmax(fabs(r.fail_euler[0]), fmax(fabs(r.fail_euler[1]), fabs(r.fail_euler[2])));
  check_abs(m, r.half_width + o.resolution, 1e-12);
  double R[9];
  pom_kin_pose p;
  pom_euler_zyx_to_matrix(R, r.fail_euler);
  check_true(pom_kin_pose_evaluate(arch, R, &p, NULL) != POM_OK || p.dexterity < o.dexterity_min);
  /* a pose count of exactly the (2k+1)^3 cube plus part of the next shell */
  long inner = (long)pow(2.0 * want_half_width_deg + 1.0, 3.0);
  check_true(r.poses > inner && r.poses <= (long)pow(2.0 * want_half_width_deg + 3.0, 3.0));

  /* GCI: the midpoint rule converges as h^2, so halving h divides the error
   * by 4: the ratio of successive differences must be near 4 (the kink of
   * 1/kappa at the isotropic home spoils the coarsest grids only; measured
   * 4.02 at 2/1/0.5 deg). The limit lies between the dexterity bounds. */
  double g1, g2, g3, f;
  double a = 10.0 * POM_DEG;
  check_true(pom_kin_gci(arch, a, 2.0 * POM_DEG, 1, &g1, &f, NULL) == POM_OK);
  check_true(pom_kin_gci(arch, a, 1.0 * POM_DEG, 1, &g2, &f, NULL) == POM_OK);
  check_true(pom_kin_gci(arch, a, 0.5 * POM_DEG, 1, &g3, &f, NULL) == POM_OK);
  double ratio = (g1 - g2) / (g2 - g3);
  check_true(ratio > 3.5 && ratio < 4.5);
  check_abs(f, 1.0, 0.0); /* the 10 deg cube lies inside the 13 deg RDW */
  check_true(g3 < 1.0 && g3 > r.min_dexterity);
  /* Without limits and with a high dexterity threshold the cube is limited
   * by dexterity: the first failing pose is below the threshold, the accepted
   * cube above it, and the cube is smaller than the stroke-limited one. */
  pom_kin_ws_opts od = o;
  od.check_limits = 0;
  od.dexterity_min = 0.9;
  pom_kin_ws_result rd;
  check_true(pom_kin_workspace(arch, &od, &rd, NULL) == POM_OK);
  check_true(rd.fail_status == POM_ERR_SINGULAR && rd.fail_dexterity < 0.9);
  check_true(rd.min_dexterity >= 0.9 && rd.half_width >= 0.0 && rd.half_width < r.half_width);
  pom_euler_zyx_to_matrix(R, rd.fail_euler);
  check_true(pom_kin_pose_evaluate(arch, R, &p, NULL) != POM_ERR_UNREACHABLE);
  check_abs(p.dexterity, rd.fail_dexterity, 0.0);
  /* a vanishing region is the isotropic home: GCI -> 1 */
  check_true(pom_kin_gci(arch, 0.0, 1.0 * POM_DEG, 1, &g1, NULL, NULL) == POM_OK);
  check_abs(g1, 1.0, 1e-12);
}

/* The pose budget: at a 0.01 deg step with max_poses = 1e4 the search may
 * run the cube up to shell 10 (21^3 = 9261 poses) but not 11 (23^3 = 12167),
 * so it stops with a half-width of 0.1 deg as a lower bound (the RDW is 13
 * deg). The progress callback sees every 4096th pose, bounded by the budget. */
typedef struct {
  long calls, last_done, bound;
} ws_progress_seen;

static void on_ws_progress(void *user, long done, long bound) {
  ws_progress_seen *s = user;
  ++s->calls;
  s->last_done = done;
  s->bound = bound;
}

static void test_workspace_budget(const pom_kin_arch *arch) {
  pom_kin_ws_opts o;
  pom_kin_ws_defaults(&o);
  o.resolution = 0.01 * POM_DEG;
  o.max_poses = 1e4;
  ws_progress_seen seen = {0, 0, 0};
  o.progress = on_ws_progress;
  o.progress_user = &seen;
  pom_kin_ws_result r;
  check_true(pom_kin_workspace(arch, &o, &r, NULL) == POM_OK);
  check_true(r.budget_reached && !r.capped);
  check_abs(r.half_width / POM_DEG, 0.1, 1e-12);
  check_true(r.poses == 9261);
  check_true(seen.calls == 2 && seen.last_done == 8192 && seen.bound == 10000);
  /* the grid sizes the CLI checks against the budget */
  check_abs(pom_kin_grid_poses(45.0 * POM_DEG, 1.0 * POM_DEG), 91.0 * 91.0 * 91.0, 0.0);
  check_abs(pom_kin_gci_poses(13.0 * POM_DEG, 1.0 * POM_DEG), 26.0 * 26.0 * 26.0, 0.0);
  /* the GCI tells its progress the same way: 26^3 = 17576 poses -> 4 calls */
  ws_progress_seen gseen = {0, 0, 0};
  double gci, frac;
  check_true(pom_kin_gci_progress(arch, 13.0 * POM_DEG, 1.0 * POM_DEG, 1, on_ws_progress, &gseen,
                                  &gci, &frac, NULL) == POM_OK);
  check_true(gseen.calls == 4 && gseen.last_done == 16384 && gseen.bound == 17576);
}

/* The GCI's measure cos(theta) dpsi dtheta dphi is dpsi du dphi with
 * u = sin(theta): an independent quadrature, midpoint rule with equal weights
 * in (psi, u, phi), must give the same mean. Both rules err by O(h^2); over
 * the +-25 deg cube (limits off, every pose assemblable) they agree to
 * 4e-6 at h = 1 deg (measured), while dropping the cos(theta) weight shifts the mean
 * by 1.7e-3 (3PSS and 3SPS alike): 2e-4 separates the two. */
static void test_gci_measure(const pom_kin_arch *arch) {
  const double a = 25.0 * POM_DEG, ua = sin(a);
  const int n = 50;
  int unreachable = 0;
  double gci, frac, sum = 0.0;
  check_true(pom_kin_gci(arch, a, 1.0 * POM_DEG, 0, &gci, &frac, NULL) == POM_OK);
  check_abs(frac, 1.0, 0.0);
  for (int j = 0; j < n; ++j) {
    double u = -ua + (j + 0.5) * 2.0 * ua / n;
    for (int i = 0; i < n; ++i)
      for (int l = 0; l < n; ++l) {
        double e[3] = {-a + (i + 0.5) * 2.0 * a / n, asin(u), -a + (l + 0.5) * 2.0 * a / n}, R[9];
        pom_euler_zyx_to_matrix(R, e);
        pom_kin_pose p;
        pom_kin_pose_evaluate(arch, R, &p, NULL);
        unreachable += !p.reachable;
        sum += p.dexterity;
      }
  }
  check_true(unreachable == 0);
  check_abs(gci, sum / ((double)n * n * n), 2e-4);
}

/* ---- mechanism ------------------------------------------------------------- */
static void test_mechanism(const char *rel, const pom_kin_arch *arch) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_cfg_load(&cfg, path, &err) == POM_OK);
  pom_mechanism m;
  pom_status st = pom_kin_mechanism_build(&m, arch, cfg, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) {
    printf("mechanism: %s\n", err.message);
    pom_cfg_destroy(cfg);
    return;
  }
  pom_kin_inertia in;
  check_true(pom_kin_inertia_load(&in, arch, cfg, &err) == POM_OK);
  pom_cfg_destroy(cfg);
  check_true(m.n_bodies == 8 && m.n_joints == 10 && m.n_actuators == 3);
  check_true(m.platform == 1);
  check_abs(m.gravity[2], -9.81, 0.0);
  double total = 0.0, want_total = in.platform.mass + 3.0 * in.body[0].mass + 3.0 * in.body[1].mass;
  for (int b = 0; b < m.n_bodies; ++b)
    total += m.body[b].mass;
  check_rel(total, want_total, 1e-15);
  for (int b = 1; b < m.n_bodies; ++b) {
    /* Q diag Q^T: symmetric, eigenvalues = the principal moments of that body
     * (bodies: 1 platform, then per limb i: 2 + 2i piston (3PSS) / cylinder
     * (3SPS), 3 + 2i link (3PSS) / piston (3SPS)) */
    const pom_kin_body_inertia *bi =
        b == 1 ? &in.platform : (b % 2 == 0 ? &in.body[0] : &in.body[1]);
    const double *I = m.body[b].inertia;
    check_abs(I[1] - I[3], 0.0, 0.0); /* symmetric by construction */
    check_abs(I[2] - I[6], 0.0, 0.0);
    check_abs(I[5] - I[7], 0.0, 0.0);
    check_rel(m.body[b].mass, bi->mass, 0.0);
    double w[3], V[9], want[3] = {bi->moments[0], bi->moments[1], bi->moments[2]};
    pom_m3_sym_eig(w, V, I);
    for (int x = 0; x < 2; ++x) /* sort descending */
      for (int y = x + 1; y < 3; ++y)
        if (want[y] > want[x]) {
          double t = want[x];
          want[x] = want[y];
          want[y] = t;
        }
    /* Jacobi eigenvalues: ~1e-15 relative to the largest */
    for (int k = 0; k < 3; ++k)
      check_abs(w[k], want[k], 1e-13 * want[0]);
  }
  int n_act = 0;
  for (int j = 0; j < m.n_joints; ++j) {
    const pom_mech_joint *jt = &m.joint[j];
    check_true(jt->body[0] >= 0 && jt->body[0] < m.n_bodies && jt->body[1] > 0 &&
               jt->body[1] < m.n_bodies && jt->body[0] != jt->body[1]);
    if (jt->type == POM_JOINT_PRISMATIC) {
      check_abs(pom_v3_norm(jt->axis), 1.0, 1e-15);
      check_true(jt->actuator >= 0);
      ++n_act;
    }
    if (jt->type == POM_JOINT_UNIVERSAL) {
      check_abs(pom_v3_dot(jt->axis, jt->axis2), 0.0, 1e-15);
      check_abs(pom_v3_norm(jt->axis2), 1.0, 1e-15);
    }
  }
  check_true(n_act == 3);
  /* limb bodies: the axial principal moment is about the limb direction */
  for (int i = 0; i < 3; ++i) {
    int b = is_3pss(arch) ? 3 + 2 * i : 2 + 2 * i; /* link i / cylinder i */
    const pom_kin_body_inertia *bi = is_3pss(arch) ? &in.body[1] : &in.body[0];
    double sdir[3];
    limb_dir(arch, i, sdir);
    double Is[3];
    pom_m3_apply(Is, m.body[b].inertia, sdir);
    for (int k = 0; k < 3; ++k)
      check_abs(Is[k], bi->moments[2] * sdir[k], 1e-18);
  }
  /* joints at the right places: last joint of each limb is at the platform point */
  for (int i = 0; i < 3; ++i) {
    const pom_mech_joint *jt = &m.joint[3 * (i + 1)]; /* O, then 3 joints per limb */
    check_true(jt->body[1] == m.platform);
    for (int k = 0; k < 3; ++k)
      check_abs(jt->point[k], PT(arch, "platform_points_m")[i][k], 0.0);
  }
}

/* Where the bodies and joints of one limb are, derived from the arch points
 * (which test_points_equal_parameters ties to the PARAMETERS §b tables) and
 * the shipped `inertia` offsets (PARAMETERS Appendix: 3SPS cylinder CM 35 mm
 * from A along the limb, piston CM 25 mm from B toward A; 3PSS piston at B,
 * link CM half-way). Positions are sums of a few products of numbers <= 0.2 m:
 * 1e-16 m of rounding, checked to 1e-15 m; unit-vector identities to 1e-15. */
static double dist3(const double a[3], const double b[3]) {
  double d[3];
  pom_v3_sub(d, a, b);
  return pom_v3_norm(d);
}

static void test_mechanism_geometry(const char *rel, const pom_kin_arch *arch) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_mechanism m;
  pom_kin_inertia in;
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_kin_inertia_load(&in, arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_build(&m, arch, cfg, &err) == POM_OK;
  pom_cfg_destroy(cfg);
  check_true(ok);
  if (!ok) {
    printf("mechanism geometry: %s\n", err.message);
    return;
  }
  const double ez[3] = {0.0, 0.0, 1.0};
  for (int i = 0; i < 3; ++i) {
    const int b0 = 2 + 2 * i, b1 = 3 + 2 * i; /* the two bodies of limb i */
    const pom_mech_joint *j0 = &m.joint[1 + 3 * i], *j1 = &m.joint[2 + 3 * i],
                         *j2 = &m.joint[3 + 3 * i];
    double s[3];
    limb_dir(arch, i, s);
    const double *P = PT(arch, "platform_points_m")[i];
    double want[3], v[3];
    if (!is_3pss(arch)) {
      const double *A = PT(arch, "base_points_m")[i];
      check_abs(in.body[0].cm_offset, 0.035, 1e-15);
      check_abs(in.body[1].cm_offset, 0.025, 1e-15);
      /* cylinder CM 35 mm from A along A->B; piston CM 25 mm from B toward A */
      pom_v3_axpy(want, A, 0.035, s);
      check_abs(dist3(m.body[b0].cm, want), 0.0, 1e-15);
      pom_v3_axpy(want, P, -0.025, s);
      check_abs(dist3(m.body[b1].cm, want), 0.0, 1e-15);
      /* U joint at A, ground-cylinder; axis 1 = unit(e_z x s) (fixed in the
       * ground, horizontal), axis 2 fixed in the cylinder, perpendicular to
       * axis 1 and to the limb, so that axis1 x axis2 = s: no spin about s */
      check_true(j0->type == POM_JOINT_UNIVERSAL && j0->body[0] == 0 && j0->body[1] == b0);
      check_abs(dist3(j0->point, A), 0.0, 0.0);
      pom_v3_cross(want, ez, s);
      pom_v3_normalize(want, want);
      check_abs(dist3(j0->axis, want), 0.0, 1e-15);
      check_abs(pom_v3_norm(j0->axis2), 1.0, 1e-15);
      check_abs(pom_v3_dot(j0->axis2, s), 0.0, 1e-15);
      pom_v3_cross(v, j0->axis, j0->axis2);
      check_abs(dist3(v, s), 0.0, 1e-15);
      /* the cylinder's transverse principal axis x is axis 1 */
      pom_m3_apply(v, m.body[b0].inertia, j0->axis);
      for (int k = 0; k < 3; ++k)
        check_abs(v[k], in.body[0].moments[0] * j0->axis[k], 1e-18);
      /* prismatic cylinder -> piston along s (positive = extension), a point
       * of its line A + t s, actuated, moving the piston */
      check_true(j1->type == POM_JOINT_PRISMATIC && j1->body[0] == b0 && j1->body[1] == b1);
      check_abs(dist3(j1->axis, s), 0.0, 1e-15);
      pom_v3_sub(v, j1->point, A);
      pom_v3_cross(want, v, s);
      check_abs(pom_v3_norm(want), 0.0, 1e-15);
      /* spherical piston-platform at B */
      check_true(j2->type == POM_JOINT_SPHERICAL && j2->body[0] == b1 && j2->body[1] == 1);
      check_abs(dist3(j2->point, P), 0.0, 0.0);
    } else {
      const double *B = PT(arch, "slider_points_m")[i], *d = PT(arch, "slider_axes")[i];
      check_abs(in.body[0].cm_offset, 0.0, 0.0);
      check_abs(in.body[1].cm_fraction, 0.5, 0.0);
      check_abs(dist3(m.body[b0].cm, B), 0.0, 1e-15);
      for (int k = 0; k < 3; ++k)
        want[k] = 0.5 * (B[k] + P[k]);
      check_abs(dist3(m.body[b1].cm, want), 0.0, 1e-15);
      /* prismatic ground -> piston along the (vertical) slider axis at B */
      check_true(j0->type == POM_JOINT_PRISMATIC && j0->body[0] == 0 && j0->body[1] == b0);
      check_abs(dist3(j0->axis, d), 0.0, 0.0);
      check_abs(dist3(j0->axis, ez), 0.0, 0.0);
      check_abs(dist3(j0->point, B), 0.0, 0.0);
      /* spherical piston-link at B, link-platform at C */
      check_true(j1->type == POM_JOINT_SPHERICAL && j1->body[0] == b0 && j1->body[1] == b1);
      check_abs(dist3(j1->point, B), 0.0, 0.0);
      check_true(j2->type == POM_JOINT_SPHERICAL && j2->body[0] == b1 && j2->body[1] == 1);
      check_abs(dist3(j2->point, P), 0.0, 0.0);
      /* the link's transverse principal axis x is unit(e_z x l) */
      pom_v3_cross(want, ez, s);
      pom_v3_normalize(want, want);
      pom_m3_apply(v, m.body[b1].inertia, want);
      for (int k = 0; k < 3; ++k)
        check_abs(v[k], in.body[1].moments[0] * want[k], 1e-18);
    }
    const pom_mech_joint *act = !is_3pss(arch) ? j1 : j0;
    check_true(act->actuator == i && m.actuator[i].joint == (int)(act - m.joint) &&
               m.actuator[i].moving_body == (!is_3pss(arch) ? b1 : b0));
    check_abs(m.actuator[i].stroke, 0.012, 0.0);
  }
  check_true(m.joint[0].type == POM_JOINT_SPHERICAL && m.joint[0].body[0] == 0 &&
             m.joint[0].body[1] == 1 && pom_v3_norm(m.joint[0].point) == 0.0);
}

/* ---- config errors --------------------------------------------------------- */
static void expect_config_error(const char *text, const char *key, const char *what) {
  pom_kin_arch a;
  pom_error err;
  pom_status st = load_text(&a, text, &err);
  int ok = st == POM_ERR_CONFIG && strstr(err.message, key) != NULL &&
           (what == NULL || strstr(err.message, what) != NULL);
  if (!ok)
    printf("expected config error naming '%s' (%s), got %d: %s\n", key, what ? what : "", (int)st,
           err.message);
  check_true(ok);
}

#define GEOM_3SPS                                                                                  \
  "geometry = { mode = \"parameters\"; platform_radius_mm = 15.0; limb_length = 7.3;"              \
  " limb_lean_deg = 35.0; limb_azimuth_deg = 90.0; };\n"

static void test_config_errors(void) {
  pom_kin_arch a;
  pom_error err;
  /* a minimal good config loads */
  check_true(load_text(&a, "architecture = \"3SPS\";\n" GEOM_3SPS, &err) == POM_OK);
  check_abs(a.stroke, 0.012, 0.0); /* default stroke */
  /* malformed */
  expect_config_error("architecture = \"3SPS\";\ngeometry = { mode = ;\n", "<test>:2", NULL);
  /* mistyped */
  expect_config_error("architecture = \"3SPS\";\n" GEOM_3SPS "limits = { stroke_mm = \"12\"; };\n",
                      "limits.stroke_mm", "expected a real number");
  expect_config_error("architecture = 3;\n" GEOM_3SPS, "architecture", "expected a string");
  /* out of range */
  expect_config_error("architecture = \"3SPS\";\n" GEOM_3SPS "limits = { stroke_mm = -3.0; };\n",
                      "limits.stroke_mm", "out of range");
  expect_config_error("architecture = \"3SPS\";\n" GEOM_3SPS
                      "workspace = { dexterity_min = 1.5; };\n",
                      "workspace.dexterity_min", "out of range");
  expect_config_error("architecture = \"3XYZ\";\n" GEOM_3SPS, "architecture",
                      "unknown architecture; registered: 3PSS, 3SPS, 3RRR");
  /* unknown keys */
  expect_config_error(
      "architecture = \"3SPS\";\n" GEOM_3SPS
      "limits = { stroke_mm = 12.0; cone_base_max_deg = 40.0; strok_mm = 12.0; };\n",
      "limits.strok_mm", "unknown key");
  expect_config_error("architecture = \"3SPS\";\n" GEOM_3SPS "limits = { strok_mm = 12.0; };\n",
                      "limits", "stroke_mm");
  expect_config_error("architecture = \"3SPS\";\n" GEOM_3SPS "workspace = { resolution = 1.0; };\n",
                      "workspace", "resolution_deg");
  expect_config_error("architecture = \"3SPS\";\n"
                      "geometry = { mode = \"parameters\"; platform_radius_mm = 15.0; "
                      "limb_length = 7.3; limb_lean_deg = 35.0; limb_azimuth_deg = 90.0; "
                      "actuator_tilt_deg = 3.0; };\n",
                      "geometry.actuator_tilt_deg", "unknown key");
  /* missing */
  expect_config_error("architecture = \"3SPS\";\n"
                      "geometry = { mode = \"parameters\"; limb_length = 7.3; "
                      "limb_lean_deg = 35.0; limb_azimuth_deg = 90.0; };\n",
                      "geometry.platform_radius_mm", "missing");
  /* wrong shape of a point list */
  expect_config_error("architecture = \"3SPS\";\ngeometry = { mode = \"points\";\n"
                      "  platform_points_m = ( [0.0, 0.015, 0.0], [-0.01299, -0.0075] );\n"
                      "  base_points_m = ( [0,0,-1], [0,0,-1], [0,0,-1] ); };\n",
                      "geometry.platform_points_m", "3 points");
  /* degenerate design: link perpendicular to the vertical slider */
  expect_config_error("architecture = \"3PSS\";\n"
                      "geometry = { mode = \"parameters\"; platform_radius_mm = 12.0; "
                      "limb_length = 3.0; limb_lean_deg = 90.0; limb_azimuth_deg = 60.0; };\n",
                      "geometry", "perpendicular");
  /* inertia: moments that no rigid body has */
  expect_config_error("architecture = \"3SPS\";\n" GEOM_3SPS
                      "inertia = { platform = { mass_kg = 0.03; moments_kgm2 = [1e-6, 1e-6, "
                      "5e-6]; };\n piston = { mass_kg = 0.016; moments_kgm2 = [3e-6, 3e-6, "
                      "5e-7]; };\n cylinder = { mass_kg = 0.448; moments_kgm2 = [2.2e-4, "
                      "2.2e-4, 1.31e-4]; }; };\n",
                      "inertia.platform.moments_kgm2", "principal moments");
  expect_config_error("architecture = \"3SPS\";\n" GEOM_3SPS
                      "inertia = { platform = { mass_kg = 0.03; moments_kgm2 = [1e-6, 1e-6, "
                      "2e-6]; };\n piston = { mass_kg = 0.016; moments_kgm2 = [3e-6, 3e-6, "
                      "5e-7]; };\n link = { mass_kg = 0.004; moments_kgm2 = [1e-6, 1e-6, "
                      "2e-7]; }; };\n",
                      "inertia.cylinder", "missing");
}

/* ---- body twists (exact dynamics) ------------------------------------------ */
/* Position of home point p of body b of a twist set. */
static void twist_point(double out[3], const pom_kin_body_twist *b, const double p[3]) {
  double d[3], r[3];
  pom_v3_sub(d, p, b->ref_home);
  pom_m3_apply(r, b->R, d);
  pom_v3_add(out, b->ref, r);
}

/* exp(t [w]) R: the platform after time t at constant angular velocity w. */
static void rotate_by(double out[9], const double w[3], double t, const double R[9]) {
  double n = pom_v3_norm(w), u[3], E[9];
  pom_v3_scale(u, 1.0 / n, w);
  pom_m3_axis_angle(E, u, n * t);
  pom_m3_mul(out, E, R);
}

/* Poses satisfy every joint of the mechanism; q and J equal the IK; twist maps
 * and velocity products equal central differences along R(t) = exp(t[w]) R
 * (constant w, so omega_dot = 0). Tolerances: central differences with
 * |w| h = 1e-6 rad (first) and 1e-4 rad (second) leave truncation ~1e-12 and
 * ~1e-8 relative (times the ratio of the fourth derivative to w^2 P, a few)
 * and rounding ~1e-10 and ~1e-8 relative (positions ~0.05 m): 1e-7 (first)
 * and 2e-7 (second differences) of the velocity/acceleration scale. */
static void test_body_twists(const char *rel, const pom_kin_arch *arch, pom_rng *rng) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_mechanism m;
  if (!check_true(pom_cfg_load(&cfg, path, &err) == POM_OK &&
                  pom_kin_mechanism_build(&m, arch, cfg, &err) == POM_OK)) {
    pom_cfg_destroy(cfg);
    return;
  }
  pom_cfg_destroy(cfg);
  double worst_joint = 0, worst_v = 0, worst_w = 0, worst_a = 0, worst_al = 0, worst_q = 0;
  for (int trial = 0; trial < 20; ++trial) {
    double R[9], w[3], q[3], J[9];
    random_pose(rng, R, 0.15);
    for (int k = 0; k < 3; ++k)
      w[k] = pom_rng_range(rng, -8.0, 8.0);
    double wn = pom_v3_norm(w);
    pom_kin_twists tw, tp, tm;
    if (!check_true(pom_kin_body_twists(arch, R, w, &tw, &err) == POM_OK)) return;
    check_true(tw.n_bodies == m.n_bodies);
    check_true(pom_kin_inverse_jacobian(arch, R, q, J, NULL) == POM_OK);
    for (int k = 0; k < 3; ++k)
      check_abs(tw.q[k], q[k], 1e-15);
    for (int k = 0; k < 9; ++k)
      check_abs(tw.J[k], J[k], 1e-15);
    /* joints */
    for (int j = 0; j < m.n_joints; ++j) {
      const pom_mech_joint *jt = &m.joint[j];
      const pom_kin_body_twist *b0 = &tw.body[jt->body[0]], *b1 = &tw.body[jt->body[1]];
      double p0[3], p1[3], dd[3];
      twist_point(p0, b0, jt->point);
      twist_point(p1, b1, jt->point);
      pom_v3_sub(dd, p1, p0);
      if (jt->type == POM_JOINT_PRISMATIC) {
        double a[3], lat[3], Rrel[9];
        pom_m3_apply(a, b0->R, jt->axis);
        double qa = pom_v3_dot(a, dd);
        pom_v3_axpy(lat, dd, -qa, a);
        worst_joint = fmax(worst_joint, pom_v3_norm(lat));
        if (jt->actuator >= 0) worst_joint = fmax(worst_joint, fabs(qa - tw.q[jt->actuator]));
        pom_m3_tmul(Rrel, b0->R, b1->R);
        Rrel[0] -= 1, Rrel[4] -= 1, Rrel[8] -= 1;
        for (int k = 0; k < 9; ++k)
          worst_joint = fmax(worst_joint, 0.05 * fabs(Rrel[k]));
      } else {
        worst_joint = fmax(worst_joint, pom_v3_norm(dd));
      }
      if (jt->type == POM_JOINT_UNIVERSAL) {
        double e[3], h[3];
        pom_m3_apply(e, b0->R, jt->axis);
        pom_m3_apply(h, b1->R, jt->axis2);
        worst_joint = fmax(worst_joint, 0.05 * fabs(pom_v3_dot(e, h)));
      }
    }
    /* first derivatives */
    double h1 = 1e-6 / wn, Rp[9], Rm[9];
    rotate_by(Rp, w, h1, R);
    rotate_by(Rm, w, -h1, R);
    check_true(pom_kin_body_twists(arch, Rp, w, &tp, NULL) == POM_OK);
    check_true(pom_kin_body_twists(arch, Rm, w, &tm, NULL) == POM_OK);
    double vscale = wn * 0.05, ascale = wn * wn * 0.05;
    for (int b = 1; b < m.n_bodies; ++b) {
      const pom_kin_body_twist *t = &tw.body[b];
      double pp[3], pm[3], r[3], d[3], v[3], wb[3], fd[3];
      twist_point(pp, &tp.body[b], m.body[b].cm);
      twist_point(pm, &tm.body[b], m.body[b].cm);
      pom_v3_sub(d, m.body[b].cm, t->ref_home);
      pom_m3_apply(r, t->R, d);
      pom_m3_apply(v, t->A, w);
      pom_m3_apply(wb, t->B, w);
      double wxr[3];
      pom_v3_cross(wxr, wb, r);
      pom_v3_add(v, v, wxr);
      for (int k = 0; k < 3; ++k)
        worst_v = fmax(worst_v, fabs((pp[k] - pm[k]) / (2 * h1) - v[k]) / vscale);
      double D[9], rv[3];
      pom_m3_mult(D, tp.body[b].R, tm.body[b].R);
      pom_m3_rotvec(rv, D);
      pom_v3_scale(fd, 1.0 / (2 * h1), rv);
      if (t->spin_free) { /* only the part across the idle spin axis is defined by R */
        pom_v3_axpy(fd, fd, -pom_v3_dot(fd, t->spin_axis), t->spin_axis);
        check_abs(pom_v3_dot(wb, t->spin_axis), 0.0, 1e-12 * wn);
      }
      for (int k = 0; k < 3; ++k)
        worst_w = fmax(worst_w, fabs(fd[k] - wb[k]) / wn);
      check_true(t->spin_free == (is_3pss(arch) && b >= 2 && b % 2 == 1));
    }
    /* second derivatives at omega_dot = 0 */
    double h2 = 1e-4 / wn;
    rotate_by(Rp, w, h2, R);
    rotate_by(Rm, w, -h2, R);
    check_true(pom_kin_body_twists(arch, Rp, w, &tp, NULL) == POM_OK);
    check_true(pom_kin_body_twists(arch, Rm, w, &tm, NULL) == POM_OK);
    for (int k = 0; k < 3; ++k)
      worst_q = fmax(worst_q,
                     fabs((tp.q[k] - 2 * tw.q[k] + tm.q[k]) / (h2 * h2) - tw.q_bias[k]) / ascale);
    for (int b = 1; b < m.n_bodies; ++b) {
      const pom_kin_body_twist *t = &tw.body[b];
      double pp[3], p0[3], pm[3], r[3], d[3], wb[3], a[3], tmp[3], wp[3], wm[3];
      twist_point(pp, &tp.body[b], m.body[b].cm);
      twist_point(p0, t, m.body[b].cm);
      twist_point(pm, &tm.body[b], m.body[b].cm);
      pom_v3_sub(d, m.body[b].cm, t->ref_home);
      pom_m3_apply(r, t->R, d);
      pom_m3_apply(wb, t->B, w);
      pom_v3_cross(tmp, t->alpha_bias, r);
      pom_v3_add(a, t->a_bias, tmp);
      double wxr[3], wwr[3];
      pom_v3_cross(wxr, wb, r);
      pom_v3_cross(wwr, wb, wxr);
      pom_v3_add(a, a, wwr);
      for (int k = 0; k < 3; ++k)
        worst_a = fmax(worst_a, fabs((pp[k] - 2 * p0[k] + pm[k]) / (h2 * h2) - a[k]) / ascale);
      pom_m3_apply(wp, tp.body[b].B, w);
      pom_m3_apply(wm, tm.body[b].B, w);
      for (int k = 0; k < 3; ++k)
        worst_al = fmax(worst_al, fabs((wp[k] - wm[k]) / (2 * h2) - t->alpha_bias[k]) / (wn * wn));
    }
  }
  check_abs(worst_joint, 0.0, 1e-13); /* m: exact geometry, rounding only */
  check_abs(worst_v, 0.0, 1e-7);
  check_abs(worst_w, 0.0, 1e-7);
  check_abs(worst_q, 0.0, 2e-7); /* second differences: observed ~5e-8 */
  check_abs(worst_a, 0.0, 2e-7);
  check_abs(worst_al, 0.0, 1e-7);
  printf("body twists %s: joints %.2g m, v %.2g, w %.2g, q_bias %.2g, a %.2g, alpha %.2g\n",
         arch->name, worst_joint, worst_v, worst_w, worst_q, worst_a, worst_al);
  /* failures: an unreachable pose names the limb; NULL omega gives zero biases */
  double Rbad[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  pom_kin_twists tw;
  check_true(pom_kin_body_twists(arch, Rbad, NULL, &tw, &err) == POM_OK);
  for (int b = 0; b < tw.n_bodies; ++b)
    check_abs(pom_v3_norm(tw.body[b].a_bias) + pom_v3_norm(tw.body[b].alpha_bias), 0.0, 0.0);
  Rbad[0] = NAN;
  check_true(pom_kin_body_twists(arch, Rbad, NULL, &tw, &err) == POM_ERR_NONFINITE);
  /* large rotations: wherever the IK fails the twists fail the same way */
  int unreachable = 0;
  for (int deg = 10; deg <= 360; deg += 10) {
    double e[3] = {0.0, 0.5 * deg * POM_DEG, deg * POM_DEG}, qq[3];
    pom_euler_zyx_to_matrix(Rbad, e);
    pom_status sk = pom_kin_inverse(arch, Rbad, qq, NULL);
    pom_status st = pom_kin_body_twists(arch, Rbad, NULL, &tw, &err);
    if (sk != POM_OK) {
      ++unreachable;
      check_true(st == sk && strstr(err.message, "limb") != NULL);
    }
  }
  if (!is_3pss(arch)) return;
  /* a 3PSS design with short, leaning links does become unreachable */
  pom_kin_design dz = {0.012, {0.5 * POM_PI, 0.0, 2.0, 80.0 * POM_DEG, 60.0 * POM_DEG, 0.0, 0.0}};
  pom_kin_arch a;
  check_true(pom_kin_arch_from_design(&a, pom_kin_arch_type_find("3PSS"), &dz, &err) == POM_OK);
  for (int deg = 1; deg <= 60 && !unreachable; ++deg) {
    double e[3] = {deg * POM_DEG, 0.0, 0.0}, qq[3];
    pom_euler_zyx_to_matrix(Rbad, e);
    pom_status sk = pom_kin_inverse(&a, Rbad, qq, NULL);
    pom_status st = pom_kin_body_twists(&a, Rbad, NULL, &tw, &err);
    if (sk != POM_OK) {
      ++unreachable;
      check_true(sk == POM_ERR_UNREACHABLE && st == sk && strstr(err.message, "limb") != NULL);
    }
  }
  check_true(unreachable > 0);
}

int main(void) {
  pom_kin_arch p3, s3;
  pom_rng rng;
  pom_rng_seed(&rng, 2385, 2);
  if (!load_file(&p3, "configs/3pss.cfg") || !load_file(&s3, "configs/3sps.cfg")) {
    check_true(0);
    return check_summary("test_kinematics");
  }
  check_true(is_3pss(&p3) && s3.type == pom_kin_arch_type_find("3SPS"));
  test_isotropic_home(&p3);
  test_isotropic_home(&s3);
  test_workspace_budget(&p3);
  test_points_equal_parameters(&p3, &s3);
  test_jacobian_fd(&p3, &rng);
  test_jacobian_fd(&s3, &rng);
  test_dexterity_closed_form(&rng);
  test_dexterity_bound();
  test_random_designs(&rng);
  test_round_trips(&p3, &rng, 3000);
  test_round_trips(&s3, &rng, 3000);
  test_full_stroke_fk(&p3, 50.5, 0.36);
  test_full_stroke_fk(&s3, 49.1, 0.40);
  test_continuation(&p3);
  test_continuation(&s3);
  test_other_branch_refused(&p3, &rng);
  test_other_branch_refused(&s3, &rng);
  test_out_of_stroke(&p3);
  test_out_of_stroke(&s3);
  test_cone_and_distance_limits(&p3);
  test_cone_and_distance_limits(&s3);
  test_unreachable();
  test_nonfinite(&p3);
  test_nonfinite(&s3);
  test_segment_distance();
  test_segment_distance_random(&rng);
  test_workspace(&p3, 13.0);
  test_workspace(&s3, 13.0);
  test_gci_measure(&p3);
  test_gci_measure(&s3);
  test_mechanism("configs/3pss.cfg", &p3);
  test_mechanism("configs/3sps.cfg", &s3);
  test_mechanism_geometry("configs/3pss.cfg", &p3);
  test_mechanism_geometry("configs/3sps.cfg", &s3);
  test_body_twists("configs/3pss.cfg", &p3, &rng);
  test_body_twists("configs/3sps.cfg", &s3, &rng);
  test_config_errors();
  return check_summary("test_kinematics");
}
