/* test_limb_table.c - the generic operations of an architecture as a
 * numeric limb table (kinematics/pom_limb.h, docs/kinematics-tables.md)
 * against the hand-coded 3P-S-S/S, 3S-P-S/S and 3-RRR (same geometry, read
 * from the shipped configs), and the forward-mode AD against central
 * differences on an R-S-S and a general non-orthogonal 3-RRR that have no
 * hand-coded version, with IK <-> FK round trips. */
#include "check.h"
#include "pom_arch_file.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_limb.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <stdio.h>
#include <string.h>

/* ---- worst relative differences, per field --------------------------------- */
#define MAX_FIELDS 64
static struct {
  const char *name;
  double worst;
} field[MAX_FIELDS];
static int n_field = 0;

/* max |a - b| / max(|b|_inf, floor) over n entries, recorded under name. */
static double record(const char *name, const double *a, const double *b, int n, double floor) {
  double d = 0.0, m = floor;
  for (int k = 0; k < n; ++k) {
    d = fmax(d, fabs(a[k] - b[k]));
    m = fmax(m, fabs(b[k]));
  }
  double r = (a == b) ? 0.0 : d / m;
  if (!(r == r)) r = INFINITY; /* NaN counts as a failure */
  int f = 0;
  while (f < n_field && strcmp(field[f].name, name) != 0)
    ++f;
  if (f == n_field && n_field < MAX_FIELDS) {
    field[n_field].name = name;
    field[n_field++].worst = 0.0;
  }
  if (f < MAX_FIELDS) field[f].worst = fmax(field[f].worst, r);
  return r;
}

static void report_fields(const char *title, double tol) {
  printf("%s (worst relative difference per field, tolerance %.0e):\n", title, tol);
  for (int f = 0; f < n_field; ++f) {
    printf("  %-28s %.3e\n", field[f].name, field[f].worst);
    check_true(field[f].worst <= tol);
  }
  n_field = 0;
}

