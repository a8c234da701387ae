/* pom_doe_uncertain.c - a study's uncertain parameters against its
 * candidates: nominal values, the check that every value a distribution
 * can draw passes the key's own validation, the per-maneuver evaluator
 * with the draws set, and the draws in the results file (docs/results.md,
 * section 10). */
#include "study_internal.h"
#include "pom_h5.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- nominal values --------------------------------------------------------- */
/* The candidate's value of each uncertain key (NaN when absent; only a
 * relative parameter needs one), and no uncertain integer keys or
 * candidates whose geometry or gains come from the pipeline. */
static pom_status nominal_values(double *nominal, const pom_doe_study *study, int c,
                                 const pom_cfg *cfg, pom_error *err) {
  const pom_doe_candidate *cand = &study->candidates[c];
  const pom_unc *unc = &study->uncertain;
  pom_status st = POM_OK;
  config_t tree;
  config_init(&tree);
  POM_TRY_GOTO(pom_doe_tree_read_string(&tree, cand->resolved, cand->source, NULL, err), done);
  static const char *const pipeline[] = {"synthesis.run_in_study", "tuning.run_in_study", NULL};
  for (int j = 0; pipeline[j]; ++j) {
    int on = 0;
    if (config_lookup_bool(&tree, pipeline[j], &on) && on) {
      st = pom_cfg_error(cfg, "uncertain", NULL, err,
                         "candidate '%s' sets %s: its geometry or gains are made when the study "
                         "loads, so drawn values cannot be applied per maneuver",
                         cand->name, pipeline[j]);
      goto done;
    }
  }
  for (int j = 0; j < unc->n; ++j) {
    char k[64];
    snprintf(k, sizeof k, "uncertain.[%d].key", j);
    /* a key the model never reads changes nothing: its indices would be 0 */
    POM_TRY_GOTO(pom_doe_check_model_key(cfg, k, unc->param[j].key, cand, err), done);
    const config_setting_t *s = config_lookup(&tree, unc->param[j].key);
    int type = s ? config_setting_type(s) : CONFIG_TYPE_NONE;
    nominal[j] = NAN;
    if (type == CONFIG_TYPE_FLOAT) {
      nominal[j] = config_setting_get_float(s);
    } else if (type == CONFIG_TYPE_INT || type == CONFIG_TYPE_INT64) {
      st = pom_cfg_error(cfg, k, NULL, err,
                         "an integer key of candidate '%s' cannot take drawn (real) values",
                         cand->name);
      goto done;
    } else if (s) {
      st = pom_cfg_error(cfg, k, NULL, err, "not a number in the config of candidate '%s'",
                         cand->name);
      goto done;
    }
    if (unc->param[j].relative && !isfinite(nominal[j])) {
      st = pom_cfg_error(cfg, k, NULL, err,
                         "relative = true needs the key in the config of candidate '%s' (the "
                         "nominal value the draws multiply)",
                         cand->name);
      goto done;
    }
    if (unc->param[j].relative && nominal[j] == 0.0) {
      st = pom_cfg_error(cfg, k, NULL, err,
                         "relative = true multiplies the nominal value, which is 0 in candidate "
                         "'%s': every draw would be 0 (give absolute values instead)",
                         cand->name);
      goto done;
    }
  }
done:
  config_destroy(&tree);
  return st;
}

/* ---- evaluators with drawn values ----------------------------------------------- */
/* Candidate c's evaluator with key j set to value[j] for every j where
 * set[j] (NULL = all). */
/* The candidate's config with key j set to value[j] where set[j] (NULL =
 * all) and, when controller_only, only for the keys whose draw the
 * controller's own model takes (uncertain.[j].controller = "drawn"). */
