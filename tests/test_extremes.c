/* test_extremes.c - the dynamics engine at the extremes (docs/dynamics.md
 * section 14): parasitic stiffness 1e3..1e10 with and without damping, rtol
 * 1e-2..1e-12, gains from tiny to huge, targets at and beyond the stroke
 * ends, near the Euler singularity, a zero and a sub-micron step, a long
 * horizon, masses scaled by 1e-3 and 1e3. Every case must give a correct
 * answer (checked against a tight reference or an analysis) or stop with a
 * specific diagnostic - never hang (solver.max_steps and solver.max_wall_s
 * bound each run), never crash, never a silent NaN. */
#include "check.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Every run of this file is bounded: at most this many steps and seconds. */
#define EXT_MAX_STEPS 60000
#define EXT_MAX_WALL  20.0

typedef struct {
  pom_mechanism mech;
  pom_kin_arch arch;
  pom_dyn_params p;
} shipped;

static int load(const char *file, shipped *s) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, file);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_kin_arch_load(&s->arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_build(&s->mech, &s->arch, cfg, &err) == POM_OK;
  pom_dyn_params_defaults(&s->p);
  ok = ok && pom_dyn_params_load(&s->p, cfg, &err) == POM_OK;
  if (!ok) printf("  loading %s: %s\n", file, err.message);
  pom_cfg_destroy(cfg);
  s->p.solver.max_steps = EXT_MAX_STEPS;
  s->p.solver.max_wall = EXT_MAX_WALL;
  return ok;
}

typedef struct {
  pom_dyn_metrics mt;
  pom_status st;
  char message[1024];
  int n;       /* trace samples */
  double *q;   /* [n][3] actuator trace (m), owned */
  double *eul; /* [n][3] platform Euler angles, owned */
} result;

static void result_free(result *r) {
  free(r->q);
  free(r->eul);
  memset(r, 0, sizeof *r);
}

/* Runs one maneuver and checks the contract common to every case: a failed
 * run carries a status, a reason and NaN times; a finished run has finite
 * energies, positions and counters, and settled[i] <=> finite settling time. */
static result simulate_ex(const pom_mechanism *mech, const pom_kin_arch *arch,
                          const pom_dyn_params *p, const double target[3],
                          const pom_dyn_initial *init) {
  result r;
  memset(&r, 0, sizeof r);
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_dyn_trace *tr = NULL;
  pom_error err;
  pom_error_clear(&err);
  r.st = pom_dyn_model_create(&m, mech, arch, p, &err);
  if (r.st == POM_OK) r.st = pom_dyn_data_create(&d, m, &err);
  if (r.st == POM_OK) r.st = pom_dyn_trace_create(&tr, m, &err);
  if (r.st == POM_OK) {
    r.st = pom_dyn_simulate_ex(m, d, target, init, &r.mt, tr, &err);
    check_true(r.mt.status == r.st);
    check_true(r.mt.wall_time < EXT_MAX_WALL + 5.0); /* bounded */
    check_true(r.mt.steps <= EXT_MAX_STEPS + 1);
    if (r.st == POM_OK) {
      check_true(r.mt.reason[0] == '\0');
      check_true(isfinite(r.mt.energy_total) && isfinite(r.mt.energy_balance_error));
      for (int a = 0; a < 3; ++a) {
        check_true(isfinite(r.mt.final_q[a]) && isfinite(r.mt.energy[a]));
        check_true(isfinite(r.mt.peak_voltage[a]) && isfinite(r.mt.saturation_time[a]));
        check_true(r.mt.settled[a] == (isfinite(r.mt.settling_time[a]) ? 1 : 0));
      }
      check_true(isnan(r.mt.execution_time) ==
                 !(r.mt.settled[0] && r.mt.settled[1] && r.mt.settled[2]));
      r.n = tr->n;
      r.q = malloc((size_t)tr->n * 3 * sizeof(double));
      r.eul = malloc((size_t)tr->n * 3 * sizeof(double));
      if (r.q && r.eul) {
        memcpy(r.q, tr->q, (size_t)tr->n * 3 * sizeof(double));
        memcpy(r.eul, tr->euler_zyx, (size_t)tr->n * 3 * sizeof(double));
        for (int i = 0; i < 3 * tr->n; ++i)
          if (!isfinite(r.q[i])) {
            check_true(isfinite(r.q[i]));
            break;
          }
      }
    } else {
      check_true(r.mt.reason[0] != '\0');
      check_true(isnan(r.mt.execution_time));
    }
  }
  snprintf(r.message, sizeof r.message, "%s", err.message);
  pom_dyn_trace_destroy(tr);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return r;
}

