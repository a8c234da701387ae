/* test_mjcf.c - pomlab's MJCF export (kinematics/pom_mjcf.h, docs/export.md)
 * loaded by MuJoCo's own C library (Debian's libmujoco-dev, mj_loadXML) for
 * every architecture of catalog/ and the three hand-coded types
 * (configs/3pss.cfg, 3sps.cfg, 3rrr.cfg). Per architecture:
 *  - MuJoCo compiles it; it has every body of the mechanism, each with the
 *    mass pomlab gives it (relative 1e-12: the file prints 17 digits; a
 *    massless body gets MuJoCo's bound, 1e-9 kg), and one motor per
 *    actuator with the coil's constant in its user data.
 *  - At home and four poses (ZYX Euler 8,-6,10; -12,5,-7; 15,10,0;
 *    0,-10,12 deg; those the architecture cannot assemble are left out, at
 *    least three must remain):
 *    (a) pomlab's limb kinematics in MuJoCo: every tree joint's qpos is
 *        computed from the body poses of pom_kin_body_twists (a hinge's
 *        angle, a slide's displacement, a ball's quaternion, a universal's
 *        two angles). MuJoCo's forward kinematics must then put every body
 *        where pomlab does (CM position 1e-12 m, orientation 1e-12 rad:
 *        rounding of a chain of 3 to 4 joints in double), the motors'
 *        joints must read pomlab's actuator coordinates q(R) - q(I)
 *        (1e-12), and the loop-closing constraints must hold: every
 *        equality residual (efc_pos) below 1e-12 m.
 *    (b) MuJoCo's own assembly: only the motors' joints are set (from
 *        pomlab's inverse kinematics); every other joint starts at home and
 *        a damped Gauss-Newton iteration on the equality residuals (MuJoCo's
 *        efc_J) moves the unactuated joints until the residual is below
 *        1e-13 m. The platform's orientation must then be pomlab's R within
 *        1e-9 rad: a residual r moves the platform by about kappa r / l
 *        (l ~ 10 mm the lever of a joint, kappa the condition number of J,
 *        printed: at most 2.33, Orbita 3D, in this catalog at these poses): with
 *        kappa <= 20, 1e-13 * 20 / 1e-2 = 2e-10 rad.
 * Exit 77 (skipped) is decided in CMake: without libmujoco-dev this test is
 * not built and a stub exits 77 (tests/kinematics.cmake). */
#include "catalog_test_util.h"
#include "check.h"
#include "pom_arch.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_io.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_mjcf.h"

#include <math.h>
#include <mujoco/mujoco.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAXN 64 /* dofs and equality rows this test handles */

static int n_models = 0;

/* ---- small linear algebra ---------------------------------------------------- */
/* Solves A x = b, A n x n symmetric positive definite (Cholesky, in place). */
static int chol_solve(double *A, double *b, int n) {
  for (int j = 0; j < n; ++j) {
    double s = A[j * n + j];
    for (int k = 0; k < j; ++k)
      s -= A[j * n + k] * A[j * n + k];
    if (!(s > 0.0)) return -1;
    A[j * n + j] = sqrt(s);
    for (int i = j + 1; i < n; ++i) {
      double t = A[i * n + j];
      for (int k = 0; k < j; ++k)
        t -= A[i * n + k] * A[j * n + k];
      A[i * n + j] = t / A[j * n + j];
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < i; ++k)
      b[i] -= A[i * n + k] * b[k];
    b[i] /= A[i * n + i];
  }
  for (int i = n - 1; i >= 0; --i) {
    for (int k = i + 1; k < n; ++k)
      b[i] -= A[k * n + i] * b[k];
    b[i] /= A[i * n + i];
  }
  return 0;
}

/* Angle (rad) of the rotation A^T B. */
static double rot_dist(const double A[9], const double B[9]) {
  double C[9];
  pom_m3_tmul(C, A, B);
  double s = 0.5 * sqrt((C[7] - C[5]) * (C[7] - C[5]) + (C[2] - C[6]) * (C[2] - C[6]) +
                        (C[3] - C[1]) * (C[3] - C[1]));
  double c = 0.5 * (C[0] + C[4] + C[8] - 1.0);
  return atan2(s, c);
}

