/* test_kin_3rrr.c - the 3-RRR spherical wrist (kinematics/arch_3rrr.c):
 * isotropic home, IK/FK, Jacobian, body twists, Agile Eye facts, the arc
 * link model and random designs (docs/kinematics-3rrr.md section 8). */
#include "check.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <stdio.h>
#include <string.h>

static const double magic_cone = 0.95531661812450927816; /* atan(sqrt 2) = 54.7356 deg */

/* ---- helpers --------------------------------------------------------------- */
/* Loads the shipped configs/<file> with `extra` put first inside its
 * geometry group in place of its own central_joint (NULL: as shipped), builds its mechanism and
 * checks the geometry group for unknown keys; the config error, if any, in err. */
static pom_status load_with(const char *file, const char *extra, pom_kin_arch *arch,
                            pom_mechanism *mech, pom_error *err) {
  static const char *const scopes[] = {"geometry", NULL};
  static char text[1 << 16], patched[(1 << 16) + 256];
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, file);
  FILE *f = fopen(path, "rb");
  size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
  if (f) fclose(f);
  text[n] = '\0';
  /* the shipped file's own setting gives way to extra */
  char *own = strstr(text, "central_joint = ");
  if (own && extra)
    for (; *own && *own != ';'; ++own)
      *own = ' ';
  if (own && extra && *own == ';') *own = ' ';
  const char *g = strstr(text, "geometry = {");
  if (!g) return POM_ERR_INTERNAL;
  int head = (int)(g - text) + (int)strlen("geometry = {");
  snprintf(patched, sizeof patched, "%.*s %s %s", head, text, extra ? extra : "", text + head);
  pom_cfg *cfg = NULL;
  pom_kin_inertia in;
  pom_status st = pom_cfg_load_string(&cfg, patched, file, err);
  if (st == POM_OK) st = pom_kin_arch_load(arch, cfg, err);
  if (st == POM_OK) st = pom_kin_inertia_load(&in, arch, cfg, err);
  if (st == POM_OK) st = pom_kin_mechanism_from(mech, arch, &in, err);
  if (st == POM_OK) st = pom_cfg_check_unknown(cfg, scopes, NULL, err);
  pom_cfg_destroy(cfg);
  return st;
}

/* The spherical joint at O is a choice of the 3-RRR (geometry.central_joint,
 * default false: the wrist as built; docs/kinematics-3rrr.md section 9), a
 * boolean; the 3P-S-S/S's joint O is its own (the key is unknown there). */
static void test_central_joint(void) {
  static pom_mechanism m;
  pom_kin_arch a;
  pom_error err;
  pom_error_clear(&err);
  check_true(load_with("3rrr.cfg", NULL, &a, &m, &err) == POM_OK);
  check_true(a.central_joint == 0 && m.n_joints == 9);
  for (int j = 0; j < m.n_joints; ++j)
    check_true(m.joint[j].type == POM_JOINT_REVOLUTE && strcmp(m.joint[j].name, "O") != 0);
  check_true(load_with("3rrr.cfg", "central_joint = false;", &a, &m, &err) == POM_OK);
  check_true(a.central_joint == 0 && m.n_joints == 9);
  check_true(load_with("3rrr.cfg", "central_joint = true;", &a, &m, &err) == POM_OK);
  check_true(a.central_joint == 1 && m.n_joints == 10);
  check_true(strcmp(m.joint[0].name, "O") == 0 && m.joint[0].type == POM_JOINT_SPHERICAL &&
             m.joint[0].body[0] == 0 && m.joint[0].body[1] == m.platform);
  check_true(load_with("3rrr.cfg", "central_joint = 1;", &a, &m, &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "geometry.central_joint") != NULL);
  check_true(load_with("3pss.cfg", NULL, &a, &m, &err) == POM_OK);
  check_true(a.central_joint == 1 && strcmp(m.joint[0].name, "O") == 0);
  check_true(load_with("3pss.cfg", "central_joint = false;", &a, &m, &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "geometry.central_joint") != NULL);
}

