/* test_kin_twist_diff_sps_rrr.c - second-order kinematics of the 3S-P-S/S and
 * the 3-RRR (the type op limb_twist_diff, docs/dynamics-exact.md section 2,
 * "Second-order kinematics"): every field it differentiates against central
 * differences of limb_twist, its *out against limb_twist's bit for bit, and
 * the fields it must leave alone.
 *
 * Tolerances. Rotation derivatives: step h = 5e-6 rad about each fixed axis
 * (near eps^(1/3), the step that balances a central difference's two
 * errors): the truncation error h^2/6 |f'''| is ~4e-12 of a field's scale
 * (the closed forms are smooth, f''' ~ f per rad^3 away from singular
 * poses) and the rounding error ~eps |f| / h = 4.4e-11 of it times the
 * amplification of the evaluation (q = n - L0 of the 3SPS differences the
 * limb length, 7 times the scale of dq; the 3RRR's q_bias loses digits in
 * its sum of terms), measured at 2.2e-9 at worst (printed; 1.9e-8 at
 * h = 1e-6, 1.4e-9 at 1e-5: it scales as 1/h, rounding). So 1e-7 of the
 * field's scale max(|f|, |df|) leaves a margin of ~45, while a wrong term
 * (a missing product-rule term moves a derivative by 1e-3 to 1 of its
 * scale) fails by orders of magnitude.
 * Angular velocity derivatives: the biases are exactly quadratic in omega at
 * fixed R, so the central difference with any step (2.5 rad/s here) is exact
 * up to rounding: 1e-10 of max(|df|, |f| / |omega|). */
#include "check.h"
#include "pom_arch.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <stdio.h>
#include <string.h>

#define H_THETA   5e-6 /* rad */
#define H_OMEGA   2.5  /* rad/s */
#define TOL_THETA 1e-7
#define TOL_OMEGA 1e-10
#define SENTINEL  7.25 /* what dout holds before the call in the fields it must not touch */

