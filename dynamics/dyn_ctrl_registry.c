/* dyn_ctrl_registry.c - the registry of controller types (the built-ins,
 * then the ones a program registers) and the descriptor-driven helpers every
 * caller uses: defaults, the one range check, loading (docs/extending.md
 * section 8). Registering a controller of the library = one line in
 * `builtin` below. */
#include "pom_dyn_ctrl.h"
#include "pom_registry.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const pom_dyn_ctrl_type *const builtin[] = {
    &pom_dyn_ctrl_pid,
    &pom_dyn_ctrl_computed_torque,
    &pom_dyn_ctrl_pid_feedforward,
};
static pom_registry registry = POM_REGISTRY_INIT(builtin, offsetof(pom_dyn_ctrl_type, name));

/* ---- registry -------------------------------------------------------------- */
int pom_dyn_ctrl_type_count(void) {
  return pom_registry_count(&registry);
}

const pom_dyn_ctrl_type *pom_dyn_ctrl_type_at(int k) {
  return pom_registry_at(&registry, k);
}

const pom_dyn_ctrl_type *pom_dyn_ctrl_type_find(const char *name) {
  return pom_registry_find(&registry, name);
}

/* The descriptors of t fit pom_dyn_controller: every offset inside it, the
 * slots within their arrays. */
static pom_status type_check(const pom_dyn_ctrl_type *t, pom_error *err) {
  if (!t || !t->name || !t->name[0]) POM_FAIL(err, POM_ERR_ARG, "controller type without a name");
  if ((!t->law && !t->law_all) || !t->describe || (t->law_all && t->partials) ||
      (!t->model_create) != (!t->model_destroy) || (!t->work_create) != (!t->work_destroy))
    POM_FAIL(err, POM_ERR_ARG, "controller %s: its operations table is incomplete", t->name);
  if (t->n_states < 0 || t->n_states > POM_DYN_CTRL_MAX_STATES || (t->n_states > 0 && !t->states))
    POM_FAIL(err, POM_ERR_ARG, "controller %s: %d states (0..%d, each described)", t->name,
             t->n_states, POM_DYN_CTRL_MAX_STATES);
  if (t->n_gains < 0 || t->n_gains > POM_DYN_CTRL_MAX_GAINS || (t->n_gains > 0 && !t->gains) ||
      t->n_options < 0 || t->n_options > POM_DYN_CTRL_MAX_OPTIONS ||
      (t->n_options > 0 && !t->options))
    POM_FAIL(err, POM_ERR_ARG, "controller %s: %d gains (0..%d) and %d options (0..%d)", t->name,
             t->n_gains, POM_DYN_CTRL_MAX_GAINS, t->n_options, POM_DYN_CTRL_MAX_OPTIONS);
  for (int k = 0; k < t->n_gains; ++k) {
    const pom_dyn_gain_desc *g = &t->gains[k];
    if (!g->key || g->offset + sizeof(double) > sizeof(pom_dyn_controller) ||
        g->offset % sizeof(double) != 0 || !(g->lo <= g->def && g->def <= g->hi))
      POM_FAIL(err, POM_ERR_ARG,
               "controller %s: gain %d (%s) has no key, an offset outside pom_dyn_controller or "
               "a default outside its range",
               t->name, k, g->key ? g->key : "?");
  }
  for (int k = 0; k < t->n_options; ++k) {
    const pom_dyn_ctrl_option_desc *o = &t->options[k];
    if (!o->key || !o->names || !o->names[0] ||
        o->offset + sizeof(int) > sizeof(pom_dyn_controller) || o->offset % sizeof(int) != 0)
      POM_FAIL(err, POM_ERR_ARG, "controller %s: option %d (%s) is incomplete", t->name, k,
               o->key ? o->key : "?");
  }
  return POM_OK;
}

pom_status pom_dyn_ctrl_register(const pom_dyn_ctrl_type *t, pom_error *err) {
  POM_TRY(type_check(t, err));
  return pom_registry_add(&registry, t, "controller", err);
}

/* ---- values through the descriptors ----------------------------------------- */
const pom_dyn_ctrl_type *pom_dyn_ctrl_of(const pom_dyn_controller *c) {
  return (c && c->type) ? c->type : &pom_dyn_ctrl_pid;
}

double *pom_dyn_ctrl_gain_ptr(pom_dyn_controller *c, int k) {
  return (double *)(void *)((char *)c + pom_dyn_ctrl_of(c)->gains[k].offset);
}

double pom_dyn_ctrl_gain(const pom_dyn_controller *c, int k) {
  return *(const double *)(const void *)((const char *)c + pom_dyn_ctrl_of(c)->gains[k].offset);
}

int pom_dyn_ctrl_option(const pom_dyn_controller *c, int k) {
  return *(const int *)(const void *)((const char *)c + pom_dyn_ctrl_of(c)->options[k].offset);
}