/* ---- the shipped configs as tables ------------------------------------------- */
static int load(const char *file, pom_kin_arch *arch, pom_kin_inertia *in) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, file);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_kin_arch_load(arch, cfg, &err) == POM_OK &&
           pom_kin_inertia_load(in, arch, cfg, &err) == POM_OK;
  if (!ok) printf("loading %s: %s\n", path, err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

static void set_joint(pom_limb_joint *j, int type, const double p[3], const double a[3]) {
  memset(j, 0, sizeof *j);
  j->type = type;
  if (p) pom_v3_copy(j->point, p);
  if (a) pom_v3_copy(j->axis, a);
}

static void set_group_body(pom_limb_body *b, const char *name, int group, int place, int cm_from,
                           pom_limb_dir cm_dir, pom_limb_dir z, pom_limb_dir x) {
  memset(b, 0, sizeof *b);
  snprintf(b->name, sizeof b->name, "%s", name);
  b->model = POM_LIMB_MASS_GROUP;
  b->group = group;
  b->place = place;
  b->cm_from = cm_from;
  b->cm_dir = cm_dir;
  b->z_dir = z;
  b->x_dir = x;
}

static void set_names(pom_limb_table *t, const char *a, const char *b, const char *c) {
  snprintf(t->joint_name[0], sizeof t->joint_name[0], "%s", a);
  snprintf(t->joint_name[1], sizeof t->joint_name[1], "%s", b);
  snprintf(t->joint_name[2], sizeof t->joint_name[2], "%s", c);
}

/* The table of a hand-coded instance h (its private point sets). */
static void table_of(pom_limb_table *t, const pom_kin_arch *h) {
  const char *name = pom_kin_arch_name(h);
  memset(t, 0, sizeof *t);
  const pom_limb_dir none = {-1, -1};
  if (strcmp(name, "3PSS") == 0) {
    const double *C = pom_kin_arch_points(h, "platform_points_m");
    const double *B = pom_kin_arch_points(h, "slider_points_m");
    const double *d = pom_kin_arch_points(h, "slider_axes");
    for (int i = 0; i < 3; ++i) {
      pom_limb *L = &t->limb[i];
      set_joint(&L->joint[0], POM_LIMB_JOINT_P, B + 3 * i, d + 3 * i);
      set_joint(&L->joint[1], POM_LIMB_JOINT_S, B + 3 * i, NULL);
      set_joint(&L->joint[2], POM_LIMB_JOINT_S, C + 3 * i, NULL);
      L->actuated = 0;
    }
    set_group_body(&t->body[0], "piston", 0, 1, 0, (pom_limb_dir){0, -1}, (pom_limb_dir){0, -1},
                   none);
    set_group_body(&t->body[1], "link", 1, 2, 0, (pom_limb_dir){1, 2}, (pom_limb_dir){1, 2}, none);
    set_names(t, "P", "B", "C");
    t->measure[1] = (pom_limb_measure){POM_LIMB_MEASURE_CONE_FIXED, 1, 2};
    t->measure[2] = (pom_limb_measure){POM_LIMB_MEASURE_CONE_PLATFORM, 1, 2};
    t->measure[3] = (pom_limb_measure){POM_LIMB_MEASURE_DISTANCE, 1, 2};
    t->central = 1;
  } else if (strcmp(name, "3SPS") == 0) {
    const double *B = pom_kin_arch_points(h, "platform_points_m");
    const double *A = pom_kin_arch_points(h, "base_points_m");
    const double *a1 = pom_kin_arch_points(h, "ujoint_axes");
    for (int i = 0; i < 3; ++i) {
      pom_limb *L = &t->limb[i];
      double s[3], mid[3];
      pom_v3_sub(s, B + 3 * i, A + 3 * i);
      double L0 = pom_v3_normalize(s, s);
      pom_v3_axpy(mid, A + 3 * i, 0.5 * L0, s);
      set_joint(&L->joint[0], POM_LIMB_JOINT_U, A + 3 * i, a1 + 3 * i);
      set_joint(&L->joint[1], POM_LIMB_JOINT_P, mid, s);
      set_joint(&L->joint[2], POM_LIMB_JOINT_S, B + 3 * i, NULL);
      L->actuated = 1;
    }
    set_group_body(&t->body[0], "cylinder", 0, 1, 0, (pom_limb_dir){0, 2}, (pom_limb_dir){0, 2},
                   (pom_limb_dir){0, -1});
    set_group_body(&t->body[1], "piston", 1, 1, 2, (pom_limb_dir){2, 0}, (pom_limb_dir){0, 2},
                   (pom_limb_dir){0, -1});
    set_names(t, "A", "P", "B");
    t->measure[1] = (pom_limb_measure){POM_LIMB_MEASURE_CONE_FIXED, 0, 2};
    t->measure[2] = (pom_limb_measure){POM_LIMB_MEASURE_CONE_PLATFORM, 0, 2};
    t->measure[3] = (pom_limb_measure){POM_LIMB_MEASURE_DISTANCE, 0, 2};
    t->central = 1;
  } else {
    const double *u = pom_kin_arch_points(h, "base_axes");
    const double *w = pom_kin_arch_points(h, "elbow_axes");
    const double *v = pom_kin_arch_points(h, "platform_axes");
    const double O[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 3; ++i) {
      pom_limb *L = &t->limb[i];
      set_joint(&L->joint[0], POM_LIMB_JOINT_R, O, u + 3 * i);
      set_joint(&L->joint[1], POM_LIMB_JOINT_R, O, w + 3 * i);
      set_joint(&L->joint[2], POM_LIMB_JOINT_R, O, v + 3 * i);
      L->actuated = 0;
    }
    /* the link model's values: density, section, elbow mass, rotor mass,
     * rotor inertia (arch_3rrr.c) */
    for (int b = 0; b < 2; ++b) {
      pom_limb_body *bd = &t->body[b];
      memset(bd, 0, sizeof *bd);
      snprintf(bd->name, sizeof bd->name, "%s", b == 0 ? "proximal" : "distal");
      bd->model = POM_LIMB_MASS_ARC;
      bd->arc_a = b;
      bd->arc_b = b + 1;
      bd->v_density = 0;
      bd->v_section = 1;
      bd->v_point_mass = b == 0 ? 3 : 2;
      bd->point_joint = b;
      bd->v_rotor = b == 0 ? 4 : -1;
      bd->rotor_joint = 0;
    }
    set_names(t, "U", "W", "V");
    t->measure[1] = (pom_limb_measure){POM_LIMB_MEASURE_AXIS_ANGLE, 1, -1};
    t->arc_radius = h->design.scale;
    t->central = -1;
  }
}

/* The catalog instance g of the same geometry as h, under the type t (h's
 * descriptors, the generic operations). */
static int catalog_twin(pom_kin_arch *g, pom_kin_arch_type *t, const pom_kin_arch *h) {
  *t = *h->type;
  pom_limb_type_ops(t);
  *g = *h;
  g->type = t;
  memset(g->data, 0, sizeof g->data);
  table_of(POM_LIMB_TABLE(g), h);
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_arch_finish(g, &err) != POM_OK) {
    printf("%s as a table: %s\n", pom_kin_arch_name(h), err.message);
    return 0;
  }
  return 1;
}

