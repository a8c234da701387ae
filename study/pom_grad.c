/* pom_grad.c - design gradients from a config (pom_grad.h, docs/optimize.md
 * "Design gradients"): the nominal and perturbed models built as a study
 * builds a candidate, then pom_dyn_simulate_sens per maneuver, and the
 * Monte-Carlo means with their gradients. */
#include "pom_grad.h"
#include "pom_math.h"
#include "study_internal.h"
#include "pom_json.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct pom_grad {
  char *text;                  /* the config with its includes resolved (libconfig text) */
  char name[POM_DOE_PATH_LEN]; /* the config's path, for messages */
  int n_keys;
  char key[POM_GRAD_MAX_PARAMS][POM_GRAD_KEY_LEN];
  double value[POM_GRAD_MAX_PARAMS]; /* current design (config units), per key */
  /* the parameters: directions in the keys' space (docs/optimize.md 12.1) */
  int n;                                                /* parameters */
  int identity;                                         /* 1: parameter j is key j */
  double dir[POM_GRAD_MAX_PARAMS][POM_GRAD_MAX_PARAMS]; /* [j][m]: d key_m / d a_j */
  double step[POM_GRAD_MAX_PARAMS];  /* h_j (units of a_j); 0 for a zero direction */
  double scale[POM_GRAD_MAX_PARAMS]; /* pbar_j = h_j / rel_step (units of a_j) */
  pom_grad_options opt;
  pom_doe_maneuvers mv;
  pom_unc unc;
  double unc_nominal[POM_UNC_MAX]; /* the config's value of each uncertain key (NaN: absent) */
  pom_doe_evaluator nom, plus[POM_GRAD_MAX_PARAMS], minus[POM_GRAD_MAX_PARAMS];
  int built;
  pom_dyn_data *d; /* data of the current nominal model */
};

/* ---- metric table ------------------------------------------------------------------- */
/* Each metric's name, its value in pom_dyn_metrics and its gradient in
 * pom_dyn_grad (element k of an array member). */
#define METRIC(name, member, k)                                                                    \
  {                                                                                                \
    name, offsetof(pom_dyn_metrics, member) + (k) * sizeof(double),                                \
        offsetof(pom_dyn_grad, member) + (k) * sizeof(pom_dyn_dmetric)                             \
  }

static const struct {
  const char *name;
  size_t value; /* byte offset of the double in pom_dyn_metrics */
  size_t grad;  /* byte offset of the pom_dyn_dmetric in pom_dyn_grad */
} metric_at[POM_GRAD_N_METRICS] = {
    METRIC("energy_total", energy_total, 0),
    METRIC("energy_1", energy, 0),
    METRIC("energy_2", energy, 1),
    METRIC("energy_3", energy, 2),
    METRIC("tracking_rms_error", tracking_rms_error, 0),
    METRIC("final_pointing_error", final_pointing_error, 0),
    METRIC("settling_time_1", settling_time, 0),
    METRIC("settling_time_2", settling_time, 1),
    METRIC("settling_time_3", settling_time, 2),
    METRIC("execution_time", execution_time, 0),
    METRIC("pointing_settling_time", pointing_settling_time, 0),
    METRIC("peak_current", peak_current, 0),
};

const char *pom_grad_metric_name(pom_grad_metric k) {
  return (unsigned)k < POM_GRAD_N_METRICS ? metric_at[k].name : "?";
}

double pom_grad_metric_value(const pom_dyn_metrics *mt, pom_grad_metric k) {
  if ((unsigned)k >= POM_GRAD_N_METRICS) return NAN;
  double v;
  memcpy(&v, (const char *)mt + metric_at[k].value, sizeof v);
  return v;
}

static pom_dyn_dmetric *grad_of(pom_dyn_grad *g, pom_grad_metric k) {
  if ((unsigned)k >= POM_GRAD_N_METRICS) k = POM_GRAD_POINTING_SETTLING_TIME;
  return (pom_dyn_dmetric *)(void *)((char *)g + metric_at[k].grad);
}

const pom_dyn_dmetric *pom_grad_metric_grad(const pom_dyn_grad *g, pom_grad_metric k) {
  return grad_of((pom_dyn_grad *)g, k);
}

void pom_grad_options_defaults(pom_grad_options *o) {
  memset(o, 0, sizeof *o);
  o->rel_step = 3e-6;
  for (int j = 0; j < POM_GRAD_MAX_PARAMS; ++j)
    o->abs_floor[j] = 1.0;
  o->method = POM_DYN_SENS_STAGGERED;
  o->error_control = 1;
  o->peak_current = 1;
  o->sens_noise_margin = POM_DYN_SENS_MARGIN_DEFAULT;
  o->quantile = 0.95;
  o->quantile_bandwidth = 1e-3;
}

void pom_grad_mc_options_defaults(pom_grad_mc_options *o) {
  memset(o, 0, sizeof *o);
}

/* ---- config trees -------------------------------------------------------------------- */
/* Splits "a.b[2]" into the path "a.b" and the index 2 (-1 when none). */
static int split_index(const char *key, char *path, size_t cap, long *index) {
  size_t n = strlen(key);
  *index = -1;
  if (n >= cap) return 0;
  memcpy(path, key, n + 1);
  if (n > 2 && path[n - 1] == ']') {
    char *lb = strrchr(path, '[');
    if (!lb) return 0;
    char *end = NULL;
    long i = strtol(lb + 1, &end, 10);
    if (end != path + n - 1 || i < 0) return 0;
    *lb = '\0';
    *index = i;
  }
  return 1;
}

/* The numeric setting of key in tree (an array element for "key[i]"), or NULL. */
static config_setting_t *lookup_number(config_t *tree, const char *key) {
  char path[POM_GRAD_KEY_LEN];
  long idx;
  if (!split_index(key, path, sizeof path, &idx)) return NULL;
  config_setting_t *s = config_lookup(tree, path);
  if (!s) return NULL;
  if (idx >= 0) {
    if (!config_setting_is_array(s) && !config_setting_is_list(s)) return NULL;
    s = config_setting_get_elem(s, (unsigned)idx);
    if (!s) return NULL;
  }
  int t = config_setting_type(s);
  return (t == CONFIG_TYPE_FLOAT || t == CONFIG_TYPE_INT || t == CONFIG_TYPE_INT64) ? s : NULL;
}

/* Sets key (present, numeric) to value as a real: an integer setting
 * outside an array is replaced by a real one; an integer array element
 * takes only integral values (libconfig arrays hold one type). */
static pom_status set_number(config_t *tree, const char *key, double value, pom_error *err) {
  config_setting_t *s = lookup_number(tree, key);
  if (!s) POM_FAIL(err, POM_ERR_CONFIG, "key '%s' is not a number in the config", key);
  if (config_setting_type(s) == CONFIG_TYPE_FLOAT) {
    config_setting_set_float(s, value);
    return POM_OK;
  }
  config_setting_t *parent = config_setting_parent(s);
  if (parent && config_setting_is_group(parent)) {
    char name[POM_GRAD_KEY_LEN];
    snprintf(name, sizeof name, "%s", config_setting_name(s));
    config_setting_remove(parent, name);
    s = config_setting_add(parent, name, CONFIG_TYPE_FLOAT);
    if (!s) POM_FAIL(err, POM_ERR_CONFIG, "key '%s': cannot be set to a real", key);
    config_setting_set_float(s, value);
    return POM_OK;
  }
  return pom_doe_tree_set_number(tree, key, value, err);
}