const char *pom_dyn_ctrl_option_name(const pom_dyn_controller *c, int k) {
  const pom_dyn_ctrl_option_desc *o = &pom_dyn_ctrl_of(c)->options[k];
  int v = pom_dyn_ctrl_option(c, k), n = 0;
  while (o->names[n])
    ++n;
  return (v >= 0 && v < n) ? o->names[v] : "?";
}

int pom_dyn_ctrl_gain_index(const pom_dyn_ctrl_type *t, const char *key) {
  for (int k = 0; t && key && k < t->n_gains; ++k)
    if (strcmp(t->gains[k].key, key) == 0) return k;
  return -1;
}

int pom_dyn_ctrl_option_index(const pom_dyn_ctrl_type *t, const char *key) {
  for (int k = 0; t && key && k < t->n_options; ++k)
    if (strcmp(t->options[k].key, key) == 0) return k;
  return -1;
}

void pom_dyn_ctrl_set_defaults(pom_dyn_controller *c, const pom_dyn_ctrl_type *t) {
  memset(c, 0, sizeof *c);
  c->type = t;
  for (int k = 0; k < t->n_gains; ++k)
    *pom_dyn_ctrl_gain_ptr(c, k) = t->gains[k].def;
  for (int k = 0; k < t->n_options; ++k)
    *(int *)(void *)((char *)c + t->options[k].offset) = 0;
}

pom_status pom_dyn_ctrl_check(const pom_dyn_controller *c, pom_error *err) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(c);
  for (int k = 0; k < t->n_gains; ++k) {
    const pom_dyn_gain_desc *g = &t->gains[k];
    double v = pom_dyn_ctrl_gain(c, k);
    if (!(v >= g->lo && v <= g->hi))
      POM_FAIL(err, POM_ERR_ARG, "controller.%s = %g %s outside [%g, %g] (controller %s)", g->key,
               v, g->unit, g->lo, g->hi, t->name);
  }
  for (int k = 0; k < t->n_options; ++k) {
    const pom_dyn_ctrl_option_desc *o = &t->options[k];
    int v = pom_dyn_ctrl_option(c, k), n = 0;
    while (o->names[n])
      ++n;
    if (v < 0 || v >= n)
      POM_FAIL(err, POM_ERR_ARG, "controller.%s = %d is not one of its %d choices (controller %s)",
               o->key, v, n, t->name);
  }
  return POM_OK;
}

/* ---- loading ------------------------------------------------------------------ */
pom_status pom_dyn_ctrl_load(pom_dyn_controller *c, const pom_cfg *cfg, pom_error *err) {
  const pom_dyn_ctrl_type *cur = pom_dyn_ctrl_of(c);
  char name[64];
  POM_TRY(pom_cfg_string_opt(cfg, "controller.type", cur->name, name, sizeof name, err));
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_type_find(name);
  if (!t) {
    char known[256] = "";
    size_t len = 0;
    for (int k = 0; k < pom_dyn_ctrl_type_count() && len < sizeof known; ++k) {
      int w = snprintf(known + len, sizeof known - len, "%s\"%s\"", k ? ", " : "",
                       pom_dyn_ctrl_type_at(k)->name);
      if (w < 0) break;
      len += (size_t)w;
    }
    return pom_cfg_error(cfg, "controller.type", name, err,
                         "is not a registered controller (%s; pomlab model --list-controllers)",
                         known);
  }
  if (t != cur) pom_dyn_ctrl_set_defaults(c, t);
  c->type = t;
  char key[96];
  for (int k = 0; k < t->n_options; ++k) {
    const pom_dyn_ctrl_option_desc *o = &t->options[k];
    int *slot = (int *)(void *)((char *)c + o->offset);
    snprintf(key, sizeof key, "controller.%s", o->key);
    POM_TRY(pom_cfg_choice_opt(cfg, key, o->names, *slot, slot, err));
  }
  for (int k = 0; k < t->n_gains; ++k) {
    const pom_dyn_gain_desc *g = &t->gains[k];
    double *slot = pom_dyn_ctrl_gain_ptr(c, k);
    snprintf(key, sizeof key, "controller.%s", g->key);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, g->lo, g->hi, *slot, slot, err));
  }
  /* keys of the other registered types may stay in the group (one config
   * carries the gains of several controllers, switched by controller.type or
   * --controller): they are not read; a key of no registered type is still
   * refused by the unknown-key check (docs/config.md) */
  for (int k = 0; k < pom_dyn_ctrl_type_count(); ++k) {
    const pom_dyn_ctrl_type *o = pom_dyn_ctrl_type_at(k);
    if (o == t) continue;
    for (int i = 0; i < o->n_gains + o->n_options; ++i) {
      const char *okey = i < o->n_gains ? o->gains[i].key : o->options[i - o->n_gains].key;
      snprintf(key, sizeof key, "controller.%s", okey);
      if (pom_cfg_has(cfg, key) && pom_dyn_ctrl_gain_index(t, okey) < 0 &&
          pom_dyn_ctrl_option_index(t, okey) < 0)
        pom_cfg_mark_used(cfg, key);
    }
  }
  return POM_OK;
}
