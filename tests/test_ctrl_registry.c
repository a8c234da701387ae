/* test_ctrl_registry.c - a program's own controller through the public API
 * (docs/extending.md section 6): two control laws defined only here,
 * registered, loaded from a config by name with their gains, and run on both
 * formulations (parasitic and rigid) of all three shipped architectures.
 *
 * - "test_pid_fd" is the built-in ideal PID law without partial derivatives:
 *   the Newton matrix falls back to finite differences (parasitic: coloured
 *   differences of the whole RHS; rigid: the controller and coil columns
 *   differenced too). Same law, same model: its metrics equal the PID's up
 *   to the integration error at rtol 1e-8, measured for each case as the
 *   difference between the PID at rtol 1e-8 and 1e-9 (the floor).
 * - "test_pid_lag" has two states per actuator (the integral and a
 *   first-order filtered rate v_f, tau_f v_f' = q_dot - v_f, u = S K_P (e +
 *   K_I z - tau_D v_f)) and state rates that read q_dot and its own states.
 *   As tau_f -> 0 it tends to the PID; the difference is first order in
 *   tau_f (a lag tau_f in the derivative path), so dividing tau_f by 10
 *   divides the difference by about 10: the test asks for a factor >= 5.
 * Also: the registry refuses a second type of the same name and an
 * incomplete table, and the config refuses an unknown type and a gain out of
 * its range, naming the key. */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"
#include "pom_dyn_ctrl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- test_pid_fd: the PID law, no partials ---------------------------------- */
static double fd_law(const pom_dyn_controller *c, const pom_dyn_ctrl_input *in, const double *z,
                     double *zdot) {
  double kp = c->gain[0], ki = c->gain[1], kd = c->gain[2];
  double e = in->target - in->q;
  if (zdot) zdot[0] = e;
  return in->sensor_gain * kp * (e + ki * z[0] - kd * in->q_dot);
}

static int fd_describe(const pom_dyn_controller *c, char *buf, size_t cap) {
  return snprintf(buf, cap, "ideal PID without partials, K_P %g, K_I %g 1/s, tau_D %g s",
                  c->gain[0], c->gain[1], c->gain[2]);
}

static const pom_dyn_ctrl_state_desc fd_states[] = {
    {"integral", "integral of e (m s or rad s)", POM_DYN_CTRL_STATE_Q_TIME}};
static const pom_dyn_gain_desc fd_gains[] = {{"kp", "K_P", "V/V", "proportional", 0.0, 1e12, 1.2e4,
                                              1, 1, POM_DYN_CTRL_GAIN_SLOT(0), 1, 1e2, 1e5},
                                             {"ki_per_s", "K_I", "1/s", "integral", 0.0, 1e9, 1e-3,
                                              1, 1, POM_DYN_CTRL_GAIN_SLOT(1), 0, 1e-4, 1e2},
                                             {"kd_s", "tau_D", "s", "derivative time", 0.0, 1e3,
                                              3e-3, 1, 1, POM_DYN_CTRL_GAIN_SLOT(2), 1, 5e-4,
                                              2e-2}};

static const pom_dyn_ctrl_type test_pid_fd = {
    .name = "test_pid_fd",
    .label = "PID (finite-difference Jacobian)",
    .description = "the ideal PID without partials (test only)",
    .n_states = 1,
    .states = fd_states,
    .rate_deps = 0,
    .n_gains = 3,
    .gains = fd_gains,
    .law = fd_law,
    .partials = NULL,
    .describe = fd_describe,
};

/* ---- test_pid_lag: a filtered derivative, two states ------------------------- */
static double lag_law(const pom_dyn_controller *c, const pom_dyn_ctrl_input *in, const double *z,
                      double *zdot) {
  double kp = c->gain[0], ki = c->gain[1], kd = c->gain[2], tau_f = c->gain[3];
  double e = in->target - in->q;
  if (zdot) {
    zdot[0] = e;
    zdot[1] = (in->q_dot - z[1]) / tau_f;
  }
  return in->sensor_gain * kp * (e + ki * z[0] - kd * z[1]);
}

static int lag_describe(const pom_dyn_controller *c, char *buf, size_t cap) {
  return snprintf(buf, cap, "PID with a filtered rate, K_P %g, K_I %g 1/s, tau_D %g s, tau_f %g s",
                  c->gain[0], c->gain[1], c->gain[2], c->gain[3]);
}

static const pom_dyn_ctrl_state_desc lag_states[] = {
    {"integral", "integral of e (m s or rad s)", POM_DYN_CTRL_STATE_Q_TIME},
    {"rate", "filtered actuator rate (m/s or rad/s)", POM_DYN_CTRL_STATE_RATE}};