/* The config of the design values[] with the uncertain draws x (NULL: none;
 * controller_only: only those the controller's model takes). */
static pom_status variant(pom_cfg **out, const pom_grad *g, const double *values, const double *x,
                          int controller_only, pom_error *err) {
  pom_status st = POM_OK;
  char *text = NULL;
  config_t tree;
  config_init(&tree);
  *out = NULL;
  POM_TRY_GOTO(pom_doe_tree_read_string(&tree, g->text, g->name, NULL, err), done);
  if (g->opt.rigid_joints) {
    config_setting_t *root = config_root_setting(&tree);
    config_setting_t *jg = config_setting_get_member(root, "joints");
    if (!jg) jg = config_setting_add(root, "joints", CONFIG_TYPE_GROUP);
    config_setting_t *m = jg ? config_setting_get_member(jg, "model") : NULL;
    if (jg && !m) m = config_setting_add(jg, "model", CONFIG_TYPE_STRING);
    if (!m || config_setting_type(m) != CONFIG_TYPE_STRING ||
        config_setting_set_string(m, "rigid") != CONFIG_TRUE)
      POM_FAIL_GOTO(err, POM_ERR_CONFIG, done, "%s: joints.model cannot be set to \"rigid\"",
                    g->name);
  }
  if (g->opt.solver_rtol > 0.0)
    POM_TRY_GOTO(pom_doe_tree_set_number(&tree, "solver.rtol", g->opt.solver_rtol, err), done);
  for (int j = 0; j < g->n_keys; ++j)
    POM_TRY_GOTO(set_number(&tree, g->key[j], values[j], err), done);
  for (int u = 0; x && u < g->unc.n; ++u) {
    const pom_unc_param *p = &g->unc.param[u];
    if (controller_only && !p->controller_drawn) continue;
    double nominal = g->unc_nominal[u];
    for (int j = 0; j < g->n_keys; ++j)
      if (strcmp(g->key[j], p->key) == 0) nominal = values[j]; /* the design moves it */
    POM_TRY_GOTO(pom_doe_tree_set_number(&tree, p->key, p->relative ? nominal * x[u] : x[u], err),
                 done);
  }
  POM_TRY_GOTO(pom_doe_tree_write(&tree, &text, err), done);
  POM_TRY_GOTO(pom_cfg_load_string(out, text, g->name, err), done);
done:
  free(text);
  config_destroy(&tree);
  return st;
}

/* The evaluator (architecture, mechanism, parameters, model) of one design. */
static pom_status evaluator(pom_doe_evaluator *ev, const pom_grad *g, const double *values,
                            const double *x, pom_error *err) {
  pom_cfg *cfg = NULL, *ctrl = NULL;
  pom_status st = variant(&cfg, g, values, x, 0, err);
  if (st == POM_OK && x && g->unc.n > 0) st = variant(&ctrl, g, values, x, 1, err);
  if (st == POM_OK) st = pom_doe_dyn_evaluator_create_ex(ev, cfg, ctrl, err);
  pom_cfg_destroy(cfg);
  pom_cfg_destroy(ctrl);
  return st;
}

static const pom_doe_dyn_base *base(const pom_doe_evaluator *ev) {
  return ev->ctx;
}

typedef struct {
  pom_doe_evaluator nom, plus[POM_GRAD_MAX_PARAMS], minus[POM_GRAD_MAX_PARAMS];
} model_set;

static void set_clear(model_set *s, int n) {
  pom_doe_evaluator_clear(&s->nom);
  for (int j = 0; j < n; ++j) {
    pom_doe_evaluator_clear(&s->plus[j]);
    pom_doe_evaluator_clear(&s->minus[j]);
  }
}

static model_set current(const pom_grad *g) {
  model_set s;
  s.nom = g->nom;
  memcpy(s.plus, g->plus, sizeof s.plus);
  memcpy(s.minus, g->minus, sizeof s.minus);
  return s;
}

/* g's models and data, freed (when built). */
static void clear_built(pom_grad *g) {
  if (!g->built) return;
  pom_dyn_data_destroy(g->d);
  model_set s = current(g);
  set_clear(&s, g->n);
  g->built = 0;
}

/* The keys' values of the design values[] moved by t along parameter j's
 * direction: v = values + t dir_j (only the keys the direction moves, so
 * that the others keep their bits). */
static void along(const pom_grad *g, const double *values, int j, double t, double *v) {
  memcpy(v, values, (size_t)g->n_keys * sizeof *v);
  for (int m = 0; m < g->n_keys; ++m)
    if (g->dir[j][m] != 0.0) v[m] = values[m] + t * g->dir[j][m];
}

/* Parameter j's name in messages: its key, or the keys of its direction. */
static void param_name(const pom_grad *g, int j, char *out, size_t cap) {
  size_t n = 0;
  out[0] = '\0';
  if (g->identity) {
    snprintf(out, cap, "%s", g->key[j]);
    return;
  }
  n += (size_t)snprintf(out, cap, "direction %d (", j + 1);
  int first = 1;
  for (int m = 0; m < g->n_keys && n < cap; ++m)
    if (g->dir[j][m] != 0.0) {
      n += (size_t)snprintf(out + n, cap - n, "%s%.6g %s", first ? "" : " + ", g->dir[j][m],
                            g->key[m]);
      first = 0;
    }
  if (n < cap) snprintf(out + n, cap - n, ")");
}

/* Every model of the design values[] (steps step[] along the parameters'
 * directions) with draws x; a zero direction (step 0) has none. A failure
 * names the parameter whose perturbed design failed. */
static pom_status build_set(model_set *s, const pom_grad *g, const double *values,
                            const double *step, const double *x, pom_error *err) {
  memset(s, 0, sizeof *s);
  pom_status st = evaluator(&s->nom, g, values, x, err);
  if (st != POM_OK) return st;
  const pom_joint_model joints = base(&s->nom)->params.joints.model;
  if (joints != POM_JOINTS_RIGID) {
    set_clear(s, 0);
    POM_FAIL(err, POM_ERR_ARG,
             "%s: design gradients need joints.model = \"rigid\" (the exact formulation); the "
             "config has \"%s\"",
             g->name, pom_dyn_joint_model_name(joints));
  }
  double v[POM_GRAD_MAX_PARAMS];
  for (int j = 0; j < g->n; ++j) {
    if (step[j] == 0.0) continue; /* a zero direction: derivative 0, no model */
    for (int side = 0; side < 2; ++side) {
      along(g, values, j, side ? -step[j] : step[j], v);
      pom_error e;
      pom_error_clear(&e);
      st = evaluator(side ? &s->minus[j] : &s->plus[j], g, v, x, &e);
      if (st != POM_OK) {
        set_clear(s, g->n);
        if (g->identity)
          return pom_error_set(err, st, __FILE__, __LINE__,
                               "%s: %s = %.10g (the design %s its step): %s", g->name, g->key[j],
                               v[j], side ? "minus" : "plus", e.message);
        char name[256];
        param_name(g, j, name, sizeof name);
        return pom_error_set(err, st, __FILE__, __LINE__,
                             "%s: %s moved by %+.10g (the design %s its step): %s", g->name, name,
                             side ? -step[j] : step[j], side ? "minus" : "plus", e.message);
      }
    }
  }
  return POM_OK;
}

