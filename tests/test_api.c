/* test_api.c - the flat entry layer (api/pom_api.h): registries, IK through
 * an architecture handle, a maneuver with its metrics and traces against the
 * module calls it composes, a small Monte-Carlo run, and every error path on
 * purpose (unknown keys, a target outside the stroke, missing output, bad
 * names and indices). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include "check.h"
#include "pom_api.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_dynamics.h"
#include "pom_math.h"
#include "pom_version.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *cfg_3pss = POM_SOURCE_DIR "/configs/3pss.cfg";

static void test_registries(void) {
  pom_api_quiet_handlers();
  const char *name = NULL, *label = NULL, *kind = NULL;
  check_true(pom_api_arch_type_info(0, &name, &label, &kind) == POM_OK);
  check_true(strcmp(name, "3PSS") == 0 && strcmp(label, "3P-S-S/S") == 0);
  check_true(strcmp(kind, "prismatic") == 0);
  check_true(pom_api_arch_type_info(-1, &name, NULL, NULL) == POM_ERR_ARG);
  check_true(pom_api_arch_type_info(pom_kin_arch_type_count(), &name, NULL, NULL) == POM_ERR_ARG);
  const char *desc = NULL;
  check_true(pom_api_ctrl_type_info(0, &name, &label, &desc) == POM_OK);
  check_true(strcmp(name, "pid") == 0 && desc && desc[0]);
  check_true(pom_api_ctrl_type_info(1000, &name, NULL, NULL) == POM_ERR_ARG);
  check_true(pom_api_struct_size("pom_error") == sizeof(pom_error));
  check_true(pom_api_struct_size("pom_kin_pose") == sizeof(pom_kin_pose));
  check_true(pom_api_struct_size("no such struct") == 0);
  check_true(pom_api_struct_size(NULL) == 0);
  check_true(strcmp(pom_api_version(), pom_version()) == 0);
}

static void test_kinematics(void) {
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_kin_arch *arch = NULL;
  check_true(pom_cfg_load(&cfg, cfg_3pss, &err) == POM_OK);
  check_true(pom_api_arch_create(&arch, cfg, &err) == POM_OK);
  double to_display = 0.0;
  check_true(strcmp(pom_api_arch_actuator_unit(arch, &to_display), "m") == 0);
  check_rel(to_display, 1e3, 0.0);
  check_true(pom_api_arch_limit_key(arch, 0, NULL) == NULL);
  check_true(pom_api_arch_limit_key(arch, 1, &to_display) != NULL);
  /* the handle's geometry is the loader's: same IK */
  pom_kin_arch direct;
  check_true(pom_kin_arch_load(&direct, cfg, &err) == POM_OK);
  double e[3] = {0.02385, -0.0171, 0.0133}, R[9], q1[3], q2[3];
  pom_euler_zyx_to_matrix(R, e);
  check_true(pom_kin_inverse(arch, R, q1, &err) == POM_OK);
  check_true(pom_kin_inverse(&direct, R, q2, &err) == POM_OK);
  for (int i = 0; i < 3; ++i)
    check_abs(q1[i], q2[i], 0.0);
  pom_api_arch_destroy(arch);
  pom_api_arch_destroy(NULL);
  /* an unknown key in a group the kinematics reads names the key */
  check_true(pom_cfg_set_number(cfg, "geometry.no_such_key", "2.385", "test", &err) == POM_OK);
  arch = NULL;
  check_true(pom_api_arch_create(&arch, cfg, &err) == POM_ERR_CONFIG);
  check_true(arch == NULL && strstr(err.message, "no_such_key") != NULL);
  check_true(pom_api_arch_create(NULL, cfg, &err) == POM_ERR_ARG);
  pom_cfg_destroy(cfg);
}

