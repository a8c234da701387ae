/* test_api_null.c - the NULL rule of the public layer (api/pom_api.h, the
 * pom_cfg_* calls of docs/api.md section 3): every function called with NULL
 * in each pointer argument, one at a time, the others valid. Status
 * functions return POM_ERR_ARG with a message, pointer functions NULL,
 * counts 0, numbers NaN, void functions nothing; optional outputs may be
 * NULL. tests/check_api_null.py fails when a function of the header is
 * missing here, so a new function cannot escape the rule. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include "check.h"
#include "pom_api.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *cfg_3pss = POM_SOURCE_DIR "/configs/3pss.cfg";

/* A refused call: POM_ERR_ARG, and a message when err was given. */
static void refused(pom_status st, const pom_error *err, const char *what) {
  if (st != POM_ERR_ARG || (err && !err->message[0]))
    fprintf(stderr, "  %s: status %d, message '%s'\n", what, (int)st, err ? err->message : "");
  check_true(st == POM_ERR_ARG);
  if (err) check_true(err->message[0] != '\0');
}

static pom_cfg *load(void) {
  pom_cfg *cfg = NULL;
  pom_error err;
  check_true(pom_cfg_load(&cfg, cfg_3pss, &err) == POM_OK);
  return cfg;
}

static void test_config(void) {
  pom_error err;
  pom_cfg *cfg = NULL;
  pom_error_clear(&err);
  refused(pom_cfg_load(NULL, cfg_3pss, &err), &err, "pom_cfg_load(NULL out)");
  refused(pom_cfg_load(&cfg, NULL, &err), &err, "pom_cfg_load(NULL path)");
  check_true(cfg == NULL);
  refused(pom_cfg_load(&cfg, NULL, NULL), NULL, "pom_cfg_load(NULL path, NULL err)");
  refused(pom_cfg_load_string(NULL, "a = 1;", "<t>", &err), &err, "load_string(NULL out)");
  refused(pom_cfg_load_string(&cfg, NULL, "<t>", &err), &err, "load_string(NULL text)");
  refused(pom_cfg_load_string(&cfg, "a = 1;", NULL, &err), &err, "load_string(NULL name)");
  check_true(cfg == NULL);
  cfg = load();
  refused(pom_cfg_set_number(NULL, "controller.kp", "1", "t", &err), &err, "set_number(NULL cfg)");
  refused(pom_cfg_set_number(cfg, NULL, "1", "t", &err), &err, "set_number(NULL key)");
  refused(pom_cfg_set_number(cfg, "controller.kp", NULL, "t", &err), &err, "set_number(NULL text)");
  refused(pom_cfg_set_number(cfg, "controller.kp", "1", NULL, &err), &err,
          "set_number(NULL origin)");
  refused(pom_cfg_set_string(NULL, "joints.model", "rigid", "t", &err), &err,
          "set_string(NULL cfg)");
  refused(pom_cfg_set_string(cfg, NULL, "rigid", "t", &err), &err, "set_string(NULL key)");
  refused(pom_cfg_set_string(cfg, "joints.model", NULL, "t", &err), &err, "set_string(NULL text)");
  refused(pom_cfg_set_string(cfg, "joints.model", "rigid", NULL, &err), &err,
          "set_string(NULL origin)");
  refused(pom_cfg_check_unknown(NULL, NULL, NULL, &err), &err, "check_unknown(NULL cfg)");
  check_true(pom_cfg_check_unknown(cfg, NULL, NULL, &err) == POM_ERR_CONFIG); /* NULL = all */
  refused(pom_cfg_check_overrides(NULL, NULL, NULL, &err), &err, "check_overrides(NULL cfg)");
  check_true(pom_cfg_check_overrides(cfg, NULL, NULL, NULL) == POM_OK);
  pom_cfg_destroy(NULL);
  pom_cfg_destroy(cfg);
}