static pom_status drawn_config(pom_cfg **out, const pom_doe_study *study, int c,
                               const double *value, const int *set, int controller_only,
                               pom_error *err) {
  const pom_doe_candidate *cand = &study->candidates[c];
  const pom_unc *unc = &study->uncertain;
  pom_status st = POM_OK;
  char *text = NULL;
  config_t tree;
  config_init(&tree);
  POM_TRY_GOTO(pom_doe_tree_read_string(&tree, cand->resolved, cand->source, NULL, err), done);
  for (int j = 0; j < unc->n; ++j)
    if ((!set || set[j]) && (!controller_only || unc->param[j].controller_drawn))
      POM_TRY_GOTO(pom_doe_tree_set_number(&tree, unc->param[j].key, value[j], err), done);
  POM_TRY_GOTO(pom_doe_tree_write(&tree, &text, err), done);
  char name[POM_DOE_PATH_LEN + 64];
  snprintf(name, sizeof name, "%s with %s values", cand->source,
           controller_only ? "the controller's" : "uncertain");
  POM_TRY_GOTO(pom_cfg_load_string(out, text, name, err), done);
done:
  free(text);
  config_destroy(&tree);
  return st;
}

/* The plant takes the draws; a model-based controller keeps the nominal
 * candidate unless a parameter says otherwise (docs/control.md section 1). */
static pom_status build(pom_doe_evaluator *eval, const pom_doe_study *study, int c,
                        const double *value, const int *set, pom_error *err) {
  pom_status st = POM_OK;
  pom_cfg *cfg = NULL, *ctrl_cfg = NULL;
  memset(eval, 0, sizeof *eval);
  POM_TRY_GOTO(drawn_config(&cfg, study, c, value, set, 0, err), done);
  POM_TRY_GOTO(drawn_config(&ctrl_cfg, study, c, value, set, 1, err), done);
  st = pom_doe_dyn_evaluator_create_ex(eval, cfg, ctrl_cfg, err);
done:
  pom_cfg_destroy(cfg);
  pom_cfg_destroy(ctrl_cfg);
  return st;
}

pom_status pom_doe_uncertain_evaluator(pom_doe_evaluator *eval, const pom_doe_study *study, int c,
                                       const double *x, pom_error *err) {
  const pom_unc *unc = &study->uncertain;
  double value[POM_UNC_MAX];
  for (int j = 0; j < unc->n; ++j)
    value[j] = unc->param[j].relative ? study->uncertain_nominal[c * unc->n + j] * x[j] : x[j];
  return build(eval, study, c, value, NULL, err);
}

/* Every value a parameter can draw passes the key's own validation: the
 * candidate is built with the key at the lower and at the upper end of its
 * distribution (keys are checked one at a time, each against its range). */
static pom_status check_ends(const pom_doe_study *study, int c, const pom_cfg *cfg,
                             pom_error *err) {
  const pom_unc *unc = &study->uncertain;
  for (int j = 0; j < unc->n; ++j) {
    const pom_unc_param *p = &unc->param[j];
    const double nominal = study->uncertain_nominal[c * unc->n + j];
    int set[POM_UNC_MAX] = {0};
    set[j] = 1;
    for (int end = 0; end < 2; ++end) {
      double draw = end ? p->dist.hi : p->dist.lo;
      double value[POM_UNC_MAX] = {0};
      value[j] = p->relative ? nominal * draw : draw;
      pom_doe_evaluator ev;
      pom_error e;
      pom_error_clear(&e);
      pom_status st = build(&ev, study, c, value, set, &e);
      pom_doe_evaluator_clear(&ev);
      if (st != POM_OK) {
        char k[64];
        snprintf(k, sizeof k, "uncertain.[%d]", j);
        return pom_cfg_error(cfg, k, NULL, err,
                             "'%s' can be drawn as %.6g (the %s end of its %s distribution%s), "
                             "where candidate '%s' is invalid: %s",
                             p->key, value[j], end ? "upper" : "lower", p->dist.ops->name,
                             p->relative ? ", times the nominal value" : "",
                             study->candidates[c].name, e.message);
      }
    }
  }
  return POM_OK;
}

