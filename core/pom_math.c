/* pom_math.c - small dense linear algebra and rotation parameterizations
 * (derivations: docs/conventions.md). */
#include "pom_math.h"

#include <float.h>
#include <string.h>

double pom_v3_normalize(double out[3], const double a[3]) {
  double n = pom_v3_norm(a);
  if (n > 0.0) {
    pom_v3_scale(out, 1.0 / n, a);
  } else {
    pom_v3_copy(out, a);
  }
  return n;
}

/* ---- 3x3 matrices -------------------------------------------------------- */
void pom_m3_identity(double M[9]) {
  memset(M, 0, 9 * sizeof(double));
  M[0] = M[4] = M[8] = 1.0;
}

void pom_m3_copy(double out[9], const double A[9]) {
  memcpy(out, A, 9 * sizeof(double));
}

void pom_m3_mul(double out[9], const double A[9], const double B[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] = A[3 * r] * B[c] + A[3 * r + 1] * B[3 + c] + A[3 * r + 2] * B[6 + c];
}

void pom_m3_tmul(double out[9], const double A[9], const double B[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] = A[r] * B[c] + A[3 + r] * B[3 + c] + A[6 + r] * B[6 + c];
}

void pom_m3_mult(double out[9], const double A[9], const double B[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] =
          A[3 * r] * B[3 * c] + A[3 * r + 1] * B[3 * c + 1] + A[3 * r + 2] * B[3 * c + 2];
}

void pom_m3_transpose(double out[9], const double A[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * c + r] = A[3 * r + c];
}

void pom_m3_apply(double out[3], const double A[9], const double v[3]) {
  out[0] = A[0] * v[0] + A[1] * v[1] + A[2] * v[2];
  out[1] = A[3] * v[0] + A[4] * v[1] + A[5] * v[2];
  out[2] = A[6] * v[0] + A[7] * v[1] + A[8] * v[2];
}

void pom_m3_tapply(double out[3], const double A[9], const double v[3]) {
  out[0] = A[0] * v[0] + A[3] * v[1] + A[6] * v[2];
  out[1] = A[1] * v[0] + A[4] * v[1] + A[7] * v[2];
  out[2] = A[2] * v[0] + A[5] * v[1] + A[8] * v[2];
}

void pom_m3_skew(double S[9], const double a[3]) {
  S[0] = 0.0;
  S[1] = -a[2];
  S[2] = a[1];
  S[3] = a[2];
  S[4] = 0.0;
  S[5] = -a[0];
  S[6] = -a[1];
  S[7] = a[0];
  S[8] = 0.0;
}

double pom_m3_det(const double A[9]) {
  return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
         A[2] * (A[3] * A[7] - A[4] * A[6]);
}

pom_status pom_m3_inverse(double out[9], const double A[9], double tiny) {
  double det = pom_m3_det(A);
  double scale = 0.0;
  for (int k = 0; k < 9; ++k)
    scale = fmax(scale, fabs(A[k]));
  if (!(fabs(det) > tiny * scale * scale * scale)) return POM_ERR_SINGULAR;
  double inv = 1.0 / det;
  double t[9];
  t[0] = (A[4] * A[8] - A[5] * A[7]) * inv;
  t[1] = (A[2] * A[7] - A[1] * A[8]) * inv;
  t[2] = (A[1] * A[5] - A[2] * A[4]) * inv;
  t[3] = (A[5] * A[6] - A[3] * A[8]) * inv;
  t[4] = (A[0] * A[8] - A[2] * A[6]) * inv;
  t[5] = (A[2] * A[3] - A[0] * A[5]) * inv;
  t[6] = (A[3] * A[7] - A[4] * A[6]) * inv;
  t[7] = (A[1] * A[6] - A[0] * A[7]) * inv;
  t[8] = (A[0] * A[4] - A[1] * A[3]) * inv;
  memcpy(out, t, sizeof t);
  return POM_OK;
}

void pom_m3_axis_angle(double R[9], const double axis[3], double angle) {
  double c = cos(angle), s = sin(angle), v = 1.0 - c;
  double x = axis[0], y = axis[1], z = axis[2];
  R[0] = c + x * x * v;
  R[1] = x * y * v - z * s;
  R[2] = x * z * v + y * s;
  R[3] = y * x * v + z * s;
  R[4] = c + y * y * v;
  R[5] = y * z * v - x * s;
  R[6] = z * x * v - y * s;
  R[7] = z * y * v + x * s;
  R[8] = c + z * z * v;
}

void pom_m3_rotvec(double rv[3], const double R[9]) {
  double q[4];
  pom_quat_from_matrix(q, R);
  double sn = sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (sn == 0.0) {
    pom_v3_set(rv, 0.0, 0.0, 0.0);
    return;
  }
  double angle = 2.0 * atan2(sn, q[0]);
  pom_v3_set(rv, q[1] * angle / sn, q[2] * angle / sn, q[3] * angle / sn);
}