/* Angle of the rotation Rr about the unit axis a (Rr = Rot(a, theta)). */
static double hinge_angle(const double Rr[9], const double a[3]) {
  double v[3] = {0.5 * (Rr[7] - Rr[5]), 0.5 * (Rr[2] - Rr[6]), 0.5 * (Rr[3] - Rr[1])};
  return atan2(pom_v3_dot(v, a), 0.5 * (Rr[0] + Rr[4] + Rr[8] - 1.0));
}

/* ---- one architecture -------------------------------------------------------- */
typedef struct {
  const pom_mechanism *mech;
  int mj_of[POM_MECH_MAX_BODIES]; /* MuJoCo body of each mechanism body */
  int mech_of[MAXN];              /* mechanism body of each MuJoCo body, -1 (a cross) */
} body_map;

/* Pose of mechanism body b from pomlab: rotation and CM position. */
static void pom_pose(const pom_kin_twists *tw, const pom_mechanism *mech, int b, double R[9],
                     double x[3]) {
  if (b == 0) {
    pom_m3_identity(R);
    pom_v3_copy(x, mech->body[0].cm);
    return;
  }
  const pom_kin_body_twist *bt = &tw->body[b];
  double d[3];
  memcpy(R, bt->R, sizeof bt->R);
  pom_v3_sub(d, mech->body[b].cm, bt->ref_home);
  pom_m3_apply(x, bt->R, d);
  pom_v3_add(x, x, bt->ref);
}

/* (a): every tree joint's qpos from pomlab's body poses; *free receives the
 * dofs left for the iteration (those of cross bodies). */
static void qpos_from_pomlab(const mjModel *m, mjData *d, const body_map *bm,
                             const pom_kin_twists *tw, int *free) {
  mju_copy(d->qpos, m->qpos0, m->nq);
  for (int v = 0; v < m->nv; ++v)
    free[v] = 0;
  for (int c = 1; c < m->nbody; ++c) {
    int p = m->body_parentid[c], bc = bm->mech_of[c], bp = bm->mech_of[p];
    int j0 = m->body_jntadr[c], nj = m->body_jntnum[c];
    if (bc < 0 || bp < 0) {
      for (int k = 0; k < nj; ++k)
        free[m->jnt_dofadr[j0 + k]] = 1;
      continue;
    }
    double Rp[9], Rc[9], xp[3], xc[3], Rr[9];
    pom_pose(tw, bm->mech, bp, Rp, xp);
    pom_pose(tw, bm->mech, bc, Rc, xc);
    pom_m3_tmul(Rr, Rp, Rc);
    if (nj == 2) { /* a universal joint: Rr = Rot(a1, t1) Rot(a2, t2) */
      const double *a1 = m->jnt_axis + 3 * j0, *a2 = m->jnt_axis + 3 * (j0 + 1);
      double v[3], w[3], R1[9], R2[9];
      pom_m3_apply(v, Rr, a2);
      pom_v3_cross(w, a2, v);
      double t1 =
          atan2(pom_v3_dot(a1, w), pom_v3_dot(a2, v) - pom_v3_dot(a1, a2) * pom_v3_dot(a1, v));
      pom_m3_axis_angle(R1, a1, t1);
      pom_m3_tmul(R2, R1, Rr);
      d->qpos[m->jnt_qposadr[j0]] = t1;
      d->qpos[m->jnt_qposadr[j0 + 1]] = hinge_angle(R2, a2);
      continue;
    }
    if (nj != 1) continue;
    int adr = m->jnt_qposadr[j0];
    const double *a = m->jnt_axis + 3 * j0;
    if (m->jnt_type[j0] == mjJNT_HINGE) {
      d->qpos[adr] = hinge_angle(Rr, a);
    } else if (m->jnt_type[j0] == mjJNT_SLIDE) {
      double dx[3], loc[3];
      pom_v3_sub(dx, xc, xp);
      pom_m3_tapply(loc, Rp, dx);
      pom_v3_sub(loc, loc, m->body_pos + 3 * c);
      d->qpos[adr] = pom_v3_dot(a, loc);
    } else if (m->jnt_type[j0] == mjJNT_BALL) {
      mju_mat2Quat(d->qpos + adr, Rr);
    }
  }
}