static result simulate(const pom_mechanism *mech, const pom_dyn_params *p, const double target[3],
                       const pom_dyn_initial *init) {
  return simulate_ex(mech, NULL, p, target, init);
}

/* max_t max_i |q_a - q_b| over the common samples (m). */
static double traj_diff(const result *a, const result *b) {
  if (!a->q || !b->q || a->n != b->n) return INFINITY;
  double w = 0.0;
  for (int i = 0; i < 3 * a->n; ++i)
    w = fmax(w, fabs(a->q[i] - b->q[i]));
  return w;
}

static const double target_mid[3] = {1.2e-3, -0.85e-3, 0.6e-3};

/* ---- 1. parasitic stiffness 1e3..1e10, with and without damping --------- */
static void test_stiffness(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 0.03;
  s.p.solver.rtol = 1e-7;
  s.p.solver.atol_scale = 1e-4;
  const double ks[] = {1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10};
  const int nk = (int)(sizeof ks / sizeof ks[0]);
  result r[8];
  for (int k = 0; k < nk; ++k) {
    pom_dyn_params p = s.p;
    p.joints.stiffness = p.joints.angular_stiffness = ks[k];
    r[k] = simulate(&s.mech, &p, target_mid, NULL);
    /* the whole range must run: soft joints are slow, stiff ones are stiff */
    if (r[k].st != POM_OK) printf("  k_p %g: %s\n", ks[k], r[k].message);
    check_true(r[k].st == POM_OK);
  }
  /* Against the stiffest: the trajectory error is the parasitic deflection
   * itself (measured within 0.5-40 % of max_deflection for every k_p): demand
   * <= 1.5 max_deflection. From 1e6 up it is first order in 1/k_p (measured
   * 6.6x, 6.7x, 12x per decade; docs 11.6: 7.7-9.6x): demand 4x. Below 1e5
   * the damper R_p = 200 N s/m dominates (c/k_p = 0.2 s >> the 30 ms run)
   * and the deflection stays ~20-50 um instead of growing like 1/k_p. */
  for (int k = 0; k + 1 < nk; ++k) {
    double e = traj_diff(&r[k], &r[nk - 1]);
    if (!check_true(e <= 1.5 * r[k].mt.max_deflection + 1e-9))
      printf("  k_p %g: traj diff %g m, deflection %g m\n", ks[k], e, r[k].mt.max_deflection);
  }
  for (int k = 3; k + 1 < nk - 1; ++k) {
    double e0 = traj_diff(&r[k], &r[nk - 1]), e1 = traj_diff(&r[k + 1], &r[nk - 1]);
    if (!check_true(e1 < e0 / 4.0)) printf("  k_p %g: %g, %g: %g\n", ks[k], e0, ks[k + 1], e1);
  }
  check_true(traj_diff(&r[3], &r[nk - 1]) < 1e-5);
  /* soft joints: large but finite deflections, reported */
  check_true(r[0].mt.max_deflection > 1e-5 && r[0].mt.max_deflection < 1e-3);
  for (int k = 0; k < nk; ++k)
    result_free(&r[k]);

  /* no parasitic damping: the joint modes ring undamped; the run must still
   * end with the same answer as the damped one within the deflection level
   * (k_p 1e6: 7 um) or a diagnostic */
  const double kz[] = {1e3, 1e6, 1e10};
  for (int k = 0; k < 3; ++k) {
    pom_dyn_params p = s.p;
    p.joints.stiffness = p.joints.angular_stiffness = kz[k];
    result damped = simulate(&s.mech, &p, target_mid, NULL);
    p.joints.damping = p.joints.angular_damping = 0.0;
    result und = simulate(&s.mech, &p, target_mid, NULL);
    if (und.st == POM_OK && damped.st == POM_OK) {
      for (int a = 0; a < 3; ++a)
        check_abs(und.mt.final_q[a], damped.mt.final_q[a],
                  fmax(2e-7, 3.0 * damped.mt.max_deflection));
      check_abs(und.mt.energy_parasitic, 0.0, 0.0);
    } else {
      printf("  undamped k_p %g: %s\n", kz[k], und.message);
      check_true(und.st == POM_ERR_SOLVER || und.st == POM_ERR_UNSTABLE);
    }
    result_free(&damped);
    result_free(&und);
  }
}