/* ---- one pose: every field of limb_twist_diff ----------------------------------- */
static void compare_body(const char *tag, const pom_kin_body_twist *a, const pom_kin_body_twist *b,
                         double len, double w2, int pose_fields) {
  static char names[8][6][40];
  (void)tag;
  (void)names;
  if (pose_fields) {
    record("body R", a->R, b->R, 9, 1.0);
    record("body ref_home", a->ref_home, b->ref_home, 3, len);
    record("body ref", a->ref, b->ref, 3, len);
    record("body spin_axis", a->spin_axis, b->spin_axis, 3, 1.0);
    check_true(a->spin_free == b->spin_free);
  }
  record("body A", a->A, b->A, 9, len);
  record("body B", a->B, b->B, 9, 1.0);
  record("body a_bias", a->a_bias, b->a_bias, 3, len * w2);
  record("body alpha_bias", a->alpha_bias, b->alpha_bias, 3, w2);
}

static void compare_twists(const pom_kin_twists *a, const pom_kin_twists *b, int i, double len,
                           double qs, double w2, int pose_fields) {
  record("q", a->q + i, b->q + i, 1, qs);
  record("J row", a->J + 3 * i, b->J + 3 * i, 3, qs);
  record("q_bias", a->q_bias + i, b->q_bias + i, 1, qs * w2);
  for (int k = 2 + 2 * i; k < 4 + 2 * i; ++k)
    compare_body("", &a->body[k], &b->body[k], len, w2, pose_fields);
}

static void random_rotation(pom_rng *rng, double R[9], double half) {
  double e[3];
  for (int k = 0; k < 3; ++k)
    e[k] = pom_rng_range(rng, -half, half);
  pom_euler_zyx_to_matrix(R, e);
}

static void random_omega(pom_rng *rng, double w[3], double norm) {
  for (int k = 0; k < 3; ++k)
    w[k] = pom_rng_normal(rng);
  pom_v3_scale(w, norm / pom_v3_norm(w), w);
}