/* Gauss-Newton on the equality residuals over the free dofs, damped
 * (Levenberg-Marquardt, minimum-norm step: loops with redundant rows, e.g.
 * a hinge closed by two connects, have a rank-deficient efc_J). Returns the
 * final largest |residual| (m). */
static double close_loops(const mjModel *m, mjData *d, const int *free) {
  double worst = 0.0;
  for (int it = 0; it < 60; ++it) {
    mj_forward(m, d);
    int ne = d->ne, nv = m->nv;
    worst = 0.0;
    for (int i = 0; i < ne; ++i)
      worst = fmax(worst, fabs(d->efc_pos[i]));
    if (worst < 1e-13 || ne > MAXN || nv > MAXN) break;
    static double A[MAXN * MAXN], y[MAXN], dq[MAXN];
    double diag = 0.0;
    for (int i = 0; i < ne; ++i)
      for (int k = 0; k < ne; ++k) {
        double s = 0.0;
        for (int v = 0; v < nv; ++v)
          if (free[v]) s += d->efc_J[i * nv + v] * d->efc_J[k * nv + v];
        A[i * ne + k] = s;
        if (i == k) diag = fmax(diag, s);
      }
    for (int i = 0; i < ne; ++i) {
      A[i * ne + i] += 1e-12 * diag + 1e-300;
      y[i] = d->efc_pos[i];
    }
    if (chol_solve(A, y, ne) != 0) break;
    for (int v = 0; v < nv; ++v) {
      double s = 0.0;
      if (free[v])
        for (int i = 0; i < ne; ++i)
          s -= d->efc_J[i * nv + v] * y[i];
      dq[v] = s;
    }
    mj_integratePos(m, d->qpos, dq, 1.0);
  }
  return worst;
}

