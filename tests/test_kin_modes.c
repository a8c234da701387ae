/* test_kin_modes.c - all solutions (kinematics/kin_modes.c,
 * docs/kinematics-modes.md): working modes (IK roots per limb) and assembly
 * modes (FK roots) against the published figures:
 *  - the Agile Eye (configs/3rrr.cfg, hand-coded 3RRR, and catalog/3rrr.arch):
 *    8 working modes at a generic orientation; 8 FK roots in SO(3) at a
 *    generic input, in 4 assembly modes up to the trivial symmetry (the
 *    platform turned half a turn about one of its own axes: Bonev, Chablat
 *    and Wenger, ICRA 2006; docs/kinematics-modes.md section 3);
 *  - the general 3-RRR (catalog/3rrr_general.arch): at most 8 FK roots
 *    (Gosselin, Sefrioui and Richard 1992);
 *  - completeness: for every 3-RRR input tested the number of FK roots the
 *    seeded Newton finds equals the number of sign changes of an independent
 *    one-dimensional sweep (section 2.3), which misses no simple root;
 *  - the Agile Eye reaches every orientation on its home working mode and
 *    det J never changes sign there (its singularities are curves, not
 *    surfaces), unlike the general 3-RRR (section 3);
 *  - the coaxial 3-RRR (catalog/3rrr_coaxial.arch) turns through every
 *    azimuth -180..180 deg at a fixed tilt, non-singular on its home working
 *    mode (section 4);
 *  - Orbita 3D's arm-angle limit (section 5). */
#include "check.h"
#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_limb.h"
#include "pom_math.h"
#include "pom_rng.h"
#include "catalog_test_util.h" /* after pom_kinematics.h */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int verbose = 0;

/* ---- the independent sweep (docs/kinematics-modes.md section 2.3) -------- */

/* u_i, w0_i (elbow at theta = 0) and v0_i (platform axis at home) of a
 * 3-RRR, hand-coded or a table. */
static int rrr_axes(const pom_kin_arch *a, double u[3][3], double w[3][3], double v[3][3]) {
  const double *pu = pom_kin_arch_points(a, "base_axes");
  const double *pw = pom_kin_arch_points(a, "elbow_axes");
  const double *pv = pom_kin_arch_points(a, "platform_axes");
  if (pu && pw && pv) {
    memcpy(u, pu, 9 * sizeof(double));
    memcpy(w, pw, 9 * sizeof(double));
    memcpy(v, pv, 9 * sizeof(double));
    return 1;
  }
  const pom_limb_table *t = POM_LIMB_CTABLE(a);
  for (int i = 0; i < 3; ++i) {
    if (t->limb[i].kernel != POM_LIMB_KERNEL_RRR) return 0;
    pom_v3_copy(u[i], t->limb[i].joint[0].axis);
    pom_v3_copy(w[i], t->limb[i].joint[1].axis);
    pom_v3_copy(v[i], t->limb[i].joint[2].axis);
  }
  return 1;
}

/* Rot(axis, t) x */
static void rot(double out[3], const double axis[3], double t, const double x[3]) {
  double R[9];
  pom_m3_axis_angle(R, axis, t);
  pom_m3_apply(out, R, x);
}

/* Number of real FK roots of a 3-RRR at theta: R(phi, psi) = Rot(w1, phi)
 * Rot(v1(0), psi) R0 covers SO(3) once with v1 = R v0_1 on the cone
 * w1 . v1 = cos a2; leg 2's constraint gives psi (two roots, A cos + B sin
 * + C = 0), leg 3's residual f is counted for sign changes along each closed
 * loop of the curve of leg 2's solutions. */
/* The roots the sweep found: the rotation at the sample of smaller |f| on
 * either side of a sign change (within pi / samples of the root in phi). */
