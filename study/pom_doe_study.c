/* pom_doe_study.c - the `name`, `montecarlo`, `study` and `candidates` keys of
 * a study file, candidate resolution and sweeps (docs/results.md). */
#include "study_internal.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CANDIDATES 4096
#define MAX_LEVELS     64

void pom_doe_study_clear(pom_doe_study *study) {
  if (!study) return;
  for (int c = 0; c < study->n_candidates; ++c) {
    free(study->candidates[c].resolved);
    pom_doe_evaluator_clear(&study->candidates[c].eval);
  }
  free(study->candidates);
  free(study->config_text);
  free(study->uncertain_nominal);
  memset(study, 0, sizeof *study);
}

pom_status pom_doe_study_select(pom_doe_study *study, const char *which, pom_error *err) {
  int pick = -1;
  for (int c = 0; c < study->n_candidates && pick < 0; ++c)
    if (strcmp(study->candidates[c].name, which) == 0) pick = c;
  if (pick < 0) {
    char *end = NULL;
    long k = strtol(which, &end, 10);
    if (end != which && *end == '\0' && k >= 1 && k <= study->n_candidates) pick = (int)k - 1;
  }
  if (pick < 0) {
    char list[512] = "";
    size_t used = 0;
    for (int c = 0; c < study->n_candidates && used + 8 < sizeof list; ++c) {
      int w = snprintf(list + used, sizeof list - used, "%s%d '%s'", c ? ", " : "", c + 1,
                       study->candidates[c].name);
      if (w < 0) break;
      used += (size_t)w < sizeof list - used ? (size_t)w : sizeof list - used - 1;
    }
    POM_FAIL(err, POM_ERR_ARG,
             "candidate '%s' is not in study '%s' (%s): give a name or a position "
             "among %s",
             which, study->name, study->source, list);
  }
  int np = study->uncertain.n;
  for (int c = 0; c < study->n_candidates; ++c) {
    if (c == pick) continue;
    free(study->candidates[c].resolved);
    pom_doe_evaluator_clear(&study->candidates[c].eval);
  }
  if (pick > 0) {
    study->candidates[0] = study->candidates[pick];
    if (study->uncertain_nominal && np > 0)
      memmove(study->uncertain_nominal, study->uncertain_nominal + (size_t)pick * (size_t)np,
              (size_t)np * sizeof *study->uncertain_nominal);
  }
  study->n_candidates = 1;
  return POM_OK;
}

