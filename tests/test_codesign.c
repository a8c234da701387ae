/* test_codesign.c - the co-design's pieces with known answers
 * (docs/optimize.md section 11): the smooth quantile (its defining
 * equation, its limit the order statistic, its implicit-function
 * derivative against central differences) and the actuator size law. */
#include "check.h"
#include "codesign_internal.h"
#include "pom_codesign.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double phi_cdf(double z) {
  return 0.5 * erfc(-z / sqrt(2.0));
}

static void test_quantile(void) {
  const double t[8] = {0.0121, 0.0093, 0.0170, 0.0102, 0.0135, 0.0088, 0.0149, 0.0111};
  const int n = 8;
  const double h = 1e-3, p = 0.95;
  double w[8];
  double q = pom_cds_smooth_quantile(t, n, p, h, w);
  /* the defining equation holds */
  double F = 0;
  for (int i = 0; i < n; ++i)
    F += phi_cdf((q - t[i]) / h);
  check_abs(F / n, p, 1e-12);
  /* weights: positive, summing to 1, equal to dq/dt_i by central
   * differences (step 1e-7 s: truncation ~ (1e-7/h)^2 relative, rounding
   * ~ 1e-16 q / 1e-7 ~ 2e-11) */
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    check_true(w[i] > 0);
    sum += w[i];
    double tp[8], tm[8];
    for (int j = 0; j < n; ++j)
      tp[j] = tm[j] = t[j];
    tp[i] += 1e-7;
    tm[i] -= 1e-7;
    double d =
        (pom_cds_smooth_quantile(tp, n, p, h, NULL) - pom_cds_smooth_quantile(tm, n, p, h, NULL)) /
        2e-7;
    check_abs(w[i], d, 1e-6);
  }
  check_abs(sum, 1.0, 1e-12);
  /* h -> 0: the order statistic. p = 0.95 of 8 lies between the 7th and
   * 8th smallest; F(q) = p then sits where Phi((q - t_(8))/h) = 8 p - 7 =
   * 0.6 with the seven others at 1: q = t_(8) + h Phi^-1(0.6) */
  double q0 = pom_cds_smooth_quantile(t, n, p, 1e-7, NULL);
  check_abs(q0, 0.0170 + 1e-7 * 0.2533471031357997, 1e-12);
  /* a constant sample: q = t + h Phi^-1(p) = t + 1.6448536 h */
  const double c[4] = {0.02, 0.02, 0.02, 0.02};
  check_abs(pom_cds_smooth_quantile(c, 4, 0.95, 1e-3, NULL), 0.02 + 1.6448536269514722e-3, 1e-12);
}

static void test_size_law(void) {
  /* K ~ s, R ~ 1/s, L ~ s, m ~ s^3, torque constant ~ s^2 (section 11.2) */
  check_rel(pom_cds_size_law(3.8, 1.0, 1.5), 5.7, 1e-15);
  check_rel(pom_cds_size_law(10.0, -1.0, 2.0), 5.0, 1e-15);
  check_rel(pom_cds_size_law(0.013, 3.0, 2.0), 0.104, 1e-15);
  check_rel(pom_cds_size_law(0.057, 2.0, 0.5), 0.01425, 1e-15);
  /* the motor constant K/sqrt(R) grows as s^1.5 */
  double s = 1.7;
  double km = pom_cds_size_law(3.8, 1.0, s) / sqrt(pom_cds_size_law(10.0, -1.0, s));
  check_rel(km, 3.8 / sqrt(10.0) * pow(s, 1.5), 1e-14);
}

/* The chain rule's key Jacobian against central differences of the size
 * law and the unit-box map (step 1e-6: truncation ~1e-12 relative). */
static void test_key_jacobian(void) {
  pom_cds_candidate cd;
  memset(&cd, 0, sizeof cd);
  cd.n_vars = 2;
  snprintf(cd.var[0].key, sizeof cd.var[0].key, "controller.kp");
  cd.var[0].lo = 1e3;
  cd.var[0].hi = 1e5;
  cd.var[0].log = 1;
  cd.var[1].kind = POM_CDS_VAR_SIZE;
  snprintf(cd.var[1].key, sizeof cd.var[1].key, "size");
  cd.var[1].lo = 0.5;
  cd.var[1].hi = 2.0;
  cd.var[1].log = 1;
  cd.n_sized = 2;
  snprintf(cd.sized[0].key, sizeof cd.sized[0].key, "actuator.resistance_ohm");
  cd.sized[0].exponent = -1.0;
  cd.sized[0].nominal = 10.0;
  snprintf(cd.sized[1].key, sizeof cd.sized[1].key, "inertia.piston.mass_kg");
  cd.sized[1].exponent = 3.0;
  cd.sized[1].nominal = 0.013;
  const char *key[POM_CDS_MAX_KEYS];
  double val[POM_CDS_MAX_KEYS], dv[POM_CDS_MAX_KEYS][POM_CDS_MAX_VARS];
  double x[2] = {1.2e4, 1.3};
  int n = pom_cds_design_keys(&cd, x, key, val, dv);
  check_true(n == 3);
  check_rel(val[1], 10.0 / 1.3, 1e-15);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k)
    for (int v = 0; v < 2; ++v) {
      double xp[2] = {x[0], x[1]}, xm[2] = {x[0], x[1]};
      double hv = h * x[v];
      xp[v] += hv;
      xm[v] -= hv;
      const char *kk[POM_CDS_MAX_KEYS];
      double vp[POM_CDS_MAX_KEYS], vm[POM_CDS_MAX_KEYS], d2[POM_CDS_MAX_KEYS][POM_CDS_MAX_VARS];
      pom_cds_design_keys(&cd, xp, kk, vp, d2);
      pom_cds_design_keys(&cd, xm, kk, vm, d2);
      check_abs(dv[k][v], (vp[k] - vm[k]) / (2 * hv), 1e-8 * fmax(1.0, fabs(dv[k][v])));
    }
  /* log map: x = 10^(log lo + u (log hi - log lo)), dx/du = x ln 10 (log hi - log lo) */
  double u = 0.37, du = 1e-7;
  double xa = pow(10.0, 3.0 + (u + du) * 2.0), xb = pow(10.0, 3.0 + (u - du) * 2.0);
  double xu = pow(10.0, 3.0 + u * 2.0);
  check_rel(pom_cds_dx_du(&cd.var[0], xu), (xa - xb) / (2 * du), 1e-8);
}

int main(void) {
  test_key_jacobian();
  test_quantile();
  test_size_law();
  return check_summary("test_codesign");
}