/* The hand-coded h against its table twin at n random reachable poses. */
static void against_hand_coded(const char *file, double half_deg, pom_rng *rng, int n) {
  pom_kin_arch h, g;
  pom_kin_arch_type t;
  pom_kin_inertia in;
  if (!check_true(load(file, &h, &in))) return;
  if (!check_true(catalog_twin(&g, &t, &h))) return;
  /* length scale: the platform radius or the link radius; q scale: m or rad */
  const double len = h.design.scale > 0.0 ? h.design.scale : 0.03;
  const double qs = h.type->actuator == POM_ACT_PRISMATIC ? len : 1.0;
  const double wn = 5.0, w2 = wn * wn;
  int used = 0, tries = 0;
  while (used < n && tries < 20 * n) {
    ++tries;
    double R[9], w[3], qh[3], Jh[9];
    random_rotation(rng, R, half_deg * POM_DEG);
    random_omega(rng, w, wn);
    if (pom_kin_inverse_jacobian(&h, R, qh, Jh, NULL) != POM_OK) continue;
    ++used;
    for (int i = 0; i < 3; ++i) {
      double q1, q2, r1[3], r2[3], t1 = -1.0, t2 = -2.0;
      check_true(h.type->limb(&h, i, R, &q1, r1, &t1) && g.type->limb(&g, i, R, &q2, r2, &t2));
      record("limb op q", &q2, &q1, 1, qs);
      record("limb op J row", r2, r1, 3, qs);
      /* the serial measure (docs/kinematics-tables.md 3.2): both write it */
      check_true(t1 >= 0.0 && t1 <= 1.0);
      record("limb op transmission", &t2, &t1, 1, 1.0);
      static pom_kin_twists ta, tb;
      static pom_kin_twists_diff da, db;
      memset(&ta, 0, sizeof ta);
      memset(&tb, 0, sizeof tb);
      memset(&da, 0, sizeof da);
      memset(&db, 0, sizeof db);
      check_true(h.type->limb_twist_diff(&h, i, R, w, &ta, &da));
      check_true(g.type->limb_twist_diff(&g, i, R, w, &tb, &db));
      compare_twists(&tb, &ta, i, len, qs, w2, 1);
      pom_kin_twists tc;
      memset(&tc, 0, sizeof tc);
      check_true(g.type->limb_twist(&g, i, R, w, &tc));
      record("limb_twist = diff's", (const double *)&tc, (const double *)&tb,
             (int)(sizeof tc / sizeof(double)), 1.0);
      for (int k = 0; k < 3; ++k) {
        /* d/dtheta: one more power of 1/rad; d/domega: one fewer of rad/s */
        compare_twists(&db.d_theta[k], &da.d_theta[k], i, len, qs, w2, 0);
        compare_twists(&db.d_omega[k], &da.d_omega[k], i, len, qs, wn, 0);
      }
    }
    double vh[9], vg[9];
    h.type->limit_values(&h, R, qh, vh);
    g.type->limit_values(&g, R, qh, vg);
    for (int k = 0; k < 3; ++k) {
      if (!h.type->limits[k + 1].name) continue;
      record(h.type->limits[k + 1].cls == POM_KIN_LIMCLASS_CONE ? "limit (angle)" : "limit value",
             vg + 3 * k, vh + 3 * k, 3, h.type->limits[k + 1].unit[0] == 'm' ? len : 1.0);
    }
  }
  printf("%s: %d reachable poses of %d drawn (ZYX Euler within +-%g deg, |omega| = %g rad/s)\n",
         file, used, tries, half_deg, wn);
  check_true(used == n);
  double fh = h.type->footprint(&h), fg = g.type->footprint(&g);
  record("footprint", &fg, &fh, 1, len);

  /* the mechanism: bodies, joints, actuators, mass properties */
  static pom_mechanism mh, mg;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_kin_mechanism_from(&mh, &h, &in, &err) == POM_OK);
  check_true(pom_kin_mechanism_from(&mg, &g, &in, &err) == POM_OK);
  check_true(mh.n_bodies == mg.n_bodies && mh.n_joints == mg.n_joints &&
             mh.n_actuators == mg.n_actuators && mh.platform == mg.platform);
  double mass_scale = 0.0, inertia_scale = 0.0;
  for (int b = 0; b < mh.n_bodies; ++b) {
    mass_scale = fmax(mass_scale, mh.body[b].mass);
    for (int k = 0; k < 9; ++k)
      inertia_scale = fmax(inertia_scale, fabs(mh.body[b].inertia[k]));
  }
  for (int b = 0; b < mh.n_bodies && b < mg.n_bodies; ++b) {
    check_true(strcmp(mh.body[b].name, mg.body[b].name) == 0);
    record("mechanism body mass", &mg.body[b].mass, &mh.body[b].mass, 1, mass_scale);
    record("mechanism body cm", mg.body[b].cm, mh.body[b].cm, 3, len);
    record("mechanism body inertia", mg.body[b].inertia, mh.body[b].inertia, 9, inertia_scale);
  }
  for (int j = 0; j < mh.n_joints && j < mg.n_joints; ++j) {
    const pom_mech_joint *a = &mh.joint[j], *b = &mg.joint[j];
    check_true(strcmp(a->name, b->name) == 0 && a->type == b->type && a->body[0] == b->body[0] &&
               a->body[1] == b->body[1] && a->actuator == b->actuator);
    record("mechanism joint point", b->point, a->point, 3, len);
    record("mechanism joint axis", b->axis, a->axis, 3, 1.0);
    record("mechanism joint axis2", b->axis2, a->axis2, 3, 1.0);
  }
  for (int k = 0; k < mh.n_actuators && k < mg.n_actuators; ++k)
    check_true(mh.actuator[k].joint == mg.actuator[k].joint &&
               mh.actuator[k].moving_body == mg.actuator[k].moving_body &&
               mh.actuator[k].kind == mg.actuator[k].kind &&
               mh.actuator[k].stroke == mg.actuator[k].stroke);
  char title[128];
  snprintf(title, sizeof title, "%s: table vs hand-coded", file);
  /* 1e-12: both sides evaluate exact formulas of the same quantities; the
   * AD's truncated series are exact, so only rounding separates them */
  report_fields(title, 1e-12);
}

/* ---- AD vs central differences on limbs with no hand-coded version ------------- */
static void rotate_by(double out[9], const double R[9], const double axis[3], double angle) {
  double E[9];
  pom_m3_axis_angle(E, axis, angle);
  pom_m3_mul(out, E, R);
}

static const double unit_e[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};

/* Limb i's fields at R (NaN when it fails: the comparison then fails). */
static void twist_at(const pom_kin_arch *g, int i, const double R[9], const double w[3],
                     pom_kin_twists *t) {
  memset(t, 0, sizeof *t);
  if (!g->type->limb_twist(g, i, R, w, t)) memset(t, 0xff, sizeof *t);
}