pom_status pom_doe_uncertain_prepare(pom_doe_study *study, const pom_cfg *cfg, pom_error *err) {
  const pom_unc *unc = &study->uncertain;
  if (unc->n == 0) return POM_OK;
  study->uncertain_nominal = malloc((size_t)(study->n_candidates * unc->n) * sizeof(double));
  if (!study->uncertain_nominal) POM_FAIL(err, POM_ERR_NOMEM, "uncertain: out of memory");
  for (int c = 0; c < study->n_candidates; ++c) {
    POM_TRY(nominal_values(study->uncertain_nominal + c * unc->n, study, c, cfg, err));
    POM_TRY(check_ends(study, c, cfg, err));
  }
  return POM_OK;
}

/* ---- results file ------------------------------------------------------------ */
/* Draws of units [0, count) (count = the study's maneuvers), row-major
 * [count][n]; malloc'ed. */
static double *all_draws(const pom_doe_study *study) {
  const pom_unc *unc = &study->uncertain;
  long m = study->maneuvers.count;
  double *x = malloc((size_t)(m * unc->n) * sizeof *x);
  if (!x) return NULL;
  for (long k = 0; k < m; ++k)
    pom_unc_draws(unc, k, x + k * unc->n);
  return x;
}

pom_status pom_doe_uncertain_write(hid_t file, const pom_doe_study *study, pom_error *err) {
  const pom_unc *unc = &study->uncertain;
  if (unc->n == 0) return POM_OK;
  pom_status st = POM_OK;
  hid_t g = -1;
  double *x = all_draws(study);
  char keys[POM_UNC_MAX * (POM_UNC_KEY_LEN + 1)] = "", dists[POM_UNC_MAX * 20] = "";
  double params[POM_UNC_MAX * 4];
  int64_t relative[POM_UNC_MAX];
  if (!x) POM_FAIL(err, POM_ERR_NOMEM, "results: out of memory");
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "uncertain", err), done);
  for (int j = 0; j < unc->n; ++j) {
    const pom_unc_param *p = &unc->param[j];
    strcat(keys, j ? "," : "");
    strcat(keys, p->key);
    strcat(dists, j ? "," : "");
    strcat(dists, p->dist.ops->name);
    for (int i = 0; i < 4; ++i)
      params[4 * j + i] = p->dist.p[i];
    relative[j] = p->relative;
  }
  POM_TRY_GOTO(pom_h5_attr_string(g, "keys", keys, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "distributions", dists, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(g, "seed", (int64_t)unc->seed, err), done);
  size_t dims[2] = {(size_t)unc->n, 4};
  POM_TRY_GOTO(pom_h5_write_doubles(g, "parameters", 2, dims, params, err), done);
  POM_TRY_GOTO(pom_h5_write_int64s(g, "relative", (size_t)unc->n, relative, err), done);
  dims[0] = (size_t)study->maneuvers.count;
  dims[1] = (size_t)unc->n;
  POM_TRY_GOTO(pom_h5_write_doubles(g, "draws", 2, dims, x, err), done);
  dims[0] = (size_t)study->n_candidates;
  POM_TRY_GOTO(pom_h5_write_doubles(g, "nominal", 2, dims, study->uncertain_nominal, err), done);
done:
  free(x);
  if (g >= 0) H5Gclose(g);
  return st;
}

/* The config key of parameter i of a distribution kind (pom_dist p[]). */
static const char *param_name(const char *dist, int i) {
  static const char *const names[][5] = {{"uniform", "min", "max", NULL, NULL},
                                         {"normal", "mean", "sd", NULL, NULL},
                                         {"truncated_normal", "mean", "sd", "min", "max"},
                                         {"lognormal", "median", "sigma_ln", "min", "max"}};
  for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
    if (strcmp(names[k][0], dist) == 0 && names[k][1 + i]) return names[k][1 + i];
  return "parameter";
}

/* The shortest of %.15g / %.17g that reads back as v. */
static void shortest(char *buf, size_t cap, double v) {
  snprintf(buf, cap, "%.15g", v);
  if (strtod(buf, NULL) != v) snprintf(buf, cap, "%.17g", v);
}

/* Resume: every setting of a parameter that changes a row is the file's:
 * its distribution and parameters, and `relative` (which the draws do not
 * show: the same draws are factors or values). */
