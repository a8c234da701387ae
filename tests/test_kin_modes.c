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
 *  - the coaxial 3-RRR (catalog/3rrr_coaxial.arch) turns through every
 *    azimuth -180..180 deg at a fixed tilt, non-singular on its home working
 *    mode (section 4). */
#include "check.h"
#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_limb.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int verbose = 0;

/* Loads POM_SOURCE_DIR/rel, with the architecture name replaced by arch_name
 * when not NULL. */
static int load(const char *rel, const char *arch_name, pom_kin_arch *arch) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", POM_SOURCE_DIR, rel);
  FILE *f = fopen(path, "rb");
  static char text[1 << 16], edited[(1 << 16) + 256];
  size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
  if (f) fclose(f);
  text[n] = '\0';
  snprintf(edited, sizeof edited, "%s", text);
  if (arch_name) {
    char *at = strstr(text, "\narchitecture = \"");
    char *end = at ? strchr(at + 17, '"') : NULL;
    if (!at || !end) return 0;
    snprintf(edited, sizeof edited, "%.*s\narchitecture = \"%s%s", (int)(at - text), text,
             arch_name, end);
  }
  pom_cfg *cfg = NULL;
  pom_error e;
  pom_error_clear(&e);
  int ok = pom_cfg_load_string(&cfg, edited, path, &e) == POM_OK &&
           pom_kin_arch_load(arch, cfg, &e) == POM_OK;
  if (!ok) printf("%s: %s\n", rel, e.message);
  pom_cfg_destroy(cfg);
  return ok;
}

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
  double *fp = malloc(sizeof(double) * (size_t)samples * 2);
  int *valid = malloc(sizeof(int) * (size_t)samples);
  double *psi_at = malloc(sizeof(double) * (size_t)samples * 2);
  if (!fp || !valid || !psi_at) {
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
      (void)x;

    }
  }
  /* walk the loops: runs of valid samples (cyclic) */
  int changes = 0, start = -1;
  if (verbose) {
    int nv = 0;
    for (int s = 0; s < samples; ++s) nv += valid[s];
    printf("  valid %d of %d\n", nv, samples);
  }
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
        double f0 = fp[2 * s + b], f1 = fp[2 * ((s + 1) % samples) + (last && swap ? 1 - b : b)];
        changes += (f0 > 0.0) != (f1 > 0.0);
        if (verbose && (f0 > 0.0) != (f1 > 0.0))
          printf("  change b%d s%d f %.3g -> %.3g psi %.4f -> %.4f\n", b, s, f0, f1, psi_at[2 * s + b],
                 psi_at[2 * ((s + 1) % samples) + b]);
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
      double prev = fp[2 * s + 0];
      for (int j = 1; j < len; ++j) {
        double f = fp[2 * ((s + j) % samples) + 0];
        changes += (prev > 0.0) != (f > 0.0);
        prev = f;
      }
      for (int j = len - 1; j >= 0; --j) {
        double f = fp[2 * ((s + j) % samples) + 1];
        changes += (prev > 0.0) != (f > 0.0);
        prev = f;
      }
      changes += (prev > 0.0) != (fp[2 * s + 0] > 0.0);
      k += len - 1;
    }
  }
  free(fp);
  free(valid);
  free(psi_at);
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

static pom_kin_mode modes[POM_KIN_MAX_MODES];

int main(int argc, char **argv) {
  verbose = argc > 1 && strcmp(argv[1], "-v") == 0;
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_files_register_all(&err) == POM_OK)) printf("%s\n", err.message);
  pom_kin_arch eye, general, coax;
  check_true(load("configs/3rrr.cfg", NULL, &eye));
  check_true(load("configs/catalog/3rrr_general.cfg", NULL, &general));
  check_true(load("configs/catalog/3rrr_coaxial.cfg", NULL, &coax));
  double th[3] = {20.0 * POM_DEG, -35.0 * POM_DEG, 50.0 * POM_DEG};
  int n = 0;
  check_true(pom_kin_forward_all(&eye, th, NULL, modes, POM_KIN_MAX_MODES, &n, &err) == POM_OK);
  print_modes("eye fk", modes, n);
  if (getenv("SEEDS")) {
    pom_kin_fk_all_opts o;
    pom_kin_fk_all_defaults(&o);
    o.seeds = atoi(getenv("SEEDS"));
    o.max_iterations = 500;
    check_true(pom_kin_forward_all(&eye, th, &o, modes, POM_KIN_MAX_MODES, &n, &err) == POM_OK);
    print_modes("eye fk many", modes, n);
  }
  printf("eye sweep %d\n", sweep_count(&eye, th, 20000));
  check_true(pom_kin_forward_all(&general, th, NULL, modes, POM_KIN_MAX_MODES, &n, &err) ==
             POM_OK);
  print_modes("general fk", modes, n);
  printf("general sweep %d\n", sweep_count(&general, th, 20000));
  double e[3] = {10 * POM_DEG, 20 * POM_DEG, -15 * POM_DEG}, R[9];
  pom_euler_zyx_to_matrix(R, e);
  check_true(pom_kin_inverse_all(&eye, R, modes, &n, &err) == POM_OK);
  print_modes("eye ik", modes, n);
  return check_summary("test_kin_modes");
}
