/* dyn_test_util.h - helpers shared by the dynamics test programs: one
 * maneuver with its model, data and trace kept alive for the checks, and the
 * shipped configs loaded into a mechanism and parameters. static inline so a
 * program that does not use one of them compiles without warnings. */
#ifndef POM_DYN_TEST_UTIL_H
#define POM_DYN_TEST_UTIL_H

#include "pom_config.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"

#include <stdio.h>
#include <string.h>

typedef struct {
  pom_dyn_model *m;
  pom_dyn_data *d;
  pom_dyn_trace *tr;
  pom_dyn_metrics mt;
  pom_status st;
  pom_error err;
} run_t;

static inline void run_free(run_t *r) {
  pom_dyn_trace_destroy(r->tr);
  pom_dyn_data_destroy(r->d);
  pom_dyn_model_destroy(r->m);
  memset(r, 0, sizeof *r);
}

/* Builds model, data and trace and runs one maneuver; returns the status
 * (the objects stay alive until run_free). */
static inline pom_status run_arch(run_t *r, const pom_mechanism *mech, const pom_kin_arch *arch,
                                  const pom_dyn_params *p, const double target[3],
                                  const pom_dyn_initial *init) {
  memset(r, 0, sizeof *r);
  pom_error_clear(&r->err);
  r->st = pom_dyn_model_create(&r->m, mech, arch, p, &r->err);
  if (r->st == POM_OK) r->st = pom_dyn_data_create(&r->d, r->m, &r->err);
  if (r->st == POM_OK) r->st = pom_dyn_trace_create(&r->tr, r->m, &r->err);
  if (r->st == POM_OK)
    r->st = pom_dyn_simulate_ex(r->m, r->d, target, init, &r->mt, r->tr, &r->err);
  if (r->st != POM_OK) printf("  run: %s\n", r->err.message);
  return r->st;
}

/* The same without the architecture (parasitic joints only). */
static inline pom_status run(run_t *r, const pom_mechanism *mech, const pom_dyn_params *p,
                             const double target[3], const pom_dyn_initial *init) {
  return run_arch(r, mech, NULL, p, target, init);
}

/* Loads configs/<file> of the source tree into arch, mech and p (defaults
 * first); returns 1 on success, prints the reason otherwise. */
static inline int load_shipped(const char *file, pom_kin_arch *arch, pom_mechanism *mech,
                               pom_dyn_params *p) {
  char path[512];
  snprintf(path, sizeof path, "%s/configs/%s", POM_SOURCE_DIR, file);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  int ok = pom_cfg_load(&cfg, path, &err) == POM_OK &&
           pom_kin_arch_load(arch, cfg, &err) == POM_OK &&
           pom_kin_mechanism_build(mech, arch, cfg, &err) == POM_OK;
  pom_dyn_params_defaults(p);
  ok = ok && pom_dyn_params_load(p, cfg, &err) == POM_OK;
  if (!ok) printf("  loading %s: %s\n", file, err.message);
  pom_cfg_destroy(cfg);
  return ok;
}

#endif
