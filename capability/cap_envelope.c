/* cap_envelope.c - the acceleration polytope and the steady-rate limit at one
 * pose (docs/capability.md sections 2 and 3): pure functions of the rigid
 * terms, no model. */
#include "pom_capability.h"

#include "pom_math.h"

#include <math.h>
#include <string.h>

/* J is treated as singular below this ratio of its determinant to the cube
 * of its largest entry (the grid never comes near: dexterity >= 0.3). */
#define CAP_SINGULAR 1e-12

/* out = J^-T (row-major); 0 when J is singular. */
static int inverse_transpose(double out[9], const double J[9]) {
  double Ji[9], big = 0.0;
  for (int k = 0; k < 9; ++k)
    big = fmax(big, fabs(J[k]));
  if (!(big > 0) || pom_m3_inverse(Ji, J, CAP_SINGULAR * big * big * big) != POM_OK) return 0;
  pom_m3_transpose(out, Ji);
  return 1;
}

/* ---- acceleration from rest (section 2) ------------------------------------- */
double pom_cap_acc_along(const double M[9], const double J[9], const double g[3], double f_max,
                         const double d[3]) {
  double JiT[9], B[9], gamma[3], b[3];
  if (!inverse_transpose(JiT, J)) return NAN;
  pom_m3_mul(B, JiT, M);
  pom_m3_apply(gamma, JiT, g);
  pom_m3_apply(b, B, d);
  double s = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (!(fabs(gamma[a]) < f_max)) return 0.0; /* cannot hold the pose */
    if (b[a] == 0.0) continue;
    s = fmin(s, (f_max + (b[a] > 0 ? gamma[a] : -gamma[a])) / fabs(b[a]));
  }
  return s;
}

double pom_cap_acc_inscribed(const double M[9], const double J[9], const double g[3], double f_max,
                             double worst[3]) {
  double JiT[9], B[9], gamma[3];
  if (!inverse_transpose(JiT, J)) return NAN;
  pom_m3_mul(B, JiT, M);
  pom_m3_apply(gamma, JiT, g);
  double r = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const double *Ba = B + 3 * a, n = pom_v3_norm(Ba);
    double ra = (f_max - fabs(gamma[a])) / n;
    if (ra < r) {
      r = ra;
      /* towards the nearer facet B_a x = gamma_a - sign(gamma_a) f_max */
      if (worst) pom_v3_scale(worst, (gamma[a] > 0 ? -1.0 : 1.0) / n, Ba);
    }
  }
  return r > 0 ? r : 0.0;
}

/* ---- steady rate (section 3) ------------------------------------------------ */
/* Smallest root s > 0 of c2 s^2 + c1 s + c0 = 0 (INFINITY when none), by the
 * cancellation-free form of the quadratic formula. */
static double smallest_positive_root(double c2, double c1, double c0) {
  double best = INFINITY;
  if (c2 == 0.0) {
    if (c1 != 0.0) {
      double s = -c0 / c1;
      if (s > 0) best = s;
    }
    return best;
  }
  double disc = c1 * c1 - 4.0 * c2 * c0;
  if (disc < 0) return best;
  double qq = -0.5 * (c1 + copysign(sqrt(disc), c1));
  double r[2] = {qq / c2, qq != 0.0 ? c0 / qq : 0.0};
  for (int k = 0; k < 2; ++k)
    if (r[k] > 0 && r[k] < best) best = r[k];
  return best;
}

/* Smallest s > 0 with |c2 s^2 + c1 s + c0| = lim (0 when already beyond). */
static double first_crossing(double c2, double c1, double c0, double lim) {
  if (!(fabs(c0) < lim)) return 0.0;
  return fmin(smallest_positive_root(c2, c1, c0 - lim), smallest_positive_root(c2, c1, c0 + lim));
}

double pom_cap_rate_along(const pom_cap_rate_model *rm, const double d[3], int *binding) {
  double JiT[9], gamma[3], h[3] = {0.0, 0.0, 0.0}, eta[3], Jd[3];
  if (binding) *binding = -1;
  if (!inverse_transpose(JiT, rm->J)) return NAN;
  pom_m3_apply(gamma, JiT, rm->gravity);
  if (!rm->no_velocity_terms)
    for (int k = 0; k < 3; ++k) {
      double Hd[3];
      pom_m3_apply(Hd, rm->H[k], d);
      h[k] = pom_v3_dot(d, Hd);
    }
  pom_m3_apply(eta, JiT, h);
  pom_m3_apply(Jd, rm->J, d);
  double best = INFINITY;
  for (int a = 0; a < 3; ++a) {
    /* i_a(s) = (-gamma_a - s^2 eta_a + b s Jd_a) / K; u_a = R_c i_a + K s Jd_a */
    const double i0 = -gamma[a] / rm->K, i1 = rm->b * Jd[a] / rm->K, i2 = -eta[a] / rm->K;
    double s = first_crossing(rm->Rc * i2, rm->Rc * i1 + rm->K * Jd[a], rm->Rc * i0, rm->V);
    if (s < best) {
      best = s;
      if (binding) *binding = a;
    }
    if (rm->I_max > 0) {
      s = first_crossing(i2, i1, i0, rm->I_max);
      if (s < best) {
        best = s;
        if (binding) *binding = a + 3;
      }
    }
  }
  return best;
}

/* The rate along d normalized first. */
static double rate_at(const pom_cap_rate_model *rm, const double v[3], double d[3]) {
  pom_v3_normalize(d, v);
  return pom_cap_rate_along(rm, d, NULL);
}

double pom_cap_rate_inscribed(const pom_cap_rate_model *rm, int n, double worst[3]) {
  double best = INFINITY, bd[3] = {0.0, 0.0, 1.0};
  if (n < 1) n = 1;
  /* Fibonacci sphere: near-uniform points, no clustering at the poles */
  const double golden = POM_PI * (3.0 - sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    double z = 1.0 - (2.0 * k + 1.0) / n, rr = sqrt(fmax(0.0, 1.0 - z * z));
    double d[3] = {rr * cos(golden * k), rr * sin(golden * k), z};
    double s = pom_cap_rate_along(rm, d, NULL);
    if (s < best) {
      best = s;
      pom_v3_copy(bd, d);
    }
  }
  /* pattern search on the sphere from the best point: the spacing of the
   * points first, halved when no move improves */
  double delta = sqrt(4.0 * POM_PI / n);
  while (delta > 1e-9 && isfinite(best)) {
    double t1[3], t2[3], e[3] = {1.0, 0.0, 0.0};
    if (fabs(bd[0]) > 0.9) e[0] = 0.0, e[1] = 1.0;
    pom_v3_cross(t1, bd, e);
    pom_v3_normalize(t1, t1);
    pom_v3_cross(t2, bd, t1);
    int moved = 0;
    const double *dirs[2] = {t1, t2};
    for (int k = 0; k < 4 && !moved; ++k) {
      double v[3], d[3];
      pom_v3_axpy(v, bd, (k & 1 ? -delta : delta), dirs[k >> 1]);
      double s = rate_at(rm, v, d);
      if (s < best) {
        best = s;
        pom_v3_copy(bd, d);
        moved = 1;
      }
    }
    if (!moved) delta *= 0.5;
  }
  if (worst) pom_v3_copy(worst, bd);
  return best;
}
