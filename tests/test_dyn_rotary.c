/* test_dyn_rotary.c - rotary voice-coil actuators on revolute joints
 * (docs/dynamics.md section 4) against an independent integration, the
 * energy audit of a rotary scene, the Jacobian pattern of the torque
 * couplings, the rotary configuration keys and a refused target's unit.
 *
 * Three rotors, each a rigid body on its own actuated revolute joint to the
 * ground, the joint axis through the CM along a principal axis (x, y and z
 * for the three rotors, different moments), no gravity. No load crosses the
 * joints (the CM does not move, the spin axis is principal), so the parasitic
 * pseudo-constraints carry nothing and the engine reduces exactly to three
 * copies of the 1-DOF model
 *
 *   J th'' = K_t i - b th',  L i' = u - R_c i - K_t th',  z' = th_set - th,
 *   u = clamp(K_S K_P (th_set - th + K_I z - tau_D th'), +-24 V),
 *
 * integrated here by classical RK4 with a fixed step of 0.1 us (the fastest
 * pole, the coil's R_c / L ~ 1.6e4 1/s with the loop, gives |lambda dt| ~ 2e-3).
 * The loop saturates at both limits (the integral winds up), as in
 * test_dyn_saturated.c for linear actuators, whose reference this mirrors. */
#include "check.h"
#include "dyn_internal.h"
#include "pom_config.h"
#include "pom_dynamics.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the reference: one rotor, RK4 ------------------------------------------ */
typedef struct {
  double J, K, R, L, b, G, kd, ki, lim, r; /* SI: kg m^2, N m/A, ohm, H, N m s/rad, V/rad, ... */
} rotor_model;

static double rotor_u_raw(const rotor_model *a, const double x[4]) {
  return a->G * (a->r - x[0] + a->ki * x[3] - a->kd * x[1]);
}

static void rotor_rhs(const rotor_model *a, const double x[4], double f[4]) {
  double u = fmax(-a->lim, fmin(a->lim, rotor_u_raw(a, x)));
  f[0] = x[1];
  f[1] = (a->K * x[2] - a->b * x[1]) / a->J;
  f[2] = (u - a->R * x[2] - a->K * x[1]) / a->L;
  f[3] = a->r - x[0];
}

typedef struct {
  double energy, energy_pos, sat, settle, final_angle, coil, bearing;
} rotor_result;

static void rotor_reference(rotor_result *res, const rotor_model *a, double T, double dt) {
  double x[4] = {0, 0, 0, 0};
  memset(res, 0, sizeof *res);
  long n = (long)llround(T / dt);
  double band = 0.02 * fabs(a->r), t_exit = 0.0;
  for (long k = 0; k < n; ++k) {
    double k1[4], k2[4], k3[4], k4[4], xt[4];
    /* powers by the trapezoid, the saturation indicator at the midpoint */
    double u0 = fmax(-a->lim, fmin(a->lim, rotor_u_raw(a, x)));
    double p0 = u0 * x[2], e0 = x[0] - a->r;
    double c0 = a->R * x[2] * x[2], b0 = a->b * x[1] * x[1];
    rotor_rhs(a, x, k1);
    for (int c = 0; c < 4; ++c)
      xt[c] = x[c] + 0.5 * dt * k1[c];
    rotor_rhs(a, xt, k2);
    for (int c = 0; c < 4; ++c)
      xt[c] = x[c] + 0.5 * dt * k2[c];
    rotor_rhs(a, xt, k3);
    double urm = rotor_u_raw(a, xt);
    for (int c = 0; c < 4; ++c)
      xt[c] = x[c] + dt * k3[c];
    rotor_rhs(a, xt, k4);
    for (int c = 0; c < 4; ++c)
      x[c] += dt / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
    double u1 = fmax(-a->lim, fmin(a->lim, rotor_u_raw(a, x)));
    double p1 = u1 * x[2], e1 = x[0] - a->r;
    res->energy += 0.5 * dt * (p0 + p1);
    res->energy_pos += 0.5 * dt * (fmax(p0, 0.0) + fmax(p1, 0.0));
    res->coil += 0.5 * dt * (c0 + a->R * x[2] * x[2]);
    res->bearing += 0.5 * dt * (b0 + a->b * x[1] * x[1]);
    if (fabs(urm) >= a->lim) res->sat += dt;
    /* last exit from the band, located linearly inside the step */
    if (fabs(e0) > band && fabs(e1) <= band) {
      double edge = e0 > 0 ? band : -band;
      t_exit = (double)k * dt + dt * (e0 - edge) / (e0 - e1);
    } else if (fabs(e1) > band) {
      t_exit = -1.0;
    }
  }
  res->settle = t_exit;
  res->final_angle = x[0];
}