static char *dup_text(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* Folder of a path, with the trailing slash ("" for a bare file name). */
static void dir_of(char *dir, size_t cap, const char *path) {
  snprintf(dir, cap, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash)
    slash[1] = '\0';
  else
    dir[0] = '\0';
}

/* File name without folder and extension. */
static void stem_of(char *stem, size_t cap, const char *path) {
  const char *base = strrchr(path, '/');
  snprintf(stem, cap, "%s", base ? base + 1 : path);
  char *dot = strrchr(stem, '.');
  if (dot && dot != stem) *dot = '\0';
}

/* ---- one candidate ------------------------------------------------------------ */
/* Study-wide inputs to candidate resolution. */
typedef struct {
  const pom_cfg *cfg;         /* the study file (validated access) */
  config_t *tree;             /* the same file parsed here, for override groups */
  char dir[POM_DOE_PATH_LEN]; /* study file folder */
  pom_doe_evaluator_factory factory;
  void *user;
} study_ctx;

/* Resolves base config + study override + candidate override + factor values
 * into cand->resolved and builds cand->eval. key = the candidate's config key
 * ("candidates.[2]" or "candidates.base.[0]"). */
static pom_status resolve_candidate(pom_doe_candidate *cand, const study_ctx *sc, const char *key,
                                    pom_error *err) {
  pom_status st = POM_OK;
  config_t base;
  pom_cfg *ccfg = NULL;
  char k[256], rel[POM_DOE_PATH_LEN];
  config_init(&base);
  snprintf(k, sizeof k, "%s.config", key);
  POM_TRY_GOTO(pom_cfg_string(sc->cfg, k, rel, sizeof rel, err), done);
  if (rel[0] == '/')
    snprintf(cand->source, sizeof cand->source, "%s", rel);
  else
    snprintf(cand->source, sizeof cand->source, "%s%s", sc->dir, rel);
  POM_TRY_GOTO(pom_doe_tree_read_file(&base, cand->source, err), done);

  int n_over = 0;
  const char *over_keys[2] = {"study.override", NULL};
  char cand_over[300];
  snprintf(cand_over, sizeof cand_over, "%s.override", key);
  over_keys[1] = cand_over;
  for (int j = 0; j < 2; ++j) {
    const config_setting_t *o = config_lookup(sc->tree, over_keys[j]);
    if (!o) continue;
    if (!config_setting_is_group(o)) {
      st = pom_cfg_error(sc->cfg, over_keys[j], NULL, err,
                         "expected a group of config settings { group = { key = value; }; }");
      goto done;
    }
    pom_cfg_mark_used(sc->cfg, over_keys[j]);
    char where[400];
    snprintf(where, sizeof where, "%s:%d: %s", pom_cfg_path(sc->cfg),
             pom_cfg_line(sc->cfg, over_keys[j]), over_keys[j]);
    POM_TRY_GOTO(pom_doe_tree_merge(config_root_setting(&base), o, where, err), done);
    ++n_over;
  }
  for (int f = 0; f < cand->n_factors; ++f)
    POM_TRY_GOTO(pom_doe_tree_set_number(&base, cand->factor_key[f], cand->factor_value[f], err),
                 done);
  POM_TRY_GOTO(pom_doe_tree_write(&base, &cand->resolved, err), done);
  if (n_over == 0 && cand->n_factors == 0) {
    /* unchanged file: load it directly so messages name its own lines */
    POM_TRY_GOTO(pom_cfg_load(&ccfg, cand->source, err), done);
  } else {
    char name[POM_DOE_PATH_LEN + 128];
    snprintf(name, sizeof name, "%s with the overrides of candidate '%s'", cand->source,
             cand->name);
    POM_TRY_GOTO(pom_cfg_load_string(&ccfg, cand->resolved, name, err), done);
  }
  POM_TRY_GOTO(sc->factory(&cand->eval, ccfg, sc->user, err), done);
  /* an override group or a factor the model never reads would change
   * nothing: a misspelt name, refused like an unknown key */
  for (int j = 0; j < 2; ++j) {
    const config_setting_t *o = config_lookup(sc->tree, over_keys[j]);
    int n = o ? config_setting_length(o) : 0;
    for (int e = 0; e < n; ++e) {
      const char *group = config_setting_name(config_setting_get_elem(o, (unsigned int)e));
      if (pom_doe_evaluator_reads(&cand->eval, group)) continue;
      char okey[400], list[256];
      snprintf(okey, sizeof okey, "%s.%s", over_keys[j], group);
      pom_doe_evaluator_group_list(list, sizeof list, &cand->eval);
      st = pom_cfg_error(sc->cfg, okey, NULL, err,
                         "unknown group: the model of candidate '%s' never reads '%s' (its "
                         "groups: %s)",
                         cand->name, group, list);
      goto done;
    }
  }
  for (int f = 0; f < cand->n_factors; ++f) {
    char fkey[64];
    snprintf(fkey, sizeof fkey, "candidates.factors.[%d].key", f);
    POM_TRY_GOTO(pom_doe_check_model_key(sc->cfg, fkey, cand->factor_key[f], cand, err), done);
  }
done:
  if (st != POM_OK) pom_error_prefix(err, "candidate '%s'", cand->name);
  pom_cfg_destroy(ccfg);
  config_destroy(&base);
  return st;
}

/* Reads name (required) of a listed candidate at key. */
static pom_status candidate_name(pom_doe_candidate *cand, const pom_cfg *cfg, const char *key,
                                 pom_error *err) {
  char k[256];
  snprintf(k, sizeof k, "%s.name", key);
  POM_TRY(pom_cfg_string(cfg, k, cand->name, sizeof cand->name, err));
  if (!cand->name[0]) return pom_cfg_error(cfg, k, NULL, err, "must not be empty");
  return POM_OK;
}

/* ---- sweeps ------------------------------------------------------------------- */
typedef struct {
  char key[POM_DOE_NAME_LEN]; /* dotted config key */
  double min, max;            /* bounds (config units) */
  long levels;                /* grid levels */
  int log;                    /* 1: spaced/sampled in log10 */
} sweep_factor;

static double factor_at(const sweep_factor *f, double u) {
  if (u <= 0) return f->min; /* exact bounds, whatever the rounding of log/pow */
  if (u >= 1) return f->max;
  if (f->log) return pow(10.0, log10(f->min) + u * (log10(f->max) - log10(f->min)));
  return f->min + u * (f->max - f->min);
}

/* Fills values[p * nf + f] for n_points points of a grid or an LHS. */
static pom_status sweep_points(double *values, long n_points, const sweep_factor *fac, int nf,
                               int lhs, uint64_t seed, pom_error *err) {
  if (!lhs) {
    for (long p = 0; p < n_points; ++p) {
      long rest = p;
      for (int f = nf - 1; f >= 0; --f) {
        long level = rest % fac[f].levels;
        rest /= fac[f].levels;
        values[p * nf + f] = factor_at(&fac[f], (double)level / (double)(fac[f].levels - 1));
      }
    }
    return POM_OK;
  }
  long *perm = malloc((size_t)n_points * sizeof *perm);
  if (!perm) POM_FAIL(err, POM_ERR_NOMEM, "sweep: out of memory");
  for (int f = 0; f < nf; ++f) {
    pom_rng rng;
    pom_rng_seed(&rng, seed, (uint64_t)f);
    for (long p = 0; p < n_points; ++p)
      perm[p] = p;
    for (long p = n_points - 1; p > 0; --p) { /* Fisher-Yates */
      long j = (long)(pom_rng_uniform(&rng) * (double)(p + 1));
      long t = perm[p];
      perm[p] = perm[j];
      perm[j] = t;
    }
    for (long p = 0; p < n_points; ++p)
      values[p * nf + f] =
          factor_at(&fac[f], ((double)perm[p] + pom_rng_uniform(&rng)) / (double)n_points);
  }
  free(perm);
  return POM_OK;
}

/* Short factor labels: the last part of each dotted key, or the whole key
 * when two factors would share it. */
static void factor_labels(pom_doe_study *study) {
  for (int f = 0; f < study->n_factors; ++f) {
    const char *dot = strrchr(study->factor_key[f], '.');
    snprintf(study->factor_label[f], sizeof study->factor_label[f], "%s",
             dot ? dot + 1 : study->factor_key[f]);
  }
  for (int f = 0; f < study->n_factors; ++f)
    for (int g = 0; g < study->n_factors; ++g)
      if (f != g && strcmp(study->factor_label[f], study->factor_label[g]) == 0) {
        snprintf(study->factor_label[f], sizeof study->factor_label[f], "%s", study->factor_key[f]);
        break;
      }
}

/* "<base> label=value ..." for `label=value` of every factor at `prec`
 * significant digits; 0 when it does not fit the name. */
static int factor_name(char *out, size_t cap, const char *base, const pom_doe_candidate *cand,
                       const pom_doe_study *study, int prec) {
  size_t n = (size_t)snprintf(out, cap, "%s", base);
  for (int f = 0; f < cand->n_factors && n < cap; ++f)
    n += (size_t)snprintf(out + n, cap - n, " %s=%.*g", study->factor_label[f], prec,
                          cand->factor_value[f]);
  return n < cap;
}

/* Names the n sweep points of one base (their name holds the base name) by
 * their factor values, with the fewest significant digits (4 to 12) that
 * tell them apart; "<base>#<j>" when the values do not fit a name. */
static void name_by_factors(pom_doe_candidate *cands, long n, const pom_doe_study *study) {
  char base[POM_DOE_NAME_LEN];
  snprintf(base, sizeof base, "%s", cands[0].name);
  for (int prec = 4; prec <= 12; ++prec) {
    int fits = 1, unique = 1;
    for (long p = 0; p < n && fits; ++p)
      fits = factor_name(cands[p].name, sizeof cands[p].name, base, &cands[p], study, prec);
    for (long p = 0; p < n && fits && unique; ++p)
      for (long q = 0; q < p && unique; ++q)
        unique = strcmp(cands[p].name, cands[q].name) != 0;
    if (!fits) break;
    if (unique) return;
  }
  for (long p = 0; p < n; ++p) {
    size_t len = strlen(base), keep = len < sizeof base - 12 ? len : sizeof base - 12;
    snprintf(cands[p].name, sizeof cands[p].name, "%.*s#%ld", (int)keep, base, p);
  }
}

static pom_status load_sweep(pom_doe_study *study, const study_ctx *sc, pom_error *err) {
  static const char *const kinds[] = {"grid", "lhs", NULL};
  const pom_cfg *cfg = sc->cfg;
  pom_status st = POM_OK;
  double *values = NULL;
  int kind = 0;
  sweep_factor fac[POM_DOE_MAX_FACTORS];
  memset(fac, 0, sizeof fac);
  POM_TRY(pom_cfg_choice(cfg, "candidates.sweep", kinds, &kind, err));
  int nb = pom_cfg_length(cfg, "candidates.base");
  if (nb < 1)
    return pom_cfg_error(cfg, "candidates.base", NULL, err,
                         "expected a list of base candidates ( { name = ...; config = ...; } )");
  int nf = pom_cfg_length(cfg, "candidates.factors");
  if (nf < 1 || nf > POM_DOE_MAX_FACTORS)
    return pom_cfg_error(cfg, "candidates.factors", NULL, err,
                         "expected a list of 1 to %d factors ( { key = ...; min = ...; max = ...; "
                         "} )",
                         POM_DOE_MAX_FACTORS);
  long n_points = 1, lhs_points = 0, seed = (long)study->maneuvers.seed;
  for (int f = 0; f < nf; ++f) {
    char k[128];
    snprintf(k, sizeof k, "candidates.factors.[%d].key", f);
    POM_TRY(pom_cfg_string(cfg, k, fac[f].key, sizeof fac[f].key, err));
    POM_TRY(pom_doe_check_dotted(cfg, k, fac[f].key, err));
    /* one key, one factor: the later one would win in the configs while the
     * tables and the effects carried the first one's values */
    for (int g = 0; g < f; ++g)
      if (strcmp(fac[g].key, fac[f].key) == 0)
        return pom_cfg_error(cfg, k, NULL, err,
                             "the key is already factor candidates.factors.[%d]: a key can be "
                             "one factor only",
                             g);
    /* an absolute draw would replace the factor's value in every maneuver
     * (a relative one scales each candidate's own value: allowed) */
    for (int j = 0; j < study->uncertain.n; ++j)
      if (strcmp(study->uncertain.param[j].key, fac[f].key) == 0 &&
          !study->uncertain.param[j].relative)
        return pom_cfg_error(cfg, k, NULL, err,
                             "the key is also uncertain.[%d] with absolute draws, which would "
                             "replace the factor's values (the candidates would tie): make that "
                             "parameter relative = true or drop one of the two",
                             j);
    snprintf(k, sizeof k, "candidates.factors.[%d].log", f);
    POM_TRY(pom_cfg_bool_opt(cfg, k, 0, &fac[f].log, err));
    snprintf(k, sizeof k, "candidates.factors.[%d].min", f);
    POM_TRY(pom_cfg_real(cfg, k, 1.0, fac[f].log ? 1e-300 : -1e300, 1e300, &fac[f].min, err));
    snprintf(k, sizeof k, "candidates.factors.[%d].max", f);
    POM_TRY(pom_cfg_real(cfg, k, 1.0, fac[f].min, 1e300, &fac[f].max, err));
    snprintf(k, sizeof k, "candidates.factors.[%d].levels", f);
    if (kind == 0) {
      POM_TRY(pom_cfg_int(cfg, k, 2, MAX_LEVELS, &fac[f].levels, err));
      n_points *= fac[f].levels;
      if (n_points * nb > MAX_CANDIDATES)
        return pom_cfg_error(cfg, "candidates.factors", NULL, err,
                             "the grid has more than %d candidates", MAX_CANDIDATES);
    } else if (pom_cfg_has(cfg, k)) {
      return pom_cfg_error(cfg, k, NULL, err, "only for sweep = \"grid\"");
    }
  }
  if (kind == 1) {
    POM_TRY(pom_cfg_int(cfg, "candidates.points", 2, MAX_CANDIDATES / nb, &lhs_points, err));
    POM_TRY(pom_cfg_int_opt(cfg, "candidates.seed", 0, 9007199254740991L, seed, &seed, err));
    n_points = lhs_points;
  } else {
    if (pom_cfg_has(cfg, "candidates.points"))
      return pom_cfg_error(cfg, "candidates.points", NULL, err, "only for sweep = \"lhs\"");
    if (pom_cfg_has(cfg, "candidates.seed"))
      return pom_cfg_error(cfg, "candidates.seed", NULL, err, "only for sweep = \"lhs\"");
  }
  values = malloc((size_t)(n_points * nf) * sizeof *values);
  study->candidates = calloc((size_t)(n_points * nb), sizeof *study->candidates);
  if (!values || !study->candidates)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "sweep: out of memory");
  POM_TRY_GOTO(sweep_points(values, n_points, fac, nf, kind == 1, (uint64_t)seed, err), done);
  study->n_factors = nf;
  for (int f = 0; f < nf; ++f) {
    snprintf(study->factor_key[f], sizeof study->factor_key[f], "%s", fac[f].key);
    study->factor_levels[f] = kind == 0 ? fac[f].levels : 0;
  }
  factor_labels(study);
  for (int b = 0; b < nb; ++b) {
    char bkey[64];
    snprintf(bkey, sizeof bkey, "candidates.base.[%d]", b);
    pom_doe_candidate *first = &study->candidates[study->n_candidates];
    for (long p = 0; p < n_points; ++p) {
      pom_doe_candidate *cand = &first[p];
      POM_TRY_GOTO(candidate_name(cand, cfg, bkey, err), done);
      cand->n_factors = nf;
      for (int f = 0; f < nf; ++f) {
        snprintf(cand->factor_key[f], sizeof cand->factor_key[f], "%s", fac[f].key);
        cand->factor_value[f] = values[p * nf + f];
      }
    }
    name_by_factors(first, n_points, study);
    for (long p = 0; p < n_points; ++p) {
      ++study->n_candidates;
      POM_TRY_GOTO(resolve_candidate(&first[p], sc, bkey, err), done);
    }
  }
done:
  free(values);
  return st;
}