#define SWEEP_MAX 16
static double sweep_R[SWEEP_MAX][9];
static double *Rs, *fp;
static int changed(int s0, int b0, int s1, int b1, int *changes) {
  double f0 = fp[2 * s0 + b0], f1 = fp[2 * s1 + b1];
  if ((f0 > 0.0) == (f1 > 0.0)) return 0;
  if (*changes < SWEEP_MAX) {
    /* linear interpolation on the geodesic between the two samples */
    const double *R0 = Rs + 9 * (2 * s0 + b0), *R1 = Rs + 9 * (2 * s1 + b1);
    double D[9], rv[3], E[9], t = f0 / (f0 - f1);
    pom_m3_tmul(D, R0, R1);
    pom_m3_rotvec(rv, D);
    double ang = pom_v3_norm(rv);
    if (ang > 0.0) {
      pom_v3_scale(rv, 1.0 / ang, rv);
      pom_m3_axis_angle(E, rv, t * ang);
      pom_m3_mul(sweep_R[*changes], R0, E);
    } else {
      memcpy(sweep_R[*changes], R0, 9 * sizeof(double));
    }
  }
  ++*changes;
  return 1;
}

static int sweep_count(const pom_kin_arch *a, const double theta[3], int samples) {
  double u[3][3], w0[3][3], v0[3][3], w[3][3], c[3];
  if (!rrr_axes(a, u, w0, v0)) return -1;
  for (int i = 0; i < 3; ++i) {
    c[i] = pom_v3_dot(w0[i], v0[i]);
    rot(w[i], u[i], theta[i], w0[i]);
  }
  /* R0: any rotation taking v0_1 to a point of leg 1's cone */
  double p[3], e[3], R0[9];
  pom_v3_cross(p, w[0], (double[3]){0.577, 0.211, -0.789});
  pom_v3_normalize(p, p);
  double s1 = sqrt(fmax(0.0, 1.0 - c[0] * c[0]));
  for (int k = 0; k < 3; ++k)
    e[k] = c[0] * w[0][k] + s1 * p[k];
  pom_kin_min_rotation(R0, v0[0], e);
  fp = malloc(sizeof(double) * (size_t)samples * 2);
  int *valid = malloc(sizeof(int) * (size_t)samples);
  double *psi_at = malloc(sizeof(double) * (size_t)samples * 2);
  Rs = malloc(sizeof(double) * (size_t)samples * 18);
  if (!fp || !valid || !psi_at || !Rs) {
    free(Rs);
    free(fp);
    free(psi_at);
    free(valid);
    return -1;
  }
  double psi_prev[2] = {0.0, 0.0};
  for (int s = 0; s < samples; ++s) {
    double phi = 2.0 * POM_PI * s / samples, P[9], Q[9], v1[3];
    pom_m3_axis_angle(P, w[0], phi);
    pom_m3_apply(v1, P, e);
    /* R = Rot(v1, psi) P R0: leg 2's v = Rot(v1, psi) y, y = P R0 v0_2 */
    double y[3], x[3];
    pom_m3_mul(Q, P, R0);
    pom_m3_apply(y, Q, v0[1]);
    /* Rot(v1, psi) y = cos psi (y - (v1.y) v1) + sin psi v1 x y + (v1.y) v1 */
    double yp[3], vxy[3], d = pom_v3_dot(v1, y);
    pom_v3_axpy(yp, y, -d, v1);
    pom_v3_cross(vxy, v1, y);
    double A = pom_v3_dot(w[1], yp), B = pom_v3_dot(w[1], vxy), C = d * pom_v3_dot(w[1], v1) - c[1];
    double rho = hypot(A, B);
    valid[s] = rho > 0.0 && fabs(C) <= rho;
    if (!valid[s]) continue;
    double base = atan2(B, A), ac = acos(-C / rho), ps[2] = {base + ac, base - ac};
    /* follow each branch by continuity: at a node of the curve (A = B = C
     * = 0, e.g. the Agile Eye's v1 = +-w2) atan2 jumps by pi and the
     * labels would swap */
    if (s > 0 && valid[s - 1]) {
      double d0 = fabs(remainder(ps[0] - psi_prev[0], 2.0 * POM_PI)) +
                  fabs(remainder(ps[1] - psi_prev[1], 2.0 * POM_PI));
      double d1 = fabs(remainder(ps[0] - psi_prev[1], 2.0 * POM_PI)) +
                  fabs(remainder(ps[1] - psi_prev[0], 2.0 * POM_PI));
      if (d1 < d0) {
        double t = ps[0];
        ps[0] = ps[1];
        ps[1] = t;
      }
    }
    psi_prev[0] = psi_at[2 * s] = ps[0];
    psi_prev[1] = psi_at[2 * s + 1] = ps[1];
    for (int b = 0; b < 2; ++b) {
      double psi = ps[b], Rv[9], R[9], z[3];
      pom_m3_axis_angle(Rv, v1, psi);
      pom_m3_mul(R, Rv, Q);
      pom_m3_apply(z, R, v0[2]);
      fp[2 * s + b] = pom_v3_dot(w[2], z) - c[2];
      memcpy(Rs + 9 * (2 * s + b), R, sizeof R);
      (void)x;
    }
  }
  /* walk the loops: runs of valid samples (cyclic) */
  int changes = 0, start = -1;

  for (int s = 0; s < samples; ++s)
    if (!valid[s]) start = s;
  if (start < 0) {
    /* the whole circle: two closed loops, one per branch, or one loop of
     * twice the length when the branches arrive swapped at phi = 2 pi */
    const double *pe = psi_at + 2 * (samples - 1);
    int swap = fabs(remainder(pe[0] - psi_at[1], 2.0 * POM_PI)) +
                   fabs(remainder(pe[1] - psi_at[0], 2.0 * POM_PI)) <
               fabs(remainder(pe[0] - psi_at[0], 2.0 * POM_PI)) +
                   fabs(remainder(pe[1] - psi_at[1], 2.0 * POM_PI));
    for (int b = 0; b < 2; ++b)
      for (int s = 0; s < samples; ++s) {
        int last = s == samples - 1;
        changed(s, b, (s + 1) % samples, last && swap ? 1 - b : b, &changes);
      }
  } else {
    for (int k = 1; k <= samples; ++k) {
      int s = (start + k) % samples;
      if (!valid[s]) continue;
      /* a run from s to t (valid), then back on the other branch */
      int t = s, len = 1;
      while (valid[(t + 1) % samples] && len < samples) {
        t = (t + 1) % samples;
        ++len;
      }
      int ps_ = s, pb = 0;
      for (int j = 1; j < len; ++j) {
        int sj = (s + j) % samples;
        changed(ps_, pb, sj, 0, &changes);
        ps_ = sj;
      }
      for (int j = len - 1; j >= 0; --j) {
        int sj = (s + j) % samples;
        changed(ps_, pb, sj, 1, &changes);
        ps_ = sj;
        pb = 1;
      }
      changed(ps_, pb, s, 0, &changes);
      k += len - 1;
    }
  }
  free(fp);
  free(valid);
  free(psi_at);
  free(Rs);
  return changes;
}