/* ---- the scene ---------------------------------------------------------- */
/* principal moments of the three rotors (kg m^2); rotor k turns about axis k */
static const double rotor_inertia[3][3] = {
    {2.385e-5, 3.17e-5, 2.91e-5}, {1.83e-5, 4.126e-5, 2.27e-5}, {2.05e-5, 1.64e-5, 1.371e-5}};
static const double rotor_mass[3] = {0.0837, 0.1193, 0.0642};

static void rotors3(pom_mechanism *mech) {
  memset(mech, 0, sizeof *mech);
  mech->n_bodies = 4;
  mech->platform = 1;
  snprintf(mech->body[0].name, sizeof mech->body[0].name, "ground");
  for (int a = 0; a < 3; ++a) {
    pom_mech_body *b = &mech->body[a + 1];
    snprintf(b->name, sizeof b->name, "rotor%d", a + 1);
    b->mass = rotor_mass[a];
    for (int k = 0; k < 3; ++k)
      b->inertia[4 * k] = rotor_inertia[a][k];
    pom_v3_set(b->cm, 0.047 * a, 0.013 * a, -0.021 * a);
    pom_mech_joint *j = &mech->joint[a];
    snprintf(j->name, sizeof j->name, "R%d", a + 1);
    j->type = POM_JOINT_REVOLUTE;
    j->body[0] = 0;
    j->body[1] = a + 1;
    pom_v3_copy(j->point, b->cm);
    j->axis[a] = 1.0;
    j->actuator = a;
    mech->actuator[a].joint = a;
    mech->actuator[a].kind = POM_ACT_REVOLUTE;
    mech->actuator[a].moving_body = a + 1;
    mech->actuator[a].stroke = 1.2; /* rad */
  }
  mech->n_joints = 3;
  mech->n_actuators = 3;
}

/* A rotary voice coil and its loop: K_S K_P = 2.4e3 V/rad (linear band
 * 0.01 rad), a large integral factor that winds up while saturated. */
static void rotary_params(pom_dyn_params *p) {
  pom_dyn_params_defaults(p);
  p->actuator.kind = POM_ACT_REVOLUTE;
  p->actuator.force_constant = 0.0412;    /* K_t (N m/A) */
  p->actuator.resistance = 3.7;           /* ohm */
  p->actuator.inductance = 2.3e-4;        /* H */
  p->actuator.bearing_friction = 1.37e-5; /* N m s/rad */
  p->actuator.voltage_limit = 24.0;
  p->actuator.sensor_gain = 9.55; /* V/rad */
  p->controller.form = POM_PID_IDEAL;
  p->controller.kp = 251.3;
  p->controller.ki = 15.0;   /* 1/s */
  p->controller.kd = 1.3e-3; /* s */
  p->scene.gravity = 0;
  p->solver.rtol = 1e-9;
  p->solver.atol_scale = 1e-6;
  p->maneuver.horizon = 0.1;
  p->maneuver.output_dt = 1e-5;
}

