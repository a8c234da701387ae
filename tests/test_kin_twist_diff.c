/* test_kin_twist_diff.c - second-order kinematics (pom_kin_body_twists_diff,
 * the architecture type's limb_twist_diff; docs/dynamics-exact.md section
 * 2.1) against central differences of pom_kin_body_twists, for every
 * registered architecture that provides the op (the 3P-S-S/S must: the test
 * fails without it; the others are tested once they have it, and the test
 * prints which). At 20 random reachable rotations and angular velocities per
 * architecture:
 *   - the twists the wrapper fills equal pom_kin_body_twists' bit for bit;
 *   - d_theta[k] against (f(exp([h e_k]x) R) - f(exp(-[h e_k]x) R)) / 2h,
 *     h = 1e-6 rad, for q, J, q_bias and every body's A, B, a_bias,
 *     alpha_bias;
 *   - d_omega[k] against (f(w + h e_k) - f(w - h e_k)) / 2h, h = 1e-3 rad/s
 *     (the fields are constant or quadratic in omega: the difference is
 *     exact up to rounding).
 * Tolerances per field, relative to the field's size S (its largest entry
 * over the mechanism) times the largest of 1 and the rotation or rate
 * scale: the central difference's truncation h^2 |f'''| / 6 is ~1e-13 S for
 * these geometries (f''' ~ S / (l.u / L)^3 with l.u / L >= 0.3) and its
 * rounding ~eps S_terms / h = 2.2e-10 S_terms (S_terms, the largest term
 * that cancels in a field, is < 50 S here): 1e-7 S for theta, with a
 * margin ~10 over the rounding bound; for omega the rounding alone,
 * eps S_terms / h ~ 1e-11 S: 1e-9 S. */
#include "check.h"
#include "pom_arch.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define N_POSES   20
#define H_THETA   1e-6 /* rad */
#define H_OMEGA   1e-3 /* rad/s */
#define TOL_THETA 1e-7 /* of the field's size */
#define TOL_OMEGA 1e-9
#define N_FIELDS  7

static const char *field_name[N_FIELDS] = {"q", "J", "q_bias", "A", "B", "a_bias", "alpha_bias"};

/* Pointers to every entry of field f of tw (n entries into v). */
static int field_values(const pom_kin_twists *tw, int f, double *v) {
  int n = 0;
  switch (f) {
  case 0:
    for (int i = 0; i < 3; ++i)
      v[n++] = tw->q[i];
    break;
  case 1:
    for (int i = 0; i < 9; ++i)
      v[n++] = tw->J[i];
    break;
  case 2:
    for (int i = 0; i < 3; ++i)
      v[n++] = tw->q_bias[i];
    break;
  default:
    for (int b = 0; b < tw->n_bodies; ++b) {
      const pom_kin_body_twist *t = &tw->body[b];
      const double *src = f == 3 ? t->A : f == 4 ? t->B : f == 5 ? t->a_bias : t->alpha_bias;
      int len = f <= 4 ? 9 : 3;
      for (int k = 0; k < len; ++k)
        v[n++] = src[k];
    }
  }
  return n;
}

/* Largest |entry| of field f over the three evaluations (at least tiny). */
static double field_size(const pom_kin_twists *a, const pom_kin_twists *b, const pom_kin_twists *c,
                         int f) {
  double v[128], s = 1e-300;
  const pom_kin_twists *all[3] = {a, b, c};
  for (int e = 0; e < 3; ++e) {
    int n = field_values(all[e], f, v);
    for (int k = 0; k < n; ++k)
      s = fmax(s, fabs(v[k]));
  }
  return s;
}

/* Worst error / tolerance of field f of the analytic derivative da against
 * the central difference of tp, tm (step h), tolerance tol x size. */
static double compare(const char *what, const pom_kin_twists *t0, const pom_kin_twists *tp,
                      const pom_kin_twists *tm, const pom_kin_twists *da, double h, double tol,
                      int f) {
  double vp[128], vm[128], vd[128];
  int n = field_values(tp, f, vp);
  field_values(tm, f, vm);
  field_values(da, f, vd);
  double size = field_size(t0, tp, tm, f), worst = 0.0;
  for (int k = 0; k < n; ++k) {
    double ref = (vp[k] - vm[k]) / (2.0 * h);
    /* derivatives may exceed the field (size / lever): scale by both */
    double e = fabs(vd[k] - ref) / (tol * fmax(size, fabs(ref)));
    if (e > 1.0)
      printf("    %s %s[%d]: analytic %.12g, central %.12g\n", what, field_name[f], k, vd[k], ref);
    worst = fmax(worst, e);
  }
  return worst;
}

/* 1 when the twists a and b agree bit for bit on the fields both fill. */
static int same_twists(const pom_kin_twists *a, const pom_kin_twists *b) {
  if (a->n_bodies != b->n_bodies) return 0;
  double va[128], vb[128];
  for (int f = 0; f < N_FIELDS; ++f) {
    int n = field_values(a, f, va);
    field_values(b, f, vb);
    if (memcmp(va, vb, (size_t)n * sizeof(double)) != 0) return 0;
  }
  for (int k = 0; k < a->n_bodies; ++k) {
    const pom_kin_body_twist *x = &a->body[k], *y = &b->body[k];
    if (memcmp(x->R, y->R, sizeof x->R) || memcmp(x->ref, y->ref, sizeof x->ref) ||
        memcmp(x->ref_home, y->ref_home, sizeof x->ref_home) || x->spin_free != y->spin_free ||
        memcmp(x->spin_axis, y->spin_axis, sizeof x->spin_axis))
      return 0;
  }
  return 1;
}