/* Cyclic Jacobi: rotations until every off-diagonal entry is negligible
 * against the diagonal at double precision. */
void pom_m3_sym_eig(double w[3], double V[9], const double S[9]) {
  double a[9];
  memcpy(a, S, sizeof a);
  pom_m3_identity(V);
  for (int sweep = 0; sweep < 64; ++sweep) {
    double off = fabs(a[1]) + fabs(a[2]) + fabs(a[5]);
    if (off == 0.0) break;
    int changed = 0;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        double apq = a[3 * p + q];
        double app = a[3 * p + p], aqq = a[3 * q + q];
        if (fabs(apq) <= DBL_EPSILON * 0.5 * (fabs(app) + fabs(aqq)) || apq == 0.0) {
          a[3 * p + q] = a[3 * q + p] = 0.0;
          continue;
        }
        changed = 1;
        double theta = (aqq - app) / (2.0 * apq);
        double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {
          double akp = a[3 * k + p], akq = a[3 * k + q];
          a[3 * k + p] = c * akp - s * akq;
          a[3 * k + q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          double apk = a[3 * p + k], aqk = a[3 * q + k];
          a[3 * p + k] = c * apk - s * aqk;
          a[3 * q + k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          double vkp = V[3 * k + p], vkq = V[3 * k + q];
          V[3 * k + p] = c * vkp - s * vkq;
          V[3 * k + q] = s * vkp + c * vkq;
        }
      }
    }
    if (!changed) break;
  }
  w[0] = a[0];
  w[1] = a[4];
  w[2] = a[8];
  /* sort descending, permuting columns of V */
  for (int i = 0; i < 2; ++i) {
    int m = i;
    for (int j = i + 1; j < 3; ++j)
      if (w[j] > w[m]) m = j;
    if (m != i) {
      double t = w[i];
      w[i] = w[m];
      w[m] = t;
      for (int k = 0; k < 3; ++k) {
        double v = V[3 * k + i];
        V[3 * k + i] = V[3 * k + m];
        V[3 * k + m] = v;
      }
    }
  }
  if (pom_m3_det(V) < 0.0)
    for (int k = 0; k < 3; ++k)
      V[3 * k + 2] = -V[3 * k + 2];
}

void pom_m3_singular_values(double sv[3], const double A[9]) {
  double AtA[9], V[9], w[3];
  pom_m3_tmul(AtA, A, A);
  pom_m3_sym_eig(w, V, AtA);
  for (int k = 0; k < 3; ++k)
    sv[k] = w[k] > 0.0 ? sqrt(w[k]) : 0.0;
}

/* ---- ZYX Euler angles ------------------------------------------------------ */
void pom_euler_zyx_to_matrix_trig(double R[9], double trig[4], const double e[3]) {
  double cps = cos(e[0]), sps = sin(e[0]);
  double cth = cos(e[1]), sth = sin(e[1]);
  double cph = cos(e[2]), sph = sin(e[2]);
  R[0] = cps * cth;
  R[1] = cps * sth * sph - sps * cph;
  R[2] = cps * sth * cph + sps * sph;
  R[3] = sps * cth;
  R[4] = sps * sth * sph + cps * cph;
  R[5] = sps * sth * cph - cps * sph;
  R[6] = -sth;
  R[7] = cth * sph;
  R[8] = cth * cph;
  if (trig) {
    trig[0] = cps;
    trig[1] = sps;
    trig[2] = cth;
    trig[3] = sth;
  }
}

void pom_euler_zyx_to_matrix(double R[9], const double e[3]) {
  pom_euler_zyx_to_matrix_trig(R, NULL, e);
}

pom_status pom_euler_zyx_from_matrix(double e[3], const double R[9]) {
  double cth = sqrt(R[0] * R[0] + R[3] * R[3]);
  e[1] = atan2(-R[6], cth);
  if (cth < 1e-12) {
    /* Gimbal lock: only psi -+ phi is defined; put it all in psi. */
    e[2] = 0.0;
    e[0] = atan2(-R[1], R[4]);
    return POM_ERR_EULER_SINGULAR;
  }
  e[0] = atan2(R[3], R[0]);
  e[2] = atan2(R[7], R[8]);
  return POM_OK;
}

pom_status pom_euler_zyx_rate_matrix(double E[9], const double e[3], double cos_min) {
  double cps = cos(e[0]), sps = sin(e[0]);
  double cth = cos(e[1]), sth = sin(e[1]);
  if (fabs(cth) < cos_min) return POM_ERR_EULER_SINGULAR;
  double tth = sth / cth;
  E[0] = cps * tth;
  E[1] = sps * tth;
  E[2] = 1.0;
  E[3] = -sps;
  E[4] = cps;
  E[5] = 0.0;
  E[6] = cps / cth;
  E[7] = sps / cth;
  E[8] = 0.0;
  return POM_OK;
}