/* The step h_j and scale pbar_j of every parameter (docs/optimize.md 12.1):
 * pbar_j = min over the keys m it moves of r_m / |c_jm| (r_m = |value_m|,
 * or abs_floor_m at 0), the move of a_j that changes some key by its own
 * magnitude, and h_j = rel_step pbar_j, so that no key moves by more than
 * rel_step of itself. A single key (c = 1): h = rel_step |value|, pbar =
 * |value|. A zero direction: both 0. */
static void steps_of(const pom_grad *g, const double *values, double *step, double *scale) {
  for (int j = 0; j < g->n; ++j) {
    double pbar = INFINITY;
    for (int m = 0; m < g->n_keys; ++m) {
      double c = fabs(g->dir[j][m]);
      if (c == 0.0) continue;
      double r = values[m] != 0.0 ? fabs(values[m]) : g->opt.abs_floor[m];
      pbar = fmin(pbar, r / c);
    }
    if (!isfinite(pbar)) pbar = 0.0;
    scale[j] = pbar;
    step[j] = g->opt.rel_step * pbar;
  }
}

/* Moves the built models of s into g (freeing g's). */
static pom_status adopt(pom_grad *g, model_set *s, pom_error *err) {
  pom_dyn_data *d = NULL;
  pom_status st = pom_dyn_data_create(&d, base(&s->nom)->model, err);
  if (st != POM_OK) {
    set_clear(s, g->n);
    return st;
  }
  clear_built(g);
  g->nom = s->nom;
  memcpy(g->plus, s->plus, sizeof g->plus);
  memcpy(g->minus, s->minus, sizeof g->minus);
  g->d = d;
  g->built = 1;
  return POM_OK;
}

/* ---- create ------------------------------------------------------------------------------ */
pom_status pom_grad_create(pom_grad **out, const pom_cfg *cfg, const char *const *keys, int n,
                           const pom_grad_options *o, pom_error *err) {
  return pom_grad_create_dirs(out, cfg, keys, n, NULL, n, o, err);
}

/* Copies the directions (NULL: the identity) into g; POM_ERR_ARG for a
 * non-finite coefficient. */
static pom_status set_dirs(pom_grad *g, const double *dirs, pom_error *err) {
  g->identity = dirs == NULL;
  for (int j = 0; j < g->n; ++j)
    for (int m = 0; m < g->n_keys; ++m) {
      double c = dirs ? dirs[j * g->n_keys + m] : (j == m ? 1.0 : 0.0);
      if (!isfinite(c))
        POM_FAIL(err, POM_ERR_ARG, "%s: direction %d has a non-finite coefficient for '%s'",
                 g->name, j + 1, g->key[m]);
      g->dir[j][m] = c;
    }
  return POM_OK;
}

pom_status pom_grad_create_dirs(pom_grad **out, const pom_cfg *cfg, const char *const *keys,
                                int n_keys, const double *dirs, int n_params,
                                const pom_grad_options *o, pom_error *err) {
  if (!out || !cfg || !keys) POM_FAIL(err, POM_ERR_ARG, "pom_grad_create: NULL argument");
  *out = NULL;
  const int n = n_keys;
  if (n < 1 || n > POM_GRAD_MAX_PARAMS)
    POM_FAIL(err, POM_ERR_ARG, "%s: %d design keys (1 to %d)", pom_cfg_path(cfg), n,
             POM_GRAD_MAX_PARAMS);
  if (n_params < 1 || n_params > POM_GRAD_MAX_PARAMS || (!dirs && n_params != n_keys))
    POM_FAIL(err, POM_ERR_ARG,
             "%s: %d parameters over %d keys (1 to %d; as many as keys without "
             "directions)",
             pom_cfg_path(cfg), n_params, n_keys, POM_GRAD_MAX_PARAMS);
  pom_status st = POM_OK;
  config_t tree;
  config_init(&tree);
  pom_grad *g = calloc(1, sizeof *g);
  if (!g) POM_FAIL(err, POM_ERR_NOMEM, "pom_grad_create: out of memory");
  if (o)
    g->opt = *o;
  else
    pom_grad_options_defaults(&g->opt);
  if (!(g->opt.rel_step > 0.0 && g->opt.rel_step < 0.1))
    POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "design gradients: rel_step %g outside (0, 0.1)",
                  g->opt.rel_step);
  /* the sensitivities' accuracy: the config's key (a file's or a command
   * line's value, one check) replaces the options' */
  POM_TRY_GOTO(pom_cfg_real_opt(cfg, POM_GRAD_KEY_NOISE_MARGIN, 1.0, POM_DYN_SENS_MARGIN_MIN,
                                POM_DYN_SENS_MARGIN_MAX, g->opt.sens_noise_margin,
                                &g->opt.sens_noise_margin, err),
               fail);
  /* the sensitivities in the error test or not (a file's or a command
   * line's value, one check) */
  {
    static const char *const onoff[] = {"off", "on", NULL};
    int on = g->opt.error_control ? 1 : 0;
    POM_TRY_GOTO(pom_cfg_choice_opt(cfg, POM_GRAD_KEY_ERROR_TEST, onoff, on, &on, err), fail);
    g->opt.error_control = on;
  }
  /* the smooth quantile of the times (a file's or a command line's value,
   * the same check) */
  POM_TRY_GOTO(pom_cfg_real_opt(cfg, POM_GRAD_KEY_QUANTILE, 1.0, POM_GRAD_QUANTILE_MIN,
                                POM_GRAD_QUANTILE_MAX, g->opt.quantile, &g->opt.quantile, err),
               fail);
  POM_TRY_GOTO(pom_cfg_real_opt(cfg, POM_GRAD_KEY_BANDWIDTH, 1e-3, POM_GRAD_BANDWIDTH_MIN_MS,
                                POM_GRAD_BANDWIDTH_MAX_MS, g->opt.quantile_bandwidth,
                                &g->opt.quantile_bandwidth, err),
               fail);
  /* a misspelt key of the group is an error, as in any group a command reads */
  POM_TRY_GOTO(pom_cfg_check_unknown(cfg, pom_grad_groups(), NULL, err), fail);
  if (!(g->opt.quantile >= POM_GRAD_QUANTILE_MIN && g->opt.quantile <= POM_GRAD_QUANTILE_MAX &&
        g->opt.quantile_bandwidth >= 1e-3 * POM_GRAD_BANDWIDTH_MIN_MS &&
        g->opt.quantile_bandwidth <= 1e-3 * POM_GRAD_BANDWIDTH_MAX_MS))
    POM_FAIL_GOTO(err, POM_ERR_ARG, fail,
                  "design gradients: quantile %g outside [%g, %g] or bandwidth %g ms outside "
                  "[%g, %g]",
                  g->opt.quantile, POM_GRAD_QUANTILE_MIN, POM_GRAD_QUANTILE_MAX,
                  1e3 * g->opt.quantile_bandwidth, POM_GRAD_BANDWIDTH_MIN_MS,
                  POM_GRAD_BANDWIDTH_MAX_MS);
  if (!(g->opt.sens_noise_margin >= POM_DYN_SENS_MARGIN_MIN &&
        g->opt.sens_noise_margin <= POM_DYN_SENS_MARGIN_MAX))
    POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "design gradients: sens_noise_margin %g outside [%g, %g]",
                  g->opt.sens_noise_margin, POM_DYN_SENS_MARGIN_MIN, POM_DYN_SENS_MARGIN_MAX);
  snprintf(g->name, sizeof g->name, "%s", pom_cfg_path(cfg));
  char dir[POM_DOE_PATH_LEN];
  snprintf(dir, sizeof dir, "%s", g->name);
  char *slash = strrchr(dir, '/');
  if (slash)
    *slash = '\0';
  else
    snprintf(dir, sizeof dir, ".");
  POM_TRY_GOTO(pom_doe_tree_read_string(&tree, pom_cfg_text(cfg), g->name, dir, err), fail);
  g->n_keys = n;
  g->n = n_params;
  for (int j = 0; j < n; ++j) {
    if (!keys[j] || strlen(keys[j]) >= POM_GRAD_KEY_LEN)
      POM_FAIL_GOTO(err, POM_ERR_CONFIG, fail, "%s: design key %d is missing or too long", g->name,
                    j + 1);
    snprintf(g->key[j], sizeof g->key[j], "%s", keys[j]);
    for (int i = 0; i < j; ++i)
      if (strcmp(g->key[i], g->key[j]) == 0)
        POM_FAIL_GOTO(err, POM_ERR_CONFIG, fail, "%s: design key '%s' given twice", g->name,
                      keys[j]);
    config_setting_t *s = lookup_number(&tree, keys[j]);
    if (!s)
      POM_FAIL_GOTO(err, POM_ERR_CONFIG, fail,
                    "%s: design key '%s' is not a number in the config (give its value there)",
                    g->name, keys[j]);
    g->value[j] = config_setting_type(s) == CONFIG_TYPE_FLOAT ? config_setting_get_float(s)
                                                              : (double)config_setting_get_int64(s);
  }
  POM_TRY_GOTO(pom_doe_tree_write(&tree, &g->text, err), fail);
  POM_TRY_GOTO(pom_doe_maneuvers_load(&g->mv, cfg, err), fail);
  POM_TRY_GOTO(pom_unc_load(&g->unc, cfg, g->mv.seed, err), fail);
  for (int u = 0; u < g->unc.n; ++u) {
    config_setting_t *s = lookup_number(&tree, g->unc.param[u].key);
    g->unc_nominal[u] = !s ? NAN
                        : config_setting_type(s) == CONFIG_TYPE_FLOAT
                            ? config_setting_get_float(s)
                            : (double)config_setting_get_int64(s);
    if (g->unc.param[u].relative && !isfinite(g->unc_nominal[u]))
      POM_FAIL_GOTO(err, POM_ERR_CONFIG, fail,
                    "%s: uncertain key '%s' is relative but has no value in the config", g->name,
                    g->unc.param[u].key);
  }
  POM_TRY_GOTO(set_dirs(g, dirs, err), fail);
  POM_TRY_GOTO(pom_grad_set_values(g, g->value, err), fail);
  config_destroy(&tree);
  *out = g;
  return POM_OK;