static const pom_dyn_gain_desc lag_gains[] = {
    {"kp", "K_P", "V/V", "proportional", 0.0, 1e12, 1.2e4, 1, 1, POM_DYN_CTRL_GAIN_SLOT(0), 1, 1e2,
     1e5},
    {"ki_per_s", "K_I", "1/s", "integral", 0.0, 1e9, 1e-3, 1, 1, POM_DYN_CTRL_GAIN_SLOT(1), 0, 1e-4,
     1e2},
    {"kd_s", "tau_D", "s", "derivative time", 0.0, 1e3, 3e-3, 1, 1, POM_DYN_CTRL_GAIN_SLOT(2), 1,
     5e-4, 2e-2},
    {"tau_f_s", "tau_f", "s", "rate filter time constant", 1e-12, 1.0, 1e-6, 0, 0,
     POM_DYN_CTRL_GAIN_SLOT(3), 0, 0.0, 0.0}};

static const pom_dyn_ctrl_type test_pid_lag = {
    .name = "test_pid_lag",
    .label = "PID with a filtered rate",
    .description = "two states per actuator, rates reading q_dot and z (test only)",
    .n_states = 2,
    .states = lag_states,
    .rate_deps = POM_DYN_CTRL_DEP_QDOT | POM_DYN_CTRL_DEP_STATE,
    .n_gains = 4,
    .gains = lag_gains,
    .law = lag_law,
    .partials = NULL,
    .describe = lag_describe,
};

/* ---- helpers ------------------------------------------------------------------ */
typedef struct {
  const char *file;
  double target[3]; /* display units: mm, or deg for the 3-RRR */
  double to_si;
} arch_case;

static const arch_case cases[] = {
    {"3pss.cfg", {1.5, -2.0, 0.5}, 1e-3},
    {"3sps.cfg", {1.5, -2.0, 0.5}, 1e-3},
    {"3rrr.cfg", {4.0, -3.0, 2.5}, 0.017453292519943295},
};

/* One maneuver of `file` with controller.type = `type` (and, when tau_f > 0,
 * controller.tau_f_s) set on the shipped config as command-line values are,
 * and the joint model; returns 1 when it ran. The shipped config's PID gains
 * (kp, ki_per_s, kd_s) are read by the test types under the same keys. */
static int run_with(const arch_case *ac, const char *type, double tau_f, pom_joint_model joints,
                    double rtol, pom_dyn_metrics *out) {
  char path[512], num[64];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, ac->file);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  pom_dyn_params_defaults(&p);
  snprintf(num, sizeof num, "%.17g", tau_f);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_cfg_set_string(cfg, "controller.type", type, "test", &err) == POM_OK &&
           (tau_f == 0.0 ||
            pom_cfg_set_number(cfg, "controller.tau_f_s", num, "test", &err) == POM_OK) &&
           pom_kin_arch_load(&arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_build(&mech, &arch, cfg, &err) == POM_OK &&
           pom_dyn_params_load(&p, cfg, &err) == POM_OK;
  pom_cfg_destroy(cfg);
  if (!ok) {
    printf("  loading %s with controller %s: %s\n", ac->file, type, err.message);
    return 0;
  }
  p.joints.model = joints;
  p.scene.coil_inductance = 1;
  p.solver.rtol = rtol;
  p.solver.atol_scale = 0.0; /* natural sizes: rtol alone sets the accuracy */
  double target[3];
  for (int i = 0; i < 3; ++i)
    target[i] = ac->target[i] * ac->to_si;
  run_t r;
  pom_status st = run_arch(&r, &mech, &arch, &p, target, NULL);
  if (st == POM_OK) *out = r.mt;
  if (st == POM_OK && joints == POM_JOINTS_PARASITIC && r.m->ctrl->n_states > 1) {
    /* the parasitic pattern built from the type's rate_deps holds every
     * derivative of the finite-difference Jacobian (a moving state: the end
     * of the run, every body state nudged) */
    int n = r.m->n_states, wi = -1, wj = -1;
    double *y = calloc((size_t)(4 * n), sizeof *y);
    memcpy(y, r.d->yfinal, (size_t)n * sizeof *y);
    for (int i = 0; i < n; ++i)
      y[i] += 1e-3 * r.m->scale[i] * (double)((i * 7919) % 13 - 6);
    double worst = pom_dyn_structure_check(r.m, r.d, y, y + n, y + 2 * n, y + 3 * n, &wi, &wj);
    if (!(worst == 0.0))
      printf("  %s: derivative %.3g outside the pattern at (%d, %d)\n", ac->file, worst, wi, wj);
    check_abs(worst, 0.0, 0.0);
    free(y);
  }
  run_free(&r);
  return st == POM_OK;
}

/* Largest relative difference of the per-actuator energies and settling
 * times of a and b (the settling times relative to the horizon 0.1 s, the
 * energies to b's total). */