/* ---- 2. rtol 1e-2 .. 1e-12 ------------------------------------------------ */
static void test_rtol(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 0.02;
  const double rt[] = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
  result r[6];
  for (int k = 0; k < 6; ++k) {
    pom_dyn_params p = s.p;
    p.solver.rtol = rt[k];
    p.solver.atol_scale = fmin(1e-3, 1e3 * rt[k]);
    r[k] = simulate(&s.mech, &p, target_mid, NULL);
    if (r[k].st != POM_OK) printf("  rtol %g: %s\n", rt[k], r[k].message);
  }
  /* the tight end must run (the reference) */
  check_true(r[4].st == POM_OK && r[5].st == POM_OK);
  /* the loose end either runs with a closed audit (<= max_balance_error) or
   * is refused by the audit guard: never a plausible-looking wrong answer */
  for (int k = 0; k < 6; ++k)
    if (r[k].st == POM_OK)
      check_true(r[k].mt.energy_balance_error <= s.p.solver.max_balance_error);
    else
      check_true(r[k].st == POM_ERR_UNSTABLE || r[k].st == POM_ERR_SOLVER);
  /* convergence: 1e-6 -> 1e-8 -> 1e-10 against 1e-12: at least 100x over
   * the four decades and 5x over each two (docs 11.7 measured ~60x per two
   * decades with the finite-difference Jacobian; with the analytic one
   * 2.7e-10 / 3.7e-11 / 3.7e-13 m, 7.5x then 99x: the step sequence, not
   * the order, sets the ratio of one maneuver) */
  double e6 = traj_diff(&r[2], &r[5]), e8 = traj_diff(&r[3], &r[5]), e10 = traj_diff(&r[4], &r[5]);
  check_true(e8 < e6 / 5.0);
  check_true(e10 < e8 / 5.0 || e10 < 1e-12);
  check_true(e10 < e6 / 100.0 || e10 < 1e-12);
  check_true(e6 < 1e-6); /* 0.1 % of the step at the shipped rtol */
  for (int k = 0; k < 6; ++k)
    result_free(&r[k]);
}

