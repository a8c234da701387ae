/* test_scene.c - the scene options of the dynamics engine (docs/dynamics.md
 * section 13): each option changes the model as documented (states,
 * constraints, energy terms) and stays close to full fidelity where the docs
 * say it is safe, with the measured differences as bounds. */
#include "check.h"
#include "dyn_test_util.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double zero3[3] = {0.0, 0.0, 0.0};

/* ---- helpers ------------------------------------------------------------- */
static void mech_init(pom_mechanism *m) {
  memset(m, 0, sizeof *m);
  m->n_bodies = 1; /* ground */
  snprintf(m->body[0].name, sizeof m->body[0].name, "ground");
  m->platform = -1; /* no platform: every body is a limb body */
}

static int mech_body(pom_mechanism *m, double mass, const double I[9], const double cm[3]) {
  int k = m->n_bodies++;
  snprintf(m->body[k].name, sizeof m->body[k].name, "body%d", k);
  m->body[k].mass = mass;
  memcpy(m->body[k].inertia, I, sizeof m->body[k].inertia);
  pom_v3_copy(m->body[k].cm, cm);
  return k;
}

static int mech_joint(pom_mechanism *m, pom_joint_type type, int b0, int b1, const double p[3],
                      const double axis[3], const double axis2[3]) {
  int k = m->n_joints++;
  pom_mech_joint *j = &m->joint[k];
  snprintf(j->name, sizeof j->name, "J%d", k);
  j->type = type;
  j->body[0] = b0;
  j->body[1] = b1;
  pom_v3_copy(j->point, p);
  if (axis) pom_v3_copy(j->axis, axis);
  if (axis2) pom_v3_copy(j->axis2, axis2);
  j->actuator = -1;
  return k;
}

static void diag_inertia(double I[9], double a, double b, double c) {
  memset(I, 0, 9 * sizeof(double));
  I[0] = a;
  I[4] = b;
  I[8] = c;
}

/* ---- 1. a body pinned at its ground pivot -------------------------------- */
/* A compound pendulum on a ground spherical joint: lumped, it turns about the
 * pivot with I + m l^2 and its weight at the CM. Period and energy are those
 * of the rigid pendulum; the pivot has no deflection. */
static void test_pinned_pendulum(void) {
  const double mass = 0.05, l = 0.04, g = 9.81, Ixx = 2.1e-6;
  double I[9], cm[3] = {0.0, 0.0, -l};
  diag_inertia(I, Ixx, 2.3e-6, 1.2e-6);
  pom_mechanism mech;
  mech_init(&mech);
  mech.gravity[2] = -g;
  mech_body(&mech, mass, I, cm);
  mech_joint(&mech, POM_JOINT_SPHERICAL, 0, 1, zero3, NULL, NULL);
  double wn = sqrt(mass * g * l / (Ixx + mass * l * l));
  double period = 2.0 * POM_PI / wn;
  pom_dyn_params p;
  pom_dyn_params_defaults(&p);
  p.scene.limb_inertia = POM_INERTIA_LUMPED;
  p.solver.rtol = 1e-9;
  p.solver.atol_scale = 1e-6;
  p.maneuver.horizon = 2.5 * period; /* a zero crossing of the swing */
  p.maneuver.output_dt = 1e-3;
  pom_dyn_initial init;
  memset(&init, 0, sizeof init);
  const double theta0 = 2e-3; /* small amplitude: period shift theta0^2/16 = 2.5e-7 */
  pom_v3_set(init.omega[1], theta0 * wn, 0.0, 0.0);
  run_t r;
  check_true(run(&r, &mech, &p, zero3, &init) == POM_OK);
  if (r.st == POM_OK) {
    double R[9], x[3], rv[3];
    check_true(pom_dyn_body_pose(r.m, r.d, 1, R, x, NULL) == POM_OK);
    pom_m3_rotvec(rv, R);
    /* at 2.5 periods the angle is theta0 sin(2 pi 2.5 (1 + eps)) ~ theta0 5 pi eps for a
     * relative period error eps; the full model's joint compliance gives eps = m g / (k l)
     * = 1.2e-5 (3.8e-7 rad); the rigid pivot must do 5x better (eps < 2.4e-6) */
    check_abs(pom_v3_norm(rv), 0.0, theta0 * 5.0 * POM_PI * 2.4e-6);
    check_abs(r.mt.max_deflection, 0.0, 0.0); /* no linear constraint left at the pivot */
    double want[3];
    pom_m3_apply(want, R, cm); /* the reported CM is the true one, at l from the pivot */
    check_abs(pom_v3_norm(x), l, 1e-12);
    check_abs(x[1], want[1], 1e-12);
  }
  run_free(&r);

  /* 3-D swing without damping: stored energy (kinetic about the pivot +
   * weight at the CM) conserved to the integration error */
  p.joints.damping = p.joints.angular_damping = 0.0;
  p.maneuver.horizon = 0.2;
  pom_v3_set(init.omega[1], 3.0, 1.5, 2.0);
  check_true(run(&r, &mech, &p, zero3, &init) == POM_OK);
  if (r.st == POM_OK) {
    /* as the full model's conservation test in test_dynamics.c: ~rtol per
     * step over ~1e3 steps, bound 2e-6; a weight applied at the pivot instead
     * of the CM would leave m g l (1 - cos) ~ 1e-2 J unaccounted */
    check_abs(r.mt.energy_stored_change / r.mt.energy_balance_scale, 0.0, 2e-6);
    check_abs(r.mt.energy_dissipated, 0.0, 0.0);
  }
  run_free(&r);
}