/* ---- the study file ------------------------------------------------------------ */
/* study.fidelity and its keys (docs/results.md section 12). */
static pom_status load_fidelity(pom_doe_study *study, const pom_cfg *cfg, pom_error *err) {
  static const char *const modes[] = {"config", "auto", NULL};
  static const char *const keys[] = {"study.fidelity_accuracy_percent", "study.fidelity_margin",
                                     "study.fidelity_maneuvers", "study.fidelity_seed",
                                     "study.fidelity_reference_rtol"};
  int mode = 0;
  long n = 0, seed = 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "study.fidelity", modes, 0, &mode, err));
  study->fidelity_auto = mode;
  pom_fidelity_opts *o = &study->fidelity;
  pom_fidelity_defaults(o);
  study->fidelity_seed = study->maneuvers.seed + 1;
  if (!mode) {
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
      if (pom_cfg_has(cfg, keys[k]))
        return pom_cfg_error(cfg, keys[k], NULL, err, "only with study.fidelity = \"auto\"");
    return POM_OK;
  }
  POM_TRY(pom_cfg_real_opt(cfg, keys[0], 1e-2, 1e-4, 50.0, o->accuracy, &o->accuracy, err));
  POM_TRY(pom_cfg_real_opt(cfg, keys[1], 1.0, 1.0, 100.0, o->margin, &o->margin, err));
  POM_TRY(pom_cfg_int_opt(cfg, keys[2], 1, POM_FIDELITY_MAX_MANEUVERS, o->n_select, &n, err));
  o->n_select = o->n_validate = (int)n;
  POM_TRY(
      pom_cfg_int_opt(cfg, keys[3], 0, 9007199254740991L, (long)study->fidelity_seed, &seed, err));
  if ((uint64_t)seed == study->maneuvers.seed)
    return pom_cfg_error(cfg, keys[3], NULL, err,
                         "is montecarlo.seed: the selection set must come from a different seed "
                         "than the maneuvers it is validated on");
  study->fidelity_seed = (uint64_t)seed;
  POM_TRY(pom_cfg_real_opt(cfg, keys[4], 1.0, POM_DYN_RTOL_MIN, 1e-6, o->reference_rtol,
                           &o->reference_rtol, err));
  return POM_OK;
}