fail:
  config_destroy(&tree);
  pom_grad_destroy(g);
  return st;
}

void pom_grad_destroy(pom_grad *g) {
  if (!g) return;
  clear_built(g);
  free(g->text);
  free(g);
}

void pom_grad_watch_peak_current(pom_grad *g, int on) {
  g->opt.peak_current = on != 0;
}

int pom_grad_n_params(const pom_grad *g) {
  return g->n;
}
int pom_grad_n_keys(const pom_grad *g) {
  return g->n_keys;
}
const char *pom_grad_key(const pom_grad *g, int j) {
  return j >= 0 && j < g->n_keys ? g->key[j] : NULL;
}
double pom_grad_value(const pom_grad *g, int j) {
  return j >= 0 && j < g->n_keys ? g->value[j] : NAN;
}
double pom_grad_step(const pom_grad *g, int j) {
  return j >= 0 && j < g->n ? g->step[j] : NAN;
}
double pom_grad_scale(const pom_grad *g, int j) {
  return j >= 0 && j < g->n ? g->scale[j] : NAN;
}
double pom_grad_dir(const pom_grad *g, int j, int m) {
  return j >= 0 && j < g->n && m >= 0 && m < g->n_keys ? g->dir[j][m] : NAN;
}
const pom_kin_arch *pom_grad_arch(const pom_grad *g) {
  return &base(&g->nom)->arch;
}
const pom_dyn_params *pom_grad_params(const pom_grad *g) {
  return &base(&g->nom)->params;
}
const pom_dyn_model *pom_grad_model(const pom_grad *g) {
  return base(&g->nom)->model;
}

pom_status pom_grad_set_values(pom_grad *g, const double *values, pom_error *err) {
  return pom_grad_set_point(g, values, NULL, err);
}

pom_status pom_grad_set_point(pom_grad *g, const double *values, const double *dirs,
                              pom_error *err) {
  double step[POM_GRAD_MAX_PARAMS], scale[POM_GRAD_MAX_PARAMS];
  for (int j = 0; j < g->n_keys; ++j)
    if (!isfinite(values[j]))
      POM_FAIL(err, POM_ERR_ARG, "%s: %s = %g is not finite", g->name, g->key[j], values[j]);
  double keep[POM_GRAD_MAX_PARAMS][POM_GRAD_MAX_PARAMS];
  const int keep_identity = g->identity;
  memcpy(keep, g->dir, sizeof keep);
  pom_status st = dirs ? set_dirs(g, dirs, err) : POM_OK;
  model_set s;
  if (st == POM_OK) {
    steps_of(g, values, step, scale);
    st = build_set(&s, g, values, step, NULL, err);
  }
  if (st == POM_OK) st = adopt(g, &s, err);
  if (st != POM_OK) {
    /* the previous design and directions stay */
    memcpy(g->dir, keep, sizeof keep);
    g->identity = keep_identity;
    return st;
  }
  memmove(g->value, values, (size_t)g->n_keys * sizeof *values);
  memcpy(g->step, step, sizeof step);
  memcpy(g->scale, scale, sizeof scale);
  return POM_OK;
}

/* ---- one maneuver ------------------------------------------------------------------------ */
static void all_undefined(pom_dyn_grad *gr, int n) {
  memset(gr, 0, sizeof *gr);
  gr->n_params = n;
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    pom_dyn_dmetric *d = grad_of(gr, (pom_grad_metric)k);
    d->defined = 0;
    d->why = POM_DYN_GRAD_UNKNOWN;
    for (int j = 0; j < n; ++j)
      d->d[j] = NAN;
  }
}

static void refused(pom_dyn_metrics *mt, pom_status st, const pom_error *e) {
  memset(mt, 0, sizeof *mt);
  mt->status = st;
  snprintf(mt->reason, sizeof mt->reason, "%s", e->message);
  mt->energy_total = mt->execution_time = mt->final_pointing_error = NAN;
  mt->tracking_rms_error = mt->pointing_settling_time = mt->peak_current = NAN;
  for (int a = 0; a < 3; ++a)
    mt->settling_time[a] = mt->energy[a] = NAN;
}

/* The engine's gradients of the np parameters par[] spread over the n of
 * g: a zero direction's derivative is 0 where the metric's is defined (with
 * no engine parameter at all, where the metric itself is finite). */
