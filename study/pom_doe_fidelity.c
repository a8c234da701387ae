/* pom_doe_fidelity.c - study.fidelity = "auto": each candidate's setting
 * chosen by the rule of pom_fidelity.h and applied before its maneuvers run
 * (docs/results.md section 12). */
#include "study_internal.h"
#include "pom_h5.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The setting's keys merged into the candidate's resolved config, so that
 * the results file's config, summary.md and the uncertain draws' rebuilt
 * evaluators carry the setting run. */
static pom_status resolve_setting(pom_doe_candidate *cand, const pom_fidelity_setting *s,
                                  pom_error *err) {
  char text[512];
  snprintf(text, sizeof text,
           "joints = { model = \"rigid\"; };\n"
           "scene = { coil_inductance = %s; limb_inertia = \"full\"; universal_joint = true; };\n"
           "solver = { rtol = %.17g; atol_scale = 0.0; };\n",
           s->coil_inductance ? "true" : "false", s->rtol);
  config_t base, over;
  config_init(&base);
  config_init(&over);
  pom_status st = POM_OK;
  char *out = NULL;
  POM_TRY_GOTO(
      pom_doe_tree_read_string(&base, cand->resolved ? cand->resolved : "", cand->name, ".", err),
      done);
  POM_TRY_GOTO(pom_doe_tree_read_string(&over, text, "study.fidelity", ".", err), done);
  POM_TRY_GOTO(pom_doe_tree_merge(config_root_setting(&base), config_root_setting(&over),
                                  "study.fidelity = \"auto\"", err),
               done);
  POM_TRY_GOTO(pom_doe_tree_write(&base, &out, err), done);
  free(cand->resolved);
  cand->resolved = out;
done:
  config_destroy(&over);
  config_destroy(&base);
  return st;
}

/* The rule on one candidate, then its model rebuilt with the choice. */
static pom_status fidelity_one(pom_doe_candidate *cand, const pom_doe_study *study,
                               pom_error *err) {
  if (!cand->eval.dyn_base)
    POM_FAIL(err, POM_ERR_CONFIG,
             "study.fidelity = \"auto\": candidate '%s' is not run by the dynamics model",
             cand->name);
  pom_doe_dyn_base *base = cand->eval.ctx;
  const pom_fidelity_opts *o = &study->fidelity;
  double(*sel)[3] = calloc((size_t)o->n_select, sizeof *sel);
  double(*val)[3] = calloc((size_t)o->n_validate, sizeof *val);
  pom_status st = POM_OK;
  if (!sel || !val) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "fidelity: out of memory");
  int n_sel = 0, n_val = 0;
  pom_doe_maneuver_targets(sel, &n_sel, &study->maneuvers, study->fidelity_seed, o->n_select,
                           &base->arch);
  /* held out: the candidate's own maneuvers (the first of the study's) */
  pom_doe_maneuver_targets(val, &n_val, &study->maneuvers, study->maneuvers.seed, o->n_validate,
                           &base->arch);
  if (n_sel < 1 || n_val < 1)
    POM_FAIL_GOTO(err, POM_ERR_LIMIT, done,
                  "study.fidelity = \"auto\": candidate '%s' reaches none of the %d %s maneuvers",
                  cand->name, n_sel < 1 ? o->n_select : o->n_validate,
                  n_sel < 1 ? "selection" : "validation");
  POM_TRY_GOTO(pom_fidelity_select(&cand->fidelity, &base->arch, &base->mech, &base->params,
                                   (const double(*)[3])sel, n_sel, (const double(*)[3])val, n_val,
                                   o, err),
               done);
  pom_dyn_params p = base->params;
  pom_fidelity_apply(&p, &cand->fidelity.setting);
  pom_dyn_model *m = NULL;
  POM_TRY_GOTO(pom_dyn_model_create(&m, &base->mech, &base->arch, &p, err), done);
  pom_dyn_model_destroy(base->model);
  base->model = m;
  base->params = p;
  POM_TRY_GOTO(resolve_setting(cand, &cand->fidelity.setting, err), done);
  cand->fidelity_chosen = 1;
done:
  if (st != POM_OK) pom_error_prefix(err, "candidate '%s'", cand->name);
  free(sel);
  free(val);
  return st;
}

pom_status pom_doe_fidelity_run(pom_doe_study *study,
                                void (*progress)(void *user, const pom_doe_candidate *cand,
                                                 int done, int total),
                                void *user, pom_error *err) {
  if (!study->fidelity_auto) return POM_OK;
  for (int c = 0; c < study->n_candidates; ++c) {
    POM_TRY(fidelity_one(&study->candidates[c], study, err));
    if (progress) progress(user, &study->candidates[c], c + 1, study->n_candidates);
  }
  return POM_OK;
}

pom_status pom_doe_fidelity_describe(const pom_doe_study *study, int c, hid_t g, pom_error *err) {
  const pom_doe_candidate *cand = &study->candidates[c];
  if (!cand->fidelity_chosen) return POM_OK;
  const pom_fidelity_result *f = &cand->fidelity;
  POM_TRY(pom_h5_attr_string(g, "fidelity", "auto", err));
  POM_TRY(pom_h5_attr_string(g, "fidelity_setting", f->setting.label, err));
  POM_TRY(pom_h5_attr_int64(g, "fidelity_met", f->met, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_accuracy", f->accuracy, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_margin", f->margin, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_error_time", f->bound_time, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_error_energy", f->bound_energy, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_selection_error_time", f->select_time, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_selection_error_energy", f->select_energy, err));
  POM_TRY(pom_h5_attr_int64(g, "fidelity_selection_maneuvers", f->n_select, err));
  POM_TRY(pom_h5_attr_int64(g, "fidelity_validation_maneuvers", f->n_validate, err));
  POM_TRY(pom_h5_attr_int64(g, "fidelity_selection_seed", (int64_t)study->fidelity_seed, err));
  POM_TRY(pom_h5_attr_int64(g, "fidelity_validation_seed", (int64_t)study->maneuvers.seed, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_reference_rtol", study->fidelity.reference_rtol, err));
  POM_TRY(pom_h5_attr_double(g, "fidelity_wall_s", f->wall, err));
  return POM_OK;
}