/* ---- 3. gains: tiny, huge (bang-bang), windup (permanent saturation) ----- */
static void test_gains(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 0.03;
  /* tiny: K_P = 1e-9: the drive is ~1e-8 V, nothing moves beyond the gravity
   * sag of the pistons (m g / k: the loop does not hold them): q stays within
   * 1e-4 of home, no actuator settles, no saturation */
  pom_dyn_params p = s.p;
  p.controller.kp = 1e-9;
  result r = simulate(&s.mech, &p, target_mid, NULL);
  check_true(r.st == POM_OK);
  if (r.st == POM_OK) {
    for (int a = 0; a < 3; ++a) {
      check_true(r.mt.settled[a] == 0);
      check_abs(r.mt.saturation_time[a], 0.0, 0.0);
      check_true(r.mt.peak_voltage[a] < 1e-6);
    }
  }
  result_free(&r);

  /* huge: K_P = 1e9 (K_S K_P = 8e11 V/m): a 30 pm linear band, the drive
   * switches between +-24 V (bang-bang); it must settle like the paper's
   * nearly bang-bang loop or stop at the step budget with that diagnostic */
  p = s.p;
  p.controller.kp = 1e9;
  r = simulate(&s.mech, &p, target_mid, NULL);
  if (r.st == POM_OK) {
    for (int a = 0; a < 3; ++a) {
      check_abs(r.mt.peak_voltage[a], p.actuator.voltage_limit, 1e-9);
      check_true(r.mt.saturation_time[a] > 0);
    }
  } else {
    printf("  K_P 1e9: %s\n", r.message);
    check_true(r.st == POM_ERR_SOLVER &&
               (strstr(r.message, "max_steps") != NULL || strstr(r.message, "max_wall") != NULL));
  }
  result_free(&r);

  /* permanent saturation: integral gain 1e6 1/s winds up (no anti-windup):
   * the drive sits at the limit most of the time and the loop limit-cycles;
   * the run reports it (long saturation time, unsettled) or a diagnostic */
  p = s.p;
  p.controller.ki = 1e6;
  r = simulate(&s.mech, &p, target_mid, NULL);
  if (r.st == POM_OK) {
    double sat =
        fmax(r.mt.saturation_time[0], fmax(r.mt.saturation_time[1], r.mt.saturation_time[2]));
    check_true(sat > 0.3 * p.maneuver.horizon);
  } else {
    printf("  K_I 1e6: %s\n", r.message);
    check_true(r.st == POM_ERR_SOLVER || r.st == POM_ERR_UNSTABLE || r.st == POM_ERR_LIMIT);
  }
  result_free(&r);
}

/* ---- 4. stroke ends and beyond -------------------------------------------- */
static void test_stroke(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 0.04;
  double half = 0.5 * s.arch.stroke;
  /* beyond: refused before any work, naming the actuator and the stroke */
  const double beyond[3] = {0.0, half * 1.0001, 0.0};
  result r = simulate(&s.mech, &s.p, beyond, NULL);
  check_true(r.st == POM_ERR_LIMIT);
  check_true(strstr(r.message, "actuator 2") != NULL && strstr(r.message, "stroke") != NULL);
  check_true(r.mt.steps == 0);
  result_free(&r);
  /* at the stroke ends: the corner with the worst dexterity of the joint
   * cube; the answer is checked against kinematics: the settled platform
   * orientation maps back to the targets by IK within the deflections */
  double worst_dex = 2.0, worst[3] = {0, 0, 0};
  for (int c = 0; c < 8; ++c) {
    double q[3] = {(c & 1) ? half : -half, (c & 2) ? half : -half, (c & 4) ? half : -half};
    double R[9], J[9], qq[3], sv[3], kap, dex;
    pom_kin_fk_opts fo;
    pom_kin_fk_defaults(&fo);
    double I[9];
    pom_m3_identity(I);
    if (pom_kin_forward(&s.arch, q, I, &fo, R, NULL, NULL) != POM_OK) continue;
    if (pom_kin_inverse_jacobian(&s.arch, R, qq, J, NULL) != POM_OK) continue;
    pom_kin_dexterity(J, sv, &kap, &dex);
    if (dex < worst_dex) {
      worst_dex = dex;
      memcpy(worst, q, sizeof worst);
    }
  }
  check_true(worst_dex < 0.6); /* a corner close to the edge of good dexterity */
  r = simulate(&s.mech, &s.p, worst, NULL);
  if (r.st == POM_OK) {
    for (int a = 0; a < 3; ++a)
      check_abs(r.mt.final_q[a], worst[a], 0.02 * half); /* inside the 2 % band */
  } else {
    printf("  stroke corner (%g, %g, %g) mm: %s\n", worst[0] * 1e3, worst[1] * 1e3, worst[2] * 1e3,
           r.message);
    check_true(r.st == POM_ERR_SOLVER || r.st == POM_ERR_UNSTABLE);
  }
  result_free(&r);
}