/* (f(+h) - f(-h)) / 2h over every double of the struct. */
static void central(pom_kin_twists *d, const pom_kin_twists *p, const pom_kin_twists *m, double h) {
  const double *a = (const double *)(const void *)p, *b = (const double *)(const void *)m;
  double *o = (double *)(void *)d;
  for (size_t k = 0; k < sizeof *d / sizeof(double); ++k)
    o[k] = (a[k] - b[k]) / (2.0 * h);
}

/* The angular velocity of a body from central differences of its pose:
 * vee((R(+h) - R(-h)) / 2h R^T). */
static void omega_fd(double w[3], const double Rp[9], const double Rm[9], const double R[9],
                     double h) {
  double D[9], X[9];
  for (int k = 0; k < 9; ++k)
    D[k] = (Rp[k] - Rm[k]) / (2.0 * h);
  pom_m3_mult(X, D, R);
  pom_v3_set(w, 0.5 * (X[7] - X[5]), 0.5 * (X[2] - X[6]), 0.5 * (X[3] - X[1]));
}

static void ad_vs_fd(const char *title, const pom_kin_arch *g, pom_rng *rng, double half_deg, int n,
                     double len, double tol) {
  const double h = 5e-6, wn = 5.0, w2 = wn * wn,
               qs = g->type->actuator == POM_ACT_PRISMATIC ? len : 1.0;
  int used = 0, tries = 0, fk_fail = 0;
  double fk_worst = 0.0;
  while (used < n && tries < 50 * n) {
    ++tries;
    double R[9], w[3], q[3], J[9];
    random_rotation(rng, R, half_deg * POM_DEG);
    random_omega(rng, w, wn);
    if (pom_kin_inverse_jacobian(g, R, q, J, NULL) != POM_OK) continue;
    double dex;
    pom_kin_dexterity(J, NULL, NULL, &dex);
    if (dex < 0.05) continue; /* away from singularities, where differences lose digits */
    /* on home's side of the parallel singularities: the FK's assembly mode */
    if (!(pom_m3_det(J) * g->home_det_sign > 0.0)) continue;
    ++used;
    /* IK <-> FK round trip from home */
    double Rf[9], D[9], rv[3];
    pom_error err;
    pom_error_clear(&err);
    /* the FK stops at |q residual| <= residual_tol, i.e. a rotation error of
     * about residual_tol / sv_min(J): 1e-14 (m or rad) keeps that far
     * below 1e-10 rad for the linear limbs too (J ~ 0.03 m/rad) */
    pom_kin_fk_opts fo;
    pom_kin_fk_defaults(&fo);
    fo.residual_tol = 1e-14;
    if (pom_kin_forward(g, q, NULL, &fo, Rf, NULL, &err) == POM_OK) {
      pom_m3_mult(D, Rf, R);
      pom_m3_rotvec(rv, D);
      fk_worst = fmax(fk_worst, pom_v3_norm(rv));
    } else {
      ++fk_fail;
    }
    for (int i = 0; i < 3; ++i) {
      static pom_kin_twists t0, tp, tm, fd;
      static pom_kin_twists_diff dd;
      memset(&t0, 0, sizeof t0);
      memset(&dd, 0, sizeof dd);
      if (!check_true(g->type->limb_twist_diff(g, i, R, w, &t0, &dd))) continue;
      for (int k = 0; k < 3; ++k) {
        double Rp[9], Rm[9], wp[3], wm[3];
        /* first order: J, A, B columns from q, ref and the body poses */
        rotate_by(Rp, R, unit_e[k], h);
        rotate_by(Rm, R, unit_e[k], -h);
        twist_at(g, i, Rp, w, &tp);
        twist_at(g, i, Rm, w, &tm);
        central(&fd, &tp, &tm, h);
        record("J column (FD of q)", fd.q + i, &t0.J[3 * i + k], 1, qs);
        for (int b = 2 + 2 * i; b < 4 + 2 * i; ++b) {
          const pom_kin_body_twist *B0 = &t0.body[b];
          double Acol[3] = {B0->A[k], B0->A[3 + k], B0->A[6 + k]};
          double Bcol[3] = {B0->B[k], B0->B[3 + k], B0->B[6 + k]}, wf[3];
          record("A column (FD of ref)", fd.body[b].ref, Acol, 3, len);
          omega_fd(wf, tp.body[b].R, tm.body[b].R, B0->R, h);
          if (B0->spin_free) { /* the pose's spin is not the body's: compare across the axis */
            const double *s = B0->spin_axis;
            pom_v3_axpy(wf, wf, -pom_v3_dot(wf, s), s);
            double sB = pom_v3_dot(Bcol, s), zero = 0.0;
            record("B column: zero spin", &sB, &zero, 1, 1.0);
          }
          record("B column (FD of pose)", wf, Bcol, 3, 1.0);
        }
        /* d_theta: central differences of every field of limb_twist */
        const pom_kin_twists *dt = &dd.d_theta[k];
        record("d_theta q", fd.q + i, dt->q + i, 1, qs);
        record("d_theta J", fd.J + 3 * i, dt->J + 3 * i, 3, qs);
        record("d_theta q_bias", fd.q_bias + i, dt->q_bias + i, 1, qs * w2);
        for (int b = 2 + 2 * i; b < 4 + 2 * i; ++b) {
          record("d_theta A", fd.body[b].A, dt->body[b].A, 9, len);
          record("d_theta B", fd.body[b].B, dt->body[b].B, 9, 1.0);
          record("d_theta a_bias", fd.body[b].a_bias, dt->body[b].a_bias, 3, len * w2);
          record("d_theta alpha_bias", fd.body[b].alpha_bias, dt->body[b].alpha_bias, 3, w2);
        }
        /* d_omega: the biases are quadratic in omega, the difference exact
         * but for rounding */
        pom_v3_axpy(wp, w, h * wn, unit_e[k]);
        pom_v3_axpy(wm, w, -h * wn, unit_e[k]);
        twist_at(g, i, R, wp, &tp);
        twist_at(g, i, R, wm, &tm);
        central(&fd, &tp, &tm, h * wn);
        const pom_kin_twists *dw = &dd.d_omega[k];
        record("d_omega q_bias", fd.q_bias + i, dw->q_bias + i, 1, qs * wn);
        for (int b = 2 + 2 * i; b < 4 + 2 * i; ++b) {
          record("d_omega a_bias", fd.body[b].a_bias, dw->body[b].a_bias, 3, len * wn);
          record("d_omega alpha_bias", fd.body[b].alpha_bias, dw->body[b].alpha_bias, 3, wn);
        }
      }
      /* the biases: d/dt of the first-order maps along the motion exp(t [w]) R */
      double Rp[9], Rm[9], wu[3];
      double a = pom_v3_norm(w);
      pom_v3_scale(wu, 1.0 / a, w);
      rotate_by(Rp, R, wu, h); /* t = +-h / |w|: a rotation of +-h rad */
      rotate_by(Rm, R, wu, -h);
      twist_at(g, i, Rp, w, &tp);
      twist_at(g, i, Rm, w, &tm);
      double qd_p = pom_v3_dot(tp.J + 3 * i, w), qd_m = pom_v3_dot(tm.J + 3 * i, w);
      double dt2 = 2.0 * h / a, qb = (qd_p - qd_m) / dt2;
      record("q_bias (FD of J w)", &qb, t0.q_bias + i, 1, qs * w2);
      for (int b = 2 + 2 * i; b < 4 + 2 * i; ++b) {
        double vp[3], vm[3], ab[3], al[3];
        pom_m3_apply(vp, tp.body[b].A, w);
        pom_m3_apply(vm, tm.body[b].A, w);
        for (int c = 0; c < 3; ++c)
          ab[c] = (vp[c] - vm[c]) / dt2;
        record("a_bias (FD of A w)", ab, t0.body[b].a_bias, 3, len * w2);
        pom_m3_apply(vp, tp.body[b].B, w);
        pom_m3_apply(vm, tm.body[b].B, w);
        for (int c = 0; c < 3; ++c)
          al[c] = (vp[c] - vm[c]) / dt2;
        record("alpha_bias (FD of B w)", al, t0.body[b].alpha_bias, 3, w2);
      }
    }
  }
  printf("%s: %d poses (dexterity >= 0.05, det J of home's sign) of %d drawn within +-%g deg; IK "
         "-> FK worst %.3e rad, "
         "%d FK failures\n",
         title, used, tries, half_deg, fk_worst, fk_fail);
  check_true(used == n);
  check_true(fk_fail == 0);
  check_true(fk_worst < 1e-10);
  report_fields(title, tol);
}