static void print_modes(const char *what, const pom_kin_mode *m, int n) {
  if (!verbose) return;
  printf("%s: %d\n", what, n);
  for (int k = 0; k < n; ++k) {
    double e[3], qt[4];
    pom_quat_from_matrix(qt, m[k].R);
    pom_quat_to_euler_zyx(e, qt);
    printf("  %2d euler %9.4f %9.4f %9.4f branch %+d%+d%+d q %9.4f %9.4f %9.4f det_unit %+.4f "
           "kappa %.4g serial %u parallel %d res %.2g st %d\n",
           k, e[0] / POM_DEG, e[1] / POM_DEG, e[2] / POM_DEG, m[k].branch[0], m[k].branch[1],
           m[k].branch[2], m[k].pose.q[0] / POM_DEG, m[k].pose.q[1] / POM_DEG,
           m[k].pose.q[2] / POM_DEG, m[k].det_unit, m[k].pose.kappa, m[k].serial, m[k].parallel,
           m[k].residual, (int)m[k].status);
  }
}

static pom_kin_mode modes[POM_KIN_MAX_MODES], modes2[POM_KIN_MAX_MODES];
static double worst_match = 0.0; /* largest sweep-to-Newton root distance (rad) */

static double rot_distance(const double A[9], const double B[9]) {
  double D[9], rv[3];
  pom_m3_tmul(D, A, B);
  pom_m3_rotvec(rv, D);
  return pom_v3_norm(rv);
}

/* A sweep root is degenerate when a leg's base and platform axes are
 * collinear there (u_i x R v0_i = 0: the leg's self-motion, its IK
 * undefined; docs/kinematics-modes.md section 3). Threshold 1e-2: the sweep
 * root is within pi / 20000 of the true one. */