static int load_arch(const char *file, pom_kin_arch *arch) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, file);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK && pom_kin_arch_load(arch, cfg, &err) == POM_OK;
  if (!ok) printf("loading configs/%s: %s\n", file, err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

/* ---- the fields of limb i as one flat list ------------------------------- */
/* q[i], J row i, q_bias[i], then per body (2 + 2i, 3 + 2i) A, B, a_bias,
 * alpha_bias: the fields limb_twist_diff differentiates. */
enum { F_Q, F_J, F_QBIAS, F_A, F_B, F_ABIAS, F_ALBIAS, F_COUNT = 3 + 4 * 2 };
static const char *const field_names[F_COUNT] = {"q",
                                                 "J row",
                                                 "q_bias",
                                                 "A body 1",
                                                 "B body 1",
                                                 "a_bias body 1",
                                                 "alpha_bias body 1",
                                                 "A body 2",
                                                 "B body 2",
                                                 "a_bias body 2",
                                                 "alpha_bias body 2"};

/* Pointer and length of field f of limb i in t. */
static double *field(pom_kin_twists *t, int i, int f, int *len) {
  if (f == F_Q) return *len = 1, &t->q[i];
  if (f == F_J) return *len = 3, t->J + 3 * i;
  if (f == F_QBIAS) return *len = 1, &t->q_bias[i];
  pom_kin_body_twist *b = &t->body[2 + 2 * i + (f - F_A) / 4];
  switch ((f - F_A) % 4) {
  case 0:
    return *len = 9, b->A;
  case 1:
    return *len = 9, b->B;
  case 2:
    return *len = 3, b->a_bias;
  default:
    return *len = 3, b->alpha_bias;
  }
}

/* Compares the analytic derivative an of every field with the difference
 * (plus - minus) / (2 step); the scale of a field is the largest of |df| and
 * base_weight |f|. Returns the worst error relative to the scale. */
static double compare_fields(pom_kin_twists *an, pom_kin_twists *plus, pom_kin_twists *minus,
                             pom_kin_twists *base, int i, double step, double base_weight,
                             double tol, const char *what, int k) {
  double worst = 0.0;
  for (int f = 0; f < F_COUNT; ++f) {
    int len;
    const double *a = field(an, i, f, &len), *p = field(plus, i, f, &len);
    const double *m = field(minus, i, f, &len), *b = field(base, i, f, &len);
    double scale = 0.0, err = 0.0;
    for (int c = 0; c < len; ++c) {
      double fd = (p[c] - m[c]) / (2.0 * step);
      scale = fmax(scale, fmax(fmax(fabs(a[c]), fabs(fd)), base_weight * fabs(b[c])));
      err = fmax(err, fabs(a[c] - fd));
    }
    double rel = scale > 0.0 ? err / scale : err;
    if (!check_true(rel <= tol))
      printf("  limb %d, %s[%d], %s: error %.3g of scale %.3g\n", i + 1, what, k, field_names[f],
             rel, scale);
    worst = fmax(worst, rel);
  }
  return worst;
}

/* Every field of two twists structs equal (==, field by field). */
static int twists_equal(const pom_kin_twists *a, const pom_kin_twists *b) {
  int eq = a->n_bodies == b->n_bodies;
  for (int c = 0; c < 3; ++c)
    eq &= a->q[c] == b->q[c] && a->q_bias[c] == b->q_bias[c];
  for (int c = 0; c < 9; ++c)
    eq &= a->J[c] == b->J[c];
  for (int n = 0; n < POM_KIN_TWIST_MAX_BODIES; ++n) {
    const pom_kin_body_twist *x = &a->body[n], *y = &b->body[n];
    eq &= x->spin_free == y->spin_free;
    for (int c = 0; c < 9; ++c)
      eq &= x->R[c] == y->R[c] && x->A[c] == y->A[c] && x->B[c] == y->B[c];
    for (int c = 0; c < 3; ++c)
      eq &= x->ref_home[c] == y->ref_home[c] && x->ref[c] == y->ref[c] &&
            x->a_bias[c] == y->a_bias[c] && x->alpha_bias[c] == y->alpha_bias[c] &&
            x->spin_axis[c] == y->spin_axis[c];
  }
  return eq;
}

/* Fills every double of t with v. */
static void fill_twists(pom_kin_twists *t, double v) {
  memset(t, 0, sizeof *t);
  for (int c = 0; c < 3; ++c)
    t->q[c] = t->q_bias[c] = v;
  for (int c = 0; c < 9; ++c)
    t->J[c] = v;
  for (int n = 0; n < POM_KIN_TWIST_MAX_BODIES; ++n) {
    pom_kin_body_twist *b = &t->body[n];
    for (int c = 0; c < 9; ++c)
      b->R[c] = b->A[c] = b->B[c] = v;
    for (int c = 0; c < 3; ++c)
      b->ref_home[c] = b->ref[c] = b->a_bias[c] = b->alpha_bias[c] = b->spin_axis[c] = v;
  }
}

/* The entries of a derivative struct that limb i must not touch (the other
 * limbs' fields, every pose field, the other bodies) still hold SENTINEL. */
static int untouched_ok(pom_kin_twists *d, int i) {
  pom_kin_twists ref, copy = *d;
  fill_twists(&ref, SENTINEL);
  /* overwrite limb i's differentiated fields in both, then compare all */
  for (int f = 0; f < F_COUNT; ++f) {
    int len;
    double *x = field(&copy, i, f, &len), *y = field(&ref, i, f, &len);
    for (int c = 0; c < len; ++c)
      x[c] = y[c] = 0.0;
  }
  copy.n_bodies = ref.n_bodies;
  for (int n = 0; n < POM_KIN_TWIST_MAX_BODIES; ++n)
    copy.body[n].spin_free = ref.body[n].spin_free;
  return twists_equal(&copy, &ref);
}

/* ---- the test ------------------------------------------------------------- */
/* 20 random poses in the shipped regular dexterous workspace (ZYX Euler cube
 * of half-width half_deg) with random omega of norm 10 rad/s. */
static void test_arch(const char *file, double half_deg, pom_rng *rng) {
  pom_kin_arch arch;
  if (!check_true(load_arch(file, &arch))) return;
  const pom_kin_arch_type *t = arch.type;
  if (!check_true(t->limb_twist_diff != NULL)) return;
  double worst_th = 0.0, worst_om = 0.0;
  static pom_kin_twists tw, tw2, tp, tm;
  static pom_kin_twists_diff dtw;
  for (int trial = 0; trial < 20; ++trial) {
    double e[3], R[9], w[3], q[3];
    for (int c = 0; c < 3; ++c) {
      e[c] = pom_rng_range(rng, -half_deg * POM_DEG, half_deg * POM_DEG);
      w[c] = pom_rng_normal(rng);
    }
    pom_v3_scale(w, 10.0 / pom_v3_norm(w), w);
    pom_euler_zyx_to_matrix(R, e);
    check_true(pom_kin_inverse(&arch, R, q, NULL) == POM_OK);
    for (int i = 0; i < 3; ++i) {
      memset(&tw, 0, sizeof tw);
      memset(&tw2, 0, sizeof tw2);
      for (int k = 0; k < 3; ++k) {
        fill_twists(&dtw.d_theta[k], SENTINEL);
        fill_twists(&dtw.d_omega[k], SENTINEL);
      }
      if (!check_true(t->limb_twist(&arch, i, R, w, &tw) == 1) ||
          !check_true(t->limb_twist_diff(&arch, i, R, w, &tw2, &dtw) == 1))
        continue;
      check_true(twists_equal(&tw, &tw2));
      for (int k = 0; k < 3; ++k) {
        check_true(untouched_ok(&dtw.d_theta[k], i));
        check_true(untouched_ok(&dtw.d_omega[k], i));
        /* rotation: R(+-h) = exp(+-h [e_k]x) R */
        double axis[3] = {0.0, 0.0, 0.0}, Rk[9], Rp[9], Rm[9];
        axis[k] = 1.0;
        pom_m3_axis_angle(Rk, axis, H_THETA);
        pom_m3_mul(Rp, Rk, R);
        pom_m3_axis_angle(Rk, axis, -H_THETA);
        pom_m3_mul(Rm, Rk, R);
        memset(&tp, 0, sizeof tp);
        memset(&tm, 0, sizeof tm);
        check_true(t->limb_twist(&arch, i, Rp, w, &tp) == 1 &&
                   t->limb_twist(&arch, i, Rm, w, &tm) == 1);
        worst_th = fmax(worst_th, compare_fields(&dtw.d_theta[k], &tp, &tm, &tw, i, H_THETA, 1.0,
                                                 TOL_THETA, "d_theta", k));
        /* angular velocity */
        double wp[3], wm[3];
        pom_v3_copy(wp, w);
        pom_v3_copy(wm, w);
        wp[k] += H_OMEGA;
        wm[k] -= H_OMEGA;
        memset(&tp, 0, sizeof tp);
        memset(&tm, 0, sizeof tm);
        check_true(t->limb_twist(&arch, i, R, wp, &tp) == 1 &&
                   t->limb_twist(&arch, i, R, wm, &tm) == 1);
        worst_om = fmax(worst_om, compare_fields(&dtw.d_omega[k], &tp, &tm, &tw, i, H_OMEGA,
                                                 1.0 / pom_v3_norm(w), TOL_OMEGA, "d_omega", k));
      }
    }
  }
  printf("%s: worst error of d_theta %.3g, of d_omega %.3g (of the field's scale)\n", file,
         worst_th, worst_om);

  /* where limb_twist fails, limb_twist_diff fails too */
  double Rbad[9];
  pom_m3_identity(Rbad);
  Rbad[4] = NAN;
  for (int i = 0; i < 3; ++i)
    check_true(t->limb_twist(&arch, i, Rbad, (double[3]){1.0, 2.0, 3.0}, &tw) == 0 &&
               t->limb_twist_diff(&arch, i, Rbad, (double[3]){1.0, 2.0, 3.0}, &tw2, &dtw) == 0);
}

int main(void) {
  pom_rng rng;
  pom_rng_seed(&rng, 2385, 20);
  /* the shipped configs' regular dexterous workspaces: +-13 deg (3SPS),
   * +-16 deg (3RRR) (`pomlab workspace`) */
  test_arch("3sps.cfg", 13.0, &rng);
  test_arch("3rrr.cfg", 16.0, &rng);
  return check_summary("test_kin_twist_diff_sps_rrr");
}
