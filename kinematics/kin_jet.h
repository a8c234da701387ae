/* kin_jet.h - truncated bivariate Taylor jets for forward-mode automatic
 * differentiation of the generic limb kernels (docs/kinematics-tables.md
 * section 5). A jet holds the coefficients of f(t, s) = sum c_ab t^a s^b for
 * a <= 2, b <= 1, in the order 1, t, t^2, s, t s, t^2 s; every operation
 * is exact up to that truncation (the monomials t^3 and s^2 are dropped).
 * Internal to kinematics/: not part of the public contract. */
#ifndef POM_KIN_JET_H
#define POM_KIN_JET_H

#include <math.h>

enum { JET_1, JET_T, JET_T2, JET_S, JET_TS, JET_T2S, JET_N };

typedef struct {
  double c[JET_N];
} pom_jet;

static inline pom_jet jet_const(double x) {
  pom_jet r = {{x, 0.0, 0.0, 0.0, 0.0, 0.0}};
  return r;
}

static inline pom_jet jet_add(pom_jet a, pom_jet b) {
  for (int k = 0; k < JET_N; ++k)
    a.c[k] += b.c[k];
  return a;
}

static inline pom_jet jet_sub(pom_jet a, pom_jet b) {
  for (int k = 0; k < JET_N; ++k)
    a.c[k] -= b.c[k];
  return a;
}

static inline pom_jet jet_scale(double x, pom_jet a) {
  for (int k = 0; k < JET_N; ++k)
    a.c[k] *= x;
  return a;
}

/* a + x b */
static inline pom_jet jet_axpy(pom_jet a, double x, pom_jet b) {
  for (int k = 0; k < JET_N; ++k)
    a.c[k] += x * b.c[k];
  return a;
}

static inline pom_jet jet_mul(pom_jet a, pom_jet b) {
  const double *x = a.c, *y = b.c;
  pom_jet r;
  r.c[JET_1] = x[0] * y[0];
  r.c[JET_T] = x[0] * y[1] + x[1] * y[0];
  r.c[JET_T2] = x[0] * y[2] + x[1] * y[1] + x[2] * y[0];
  r.c[JET_S] = x[0] * y[3] + x[3] * y[0];
  r.c[JET_TS] = x[0] * y[4] + x[1] * y[3] + x[3] * y[1] + x[4] * y[0];
  r.c[JET_T2S] = x[0] * y[5] + x[1] * y[4] + x[2] * y[3] + x[3] * y[2] + x[4] * y[1] + x[5] * y[0];
  return r;
}

/* f(a) for a scalar function with derivatives f0..f3 at a's constant term:
 * f(a0 + n) = f0 + f1 n + f2 n^2 / 2 + f3 n^3 / 6 (n^4 = 0: n has no
 * constant term and the highest monomial, t^2 s, has total degree 3). */
static inline pom_jet jet_apply(pom_jet a, double f0, double f1, double f2, double f3) {
  pom_jet n = a, n2, n3, r = jet_const(f0);
  n.c[JET_1] = 0.0;
  n2 = jet_mul(n, n);
  n3 = jet_mul(n2, n);
  r = jet_axpy(r, f1, n);
  r = jet_axpy(r, 0.5 * f2, n2);
  return jet_axpy(r, f3 / 6.0, n3);
}

static inline pom_jet jet_recip(pom_jet a) {
  double x = 1.0 / a.c[JET_1];
  return jet_apply(a, x, -x * x, 2.0 * x * x * x, -6.0 * x * x * x * x);
}

static inline pom_jet jet_div(pom_jet a, pom_jet b) {
  return jet_mul(a, jet_recip(b));
}

static inline pom_jet jet_sqrt(pom_jet a) {
  double r = sqrt(a.c[JET_1]), i = 1.0 / a.c[JET_1];
  return jet_apply(a, r, 0.5 * r * i, -0.25 * r * i * i, 0.375 * r * i * i * i);
}

static inline pom_jet jet_cos(pom_jet a) {
  double c = cos(a.c[JET_1]), s = sin(a.c[JET_1]);
  return jet_apply(a, c, -s, -c, s);
}

static inline pom_jet jet_sin(pom_jet a) {
  double c = cos(a.c[JET_1]), s = sin(a.c[JET_1]);
  return jet_apply(a, s, c, -s, -c);
}

/* d/dt: (c_t, 2 c_t2, 0, c_ts, 2 c_t2s, 0). */
static inline pom_jet jet_dt(pom_jet a) {
  pom_jet r = {{a.c[JET_T], 2.0 * a.c[JET_T2], 0.0, a.c[JET_TS], 2.0 * a.c[JET_T2S], 0.0}};
  return r;
}

/* ---- 3-vectors and 3x3 matrices of jets (row-major) ---- */
static inline pom_jet jv_dot(const pom_jet a[3], const pom_jet b[3]) {
  return jet_add(jet_add(jet_mul(a[0], b[0]), jet_mul(a[1], b[1])), jet_mul(a[2], b[2]));
}

/* a . x for a constant x */
static inline pom_jet jv_dotc(const pom_jet a[3], const double x[3]) {
  return jet_axpy(jet_axpy(jet_scale(x[0], a[0]), x[1], a[1]), x[2], a[2]);
}

static inline void jv_cross(pom_jet out[3], const pom_jet a[3], const pom_jet b[3]) {
  pom_jet r[3];
  r[0] = jet_sub(jet_mul(a[1], b[2]), jet_mul(a[2], b[1]));
  r[1] = jet_sub(jet_mul(a[2], b[0]), jet_mul(a[0], b[2]));
  r[2] = jet_sub(jet_mul(a[0], b[1]), jet_mul(a[1], b[0]));
  out[0] = r[0];
  out[1] = r[1];
  out[2] = r[2];
}

static inline void jv_const(pom_jet out[3], const double x[3]) {
  for (int k = 0; k < 3; ++k)
    out[k] = jet_const(x[k]);
}

static inline void jv_sub(pom_jet out[3], const pom_jet a[3], const pom_jet b[3]) {
  for (int k = 0; k < 3; ++k)
    out[k] = jet_sub(a[k], b[k]);
}

/* out = a x + b (scalar jet a, constant vector x) */
static inline void jv_sxpy(pom_jet out[3], pom_jet a, const double x[3], const pom_jet b[3]) {
  for (int k = 0; k < 3; ++k)
    out[k] = jet_add(jet_scale(x[k], a), b[k]);
}

/* out = a v for a scalar jet a and a vector jet v */
static inline void jv_scale(pom_jet out[3], pom_jet a, const pom_jet v[3]) {
  for (int k = 0; k < 3; ++k)
    out[k] = jet_mul(a, v[k]);
}

/* out = M x for a matrix jet M and a constant x */
static inline void jm_applyc(pom_jet out[3], const pom_jet M[9], const double x[3]) {
  for (int r = 0; r < 3; ++r)
    out[r] = jet_axpy(jet_axpy(jet_scale(x[0], M[3 * r]), x[1], M[3 * r + 1]), x[2], M[3 * r + 2]);
}

/* Coefficient k of every entry of a vector / matrix jet. */
static inline void jv_coef(double out[3], const pom_jet a[3], int k) {
  for (int r = 0; r < 3; ++r)
    out[r] = a[r].c[k];
}

#endif