/* ---- (a) + (b): three rotors against the reference, energy audit --------- */
static void test_rotors(void) {
  const double target[3] = {0.31, -0.27, 0.22}; /* rad */
  pom_mechanism mech;
  rotors3(&mech);
  pom_dyn_params p;
  rotary_params(&p);
  rotor_result ref[3];
  double exec = 0.0;
  for (int k = 0; k < 3; ++k) {
    rotor_model a = {rotor_inertia[k][k],
                     p.actuator.force_constant,
                     p.actuator.resistance,
                     p.actuator.inductance,
                     p.actuator.bearing_friction,
                     p.actuator.sensor_gain * p.controller.kp,
                     p.controller.kd,
                     p.controller.ki,
                     p.actuator.voltage_limit,
                     target[k]};
    rotor_reference(&ref[k], &a, p.maneuver.horizon, 1e-7);
    exec = fmax(exec, ref[k].settle);
    printf("  rotor %d, step %+.2f rad: reference E %.6f J (E+ %.6f), saturated %.4f ms, settled "
           "%.4f ms, final %.9f rad\n",
           k + 1, target[k], ref[k].energy, ref[k].energy_pos, ref[k].sat * 1e3,
           ref[k].settle * 1e3, ref[k].final_angle);
    /* every rotor must saturate and settle, or the comparison tests little */
    check_true(ref[k].sat > 1e-4 && ref[k].settle > 0.0);
  }

  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_dyn_metrics mt;
  pom_error err;
  pom_error_clear(&err);
  if (check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_OK &&
                 pom_dyn_data_create(&d, m, &err) == POM_OK &&
                 pom_dyn_simulate(m, d, target, &mt, NULL, &err) == POM_OK)) {
    for (int k = 0; k < 3; ++k) {
      printf("  rotor %d, engine - reference: E %.2e (relative), saturated %.2e s, settled %.2e "
             "s, final %.2e rad, coil %.2e, bearing %.2e (relative)\n",
             k + 1, mt.energy[k] / ref[k].energy - 1.0, mt.saturation_time[k] - ref[k].sat,
             mt.settling_time[k] - ref[k].settle, mt.final_q[k] - ref[k].final_angle,
             mt.energy_coil[k] / ref[k].coil - 1.0, mt.energy_bearing[k] / ref[k].bearing - 1.0);
      /* energies: the BDF at rtol 1e-9 against RK4 at 0.1 us; measured
       * <= 3e-8 relative (bearing 2e-6: a small difference of a small
       * term); the linear case's budget (test_dyn_saturated.c), far below
       * what a wrong torque sign or back-EMF changes (> 1e-3) */
      check_rel(mt.energy[k], ref[k].energy, 1e-5);
      check_rel(mt.energy_positive[k], ref[k].energy_pos, 1e-5);
      check_rel(mt.energy_coil[k], ref[k].coil, 1e-5);
      /* time at the limit: a fraction of a step at each of the switches
       * (measured <= 3.5e-7 s) */
      check_abs(mt.saturation_time[k], ref[k].sat, 2e-6);
      /* settling: both interpolate the last band exit between samples
       * (10 us engine, 0.1 us reference), error ~ dt^2 q'' / (8 q');
       * measured <= 2e-8 s */
      check_true(mt.settled[k] == 1);
      check_abs(mt.settling_time[k], ref[k].settle, 2e-7);
      /* final angle (still creeping back after the integral's overshoot):
       * the integrators differ by their tolerance, rtol 1e-9 of 0.3 rad
       * plus the accumulated error; measured <= 7e-10 rad */
      check_abs(mt.final_q[k], ref[k].final_angle, 1e-8);
    }
    check_abs(mt.execution_time, exec, 2e-7);
    /* (b) the energy audit closes: supplied = dissipated + stored change, to
     * the integration tolerance (rtol 1e-9; measured 1e-9) */
    printf("  energy audit: supplied %.6f J, dissipated %.6f J, stored change %.3e J, balance "
           "error %.2e, parasitic %.2e J\n",
           mt.energy_supplied, mt.energy_dissipated, mt.energy_stored_change,
           mt.energy_balance_error, mt.energy_parasitic);
    check_true(mt.energy_balance_error < 1e-6);
    /* nothing loads the joints: no parasitic deflection to speak of */
    check_true(mt.max_deflection < 1e-12 && mt.max_angular_deflection < 1e-12);
  } else {
    printf("  %s\n", err.message);
  }
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* ---- the Jacobian pattern holds the torque couplings ----------------------- */
static void test_rotary_pattern(void) {
  pom_mechanism mech;
  rotors3(&mech);
  /* a generic axis for rotor 3 (the pattern must not rely on principal axes) */
  pom_v3_set(mech.joint[2].axis, 0.48, -0.6, 0.64);
  pom_dyn_params p;
  rotary_params(&p);
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  if (check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_OK &&
                 pom_dyn_data_create(&d, m, &err) == POM_OK)) {
    int n = m->n_states, wi = -1, wj = -1;
    double *y = calloc((size_t)n * 4, sizeof *y);
    if (check_true(y != NULL)) {
      double *f0 = y + n, *yp = y + 2 * n, *fp = y + 3 * n;
      for (int i = 0; i < n; ++i) /* a generic state near home */
        y[i] = m->scale[i] * (0.37 + 0.11 * (double)(i % 7));
      d->target[0] = 0.113, d->target[1] = -0.071, d->target[2] = 0.052;
      double worst = pom_dyn_structure_check(m, d, y, f0, yp, fp, &wi, &wj);
      printf("  rotary pattern: largest derivative outside it %.2e (%d, %d)\n", worst, wi, wj);
      check_abs(worst, 0.0, 0.0);
    }
    free(y);
  } else {
    printf("  %s\n", err.message);
  }
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* ---- (c) kinds and keys ---------------------------------------------------- */
static pom_status load_params(const char *text, pom_dyn_params *p, pom_error *err) {
  pom_cfg *cfg = NULL;
  pom_dyn_params_defaults(p);
  pom_status st = pom_cfg_load_string(&cfg, text, "test.cfg", err);
  if (st == POM_OK) st = pom_dyn_params_load(p, cfg, err);
  pom_cfg_destroy(cfg);
  return st;
}

