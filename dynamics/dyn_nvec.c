/* dyn_nvec.c - the serial N_Vector kernels CVODE spends its time in,
 * compiled with the project's optimization flags. The distribution's
 * SUNDIALS 6.4 serial vector is built without optimization (its loops keep
 * every index in memory), and at ~100 states the vector kernels are a third
 * of a maneuver (bench/README.md). Same arithmetic, same order of operations
 * as SUNDIALS' serial kernels; the fused operations are provided too, which
 * SUNDIALS then uses instead of chains of linear sums. */
#include "dyn_internal.h"

#include <math.h>

#define LEN(v)  ((long)NV_LENGTH_S(v))
#define DATA(v) (NV_DATA_S(v))

/* The element-wise kernels work in blocks of four: the block's loads come
 * before its stores, so z may be x or y (CVODE updates in place) and the
 * compiler still packs each block into vector instructions at -O2. Each
 * element gets the same operations as in the plain loop. */
#define BLOCK 4

static void lin_sum(sunrealtype a, N_Vector x, sunrealtype b, N_Vector y, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x), *yd = DATA(y);
  double *zd = DATA(z);
  long i = 0;
  for (; i + BLOCK <= n; i += BLOCK) {
    double t[BLOCK];
    for (int k = 0; k < BLOCK; ++k)
      t[k] = a * xd[i + k] + b * yd[i + k];
    for (int k = 0; k < BLOCK; ++k)
      zd[i + k] = t[k];
  }
  for (; i < n; ++i)
    zd[i] = a * xd[i] + b * yd[i];
}

static void vconst(sunrealtype c, N_Vector z) {
  const long n = LEN(z);
  double *zd = DATA(z);
  for (long i = 0; i < n; ++i)
    zd[i] = c;
}

static void prod(N_Vector x, N_Vector y, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x), *yd = DATA(y);
  double *zd = DATA(z);
  for (long i = 0; i < n; ++i)
    zd[i] = xd[i] * yd[i];
}

static void vdiv(N_Vector x, N_Vector y, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x), *yd = DATA(y);
  double *zd = DATA(z);
  for (long i = 0; i < n; ++i)
    zd[i] = xd[i] / yd[i];
}

static void scale(sunrealtype c, N_Vector x, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  double *zd = DATA(z);
  long i = 0;
  for (; i + BLOCK <= n; i += BLOCK) {
    double t[BLOCK];
    for (int k = 0; k < BLOCK; ++k)
      t[k] = c * xd[i + k];
    for (int k = 0; k < BLOCK; ++k)
      zd[i + k] = t[k];
  }
  for (; i < n; ++i)
    zd[i] = c * xd[i];
}

static void vabs(N_Vector x, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  double *zd = DATA(z);
  for (long i = 0; i < n; ++i)
    zd[i] = fabs(xd[i]);
}

static void inv(N_Vector x, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  double *zd = DATA(z);
  for (long i = 0; i < n; ++i)
    zd[i] = 1.0 / xd[i];
}

static void add_const(N_Vector x, sunrealtype b, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  double *zd = DATA(z);
  for (long i = 0; i < n; ++i)
    zd[i] = xd[i] + b;
}

static sunrealtype dot(N_Vector x, N_Vector y) {
  const long n = LEN(x);
  const double *xd = DATA(x), *yd = DATA(y);
  double s = 0.0;
  for (long i = 0; i < n; ++i)
    s += xd[i] * yd[i];
  return s;
}

static sunrealtype max_norm(N_Vector x) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  double m = 0.0;
  for (long i = 0; i < n; ++i)
    if (fabs(xd[i]) > m) m = fabs(xd[i]);
  return m;
}

static sunrealtype wsqr_sum(N_Vector x, N_Vector w) {
  const long n = LEN(x);
  const double *xd = DATA(x), *wd = DATA(w);
  double s = 0.0;
  for (long i = 0; i < n; ++i) {
    double p = xd[i] * wd[i];
    s += p * p;
  }
  return s;
}

static sunrealtype wrms_norm(N_Vector x, N_Vector w) {
  return sqrt(wsqr_sum(x, w) / (double)LEN(x));
}

