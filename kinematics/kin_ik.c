/* kin_ik.c - closed-form inverse kinematics on the home branch, the Jacobian,
 * dexterity and the limit checks (docs/kinematics.md sections 3 and 5). */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- inverse kinematics and Jacobian --------------------------------------- */
/* q and J of all limbs (and, with J, the transmission indices tr when
 * non-NULL); outputs untouched on failure, *bad = failing limb. */
static pom_status ik_rows(const pom_kin_arch *arch, const double R[9], double q[3], double J[9],
                          double tr[3], int *bad, pom_error *err) {
  double qq[3], JJ[9], tt[3] = {1.0, 1.0, 1.0};
  if (tr) memcpy(tt, tr, sizeof tt); /* kept where a limb op does not write it */
  for (int i = 0; i < 3; ++i) {
    int ok = arch->type->limb(arch, i, R, &qq[i], J ? JJ + 3 * i : NULL, tr ? tt + i : NULL);
    if (!ok) {
      /* a NaN/Inf rotation also fails the reach tests above: say so, not
       * "unreachable" (checked here only, off the hot path) */
      for (int k = 0; k < 9; ++k)
        if (!isfinite(R[k]))
          POM_FAIL(err, POM_ERR_NONFINITE, "inverse kinematics: rotation entry R[%d] = %g", k,
                   R[k]);
      if (bad) *bad = i;
      POM_FAIL(err, POM_ERR_UNREACHABLE, "limb %d: %s", i + 1, arch->type->unreachable);
    }
  }
  if (q) memcpy(q, qq, sizeof qq);
  if (J) memcpy(J, JJ, sizeof JJ);
  if (tr) memcpy(tr, tt, sizeof tt);
  return POM_OK;
}

pom_status pom_kin_inverse(const pom_kin_arch *arch, const double R[9], double q[3],
                           pom_error *err) {
  return ik_rows(arch, R, q, NULL, NULL, NULL, err);
}

pom_status pom_kin_jacobian(const pom_kin_arch *arch, const double R[9], double J[9],
                            pom_error *err) {
  return ik_rows(arch, R, NULL, J, NULL, NULL, err);
}

pom_status pom_kin_inverse_jacobian(const pom_kin_arch *arch, const double R[9], double q[3],
                                    double J[9], pom_error *err) {
  return ik_rows(arch, R, q, J, NULL, NULL, err);
}

/* Eigenvalues (descending) of a symmetric 3x3 matrix in closed form: the
 * trigonometric solution of the characteristic cubic (docs/kinematics.md
 * 3.4). Absolute error ~1e-16 |S|, growing to ~1e-8 |S| for a (near-)double
 * eigenvalue, where the cubic's root is ill-conditioned. */
static void sym3_eigenvalues(double w[3], const double S[9]) {
  double p1 = S[1] * S[1] + S[2] * S[2] + S[5] * S[5];
  double q = (S[0] + S[4] + S[8]) / 3.0;
  double d0 = S[0] - q, d1 = S[4] - q, d2 = S[8] - q;
  double p2 = d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * p1;
  if (p2 == 0.0) {
    w[0] = w[1] = w[2] = q;
    return;
  }
  double p = sqrt(p2 / 6.0), ip = 1.0 / p;
  /* B = (S - q I) / p; r = det(B) / 2 in [-1, 1] */
  double b0 = d0 * ip, b4 = d1 * ip, b8 = d2 * ip, b1 = S[1] * ip, b2 = S[2] * ip, b5 = S[5] * ip;
  double r = 0.5 * (b0 * (b4 * b8 - b5 * b5) - b1 * (b1 * b8 - b5 * b2) + b2 * (b1 * b5 - b4 * b2));
  r = r < -1.0 ? -1.0 : r > 1.0 ? 1.0 : r;
  double phi = acos(r) / 3.0;
  w[0] = q + 2.0 * p * cos(phi);
  w[2] = q + 2.0 * p * cos(phi + 2.0 * POM_PI / 3.0);
  w[1] = 3.0 * q - w[0] - w[2];
}

void pom_kin_dexterity(const double J[9], double sv[3], double *kappa, double *dexterity) {
  double s[3], JtJ[9];
  pom_m3_tmul(JtJ, J, J);
  sym3_eigenvalues(s, JtJ);
  for (int k = 0; k < 3; ++k)
    s[k] = s[k] > 0.0 ? sqrt(s[k]) : 0.0;
  if (sv) memcpy(sv, s, sizeof s);
  double dex = s[0] > 0.0 ? s[2] / s[0] : 0.0;
  if (dexterity) *dexterity = dex;
  if (kappa) *kappa = dex > 0.0 ? s[0] / s[2] : INFINITY;
}

