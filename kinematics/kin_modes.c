/* kin_modes.c - all solutions: the working modes (one IK root per limb) at
 * a rotation and the assembly modes (FK roots) at actuator coordinates, for
 * any architecture through its flip_branch operation
 * (docs/kinematics-modes.md). */
#include "pom_kinematics.h"

#include "pom_arch.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>

void pom_kin_fk_all_defaults(pom_kin_fk_all_opts *o) {
  o->seeds = 128;
  o->residual_tol = 1e-12;
  o->max_iterations = 60;
  o->max_rotation = 0.3;
  o->same_tol = 1e-7;
  o->singular_tol = 1e-9;
}

int pom_kin_two_root_limbs(const pom_kin_arch *arch, int two_roots[3]) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    pom_kin_arch tmp = *arch;
    two_roots[i] = arch->type->flip_branch ? arch->type->flip_branch(&tmp, i) : 0;
    n += two_roots[i];
  }
  return n;
}

pom_status pom_kin_arch_with_branches(pom_kin_arch *out, const pom_kin_arch *arch,
                                      const int branch[3], pom_error *err) {
  *out = *arch;
  for (int i = 0; i < 3; ++i) {
    if (branch[i] == 1) continue;
    if (branch[i] != -1)
      POM_FAIL(err, POM_ERR_ARG, "working mode: branch %d of limb %d must be +1 or -1", branch[i],
               i + 1);
    if (!(arch->type->flip_branch && arch->type->flip_branch(out, i)))
      POM_FAIL(err, POM_ERR_ARG, "working mode: limb %d of %s has a single IK root (branch +1)",
               i + 1, arch->type->name);
  }
  return POM_OK;
}

/* Actuator difference a - b: wrapped to [-pi, pi] for rotary actuators. */
static double q_diff(int rotary, double a, double b) {
  double d = a - b;
  return rotary ? remainder(d, 2.0 * POM_PI) : d;
}

/* Fills everything of m but R, branch and residual (set by the caller) on
 * the working mode ab (arch with m->branch applied). */
static void mode_evaluate(const pom_kin_arch *ab, double singular_tol, pom_kin_mode *m) {
  m->status = pom_kin_pose_evaluate(ab, m->R, &m->pose, NULL);
  m->det = 0.0;
  m->det_unit = 0.0;
  m->serial = 0;
  m->parallel = 0;
  if (!m->pose.reachable) return;
  const double *J = m->pose.J;
  double N[9];
  for (int i = 0; i < 3; ++i) {
    double n = pom_v3_norm(J + 3 * i);
    for (int k = 0; k < 3; ++k)
      N[3 * i + k] = n > 0.0 ? J[3 * i + k] / n : 0.0;
  }
  m->det = pom_m3_det(J);
  m->det_unit = pom_m3_det(N);
  m->parallel = !(fabs(m->det_unit) > singular_tol);
  /* leg singularity: the pose's own criterion, the limb's transmission index
   * (where two IK roots meet it is 0; docs/kinematics-tables.md 3.2) */
  m->serial = m->pose.serial_limbs;
}

/* The branches of working mode k (binary, limb 1 slowest, +1 before -1)
 * over the limbs with two roots. */
static void mode_branches(int k, const int two[3], int n2, int branch[3]) {
  int bit = n2 - 1;
  for (int i = 0; i < 3; ++i) {
    if (!two[i]) {
      branch[i] = 0;
      continue;
    }
    branch[i] = (k >> bit) & 1 ? -1 : 1;
    --bit;
  }
}