static int degenerate(const pom_kin_arch *a, const double R[9]) {
  double u[3][3], w[3][3], v[3][3];
  rrr_axes(a, u, w, v);
  for (int i = 0; i < 3; ++i) {
    double x[3], c[3];
    pom_m3_apply(x, R, v[i]);
    pom_v3_cross(c, u[i], x);
    if (pom_v3_norm(c) < 1e-2) return 1;
  }
  return 0;
}

/* FK roots of a 3-RRR at theta against the sweep: every non-degenerate
 * sweep root within 2e-3 rad of a Newton root and as many of each; returns
 * the number of Newton roots (-1 when they disagree) and the degenerate
 * sweep roots in *n_deg. */
static int fk_checked(const char *what, const pom_kin_arch *a, const double th[3], int *n_deg) {
  int n = 0;
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_kin_forward_all(a, th, NULL, modes, POM_KIN_MAX_MODES, &n, &err) == POM_OK)) {
    printf("%s: %s\n", what, err.message);
    return -1;
  }
  int ns = sweep_count(a, th, 20000), nd = 0, ok = ns >= 0 && ns <= SWEEP_MAX;
  unsigned long long taken = 0;
  for (int k = 0; ok && k < ns; ++k) {
    if (degenerate(a, sweep_R[k])) {
      ++nd;
      continue;
    }
    /* its nearest Newton root, each taken once */
    int best = -1;
    double dbest = INFINITY;
    for (int j = 0; j < n; ++j) {
      double d = rot_distance(sweep_R[k], modes[j].R);
      if (d < dbest) {
        dbest = d;
        best = j;
      }
    }
    ok = best >= 0 && !(taken >> best & 1u) && dbest < 1e-3;
    if (best >= 0) taken |= 1u << best;
    worst_match = fmax(worst_match, dbest);
  }
  ok = ok && ns - nd == n;
  for (int j = 0; ok && j < n; ++j)
    ok = modes[j].residual <= 1e-12 && modes[j].pose.reachable && !modes[j].serial &&
         !modes[j].parallel;
  *n_deg = nd;
  if (!check_true(ok) || verbose) {
    printf("%s at theta (%.2f, %.2f, %.2f) deg: Newton %d roots, sweep %d sign changes (%d "
           "degenerate)\n",
           what, th[0] / POM_DEG, th[1] / POM_DEG, th[2] / POM_DEG, n, ns, nd);
    print_modes(what, modes, n);
  }
  return ok ? n : -1;
}

/* The Agile Eye: 8 working modes at generic orientations, the other root of
 * each leg at theta + 180 deg (u . w0 = 0 makes w(theta + pi) = -w(theta));
 * 4 assembly modes at generic inputs, R and R times a half-turn about each
 * platform axis (the same |det| and kappa), on 4 distinct working modes; 4
 * more roots of the sweep, degenerate (every leg's u_i parallel to v_i). */
