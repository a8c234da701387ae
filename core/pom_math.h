/* pom_math.h - 3-vectors, row-major 3x3 matrices, unit quaternions and ZYX
 * Euler angles.
 *
 * Conventions (docs/conventions.md):
 * - Vectors double v[3]; matrices row-major double M[9], M[3*r + c].
 * - A rotation matrix R maps body-frame components to fixed-frame ones:
 *   v_fixed = R v_body.
 * - Quaternions double q[4] = (w, x, y, z), unit norm, same rotation as R.
 * - ZYX Euler angles double e[3] = (psi, theta, phi) in radians: yaw psi about
 *   z, then pitch theta about the new y, then roll phi about the newest x:
 *   R = Rz(psi) Ry(theta) Rx(phi). Singular at theta = +-pi/2.
 * Outputs come first; outputs may not alias inputs unless stated. */
#ifndef POM_MATH_H
#define POM_MATH_H

#include "pom_status.h"

#include <math.h>

#define POM_PI  3.14159265358979323846
#define POM_DEG (POM_PI / 180.0) /* radians per degree */

/* ---- vectors ------------------------------------------------------------ */
static inline void pom_v3_set(double out[3], double x, double y, double z) {
  out[0] = x;
  out[1] = y;
  out[2] = z;
}
static inline void pom_v3_copy(double out[3], const double a[3]) {
  out[0] = a[0];
  out[1] = a[1];
  out[2] = a[2];
}
static inline void pom_v3_add(double out[3], const double a[3], const double b[3]) {
  out[0] = a[0] + b[0];
  out[1] = a[1] + b[1];
  out[2] = a[2] + b[2];
}
static inline void pom_v3_sub(double out[3], const double a[3], const double b[3]) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}
static inline void pom_v3_scale(double out[3], double s, const double a[3]) {
  out[0] = s * a[0];
  out[1] = s * a[1];
  out[2] = s * a[2];
}
/* out = a + s b (out may alias a) */
static inline void pom_v3_axpy(double out[3], const double a[3], double s, const double b[3]) {
  out[0] = a[0] + s * b[0];
  out[1] = a[1] + s * b[1];
  out[2] = a[2] + s * b[2];
}
static inline double pom_v3_dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
/* out = a x b (out must not alias a or b) */
static inline void pom_v3_cross(double out[3], const double a[3], const double b[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
static inline double pom_v3_norm(const double a[3]) {
  return sqrt(pom_v3_dot(a, a));
}
/* Normalizes a in place into out; returns the original norm (0 leaves out = a). */
double pom_v3_normalize(double out[3], const double a[3]);

/* ---- 3x3 matrices (row-major) ------------------------------------------- */
void pom_m3_identity(double M[9]);
void pom_m3_copy(double out[9], const double A[9]);
/* out = A B (out must not alias) */
void pom_m3_mul(double out[9], const double A[9], const double B[9]);
/* out = A^T B (out must not alias) */
void pom_m3_tmul(double out[9], const double A[9], const double B[9]);
/* out = A B^T (out must not alias) */
void pom_m3_mult(double out[9], const double A[9], const double B[9]);
void pom_m3_transpose(double out[9], const double A[9]);
/* out = A v (out must not alias v) */
void pom_m3_apply(double out[3], const double A[9], const double v[3]);
/* out = A^T v (out must not alias v) */
void pom_m3_tapply(double out[3], const double A[9], const double v[3]);
/* Skew-symmetric matrix with S b = a x b. */
void pom_m3_skew(double S[9], const double a[3]);
double pom_m3_det(const double A[9]);
/* Inverse by the adjugate; returns POM_ERR_SINGULAR when |det| <= tiny * ||A||^3
 * (tiny given by the caller, e.g. 1e-14), leaving out untouched. */
pom_status pom_m3_inverse(double out[9], const double A[9], double tiny);
/* Rotation about a unit axis by angle (rad), Rodrigues. */
void pom_m3_axis_angle(double R[9], const double axis[3], double angle);
/* Rotation vector (axis * angle, |angle| <= pi) of a rotation matrix. */
void pom_m3_rotvec(double rv[3], const double R[9]);
/* Singular values of a general 3x3 matrix, descending, via the symmetric
 * eigenproblem of A^T A (Jacobi rotations; accurate to ~1e-15 relative to the
 * largest). */
void pom_m3_singular_values(double sv[3], const double A[9]);
/* Eigen-decomposition of a symmetric 3x3 matrix S = V diag(w) V^T with the
 * eigenvalues descending and V orthonormal, columns = eigenvectors, det V = +1. */
void pom_m3_sym_eig(double w[3], double V[9], const double S[9]);

/* ---- ZYX Euler angles --------------------------------------------------- */
/* R = Rz(e[0]) Ry(e[1]) Rx(e[2]) */
void pom_euler_zyx_to_matrix(double R[9], const double e[3]);
/* pom_euler_zyx_to_matrix that also returns trig = (cos psi, sin psi,
 * cos theta, sin theta) for the Euler rate matrix of the same angles (the
 * dynamics' hot path); trig may be NULL. Bit-identical R. */
void pom_euler_zyx_to_matrix_trig(double R[9], double trig[4], const double e[3]);
/* Angles of R with theta in [-pi/2, pi/2]. At the singularity (|cos theta| <
 * 1e-12) psi + phi (or psi - phi) is what is defined: phi is set to 0 and the
 * return is POM_ERR_EULER_SINGULAR (the angles are still a valid
 * decomposition). POM_OK otherwise. */
pom_status pom_euler_zyx_from_matrix(double e[3], const double R[9]);
/* Matrix E with e_dot = E(e) omega, omega the angular velocity in the fixed
 * frame. Returns POM_ERR_EULER_SINGULAR (E untouched) when |cos theta| <
 * cos_min. */
pom_status pom_euler_zyx_rate_matrix(double E[9], const double e[3], double cos_min);

/* ---- unit quaternions (w, x, y, z) ------------------------------------- */
void pom_quat_identity(double q[4]);
void pom_quat_to_matrix(double R[9], const double q[4]);
/* Quaternion of a rotation matrix (Shepperd), with w >= 0. */
void pom_quat_from_matrix(double q[4], const double R[9]);
/* out = a b (composition: rotate by b, then a). out must not alias. */
void pom_quat_mul(double out[4], const double a[4], const double b[4]);
/* out = R(q) v */
void pom_quat_rotate(double out[3], const double q[4], const double v[3]);
void pom_quat_normalize(double q[4]);
/* q_dot for omega in the fixed frame: q_dot = 0.5 (0, omega) q. */
void pom_quat_rate(double qdot[4], const double q[4], const double omega_fixed[3]);
void pom_quat_from_euler_zyx(double q[4], const double e[3]);
pom_status pom_quat_to_euler_zyx(double e[3], const double q[4]);

/* ---- statistics ---------------------------------------------------------- */
/* The kernel-smoothed p-quantile of t[0..n-1] with a Gaussian kernel of
 * bandwidth h > 0 (docs/optimize.md 11.3): the q with
 * (1/n) sum_i Phi((q - t_i)/h) = p, 0 < p < 1, to 1e-15 relative; with w,
 * also dq/dt_i = phi(z_i) / sum_j phi(z_j) (the implicit-function theorem;
 * positive, summing to 1). NaN when n < 1. */
double pom_smooth_quantile(const double *t, int n, double p, double h, double *w);

#endif