static pom_status load_study_group(pom_doe_study *study, const pom_cfg *cfg, pom_error *err) {
  static const char *const ranks[] = {"execution_time", "energy", NULL};
  static const char *const times[] = {"auto", "execution_time", "pointing_settling_time", NULL};
  int time_metric = 0;
  char dflt[POM_DOE_PATH_LEN];
  long threads = 0;
  int rank_by = 0;
  snprintf(dflt, sizeof dflt, "results/%s.h5", study->name);
  POM_TRY(pom_cfg_string_opt(cfg, "study.output", dflt, study->output, sizeof study->output, err));
  POM_TRY(pom_cfg_string_opt(cfg, "study.tabular", "", study->tabular, sizeof study->tabular, err));
  POM_TRY(pom_cfg_int_opt(cfg, "study.threads", 0, 1024, 0, &threads, err));
  POM_TRY(pom_cfg_real_opt(cfg, "study.alpha", 1.0, 1e-6, 0.5, 0.05, &study->alpha, err));
  POM_TRY(
      pom_cfg_real_opt(cfg, "study.confidence", 1.0, 0.5, 0.9999, 0.95, &study->confidence, err));
  POM_TRY(pom_cfg_choice_opt(cfg, "study.rank_by", ranks, 0, &rank_by, err));
  study->threads = (int)threads;
  study->rank_by = (pom_doe_rank_by)rank_by;
  POM_TRY(pom_cfg_choice_opt(cfg, "study.time_metric", times, 0, &time_metric, err));
  /* auto: the platform's pointing in orientation space, where the study
   * asks for an orientation; the paper's per-actuator time in joint space */
  study->time_metric = time_metric == 0 ? (study->maneuvers.space == POM_DOE_SPACE_ORIENTATION
                                               ? POM_DOE_TIME_POINTING
                                               : POM_DOE_TIME_EXECUTION)
                                        : (pom_doe_time_metric)(time_metric - 1);
  POM_TRY(pom_doe_capability_load(study, cfg, err));
  return load_fidelity(study, cfg, err);
}