static void test_rotary_config(void) {
  pom_dyn_params p;
  pom_error err;
  pom_error_clear(&err);
  check_true(load_params("actuator = { kind = \"rotary\"; torque_constant_Nm_per_A = 0.0412; "
                         "bearing_friction_Nms_per_rad = 1.37e-5; sensor_gain_V_per_rad = 9.55; "
                         "resistance_ohm = 3.7; };",
                         &p, &err) == POM_OK);
  check_true(p.actuator.kind == POM_ACT_REVOLUTE);
  check_rel(p.actuator.force_constant, 0.0412, 1e-15);
  check_rel(p.actuator.bearing_friction, 1.37e-5, 1e-15);
  check_rel(p.actuator.sensor_gain, 9.55, 1e-15);
  check_rel(p.actuator.resistance, 3.7, 1e-15);
  /* a linear key with kind rotary is refused, naming it and the right one */
  check_true(load_params("actuator = { kind = \"rotary\"; force_constant_N_per_A = 3.8; };", &p,
                         &err) == POM_ERR_CONFIG);
  printf("  %s\n", err.message);
  check_true(strstr(err.message, "actuator.force_constant_N_per_A") != NULL &&
             strstr(err.message, "actuator.torque_constant_Nm_per_A") != NULL);
  check_true(load_params("actuator = { kind = \"rotary\"; sensor_gain_V_per_m = 800.0; };", &p,
                         &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "actuator.sensor_gain_V_per_rad") != NULL);
  /* and a rotary key with the default (linear) kind */
  check_true(load_params("actuator = { bearing_friction_Nms_per_rad = 1e-5; };", &p, &err) ==
             POM_ERR_CONFIG);
  check_true(strstr(err.message, "actuator.bearing_friction_Nms_per_rad") != NULL &&
             strstr(err.message, "actuator.bearing_friction_Ns_per_m") != NULL);
  check_true(load_params("actuator = { kind = \"spinning\"; };", &p, &err) != POM_OK);
  check_true(load_params("actuator = { force_constant_N_per_A = 3.1; };", &p, &err) == POM_OK &&
             p.actuator.kind == POM_ACT_PRISMATIC);

  /* the parameters' kind must be the mechanism's */
  pom_mechanism mech;
  rotors3(&mech);
  pom_dyn_params_defaults(&p); /* linear */
  pom_dyn_model *m = NULL;
  check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_ERR_ARG && m == NULL);
  printf("  %s\n", err.message);
  check_true(strstr(err.message, "actuator.kind = \"rotary\"") != NULL);
  /* a rotary actuator on a prismatic joint is refused too */
  rotary_params(&p);
  mech.joint[1].type = POM_JOINT_PRISMATIC;
  check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_ERR_ARG && m == NULL);
  check_true(strstr(err.message, "revolute") != NULL);
  /* the rigid formulation needs the architecture */
  rotors3(&mech);
  p.joints.model = POM_JOINTS_RIGID;
  check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_ERR_ARG && m == NULL);
  check_true(strstr(err.message, "needs the architecture") != NULL);
}