static sunrealtype vmin(N_Vector x) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  double m = xd[0];
  for (long i = 1; i < n; ++i)
    if (xd[i] < m) m = xd[i];
  return m;
}

static void compare(sunrealtype c, N_Vector x, N_Vector z) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  double *zd = DATA(z);
  for (long i = 0; i < n; ++i)
    zd[i] = (fabs(xd[i]) >= c) ? 1.0 : 0.0;
}

/* z = sum_k c[k] X[k]; z may be any of the X[k]. Block by block: the same
 * sum in the same order per entry, each vector's data pointer fetched once
 * per block (CVodeGetDky at every output sample, bench/README.md issue 10). */
static int lin_comb(int nv, sunrealtype *c, N_Vector *X, N_Vector z) {
  const long n = LEN(z);
  double *zd = DATA(z);
  long i = 0;
  for (; i + BLOCK <= n; i += BLOCK) {
    double t[BLOCK];
    const double *x0 = DATA(X[0]) + i;
    for (int b = 0; b < BLOCK; ++b)
      t[b] = c[0] * x0[b];
    for (int k = 1; k < nv; ++k) {
      const double *xk = DATA(X[k]) + i;
      for (int b = 0; b < BLOCK; ++b)
        t[b] += c[k] * xk[b];
    }
    for (int b = 0; b < BLOCK; ++b)
      zd[i + b] = t[b];
  }
  for (; i < n; ++i) {
    double s = c[0] * DATA(X[0])[i];
    for (int k = 1; k < nv; ++k)
      s += c[k] * DATA(X[k])[i];
    zd[i] = s;
  }
  return 0;
}

/* Z[k] = a[k] x + Y[k]; Z[k] may be Y[k] */
static int scale_add_multi(int nv, sunrealtype *a, N_Vector x, N_Vector *Y, N_Vector *Z) {
  const long n = LEN(x);
  const double *xd = DATA(x);
  for (int k = 0; k < nv; ++k) {
    const double *yd = DATA(Y[k]);
    double *zd = DATA(Z[k]);
    const double ak = a[k];
    long i = 0;
    for (; i + BLOCK <= n; i += BLOCK) {
      double t[BLOCK];
      for (int b = 0; b < BLOCK; ++b)
        t[b] = ak * xd[i + b] + yd[i + b];
      for (int b = 0; b < BLOCK; ++b)
        zd[i + b] = t[b];
    }
    for (; i < n; ++i)
      zd[i] = ak * xd[i] + yd[i];
  }
  return 0;
}

/* Z[k] = c[k] X[k] */
static int scale_array(int nv, sunrealtype *c, N_Vector *X, N_Vector *Z) {
  for (int k = 0; k < nv; ++k)
    scale(c[k], X[k], Z[k]);
  return 0;
}

/* Z[k] = a X[k] + b Y[k] */
static int lin_sum_array(int nv, sunrealtype a, N_Vector *X, sunrealtype b, N_Vector *Y,
                         N_Vector *Z) {
  for (int k = 0; k < nv; ++k)
    lin_sum(a, X[k], b, Y[k], Z[k]);
  return 0;
}

void pom_dyn_nvec_fast_ops(N_Vector v) {
  N_Vector_Ops o = v->ops;
  o->nvlinearsum = lin_sum;
  o->nvconst = vconst;
  o->nvprod = prod;
  o->nvdiv = vdiv;
  o->nvscale = scale;
  o->nvabs = vabs;
  o->nvinv = inv;
  o->nvaddconst = add_const;
  o->nvdotprod = dot;
  o->nvdotprodlocal = dot;
  o->nvmaxnorm = max_norm;
  o->nvmaxnormlocal = max_norm;
  o->nvwrmsnorm = wrms_norm;
  o->nvwsqrsumlocal = wsqr_sum;
  o->nvmin = vmin;
  o->nvminlocal = vmin;
  o->nvcompare = compare;
  o->nvlinearcombination = lin_comb;
  o->nvscaleaddmulti = scale_add_multi;
  o->nvscalevectorarray = scale_array;
  o->nvlinearsumvectorarray = lin_sum_array;
}