/* Names must be unique: they label tables and results. */
static pom_status check_names(const pom_doe_study *study, const pom_cfg *cfg, pom_error *err) {
  for (int a = 0; a < study->n_candidates; ++a)
    for (int b = 0; b < a; ++b)
      if (strcmp(study->candidates[a].name, study->candidates[b].name) == 0)
        return pom_cfg_error(cfg, "candidates", NULL, err, "candidate name '%s' is used twice",
                             study->candidates[a].name);
  return POM_OK;
}

/* The maneuvers against the candidates' actuator kinds (joint space: one
 * kind, range keys in its unit). */
static pom_status check_kinds(const pom_doe_study *study, const pom_cfg *cfg, pom_error *err) {
  pom_actuator_kind *kinds = malloc((size_t)study->n_candidates * sizeof *kinds);
  if (!kinds) POM_FAIL(err, POM_ERR_NOMEM, "study: out of memory");
  for (int c = 0; c < study->n_candidates; ++c)
    kinds[c] = study->candidates[c].eval.actuator_kind;
  pom_status st =
      pom_doe_maneuvers_check_kinds(&study->maneuvers, kinds, study->n_candidates, cfg, err);
  free(kinds);
  return st;
}

pom_status pom_doe_study_load(pom_doe_study *study, const pom_cfg *cfg,
                              pom_doe_evaluator_factory factory, void *user, pom_error *err) {
  /* a study file holds these and nothing else (mechanism groups belong in the
   * candidates' configs or in study.override); a sensitivity file is a study
   * file with one more group (pomlab sensitivity reads it) */
  const char *const *scopes = pom_doe_study_groups();
  pom_cfg_groups known_top;
  pom_status st = POM_OK;
  config_t tree;
  config_init(&tree);
  memset(study, 0, sizeof *study);
  pom_cfg_groups_init(&known_top);
  POM_TRY_GOTO(pom_cfg_groups_add(&known_top, scopes, err), fail);
  POM_TRY_GOTO(pom_cfg_groups_add(&known_top, pom_doe_sens_groups(), err), fail);
  study_ctx sc;
  memset(&sc, 0, sizeof sc);
  sc.cfg = cfg;
  sc.tree = &tree;
  sc.factory = factory;
  sc.user = user;
  dir_of(sc.dir, sizeof sc.dir, pom_cfg_path(cfg));
  snprintf(study->source, sizeof study->source, "%s", pom_cfg_path(cfg));
  study->config_text = dup_text(pom_cfg_text(cfg));
  if (!study->config_text) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "study: out of memory");
  POM_TRY_GOTO(pom_doe_tree_read_string(&tree, pom_cfg_text(cfg), pom_cfg_path(cfg),
                                        sc.dir[0] ? sc.dir : ".", err),
               fail);

  char stem[POM_DOE_NAME_LEN];
  stem_of(stem, sizeof stem, pom_cfg_path(cfg));
  POM_TRY_GOTO(pom_cfg_string_opt(cfg, "name", stem, study->name, sizeof study->name, err), fail);
  for (char *p = study->name; *p; ++p)
    if (*p == '/' || *p == ' ') *p = '_';
  POM_TRY_GOTO(pom_doe_maneuvers_load(&study->maneuvers, cfg, err), fail);
  POM_TRY_GOTO(load_study_group(study, cfg, err), fail);
  POM_TRY_GOTO(pom_unc_load(&study->uncertain, cfg, study->maneuvers.seed, err), fail);
  if (pom_cfg_has(cfg, "study.override")) pom_cfg_mark_used(cfg, "study.override");

  if (!pom_cfg_has(cfg, "candidates"))
    POM_FAIL_GOTO(err, POM_ERR_CONFIG, fail,
                  "%s: key 'candidates': missing: expected a list of candidates or a sweep group "
                  "(docs/results.md)",
                  pom_cfg_path(cfg));
  if (pom_cfg_has(cfg, "candidates.sweep")) {
    POM_TRY_GOTO(load_sweep(study, &sc, err), fail);
  } else {
    const config_setting_t *list = config_lookup(&tree, "candidates");
    int n = pom_cfg_length(cfg, "candidates");
    if (!config_setting_is_list(list) || n < 1 || n > MAX_CANDIDATES) {
      st = pom_cfg_error(cfg, "candidates", NULL, err,
                         "expected a list of 1 to %d groups ( { name = ...; config = ...; } ) or a "
                         "sweep group",
                         MAX_CANDIDATES);
      goto fail;
    }
    study->candidates = calloc((size_t)n, sizeof *study->candidates);
    if (!study->candidates) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "study: out of memory");
    for (int c = 0; c < n; ++c) {
      char key[64];
      snprintf(key, sizeof key, "candidates.[%d]", c);
      pom_doe_candidate *cand = &study->candidates[c];
      POM_TRY_GOTO(candidate_name(cand, cfg, key, err), fail);
      ++study->n_candidates;
    }
    POM_TRY_GOTO(check_names(study, cfg, err), fail);
    /* unknown keys before any expensive model building */
    for (int c = 0; c < n; ++c) {
      char key[64];
      snprintf(key, sizeof key, "candidates.[%d].config", c);
      pom_cfg_mark_used(cfg, key);
      snprintf(key, sizeof key, "candidates.[%d].override", c);
      if (pom_cfg_has(cfg, key)) pom_cfg_mark_used(cfg, key);
    }
    POM_TRY_GOTO(pom_cfg_check_unknown(cfg, scopes, known_top.name, err), fail);
    for (int c = 0; c < n; ++c) {
      char key[64];
      snprintf(key, sizeof key, "candidates.[%d]", c);
      POM_TRY_GOTO(resolve_candidate(&study->candidates[c], &sc, key, err), fail);
    }
  }
  POM_TRY_GOTO(check_names(study, cfg, err), fail);
  POM_TRY_GOTO(pom_cfg_check_unknown(cfg, scopes, known_top.name, err), fail);
  for (int c = 0; c < study->n_candidates; ++c)
    if (study->maneuvers.space == POM_DOE_SPACE_ORIENTATION && !study->candidates[c].eval.targets)
      POM_FAIL_GOTO(err, POM_ERR_CONFIG, fail,
                    "%s: montecarlo.space = \"orientation\" but candidate '%s' cannot map "
                    "orientations to actuator targets",
                    pom_cfg_path(cfg), study->candidates[c].name);
  POM_TRY_GOTO(check_kinds(study, cfg, err), fail);
  POM_TRY_GOTO(pom_doe_uncertain_prepare(study, cfg, err), fail);
  config_destroy(&tree);
  return POM_OK;