static void check_arch(const char *label, const pom_kin_arch *g, const pom_mechanism *mech) {
  ++n_models;
  char path[512];
  snprintf(path, sizeof path, "%s/test_mjcf_%d.xml", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp",
           n_models);
  pom_error err;
  pom_error_clear(&err);
  const pom_mjcf_coil coil = {.constant = 3.8, .resistance = 10.0, .voltage_limit = 24.0};
  pom_io_file wf;
  pom_status st = pom_io_create(&wf, path, &err);
  if (st == POM_OK) {
    st = pom_mjcf_write(wf.f, label, g, mech, &coil, &err);
    st = st == POM_OK ? pom_io_commit(&wf, &err) : (pom_io_abort(&wf), st);
  }
  if (!check_true(st == POM_OK)) {
    printf("%s: export: %s\n", label, err.message);
    return;
  }
  char msg[1000] = "";
  mjModel *m = mj_loadXML(path, NULL, msg, sizeof msg);
  if (!check_true(m != NULL)) {
    printf("%s: MuJoCo refuses %s: %s\n", label, path, msg);
    return;
  }
  remove(path);
  m->opt.jacobian = mjJAC_DENSE;
  mjData *d = mj_makeData(m);
  body_map bm = {.mech = mech};
  for (int b = 0; b < MAXN; ++b)
    bm.mech_of[b] = -1;
  bm.mech_of[0] = 0;
  bm.mj_of[0] = 0;
  double mass_worst = 0.0;
  for (int b = 1; b < mech->n_bodies; ++b) {
    int id = mj_name2id(m, mjOBJ_BODY, mech->body[b].name);
    if (!check_true(id > 0 && id < MAXN)) {
      printf("%s: body %s missing\n", label, mech->body[b].name);
      goto done;
    }
    bm.mj_of[b] = id;
    bm.mech_of[id] = b;
    double want = mech->body[b].mass > 0.0 ? mech->body[b].mass : 1e-9;
    mass_worst = fmax(mass_worst, fabs(m->body_mass[id] - want) / want);
  }
  check_true(m->nv <= MAXN);
  check_true(mass_worst <= 1e-12);
  check_true(m->nu == mech->n_actuators);
  for (int a = 0; a < m->nu && a < mech->n_actuators; ++a) {
    check_true(m->actuator_trntype[a] == mjTRN_JOINT);
    check_abs(m->actuator_user[a * m->nuser_actuator], 3.8, 0.0);
  }
  static const double poses[5][3] = {
      {0, 0, 0}, {8, -6, 10}, {-12, 5, -7}, {15, 10, 0}, {0, -10, 12}};
  double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  pom_kin_twists tw0, tw;
  if (!check_true(pom_kin_body_twists(g, I, NULL, &tw0, NULL) == POM_OK)) goto done;
  int used = 0;
  double pos_worst = 0.0, rot_worst = 0.0, q_worst = 0.0, res_worst = 0.0, asm_res = 0.0,
         asm_worst = 0.0, kappa_worst = 0.0;
  for (int p = 0; p < 5; ++p) {
    double e[3], R[9];
    for (int k = 0; k < 3; ++k)
      e[k] = poses[p][k] * POM_DEG;
    pom_euler_zyx_to_matrix(R, e);
    if (pom_kin_body_twists(g, R, NULL, &tw, NULL) != POM_OK) continue;
    ++used;
    double qk[3], Jk[9], kappa = NAN;
    if (pom_kin_inverse_jacobian(g, R, qk, Jk, NULL) == POM_OK)
      pom_kin_dexterity(Jk, NULL, &kappa, NULL);
    kappa_worst = fmax(kappa_worst, kappa);
    /* (a) */
    int free[MAXN];
    qpos_from_pomlab(m, d, &bm, &tw, free);
    res_worst = fmax(res_worst, close_loops(m, d, free));
    for (int b = 1; b < mech->n_bodies; ++b) {
      double Rb[9], xb[3], dx[3];
      pom_pose(&tw, mech, b, Rb, xb);
      pom_v3_sub(dx, xb, d->xpos + 3 * bm.mj_of[b]);
      pos_worst = fmax(pos_worst, pom_v3_norm(dx));
      rot_worst = fmax(rot_worst, rot_dist(Rb, d->xmat + 9 * bm.mj_of[b]));
    }
    for (int a = 0; a < m->nu && a < mech->n_actuators; ++a) {
      int jnt = m->actuator_trnid[2 * a];
      q_worst = fmax(q_worst, fabs(d->qpos[m->jnt_qposadr[jnt]] - (tw.q[a] - tw0.q[a])));
    }
    /* (b) */
    double qa[POM_MECH_MAX_ACTUATORS];
    for (int a = 0; a < m->nu && a < POM_MECH_MAX_ACTUATORS; ++a)
      qa[a] = tw.q[a] - tw0.q[a];
    mju_copy(d->qpos, m->qpos0, m->nq);
    for (int v = 0; v < m->nv; ++v)
      free[v] = 1;
    for (int a = 0; a < m->nu && a < POM_MECH_MAX_ACTUATORS; ++a) {
      int jnt = m->actuator_trnid[2 * a];
      d->qpos[m->jnt_qposadr[jnt]] = qa[a];
      free[m->jnt_dofadr[jnt]] = 0;
    }
    asm_res = fmax(asm_res, close_loops(m, d, free));
    asm_worst = fmax(asm_worst, rot_dist(R, d->xmat + 9 * bm.mj_of[mech->platform]));
  }
  printf("%-16s nbody %2d nv %2d ne %2d poses %d: (a) body %.1e m %.1e rad, q %.1e, "
         "residual %.1e m; (b) residual %.1e m, platform %.1e rad; kappa <= %.2f\n",
         label, m->nbody, m->nv, d->ne, used, pos_worst, rot_worst, q_worst, res_worst, asm_res,
         asm_worst, kappa_worst);
  check_true(used >= 3);
  check_true(pos_worst <= 1e-12);
  check_true(rot_worst <= 1e-12);
  check_true(q_worst <= 1e-12);
  check_true(res_worst <= 1e-12);
  check_true(asm_res <= 1e-13);
  check_true(asm_worst <= 1e-9);
done:
  mj_deleteData(d);
  mj_deleteModel(m);
}