pom_status pom_kin_inverse_all(const pom_kin_arch *arch, const double R[9], pom_kin_mode modes[8],
                               int *n, pom_error *err) {
  *n = 0;
  for (int k = 0; k < 9; ++k)
    if (!isfinite(R[k])) POM_FAIL(err, POM_ERR_NONFINITE, "working modes: R is not finite");
  int two[3];
  const int n2 = pom_kin_two_root_limbs(arch, two);
  const pom_kin_fk_all_opts def = {0, 0.0, 0, 0.0, 0.0, 1e-9};
  for (int k = 0; k < (1 << n2); ++k) {
    pom_kin_mode *m = &modes[k];
    memset(m, 0, sizeof *m);
    memcpy(m->R, R, sizeof m->R);
    mode_branches(k, two, n2, m->branch);
    int b[3];
    for (int i = 0; i < 3; ++i)
      b[i] = m->branch[i] ? m->branch[i] : 1;
    pom_kin_arch ab;
    pom_status st = pom_kin_arch_with_branches(&ab, arch, b, err);
    if (st != POM_OK) return st;
    mode_evaluate(&ab, def.singular_tol, m);
  }
  *n = 1 << n2;
  return POM_OK;
}

/* Radical inverse of k in base b (Halton sequence). */
static double halton(unsigned k, unsigned b) {
  double f = 1.0, r = 0.0;
  while (k > 0) {
    f /= b;
    r += f * (double)(k % b);
    k /= b;
  }
  return r;
}

/* Start rotation k: k = 0 home, else a quasi-uniform unit quaternion
 * (Shoemake's map of the Halton point in bases 2, 3, 5). */
static void seed_rotation(int k, double R[9]) {
  if (k == 0) {
    pom_m3_identity(R);
    return;
  }
  const unsigned u = (unsigned)k;
  double u1 = halton(u, 2), u2 = halton(u, 3), u3 = halton(u, 5);
  double a = sqrt(1.0 - u1), b = sqrt(u1), q[4];
  q[0] = b * cos(2.0 * POM_PI * u3);
  q[1] = a * sin(2.0 * POM_PI * u2);
  q[2] = a * cos(2.0 * POM_PI * u2);
  q[3] = b * sin(2.0 * POM_PI * u3);
  pom_quat_to_matrix(R, q);
}

/* max_i |q_i(R) - target_i| on working mode ab; INFINITY when unreachable. */
static double residual_at(const pom_kin_arch *ab, const double target[3], const double R[9],
                          double r[3], double J[9]) {
  double q[3];
  pom_status st = J ? pom_kin_inverse_jacobian(ab, R, q, J, NULL) : pom_kin_inverse(ab, R, q, NULL);
  if (st != POM_OK) return INFINITY;
  const int rotary = pom_kin_type_actuator(ab->type) == POM_ACT_REVOLUTE;
  double m = 0.0;
  for (int k = 0; k < 3; ++k) {
    double d = q_diff(rotary, target[k], q[k]);
    if (r) r[k] = d;
    m = fmax(m, fabs(d));
  }
  return m;
}

/* Damped Newton on SO(3) from R (updated in place): R <- exp([t delta]) R
 * with J delta = q_target - q(R), |t delta| <= max_rotation, t halved until
 * the residual falls. Returns 1 converged (*res the residual), 0 not. */
static int newton_damped(const pom_kin_arch *ab, const double target[3], double R[9],
                         const pom_kin_fk_all_opts *o, double *res) {
  double r[3], J[9];
  double m = residual_at(ab, target, R, r, J);
  for (int it = 0; it < o->max_iterations; ++it) {
    if (!isfinite(m)) return 0;
    if (m <= o->residual_tol) {
      *res = m;
      return 1;
    }
    double Ji[9], delta[3];
    if (pom_m3_inverse(Ji, J, 0.0) != POM_OK) return 0;
    pom_m3_apply(delta, Ji, r);
    double angle = pom_v3_norm(delta);
    if (!(angle > 0.0) || !isfinite(angle)) return 0;
    double axis[3], step = fmin(angle, o->max_rotation);
    pom_v3_scale(axis, 1.0 / angle, delta);
    int accepted = 0;
    for (int h = 0; h < 12 && !accepted; ++h, step *= 0.5) {
      double E[9], Rn[9], rn[3], Jn[9];
      pom_m3_axis_angle(E, axis, step);
      pom_m3_mul(Rn, E, R); /* omega in the fixed frame: left multiplication */
      double mn = residual_at(ab, target, Rn, rn, Jn);
      if (mn < m) {
        memcpy(R, Rn, sizeof Rn);
        memcpy(r, rn, sizeof rn);
        memcpy(J, Jn, sizeof Jn);
        m = mn;
        accepted = 1;
      }
    }
    if (!accepted) return 0;
  }
  *res = m;
  return m <= o->residual_tol;
}