fail:
  config_destroy(&tree);
  pom_doe_study_clear(study);
  return st;
}

pom_status pom_doe_study_single(pom_doe_study *study, const pom_cfg *cfg,
                                pom_doe_evaluator_factory factory, void *user, pom_error *err) {
  const char *const *scopes = pom_doe_montecarlo_groups();
  pom_status st = POM_OK;
  config_t tree;
  config_init(&tree);
  memset(study, 0, sizeof *study);
  snprintf(study->source, sizeof study->source, "%s", pom_cfg_path(cfg));
  study->config_text = dup_text(pom_cfg_text(cfg));
  study->candidates = calloc(1, sizeof *study->candidates);
  if (!study->config_text || !study->candidates)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "montecarlo: out of memory");
  study->n_candidates = 1;
  char stem[POM_DOE_NAME_LEN];
  stem_of(stem, sizeof stem, pom_cfg_path(cfg));
  snprintf(study->name, sizeof study->name, "%s", stem);
  snprintf(study->output, sizeof study->output, "results/%s-montecarlo.h5", stem);
  study->alpha = 0.05;
  study->confidence = 0.95;
  pom_doe_candidate *cand = &study->candidates[0];
  POM_TRY_GOTO(pom_cfg_string_opt(cfg, "name", stem, cand->name, sizeof cand->name, err), fail);
  snprintf(cand->source, sizeof cand->source, "%s", pom_cfg_path(cfg));
  POM_TRY_GOTO(pom_doe_maneuvers_load(&study->maneuvers, cfg, err), fail);
  study->time_metric = study->maneuvers.space == POM_DOE_SPACE_ORIENTATION ? POM_DOE_TIME_POINTING
                                                                           : POM_DOE_TIME_EXECUTION;
  POM_TRY_GOTO(pom_cfg_check_unknown(cfg, scopes, NULL, err), fail);
  char dir[POM_DOE_PATH_LEN];
  dir_of(dir, sizeof dir, pom_cfg_path(cfg));
  POM_TRY_GOTO(pom_doe_tree_read_string(&tree, pom_cfg_text(cfg), pom_cfg_path(cfg),
                                        dir[0] ? dir : ".", err),
               fail);
  POM_TRY_GOTO(pom_doe_tree_write(&tree, &cand->resolved, err), fail);
  POM_TRY_GOTO(factory(&cand->eval, cfg, user, err), fail);
  if (study->maneuvers.space == POM_DOE_SPACE_ORIENTATION && !cand->eval.targets)
    POM_FAIL_GOTO(err, POM_ERR_CONFIG, fail,
                  "%s: montecarlo.space = \"orientation\" needs an evaluator with inverse "
                  "kinematics",
                  pom_cfg_path(cfg));
  POM_TRY_GOTO(check_kinds(study, cfg, err), fail);
  config_destroy(&tree);
  return POM_OK;
fail:
  config_destroy(&tree);
  pom_doe_study_clear(study);
  return st;
}