/* ---- 2. options on the shipped mechanisms --------------------------------- */
typedef struct {
  int n_states;
  double exec, energy, bearing, max_ang;
  pom_status st;
} outcome;

static outcome simulate_shipped(const pom_mechanism *mech, const pom_dyn_params *p) {
  outcome o;
  memset(&o, 0, sizeof o);
  const double target[3] = {3e-3, -3e-3, 3e-3};
  run_t r;
  o.st = run(&r, mech, p, target, NULL);
  if (r.m) o.n_states = pom_dyn_model_n_states(r.m);
  o.exec = r.mt.execution_time;
  o.energy = r.mt.energy_total;
  o.bearing = r.mt.energy_bearing[0] + r.mt.energy_bearing[1] + r.mt.energy_bearing[2];
  o.max_ang = r.mt.max_angular_deflection;
  run_free(&r);
  return o;
}

static void test_shipped_options(const char *file, int links) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!check_true(load_shipped(file, &arch, &mech, &p))) return;
  p.solver.rtol = 1e-7;
  outcome full = simulate_shipped(&mech, &p);
  check_true(full.st == POM_OK);

  /* quasi-static coil: three flux states fewer; settling within 0.5 %, energy within 1 %
   * (measured 0.1 % and 0.1-0.3 %: L/R = 14.5 us against 10-20 ms maneuvers) */
  pom_dyn_params q = p;
  q.scene.coil_inductance = 0;
  outcome qs = simulate_shipped(&mech, &q);
  check_true(qs.n_states == full.n_states - 3);
  check_rel(qs.exec, full.exec, 5e-3);
  check_rel(qs.energy, full.energy, 1e-2);

  /* bearing friction off: no bearing dissipation at all */
  q = p;
  q.scene.bearing_friction = 0;
  outcome nb = simulate_shipped(&mech, &q);
  check_true(full.bearing > 0);
  check_abs(nb.bearing, 0.0, 0.0);

  /* quaternion: one state more per moving body (7 bodies) */
  q = p;
  q.scene.orientation = POM_ORIENT_QUATERNION;
  outcome qu = simulate_shipped(&mech, &q);
  check_true(qu.n_states == full.n_states + 7);

  /* universal joints as spherical: the spin constraint is gone (no angular
   * deflection on the U joints; the prismatic joints keep theirs) and the
   * result barely moves: the limbs are axisymmetric with the CM on the axis,
   * so their spin is decoupled (3SPS measured: energy 1e-5, settling 0) */
  q = p;
  q.scene.universal_joint = 0;
  outcome nu = simulate_shipped(&mech, &q);
  check_true(nu.n_states == full.n_states);
  check_rel(nu.exec, full.exec, 1e-4);
  check_rel(nu.energy, full.energy, 1e-4);

  /* lumped limbs */
  q = p;
  q.scene.limb_inertia = POM_INERTIA_LUMPED;
  outcome lu = simulate_shipped(&mech, &q);
  check_true(lu.st == POM_OK);
  if (links) {
    /* 3PSS: the three links become rods (12 states each fewer). Their
     * transverse inertia changes from 1.09e-6 to m l^2 / 4 = 1.58e-6 kg m^2
     * and their spin disappears: measured settling +0.1 %, energy +0.7 % */
    check_true(lu.n_states == full.n_states - 36);
    check_rel(lu.exec, full.exec, 5e-3);
    check_rel(lu.energy, full.energy, 2e-2);
  } else {
    /* 3SPS: cylinders pinned at A (same state count, 6 of them frozen).
     * Exact for a rigid pivot: at k_p = 1e8 full and lumped agree (measured
     * energy 0.5 %, settling 0.1 %); at the paper's 1e6 the full model's
     * 448 g cylinders bounce on the pivot springs and its energy is 23 % off
     * its own k_p -> inf limit (docs/dynamics.md section 13). */
    check_true(lu.n_states == full.n_states);
    pom_dyn_params s = p, t = q;
    s.joints.stiffness = s.joints.angular_stiffness = 1e8;
    t.joints.stiffness = t.joints.angular_stiffness = 1e8;
    outcome fs = simulate_shipped(&mech, &s), ls = simulate_shipped(&mech, &t);
    check_rel(ls.exec, fs.exec, 5e-3);
    check_rel(ls.energy, fs.energy, 1.5e-2);
  }
}