static void expand(pom_dyn_grad *gr, const pom_dyn_metrics *mt, pom_status st, const int *par,
                   int np, int n) {
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    pom_dyn_dmetric *dm = grad_of(gr, (pom_grad_metric)k);
    if (np == 0) {
      int fin = st == POM_OK && mt->status == POM_OK &&
                isfinite(pom_grad_metric_value(mt, (pom_grad_metric)k));
      dm->defined = fin;
      dm->why = fin ? POM_DYN_GRAD_OK : POM_DYN_GRAD_UNKNOWN;
    }
    double dd[POM_GRAD_MAX_PARAMS];
    for (int j = 0; j < n; ++j)
      dd[j] = dm->defined ? 0.0 : NAN;
    for (int i = 0; i < np; ++i)
      dd[par[i]] = dm->d[i];
    memcpy(dm->d, dd, (size_t)n * sizeof *dd);
  }
  gr->n_params = n;
}

/* One maneuver on a model set: joint targets q (all models) or orientation R
 * (each model's IK). */
static pom_status run_set(const pom_grad *g, const model_set *s, pom_dyn_data *d, const double *q,
                          const double *R, pom_dyn_metrics *mt, pom_dyn_grad *gr, pom_error *err) {
  /* the engine's parameters: those with a direction (a zero direction's
   * derivative is 0 and needs no run) */
  int par[POM_GRAD_MAX_PARAMS], np = 0;
  for (int j = 0; j < g->n; ++j)
    if (g->step[j] > 0.0) par[np++] = j;
  pom_dyn_sens_spec sp;
  pom_dyn_sens_spec_defaults(&sp);
  sp.n = np;
  sp.method = g->opt.method;
  sp.error_control = g->opt.error_control;
  sp.peak_current = g->opt.peak_current;
  sp.noise_margin = g->opt.sens_noise_margin;
  double target[3];
  pom_error e;
  pom_error_clear(&e);
  all_undefined(gr, g->n);
  pom_status st = POM_OK;
  if (R) {
    pom_doe_maneuver man;
    memset(&man, 0, sizeof man);
    memcpy(man.R, R, sizeof man.R);
    st = pom_doe_dyn_targets(s->nom.ctx, &man, target, &e);
    for (int i = 0; i < np && st == POM_OK; ++i) {
      st = pom_kin_inverse(&base(&s->plus[par[i]])->arch, R, sp.target_plus[i], &e);
      if (st == POM_OK)
        st = pom_kin_inverse(&base(&s->minus[par[i]])->arch, R, sp.target_minus[i], &e);
    }
  } else {
    memcpy(target, q, sizeof target);
    for (int i = 0; i < np; ++i) {
      memcpy(sp.target_plus[i], q, sizeof target);
      memcpy(sp.target_minus[i], q, sizeof target);
    }
  }
  if (st != POM_OK) {
    refused(mt, st, &e);
    if (err) *err = e;
    return st;
  }
  for (int i = 0; i < np; ++i) {
    sp.plus[i] = base(&s->plus[par[i]])->model;
    sp.minus[i] = base(&s->minus[par[i]])->model;
    sp.step[i] = g->step[par[i]];
    sp.scale[i] = g->scale[par[i]];
  }
  const pom_doe_dyn_base *b = base(&s->nom);
  if (np > 0) {
    st = pom_dyn_simulate_sens(b->model, d, target, &sp, mt, gr, err);
  } else {
    /* every direction zero: a plain run (watching the peak current as a
     * sensitivity run would), every defined derivative 0 */
    pom_dyn_data_watch_peak_current(d, g->opt.peak_current);
    st = pom_doe_dyn_run(b, d, target, mt, err);
    pom_dyn_data_watch_peak_current(d, 0); /* the data's plain runs do not watch it */
  }
  if (np < g->n) expand(gr, mt, st, par, np, g->n);
  if (st == POM_OK) {
    /* the study's rule: a run that leaves the stroke is a failure */
    st = pom_doe_check_final_stroke_kind(mt, b->arch.stroke, b->params.actuator.kind, err);
    if (st != POM_OK) all_undefined(gr, g->n);
  }
  return st;
}

pom_status pom_grad_maneuver_joint(pom_grad *g, const double q[3], pom_dyn_metrics *mt,
                                   pom_dyn_grad *gr, pom_error *err) {
  model_set s = current(g);
  return run_set(g, &s, g->d, q, NULL, mt, gr, err);
}

pom_status pom_grad_maneuver_orientation(pom_grad *g, const double R[9], pom_dyn_metrics *mt,
                                         pom_dyn_grad *gr, pom_error *err) {
  model_set s = current(g);
  return run_set(g, &s, g->d, NULL, R, mt, gr, err);
}

/* ---- central differences of whole runs --------------------------------------------------- */
static pom_status plain_run(const pom_grad *g, const pom_doe_evaluator *ev, const double *q,
                            const double *R, pom_dyn_metrics *mt) {
  const pom_doe_dyn_base *b = base(ev);
  pom_dyn_data *d = NULL;
  pom_error e;
  pom_error_clear(&e);
  double target[3];
  pom_status st = POM_OK;
  if (R) {
    pom_doe_maneuver man;
    memset(&man, 0, sizeof man);
    memcpy(man.R, R, sizeof man.R);
    st = pom_doe_dyn_targets(b, &man, target, &e);
  } else {
    memcpy(target, q, sizeof target);
  }
  if (st == POM_OK) st = pom_dyn_data_create(&d, b->model, &e);
  if (st == POM_OK) pom_dyn_data_watch_peak_current(d, g->opt.peak_current); /* its check */
  if (st == POM_OK)
    st = pom_doe_dyn_run(b, d, target, mt, &e);
  else
    refused(mt, st, &e);
  pom_dyn_data_destroy(d);
  return st;
}

/* The runs of one maneuver at value_j +- dh_j, one key at a time (the
 * others at values[]): side[0][j] at the plus step, side[1][j] at the minus
 * step, with their statuses. A design that cannot be built fails the call. */
typedef struct {
  pom_dyn_metrics mt[2][POM_GRAD_MAX_PARAMS];
  pom_status st[2][POM_GRAD_MAX_PARAMS];
} fd_runs;

static pom_status fd_sides(const pom_grad *g, const double *values, const double *x,
                           const double *q, const double *R, const double *dh, fd_runs *r,
                           pom_error *err) {
  double v[POM_GRAD_MAX_PARAMS];
  for (int j = 0; j < g->n; ++j) {
    if (g->step[j] == 0.0) { /* a zero direction: both sides are the nominal design */
      r->st[0][j] = r->st[1][j] = POM_ERR_ARG;
      continue;
    }
    for (int side = 0; side < 2; ++side) {
      pom_doe_evaluator ev;
      along(g, values, j, side ? -dh[j] : dh[j], v);
      pom_status sb = evaluator(&ev, g, v, x, err);
      if (sb != POM_OK) return sb;
      r->st[side][j] = plain_run(g, &ev, q, R, &r->mt[side][j]);
      pom_doe_evaluator_clear(&ev);
    }
  }
  return POM_OK;
}

/* Metric k at the plus (side 0) or minus (side 1) step of key j: NaN when
 * that run failed. */