/* ---- 5. near the Euler singularity ---------------------------------------- */
/* A free platform on its spherical joint spun about y so that pitch reaches
 * 84 deg: the Euler path (cos pitch 0.1 > euler_cos_min) must follow the
 * quaternion path; pushed beyond 89.4 deg it must stop with
 * POM_ERR_EULER_SINGULAR (docs/dynamics.md section 7). */
static void test_euler_near(void) {
  pom_mechanism mech;
  memset(&mech, 0, sizeof mech);
  mech.n_bodies = 2;
  mech.platform = 1;
  snprintf(mech.body[1].name, sizeof mech.body[1].name, "platform");
  mech.body[1].mass = 0.03;
  mech.body[1].inertia[0] = mech.body[1].inertia[4] = 1.1e-6;
  mech.body[1].inertia[8] = 2.0e-6;
  mech.n_joints = 1;
  mech.joint[0].type = POM_JOINT_SPHERICAL;
  mech.joint[0].body[0] = 0;
  mech.joint[0].body[1] = 1;
  mech.joint[0].actuator = -1;
  pom_dyn_params p;
  pom_dyn_params_defaults(&p);
  p.scene.gravity = 0;
  p.solver.rtol = 1e-9;
  p.solver.atol_scale = 1e-6;
  p.solver.max_steps = EXT_MAX_STEPS;
  p.maneuver.horizon = 0.1;
  p.maneuver.output_dt = 1e-3;
  pom_dyn_initial init;
  memset(&init, 0, sizeof init);
  const double zero[3] = {0, 0, 0};
  /* about y at 84 deg / 0.1 s, plus a small roll rate so it is not planar */
  init.omega[1][1] = 84.0 * POM_DEG / 0.1;
  init.omega[1][0] = 0.05;
  result e = simulate(&mech, &p, zero, &init);
  p.scene.orientation = POM_ORIENT_QUATERNION;
  result q = simulate(&mech, &p, zero, &init);
  check_true(e.st == POM_OK && q.st == POM_OK);
  if (e.eul && q.eul && e.n == q.n) {
    double w = 0.0;
    for (int i = 0; i < 3 * e.n; ++i)
      w = fmax(w, fabs(e.eul[i] - q.eul[i]));
    /* psi and phi are ill-conditioned like 1/cos(pitch) = 10 here: 1e-9 x 10 x steps */
    check_abs(w, 0.0, 1e-5);
    check_abs(e.eul[3 * (e.n - 1) + 1], 84.0 * POM_DEG, 2e-3);
  }
  result_free(&e);
  result_free(&q);
  p.scene.orientation = POM_ORIENT_EULER_ZYX;
  init.omega[1][1] = 95.0 * POM_DEG / 0.1;
  e = simulate(&mech, &p, zero, &init);
  check_true(e.st == POM_ERR_EULER_SINGULAR);
  check_true(strstr(e.message, "quaternion") != NULL);
  result_free(&e);
}

/* ---- 6. zero step, sub-micron step ----------------------------------------- */
static void test_tiny_steps(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 0.03;
  const double zero[3] = {0, 0, 0};
  result r = simulate(&s.mech, &s.p, zero, NULL);
  check_true(r.st == POM_OK);
  if (r.st == POM_OK) {
    /* no band: settled at t = 0 by definition (docs 8); the loop still holds
     * the gravity load: the pistons stay within the static error (~34 nm) */
    check_abs(r.mt.execution_time, 0.0, 0.0);
    for (int a = 0; a < 3; ++a)
      check_abs(r.mt.final_q[a], 0.0, 1e-7);
  }
  result_free(&r);
  /* 0.3 um steps: the 2 % band is 6 nm, below the ~34 nm static error under
   * gravity, so the actuators are reported unsettled (flag + NaN), with the
   * stepinfo variant (band about the final value) still finite */
  const double sub[3] = {0.3e-6, -0.3e-6, 0.3e-6};
  r = simulate(&s.mech, &s.p, sub, NULL);
  check_true(r.st == POM_OK);
  if (r.st == POM_OK) {
    int unsettled = 0;
    for (int a = 0; a < 3; ++a) {
      unsettled += !r.mt.settled[a];
      check_true(isfinite(r.mt.settling_time_final[a]));
      check_abs(r.mt.final_q[a], sub[a], 1e-7); /* within the static error */
    }
    check_true(unsettled > 0);
    check_true(isnan(r.mt.execution_time));
  }
  result_free(&r);
  /* without gravity there is no static load: the same step settles */
  s.p.scene.gravity = 0;
  r = simulate(&s.mech, &s.p, sub, NULL);
  check_true(r.st == POM_OK && isfinite(r.mt.execution_time));
  result_free(&r);
}