static void test_agile_eye(const pom_kin_arch *eye, const pom_kin_arch *table, pom_rng *rng) {
  int n_ik = 0, n_fk = 0;
  for (int t = 0; t < 20; ++t) {
    double e[3], R[9];
    for (int k = 0; k < 3; ++k)
      e[k] = (2.0 * pom_rng_uniform(rng) - 1.0) * 40.0 * POM_DEG;
    pom_euler_zyx_to_matrix(R, e);
    int n = 0;
    check_true(pom_kin_inverse_all(eye, R, modes, &n, NULL) == POM_OK);
    int ok = n == 8;
    for (int k = 0; ok && k < n; ++k) {
      ok = modes[k].pose.reachable && !modes[k].serial;
      for (int i = 0; ok && i < 3; ++i) {
        double d = fabs(remainder(modes[k].pose.q[i] - modes[0].pose.q[i], 2.0 * POM_PI));
        ok = modes[k].branch[i] == modes[0].branch[i] ? d < 1e-12 : fabs(d - POM_PI) < 1e-12;
      }
    }
    n_ik += check_true(ok);
  }
  check_true(n_ik == 20);
  for (int t = 0; t < 10; ++t) {
    double th[3];
    for (int k = 0; k < 3; ++k)
      th[k] = (2.0 * pom_rng_uniform(rng) - 1.0) * 60.0 * POM_DEG;
    int nd = 0, n = fk_checked("Agile Eye", eye, th, &nd);
    if (!check_true(n == 4 && nd == 4)) continue;
    double u[3][3], w[3][3], v[3][3];
    rrr_axes(eye, u, w, v);
    int ok = 1;
    for (int j = 1; j < n; ++j) {
      /* R_j = R_0 Rot(v0_k, pi) for one k */
      double D[9], rv[3];
      pom_m3_tmul(D, modes[0].R, modes[j].R);
      pom_m3_rotvec(rv, D);
      double ang = pom_v3_norm(rv), best = 0.0;
      for (int k = 0; k < 3; ++k)
        best = fmax(best, fabs(pom_v3_dot(rv, v[k])) / ang);
      ok = ok && fabs(ang - POM_PI) < 1e-9 && best > 1.0 - 1e-9;
      ok = ok && fabs(fabs(modes[j].det_unit) - fabs(modes[0].det_unit)) < 1e-9;
      for (int i = 0; i < j; ++i)
        ok = ok && memcmp(modes[i].branch, modes[j].branch, sizeof modes[i].branch) != 0;
    }
    /* the table gives the same roots */
    int m = 0;
    check_true(pom_kin_forward_all(table, th, NULL, modes2, POM_KIN_MAX_MODES, &m, NULL) == POM_OK);
    ok = ok && m == n;
    for (int j = 0; ok && j < n; ++j)
      ok = rot_distance(modes[j].R, modes2[j].R) < 1e-9 &&
           memcmp(modes[j].branch, modes2[j].branch, sizeof modes[j].branch) == 0;
    n_fk += check_true(ok);
  }
  check_true(n_fk == 10);
  if (verbose)
    printf("Agile Eye: 8 working modes at 20 orientations, 4 assembly modes at %d inputs\n", n_fk);
}

/* The general 3-RRR: at most 8 FK roots, all found (the sweep), even in
 * number (the real roots of a real polynomial of degree 8 at a generic
 * input). */
static void test_general(const pom_kin_arch *g, pom_rng *rng) {
  int hist[9] = {0};
  for (int t = 0; t < 30; ++t) {
    double th[3];
    for (int k = 0; k < 3; ++k)
      th[k] = (2.0 * pom_rng_uniform(rng) - 1.0) * 90.0 * POM_DEG;
    int nd = 0, n = fk_checked("general 3-RRR", g, th, &nd);
    if (check_true(n >= 0 && n <= 8 && n % 2 == 0 && nd == 0)) ++hist[n];
  }
  if (verbose)
    printf("general 3-RRR, FK roots at 30 inputs: 0:%d 2:%d 4:%d 6:%d 8:%d\n", hist[0], hist[2],
           hist[4], hist[6], hist[8]);
}

/* Pointing at azimuth phi and tilt tau with zero torsion: R = Rz(phi)
 * Ry(tau) Rz(-phi) (tilt-and-torsion angles, docs/kinematics-modes.md
 * section 4), or with spin R = Rz(phi) Ry(tau) (the platform turns with
 * the azimuth: each actuator one full turn). Over phi = -180..180 deg in 0.5 deg steps on the home
 * working mode: every pose reachable, no leg singular, |det_unit| >= floor with one sign; returns
 * the smallest |det_unit| (0 when a pose fails) and the actuator travel of limb 1 (unwrapped, deg)
 * in *travel. */