/* above it the eigenvalue dexterity is accurate enough for the parallel bit */
#define DEX_EIGEN_SAFE 1e-3

/* s_min / s_max of J from det J, the largest singular value s_max and that
 * of the cofactor matrix (s_max s_mid), each accurate to rounding however
 * ill-conditioned J is (docs/kinematics-modes.md 6.5). */
static double dexterity_accurate(const double J[9], double s_max) {
  const double c[9] = {
      J[4] * J[8] - J[5] * J[7], J[5] * J[6] - J[3] * J[8], J[3] * J[7] - J[4] * J[6],
      J[2] * J[7] - J[1] * J[8], J[0] * J[8] - J[2] * J[6], J[1] * J[6] - J[0] * J[7],
      J[1] * J[5] - J[2] * J[4], J[2] * J[3] - J[0] * J[5], J[0] * J[4] - J[1] * J[3]};
  const double det = J[0] * c[0] + J[1] * c[1] + J[2] * c[2];
  double CtC[9], w[3];
  pom_m3_tmul(CtC, c, c);
  sym3_eigenvalues(w, CtC);
  const double s01 = sqrt(fmax(fmax(w[0], w[1]), fmax(w[2], 0.0)));
  return s01 > 0.0 && s_max > 0.0 ? fabs(det) / (s01 * s_max) : 0.0;
}

double pom_kin_dexterity_bound(const double J[9]) {
  /* cofactors C (adj J = C^T), det J along the first row */
  const double c[9] = {
      J[4] * J[8] - J[5] * J[7], J[5] * J[6] - J[3] * J[8], J[3] * J[7] - J[4] * J[6],
      J[2] * J[7] - J[1] * J[8], J[0] * J[8] - J[2] * J[6], J[1] * J[6] - J[0] * J[7],
      J[1] * J[5] - J[2] * J[4], J[2] * J[3] - J[0] * J[5], J[0] * J[4] - J[1] * J[3]};
  const double det = J[0] * c[0] + J[1] * c[1] + J[2] * c[2];
  double nj = 0.0, nc = 0.0;
  for (int k = 0; k < 9; ++k) {
    nj += J[k] * J[k];
    nc += c[k] * c[k];
  }
  const double den = sqrt(nj * nc); /* 0 when rank J <= 1 */
  return den > 0.0 ? 3.0 * fabs(det) / den : 0.0;
}

/* ---- geometry helpers ------------------------------------------------------ */
static double clamp01(double x) {
  return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
}

/* Closest points of two segments: minimise |p0 + s d1 - q0 - t d2| over
 * s, t in [0, 1] (docs/kinematics.md 5.3). */
double pom_kin_segment_distance(const double p0[3], const double p1[3], const double q0[3],
                                const double q1[3]) {
  double d1[3], d2[3], r[3];
  pom_v3_sub(d1, p1, p0);
  pom_v3_sub(d2, q1, q0);
  pom_v3_sub(r, p0, q0);
  double a = pom_v3_dot(d1, d1), e = pom_v3_dot(d2, d2), f = pom_v3_dot(d2, r);
  double s = 0.0, t = 0.0;
  if (a == 0.0 && e == 0.0) return pom_v3_norm(r);
  if (a == 0.0) {
    t = clamp01(f / e);
  } else {
    double c = pom_v3_dot(d1, r);
    if (e == 0.0) {
      s = clamp01(-c / a);
    } else {
      double b = pom_v3_dot(d1, d2), denom = a * e - b * b;
      /* denom = a e sin^2(angle): for (near-)parallel segments any s works;
       * start from s = 0 and let the clamping below find the closest pair. */
      s = denom > 0.0 ? clamp01((b * f - c * e) / denom) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = clamp01(-c / a);
      } else if (t > 1.0) {
        t = 1.0;
        s = clamp01((b - c) / a);
      }
    }
  }
  double w[3];
  for (int k = 0; k < 3; ++k)
    w[k] = r[k] + s * d1[k] - t * d2[k];
  return pom_v3_norm(w);
}

double pom_kin_angle_between(const double a[3], const double b[3]) {
  double c[3];
  pom_v3_cross(c, a, b);
  return atan2(pom_v3_norm(c), pom_v3_dot(a, b));
}

