/* kin_jet.h - truncated multivariate Taylor jets for forward-mode automatic
 * differentiation of the generic limb kernels (docs/kinematics-tables.md
 * section 5). Two algebras, each exact up to its truncation:
 *
 * V ("velocity", pom_vjet, 6 coefficients): f = c_1 + c_t t + c_t2 t^2 +
 *   sum_k c_sk s_k with t s_k = s_j s_k = 0: second order along one motion
 *   t, first order along three rotation increments s_0..2 at once
 *   (limb_twist: biases from t, twist maps from s).
 * D ("derivatives", pom_djet, 33 coefficients): t up to t^2 times six
 *   first-order directions d_0..5 (d_0..2 = s_k, the rotation increments;
 *   d_3..5 = sigma_k, the angular-velocity increments), plus three more
 *   first-order rotation increments u_j and the products u_j s_k; every
 *   other product of two directions is dropped (limb_twist_diff).
 *
 * Each algebra defines its product, t-derivative and scalar-function
 * application; kin_jet_ops.inc then generates the shared operations (sums,
 * 1/x, sqrt, cos, sin, vectors) for it. Internal to kinematics/: not part
 * of the public contract. */
#ifndef POM_KIN_JET_H
#define POM_KIN_JET_H

#include <math.h>

/* The jet operations are small and called with structs by value: inlined
 * always, so that the copies vanish (docs/kinematics-tables.md section 8). */
#if defined(__GNUC__) || defined(__clang__)
#define JET_INLINE inline __attribute__((always_inline))
#else
#define JET_INLINE inline
#endif

/* ---- algebra V ----------------------------------------------------------- */
enum { VJ_1, VJ_T, VJ_T2, VJ_S, VJ_N = VJ_S + 3 }; /* VJ_S + k: s_k */

typedef struct {
  double c[VJ_N];
} pom_vjet;

static JET_INLINE pom_vjet vj_mul(pom_vjet a, pom_vjet b) {
  const double *x = a.c, *y = b.c;
  pom_vjet r;
  r.c[VJ_1] = x[0] * y[0];
  r.c[VJ_T] = x[0] * y[1] + x[1] * y[0];
  r.c[VJ_T2] = x[0] * y[2] + x[1] * y[1] + x[2] * y[0];
  for (int k = VJ_S; k < VJ_N; ++k)
    r.c[k] = x[0] * y[k] + x[k] * y[0];
  return r;
}

/* f(a) with f0..f3 the derivatives of f at a's constant term: a = a0 + n,
 * n^2 = n_t^2 t^2, n^3 = 0 (no monomial of degree 3). */
static JET_INLINE pom_vjet vj_apply(pom_vjet a, double f0, double f1, double f2, double f3) {
  pom_vjet r;
  (void)f3;
  r.c[VJ_1] = f0;
  for (int k = 1; k < VJ_N; ++k)
    r.c[k] = f1 * a.c[k];
  r.c[VJ_T2] += 0.5 * f2 * a.c[VJ_T] * a.c[VJ_T];
  return r;
}

/* d/dt (the s_k t terms it would give are truncated) */
static JET_INLINE pom_vjet vj_dt(pom_vjet a) {
  pom_vjet r = {{a.c[VJ_T], 2.0 * a.c[VJ_T2], 0.0, 0.0, 0.0, 0.0}};
  return r;
}

/* ---- algebra D ----------------------------------------------------------- */
/* direction m (0..5): DJ_D(m) the d_m term, DJ_TD(m) t d_m, DJ_T2D(m) t^2 d_m;
 * DJ_U + j: u_j; DJ_US + 3 j + k: u_j s_k */
enum { DJ_1, DJ_T, DJ_T2, DJ_DIR, DJ_U = DJ_DIR + 18, DJ_US = DJ_U + 3, DJ_N = DJ_US + 9 };
#define DJ_D(m)   (DJ_DIR + 3 * (m))
#define DJ_TD(m)  (DJ_DIR + 3 * (m) + 1)
#define DJ_T2D(m) (DJ_DIR + 3 * (m) + 2)

