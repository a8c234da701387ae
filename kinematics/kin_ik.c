/* kin_ik.c - closed-form inverse kinematics on the home branch, the Jacobian,
 * dexterity and the limit checks (docs/kinematics.md sections 3 and 5). */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- inverse kinematics and Jacobian --------------------------------------- */
/* One limb of the 3PSS: q and Jacobian row (docs/kinematics.md 3.1).
 * Returns 0 when the link cannot reach the slider axis. */
static int limb_3pss(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3]) {
  double c[3], d[3];
  pom_m3_apply(c, R, arch->platform_point[i]);
  pom_v3_sub(d, c, arch->slider_mid[i]);
  const double *u = arch->slider_axis[i];
  double L = arch->link_length[i];
  double du = pom_v3_dot(d, u);
  double disc = du * du - pom_v3_dot(d, d) + L * L;
  if (!(disc >= 0.0)) return 0;
  double root = sqrt(disc);
  double qi = du - arch->branch_sign[i] * root;
  *q = qi;
  if (row) {
    /* l = R c - B(q); l.u = branch_sign * root */
    double l[3], cl[3];
    pom_v3_axpy(l, d, -qi, u);
    pom_v3_cross(cl, c, l);
    double lu = arch->branch_sign[i] * root;
    if (lu == 0.0) return 0;
    pom_v3_scale(row, 1.0 / lu, cl);
  }
  return 1;
}

/* One limb of the 3SPS (docs/kinematics.md 3.2). */
static int limb_3sps(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3]) {
  double b[3], v[3];
  pom_m3_apply(b, R, arch->platform_point[i]);
  pom_v3_sub(v, b, arch->base_point[i]);
  double n = pom_v3_norm(v);
  if (!(n > 0.0 && n < INFINITY)) return 0; /* zero length, or a non-finite R */
  *q = n - arch->limb_length_mid[i];
  if (row) {
    double s[3];
    pom_v3_scale(s, 1.0 / n, v);
    pom_v3_cross(row, b, s);
  }
  return 1;
}

/* q and J of all limbs; outputs untouched on failure, *bad = failing limb. */
static pom_status ik_rows(const pom_kin_arch *arch, const double R[9], double q[3], double J[9],
                          int *bad, pom_error *err) {
  double qq[3], JJ[9];
  for (int i = 0; i < 3; ++i) {
    int ok = arch->type == POM_ARCH_3PSS ? limb_3pss(arch, i, R, &qq[i], J ? JJ + 3 * i : NULL)
                                         : limb_3sps(arch, i, R, &qq[i], J ? JJ + 3 * i : NULL);
    if (!ok) {
      /* a NaN/Inf rotation also fails the reach tests above: say so, not
       * "unreachable" (checked here only, off the hot path) */
      for (int k = 0; k < 9; ++k)
        if (!isfinite(R[k]))
          POM_FAIL(err, POM_ERR_NONFINITE, "inverse kinematics: rotation entry R[%d] = %g", k,
                   R[k]);
      if (bad) *bad = i;
      POM_FAIL(err, POM_ERR_UNREACHABLE,
               arch->type == POM_ARCH_3PSS
                   ? "limb %d: the link cannot reach the slider axis (no real IK root)"
                   : "limb %d: the limb has zero length",
               i + 1);
    }
  }
  if (q) memcpy(q, qq, sizeof qq);
  if (J) memcpy(J, JJ, sizeof JJ);
  return POM_OK;
}

pom_status pom_kin_inverse(const pom_kin_arch *arch, const double R[9], double q[3],
                           pom_error *err) {
  return ik_rows(arch, R, q, NULL, NULL, err);
}

pom_status pom_kin_jacobian(const pom_kin_arch *arch, const double R[9], double J[9],
                            pom_error *err) {
  return ik_rows(arch, R, NULL, J, NULL, err);
}

