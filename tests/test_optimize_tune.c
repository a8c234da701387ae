/* test_optimize_tune.c - the gain-tuning criterion and its failure paths on
 * the shipped 3PSS reference config. */
#include "check.h"
#include "pom_tune.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static pom_tune_problem pb;

static int load(void) {
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load(&cfg, POM_SOURCE_DIR "/configs/3pss.cfg", &err);
  if (st == POM_OK) st = pom_tune_load(&pb, cfg, &err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) printf("load: %s\n", err.message);
  return st == POM_OK;
}

/* The criterion of one maneuver is its execution time plus the stated
 * penalties, computed from the same simulation. */
static void test_criterion(void) {
  pom_error err;
  pb.n_maneuvers = 1;
  pb.target[0][0] = 2.385e-3;
  pb.target[0][1] = -1.17e-3;
  pb.target[0][2] = 0.643e-3;
  pom_tune_eval ev;
  check_true(pom_tune_evaluate(&pb, &pb.params.controller, &ev, &err) == POM_OK);
  /* the same maneuver simulated directly */
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_dyn_metrics mt;
  check_true(pom_dyn_model_create(&m, &pb.mech, NULL, &pb.params, &err) == POM_OK);
  check_true(pom_dyn_data_create(&d, m, &err) == POM_OK);
  pom_dyn_trace *tr = NULL;
  check_true(pom_dyn_trace_create(&tr, m, &err) == POM_OK);
  check_true(pom_dyn_simulate(m, d, pb.target[0], &mt, tr, &err) == POM_OK);
  check_true(isfinite(mt.execution_time) && ev.unsettled == 0);
  /* overshoot: the largest excursion of an actuator beyond its setpoint, as
     a fraction of its step, from the sampled trace (docs/optimize.md 9) */
  double os = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < tr->n; ++k) {
      double s = pb.target[0][a] > 0.0 ? 1.0 : -1.0;
      os = fmax(os, s * (tr->q[3 * k + a] - pb.target[0][a]) / fabs(pb.target[0][a]));
    }
  check_true(os > 0.0); /* the reference gains overshoot a little: the check can fail */
  check_rel(ev.max_overshoot, os, 1e-12);
  pom_dyn_trace_destroy(tr);
  check_rel(ev.mean_execution, mt.execution_time, 1e-12);
  double sat = fmax(mt.saturation_time[0], fmax(mt.saturation_time[1], mt.saturation_time[2]));
  check_rel(ev.max_saturation, sat, 1e-12);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  /* limits that do not bind: criterion = execution time */
  check_rel(ev.criterion, ev.mean_execution, 1e-15);
  /* limits that bind: the penalty formula of docs/optimize.md 9 */
  pom_tune_problem tight = pb;
  tight.overshoot_max = 0.5 * ev.max_overshoot + 1e-6;
  tight.saturation_time_max = 0.5 * ev.max_saturation;
  pom_tune_eval ev2;
  check_true(pom_tune_evaluate(&tight, &pb.params.controller, &ev2, &err) == POM_OK);
  double pen = 0.0;
  if (ev2.max_overshoot > tight.overshoot_max)
    pen += (ev2.max_overshoot - tight.overshoot_max) / fmax(tight.overshoot_max, 1e-3);
  if (ev2.max_saturation > tight.saturation_time_max)
    pen += (ev2.max_saturation - tight.saturation_time_max) /
           fmax(tight.saturation_time_max, 1e-3 * pb.params.maneuver.horizon);
  check_true(pen > 0.0);
  check_rel(ev2.criterion, ev2.mean_execution + tight.penalty_weight * pen, 1e-12);

  /* A loop too soft to reach the 2 % band (proportional only, kp = 1: the
     steady-state error against gravity and friction stays): the maneuver is
     unsettled and censored at the horizon. */
  pom_dyn_controller soft = pb.params.controller;
  soft.kp = 1.0;
  soft.ki = 0.0;
  soft.kd = 0.0;
  pom_tune_eval ev3;
  check_true(pom_tune_evaluate(&pb, &soft, &ev3, &err) == POM_OK);
  check_true(ev3.unsettled == 1);
  check_rel(ev3.mean_execution, pb.params.maneuver.horizon, 1e-15);
}

/* What the progress callback saw. */
typedef struct {
  long calls, last_done, bound, out_of_order;
} progress_seen;

static void on_progress(void *user, const char *phase, long done, long bound) {
  progress_seen *s = user;
  if (strcmp(phase, "tune") != 0) ++s->out_of_order;
  if (done != s->last_done + 1 && done != bound) ++s->out_of_order;
  ++s->calls;
  s->last_done = done;
  s->bound = bound;
}