static pom_status check_settings(hid_t g, const pom_doe_study *study, const char *path,
                                 pom_error *err) {
  const pom_unc *unc = &study->uncertain;
  char dists[POM_UNC_MAX * 20] = "", stored[sizeof dists];
  double relative[POM_UNC_MAX], params[POM_UNC_MAX * 4];
  for (int j = 0; j < unc->n; ++j) {
    strcat(dists, j ? "," : "");
    strcat(dists, unc->param[j].dist.ops->name);
  }
  POM_TRY(pom_h5_read_attr_string(g, "distributions", stored, sizeof stored, err));
  POM_TRY(pom_h5_read_doubles(g, "relative", (size_t)unc->n, relative, err));
  POM_TRY(pom_h5_read_doubles(g, "parameters", (size_t)unc->n * 4, params, err));
  char changed[256] = "";
  if (strcmp(stored, dists) != 0)
    snprintf(changed, sizeof changed, "the distributions (%s in the file, %s now)", stored, dists);
  for (int j = 0; j < unc->n && !changed[0]; ++j) {
    const pom_unc_param *p = &unc->param[j];
    if (relative[j] != (double)p->relative)
      snprintf(changed, sizeof changed, "key 'uncertain.[%d].relative' (%s in the file, %s now)", j,
               relative[j] != 0 ? "true" : "false", p->relative ? "true" : "false");
    for (int i = 0; i < 4 && !changed[0]; ++i) {
      double a = params[4 * j + i], b = p->dist.p[i];
      if (a != b && !(isnan(a) && isnan(b))) {
        char was[32], now[32];
        shortest(was, sizeof was, a);
        shortest(now, sizeof now, b);
        snprintf(changed, sizeof changed,
                 "key 'uncertain.[%d].%s' of '%s' (%s in the file, %s now)", j,
                 param_name(p->dist.ops->name, i), p->key, was, now);
      }
    }
  }
  if (changed[0])
    POM_FAIL(err, POM_ERR_ARG,
             "'%s' holds another study; changed: %s; remove it or choose another output", path,
             changed);
  return POM_OK;
}

pom_status pom_doe_uncertain_check(hid_t file, const pom_doe_study *study, const char *path,
                                   pom_error *err) {
  const pom_unc *unc = &study->uncertain;
  int have = H5Lexists(file, "uncertain", H5P_DEFAULT) > 0;
  if (have != (unc->n > 0))
    POM_FAIL(err, POM_ERR_ARG,
             "'%s' was written %s an `uncertain` group and this study has %s: remove it or "
             "choose another output",
             path, have ? "with" : "without", have ? "none" : "one");
  if (!have) return POM_OK;
  pom_status st = POM_OK;
  hid_t g = -1;
  size_t n = (size_t)(study->maneuvers.count * unc->n);
  double *want = all_draws(study), *got = malloc(n * sizeof *got);
  char keys[POM_UNC_MAX * (POM_UNC_KEY_LEN + 1)] = "", stored[sizeof keys];
  for (int j = 0; j < unc->n; ++j) {
    strcat(keys, j ? "," : "");
    strcat(keys, unc->param[j].key);
  }
  if (!want || !got) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "results: out of memory");
  POM_TRY_GOTO(pom_h5_open_group(&g, file, "uncertain", err), done);
  POM_TRY_GOTO(pom_h5_read_attr_string(g, "keys", stored, sizeof stored, err), done);
  if (strcmp(stored, keys) != 0)
    POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                  "'%s' has uncertain keys %s, this study %s: remove it or choose another output",
                  path, stored, keys);
  POM_TRY_GOTO(check_settings(g, study, path, err), done);
  POM_TRY_GOTO(pom_h5_read_doubles(g, "draws", n, got, err), done);
  if (memcmp(got, want, n * sizeof *got) != 0)
    POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                  "'%s': the uncertain draws stored differ from the ones drawn now (another "
                  "distribution or seed): remove the file or choose another output",
                  path);
done:
  free(want);
  free(got);
  if (g >= 0) H5Gclose(g);
  return st;
}