/* ---- quaternions ---------------------------------------------------------- */
void pom_quat_identity(double q[4]) {
  q[0] = 1.0;
  q[1] = q[2] = q[3] = 0.0;
}

void pom_quat_to_matrix(double R[9], const double q[4]) {
  double w = q[0], x = q[1], y = q[2], z = q[3];
  R[0] = 1.0 - 2.0 * (y * y + z * z);
  R[1] = 2.0 * (x * y - w * z);
  R[2] = 2.0 * (x * z + w * y);
  R[3] = 2.0 * (x * y + w * z);
  R[4] = 1.0 - 2.0 * (x * x + z * z);
  R[5] = 2.0 * (y * z - w * x);
  R[6] = 2.0 * (x * z - w * y);
  R[7] = 2.0 * (y * z + w * x);
  R[8] = 1.0 - 2.0 * (x * x + y * y);
}

void pom_quat_from_matrix(double q[4], const double R[9]) {
  double tr = R[0] + R[4] + R[8];
  if (tr >= R[0] && tr >= R[4] && tr >= R[8]) {
    double s = 2.0 * sqrt(1.0 + tr);
    q[0] = 0.25 * s;
    q[1] = (R[7] - R[5]) / s;
    q[2] = (R[2] - R[6]) / s;
    q[3] = (R[3] - R[1]) / s;
  } else if (R[0] >= R[4] && R[0] >= R[8]) {
    double s = 2.0 * sqrt(1.0 + R[0] - R[4] - R[8]);
    q[0] = (R[7] - R[5]) / s;
    q[1] = 0.25 * s;
    q[2] = (R[1] + R[3]) / s;
    q[3] = (R[2] + R[6]) / s;
  } else if (R[4] >= R[8]) {
    double s = 2.0 * sqrt(1.0 + R[4] - R[0] - R[8]);
    q[0] = (R[2] - R[6]) / s;
    q[1] = (R[1] + R[3]) / s;
    q[2] = 0.25 * s;
    q[3] = (R[5] + R[7]) / s;
  } else {
    double s = 2.0 * sqrt(1.0 + R[8] - R[0] - R[4]);
    q[0] = (R[3] - R[1]) / s;
    q[1] = (R[2] + R[6]) / s;
    q[2] = (R[5] + R[7]) / s;
    q[3] = 0.25 * s;
  }
  if (q[0] < 0.0)
    for (int k = 0; k < 4; ++k)
      q[k] = -q[k];
  pom_quat_normalize(q);
}

void pom_quat_mul(double out[4], const double a[4], const double b[4]) {
  out[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
  out[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
  out[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
  out[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}

void pom_quat_rotate(double out[3], const double q[4], const double v[3]) {
  double R[9];
  pom_quat_to_matrix(R, q);
  pom_m3_apply(out, R, v);
}

void pom_quat_normalize(double q[4]) {
  double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (n > 0.0)
    for (int k = 0; k < 4; ++k)
      q[k] /= n;
}

void pom_quat_rate(double qdot[4], const double q[4], const double omega_fixed[3]) {
  double wq[4] = {0.0, omega_fixed[0], omega_fixed[1], omega_fixed[2]};
  pom_quat_mul(qdot, wq, q);
  for (int k = 0; k < 4; ++k)
    qdot[k] *= 0.5;
}

void pom_quat_from_euler_zyx(double q[4], const double e[3]) {
  double R[9];
  pom_euler_zyx_to_matrix(R, e);
  pom_quat_from_matrix(q, R);
}

pom_status pom_quat_to_euler_zyx(double e[3], const double q[4]) {
  double R[9];
  pom_quat_to_matrix(R, q);
  return pom_euler_zyx_from_matrix(e, R);
}

/* ---- statistics ------------------------------------------------------------ */
static double phi_cdf(double z) {
  return 0.5 * erfc(-z / sqrt(2.0));
}

double pom_smooth_quantile(const double *t, int n, double p, double h, double *w) {
  if (n < 1) return NAN;
  double lo = t[0], hi = t[0];
  for (int i = 1; i < n; ++i) {
    lo = fmin(lo, t[i]);
    hi = fmax(hi, t[i]);
  }
  /* F(q) = (1/n) sum Phi((q - t_i)/h) is increasing from 0 to 1: bisection on
   * a bracket that holds the root, then Newton polish */
  lo -= 10.0 * h;
  hi += 10.0 * h;
  double q = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    q = 0.5 * (lo + hi);
    double F = 0.0;
    for (int i = 0; i < n; ++i)
      F += phi_cdf((q - t[i]) / h);
    F /= n;
    if (F < p)
      lo = q;
    else
      hi = q;
    if (hi - lo <= 1e-15 * fmax(1.0, fabs(q))) break;
  }
  if (w) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) {
      double z = (q - t[i]) / h;
      w[i] = exp(-0.5 * z * z);
      s += w[i];
    }
    for (int i = 0; i < n; ++i)
      w[i] = s > 0 ? w[i] / s : 1.0 / n;
  }
  return q;
}