/* An R-S-S with each limb a little different (no symmetry to hide behind). */
static int make_rss(pom_kin_arch *g, pom_kin_arch_type *t) {
  memset(t, 0, sizeof *t);
  *t = *pom_kin_arch_type_find("3RRR");
  t->name = "RSS_TEST";
  t->optional_central_joint = 0;
  t->n_inertia_values = 0;
  t->n_inertia_bodies = 0;
  pom_limb_type_ops(t);
  memset(g, 0, sizeof *g);
  g->type = t;
  pom_kin_limits_defaults(g);
  g->central_joint = 1;
  g->design.scale = 0.03;
  pom_limb_table *tb = POM_LIMB_TABLE(g);
  for (int i = 0; i < 3; ++i) {
    double phi = POM_PI / 2 + 2.0 * POM_PI * i / 3.0 + 0.05 * i;
    double er[3] = {cos(phi), sin(phi), 0.0}, et[3] = {-sin(phi), cos(phi), 0.0};
    double p0[3], p1[3], p2[3], a[3];
    for (int k = 0; k < 3; ++k) {
      p2[k] = 0.03 * er[k] + (k == 2 ? 0.004 * i : 0.0);
      p0[k] = 0.05 * er[k] + (k == 2 ? -0.035 : 0.0);
      a[k] = et[k] + 0.2 * (k == 2) + 0.1 * i * er[k];
      p1[k] = p0[k] + 0.012 * (0.8 * er[k] + (k == 2 ? 0.6 : 0.0)) + 0.002 * i * et[k];
    }
    pom_limb *L = &tb->limb[i];
    set_joint(&L->joint[0], POM_LIMB_JOINT_R, p0, a);
    set_joint(&L->joint[1], POM_LIMB_JOINT_S, p1, NULL);
    set_joint(&L->joint[2], POM_LIMB_JOINT_S, p2, NULL);
    L->actuated = 0;
  }
  for (int b = 0; b < 2; ++b)
    snprintf(tb->body[b].name, sizeof tb->body[b].name, "%s", b ? "link" : "crank");
  set_names(tb, "R", "B", "C");
  tb->measure[1] = (pom_limb_measure){POM_LIMB_MEASURE_DISTANCE, 1, 2};
  tb->central = 1;
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_arch_finish(g, &err) != POM_OK) {
    printf("R-S-S: %s\n", err.message);
    return 0;
  }
  return 1;
}