/* ---- 7. long horizon ------------------------------------------------------- */
static void test_long_horizon(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 5.0;
  s.p.maneuver.output_dt = 1e-3;
  result r = simulate(&s.mech, &s.p, target_mid, NULL);
  check_true(r.st == POM_OK);
  if (r.st == POM_OK) {
    /* settled as in the 100 ms maneuver (the integral term is ~1e-3 1/s and
     * does not change the first 15 ms); audit closed over 5 s; the final
     * error is the static error of the proportional loop under gravity and
     * the other limbs' reactions (docs 8: ~34 nm from the holding force
     * alone, measured 41 nm): the 1e-3 1/s integral removes 0.5 % of it in
     * 5 s, so the bound is 60 nm */
    check_true(r.mt.execution_time < 0.02);
    check_true(r.mt.energy_balance_error < 1e-4);
    for (int a = 0; a < 3; ++a)
      check_abs(r.mt.final_q[a], target_mid[a], 6e-8);
    printf("  5 s horizon: %ld steps, %.3f s wall\n", r.mt.steps, r.mt.wall_time);
  }
  result_free(&r);
}

/* ---- 8. masses and inertias scaled ------------------------------------------ */
static void test_mass_scaling(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 0.1;
  result nominal = simulate(&s.mech, &s.p, target_mid, NULL);
  check_true(nominal.st == POM_OK);
  const double scale[2] = {1e-3, 1e3};
  for (int c = 0; c < 2; ++c) {
    pom_mechanism mech = s.mech;
    for (int b = 1; b < mech.n_bodies; ++b) {
      mech.body[b].mass *= scale[c];
      for (int k = 0; k < 9; ++k)
        mech.body[b].inertia[k] *= scale[c];
    }
    result r = simulate(&mech, &s.p, target_mid, NULL);
    if (c == 0) {
      /* 1000x lighter: the loop is limited by the coil and the bearing; it
       * must settle, and faster than the nominal mechanism */
      check_true(r.st == POM_OK);
      if (r.st == POM_OK && nominal.st == POM_OK)
        check_true(r.mt.execution_time < nominal.mt.execution_time);
    } else {
      /* 1000x heavier (23 kg per axis): a bang-bang move of 1.2 mm with
       * 9.1 N takes at least 2 sqrt(d M / F) = 2 sqrt(1.2e-3 23 / 9.1) =
       * 0.11 s > the 0.1 s horizon: the analysis says it cannot settle */
      if (r.st == POM_OK) {
        check_true(r.mt.settled[0] == 0);
        check_true(isnan(r.mt.execution_time));
      } else {
        printf("  mass x1e3: %s\n", r.message);
        check_true(r.st == POM_ERR_SOLVER || r.st == POM_ERR_UNSTABLE);
      }
    }
    result_free(&r);
  }
  result_free(&nominal);
}

/* ---- 9. the rigid (exact-constraint) path at the extremes ------------------ */
/* The same contract on the rigid path (joints.model = rigid), and the
 * parasitic path's k_p -> infinity limit against it. */