/* Segment-limb limits shared by the 3PSS and 3SPS (docs/kinematics.md 5). */
void pom_kin_segment_limits(const double R[9], const double *from, const double *to,
                            const double *dir_home, double value[9]) {
  for (int i = 0; i < 3; ++i) {
    double l[3], lp[3];
    pom_v3_sub(l, to + 3 * i, from + 3 * i);
    pom_m3_tapply(lp, R, l); /* limb direction in the platform frame */
    value[i] = pom_kin_angle_between(l, dir_home + 3 * i);
    value[3 + i] = pom_kin_angle_between(lp, dir_home + 3 * i);
  }
  for (int k = 0; k < 3; ++k) {
    int i = k, j = (k + 1) % 3;
    value[6 + k] = pom_kin_segment_distance(from + 3 * i, to + 3 * i, from + 3 * j, to + 3 * j);
  }
}

/* ---- limits ---------------------------------------------------------------- */
const char *pom_kin_limit_name(const pom_kin_arch *arch, int k, char *buf, size_t cap) {
  static const char *const pairs[3] = {"1-2", "2-3", "3-1"};
  if (cap == 0) return buf;
  snprintf(buf, cap, "?");
  if (!arch || !arch->type || k < 0 || k >= POM_KIN_LIM_COUNT) return buf;
  int kind = k / 3, member = k % 3;
  if (kind == 0) {
    snprintf(buf, cap, "%s limb %d", pom_act_kind_desc(arch->type->actuator)->range_word,
             member + 1);
    return buf;
  }
  const pom_kin_limit_desc *ld = &arch->type->limits[kind];
  if (!ld->name) return buf;
  if (ld->per_pair)
    snprintf(buf, cap, "%s limbs %s", ld->name, pairs[member]);
  else
    snprintf(buf, cap, "%s limb %d", ld->name, member + 1);
  return buf;
}

void pom_kin_violations_text(const pom_kin_arch *arch, unsigned violations, char *buf, size_t cap) {
  size_t used = 0;
  char name[64];
  if (cap == 0) return;
  buf[0] = '\0';
  if (violations == 0) {
    snprintf(buf, cap, "none");
    return;
  }
  for (int k = 0; k < POM_KIN_LIM_COUNT; ++k) {
    if (!(violations & (1u << k))) continue;
    int w = snprintf(buf + used, cap - used, "%s%s", used ? ", " : "",
                     pom_kin_limit_name(arch, k, name, sizeof name));
    if (w < 0 || (size_t)w >= cap - used) return;
    used += (size_t)w;
  }
}

/* Fills the limit values and the violation bits of a reachable pose. */
static void check_limits(const pom_kin_arch *arch, const double R[9], pom_kin_pose *p) {
  const pom_kin_arch_type *t = arch->type;
  unsigned v = 0;
  for (int i = 0; i < 3; ++i) {
    p->limit[POM_KIN_LIM_STROKE + i] = fabs(p->q[i]);
    if (fabs(p->q[i]) > 0.5 * arch->stroke) v |= 1u << (POM_KIN_LIM_STROKE + i);
  }
  t->limit_values(arch, R, p->q, p->limit + 3);
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_kin_limit_desc *ld = &t->limits[kind];
    if (!ld->name) continue;
    for (int m = 0; m < 3; ++m) {
      double val = p->limit[3 * kind + m], b = arch->limit_bound[kind];
      if (ld->lower ? val < b : val > b) v |= 1u << (3 * kind + m);
    }
  }
  p->violations = v;
}

static void limit_message(const pom_kin_arch *arch, const pom_kin_pose *p, char *buf, size_t cap) {
  const pom_act_desc *u = pom_act_kind_desc(arch->type->actuator);
  size_t used = 0;
  char name[64];
  buf[0] = '\0';
  for (int k = 0; k < POM_KIN_LIM_COUNT; ++k) {
    if (!(p->violations & (1u << k))) continue;
    int i = k % 3, kind = k / 3, w;
    const char *sep = used ? "; " : "";
    pom_kin_limit_name(arch, k, name, sizeof name);
    if (kind == 0) {
      w = snprintf(buf + used, cap - used, "%s%s: q = %.6g %s, allowed +-%.6g %s", sep, name,
                   p->q[i] * u->to_display, u->display, 0.5 * arch->stroke * u->to_display,
                   u->display);
    } else {
      const pom_kin_limit_desc *ld = &arch->type->limits[kind];
      w = snprintf(buf + used, cap - used, "%s%s: %.4g %s %s %.4g %s", sep, name,
                   p->limit[k] * ld->to_display, ld->unit, ld->lower ? "<" : ">",
                   arch->limit_bound[kind] * ld->to_display, ld->unit);
    }
    if (w < 0 || (size_t)w >= cap - used) return;
    used += (size_t)w;
  }
}