static double side_value(const fd_runs *r, int side, int j, int k) {
  return r->st[side][j] == POM_OK ? pom_grad_metric_value(&r->mt[side][j], (pom_grad_metric)k)
                                  : NAN;
}

static pom_status fd_set(const pom_grad *g, const double *values, const double *x, const double *q,
                         const double *R, const double *dh, pom_dyn_metrics *mt, pom_dyn_grad *fd,
                         pom_error *err) {
  pom_doe_evaluator ev;
  all_undefined(fd, g->n);
  pom_status st = evaluator(&ev, g, values, x, err);
  if (st != POM_OK) return st;
  st = plain_run(g, &ev, q, R, mt);
  pom_doe_evaluator_clear(&ev);
  fd_runs *r = malloc(sizeof *r);
  if (!r) POM_FAIL(err, POM_ERR_NOMEM, "design gradients: out of memory for the differences");
  pom_status sb = fd_sides(g, values, x, q, R, dh, r, err);
  for (int k = 0; k < POM_GRAD_N_METRICS && sb == POM_OK; ++k) {
    pom_dyn_dmetric *d = grad_of(fd, (pom_grad_metric)k);
    d->defined = 1;
    for (int j = 0; j < g->n; ++j) {
      if (g->step[j] == 0.0) {
        d->d[j] = 0.0;
        continue;
      }
      double a = side_value(r, 0, j, k), b = side_value(r, 1, j, k);
      d->d[j] = (a - b) / (2.0 * dh[j]);
      if (!(isfinite(a) && isfinite(b))) d->defined = 0, d->d[j] = NAN;
    }
    d->why = d->defined ? POM_DYN_GRAD_OK : POM_DYN_GRAD_UNKNOWN;
  }
  free(r);
  return sb != POM_OK ? sb : st;
}

pom_status pom_grad_fd_maneuver(pom_grad *g, const double *q, const double *R, const double *dh,
                                pom_dyn_metrics *mt, pom_dyn_grad *fd, pom_error *err) {
  if (!q == !R) POM_FAIL(err, POM_ERR_ARG, "pom_grad_fd_maneuver: give exactly one of q and R");
  return fd_set(g, g->value, NULL, q, R, dh ? dh : g->step, mt, fd, err);
}

/* ---- the honest reference (docs/optimize.md 12.4) ------------------------------------------ */
/* Key j of metric k from the runs at H, H/2, H/4 (r[0..2]) and the nominal
 * value M0: D_i = (M+_i - M-_i) / (2 h_i), the Richardson pair R1 (from D_0,
 * D_1) and R2 (from D_1, D_2); the runs' noise at step h is eta(h) =
 * run_error |M0| / h (two runs' errors over 2h). */
static void ref_one(pom_grad_ref *o, int j, double M0, const double Mp[3], const double Mm[3],
                    double H, double run_error) {
  double D[3], h[3], eta[3];
  for (int i = 0; i < 3; ++i) {
    h[i] = H / (double)(1 << i); /* H, H/2, H/4 */
    D[i] = (Mp[i] - Mm[i]) / (2.0 * h[i]);
    eta[i] = run_error * fabs(M0) / h[i];
  }
  const double d1 = D[0] - D[1], d2 = D[1] - D[2];
  const double R1 = D[1] - d1 / 3.0, R2 = D[2] - d2 / 3.0;
  /* the h^2 law: d1 = 4 d2 up to the h^4 term (half of d1 allowed) and the
   * noise of the four differences (eta_0 + 5 eta_1 + 4 eta_2) */
  const int law = fabs(d1 - 4.0 * d2) <= 0.5 * fabs(d1) + eta[0] + 5.0 * eta[1] + 4.0 * eta[2];
  /* forward against backward at H/4: F - B = h C(h), C the second
   * difference, which tends to M'' (C(H/4) within half of C(H/2)); a kink
   * of jump J within h makes F - B -> J, C(h) ~ J / h. C's noise is
   * 4 run_error |M0| / h^2. */
  double C[2];
  for (int i = 1; i < 3; ++i)
    C[i - 1] = (Mp[i] - 2.0 * M0 + Mm[i]) / (h[i] * h[i]);
  const double cnoise = 4.0 * run_error * fabs(M0) * (1.0 / (h[1] * h[1]) + 1.0 / (h[2] * h[2]));
  const int sides = fabs(C[1] - C[0]) <= 0.5 * fabs(C[0]) + cnoise;
  o->kink[j] = !(law && sides);
  if (!o->kink[j]) {
    o->d[j] = R2;
    o->err[j] = fabs(R1 - R2) + 1.5 * eta[2]; /* R2's noise: (4 eta_2 + eta_1) / 3 */
  } else {
    o->d[j] = D[2];
    o->err[j] = fmax(fmax(fabs(d1), fabs(d2)), h[2] * fabs(C[1])) + eta[2];
  }
}

pom_status pom_grad_reference(pom_grad *g, const double *q, const double *R, const double *H,
                              const double *run_error, pom_dyn_metrics *mt, pom_grad_ref *ref,
                              pom_error *err) {
  if (!q == !R || !run_error)
    POM_FAIL(err, POM_ERR_ARG, "pom_grad_reference: give exactly one of q and R, and run_error");
  for (int j = 0; j < g->n; ++j)
    if (!(H[j] > 0.0 && isfinite(H[j])))
      POM_FAIL(err, POM_ERR_ARG, "pom_grad_reference: %s has step %g (must be > 0)", g->key[j],
               H[j]);
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    ref[k].defined = 0;
    for (int j = 0; j < POM_GRAD_MAX_PARAMS; ++j)
      ref[k].d[j] = ref[k].err[j] = NAN, ref[k].kink[j] = 0;
  }
  pom_doe_evaluator ev;
  pom_status st = evaluator(&ev, g, g->value, NULL, err);
  if (st != POM_OK) return st;
  st = plain_run(g, &ev, q, R, mt);
  pom_doe_evaluator_clear(&ev);
  fd_runs *r = malloc(3 * sizeof *r);
  if (!r) POM_FAIL(err, POM_ERR_NOMEM, "design gradients: out of memory for the reference");
  pom_status sb = POM_OK;
  for (int i = 0; i < 3 && sb == POM_OK; ++i) {
    double dh[POM_GRAD_MAX_PARAMS];
    for (int j = 0; j < g->n; ++j)
      dh[j] = H[j] / (double)(1 << i);
    sb = fd_sides(g, g->value, NULL, q, R, dh, &r[i], err);
  }
  for (int k = 0; k < POM_GRAD_N_METRICS && sb == POM_OK && st == POM_OK; ++k) {
    const double M0 = pom_grad_metric_value(mt, (pom_grad_metric)k);
    ref[k].defined = isfinite(M0);
    for (int j = 0; j < g->n; ++j) {
      if (g->step[j] == 0.0) { /* a zero direction: exactly 0 */
        ref[k].d[j] = ref[k].err[j] = 0.0;
        continue;
      }
      double Mp[3], Mm[3];
      for (int i = 0; i < 3; ++i) {
        Mp[i] = side_value(&r[i], 0, j, k);
        Mm[i] = side_value(&r[i], 1, j, k);
        if (!(isfinite(Mp[i]) && isfinite(Mm[i]))) ref[k].defined = 0;
      }
      if (ref[k].defined) ref_one(&ref[k], j, M0, Mp, Mm, H[j], run_error[k]);
    }
    if (!ref[k].defined)
      for (int j = 0; j < g->n; ++j)
        ref[k].d[j] = ref[k].err[j] = NAN, ref[k].kink[j] = 0;
  }
  free(r);
  return sb != POM_OK ? sb : st;
}