static double azimuth_sweep(const pom_kin_arch *a, double tilt, int spin, double *travel) {
  double worst = INFINITY, sign = 0.0, q_prev = 0.0, path = 0.0;
  for (int k = -360; k <= 360; ++k) {
    double phi = 0.5 * k * POM_DEG, A[9], B[9], C[9], T[9], R[9];
    pom_m3_axis_angle(A, (double[3]){0, 0, 1}, phi);
    pom_m3_axis_angle(B, (double[3]){0, 1, 0}, tilt);
    pom_m3_axis_angle(C, (double[3]){0, 0, 1}, spin ? 0.0 : -phi);
    pom_m3_mul(T, A, B);
    pom_m3_mul(R, T, C);
    int n = 0;
    if (pom_kin_inverse_all(a, R, modes, &n, NULL) != POM_OK || n < 1) return 0.0;
    const pom_kin_mode *m = &modes[0]; /* the home working mode (+1, +1, +1) */
    if (!m->pose.reachable || m->serial || m->parallel) return 0.0;
    if (sign == 0.0) sign = m->det_unit > 0.0 ? 1.0 : -1.0;
    if (m->det_unit * sign <= 0.0) return 0.0;
    worst = fmin(worst, fabs(m->det_unit));
    if (k > -360) path += remainder(m->pose.q[0] - q_prev, 2.0 * POM_PI);
    q_prev = m->pose.q[0];
  }
  *travel = path / POM_DEG;
  return worst;
}

/* Orbita 3D's arm-angle limit (catalog/orbita3d.arch, measure "arm_angle",
 * docs/architecture-files.md 2.6): at random reachable orientations the
 * values are the angles between successive arms, 120 deg + q_i - q_(i+1)
 * mod 360 (docs/catalog.md C06: the arms are 120 deg apart at home and arm i
 * turns by -q_i about +z), to 1e-9 rad; the "min" bit is set exactly when a
 * value is below 40 deg, the "max" bit exactly when above 175 deg; both
 * occur, and poses inside both bounds occur. */
static void test_orbita_arm_angle(const pom_kin_arch *orb, pom_rng *rng) {
  int kmin = 0, kmax = 0;
  for (int k = 1; k < POM_KIN_LIM_KINDS; ++k) {
    const char *nm = orb->type->limits[k].name;
    if (nm && strcmp(nm, "arm angle min") == 0) kmin = k;
    if (nm && strcmp(nm, "arm angle max") == 0) kmax = k;
  }
  if (!check_true(kmin > 0 && kmax > 0)) return;
  check_abs(orb->limit_bound[kmin] / POM_DEG, 40.0, 1e-12);
  check_abs(orb->limit_bound[kmax] / POM_DEG, 175.0, 1e-12);
  int n_low = 0, n_high = 0, n_in = 0, bad = 0;
  for (int t = 0; t < 4000; ++t) {
    double e[3] = {(2.0 * pom_rng_uniform(rng) - 1.0) * 180.0 * POM_DEG,
                   (2.0 * pom_rng_uniform(rng) - 1.0) * 70.0 * POM_DEG,
                   (2.0 * pom_rng_uniform(rng) - 1.0) * 70.0 * POM_DEG},
           R[9];
    pom_euler_zyx_to_matrix(R, e);
    pom_kin_pose p;
    pom_kin_pose_evaluate(orb, R, &p, NULL);
    if (!p.reachable) continue;
    int low = 0, high = 0;
    for (int i = 0; i < 3; ++i) {
      double want = 120.0 * POM_DEG + p.q[i] - p.q[(i + 1) % 3];
      want -= 2.0 * POM_PI * floor(want / (2.0 * POM_PI));
      double vmin = p.limit[3 * kmin + i], vmax = p.limit[3 * kmax + i];
      bad += fabs(remainder(vmin - want, 2.0 * POM_PI)) > 1e-9 || vmax != vmin;
      int lo = vmin<40.0 * POM_DEG, hi = vmax> 175.0 * POM_DEG;
      bad += lo != (int)(p.violations >> (3 * kmin + i) & 1u);
      bad += hi != (int)(p.violations >> (3 * kmax + i) & 1u);
      low |= lo;
      high |= hi;
    }
    n_low += low;
    n_high += high;
    n_in += !low && !high;
  }
  check_true(bad == 0);
  check_true(n_low > 0 && n_high > 0 && n_in > 0);
  if (verbose)
    printf("Orbita arm angle: %d poses below 40 deg, %d above 175 deg, %d inside; %d wrong\n",
           n_low, n_high, n_in, bad);
}

/* Sign of det_unit on the home working mode over random rotations (uniform
 * quaternions): counts of each sign and the smallest |det_unit| seen. */