pom_status pom_kin_inverse_jacobian(const pom_kin_arch *arch, const double R[9], double q[3],
                                    double J[9], pom_error *err) {
  return ik_rows(arch, R, q, J, NULL, err);
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

/* ---- geometry helpers ------------------------------------------------------ */
void pom_kin_limb_segments(const pom_kin_arch *arch, const double R[9], const double q[3],
                           double from[3][3], double to[3][3]) {
  for (int i = 0; i < 3; ++i) {
    pom_m3_apply(to[i], R, arch->platform_point[i]);
    if (arch->type == POM_ARCH_3PSS) {
      pom_v3_axpy(from[i], arch->slider_mid[i], q[i], arch->slider_axis[i]);
    } else {
      pom_v3_copy(from[i], arch->base_point[i]);
    }
  }
}

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

static double angle_between(const double a[3], const double b[3]) {
  double c[3];
  pom_v3_cross(c, a, b);
  return atan2(pom_v3_norm(c), pom_v3_dot(a, b));
}

/* ---- limits ---------------------------------------------------------------- */
const char *pom_kin_limit_name(int k) {
  static const char *const names[POM_KIN_LIM_COUNT] = {
      "stroke limb 1",        "stroke limb 2",      "stroke limb 3",        "base cone limb 1",
      "base cone limb 2",     "base cone limb 3",   "platform cone limb 1", "platform cone limb 2",
      "platform cone limb 3", "distance limbs 1-2", "distance limbs 2-3",   "distance limbs 3-1"};
  return k >= 0 && k < POM_KIN_LIM_COUNT ? names[k] : "?";
}

void pom_kin_violations_text(unsigned violations, char *buf, size_t cap) {
  size_t used = 0;
  if (cap == 0) return;
  buf[0] = '\0';
  if (violations == 0) {
    snprintf(buf, cap, "none");
    return;
  }
  for (int k = 0; k < POM_KIN_LIM_COUNT; ++k) {
    if (!(violations & (1u << k))) continue;
    int w = snprintf(buf + used, cap - used, "%s%s", used ? ", " : "", pom_kin_limit_name(k));
    if (w < 0 || (size_t)w >= cap - used) return;
    used += (size_t)w;
  }
}

/* Fills cones, distances and the violation bits of a reachable pose. */
static void check_limits(const pom_kin_arch *arch, const double R[9], pom_kin_pose *p) {
  double from[3][3], to[3][3];
  unsigned v = 0;
  pom_kin_limb_segments(arch, R, p->q, from, to);
  for (int i = 0; i < 3; ++i) {
    double l[3], lp[3];
    pom_v3_sub(l, to[i], from[i]);
    pom_m3_tapply(lp, R, l); /* limb direction in the platform frame */
    p->cone_base[i] = angle_between(l, arch->limb_dir_home[i]);
    p->cone_platform[i] = angle_between(lp, arch->limb_dir_home[i]);
    if (fabs(p->q[i]) > 0.5 * arch->stroke) v |= 1u << (POM_KIN_LIM_STROKE + i);
    if (p->cone_base[i] > arch->cone_base_max) v |= 1u << (POM_KIN_LIM_CONE_BASE + i);
    if (p->cone_platform[i] > arch->cone_platform_max) v |= 1u << (POM_KIN_LIM_CONE_PLATFORM + i);
  }
  for (int k = 0; k < 3; ++k) {
    int i = k, j = (k + 1) % 3;
    p->limb_distance[k] = pom_kin_segment_distance(from[i], to[i], from[j], to[j]);
    if (p->limb_distance[k] < arch->min_limb_distance) v |= 1u << (POM_KIN_LIM_DISTANCE + k);
  }
  p->violations = v;
}

static void limit_message(const pom_kin_arch *arch, const pom_kin_pose *p, char *buf, size_t cap) {
  size_t used = 0;
  buf[0] = '\0';
  for (int k = 0; k < POM_KIN_LIM_COUNT; ++k) {
    if (!(p->violations & (1u << k))) continue;
    int i = k % 3, w;
    const char *sep = used ? "; " : "";
    if (k < POM_KIN_LIM_CONE_BASE) {
      w = snprintf(buf + used, cap - used, "%s%s: q = %.4g mm, allowed +-%.4g mm", sep,
                   pom_kin_limit_name(k), p->q[i] * 1e3, 0.5 * arch->stroke * 1e3);
    } else if (k < POM_KIN_LIM_CONE_PLATFORM) {
      w = snprintf(buf + used, cap - used, "%s%s: %.4g deg > %.4g deg", sep, pom_kin_limit_name(k),
                   p->cone_base[i] / POM_DEG, arch->cone_base_max / POM_DEG);
    } else if (k < POM_KIN_LIM_DISTANCE) {
      w = snprintf(buf + used, cap - used, "%s%s: %.4g deg > %.4g deg", sep, pom_kin_limit_name(k),
                   p->cone_platform[i] / POM_DEG, arch->cone_platform_max / POM_DEG);
    } else {
      w = snprintf(buf + used, cap - used, "%s%s: %.4g mm < %.4g mm", sep, pom_kin_limit_name(k),
                   p->limb_distance[i] * 1e3, arch->min_limb_distance * 1e3);
    }
    if (w < 0 || (size_t)w >= cap - used) return;
    used += (size_t)w;
  }
}

pom_status pom_kin_pose_evaluate(const pom_kin_arch *arch, const double R[9], pom_kin_pose *pose,
                                 pom_error *err) {
  memset(pose, 0, sizeof *pose);
  pose->unreachable_limb = -1;
  pom_status st = ik_rows(arch, R, pose->q, pose->J, &pose->unreachable_limb, err);
  if (st != POM_OK) {
    pose->kappa = INFINITY;
    return st;
  }
  pose->reachable = 1;
  pom_kin_dexterity(pose->J, pose->sv, &pose->kappa, &pose->dexterity);
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
