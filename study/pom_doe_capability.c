/* pom_doe_capability.c - study.capability: each candidate's capability
 * figures (capability/pom_cap_figures.h) as columns of the study, and the
 * requirements study.capability_require on them (docs/capability.md, "As
 * study responses and constraints"). */
#include "study_internal.h"
#include "pom_h5.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void want(pom_doe_study *study, int i) {
  if (!study->capability_want[i]) ++study->capability_n;
  study->capability_want[i] = 1;
}

pom_status pom_doe_capability_load(pom_doe_study *study, const pom_cfg *cfg, pom_error *err) {
  static const char *const keys[] = {"study.capability_grid_points", "study.capability_require"};
  char list[256], k[64], name[64];
  pom_cap_figure_list(list, sizeof list);
  study->capability_n = 0;
  memset(study->capability_want, 0, sizeof study->capability_want);
  study->capability_grid = 3;
  study->n_requirements = 0;
  int n = pom_cfg_length(cfg, "study.capability");
  if (n > 0) { /* a list of figure names */
    for (int j = 0; j < n; ++j) {
      snprintf(k, sizeof k, "study.capability.[%d]", j);
      POM_TRY(pom_cfg_string(cfg, k, name, sizeof name, err));
      int i = pom_cap_figure_index(name);
      if (i < 0)
        return pom_cfg_error(cfg, k, name, err, "unknown capability figure (figures: %s)", list);
      want(study, i);
    }
    pom_cfg_mark_used(cfg, "study.capability");
  } else {
    int all = 0;
    POM_TRY(pom_cfg_bool_opt(cfg, "study.capability", 0, &all, err));
    for (int i = 0; all && i < POM_CAP_N_FIGURES; ++i)
      want(study, i);
  }
  int max = (int)(sizeof study->requirement / sizeof study->requirement[0]);
  POM_TRY(pom_cap_requirements_load(cfg, keys[1], study->requirement, max, &study->n_requirements,
                                    err));
  for (int j = 0; j < study->n_requirements; ++j)
    want(study, study->requirement[j].figure); /* a required figure is computed and shown */
  if (study->capability_n == 0) {
    if (pom_cfg_has(cfg, keys[0]))
      return pom_cfg_error(cfg, keys[0], NULL, err,
                           "only with study.capability or study.capability_require");
    return POM_OK;
  }
  long g = study->capability_grid;
  POM_TRY(pom_cfg_int_opt(cfg, keys[0], 1, POM_CAP_MAX_GRID, g, &g, err));
  if (g % 2 == 0) return pom_cfg_error(cfg, keys[0], NULL, err, "must be odd (home on the grid)");
  study->capability_grid = (int)g;
  return POM_OK;
}

/* The figures of one candidate: its model (the pipeline's geometry when it
 * made one), the workspace and capability groups of its resolved config. */
static pom_status capability_one(pom_doe_candidate *cand, const pom_doe_study *study,
                                 pom_error *err) {
  if (!cand->eval.dyn_base)
    POM_FAIL(err, POM_ERR_CONFIG,
             "study.capability: candidate '%s' is not run by the dynamics model", cand->name);
  const pom_doe_dyn_base *base = cand->eval.ctx;
  pom_cfg *ccfg = NULL;
  pom_cap_result res;
  memset(&res, 0, sizeof res);
  pom_kin_ws_opts ws;
  pom_cap_opts o;
  pom_status st = POM_OK;
  POM_TRY_GOTO(pom_cfg_load_string(&ccfg, cand->resolved ? cand->resolved : "", cand->name, err),
               done);
  POM_TRY_GOTO(pom_kin_ws_load(&ws, ccfg, err), done);
  POM_TRY_GOTO(pom_cap_load(&o, ccfg, err), done);
  pom_cap_opts_for_figures(&o, study->capability_want, study->capability_grid);
  POM_TRY_GOTO(pom_cap_run(&base->arch, &ws, &base->mech, &base->params, &o, &res, err), done);
  cand->capability_met = 1;
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
    cand->capability[i] = study->capability_want[i] ? pom_cap_figure_value(&res, i) : NAN;
  for (int j = 0; j < study->n_requirements; ++j) {
    const pom_cap_requirement *q = &study->requirement[j];
    if (!pom_cap_requirement_met(q, cand->capability[q->figure])) cand->capability_met = 0;
  }
  cand->capability_done = 1;
done:
  if (st != POM_OK) pom_error_prefix(err, "candidate '%s': study.capability", cand->name);
  pom_cap_result_free(&res);
  pom_cfg_destroy(ccfg);
  return st;
}

pom_status pom_doe_capability_run(pom_doe_study *study,
                                  void (*progress)(void *user, const pom_doe_candidate *cand,
                                                   int done, int total),
                                  void *user, pom_error *err) {
  if (study->capability_n == 0) return POM_OK;
  for (int c = 0; c < study->n_candidates; ++c) {
    POM_TRY(capability_one(&study->candidates[c], study, err));
    if (progress) progress(user, &study->candidates[c], c + 1, study->n_candidates);
  }
  return POM_OK;
}

pom_status pom_doe_capability_describe(const pom_doe_study *study, int c, hid_t g, pom_error *err) {
  const pom_doe_candidate *cand = &study->candidates[c];
  if (!cand->capability_done) return POM_OK;
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i) {
    if (!study->capability_want[i]) continue;
    char an[96];
    snprintf(an, sizeof an, "capability:%s", pom_cap_figure_name(i));
    POM_TRY(pom_h5_attr_double(g, an, cand->capability[i], err));
  }
  POM_TRY(pom_h5_attr_int64(g, "capability_grid_points", study->capability_grid, err));
  if (study->n_requirements > 0)
    POM_TRY(pom_h5_attr_int64(g, "capability_met", cand->capability_met, err));
  return POM_OK;
}