/* The smooth quantile of each time metric over the set and its gradient,
 * dq/dp = sum_i w_i dt_i/dp with w_i = dq/dt_i (docs/optimize.md 11.3,
 * 12.3); defined as the means are: every maneuver finished with that
 * derivative defined (a censored time, a failed maneuver: undefined, with
 * the first maneuver's reason). */
static int is_time_metric(pom_grad_metric k) {
  return (k >= POM_GRAD_SETTLING_TIME_1 && k <= POM_GRAD_SETTLING_TIME_3) ||
         k == POM_GRAD_EXECUTION_TIME || k == POM_GRAD_POINTING_SETTLING_TIME;
}

static void smooth_quantiles(const pom_grad *g, pom_grad_mc_result *r) {
  r->quantile_p = g->opt.quantile;
  r->quantile_bandwidth = g->opt.quantile_bandwidth;
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    pom_dyn_dmetric *dq = &r->dquantile[k];
    r->quantile[k] = NAN;
    dq->defined = 0;
    dq->why = POM_DYN_GRAD_UNKNOWN;
    for (int j = 0; j < POM_DYN_SENS_MAX; ++j)
      dq->d[j] = j < g->n ? NAN : 0.0;
    if (!is_time_metric((pom_grad_metric)k) || r->n < 1) continue;
    double *t = malloc((size_t)r->n * 2 * sizeof *t);
    if (!t) continue; /* left undefined */
    double *w = t + r->n;
    int all = 1;
    for (long i = 0; i < r->n && all; ++i) {
      t[i] = pom_grad_metric_value(&r->metrics[i], (pom_grad_metric)k);
      all = r->metrics[i].status == POM_OK && isfinite(t[i]);
    }
    if (all)
      r->quantile[k] = pom_smooth_quantile(t, (int)r->n, r->quantile_p, r->quantile_bandwidth, w);
    /* the gradient under the means' rule (their reason when undefined) */
    dq->why = r->dmean[k].why;
    if (all && r->dmean[k].defined) {
      dq->defined = 1;
      dq->why = POM_DYN_GRAD_OK;
      for (int j = 0; j < g->n; ++j) {
        double s = 0.0;
        for (long i = 0; i < r->n; ++i)
          s += w[i] * grad_of(&r->grads[i], (pom_grad_metric)k)->d[j];
        dq->d[j] = s;
      }
    }
    free(t);
  }
}

/* ---- Monte-Carlo ------------------------------------------------------------------------- */
void pom_grad_mc_free(pom_grad_mc_result *r) {
  if (!r) return;
  free(r->metrics);
  free(r->grads);
  memset(r, 0, sizeof *r);
}

pom_status pom_grad_montecarlo(pom_grad *g, const pom_grad_mc_options *o, pom_grad_mc_result *r,
                               pom_error *err) {
  pom_grad_mc_options def;
  if (!o) {
    pom_grad_mc_options_defaults(&def);
    o = &def;
  }
  memset(r, 0, sizeof *r);
  r->n_params = g->n;
  r->plain_fd = o->plain_fd;
  r->rel_step = g->opt.rel_step;
  r->solver_rtol = pom_dyn_model_params(base(&g->nom)->model)->solver.rtol;
  pom_doe_maneuvers mv = g->mv;
  pom_unc unc = g->unc;
  if (o->seed_set) mv.seed = unc.seed = o->seed;
  long count = o->count > 0 ? o->count : mv.count;
  r->metrics = calloc((size_t)count, sizeof *r->metrics);
  r->grads = calloc((size_t)count, sizeof *r->grads);
  if (!r->metrics || !r->grads) {
    pom_grad_mc_free(r);
    POM_FAIL(err, POM_ERR_NOMEM, "design gradients: out of memory for %ld maneuvers", count);
  }
  pom_status st = POM_OK;
  for (long k = 0; k < count; ++k) {
    pom_doe_maneuver man;
    pom_doe_maneuver_draw(&man, &mv, k);
    const double *q = mv.space == POM_DOE_SPACE_JOINT ? man.q : NULL;
    const double *R = mv.space == POM_DOE_SPACE_JOINT ? NULL : man.R;
    double x[POM_UNC_MAX];
    if (unc.n > 0) pom_unc_draws(&unc, k, x);
    pom_error e;
    pom_error_clear(&e);
    pom_dyn_metrics *mt = &r->metrics[k];
    pom_dyn_grad *gr = &r->grads[k];
    if (o->plain_fd) {
      st = fd_set(g, g->value, unc.n > 0 ? x : NULL, q, R, g->step, mt, gr, &e);
    } else if (unc.n > 0) {
      model_set s;
      st = build_set(&s, g, g->value, g->step, x, &e);
      if (st == POM_OK) {
        pom_dyn_data *d = NULL;
        st = pom_dyn_data_create(&d, base(&s.nom)->model, &e);
        if (st == POM_OK) st = run_set(g, &s, d, q, R, mt, gr, &e);
        pom_dyn_data_destroy(d);
        set_clear(&s, g->n);
      }
    } else {
      model_set s = current(g);
      st = run_set(g, &s, g->d, q, R, mt, gr, &e);
    }
    if (st == POM_ERR_NOMEM || st == POM_ERR_CONFIG || st == POM_ERR_ARG) {
      if (err) *err = e;
      pom_grad_mc_free(r);
      return st;
    }
    if (mt->status == POM_OK && st != POM_OK) mt->status = st;
    ++r->n;
  }
  /* means and their gradients */
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    pom_dyn_dmetric *dm = &r->dmean[k];
    double sum = 0.0, dsum[POM_GRAD_MAX_PARAMS] = {0};
    long used = 0, defined = 0;
    dm->why = POM_DYN_GRAD_OK;
    for (long i = 0; i < r->n; ++i) {
      const pom_dyn_metrics *mt = &r->metrics[i];
      const pom_dyn_dmetric *d = grad_of(&r->grads[i], (pom_grad_metric)k);
      double v = pom_grad_metric_value(mt, (pom_grad_metric)k);
      if (mt->status == POM_OK && isfinite(v)) sum += v, ++used;
      if (mt->status == POM_OK && d->defined) {
        ++defined;
        for (int j = 0; j < g->n; ++j)
          dsum[j] += d->d[j];
      } else if (dm->why == POM_DYN_GRAD_OK) {
        dm->why = mt->status == POM_OK ? d->why : POM_DYN_GRAD_UNKNOWN;
      }
    }
    r->mean[k] = used > 0 ? sum / (double)used : NAN;
    r->n_defined[k] = defined;
    dm->defined = r->n > 0 && defined == r->n;
    if (!dm->defined && dm->why == POM_DYN_GRAD_OK) dm->why = POM_DYN_GRAD_UNKNOWN;
    for (int j = 0; j < POM_DYN_SENS_MAX; ++j)
      dm->d[j] = j < g->n ? (dm->defined ? dsum[j] / (double)r->n : NAN) : 0.0;
  }
  smooth_quantiles(g, r);
  long fin = 0;
  for (long i = 0; i < r->n; ++i)
    fin += r->metrics[i].status == POM_OK;
  r->n_finished = fin;
  return POM_OK;
}