static void test_checks(void) {
  pom_error err;
  pom_cfg_groups g;
  pom_cfg *cfg = load();
  const char *const *const scopes[] = {pom_kin_arch_groups(), NULL};
  refused(pom_api_known_groups(NULL, &err), &err, "pom_api_known_groups(NULL)");
  check_true(pom_api_known_groups(&g, NULL) == POM_OK && g.n > 10);
  refused(pom_api_check_keys(NULL, scopes, NULL, &err), &err, "check_keys(NULL cfg)");
  refused(pom_api_check_keys(cfg, NULL, NULL, &err), &err, "check_keys(NULL scopes)");
  check_true(pom_api_check_threads(2, NULL, &err) == POM_OK);
  refused(pom_api_check_threads(-1, NULL, &err), &err, "check_threads(-1, NULL origin)");
  check_true(strstr(err.message, "threads") != NULL);
  pom_cfg_destroy(cfg);
}

static void test_registries(void) {
  pom_api_quiet_handlers();
  check_true(pom_api_version() != NULL && pom_api_git_commit() != NULL);
  check_true(pom_api_struct_size(NULL) == 0);
  /* every output optional */
  check_true(pom_api_arch_type_info(0, NULL, NULL, NULL) == POM_OK);
  check_true(pom_api_ctrl_type_info(0, NULL, NULL, NULL) == POM_OK);
  check_true(pom_api_register_architecture_files(NULL) == POM_OK);
  char buf[96];
  check_true(pom_api_metric_count() > 0);
  check_true(pom_api_metric_key(0, NULL, sizeof buf) == NULL);
  check_true(pom_api_metric_key(0, buf, sizeof buf) != NULL);
  check_true(pom_api_metric_width(0) >= 1);
  check_true(pom_api_metric_is_integer(-1) == 0);
}

static void test_kinematics(void) {
  pom_error err;
  pom_cfg *cfg = load();
  pom_kin_arch *arch = NULL;
  pom_kin_ws_result res;
  double out[3], f = 0.0;
  refused(pom_api_arch_create(NULL, cfg, &err), &err, "arch_create(NULL out)");
  refused(pom_api_arch_create(&arch, NULL, &err), &err, "arch_create(NULL cfg)");
  check_true(arch == NULL);
  check_true(pom_api_arch_create(&arch, cfg, &err) == POM_OK);
  check_true(pom_api_arch_actuator_unit(NULL, NULL) == NULL);
  check_true(pom_api_arch_actuator_unit(NULL, &f) == NULL);
  check_true(pom_api_arch_actuator_unit(arch, NULL) != NULL);
  check_true(pom_api_arch_limit_key(NULL, 1, &f) == NULL);
  check_true(pom_api_arch_limit_key(arch, 1, NULL) != NULL);
  refused(pom_api_workspace(NULL, cfg, &res, out, &err), &err, "workspace(NULL arch)");
  refused(pom_api_workspace(arch, NULL, &res, out, &err), &err, "workspace(NULL cfg)");
  refused(pom_api_workspace(arch, cfg, NULL, out, &err), &err, "workspace(NULL res)");
  refused(pom_api_workspace(arch, cfg, &res, NULL, &err), &err, "workspace(NULL out)");
  pom_api_arch_destroy(NULL);
  pom_api_arch_destroy(arch);
  pom_cfg_destroy(cfg);
}

