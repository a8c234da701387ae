/* test_dyn_nvec.c - the vector kernels of dynamics/dyn_nvec.c against
 * SUNDIALS' own serial kernels: bit for bit (same operations per element),
 * for lengths around the kernels' blocks of four and the models' 106 states,
 * with the output vector distinct from or equal to an input (CVODE updates
 * in place). */
#include "check.h"
#include "dyn_internal.h"

#include <stdint.h>
#include <string.h>

static double urand(uint64_t *s) {
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) / 4503599627370496.0 - 1.0;
}

/* largest |a_i - b_i| */
static double diff(N_Vector a, N_Vector b) {
  double w = 0.0;
  for (sunindextype i = 0; i < NV_LENGTH_S(a); ++i)
    w = fmax(w, fabs(NV_Ith_S(a, i) - NV_Ith_S(b, i)));
  return w;
}

#define NV 4 /* vectors per side */

static void check_length(SUNContext ctx, sunindextype n, uint64_t *seed) {
  N_Vector r[NV], f[NV]; /* reference (SUNDIALS) and fast copies of the same data */
  for (int k = 0; k < NV; ++k) {
    r[k] = N_VNew_Serial(n, ctx);
    f[k] = N_VNew_Serial(n, ctx);
    N_VEnableFusedOps_Serial(r[k], SUNTRUE);
    pom_dyn_nvec_fast_ops(f[k]);
  }
  const double a = 2.385, b = -0.731, c[NV] = {1.0, -0.377, 0.125, 3.3};
  for (int pass = 0; pass < 2; ++pass) {
    /* pass 0: results in a fresh vector; pass 1: in place over an input */
    for (int k = 0; k < NV; ++k)
      for (sunindextype i = 0; i < n; ++i)
        NV_Ith_S(r[k], i) = NV_Ith_S(f[k], i) = urand(seed);
    int z = pass ? 0 : 3;
    N_VLinearSum(a, r[0], b, r[1], r[z]);
    N_VLinearSum(a, f[0], b, f[1], f[z]);
    check_abs(diff(r[z], f[z]), 0.0, 0.0);
    N_VScale(c[1], r[1], r[pass ? 1 : 3]);
    N_VScale(c[1], f[1], f[pass ? 1 : 3]);
    check_abs(diff(r[pass ? 1 : 3], f[pass ? 1 : 3]), 0.0, 0.0);
    N_VLinearCombination(3, (double *)c, r, r[z]);
    N_VLinearCombination(3, (double *)c, f, f[z]);
    check_abs(diff(r[z], f[z]), 0.0, 0.0);
    N_Vector ry[2] = {r[1], r[2]}, fy[2] = {f[1], f[2]};
    N_Vector rz[2] = {pass ? r[1] : r[3], r[2]}, fz[2] = {pass ? f[1] : f[3], f[2]};
    N_VScaleAddMulti(2, (double *)c + 1, r[0], ry, rz);
    N_VScaleAddMulti(2, (double *)c + 1, f[0], fy, fz);
    check_abs(diff(rz[0], fz[0]), 0.0, 0.0);
    check_abs(diff(rz[1], fz[1]), 0.0, 0.0);
    check_abs(N_VWrmsNorm(r[0], r[1]) - N_VWrmsNorm(f[0], f[1]), 0.0, 0.0);
    check_abs(N_VMaxNorm(r[2]) - N_VMaxNorm(f[2]), 0.0, 0.0);
  }
  for (int k = 0; k < NV; ++k) {
    N_VDestroy(r[k]);
    N_VDestroy(f[k]);
  }
}

int main(void) {
  SUNContext ctx;
  if (!check_true(SUNContext_Create(NULL, &ctx) == 0)) return check_summary("test_dyn_nvec");
  uint64_t seed = 2385;
  const sunindextype lengths[] = {1, 3, 4, 5, 7, 8, 9, 13, 106, 107};
  for (size_t k = 0; k < sizeof lengths / sizeof lengths[0]; ++k)
    check_length(ctx, lengths[k], &seed);
  SUNContext_Free(&ctx);
  return check_summary("test_dyn_nvec");
}
