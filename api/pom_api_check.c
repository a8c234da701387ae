/* pom_api_check.c - the checks every caller of the library shares with the
 * program: which config keys a command reads (unknown keys, unknown
 * top-level names, overrides nobody read) and the range of a thread count
 * (pom_api.h). Its own file, with no dependency beyond the libraries' group
 * lists, so that a program can link it alone. */
#include "pom_api.h"

#include "pom_capability.h"
#include "pom_study.h"
#include "pom_dynamics.h"
#include "pom_synth.h"
#include "pom_tune.h"

#include <stddef.h>

/* ---- config keys ---------------------------------------------------------------- */
pom_status pom_api_known_groups(pom_cfg_groups *g, pom_error *err) {
  if (!g) POM_FAIL(err, POM_ERR_ARG, "pom_api_known_groups: NULL argument");
  const char *const *const lists[] = {pom_kin_model_groups(),
                                      pom_kin_ws_groups(),
                                      pom_dyn_param_groups(),
                                      pom_doe_study_groups(),
                                      pom_doe_sens_groups(),
                                      pom_grad_groups(),
                                      pom_tradeoff_groups(),
                                      pom_syn_groups(),
                                      pom_tune_groups(),
                                      pom_cap_groups(),
                                      NULL};
  pom_cfg_groups_init(g);
  for (int k = 0; lists[k]; ++k)
    POM_TRY(pom_cfg_groups_add(g, lists[k], err));
  return POM_OK;
}

pom_status pom_api_check_keys(const pom_cfg *cfg, const char *const *const scopes[],
                              const char *const *later, pom_error *err) {
  if (!cfg || !scopes) POM_FAIL(err, POM_ERR_ARG, "pom_api_check_keys: NULL argument");
  pom_cfg_groups own, known;
  pom_cfg_groups_init(&own);
  for (int k = 0; scopes[k]; ++k)
    POM_TRY(pom_cfg_groups_add(&own, scopes[k], err));
  POM_TRY(pom_api_known_groups(&known, err));
  POM_TRY(pom_cfg_check_unknown(cfg, own.name, known.name, err));
  return pom_cfg_check_overrides(cfg, own.name, later, err);
}

/* ---- arguments ------------------------------------------------------------------- */
pom_status pom_api_check_threads(long threads, const char *origin, pom_error *err) {
  if (threads < 0 || threads > POM_API_THREADS_MAX)
    POM_FAIL(err, POM_ERR_ARG,
             "%s = %ld: expected an integer in [1, %d] worker threads (0 = study.threads, else "
             "every core)",
             origin ? origin : "threads", threads, POM_API_THREADS_MAX);
  return POM_OK;
}
