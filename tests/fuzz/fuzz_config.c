/* fuzz_config.c - libFuzzer target: bytes -> a mechanism config file ->
 * everything `pomlab model` checks (architecture, geometry, limits,
 * workspace, inertia, mechanism, the dynamics groups and the dynamics model
 * built from them) and the loaders of the other groups a mechanism config
 * may hold (synthesis, tuning, montecarlo, tradeoff), then the unknown-key
 * check. Nothing is simulated or written (docs/fuzzing.md). */
#include "fuzz_common.h"
#include "pom_config.h"
#include "pom_run.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_synth.h"
#include "pom_explore.h"
#include "pom_tune.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *input_path;

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  input_path = pom_fuzz_setup();
  if (!input_path) abort();
  return 0;
}

/* The groups of a mechanism config that need a loader of their own, with
 * their scope name in the unknown-key check. */
static pom_status load_extras(const pom_cfg *cfg, const char **scopes, int *n_scopes,
                              pom_error *err) {
  if (pom_cfg_has(cfg, "synthesis")) {
    pom_syn_problem *syn = calloc(1, sizeof *syn);
    if (!syn) return POM_ERR_NOMEM;
    pom_syn_defaults(syn);
    pom_status st = pom_syn_load(syn, cfg, err);
    free(syn);
    pom_fuzz_check_failure(st, err, "pom_syn_load");
    if (st != POM_OK) return st;
    scopes[(*n_scopes)++] = "synthesis";
  }
  if (pom_cfg_has(cfg, "tuning")) {
    pom_tune_problem *tune = calloc(1, sizeof *tune);
    if (!tune) return POM_ERR_NOMEM;
    pom_tune_defaults(tune);
    pom_status st = pom_tune_load(tune, cfg, err);
    free(tune);
    pom_fuzz_check_failure(st, err, "pom_tune_load");
    if (st != POM_OK) return st;
    scopes[(*n_scopes)++] = "tuning";
  }
  pom_doe_maneuvers mv;
  pom_status st = pom_doe_maneuvers_load(&mv, cfg, err);
  pom_fuzz_check_failure(st, err, "pom_doe_maneuvers_load");
  if (st != POM_OK) return st;
  scopes[(*n_scopes)++] = "montecarlo";
  pom_tradeoff_opts tr;
  pom_tradeoff_defaults(&tr);
  st = pom_tradeoff_load(&tr, cfg, err);
  pom_fuzz_check_failure(st, err, "pom_tradeoff_load");
  if (st != POM_OK) return st;
  scopes[(*n_scopes)++] = "tradeoff";
  return POM_OK;
}

static int all_finite(const double *v, int n) {
  for (int k = 0; k < n; ++k)
    if (!isfinite(v[k])) return 0;
  return 1;
}

/* A mechanism built without an error holds finite numbers only: a value
 * that overflows in a unit conversion or a derived mass property must be
 * refused where it is read (docs/STYLE.md 6), not met by the solver. */
static void check_mechanism(const pom_mechanism *m) {
  const char *what = NULL;
  int at = -1;
  for (int b = 0; b < m->n_bodies && !what; ++b)
    if (!isfinite(m->body[b].mass) || !all_finite(m->body[b].inertia, 9) ||
        !all_finite(m->body[b].cm, 3))
      what = "body", at = b;
  for (int j = 0; j < m->n_joints && !what; ++j)
    if (!all_finite(m->joint[j].point, 3) || !all_finite(m->joint[j].axis, 3) ||
        !all_finite(m->joint[j].axis2, 3))
      what = "joint", at = j;
  for (int a = 0; a < m->n_actuators && !what; ++a)
    if (!isfinite(m->actuator[a].stroke)) what = "actuator", at = a;
  if (!what && !all_finite(m->gravity, 3)) what = "gravity";
  if (what) {
    fprintf(stderr, "fuzz: the mechanism was built with a non-finite %s (%d)\n", what, at);
    abort();
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (pom_fuzz_refused(data, size)) return -1; /* not added to the corpus */
  if (pom_fuzz_write(input_path, data, size) != 0) abort();
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load(&cfg, input_path, &err);
  pom_fuzz_check_failure(st, &err, "pom_cfg_load");
  if (st != POM_OK) return 0;

  /* what `pomlab model` reads, in its order (cli/cmd_model.c) */
  const char *scopes[24] = {"name",      "architecture", "geometry", "limits",
                            "workspace", "inertia",      "actuator", "controller",
                            "joints",    "scene",        "solver",   "maneuver"};
  int n_scopes = 12;
  pom_kin_arch arch;
  pom_kin_ws_opts ws;
  pom_mechanism mech;
  pom_dyn_params dyn;
  pom_dyn_model *model = NULL;
  pom_dyn_data *work = NULL;
  pom_kin_ws_defaults(&ws);
  pom_dyn_params_defaults(&dyn);
  st = pom_kin_arch_load(&arch, cfg, &err);
  pom_fuzz_check_failure(st, &err, "pom_kin_arch_load");
  if (st == POM_OK) {
    st = pom_kin_ws_load(&ws, cfg, &err);
    pom_fuzz_check_failure(st, &err, "pom_kin_ws_load");
  }
  if (st == POM_OK) {
    st = pom_kin_mechanism_build(&mech, &arch, cfg, &err);
    pom_fuzz_check_failure(st, &err, "pom_kin_mechanism_build");
    if (st == POM_OK) check_mechanism(&mech);
  }
  if (st == POM_OK) {
    st = pom_dyn_params_load(&dyn, cfg, &err);
    pom_fuzz_check_failure(st, &err, "pom_dyn_params_load");
  }
  /* the model a simulation would use, sized once (never run) */
  if (st == POM_OK) {
    st = pom_dyn_model_create(&model, &mech, &arch, &dyn, &err);
    pom_fuzz_check_failure(st, &err, "pom_dyn_model_create");
  }
  if (st == POM_OK) {
    st = pom_dyn_data_create(&work, model, &err);
    pom_fuzz_check_failure(st, &err, "pom_dyn_data_create");
  }
  if (st == POM_OK) st = load_extras(cfg, scopes, &n_scopes, &err);
  if (st == POM_OK) {
    scopes[n_scopes] = NULL;
    st = pom_cfg_check_unknown(cfg, scopes, NULL, &err);
    pom_fuzz_check_failure(st, &err, "pom_cfg_check_unknown");
  }
  pom_dyn_data_destroy(work);
  pom_dyn_model_destroy(model);
  pom_cfg_destroy(cfg);
  return 0;
}