/* ---- a target outside a rotary stroke --------------------------------------- */
/* Reads "... = <value> <unit> ..." after `label` in text: 1 when both were
 * found (unit at most 7 characters). */
static int read_quantity(const char *text, const char *label, double *value, char unit[8]) {
  const char *at = strstr(text, label);
  return at && sscanf(at + strlen(label), "%lf %7s", value, unit) == 2;
}

/* The refusal reports the target and the stroke in the actuator kind's
 * display unit, degrees here (it said mm: 0.7 rad read as "700 mm").
 * Numbers are read back and compared: %.10g keeps 10 digits, 5e-10
 * relative. */
static void test_rotary_refusal(void) {
  pom_mechanism mech;
  rotors3(&mech); /* stroke 1.2 rad: +-0.6 rad = +-34.377 deg */
  pom_dyn_params p;
  rotary_params(&p);
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_dyn_metrics mt;
  pom_error err;
  pom_error_clear(&err);
  const double target[3] = {0.1, 0.7, -0.2}; /* rad: actuator 2 beyond +-0.6 */
  if (check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_OK &&
                 pom_dyn_data_create(&d, m, &err) == POM_OK &&
                 pom_dyn_simulate(m, d, target, &mt, NULL, &err) == POM_ERR_LIMIT)) {
    printf("  %s\n  reason: %s\n", err.message, mt.reason);
    double q = 0.0, half = 0.0, q_reason = 0.0;
    char unit[8] = "", half_unit[8] = "", reason_unit[8] = "";
    check_true(mt.status == POM_ERR_LIMIT);
    check_true(read_quantity(err.message, "actuator 2 = ", &q, unit) &&
               read_quantity(err.message, "stroke +-", &half, half_unit) &&
               read_quantity(mt.reason, "actuator 2 = ", &q_reason, reason_unit));
    check_true(strcmp(unit, "deg") == 0 && strcmp(half_unit, "deg") == 0 &&
               strcmp(reason_unit, "deg") == 0);
    check_rel(q, 0.7 / POM_DEG, 5e-10);
    check_rel(half, 0.6 / POM_DEG, 5e-10);
    check_rel(q_reason, 0.7 / POM_DEG, 5e-10);
  }
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* Kinds that are not kinds are refused where they enter the dynamics, in
 * the parameters and in the mechanism. */
static void test_unknown_kind(void) {
  pom_mechanism mech;
  rotors3(&mech);
  pom_dyn_params p;
  rotary_params(&p);
  pom_dyn_model *m = NULL;
  pom_error err;
  pom_error_clear(&err);
  p.actuator.kind = (pom_actuator_kind)POM_ACT_KINDS;
  check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_ERR_ARG && m == NULL);
  printf("  %s\n", err.message);
  check_true(strstr(err.message, "neither linear nor rotary") != NULL);
  rotary_params(&p);
  mech.actuator[2].kind = (pom_actuator_kind)-1;
  check_true(pom_dyn_model_create(&m, &mech, NULL, &p, &err) == POM_ERR_ARG && m == NULL);
  printf("  %s\n", err.message);
  check_true(strstr(err.message, "actuator 3 of the mechanism has kind -1") != NULL);
}

int main(void) {
  test_rotors();
  test_rotary_pattern();
  test_rotary_config();
  test_rotary_refusal();
  test_unknown_kind();
  return check_summary("test_dyn_rotary");
}