static void test_sim(void) {
  pom_error err;
  pom_cfg *cfg = load();
  pom_api_sim *sim = NULL;
  double v[3], target[3] = {1.385e-3, -2.0e-3, 0.5e-3};
  const char *reason = NULL;
  int w = 0;
  refused(pom_api_sim_create(NULL, cfg, 0, &err), &err, "sim_create(NULL out)");
  refused(pom_api_sim_create(&sim, NULL, 0, &err), &err, "sim_create(NULL cfg)");
  check_true(sim == NULL);
  /* the calls on a NULL simulation */
  refused(pom_api_sim_run(NULL, target, &err), &err, "sim_run(NULL sim)");
  check_true(pom_api_sim_name(NULL) == NULL);
  check_true(isnan(pom_api_sim_half_stroke(NULL)));
  refused(pom_api_sim_status(NULL, &reason), NULL, "sim_status(NULL sim)");
  check_true(reason != NULL && reason[0] != '\0');
  refused(pom_api_sim_status(NULL, NULL), NULL, "sim_status(NULL, NULL)");
  check_true(pom_api_sim_metric(NULL, 0, v) == 0);
  check_true(pom_api_sim_samples(NULL) == 0);
  check_true(pom_api_sim_trace(NULL, "t", &w) == NULL);
  pom_api_sim_destroy(NULL);
  /* NULL inputs and optional outputs on a real one */
  check_true(pom_api_sim_create(&sim, cfg, 1, &err) == POM_OK);
  refused(pom_api_sim_run(sim, NULL, &err), &err, "sim_run(NULL target)");
  check_true(pom_api_sim_metric(sim, 0, NULL) == 0);
  check_true(pom_api_sim_run(sim, target, NULL) == POM_OK);
  check_true(pom_api_sim_status(sim, NULL) == POM_OK);
  check_true(pom_api_sim_metric(sim, 0, NULL) == 0);
  check_true(pom_api_sim_trace(sim, NULL, &w) == NULL);
  check_true(pom_api_sim_trace(sim, "t", NULL) != NULL);
  pom_api_sim_destroy(sim);
  pom_cfg_destroy(cfg);
}

static void test_study(void) {
  pom_error err;
  pom_cfg *cfg = load();
  pom_api_study_opts o;
  pom_api_study_defaults(NULL);
  pom_api_study_defaults(&o);
  o.montecarlo = 1;
  refused(pom_api_study_run(NULL, &o, NULL, NULL, &err), &err, "study_run(NULL cfg)");
  refused(pom_api_study_run(cfg, NULL, NULL, NULL, &err), &err, "study_run(NULL opts)");
  o.output = NULL;
  refused(pom_api_study_run(cfg, &o, NULL, NULL, &err), &err, "study_run(NULL output)");
  char *json = NULL;
  refused(pom_api_study_run_json(NULL, &o, NULL, NULL, &json, &err), &err,
          "study_run_json(NULL cfg)");
  refused(pom_api_study_run_json(cfg, NULL, NULL, NULL, &json, &err), &err,
          "study_run_json(NULL opts)");
  check_true(json == NULL);
  /* the design gradients: every pointer argument NULL in turn */
  const char *gkeys[1] = {"actuator.resistance_ohm"};
  refused(pom_api_gradient_json(NULL, gkeys, 1, 1, &json, &err), &err, "gradient_json(NULL cfg)");
  refused(pom_api_gradient_json(cfg, NULL, 1, 1, &json, &err), &err, "gradient_json(NULL keys)");
  refused(pom_api_gradient_json(cfg, gkeys, 1, 1, NULL, &err), &err, "gradient_json(NULL json)");
  check_true(pom_api_gradient_json(cfg, gkeys, 1, 1, &json, NULL) != POM_OK); /* parasitic */
  check_true(json == NULL);
  pom_api_free(NULL);
  /* NULL done, total, tabular and err: a run all the same */
  char dir[] = "/tmp/pom_test_api_null_XXXXXX", h5[128];
  check_true(mkdtemp(dir) != NULL);
  snprintf(h5, sizeof h5, "%s/mc.h5", dir);
  check_true(pom_cfg_set_number(cfg, "montecarlo.maneuvers", "2", "test", &err) == POM_OK);
  check_true(pom_cfg_set_string(cfg, "joints.model", "rigid", "test", &err) == POM_OK);
  o.output = h5;
  o.tabular = NULL;
  o.threads = 1;
  check_true(pom_api_study_run(cfg, &o, NULL, NULL, NULL) == POM_OK);
  remove(h5);
  /* NULL json too: the run without its report */
  check_true(pom_api_study_run_json(cfg, &o, NULL, NULL, NULL, NULL) == POM_OK);
  remove(h5);
  check_true(pom_api_study_run_json(cfg, &o, NULL, NULL, &json, NULL) == POM_OK);
  check_true(json != NULL && json[0] == '{');
  pom_api_free(json);
  remove(h5);
  rmdir(dir);
  pom_cfg_destroy(cfg);
}

int main(void) {
  test_config();
  test_checks();
  test_registries();
  test_kinematics();
  test_sim();
  test_study();
  return check_summary("test_api_null");
}