/* A short search from a deliberately slow derivative time improves it. */
static void test_search(void) {
  pom_error err;
  pom_tune_problem p = pb;
  p.n_vars = 1;
  p.var[0] = POM_TUNE_KD;
  p.lo[0] = 1e-3;
  p.hi[0] = 2e-2;
  p.log_scale[0] = 1;
  p.params.controller.kd = 1.8e-2; /* heavily damped: slow */
  p.opt.global = POM_OPT_GLOBAL_DIRECT_L;
  p.opt.global_max_evals = 8;
  p.opt.local_max_evals = 8;
  pom_tune_result res;
  progress_seen seen = {0, 0, 0, 0};
  p.progress = on_progress;
  p.progress_user = &seen;
  check_true(pom_tune_run(&p, &res, &err) == POM_OK);
  check_true(res.best_eval.criterion < 0.7 * res.initial_eval.criterion);
  /* told once per evaluation, counting up by one, and at the end the bound
   * (2 + 8 + 8) even when the searches stopped early */
  check_true(seen.calls == res.opt.evals_global + res.opt.evals_local + 2);
  check_true(seen.last_done == 18 && seen.bound == 18 && seen.out_of_order == 0);
  check_true(res.best.kd >= p.lo[0] && res.best.kd <= p.hi[0]);
  check_true(res.simulations == (res.opt.evals_global + res.opt.evals_local + 2) * p.n_maneuvers);
  /* the gains in config form */
  /* a name unique per process: several build trees may run the suite at once */
  char path[128];
  unsigned long tag = (unsigned long)time(NULL) ^ (unsigned long)(uintptr_t)&tag;
  snprintf(path, sizeof path, "/tmp/pomlab_test_tune_%lx.controller.cfg", tag);
  check_true(pom_tune_write_controller(&p, &res, path, &err) == POM_OK);
  pom_cfg *cfg = NULL;
  char text[512];
  snprintf(text, sizeof text, "@include \"%s\"\n", path);
  check_true(pom_cfg_load_string(&cfg, text, "<back>", &err) == POM_OK);
  pom_dyn_params back;
  pom_dyn_params_defaults(&back);
  check_true(pom_dyn_params_load(&back, cfg, &err) == POM_OK);
  check_rel(back.controller.kd, res.best.kd, 1e-8);
  check_rel(back.controller.kp, res.best.kp, 1e-8);
  pom_cfg_destroy(cfg);
  remove(path);
}

/* tuning.optimizer.local_starts and local_start_separation (docs/optimize.md
 * 9): read, range-checked with file, line and key, a misspelt name refused
 * as an unknown key; the progress bound counts every local run. */
static pom_status load_tuning(pom_tune_problem *p, const char *tuning, pom_error *err) {
  char text[1024];
  /* (an empty group is an unknown key: none then) */
  snprintf(text, sizeof text, "@include \"%s/configs/3pss.cfg\"\n%s%s%s\n", POM_SOURCE_DIR,
           tuning[0] ? "tuning = { " : "", tuning, tuning[0] ? " };" : "");
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load_string(&cfg, text, "<starts>", err);
  if (st == POM_OK) st = pom_tune_load(p, cfg, err);
  const char *const scopes[] = {"tuning", NULL};
  if (st == POM_OK) st = pom_cfg_check_unknown(cfg, scopes, NULL, err);
  pom_cfg_destroy(cfg);
  return st;
}

static void test_local_starts_keys(void) {
  static pom_tune_problem p;
  pom_error err;
  pom_error_clear(&err);
  check_true(load_tuning(&p, "", &err) == POM_OK);
  check_true(p.opt.local_starts == 1 && p.opt.local_start_separation == 0.1);
  check_true(load_tuning(&p, "optimizer = { local_starts = 3; local_start_separation = 0.25; };",
                         &err) == POM_OK);
  check_true(p.opt.local_starts == 3 && p.opt.local_start_separation == 0.25);
  static const char *const bad[] = {"optimizer = { local_starts = 0; };",
                                    "optimizer = { local_starts = 17; };",
                                    "optimizer = { local_starts = 2.5; };",
                                    "optimizer = { local_starts = \"2\"; };",
                                    "optimizer = { local_start_separation = 0.0; };",
                                    "optimizer = { local_start_separation = 1.5; };"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
    pom_error_clear(&err);
    check_true(load_tuning(&p, bad[k], &err) == POM_ERR_CONFIG);
    check_true(strstr(err.message, "<starts>:2") != NULL);
    check_true(strstr(err.message, "tuning.optimizer.local_start") != NULL);
  }
  pom_error_clear(&err);
  check_true(load_tuning(&p, "optimizer = { local_start = 3; };", &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "local_start") != NULL);

  /* five global evaluations, two local runs of at most 3 each: the bound
   * 2 + 5 + 2 x 3 */
  pom_tune_problem q = pb;
  q.n_maneuvers = 1;
  q.n_vars = 1;
  q.var[0] = POM_TUNE_KD;
  q.lo[0] = 1e-3;
  q.hi[0] = 2e-2;
  q.log_scale[0] = 1;
  q.opt.global = POM_OPT_GLOBAL_DIRECT_L;
  q.opt.global_max_evals = 5;
  q.opt.local_max_evals = 3;
  q.opt.local_starts = 2;
  q.opt.local_start_separation = 0.05;
  progress_seen seen = {0, 0, 0, 0};
  q.progress = on_progress;
  q.progress_user = &seen;
  pom_tune_result res;
  check_true(pom_tune_run(&q, &res, &err) == POM_OK);
  check_true(res.opt.local_runs == 2);
  check_true(seen.calls == res.opt.evals_global + res.opt.evals_local + 2);
  check_true(seen.last_done == 13 && seen.bound == 13 && seen.out_of_order == 0);
}

/* A failing simulation stops the search with its own status: never a value. */
static void test_failure(void) {
  pom_error err;
  pom_error_clear(&err);
  pom_tune_problem p = pb;
  p.params.solver.max_steps = 5;
  pom_tune_result res;
  pom_status st = pom_tune_run(&p, &res, &err);
  check_true(st != POM_OK);
  check_true(strstr(err.message, "maneuver 1") != NULL);
  /* the criterion alone reports the same failure (a stop inside the NLopt
     stages is covered by test_optimize) */
  pom_tune_eval ev;
  check_true(pom_tune_evaluate(&p, &p.params.controller, &ev, &err) == st);
}

int main(void) {
  if (!load()) return check_summary("test_optimize_tune") + 1;
  test_criterion();
  test_search();
  test_local_starts_keys();
  test_failure();
  return check_summary("test_optimize_tune");
}