static void test_simulate(void) {
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_api_sim *sim = NULL;
  check_true(pom_cfg_load(&cfg, cfg_3pss, &err) == POM_OK);
  check_true(pom_cfg_set_string(cfg, "joints.model", "rigid", "test", &err) == POM_OK);
  check_true(pom_api_sim_create(&sim, cfg, 1, &err) == POM_OK);
  const char *reason = NULL;
  check_true(pom_api_sim_status(sim, &reason) == POM_ERR_ARG); /* nothing ran yet */
  check_true(pom_api_sim_samples(sim) == 0);
  /* outside the stroke: refused, nothing run */
  double far[3] = {0.0, 0.0, 0.0071};
  check_true(pom_api_sim_run(sim, far, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "stroke") != NULL);
  double nan_target[3] = {0.0, NAN, 0.0};
  check_true(pom_api_sim_run(sim, nan_target, &err) == POM_ERR_ARG);
  double target[3] = {1.385e-3, -2.0e-3, 0.5e-3};
  check_true(pom_api_sim_run(sim, target, &err) == POM_OK);
  check_true(pom_api_sim_status(sim, &reason) == POM_OK && reason[0] == '\0');
  check_rel(pom_api_sim_half_stroke(sim), 0.006, 1e-15);

  /* the metrics are pom_dyn_simulate's on the same config */
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_params par;
  pom_dyn_model *model = NULL;
  pom_dyn_data *data = NULL;
  pom_dyn_metrics mt;
  check_true(mech != NULL);
  check_true(pom_kin_arch_load(&arch, cfg, &err) == POM_OK);
  check_true(pom_kin_mechanism_build(mech, &arch, cfg, &err) == POM_OK);
  pom_dyn_params_defaults(&par);
  check_true(pom_dyn_params_load(&par, cfg, &err) == POM_OK);
  check_true(pom_dyn_model_create(&model, mech, &arch, &par, &err) == POM_OK);
  check_true(pom_dyn_data_create(&data, model, &err) == POM_OK);
  check_true(pom_dyn_simulate(model, data, target, &mt, NULL, &err) == POM_OK);
  int n = pom_api_metric_count(), found_time = 0;
  check_true(n == POM_DYN_N_METRICS);
  for (int j = 0; j < n; ++j) {
    char key[96];
    double v[3];
    check_true(pom_api_metric_key(j, key, sizeof key) != NULL);
    int w = pom_api_sim_metric(sim, j, v);
    check_true(w == pom_api_metric_width(j));
    if (strcmp(key, "execution_time_s") == 0) {
      found_time = 1;
      check_abs(v[0], mt.execution_time, 0.0);
      check_true(!pom_api_metric_is_integer(j));
    }
    if (strcmp(key, "steps") == 0) check_true(pom_api_metric_is_integer(j));
  }
  check_true(found_time);
  char key[8];
  check_true(pom_api_metric_key(n, key, sizeof key) == NULL);
  check_true(pom_api_metric_key(-1, key, sizeof key) == NULL);
  check_true(pom_api_metric_width(n) == 0);
  double v[3];
  check_true(pom_api_sim_metric(sim, n, v) == 0);

  /* traces: every column, the last sample at the horizon */
  int ns = pom_api_sim_samples(sim), w = 0;
  check_true(ns > 100);
  const double *t = pom_api_sim_trace(sim, "t", &w);
  check_true(t != NULL && w == 1);
  if (t) check_rel(t[ns - 1], par.maneuver.horizon, 1e-12);
  const double *quat = pom_api_sim_trace(sim, "quat", &w);
  check_true(quat != NULL && w == 4);
  const char *names[] = {"q", "q_dot", "current", "voltage", "energy", "euler_zyx", "deflection"};
  for (int k = 0; k < 7; ++k)
    check_true(pom_api_sim_trace(sim, names[k], &w) != NULL);
  check_true(pom_api_sim_trace(sim, "no_such_column", &w) == NULL);

  pom_dyn_data_destroy(data);
  pom_dyn_model_destroy(model);
  free(mech);
  pom_api_sim_destroy(sim);
  pom_api_sim_destroy(NULL);

  /* a bad controller value names its key; no handle is returned */
  sim = NULL;
  check_true(pom_cfg_set_string(cfg, "controller.type", "no_such_law", "test", &err) == POM_OK);
  check_true(pom_api_sim_create(&sim, cfg, 0, &err) == POM_ERR_CONFIG);
  check_true(sim == NULL && strstr(err.message, "controller.type") != NULL);
  pom_cfg_destroy(cfg);
}

/* Overrides are checked as the file's keys are (docs/api.md section 2): a
 * misspelt group, a name no command knows, or a group the call does not
 * read is refused, naming the override. */
static pom_status sim_with(const char *key, const char *value, pom_error *err) {
  pom_cfg *cfg = NULL;
  pom_api_sim *sim = NULL;
  pom_status st = pom_cfg_load(&cfg, cfg_3pss, err);
  if (st == POM_OK) st = pom_cfg_set_number(cfg, key, value, "override test", err);
  if (st == POM_OK) st = pom_api_sim_create(&sim, cfg, 0, err);
  pom_api_sim_destroy(sim);
  pom_cfg_destroy(cfg);
  return st;
}