typedef struct {
  double c[DJ_N];
} pom_djet;

static JET_INLINE pom_djet dj_mul(pom_djet a, pom_djet b) {
  const double *x = a.c, *y = b.c;
  pom_djet r;
  r.c[DJ_1] = x[0] * y[0];
  r.c[DJ_T] = x[0] * y[1] + x[1] * y[0];
  r.c[DJ_T2] = x[0] * y[2] + x[1] * y[1] + x[2] * y[0];
  for (int d = DJ_DIR; d < DJ_U; d += 3) {
    r.c[d] = x[0] * y[d] + x[d] * y[0];
    r.c[d + 1] = x[0] * y[d + 1] + x[1] * y[d] + x[d] * y[1] + x[d + 1] * y[0];
    r.c[d + 2] = x[0] * y[d + 2] + x[1] * y[d + 1] + x[2] * y[d] + x[d] * y[2] + x[d + 1] * y[1] +
                 x[d + 2] * y[0];
  }
  for (int j = 0; j < 3; ++j) {
    const int u = DJ_U + j;
    r.c[u] = x[0] * y[u] + x[u] * y[0];
    for (int k = 0; k < 3; ++k) {
      const int us = DJ_US + 3 * j + k, s = DJ_D(k);
      r.c[us] = x[0] * y[us] + x[u] * y[s] + x[s] * y[u] + x[us] * y[0];
    }
  }
  return r;
}

/* f(a) with f0..f3 the derivatives of f at a's constant term: a = a0 + n,
 * f = f0 + f1 n + f2 n^2 / 2 + f3 n^3 / 6; n^2 and n^3 written out (n^3 has
 * only the t^2 d_m terms, 3 n_t^2 n_dm). */
static JET_INLINE pom_djet dj_apply(pom_djet a, double f0, double f1, double f2, double f3) {
  const double *n = a.c;
  const double h = 0.5 * f2, g = f3 / 6.0;
  pom_djet r;
  r.c[DJ_1] = f0;
  for (int k = 1; k < DJ_N; ++k)
    r.c[k] = f1 * n[k];
  r.c[DJ_T2] += h * n[DJ_T] * n[DJ_T];
  for (int d = DJ_DIR; d < DJ_U; d += 3) {
    r.c[d + 1] += h * 2.0 * n[DJ_T] * n[d];
    r.c[d + 2] +=
        h * 2.0 * (n[DJ_T] * n[d + 1] + n[DJ_T2] * n[d]) + g * 3.0 * n[DJ_T] * n[DJ_T] * n[d];
  }
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k)
      r.c[DJ_US + 3 * j + k] += h * 2.0 * n[DJ_U + j] * n[DJ_D(k)];
  return r;
}

/* d/dt */
static JET_INLINE pom_djet dj_dt(pom_djet a) {
  pom_djet r;
  for (int k = 0; k < DJ_N; ++k)
    r.c[k] = 0.0;
  r.c[DJ_1] = a.c[DJ_T];
  r.c[DJ_T] = 2.0 * a.c[DJ_T2];
  for (int d = DJ_DIR; d < DJ_U; d += 3) {
    r.c[d] = a.c[d + 1];
    r.c[d + 1] = 2.0 * a.c[d + 2];
  }
  return r;
}

/* ---- the shared operations of each algebra (kin_jet_ops.inc) -------------- */
#define JT     pom_vjet
#define JN     VJ_N
#define JP(n_) vj_##n_
#include "kin_jet_ops.inc"
#undef JT
#undef JN
#undef JP

#define JT     pom_djet
#define JN     DJ_N
#define JP(n_) dj_##n_
#include "kin_jet_ops.inc"
#undef JT
#undef JN
#undef JP

#endif