static void test_rigid(void) {
  shipped s;
  if (!check_true(load("3pss.cfg", &s))) return;
  s.p.maneuver.horizon = 0.03;
  s.p.solver.rtol = 1e-8;
  s.p.solver.atol_scale = 1e-5;
  pom_dyn_params rp = s.p;
  rp.joints.model = POM_JOINTS_RIGID;
  result rig = simulate_ex(&s.mech, &s.arch, &rp, target_mid, NULL);
  check_true(rig.st == POM_OK);
  /* parasitic at k_p 1e9 against the exact path: the deflection is 13 nm
   * (test_stiffness) but the two models differ by ~0.3 um (measured 2.6e-4
   * of the step in pomlab tradeoff; the rigid path's link-spin treatment,
   * docs/tradeoff.md): bound 1e-6 m, against 7 um at the shipped 1e6 */
  pom_dyn_params pp = s.p;
  pp.joints.stiffness = pp.joints.angular_stiffness = 1e9;
  result par = simulate(&s.mech, &pp, target_mid, NULL);
  check_true(par.st == POM_OK);
  double d9 = traj_diff(&par, &rig);
  if (!check_true(d9 < 1e-6)) printf("  parasitic 1e9 vs rigid: %g m\n", d9);
  result_free(&par);
  pp.joints.stiffness = pp.joints.angular_stiffness = 1e6;
  par = simulate(&s.mech, &pp, target_mid, NULL);
  double d6 = traj_diff(&par, &rig);
  check_true(d6 > d9 && d6 < 2e-5); /* the shipped k_p: the deflection level */
  result_free(&par);

  /* rtol extremes, stroke corner, beyond the stroke, huge gains, tiny step */
  const double rt[] = {1e-2, 1e-12};
  for (int k = 0; k < 2; ++k) {
    pom_dyn_params p = rp;
    p.solver.rtol = rt[k];
    p.solver.atol_scale = fmin(1e-3, 1e3 * rt[k]);
    result r = simulate_ex(&s.mech, &s.arch, &p, target_mid, NULL);
    if (r.st == POM_OK) {
      check_true(traj_diff(&r, &rig) < (k == 0 ? 3e-5 : 1e-9));
    } else {
      printf("  rigid rtol %g: %s\n", rt[k], r.message);
      check_true(r.st == POM_ERR_UNSTABLE || r.st == POM_ERR_SOLVER);
    }
    result_free(&r);
  }
  double half = 0.5 * s.arch.stroke;
  const double beyond[3] = {-half * 1.01, 0.0, 0.0};
  result r = simulate_ex(&s.mech, &s.arch, &rp, beyond, NULL);
  check_true(r.st == POM_ERR_LIMIT && r.mt.steps == 0);
  result_free(&r);
  const double corner[3] = {half, -half, half};
  r = simulate_ex(&s.mech, &s.arch, &rp, corner, NULL);
  if (r.st == POM_OK) {
    for (int a = 0; a < 3; ++a)
      check_abs(r.mt.final_q[a], corner[a], 0.02 * half);
  } else {
    printf("  rigid corner: %s\n", r.message);
    check_true(r.st == POM_ERR_UNREACHABLE || r.st == POM_ERR_SINGULAR || r.st == POM_ERR_SOLVER ||
               r.st == POM_ERR_LIMIT);
  }
  result_free(&r);
  pom_dyn_params p = rp;
  p.controller.kp = 1e9;
  r = simulate_ex(&s.mech, &s.arch, &p, target_mid, NULL);
  if (r.st == POM_OK)
    check_abs(r.mt.peak_voltage[0], p.actuator.voltage_limit, 1e-9);
  else
    check_true(r.st == POM_ERR_SOLVER);
  result_free(&r);
  const double sub[3] = {0.3e-6, -0.3e-6, 0.3e-6};
  r = simulate_ex(&s.mech, &s.arch, &rp, sub, NULL);
  check_true(r.st == POM_OK);
  result_free(&r);
  result_free(&rig);
}

int main(int argc, char **argv) {
  /* optional: run one case by name */
  const char *only = argc > 1 ? argv[1] : NULL;
#define CASE(name)                                                                                 \
  if (!only || strcmp(only, #name) == 0) test_##name()
  CASE(stiffness);
  CASE(rtol);
  CASE(gains);
  CASE(stroke);
  CASE(euler_near);
  CASE(tiny_steps);
  CASE(long_horizon);
  CASE(mass_scaling);
  CASE(rigid);
#undef CASE
  return check_summary("test_extremes");
}