/* ---- JSON ---------------------------------------------------------------------------- */
static void json_grad(FILE *out, const pom_dyn_dmetric *d, int n) {
  if (!d->defined) {
    fprintf(out, "null");
    return;
  }
  pom_json_vec(out, d->d, n, 1.0);
}

static void json_one(FILE *out, const pom_grad *g, const pom_dyn_metrics *mt,
                     const pom_dyn_grad *gr, const pom_dyn_grad *fd) {
  const int n = pom_grad_n_params(g);
  fprintf(out, "{\"status\": ");
  pom_json_string(out, pom_status_name(mt->status));
  fprintf(out, ", \"reason\": ");
  pom_json_string(out, mt->reason);
  fprintf(out, ", \"target\": ");
  pom_json_vec(out, mt->target, 3, 1.0);
  fprintf(out, ", \"metrics\": {");
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    fprintf(out, "%s\"%s\": ", k ? ", " : "", pom_grad_metric_name((pom_grad_metric)k));
    pom_json_number(out, pom_grad_metric_value(mt, (pom_grad_metric)k));
  }
  fprintf(out, "}, \"gradient\": {");
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    fprintf(out, "%s\"%s\": ", k ? ", " : "", pom_grad_metric_name((pom_grad_metric)k));
    json_grad(out, pom_grad_metric_grad(gr, (pom_grad_metric)k), n);
  }
  fprintf(out, "}, \"undefined\": {");
  int first = 1;
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    const pom_dyn_dmetric *d = pom_grad_metric_grad(gr, (pom_grad_metric)k);
    if (d->defined) continue;
    fprintf(out, "%s\"%s\": ", first ? "" : ", ", pom_grad_metric_name((pom_grad_metric)k));
    pom_json_string(out, pom_dyn_grad_why_text(d->why));
    first = 0;
  }
  fprintf(out, "}, \"peak_current_at\": {\"time\": ");
  pom_json_number(out, isfinite(mt->peak_current) ? gr->peak_time : NAN);
  fprintf(out, ", \"coil\": %d}", isfinite(mt->peak_current) ? gr->peak_coil + 1 : 0);
  if (fd) {
    fprintf(out, ", \"check\": {");
    for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
      fprintf(out, "%s\"%s\": ", k ? ", " : "", pom_grad_metric_name((pom_grad_metric)k));
      json_grad(out, pom_grad_metric_grad(fd, (pom_grad_metric)k), n);
    }
    fprintf(out, "}");
  }
  fprintf(out, "}");
}

/* {"gradients": "sensitivities" | "whole-run differences", "rel_step": h,
 * "solver_rtol": rtol} of a Monte-Carlo result */
static void json_method(FILE *out, const pom_grad_mc_result *r) {
  fprintf(out, "{\"gradients\": ");
  pom_json_string(out, r->plain_fd ? "whole-run differences" : "sensitivities");
  fprintf(out, ", \"rel_step\": ");
  pom_json_number(out, r->rel_step);
  fprintf(out, ", \"solver_rtol\": ");
  pom_json_number(out, r->solver_rtol);
  fprintf(out, "}");
}

void pom_grad_mc_json(FILE *out, const char *cfg_path, const pom_grad *g,
                      const pom_grad_mc_result *r, const pom_grad_mc_result *check) {
  const int nk = pom_grad_n_keys(g);
  fprintf(out, "{\"config\": ");
  pom_json_string(out, cfg_path);
  fprintf(out, ", \"keys\": [");
  for (int j = 0; j < nk; ++j) {
    fprintf(out, "%s", j ? ", " : "");
    pom_json_string(out, pom_grad_key(g, j));
  }
  fprintf(out, "], \"values\": [");
  for (int j = 0; j < nk; ++j) {
    fprintf(out, "%s", j ? ", " : "");
    pom_json_number(out, pom_grad_value(g, j));
  }
  fprintf(out, "]");
  if (!g->identity) {
    /* the parameters the gradients are with respect to: one row of key
     * coefficients each */
    fprintf(out, ", \"directions\": [");
    for (int j = 0; j < g->n; ++j) {
      fprintf(out, "%s", j ? ", " : "");
      pom_json_vec(out, g->dir[j], nk, 1.0);
    }
    fprintf(out, "]");
  }
  fprintf(out, ", \"maneuvers\": [");
  for (long i = 0; i < r->n; ++i) {
    fprintf(out, "%s\n  ", i ? "," : "");
    json_one(out, g, &r->metrics[i], &r->grads[i], check ? &check->grads[i] : NULL);
  }
  fprintf(out, "],\n \"finished\": %ld, \"mean\": {", r->n_finished);
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    fprintf(out, "%s\"%s\": ", k ? ", " : "", pom_grad_metric_name((pom_grad_metric)k));
    pom_json_number(out, r->mean[k]);
  }
  fprintf(out, "}, \"mean_gradient\": {");
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k) {
    fprintf(out, "%s\"%s\": ", k ? ", " : "", pom_grad_metric_name((pom_grad_metric)k));
    json_grad(out, &r->dmean[k], g->n);
  }
  fprintf(out, "}, \"mean_gradient_defined_in\": {");
  for (int k = 0; k < POM_GRAD_N_METRICS; ++k)
    fprintf(out, "%s\"%s\": %ld", k ? ", " : "", pom_grad_metric_name((pom_grad_metric)k),
            r->n_defined[k]);
  fprintf(out, "},\n \"quantile\": {\"p\": ");
  pom_json_number(out, r->quantile_p);
  fprintf(out, ", \"bandwidth_s\": ");
  pom_json_number(out, r->quantile_bandwidth);
  fprintf(out, ", \"value\": {");
  for (int k = 0, first = 1; k < POM_GRAD_N_METRICS; ++k) {
    if (!is_time_metric((pom_grad_metric)k)) continue;
    fprintf(out, "%s\"%s\": ", first ? "" : ", ", pom_grad_metric_name((pom_grad_metric)k));
    pom_json_number(out, r->quantile[k]);
    first = 0;
  }
  fprintf(out, "}, \"gradient\": {");
  for (int k = 0, first = 1; k < POM_GRAD_N_METRICS; ++k) {
    if (!is_time_metric((pom_grad_metric)k)) continue;
    fprintf(out, "%s\"%s\": ", first ? "" : ", ", pom_grad_metric_name((pom_grad_metric)k));
    json_grad(out, &r->dquantile[k], g->n);
    first = 0;
  }
  fprintf(out, "}, \"undefined\": {");
  for (int k = 0, first = 1; k < POM_GRAD_N_METRICS; ++k) {
    if (!is_time_metric((pom_grad_metric)k) || r->dquantile[k].defined) continue;
    fprintf(out, "%s\"%s\": ", first ? "" : ", ", pom_grad_metric_name((pom_grad_metric)k));
    pom_json_string(out, pom_dyn_grad_why_text(r->dquantile[k].why));
    first = 0;
  }
  fprintf(out, "}},\n \"method\": ");
  json_method(out, r);
  if (check) {
    fprintf(out, ", \"check_method\": ");
    json_method(out, check);
  }
  fprintf(out, "}\n");
}