static int load_arch(const pom_kin_arch_type *type, pom_kin_arch *arch) {
  char file[64], path[512];
  size_t k = 0;
  for (const char *c = type->name; *c && k + 1 < sizeof file; ++c)
    file[k++] = (char)tolower((unsigned char)*c);
  file[k] = '\0';
  snprintf(path, sizeof path, "%s/configs/%s.cfg", POM_SOURCE_DIR, file);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK && pom_kin_arch_load(arch, cfg, &err) == POM_OK;
  if (!ok) printf("  %s: %s\n", path, err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

static pom_kin_twists_diff dd; /* large: static */

static void check_type(const pom_kin_arch_type *type) {
  pom_kin_arch arch;
  if (!load_arch(type, &arch)) {
    check_true(0);
    return;
  }
  pom_rng rng;
  pom_rng_seed(&rng, 7019, 0);
  double worst_t[N_FIELDS] = {0}, worst_w[N_FIELDS] = {0};
  int same = 1, done = 0;
  for (int tries = 0; done < N_POSES && tries < 50 * N_POSES; ++tries) {
    double e[3], R[9], w[3];
    for (int k = 0; k < 3; ++k) {
      e[k] = pom_rng_range(&rng, -0.15, 0.15);
      w[k] = pom_rng_range(&rng, -5.0, 5.0);
    }
    pom_euler_zyx_to_matrix(R, e);
    pom_kin_twists t0, td, tp, tm;
    if (pom_kin_body_twists(&arch, R, w, &t0, NULL) != POM_OK) continue; /* unreachable */
    /* the steps must stay reachable too */
    int ok = pom_kin_body_twists_diff(&arch, R, w, &td, &dd, NULL) == POM_OK;
    check_true(ok);
    if (!ok) continue;
    same &= same_twists(&t0, &td);
    for (int k = 0; k < 3; ++k) {
      double ax[3] = {0.0, 0.0, 0.0}, Rs[9], Rp[9], Rm[9], wp[3], wm[3];
      ax[k] = 1.0;
      pom_m3_axis_angle(Rs, ax, H_THETA);
      pom_m3_mul(Rp, Rs, R);
      pom_m3_axis_angle(Rs, ax, -H_THETA);
      pom_m3_mul(Rm, Rs, R);
      ok = pom_kin_body_twists(&arch, Rp, w, &tp, NULL) == POM_OK &&
           pom_kin_body_twists(&arch, Rm, w, &tm, NULL) == POM_OK;
      check_true(ok);
      if (!ok) break;
      for (int f = 0; f < N_FIELDS; ++f)
        worst_t[f] = fmax(worst_t[f],
                          compare("theta", &t0, &tp, &tm, &dd.d_theta[k], H_THETA, TOL_THETA, f));
      pom_v3_copy(wp, w);
      pom_v3_copy(wm, w);
      wp[k] += H_OMEGA;
      wm[k] -= H_OMEGA;
      ok = pom_kin_body_twists(&arch, R, wp, &tp, NULL) == POM_OK &&
           pom_kin_body_twists(&arch, R, wm, &tm, NULL) == POM_OK;
      check_true(ok);
      if (!ok) break;
      for (int f = 0; f < N_FIELDS; ++f)
        worst_w[f] = fmax(worst_w[f],
                          compare("omega", &t0, &tp, &tm, &dd.d_omega[k], H_OMEGA, TOL_OMEGA, f));
    }
    ++done;
  }
  check_true(done == N_POSES);
  check_true(same);
  printf("%s: %d poses; worst error / tolerance (theta, omega):", type->name, done);
  for (int f = 0; f < N_FIELDS; ++f) {
    printf(" %s %.2g %.2g%s", field_name[f], worst_t[f], worst_w[f], f + 1 < N_FIELDS ? "," : "");
    check_true(worst_t[f] <= 1.0 && worst_w[f] <= 1.0);
  }
  printf("; twists as pom_kin_body_twists: %s\n", same ? "yes" : "NO");
}

int main(void) {
  /* the architectures whose second-order kinematics the exact path needs:
   * every shipped one (a user's may go without: its columns are differenced) */
  static const char *required[] = {"3PSS", "3SPS", "3RRR"}; /* every shipped type */
  for (size_t r = 0; r < sizeof required / sizeof required[0]; ++r) {
    const pom_kin_arch_type *t = pom_kin_arch_type_find(required[r]);
    check_true(t != NULL && t->limb_twist_diff != NULL);
    if (t && !t->limb_twist_diff) printf("%s: no limb_twist_diff (required)\n", t->name);
  }
  int tested = 0;
  for (int k = 0; k < pom_kin_arch_type_count(); ++k) {
    const pom_kin_arch_type *t = pom_kin_arch_type_at(k);
    if (!t->limb_twist_diff) {
      printf("%s: no limb_twist_diff, not tested\n", t->name);
      pom_kin_arch arch;
      /* the wrapper says so, touching nothing */
      if (load_arch(t, &arch)) {
        pom_kin_twists tw;
        double R[9];
        pom_m3_identity(R);
        check_true(!pom_kin_has_twists_diff(&arch));
        check_true(pom_kin_body_twists_diff(&arch, R, NULL, &tw, &dd, NULL) == POM_ERR_ARG);
      }
      continue;
    }
    check_type(t);
    ++tested;
  }
  check_true(tested >= 1);
  return check_summary("test_kin_twist_diff");
}