/* A general 3-RRR: nine axes through O with no symmetry, no right angles. */
static int make_rrr(pom_kin_arch *g, pom_kin_arch_type *t) {
  *t = *pom_kin_arch_type_find("3RRR");
  t->name = "RRR_TEST";
  pom_limb_type_ops(t);
  memset(g, 0, sizeof *g);
  g->type = t;
  pom_kin_limits_defaults(g);
  g->design.scale = 0.05;
  pom_limb_table *tb = POM_LIMB_TABLE(g);
  const double O[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 3; ++i) {
    double phi = 0.3 + 2.0 * POM_PI * i / 3.0 + 0.1 * i * i, u[3], v[3], w[3];
    double bu = (50.0 + 4.0 * i) * POM_DEG, bv = (62.0 - 3.0 * i) * POM_DEG;
    pom_v3_set(u, sin(bu) * cos(phi), sin(bu) * sin(phi), -cos(bu));
    pom_v3_set(v, sin(bv) * cos(phi + 0.4), sin(bv) * sin(phi + 0.4), cos(bv));
    double uxv[3];
    pom_v3_cross(uxv, u, v);
    for (int k = 0; k < 3; ++k)
      w[k] = 0.55 * u[k] + 0.45 * v[k] + (0.7 + 0.05 * i) * uxv[k];
    pom_v3_normalize(w, w);
    pom_limb *L = &tb->limb[i];
    set_joint(&L->joint[0], POM_LIMB_JOINT_R, O, u);
    set_joint(&L->joint[1], POM_LIMB_JOINT_R, O, w);
    set_joint(&L->joint[2], POM_LIMB_JOINT_R, O, v);
    L->actuated = 0;
  }
  for (int b = 0; b < 2; ++b)
    snprintf(tb->body[b].name, sizeof tb->body[b].name, "%s", b ? "distal" : "proximal");
  set_names(tb, "U", "W", "V");
  tb->measure[1] = (pom_limb_measure){POM_LIMB_MEASURE_AXIS_ANGLE, 1, -1};
  tb->central = -1;
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_arch_finish(g, &err) != POM_OK) {
    printf("general 3-RRR: %s\n", err.message);
    return 0;
  }
  return 1;
}

/* The shipped 3S-P-S/S with spherical joints at the ground: S-P-S limbs
 * whose cylinder and piston spin freely. */