pom_status pom_kin_pose_evaluate(const pom_kin_arch *arch, const double R[9], pom_kin_pose *pose,
                                 pom_error *err) {
  memset(pose, 0, sizeof *pose);
  pose->unreachable_limb = -1;
  pose->constraint_sv = 1.0;
  for (int i = 0; i < 3; ++i) /* limb ops that do not write it: no serial measure */
    pose->transmission[i] = 1.0;
  pom_status st =
      ik_rows(arch, R, pose->q, pose->J, pose->transmission, &pose->unreachable_limb, err);
  if (st != POM_OK) {
    pose->kappa = INFINITY;
    memset(pose->transmission, 0, sizeof pose->transmission);
    /* a limb that assembles without its Jacobian row is at a serial (leg)
     * singularity (the limb op's contract, pom_arch.h) */
    double qi;
    int k = pose->unreachable_limb;
    if (st == POM_ERR_UNREACHABLE && k >= 0 && arch->type->limb(arch, k, R, &qi, NULL, NULL)) {
      pose->singular |= POM_KIN_SING_SERIAL;
      pose->serial_limbs = 1u << k;
    }
    return st;
  }
  pose->reachable = 1;
  /* serial (leg) singularity: a limb's transmission index, the normalised
   * actuator side of its row, at or below sqrt(POM_KIN_SING_TOL)
   * (docs/kinematics-tables.md 3.2) */
  for (int i = 0; i < 3; ++i)
    if (!(pose->transmission[i] > POM_KIN_SERIAL_TOL)) pose->serial_limbs |= 1u << i;
  if (pose->serial_limbs) pose->singular |= POM_KIN_SING_SERIAL;
  pom_kin_dexterity(pose->J, pose->sv, &pose->kappa, &pose->dexterity);
  /* The eigenvalues of J^T J square the condition number: past 1e8 the two
   * smallest singular values are rounding. The flag therefore takes
   * s_min / s_max = |det J| / (s_max ||adj J||_2), since ||adj J||_2 =
   * s_max s_mid: the largest eigenvalues of J^T J and C^T C (C the
   * cofactors) and det J are accurate to the singularity
   * (docs/kinematics-modes.md 6.5); the reported dexterity is unchanged. */
  /* only where the eigenvalues may be rounding: their s_min^2 carries an
   * absolute error up to ~1e4 eps s_max^2 (measured beside folds), so above
   * a dexterity of 1e-3 (s_min^2 / s_max^2 = 1e-6) they are exact enough to
   * leave the bit clear, and the generic pose pays nothing */
  const double dex_det =
      pose->dexterity > DEX_EIGEN_SAFE ? pose->dexterity : dexterity_accurate(pose->J, pose->sv[0]);
  if (!(dex_det > POM_KIN_SING_TOL)) pose->singular |= POM_KIN_SING_PARALLEL;
  double F[9], M[9];
  if (arch->type->constraint && arch->type->constraint(arch, R, F, M) == 3) {
    double sv[3];
    pose->n_constraint = 3;
    pom_m3_singular_values(sv, F);
    pose->constraint_sv = sv[2];
    for (int i = 0; i < 3; ++i)
      pose->constraint_offset = fmax(pose->constraint_offset, pom_v3_norm(M + 3 * i));
    if (!(sv[2] > POM_KIN_SING_TOL)) pose->singular |= POM_KIN_SING_CONSTRAINT;
  }
  check_limits(arch, R, pose);
  if (pose->violations) {
    if (err) {
      char msg[900];
      limit_message(arch, pose, msg, sizeof msg);
      POM_FAIL(err, POM_ERR_LIMIT, "%s", msg);
    }
    return POM_ERR_LIMIT;
  }
  return POM_OK;
}

const char *pom_kin_singular_text(int singular, unsigned serial_limbs, char *buf, size_t cap) {
  size_t n = 0;
  buf[0] = '\0';
  if (!singular) {
    snprintf(buf, cap, "none");
    return buf;
  }
  if (singular & POM_KIN_SING_SERIAL) {
    const unsigned m = serial_limbs & 7u;
    const char *first = (m & (m - 1u)) ? " (limbs " : " (limb ";
    n += (size_t)snprintf(buf, cap, "serial");
    for (int i = 0, c = 0; i < 3 && n < cap; ++i)
      if (m >> i & 1u) n += (size_t)snprintf(buf + n, cap - n, "%s%d", c++ ? ", " : first, i + 1);
    if (m && n < cap) n += (size_t)snprintf(buf + n, cap - n, ")");
  }
  if ((singular & POM_KIN_SING_PARALLEL) && n < cap)
    n += (size_t)snprintf(buf + n, cap - n, "%sparallel", n ? ", " : "");
  if ((singular & POM_KIN_SING_CONSTRAINT) && n < cap)
    snprintf(buf + n, cap - n, "%sconstraint", n ? ", " : "");
  return buf;
}
