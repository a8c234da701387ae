/* kin_twist.c - pose of every body of the rigid mechanism as a function of
 * the platform rotation, with the maps from the platform angular velocity to
 * each body's twist and the velocity-product (bias) accelerations
 * (docs/dynamics-exact.md section 2). */
#include "pom_kinematics.h"

#include "pom_arch.h"

#include "pom_math.h"

#include <math.h>
#include <string.h>

/* ---- small helpers --------------------------------------------------------- */
/* out = u v^T (outer product) */
void pom_kin_outer(double out[9], const double u[3], const double v[3]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] = u[r] * v[c];
}

/* Rotation taking unit a to unit b by the smallest angle (a . b > -1):
 * R = I + [k]x + [k]x^2 / (1 + c), k = a x b, c = a . b, with
 * [k]x^2 = k k^T - |k|^2 I. */
void pom_kin_min_rotation(double R[9], const double a[3], const double b[3]) {
  double k[3];
  pom_v3_cross(k, a, b);
  double f = 1.0 / (1.0 + pom_v3_dot(a, b)), d = 1.0 - f * pom_v3_dot(k, k);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      R[3 * r + c] = (r == c ? d : 0.0) + f * k[r] * k[c];
  R[1] -= k[2];
  R[2] += k[1];
  R[3] += k[2];
  R[5] -= k[0];
  R[6] -= k[1];
  R[7] += k[0];
}

void pom_kin_twist_rest(pom_kin_body_twist *b) {
  memset(b, 0, sizeof *b);
  pom_m3_identity(b->R);
}

/* ---- public ---------------------------------------------------------------- */
/* The platform (body 1) and the ground (body 0) at rotation R. */
static void platform_twist(pom_kin_twists *out, const double R[9]) {
  out->n_bodies = 8;
  pom_kin_twist_rest(&out->body[0]);
  pom_kin_body_twist *pf = &out->body[1];
  pom_kin_twist_rest(pf);
  pom_m3_copy(pf->R, R);
  pom_m3_identity(pf->B);
}

/* The failure of limb i (err non-NULL: with its message). */
static pom_status limb_failure(const pom_kin_arch *arch, int i, const double R[9], pom_error *err) {
  if (!err) return POM_ERR_UNREACHABLE; /* no formatting in the hot path */
  for (int k = 0; k < 9; ++k)
    if (!isfinite(R[k]))
      POM_FAIL(err, POM_ERR_NONFINITE, "body twists: rotation entry R[%d] = %g", k, R[k]);
  POM_FAIL(err, POM_ERR_UNREACHABLE, "limb %d: %s", i + 1, arch->type->unreachable);
}

pom_status pom_kin_body_twists(const pom_kin_arch *arch, const double R[9], const double omega[3],
                               pom_kin_twists *out, pom_error *err) {
  static const double zero[3] = {0.0, 0.0, 0.0};
  const double *w = omega ? omega : zero;
  if (!arch->type) POM_FAIL(err, POM_ERR_ARG, "pom_kin_body_twists: architecture without a type");
  platform_twist(out, R);
  for (int i = 0; i < 3; ++i)
    if (!arch->type->limb_twist(arch, i, R, w, out)) return limb_failure(arch, i, R, err);
  return POM_OK;
}

int pom_kin_has_twists_diff(const pom_kin_arch *arch) {
  return arch->type && arch->type->limb_twist_diff ? 1 : 0;
}

pom_status pom_kin_body_twists_diff(const pom_kin_arch *arch, const double R[9],
                                    const double omega[3], pom_kin_twists *out,
                                    pom_kin_twists_diff *dout, pom_error *err) {
  static const double zero[3] = {0.0, 0.0, 0.0};
  const double *w = omega ? omega : zero;
  if (!pom_kin_has_twists_diff(arch))
    POM_FAIL(err, POM_ERR_ARG,
             "pom_kin_body_twists_diff: architecture %s has no second-order "
             "kinematics (limb_twist_diff)",
             arch->type ? arch->type->name : "without a type");
  platform_twist(out, R);
  /* the platform's A = 0, B = I and zero biases are constants: zero
   * derivatives, as are the ground's; the fields a limb op leaves alone (the
   * omega derivatives of q, J, A, B) are zero too. The pose fields are not
   * written (no entry: section 2.1); zeroing the whole 17 kB would cost more
   * than the derivatives themselves. */
  for (int k = 0; k < 6; ++k) {
    pom_kin_twists *t = k < 3 ? &dout->d_theta[k] : &dout->d_omega[k - 3];
    t->n_bodies = out->n_bodies;
    for (int i = 0; i < 3; ++i)
      t->q[i] = t->q_bias[i] = 0.0;
    for (int i = 0; i < 9; ++i)
      t->J[i] = 0.0;
    for (int b = 0; b < out->n_bodies; ++b) {
      pom_kin_body_twist *x = &t->body[b];
      for (int i = 0; i < 9; ++i)
        x->A[i] = x->B[i] = 0.0;
      for (int i = 0; i < 3; ++i)
        x->a_bias[i] = x->alpha_bias[i] = 0.0;
    }
  }
  for (int i = 0; i < 3; ++i)
    if (!arch->type->limb_twist_diff(arch, i, R, w, out, dout))
      return limb_failure(arch, i, R, err);
  return POM_OK;
}