static void test_overrides(void) {
  pom_error err;
  pom_error_clear(&err);
  check_true(sim_with("controller.kp", "5000", &err) == POM_OK);
  check_true(sim_with("contoller.kp", "5", &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "contoller.kp") && strstr(err.message, "unknown top-level"));
  check_true(strstr(err.message, "override test") != NULL);
  check_true(sim_with("nosuch.key", "1", &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "nosuch.key") != NULL);
  check_true(sim_with("controller.kpp", "1", &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "controller.kpp") != NULL);
  /* groups another command reads: nothing here would read them */
  check_true(sim_with("montecarlo.maneuvers", "5", &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "montecarlo.maneuvers") && strstr(err.message, "not read"));
  check_true(sim_with("workspace.resolution_deg", "0.5", &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "workspace.resolution_deg") != NULL);
  /* keys that are no config names: a config error naming them */
  const char *bad[] = {"", "controller. kp", "controller..kp", ".kp", "controller.kp.", "9a"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
    check_true(sim_with(bad[k], "1", &err) == POM_ERR_CONFIG);
    check_true(strstr(err.message, "not a config key") != NULL);
  }
  /* the architecture leaves the workspace group to pom_api_workspace, which
   * reads it; a Monte-Carlo key is read by neither */
  pom_cfg *cfg = NULL;
  pom_kin_arch *arch = NULL;
  pom_kin_ws_result res;
  double out[3];
  check_true(pom_cfg_load(&cfg, cfg_3pss, &err) == POM_OK);
  check_true(pom_cfg_set_number(cfg, "workspace.resolution_deg", "2.385", "o", &err) == POM_OK);
  check_true(pom_api_arch_create(&arch, cfg, &err) == POM_OK);
  check_true(pom_cfg_set_number(cfg, "workspace.no_such_key", "1", "o", &err) == POM_OK);
  check_true(pom_api_workspace(arch, cfg, &res, out, &err) == POM_ERR_CONFIG);
  check_true(strstr(err.message, "workspace.no_such_key") != NULL);
  pom_api_arch_destroy(arch);
  arch = NULL;
  check_true(pom_cfg_set_number(cfg, "montecarlo.seed", "7", "o", &err) == POM_OK);
  check_true(pom_api_arch_create(&arch, cfg, &err) == POM_ERR_CONFIG);
  check_true(arch == NULL && strstr(err.message, "montecarlo.seed") != NULL);
  pom_cfg_destroy(cfg);
}

static void test_study(void) {
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  check_true(pom_cfg_load(&cfg, cfg_3pss, &err) == POM_OK);
  check_true(pom_cfg_set_number(cfg, "montecarlo.maneuvers", "6", "test", &err) == POM_OK);
  check_true(pom_cfg_set_string(cfg, "joints.model", "rigid", "test", &err) == POM_OK);
  pom_api_study_opts o;
  pom_api_study_defaults(&o);
  o.montecarlo = 1;
  o.threads = 2;
  /* no results file: refused */
  check_true(pom_api_study_run(cfg, &o, NULL, NULL, &err) == POM_ERR_ARG);
  /* thread counts the program refuses */
  o.output = "unused.h5";
  const int bad_threads[] = {-1, -5, POM_API_THREADS_MAX + 1, 1000000};
  for (int k = 0; k < 4; ++k) {
    o.threads = bad_threads[k];
    check_true(pom_api_study_run(cfg, &o, NULL, NULL, &err) == POM_ERR_ARG);
    check_true(strstr(err.message, "threads") != NULL);
  }
  o.threads = 2;
  char dir[] = "/tmp/pom_test_api_XXXXXX";
  check_true(mkdtemp(dir) != NULL);
  char h5[128], csv[128], cand[160];
  snprintf(h5, sizeof h5, "%s/mc.h5", dir);
  snprintf(csv, sizeof csv, "%s/mc.csv", dir);
  snprintf(cand, sizeof cand, "%s/mc_candidates.csv", dir);
  o.output = h5;
  o.tabular = csv;
  long done = 0, total = 0;
  check_true(pom_api_study_run(cfg, &o, &done, &total, &err) == POM_OK);
  check_true(done == 6 && total == 6);
  FILE *f = fopen(csv, "r");
  int lines = 0;
  for (int c; f && (c = fgetc(f)) != EOF;)
    lines += c == '\n';
  if (f) fclose(f);
  check_true(lines == 7); /* header and 6 rows */
  /* overrides the Monte-Carlo run does not read are refused, as in a file */
  const char *unread[][2] = {
      {"contoller.kp", "5"}, {"nosuch.key", "1"}, {"workspace.resolution_deg", "1"}};
  for (int k = 0; k < 3; ++k) {
    pom_cfg *c2 = NULL;
    check_true(pom_cfg_load(&c2, cfg_3pss, &err) == POM_OK);
    check_true(pom_cfg_set_number(c2, "montecarlo.maneuvers", "2", "test", &err) == POM_OK);
    check_true(pom_cfg_set_number(c2, unread[k][0], unread[k][1], "test", &err) == POM_OK);
    check_true(pom_api_study_run(c2, &o, NULL, NULL, &err) == POM_ERR_CONFIG);
    check_true(strstr(err.message, unread[k][0]) != NULL);
    pom_cfg_destroy(c2);
  }
  /* a mechanism config is not a study; a study file is not a Monte-Carlo run */
  o.montecarlo = 0;
  check_true(pom_api_study_run(cfg, &o, NULL, NULL, &err) != POM_OK);
  pom_cfg_destroy(cfg);
  check_true(pom_cfg_load(&cfg, POM_SOURCE_DIR "/configs/paper.cfg", &err) == POM_OK);
  o.montecarlo = 1;
  check_true(pom_api_study_run(cfg, &o, NULL, NULL, &err) == POM_ERR_CONFIG);
  pom_cfg_destroy(cfg);
  remove(csv);
  remove(cand);
  remove(h5);
  rmdir(dir);
}

int main(void) {
  test_registries();
  test_kinematics();
  test_simulate();
  test_overrides();
  test_study();
  return check_summary("test_api");
}