/* A config's text with `architecture = "name"` (NULL: as it is), loaded. */
static void check_config(const char *cfg_path, const char *name) {
  char *text = slurp(cfg_path);
  if (!check_true(text != NULL)) {
    printf("cannot read %s\n", cfg_path);
    return;
  }
  static char edited[1 << 17];
  snprintf(edited, sizeof edited, "%s", text);
  if (name) {
    char *at = strstr(text, "\narchitecture = \"");
    char *end = at ? strchr(at + 17, '"') : NULL;
    if (!check_true(at && end)) {
      free(text);
      return;
    }
    snprintf(edited, sizeof edited, "%.*s\narchitecture = \"%s%s", (int)(at - text), text, name,
             end);
  }
  free(text);
  pom_cfg *cfg = NULL;
  pom_error e;
  pom_error_clear(&e);
  pom_kin_arch g;
  pom_mechanism mech;
  if (pom_cfg_load_string(&cfg, edited, cfg_path, &e) != POM_OK ||
      pom_kin_arch_load(&g, cfg, &e) != POM_OK || pom_kin_mechanism_build(&mech, &g, cfg, &e)) {
    check_true(0);
    printf("%s: %s\n", cfg_path, e.message);
    pom_cfg_destroy(cfg);
    return;
  }
  pom_cfg_destroy(cfg);
  check_arch(pom_kin_arch_name(&g), &g, &mech);
}

static pom_status each_file(const char *path, void *user, pom_error *err) {
  (void)user;
  (void)err;
  char stem[128], name[128], cfg_path[600];
  const char *base = strrchr(path, '/');
  base = base ? base + 1 : path;
  size_t len = strlen(base);
  if (len < 6 || len - 5 >= sizeof stem) return POM_OK;
  memcpy(stem, base, len - 5);
  stem[len - 5] = '\0';
  char *t = slurp(path);
  const char *at = t ? strstr(t, "\nname = \"") : NULL;
  const char *end = at ? strchr(at + 9, '"') : NULL;
  if (!check_true(at && end && (size_t)(end - at - 9) < sizeof name)) {
    free(t);
    return POM_OK;
  }
  memcpy(name, at + 9, (size_t)(end - at - 9));
  name[end - at - 9] = '\0';
  free(t);
  snprintf(cfg_path, sizeof cfg_path, "%s/configs/catalog/%s.cfg", POM_SOURCE_DIR, stem);
  FILE *fp = fopen(cfg_path, "r");
  if (fp)
    fclose(fp);
  else
    snprintf(cfg_path, sizeof cfg_path, "%s/configs/%s.cfg", POM_SOURCE_DIR, stem);
  check_config(cfg_path, name);
  return POM_OK;
}

int main(void) {
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_files_register_all(&err) == POM_OK)) printf("%s\n", err.message);
  const char *shipped[] = {"3pss", "3sps", "3rrr"};
  for (int k = 0; k < 3; ++k) {
    char p[600];
    snprintf(p, sizeof p, "%s/configs/%s.cfg", POM_SOURCE_DIR, shipped[k]);
    check_config(p, NULL);
  }
  const char *dir = pom_arch_catalog_dir();
  if (dir && !check_true(pom_arch_catalog_each(dir, each_file, NULL, &err) == POM_OK))
    printf("%s\n", err.message);
  check_true(n_models >= 15);
  return check_summary("test_mjcf");
}