static double metric_diff(const pom_dyn_metrics *a, const pom_dyn_metrics *b) {
  double d = 0.0;
  for (int i = 0; i < 3; ++i) {
    d = fmax(d, fabs(a->energy[i] - b->energy[i]) / fabs(b->energy_total));
    d = fmax(d, fabs(a->settling_time[i] - b->settling_time[i]) / 0.1);
  }
  return d;
}

/* ---- the registry ------------------------------------------------------------- */
static void test_registry(void) {
  pom_error err;
  pom_error_clear(&err);
  int n0 = pom_dyn_ctrl_type_count();
  check_true(pom_dyn_ctrl_type_find("pid") == &pom_dyn_ctrl_pid);
  check_true(pom_dyn_ctrl_register(&test_pid_fd, &err) == POM_OK);
  check_true(pom_dyn_ctrl_register(&test_pid_lag, &err) == POM_OK);
  check_true(pom_dyn_ctrl_type_count() == n0 + 2);
  check_true(pom_dyn_ctrl_type_find("test_pid_lag") == &test_pid_lag);
  /* a name taken, an incomplete table, a default outside its range */
  check_true(pom_dyn_ctrl_register(&test_pid_fd, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "registered already") != NULL);
  pom_dyn_ctrl_type broken = test_pid_fd;
  broken.name = "broken";
  broken.law = NULL;
  check_true(pom_dyn_ctrl_register(&broken, &err) == POM_ERR_ARG);
  pom_dyn_gain_desc bad_gain[3];
  memcpy(bad_gain, fd_gains, sizeof bad_gain);
  bad_gain[0].def = -1.0;
  broken = test_pid_fd;
  broken.name = "broken2";
  broken.gains = bad_gain;
  check_true(pom_dyn_ctrl_register(&broken, &err) == POM_ERR_ARG);
  check_true(pom_dyn_ctrl_type_find("broken") == NULL && pom_dyn_ctrl_type_find("broken2") == NULL);
}

/* The config: an unknown type and a gain out of range are refused by key. */
static void test_config_errors(void) {
  pom_dyn_metrics mt;
  printf("  (two refusals expected)\n");
  check_true(!run_with(&cases[0], "no_such_law", 0.0, POM_JOINTS_RIGID, 1e-6, &mt));
  check_true(!run_with(&cases[0], "test_pid_lag", 2.0, POM_JOINTS_RIGID, 1e-6, &mt));
}

#ifndef RTOL
#define RTOL 1e-8
#endif
#ifndef TAU_F
#define TAU_F 1e-7
#endif

/* ---- the runs -------------------------------------------------------------------- */
static void test_runs(void) {
  static const pom_joint_model models[] = {POM_JOINTS_PARASITIC, POM_JOINTS_RIGID};
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 2; ++k) {
      const arch_case *ac = &cases[c];
      pom_dyn_metrics pid, pid_tight, fd, lag1, lag2;
      int ok = run_with(ac, "pid", 0.0, models[k], RTOL, &pid) &&
               run_with(ac, "pid", 0.0, models[k], 0.1 * RTOL, &pid_tight) &&
               run_with(ac, "test_pid_fd", 0.0, models[k], RTOL, &fd) &&
               run_with(ac, "test_pid_lag", TAU_F, models[k], RTOL, &lag1) &&
               run_with(ac, "test_pid_lag", 0.1 * TAU_F, models[k], RTOL, &lag2);
      check_true(ok);
      if (!ok) continue;
      /* the integration error of the PID run at rtol 1e-8, measured against
       * rtol 1e-9: the floor of any comparison at rtol 1e-8 */
      double floor = metric_diff(&pid, &pid_tight);
      double d_fd = metric_diff(&fd, &pid);
      double d1 = metric_diff(&lag1, &pid), d2 = metric_diff(&lag2, &pid);
      printf("  %s %s: floor %.2e, |fd - pid| %.2e, |lag(tau_f) - pid| %.2e, |lag(tau_f / 10) - "
             "pid| %.2e (%ld vs %ld steps)\n",
             ac->file, models[k] == POM_JOINTS_RIGID ? "rigid" : "parasitic", floor, d_fd, d1, d2,
             fd.steps, pid.steps);
      /* the same law: the difference is integration error. The floor is
       * one estimate of it from one pair of tolerances, good to an order of
       * magnitude, and both runs carry their own: 10 x floor (measured:
       * 0.3-4 x floor at rtol 1e-8 and 1e-9) */
      check_true(d_fd <= 10.0 * floor + 1e-9);
      /* first order in tau_f: a tenth of tau_f, a tenth of the gap (measured
       * 9.5-11 x); the test asks for 5 x above the floor */
      check_true(d2 <= 0.2 * d1 + 10.0 * floor);
      check_true(d1 > 10.0 * floor && d1 < 1e-3); /* visible, and small */
    }
  }
}

int main(void) {
  test_registry();
  test_config_errors();
  test_runs();
  return check_summary("test_ctrl_registry");
}