/* Rotation angle between A and B (rad). */
static double rotation_distance(const double A[9], const double B[9]) {
  double D[9], rv[3];
  pom_m3_tmul(D, A, B);
  pom_m3_rotvec(rv, D);
  return pom_v3_norm(rv);
}

static double rotation_angle(const double R[9]) {
  double rv[3];
  pom_m3_rotvec(rv, R);
  return pom_v3_norm(rv);
}

pom_status pom_kin_forward_all(const pom_kin_arch *arch, const double q[3],
                               const pom_kin_fk_all_opts *opts, pom_kin_mode *modes, int cap,
                               int *n, pom_error *err) {
  pom_kin_fk_all_opts o;
  if (opts) {
    o = *opts;
  } else {
    pom_kin_fk_all_defaults(&o);
  }
  *n = 0;
  if (cap < POM_KIN_MAX_MODES)
    POM_FAIL(err, POM_ERR_ARG, "assembly modes: room for %d modes, %d needed", cap,
             POM_KIN_MAX_MODES);
  if (o.seeds < 1 || !(o.residual_tol > 0.0) || o.max_iterations < 1 || !(o.max_rotation > 0.0) ||
      !(o.same_tol > 0.0) || !(o.singular_tol >= 0.0))
    POM_FAIL(err, POM_ERR_ARG, "assembly modes: invalid options");
  for (int k = 0; k < 3; ++k)
    if (!isfinite(q[k])) POM_FAIL(err, POM_ERR_NONFINITE, "assembly modes: q[%d] is not finite", k);
  int two[3];
  const int n2 = pom_kin_two_root_limbs(arch, two);
  int count = 0;
  for (int k = 0; k < (1 << n2); ++k) {
    int branch[3], b[3];
    mode_branches(k, two, n2, branch);
    for (int i = 0; i < 3; ++i)
      b[i] = branch[i] ? branch[i] : 1;
    pom_kin_arch ab;
    pom_status st = pom_kin_arch_with_branches(&ab, arch, b, err);
    if (st != POM_OK) return st;
    for (int s = 0; s < o.seeds; ++s) {
      double R[9], res = INFINITY;
      seed_rotation(s, R);
      if (!newton_damped(&ab, q, R, &o, &res)) continue;
      int known = 0;
      for (int j = 0; j < count && !known; ++j)
        known = rotation_distance(modes[j].R, R) < o.same_tol;
      if (known) continue;
      if (count == cap || count == POM_KIN_MAX_MODES) {
        *n = count;
        POM_FAIL(err, POM_ERR_NOCONVERGE,
                 "assembly modes: more than %d distinct orientations give q = (%.6g, %.6g, "
                 "%.6g): a continuum of solutions (self-motion)",
                 POM_KIN_MAX_MODES, q[0], q[1], q[2]);
      }
      pom_kin_mode *m = &modes[count++];
      memset(m, 0, sizeof *m);
      memcpy(m->R, R, sizeof m->R);
      memcpy(m->branch, branch, sizeof m->branch);
      m->residual = res;
      mode_evaluate(&ab, o.singular_tol, m);
    }
  }
  /* sort by rotation angle from home (insertion sort: at most 64) */
  for (int i = 1; i < count; ++i) {
    pom_kin_mode t = modes[i];
    double a = rotation_angle(t.R);
    int j = i - 1;
    while (j >= 0 && rotation_angle(modes[j].R) > a) {
      modes[j + 1] = modes[j];
      --j;
    }
    modes[j + 1] = t;
  }
  *n = count;
  return POM_OK;
}