/* ---- 3. config and model errors ------------------------------------------- */
static void test_errors(void) {
  static const char *const bad[] = {
      "scene = { limb_inertia = \"point\"; };",
      "scene = { universal_joint = 2; };",
      "scene = { limb_inertia = 1; };",
  };
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
    pom_cfg *cfg = NULL;
    pom_error err;
    pom_error_clear(&err);
    pom_dyn_params p;
    pom_dyn_params_defaults(&p);
    check_true(pom_cfg_load_string(&cfg, bad[k], "<scene>", &err) == POM_OK);
    check_true(pom_dyn_params_load(&p, cfg, &err) == POM_ERR_CONFIG);
    check_true(strstr(err.message, "scene.") != NULL);
    pom_cfg_destroy(cfg);
  }
  /* a link whose CM lies outside the segment of its two joints cannot be lumped */
  double I[9], c1[3] = {0, 0, -0.05}, c2[3] = {0, 0, -0.11}, p2[3] = {0, 0, -0.1};
  diag_inertia(I, 1e-6, 1e-6, 2e-7);
  pom_mechanism mech;
  mech_init(&mech);
  mech_body(&mech, 0.01, I, c1);
  mech_body(&mech, 0.02, I, c2);
  mech_joint(&mech, POM_JOINT_SPHERICAL, 0, 1, zero3, NULL, NULL);
  mech_joint(&mech, POM_JOINT_SPHERICAL, 1, 2, p2, NULL, NULL);
  mech.platform = 2;
  mech.body[1].cm[2] = -0.12; /* beyond the lower joint */
  pom_dyn_params p;
  pom_dyn_params_defaults(&p);
  p.scene.limb_inertia = POM_INERTIA_LUMPED;
  pom_dyn_model *m = NULL;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "outside the segment") != NULL);
  check_true(m == NULL);
  mech.body[1].cm[2] = -0.05; /* on the segment: a rod from the ground to body 2 */
  check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_OK);
  if (m) check_true(pom_dyn_model_n_states(m) < 2 * 12 + 1); /* one body left */
  pom_dyn_model_destroy(m);
}

int main(void) {
  test_pinned_pendulum();
  test_shipped_options("3pss.cfg", 1);
  test_shipped_options("3sps.cfg", 0);
  test_errors();
  return check_summary("test_scene");
}