static void det_signs(const pom_kin_arch *a, pom_rng *rng, int n, int *pos, int *neg,
                      double *smallest) {
  *pos = *neg = 0;
  *smallest = INFINITY;
  for (int t = 0; t < n; ++t) {
    double q[4], R[9], s2 = 0.0;
    for (int k = 0; k < 4; ++k) {
      /* Gaussian by Box-Muller: uniform over the sphere of quaternions */
      double u1 = pom_rng_uniform(rng), u2 = pom_rng_uniform(rng);
      q[k] = sqrt(-2.0 * log(u1 > 0.0 ? u1 : 1e-300)) * cos(2.0 * POM_PI * u2);
      s2 += q[k] * q[k];
    }
    for (int k = 0; k < 4; ++k)
      q[k] /= sqrt(s2);
    pom_quat_to_matrix(R, q);
    int nm = 0;
    if (pom_kin_inverse_all(a, R, modes, &nm, NULL) != POM_OK || !modes[0].pose.reachable) continue;
    if (modes[0].det_unit > 0.0) ++*pos;
    if (modes[0].det_unit < 0.0) ++*neg;
    *smallest = fmin(*smallest, fabs(modes[0].det_unit));
  }
}

int main(int argc, char **argv) {
  verbose = argc > 1 && strcmp(argv[1], "-v") == 0;
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_files_register_all(&err) == POM_OK)) printf("%s\n", err.message);
  pom_kin_arch eye, general, coax;
  check_true(load_config_arch("configs/3rrr.cfg", NULL, &eye));
  check_true(load_config_arch("configs/catalog/3rrr_general.cfg", NULL, &general));
  check_true(load_config_arch("configs/catalog/3rrr_coaxial.cfg", NULL, &coax));
  pom_kin_arch orbita;
  check_true(load_config_arch("configs/catalog/orbita3d.cfg", NULL, &orbita));
  pom_kin_arch eye_table;
  check_true(load_config_arch("configs/3rrr.cfg", "3RRR-table", &eye_table));
  pom_rng rng;
  pom_rng_seed(&rng, 27u, 5u);
  test_agile_eye(&eye, &eye_table, &rng);
  test_general(&general, &rng);
  test_orbita_arm_angle(&orbita, &rng);
  /* the Agile Eye's singularities are curves, not surfaces (Bonev, Chablat
   * and Wenger): on its home working mode every orientation is reachable and
   * det_unit never changes sign (it touches 0 on the curves only); the
   * general 3-RRR's parallel singularities are surfaces, crossed: both signs */
  int pos = 0, neg = 0;
  double sm = 0.0;
  det_signs(&eye, &rng, 20000, &pos, &neg, &sm);
  check_true(pos == 0 && neg == 20000);
  if (verbose) printf("Agile Eye det_unit: + %d, - %d, min |det_unit| %.3g\n", pos, neg, sm);
  det_signs(&general, &rng, 20000, &pos, &neg, &sm);
  check_true(pos > 0 && neg > 0);
  if (verbose) printf("general 3-RRR det_unit: + %d, - %d, min |det_unit| %.3g\n", pos, neg, sm);
  if (verbose) printf("sweep roots within %.3g rad of the Newton roots\n", worst_match);
  /* the coaxial 3-RRR at 20 deg tilt: pointing at every azimuth with the
   * torsion held (the actuators swing back: no net travel), and turning
   * with it (each actuator one full turn); home |det_unit| = 0.992, 0.895
   * measured at worst, bound 0.5 */
  double travel = NAN;
  check_true(azimuth_sweep(&coax, 20.0 * POM_DEG, 0, &travel) >= 0.5);
  check_abs(travel, 0.0, 1e-9);
  check_true(azimuth_sweep(&coax, 20.0 * POM_DEG, 1, &travel) >= 0.5);
  check_abs(fabs(travel), 360.0, 1e-9);
  if (verbose)
    for (int t = 18; t <= 26; ++t) {
      double tr = 0.0, w0 = azimuth_sweep(&coax, t * POM_DEG, 0, &tr),
             w1 = azimuth_sweep(&coax, t * POM_DEG, 1, &tr);
      printf("coaxial tilt %d deg: min |det_unit| pointing %.4f, turning %.4f\n", t, w0, w1);
    }
  return check_summary("test_kin_modes");
}
