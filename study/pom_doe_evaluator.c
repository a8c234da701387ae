/* pom_doe_evaluator.c - an evaluator's config groups, and the check that a
 * sweep factor or uncertain key is one the candidate's model reads. */
#include "pom_dyn_ctrl.h"
#include "study_internal.h"

#include <stdio.h>
#include <string.h>

void pom_doe_evaluator_clear(pom_doe_evaluator *eval) {
  if (!eval) return;
  if (eval->ctx_destroy && eval->ctx) eval->ctx_destroy(eval->ctx);
  memset(eval, 0, sizeof *eval);
}

pom_status pom_doe_evaluator_add_groups(pom_doe_evaluator *eval, const char *const *names,
                                        pom_error *err) {
  int n = 0;
  while (eval->groups[n])
    ++n;
  for (; *names; ++names) {
    if (n >= POM_DOE_MAX_GROUPS)
      POM_FAIL(err, POM_ERR_INTERNAL, "evaluator: more than %d config groups", POM_DOE_MAX_GROUPS);
    eval->groups[n++] = *names;
  }
  eval->groups[n] = NULL;
  return POM_OK;
}

int pom_doe_evaluator_reads(const pom_doe_evaluator *eval, const char *group) {
  if (!eval->groups[0]) return 1;
  for (int k = 0; eval->groups[k]; ++k)
    if (strcmp(eval->groups[k], group) == 0) return 1;
  return 0;
}

/* ---- keys the model reads ------------------------------------------------------- */
void pom_doe_evaluator_group_list(char *buf, size_t cap, const pom_doe_evaluator *eval) {
  size_t used = 0;
  buf[0] = '\0';
  for (int k = 0; eval->groups[k] && used < cap; ++k) {
    int w = snprintf(buf + used, cap - used, "%s%s", k ? ", " : "", eval->groups[k]);
    if (w < 0) break;
    used += (size_t)w;
  }
}

pom_status pom_doe_check_dotted(const pom_cfg *cfg, const char *what, const char *key,
                                pom_error *err) {
  const char *dot = strchr(key, '.');
  if (!dot || dot == key || dot[1] == '\0' || dot[strcspn(dot, "[")] != '\0')
    return pom_cfg_error(cfg, what, NULL, err,
                         "expected a dotted key group.name of the candidates' configs (e.g. "
                         "\"controller.kp\")");
  return POM_OK;
}

pom_status pom_doe_check_model_key(const pom_cfg *cfg, const char *what, const char *key,
                                   const pom_doe_candidate *cand, pom_error *err) {
  POM_TRY(pom_doe_check_dotted(cfg, what, key, err));
  char group[POM_DOE_NAME_LEN];
  snprintf(group, sizeof group, "%.*s", (int)(strchr(key, '.') - key), key);
  if (!pom_doe_evaluator_reads(&cand->eval, group)) {
    char list[256];
    pom_doe_evaluator_group_list(list, sizeof list, &cand->eval);
    return pom_cfg_error(cfg, what, NULL, err,
                         "the model of candidate '%s' never reads group '%s', so the key would "
                         "change nothing (its groups: %s)",
                         cand->name, group, list);
  }
  /* the controller group holds the keys of every registered type (one config
   * carries several controllers' gains); the candidate's type reads its own */
  if (cand->eval.dyn_base && strcmp(group, "controller") == 0) {
    const pom_dyn_ctrl_type *t =
        pom_dyn_ctrl_of(&((const pom_doe_dyn_base *)cand->eval.ctx)->params.controller);
    const char *name = key + strlen("controller.");
    if (strcmp(name, "type") != 0 && pom_dyn_ctrl_gain_index(t, name) < 0 &&
        pom_dyn_ctrl_option_index(t, name) < 0) {
      char keys[256] = "";
      size_t used = 0;
      for (int k = 0; k < t->n_gains + t->n_options && used < sizeof keys; ++k) {
        int w = snprintf(keys + used, sizeof keys - used, "%s%s", k ? ", " : "",
                         k < t->n_gains ? t->gains[k].key : t->options[k - t->n_gains].key);
        if (w < 0) break;
        used += (size_t)w;
      }
      return pom_cfg_error(cfg, what, NULL, err,
                           "the %s controller (controller.type = \"%s\") of candidate '%s' never "
                           "reads it, so the key would change nothing (its keys: %s)",
                           t->label, t->name, cand->name, keys);
    }
  }
  return POM_OK;
}