static int make_sps(pom_kin_arch *g, pom_kin_arch_type *t) {
  pom_kin_arch h;
  pom_kin_inertia in;
  if (!load("3sps.cfg", &h, &in)) return 0;
  *t = *h.type;
  pom_limb_type_ops(t);
  *g = h;
  g->type = t;
  memset(g->data, 0, sizeof g->data);
  pom_limb_table *tb = POM_LIMB_TABLE(g);
  table_of(tb, &h);
  for (int i = 0; i < 3; ++i) {
    tb->limb[i].joint[0].type = POM_LIMB_JOINT_S;
    pom_v3_set(tb->limb[i].joint[0].axis, 0.0, 0.0, 0.0);
  }
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_arch_finish(g, &err) != POM_OK) {
    printf("S-P-S: %s\n", err.message);
    return 0;
  }
  pom_mechanism m;
  check_true(pom_kin_mechanism_from(&m, g, &in, &err) == POM_OK && m.n_bodies == 8 &&
             m.joint[1].type == POM_JOINT_SPHERICAL);
  return 1;
}

/* finish refuses what no kernel covers, and a branch that is not home's. */
static void refusals(void) {
  pom_kin_arch g;
  pom_kin_arch_type t;
  pom_error err;
  if (!check_true(make_rss(&g, &t))) return;
  pom_kin_arch bad = g;
  pom_limb_table *tb = POM_LIMB_TABLE(&bad);
  tb->limb[1].joint[1].type = POM_LIMB_JOINT_U;
  pom_error_clear(&err);
  check_true(pom_kin_arch_finish(&bad, &err) == POM_ERR_ARG &&
             strstr(err.message, "limb 2: no IK kernel") != NULL);
  bad = g;
  tb = POM_LIMB_TABLE(&bad);
  tb->limb[0].branch = -tb->limb[0].branch;
  pom_error_clear(&err);
  check_true(pom_kin_arch_finish(&bad, &err) == POM_ERR_ARG &&
             strstr(err.message, "not the IK root through the home") != NULL);
  bad = g;
  tb = POM_LIMB_TABLE(&bad);
  tb->central = 0;
  pom_error_clear(&err);
  check_true(pom_kin_arch_finish(&bad, &err) == POM_ERR_ARG &&
             strstr(err.message, "central spherical joint is needed") != NULL);
}

int main(void) {
  pom_rng rng;
  pom_rng_seed(&rng, 27, 1);
  check_true(sizeof(pom_limb_table) <= sizeof(((pom_kin_arch *)0)->data));
  /* the shipped configs, 200 reachable poses each within their workspaces */
  against_hand_coded("3pss.cfg", 20.0, &rng, 200);
  against_hand_coded("3sps.cfg", 15.0, &rng, 200);
  against_hand_coded("3rrr.cfg", 30.0, &rng, 200);

  pom_kin_arch g;
  pom_kin_arch_type t;
  /* central differences, h = 5e-6 rad: truncation h^2 |f'''| / 6, rounding
   * eps |f| / h ~ 4e-11 of the field's scale. The differences measured
   * scale as h^2 (R-S-S d_theta a_bias: 4.1e-7, 1.0e-7, 2.6e-8 at h = 2e-5,
   * 1e-5, 5e-6), so they are truncation, not AD error; 1e-7 bounds them at
   * this h with a margin of 4 */
  if (check_true(make_rss(&g, &t)))
    ad_vs_fd("R-S-S: AD vs central differences", &g, &rng, 15.0, 40, 0.03, 1e-7);
  if (check_true(make_rrr(&g, &t)))
    ad_vs_fd("general 3-RRR: AD vs central differences", &g, &rng, 20.0, 40, 0.05, 1e-7);
  if (check_true(make_sps(&g, &t)))
    ad_vs_fd("S-P-S: AD vs central differences", &g, &rng, 15.0, 40, 0.03, 1e-7);
  /* the R-U-U and U-P-U kernels (catalog C13, C14: no hand-coded version;
   * docs/kinematics-tables.md 2.5), the same differences and bound */
  pom_error err;
  pom_error_clear(&err);
  if (!check_true(pom_arch_files_register_all(&err) == POM_OK)) printf("%s\n", err.message);
  pom_kin_inertia in;
  if (check_true(load("catalog/3ruu_wrist.cfg", &g, &in)))
    ad_vs_fd("R-U-U (3ruu_wrist): AD vs central differences", &g, &rng, 20.0, 40, 0.025, 1e-7);
  if (check_true(load("catalog/3upu_wrist.cfg", &g, &in)))
    ad_vs_fd("U-P-U (3upu_wrist): AD vs central differences", &g, &rng, 15.0, 40, 0.03, 1e-7);
  refusals();
  return check_summary("test_limb_table");
}