static int load_cfg(pom_kin_arch *arch, pom_mechanism *mech, pom_kin_inertia *in) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/3rrr.cfg", POM_SOURCE_DIR);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_kin_arch_load(arch, cfg, &err) == POM_OK &&
           pom_kin_inertia_load(in, arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_from(mech, arch, in, &err) == POM_OK;
  if (!ok) printf("loading configs/3rrr.cfg: %s\n", err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

static double rotation_angle_between(const double A[9], const double B[9]) {
  double D[9], rv[3];
  pom_m3_mult(D, A, B);
  pom_m3_rotvec(rv, D);
  return pom_v3_norm(rv);
}

static void random_pose(pom_rng *rng, double R[9], double half_width) {
  double e[3];
  for (int k = 0; k < 3; ++k)
    e[k] = pom_rng_range(rng, -half_width, half_width);
  pom_euler_zyx_to_matrix(R, e);
}

/* Worst |central difference of the IK - J| over n poses (rad/rad). */
static double jacobian_fd(const pom_kin_arch *a, pom_rng *rng, int n, double half, double dex_min,
                          int *used) {
  const double eps = 1e-6;
  double worst = 0.0;
  *used = 0;
  for (int s = 0; s < n; ++s) {
    double R[9], q[3], J[9], dex;
    random_pose(rng, R, half);
    if (pom_kin_inverse_jacobian(a, R, q, J, NULL) != POM_OK) continue;
    pom_kin_dexterity(J, NULL, NULL, &dex);
    if (dex < dex_min) continue;
    ++*used;
    for (int k = 0; k < 3; ++k) {
      double ax[3] = {0, 0, 0}, E[9], Rp[9], Rm[9], qp[3], qm[3];
      ax[k] = 1.0;
      pom_m3_axis_angle(E, ax, eps);
      pom_m3_mul(Rp, E, R);
      pom_m3_axis_angle(E, ax, -eps);
      pom_m3_mul(Rm, E, R);
      if (!check_true(pom_kin_inverse(a, Rp, qp, NULL) == POM_OK &&
                      pom_kin_inverse(a, Rm, qm, NULL) == POM_OK))
        continue;
      for (int i = 0; i < 3; ++i)
        worst = fmax(worst, fabs((qp[i] - qm[i]) / (2.0 * eps) - J[3 * i + k]));
    }
  }
  return worst;
}

/* Worst rotation error and residual of IK -> FK over n poses. */
static void round_trips(const pom_kin_arch *a, pom_rng *rng, int n, double half, double *worst,
                        double *worst_res, int *fails) {
  *worst = *worst_res = 0.0;
  *fails = 0;
  for (int s = 0; s < n; ++s) {
    double R[9], q[3], Rf[9];
    random_pose(rng, R, half);
    if (pom_kin_inverse(a, R, q, NULL) != POM_OK) {
      ++*fails;
      continue;
    }
    pom_kin_fk_info info;
    if (pom_kin_forward(a, q, NULL, NULL, Rf, &info, NULL) != POM_OK) {
      ++*fails;
      continue;
    }
    *worst = fmax(*worst, rotation_angle_between(R, Rf));
    *worst_res = fmax(*worst_res, info.residual);
  }
}

/* ---- isotropic home -------------------------------------------------------- */
/* At home w_i = u_i x v_i with u_i . v_i = 0, so row i = u_i exactly (section
 * 7): J = [u_1; u_2; u_3], orthogonal; the only error is the rounding of the
 * construction (~1e-16). */
static void test_home(const pom_kin_arch *a) {
  double I[9], q[3], J[9], sv[3], kappa, dex, JJ[9];
  pom_m3_identity(I);
  check_true(pom_kin_inverse_jacobian(a, I, q, J, NULL) == POM_OK);
  for (int i = 0; i < 3; ++i)
    check_abs(q[i], 0.0, 1e-14);
  pom_kin_dexterity(J, sv, &kappa, &dex);
  for (int k = 0; k < 3; ++k)
    check_abs(sv[k], 1.0, 1e-12);
  check_abs(dex, 1.0, 1e-12);
  pom_m3_mult(JJ, J, J);
  for (int k = 0; k < 9; ++k)
    check_abs(JJ[k], k % 4 == 0 ? 1.0 : 0.0, 1e-12);
  const double *u = pom_kin_arch_points(a, "base_axes");
  for (int k = 0; k < 9; ++k)
    check_abs(J[k], u[k], 1e-12);
}

/* ---- Agile Eye facts (section 7) --------------------------------------------- */
/* Singularities of the Agile Eye are curves (Bonev, Chablat, Wenger 2006),
 * where a leg's u_i and v_i align (its self-motion) or the platform locks.
 * Tilts about horizontal axes keep every v_i more than 40 deg away from its
 * u_i for tilt <= 60 deg (v_i . u_i = 0 at home; a rotation by t changes the
 * angle by at most t), so no singularity lies there: dexterity stays > 0.
 * The torsion of 120 deg about z turns v_i onto -u_i: every leg is in a
 * self-motion and IK must refuse it. Tilting acos(-1/5) = 101.537 deg about
 * the axis at azimuth 30 deg brings v_1 onto -u_1: dexterity -> 0 there. */
static void test_agile_eye(const pom_kin_arch *a) {
  double min_dex = 1.0;
  for (int az = 0; az < 360; az += 5)
    for (int t = 1; t <= 60; ++t) {
      double ax[3] = {cos(az * POM_DEG), sin(az * POM_DEG), 0.0}, R[9], q[3], J[9], dex;
      pom_m3_axis_angle(R, ax, t * POM_DEG);
      if (!check_true(pom_kin_inverse_jacobian(a, R, q, J, NULL) == POM_OK)) return;
      pom_kin_dexterity(J, NULL, NULL, &dex);
      min_dex = fmin(min_dex, dex);
    }
  check_true(min_dex > 0.1);
  printf("agile eye: min dexterity over tilt <= 60 deg: %.3f\n", min_dex);
  double z[3] = {0, 0, 1}, R[9], q[3], J[9];
  pom_error err;
  pom_m3_axis_angle(R, z, 120.0 * POM_DEG);
  pom_error_clear(&err);
  check_true(pom_kin_inverse_jacobian(a, R, q, J, &err) != POM_OK);
  check_true(strstr(err.message, "limb") != NULL);
  /* dexterity on the way to the leg self-motion: minimum by ternary search */
  double ax[3] = {cos(30 * POM_DEG), sin(30 * POM_DEG), 0.0}, lo = 95 * POM_DEG, hi = 105 * POM_DEG;
  for (int k = 0; k < 100; ++k) {
    double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3, d1 = 0, d2 = 0;
    pom_m3_axis_angle(R, ax, m1);
    if (pom_kin_inverse_jacobian(a, R, q, J, NULL) == POM_OK) pom_kin_dexterity(J, NULL, NULL, &d1);
    pom_m3_axis_angle(R, ax, m2);
    if (pom_kin_inverse_jacobian(a, R, q, J, NULL) == POM_OK) pom_kin_dexterity(J, NULL, NULL, &d2);
    if (d1 < d2) {
      hi = m2;
    } else {
      lo = m1;
    }
  }
  double dex = 1.0, v[3];
  pom_m3_axis_angle(R, ax, 0.5 * (lo + hi));
  if (pom_kin_inverse_jacobian(a, R, q, J, NULL) == POM_OK) pom_kin_dexterity(J, NULL, NULL, &dex);
  check_abs(dex, 0.0, 1e-6);
  /* the closed form (docs/kinematics-modes.md 6.2): cos(tilt) = -1/5, 101.537
   * deg; the search on the dexterity (~ the squared distance to the curve,
   * computed through a condition number ~1/distance^2) stops within ~1e-3 rad */
  check_abs(0.5 * (lo + hi), acos(-0.2), 1e-3);
  pom_m3_apply(v, R, pom_kin_arch_points(a, "platform_axes"));
  check_abs(pom_v3_dot(v, pom_kin_arch_points(a, "base_axes")), -1.0, 1e-6);
  pom_m3_axis_angle(R, ax, acos(-0.2));
  pom_m3_apply(v, R, pom_kin_arch_points(a, "platform_axes"));
  check_abs(pom_v3_dot(v, pom_kin_arch_points(a, "base_axes")), -1.0, 1e-12);
}

/* ---- body twists --------------------------------------------------------------- */
static void rotate_by(double out[9], const double w[3], double t, const double R[9]) {
  double n = pom_v3_norm(w), u[3], E[9];
  pom_v3_scale(u, 1.0 / n, w);
  pom_m3_axis_angle(E, u, n * t);
  pom_m3_mul(out, E, R);
}

/* Angle of R about unit a (R a = a), from a perpendicular p. */
static double angle_about(const double R[9], const double a[3]) {
  double p[3], t[3] = {1, 0, 0}, Rp[3], c[3];
  if (fabs(a[0]) > 0.9) t[0] = 0, t[1] = 1;
  pom_v3_cross(p, a, t);
  pom_v3_normalize(p, p);
  pom_m3_apply(Rp, R, p);
  pom_v3_cross(c, p, Rp);
  return atan2(pom_v3_dot(c, a), pom_v3_dot(p, Rp));
}

/* Every body rotates about O (ref = 0): joints keep O; a revolute joint of
 * axis a keeps (R0 a) x (R1 a) = 0. Differences along R(t) = exp(t[w]) R at
 * |w| h = 1e-6 (first) and 1e-4 rad (second): truncation ~1e-12 and 1e-8,
 * rounding ~1e-10 and 1e-8 relative: 1e-7 and 2e-7 of |w| and |w|^2. */
static void test_body_twists(const pom_kin_arch *a, const pom_mechanism *m, pom_rng *rng) {
  double wj = 0, wq = 0, ww = 0, wal = 0, wqb = 0;
  for (int trial = 0; trial < 40; ++trial) {
    double R[9], w[3], q[3], J[9], Rp[9], Rm[9];
    random_pose(rng, R, 25.0 * POM_DEG);
    for (int k = 0; k < 3; ++k)
      w[k] = pom_rng_range(rng, -8.0, 8.0);
    double wn = pom_v3_norm(w);
    pom_kin_twists tw, tp, tm;
    if (!check_true(pom_kin_body_twists(a, R, w, &tw, NULL) == POM_OK)) return;
    check_true(tw.n_bodies == m->n_bodies && m->n_bodies == 8 && m->n_joints == 9);
    check_true(pom_kin_inverse_jacobian(a, R, q, J, NULL) == POM_OK);
    for (int k = 0; k < 3; ++k)
      check_abs(tw.q[k], q[k], 0.0);
    for (int k = 0; k < 9; ++k)
      check_abs(tw.J[k], J[k], 0.0);
    for (int j = 0; j < m->n_joints; ++j) {
      const pom_mech_joint *jt = &m->joint[j];
      const pom_kin_body_twist *b0 = &tw.body[jt->body[0]], *b1 = &tw.body[jt->body[1]];
      wj = fmax(wj, pom_v3_norm(jt->point) + pom_v3_norm(b0->ref) + pom_v3_norm(b1->ref));
      if (jt->type != POM_JOINT_REVOLUTE) continue;
      double a0[3], a1[3], c[3], Rrel[9];
      pom_m3_apply(a0, b0->R, jt->axis);
      pom_m3_apply(a1, b1->R, jt->axis);
      pom_v3_cross(c, a0, a1);
      wj = fmax(wj, pom_v3_norm(c));
      if (jt->actuator >= 0) {
        pom_m3_tmul(Rrel, b0->R, b1->R);
        wq = fmax(wq, fabs(angle_about(Rrel, jt->axis) -
                           tw.q[m->actuator[jt->actuator].joint == j ? jt->actuator : 0]));
      }
    }
    double h1 = 1e-6 / wn;
    rotate_by(Rp, w, h1, R);
    rotate_by(Rm, w, -h1, R);
    check_true(pom_kin_body_twists(a, Rp, w, &tp, NULL) == POM_OK &&
               pom_kin_body_twists(a, Rm, w, &tm, NULL) == POM_OK);
    for (int b = 1; b < m->n_bodies; ++b) {
      double D[9], rv[3], wb[3];
      pom_m3_mult(D, tp.body[b].R, tm.body[b].R);
      pom_m3_rotvec(rv, D);
      pom_m3_apply(wb, tw.body[b].B, w);
      for (int k = 0; k < 3; ++k)
        ww = fmax(ww, fabs(rv[k] / (2 * h1) - wb[k]) / wn);
    }
    double h2 = 1e-4 / wn;
    rotate_by(Rp, w, h2, R);
    rotate_by(Rm, w, -h2, R);
    check_true(pom_kin_body_twists(a, Rp, w, &tp, NULL) == POM_OK &&
               pom_kin_body_twists(a, Rm, w, &tm, NULL) == POM_OK);
    for (int k = 0; k < 3; ++k)
      wqb =
          fmax(wqb, fabs((tp.q[k] - 2 * tw.q[k] + tm.q[k]) / (h2 * h2) - tw.q_bias[k]) / (wn * wn));
    for (int b = 1; b < m->n_bodies; ++b) {
      double wp[3], wm[3];
      pom_m3_apply(wp, tp.body[b].B, w);
      pom_m3_apply(wm, tm.body[b].B, w);
      for (int k = 0; k < 3; ++k)
        wal = fmax(wal, fabs((wp[k] - wm[k]) / (2 * h2) - tw.body[b].alpha_bias[k]) / (wn * wn));
    }
  }
  check_abs(wj, 0.0, 1e-14);
  check_abs(wq, 0.0, 1e-13);
  check_abs(ww, 0.0, 1e-7);
  check_abs(wqb, 0.0, 2e-7);
  check_abs(wal, 0.0, 1e-7);
  printf("body twists: joints %.2g, actuated angle %.2g rad, omega %.2g, q_bias %.2g, alpha %.2g\n",
         wj, wq, ww, wqb, wal);
}

/* ---- arc link model (section 6) --------------------------------------------------- */
static void test_link_model(const pom_kin_arch *a, const pom_mechanism *m,
                            const pom_kin_inertia *in) {
  const double r = a->design.scale, lam = in->value[0] * in->value[1];
  const double al1 = a->design.x[1], al2 = a->design.x[2];
  for (int i = 0; i < 3; ++i) {
    const pom_mech_body *p = &m->body[2 + 2 * i], *d = &m->body[3 + 2 * i];
    check_rel(p->mass, lam * r * al1 + in->value[3], 1e-14);
    check_rel(d->mass, lam * r * al2 + in->value[2], 1e-14);
    for (int b = 0; b < 2; ++b) {
      const double *I = b ? d->inertia : p->inertia;
      double ev[3], V[9];
      check_abs(I[1] - I[3], 0.0, 0.0);
      check_abs(I[2] - I[6], 0.0, 0.0);
      check_abs(I[5] - I[7], 0.0, 0.0);
      pom_m3_sym_eig(ev, V, I);
      check_true(ev[0] > 0.0 && ev[1] > 0.0 && ev[2] > 0.0);
      double tol = 1e-12 * (ev[0] + ev[1] + ev[2]);
      check_true(ev[0] + ev[1] >= ev[2] - tol && ev[1] + ev[2] >= ev[0] - tol &&
                 ev[0] + ev[2] >= ev[1] - tol);
    }
  }
  /* an arc of 90 deg about O: I_O along the arc's normal is m r^2 */
  const double *u = pom_kin_arch_points(a, "base_axes"), *w = pom_kin_arch_points(a, "elbow_axes");
  const pom_mech_body *d = &m->body[3];
  double nrm[3], In[3], c = 0;
  pom_v3_cross(nrm, w, pom_kin_arch_points(a, "platform_axes"));
  (void)u;
  pom_m3_apply(In, d->inertia, nrm);
  /* back to O: I_O n . n = I_cm n . n + m |cm x n|^2 */
  double cxn[3];
  pom_v3_cross(cxn, d->cm, nrm);
  c = pom_v3_dot(In, nrm) + d->mass * pom_v3_dot(cxn, cxn);
  check_rel(c, (lam * r * al2 + in->value[2]) * r * r, 1e-12);
}

/* ---- random designs ---------------------------------------------------------------- */
static void test_random_designs(pom_rng *rng) {
  int designs = 0, poses = 0, rt_fails = 0;
  double worst_fd = 0, worst_rt = 0, worst_res = 0;
  for (int n = 0; n < 60; ++n) {
    pom_kin_design d = {0.03,
                        {pom_rng_range(rng, -POM_PI, POM_PI), pom_rng_range(rng, 45, 110) * POM_DEG,
                         pom_rng_range(rng, 45, 110) * POM_DEG,
                         pom_rng_range(rng, 30, 80) * POM_DEG, pom_rng_range(rng, 30, 80) * POM_DEG,
                         pom_rng_range(rng, 20, 100) * POM_DEG, n % 2 ? 1.0 : -1.0}};
    pom_kin_arch a;
    if (pom_kin_arch_from_design(&a, pom_kin_arch_type_find("3RRR"), &d, NULL) != POM_OK) continue;
    double I[9], J[9], dex;
    pom_m3_identity(I);
    if (pom_kin_jacobian(&a, I, J, NULL) != POM_OK) continue;
    pom_kin_dexterity(J, NULL, NULL, &dex);
    if (dex < 0.2) continue;
    ++designs;
    int used;
    worst_fd = fmax(worst_fd, jacobian_fd(&a, rng, 10, 5.0 * POM_DEG, 0.1, &used));
    poses += used;
    double wr, wres;
    int f;
    round_trips(&a, rng, 10, 3.0 * POM_DEG, &wr, &wres, &f);
    rt_fails += f;
    worst_rt = fmax(worst_rt, wr);
    worst_res = fmax(worst_res, wres);
  }
  check_true(designs >= 15 && poses >= 100);
  check_abs(worst_fd, 0.0, 1e-8);
  check_true(rt_fails <= 5); /* see the report: FK failures on random designs */
  check_abs(worst_rt, 0.0, 1e-9);
  printf("random designs: %d FK failures; ", rt_fails);
  printf("random designs: %d designs, %d poses, J-fd %.2g, round trip %.2g rad (res %.2g)\n",
         designs, poses, worst_fd, worst_rt, worst_res);
}

int main(void) {
  static pom_mechanism mech;
  pom_kin_arch a;
  pom_kin_inertia in;
  pom_rng rng;
  pom_rng_seed(&rng, 2385, 7);
  if (!check_true(load_cfg(&a, &mech, &in))) return check_summary("test_kin_3rrr");
  check_abs(a.design.x[3], magic_cone, 1e-15);
  test_home(&a);
  test_agile_eye(&a);
  double wr, wres;
  int fails, used;
  round_trips(&a, &rng, 3000, 25.0 * POM_DEG, &wr, &wres, &fails);
  /* FK stops at |q(R) - q| <= 1e-12 rad; sv_min >= 0.1 rad/rad within 25 deg:
   * 1e-11 rad */
  check_true(fails == 0);
  check_abs(wr, 0.0, 1e-10);
  check_abs(wres, 0.0, 1e-12);
  printf("round trips: worst rotation %.2g rad, residual %.2g\n", wr, wres);
  /* central differences, eps = 1e-6: truncation ~eps^2 |q'''| ~ 1e-12,
   * rounding 1e-16 / 1e-6 = 1e-10 */
  double fd = jacobian_fd(&a, &rng, 300, 25.0 * POM_DEG, 0.0, &used);
  check_true(used == 300);
  check_abs(fd, 0.0, 1e-8);
  printf("jacobian fd: %.2g rad/rad\n", fd);
  test_body_twists(&a, &mech, &rng);
  test_link_model(&a, &mech, &in);
  test_random_designs(&rng);
  test_central_joint();
  return check_summary("test_kin_3rrr");
}
