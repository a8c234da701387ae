/* kin_arch_file.c - architecture files (pom_arch_file.h, format of
 * docs/architecture-files.md): the loader that checks a file and compiles
 * its expressions, and the evaluation of the expressions at a design. */
#define _DEFAULT_SOURCE /* DIR, struct dirent, readlink */
#include "pom_arch_file.h"

#include "kin_internal.h"
#include "pom_config.h"
#include "pom_math.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- variables ------------------------------------------------------------------- */
/* The variables visible to an expression: a table grown scope by scope. */
typedef struct {
  pom_expr_var var[POM_KIN_MAX_PARAMS + 1 + 2 * POM_AF_MAX_LETS + 8];
  int n;
  int slots; /* doubles used */
} scope;

/* Limb variables, after the globals: i, eta, er, et, ez. */
enum { LV_I, LV_ETA, LV_ER, LV_ET = LV_ER + 3, LV_EZ = LV_ET + 3, LV_COUNT = LV_EZ + 3 };

static const char *const limb_var_names[] = {"i", "eta", "er", "et", "ez", NULL};

static int in_scope(const scope *s, const char *name) {
  for (int k = 0; k < s->n; ++k)
    if (strcmp(s->var[k].name, name) == 0) return 1;
  return 0;
}

static void add_var(scope *s, const char *name, pom_expr_kind kind) {
  s->var[s->n].name = name;
  s->var[s->n].kind = kind;
  s->var[s->n].slot = s->slots;
  s->slots += (int)kind;
  ++s->n;
}

/* ---- config helpers ------------------------------------------------------------- */
/* A string value or a group/list element key: "limbs.joints.[1].point". */
static pom_status read_string(const pom_cfg *cfg, const char *key, int required, const char *dflt,
                              char *buf, size_t cap, pom_error *err) {
  if (required) return pom_cfg_string(cfg, key, buf, cap, err);
  return pom_cfg_string_opt(cfg, key, dflt, buf, cap, err);
}

/* A name usable in expressions: an identifier, not reserved, not taken. */
static pom_status check_name(const pom_cfg *cfg, const char *key, const char *name, const scope *s,
                             pom_error *err) {
  char quoted[80];
  snprintf(quoted, sizeof quoted, "\"%s\"", name);
  if (!pom_expr_identifier(name) || strlen(name) >= POM_AF_NAME_LEN)
    return pom_cfg_error(cfg, key, quoted, err,
                         "not a name for expressions: a letter or '_', then letters, digits or "
                         "'_' (at most %d characters)",
                         POM_AF_NAME_LEN - 1);
  if (pom_expr_reserved(name))
    return pom_cfg_error(cfg, key, quoted, err, "reserved: pi and the function names");
  for (int k = 0; limb_var_names[k]; ++k)
    if (strcmp(name, limb_var_names[k]) == 0)
      return pom_cfg_error(cfg, key, quoted, err,
                           "reserved: the limb variables are i, eta, er, et and ez");
  if (s && in_scope(s, name))
    return pom_cfg_error(cfg, key, quoted, err, "already defined (a symbol or a let)");
  return POM_OK;
}

/* Compiles the string at key over scope s into x; want = 0: any kind. */
static pom_status compile_at(const pom_cfg *cfg, const char *key, const scope *s,
                             pom_expr_kind want, pom_af_expr *x, pom_error *err) {
  char text[POM_EXPR_MAX_TEXT + 1];
  POM_TRY(pom_cfg_string(cfg, key, text, sizeof text, err));
  pom_expr_error er;
  if (pom_expr_compile(&x->e, text, s->var, s->n, &er) != POM_OK)
    return pom_cfg_error(cfg, key, NULL, err, "%s", er.message);
  if (want && x->e.kind != want)
    return pom_cfg_error(cfg, key, NULL, err, "expected %s expression, this one is %s",
                         want == POM_EXPR_VECTOR ? "a vector" : "a scalar",
                         x->e.kind == POM_EXPR_VECTOR ? "a vector" : "a scalar");
  x->line = pom_cfg_line(cfg, key);
  snprintf(x->key, sizeof x->key, "%s", key);
  snprintf(x->text, sizeof x->text, "%s", text);
  return POM_OK;
}

/* The named expressions of group `key` (optional) appended to s and lets. */
static pom_status load_lets(const pom_cfg *cfg, const char *key, scope *s, pom_af_let *lets,
                            int *n_lets, pom_error *err) {
  *n_lets = 0;
  if (!pom_cfg_has(cfg, key)) return POM_OK;
  int n = pom_cfg_length(cfg, key);
  if (!pom_cfg_member_name(cfg, key, 0) && n > 0)
    return pom_cfg_error(cfg, key, NULL, err,
                         "expected a group of named expressions { NAME = \"...\"; ... }");
  if (n > POM_AF_MAX_LETS)
    return pom_cfg_error(cfg, key, NULL, err, "more than %d named expressions", POM_AF_MAX_LETS);
  for (int k = 0; k < n; ++k) {
    const char *name = pom_cfg_member_name(cfg, key, k);
    char sub[160];
    snprintf(sub, sizeof sub, "%s.%s", key, name);
    POM_TRY(check_name(cfg, sub, name, s, err));
    pom_af_let *l = &lets[k];
    snprintf(l->name, sizeof l->name, "%s", name);
    POM_TRY(compile_at(cfg, sub, s, 0, &l->value, err));
    l->slot = s->slots;
    add_var(s, l->name, l->value.e.kind);
    *n_lets = k + 1;
  }
  return POM_OK;
}

/* Unit factor of a key from its suffix: _deg -> rad, _mm -> m, _mm2 -> m^2,
 * else 1 (dimensionless or SI). */
static double suffix_to_si(const char *key) {
  size_t n = strlen(key);
  if (n > 4 && strcmp(key + n - 4, "_deg") == 0) return POM_DEG;
  if (n > 4 && strcmp(key + n - 4, "_mm2") == 0) return 1e-6;
  if (n > 3 && strcmp(key + n - 3, "_mm") == 0) return 1e-3;
  return 1.0;
}

static pom_status read_range(const pom_cfg *cfg, const char *key, double *lo, double *hi,
                             pom_error *err) {
  double r[2];
  POM_TRY(pom_cfg_reals(cfg, key, 2, 1.0, -1e9, 1e9, r, err));
  if (!(r[0] < r[1]))
    return pom_cfg_error(cfg, key, NULL, err, "expected [low, high] with low < high");
  *lo = r[0];
  *hi = r[1];
  return POM_OK;
}

/* ---- sections -------------------------------------------------------------------- */
static pom_status load_head(pom_arch_file *f, const pom_cfg *cfg, pom_error *err) {
  long format;
  POM_TRY(pom_cfg_int(cfg, "format", 1, 1000, &format, err));
  if (format != POM_AF_FORMAT)
    return pom_cfg_error(cfg, "format", NULL, err, "this pomlab reads architecture format %d",
                         POM_AF_FORMAT);
  POM_TRY(pom_cfg_string(cfg, "name", f->name, sizeof f->name, err));
  for (const char *c = f->name; *c; ++c)
    if (!((*c >= 'A' && *c <= 'Z') || (*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') ||
          *c == '-' || *c == '_' || *c == '.'))
      return pom_cfg_error(cfg, "name", NULL, err,
                           "an architecture name holds letters, digits, '-', '_' and '.' only");
  if (!f->name[0]) return pom_cfg_error(cfg, "name", NULL, err, "empty");
  POM_TRY(pom_cfg_string(cfg, "label", f->label, sizeof f->label, err));
  POM_TRY(pom_cfg_string(cfg, "description", f->description, sizeof f->description, err));
  POM_TRY(read_string(cfg, "unreachable", 0, "a limb cannot be assembled (no real IK root)",
                      f->unreachable, sizeof f->unreachable, err));
  if (pom_cfg_has(cfg, "references")) {
    int n = pom_cfg_length(cfg, "references");
    if (!pom_cfg_is_list(cfg, "references") && n > 0 && pom_cfg_member_name(cfg, "references", 0))
      return pom_cfg_error(cfg, "references", NULL, err, "expected a list of strings ( \"...\" )");
    if (n > POM_AF_MAX_REFS)
      return pom_cfg_error(cfg, "references", NULL, err, "more than %d references",
                           POM_AF_MAX_REFS);
    for (int k = 0; k < n; ++k) {
      char key[64];
      snprintf(key, sizeof key, "references.[%d]", k);
      POM_TRY(pom_cfg_string(cfg, key, f->refs[k], sizeof f->refs[k], err));
    }
    f->n_refs = n;
  }
  static const char *const centrals[] = {"none", "S", "optional", NULL};
  int central = 0;
  POM_TRY(pom_cfg_choice(cfg, "central_joint", centrals, &central, err));
  f->central = (pom_af_central)central;
  static const char *const modes[] = {"home", NULL};
  int mode = 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "assembly_mode", modes, 0, &mode, err));

  char kind[32];
  pom_actuator_kind ak;
  POM_TRY(pom_cfg_string(cfg, "actuator", kind, sizeof kind, err));
  if (!pom_act_kind_parse(kind, &ak))
    return pom_cfg_error(cfg, "actuator", NULL, err, "expected \"linear\" or \"rotary\"");
  const pom_act_desc *u = pom_act_kind_desc(ak);
  char key[64];
  snprintf(key, sizeof key, "default_%s%s", u->range_word, u->key_suffix);
  POM_TRY(pom_cfg_real(cfg, key, 1.0 / u->to_display, 0.01, u->range_max, &f->type.default_stroke,
                       err));
  f->type.actuator = ak;
  return POM_OK;
}

static pom_status load_params(pom_arch_file *f, const pom_cfg *cfg, scope *s, pom_error *err) {
  char key[160];
  /* the scale */
  POM_TRY(pom_cfg_string(cfg, "scale.key", f->scale_key, sizeof f->scale_key, err));
  size_t n = strlen(f->scale_key);
  if (n < 4 || strcmp(f->scale_key + n - 3, "_mm") != 0)
    return pom_cfg_error(cfg, "scale.key", NULL, err,
                         "the scale is a length in mm: its key ends in _mm");
  POM_TRY(pom_cfg_string(cfg, "scale.meaning", f->scale_meaning, sizeof f->scale_meaning, err));
  POM_TRY(pom_cfg_string(cfg, "scale.symbol", f->scale_symbol, sizeof f->scale_symbol, err));
  POM_TRY(pom_cfg_bool(cfg, "scale.sets_kinematics", &f->type.scale_sets_kinematics, err));
  if (!pom_cfg_has(cfg, "parameters"))
    return pom_cfg_error(cfg, "parameters", NULL, err,
                         "missing: expected a list of design parameters ( { key = ...; }, ... )");
  int np = pom_cfg_length(cfg, "parameters");
  if (!pom_cfg_is_list(cfg, "parameters"))
    return pom_cfg_error(cfg, "parameters", NULL, err, "expected a list ( { key = ...; }, ... )");
  if (np > POM_KIN_MAX_PARAMS)
    return pom_cfg_error(cfg, "parameters", NULL, err, "more than %d design parameters",
                         POM_KIN_MAX_PARAMS);
  for (int k = 0; k < np; ++k) {
    pom_kin_param_desc *p = &f->params[k];
    snprintf(key, sizeof key, "parameters.[%d].key", k);
    POM_TRY(pom_cfg_string(cfg, key, f->param_key[k], sizeof f->param_key[k], err));
    if (!pom_expr_identifier(f->param_key[k]))
      return pom_cfg_error(cfg, key, NULL, err, "a config key: letters, digits and '_'");
    if (strcmp(f->param_key[k], f->scale_key) == 0 || strcmp(f->param_key[k], "mode") == 0 ||
        strcmp(f->param_key[k], "central_joint") == 0)
      return pom_cfg_error(cfg, key, NULL, err, "taken (the scale, mode or central_joint)");
    for (int j = 0; j < k; ++j)
      if (strcmp(f->param_key[j], f->param_key[k]) == 0)
        return pom_cfg_error(cfg, key, NULL, err, "a second parameter with this key");
    double to_si = suffix_to_si(f->param_key[k]);
    if (to_si != 1.0 && to_si != POM_DEG)
      return pom_cfg_error(cfg, key, NULL, err,
                           "a design parameter is an angle (_deg) or a ratio to the scale (no "
                           "unit suffix)");
    p->key = f->param_key[k];
    p->to_si = to_si;
    snprintf(key, sizeof key, "parameters.[%d].symbol", k);
    POM_TRY(pom_cfg_string(cfg, key, f->param_symbol[k], sizeof f->param_symbol[k], err));
    POM_TRY(check_name(cfg, key, f->param_symbol[k], s, err));
    if (strcmp(f->param_symbol[k], f->scale_symbol) == 0)
      return pom_cfg_error(cfg, key, NULL, err, "already the scale's symbol");
    add_var(s, f->param_symbol[k], POM_EXPR_SCALAR);
    snprintf(key, sizeof key, "parameters.[%d].meaning", k);
    POM_TRY(pom_cfg_string(cfg, key, f->param_meaning[k], sizeof f->param_meaning[k], err));
    p->meaning = f->param_meaning[k];
    snprintf(key, sizeof key, "parameters.[%d].range", k);
    POM_TRY(read_range(cfg, key, &p->lo, &p->hi, err));
    snprintf(key, sizeof key, "parameters.[%d].default", k);
    p->optional = pom_cfg_has(cfg, key);
    if (p->optional) POM_TRY(pom_cfg_real(cfg, key, 1.0, p->lo, p->hi, &p->def, err));
    snprintf(key, sizeof key, "parameters.[%d].synth", k);
    POM_TRY(pom_cfg_bool_opt(cfg, key, 0, &p->synth, err));
    snprintf(key, sizeof key, "parameters.[%d].integer", k);
    POM_TRY(pom_cfg_bool_opt(cfg, key, 0, &p->integer, err));
    if (p->integer && p->synth)
      return pom_cfg_error(cfg, key, NULL, err,
                           "a whole-number choice cannot be a synthesis variable");
    snprintf(key, sizeof key, "parameters.[%d].source", k);
    POM_TRY(read_string(cfg, key, 0, "", f->param_source[k], sizeof f->param_source[k], err));
  }
  /* the scale symbol after the parameters: slots 0..np-1 are d->x, np the scale */
  POM_TRY(check_name(cfg, "scale.symbol", f->scale_symbol, s, err));
  add_var(s, f->scale_symbol, POM_EXPR_SCALAR);
  f->type.n_params = np;
  f->type.params = f->params;
  f->type.scale_key = f->scale_key;
  f->type.scale_meaning = f->scale_meaning;
  return POM_OK;
}

static pom_status load_values(pom_arch_file *f, const pom_cfg *cfg, pom_error *err) {
  char key[160];
  if (!pom_cfg_has(cfg, "inertia_values")) return POM_OK;
  int n = pom_cfg_length(cfg, "inertia_values");
  if (!pom_cfg_is_list(cfg, "inertia_values") || n > POM_KIN_MAX_INERTIA_VALUES)
    return pom_cfg_error(cfg, "inertia_values", NULL, err,
                         "expected a list of at most %d values ( { key = ...; }, ... )",
                         POM_KIN_MAX_INERTIA_VALUES);
  for (int k = 0; k < n; ++k) {
    pom_kin_value_desc *v = &f->values[k];
    snprintf(key, sizeof key, "inertia_values.[%d].key", k);
    POM_TRY(pom_cfg_string(cfg, key, f->value_key[k], sizeof f->value_key[k], err));
    if (!pom_expr_identifier(f->value_key[k]))
      return pom_cfg_error(cfg, key, NULL, err, "a config key: letters, digits and '_'");
    for (int j = 0; j < k; ++j)
      if (strcmp(f->value_key[j], f->value_key[k]) == 0)
        return pom_cfg_error(cfg, key, NULL, err, "a second value with this key");
    v->key = f->value_key[k];
    v->to_si = suffix_to_si(v->key);
    snprintf(key, sizeof key, "inertia_values.[%d].meaning", k);
    POM_TRY(pom_cfg_string(cfg, key, f->value_meaning[k], sizeof f->value_meaning[k], err));
    v->meaning = f->value_meaning[k];
    snprintf(key, sizeof key, "inertia_values.[%d].range", k);
    POM_TRY(read_range(cfg, key, &v->lo, &v->hi, err));
    snprintf(key, sizeof key, "inertia_values.[%d].default", k);
    v->optional = pom_cfg_has(cfg, key);
    if (v->optional) POM_TRY(pom_cfg_real(cfg, key, 1.0, v->lo, v->hi, &v->def, err));
  }
  f->type.n_inertia_values = n;
  f->type.inertia_values = f->values;
  return POM_OK;
}

/* The index of inertia value `key` named at cfg key `at` (required or -1). */
static pom_status value_index(const pom_arch_file *f, const pom_cfg *cfg, const char *at,
                              int required, int *index, pom_error *err) {
  char name[64];
  *index = -1;
  if (!required && !pom_cfg_has(cfg, at)) return POM_OK;
  POM_TRY(pom_cfg_string(cfg, at, name, sizeof name, err));
  for (int k = 0; k < f->type.n_inertia_values; ++k)
    if (strcmp(f->value_key[k], name) == 0) *index = k;
  if (*index < 0) return pom_cfg_error(cfg, at, NULL, err, "not one of the inertia_values keys");
  return POM_OK;
}

static pom_status joint_type_of(const pom_cfg *cfg, const char *key, pom_joint_type *t,
                                pom_error *err) {
  static const char *const types[] = {"R", "P", "U", "S", NULL};
  static const pom_joint_type map[] = {POM_JOINT_REVOLUTE, POM_JOINT_PRISMATIC, POM_JOINT_UNIVERSAL,
                                       POM_JOINT_SPHERICAL};
  int k = 0;
  POM_TRY(pom_cfg_choice(cfg, key, types, &k, err));
  *t = map[k];
  return POM_OK;
}

/* The two bodies of the limb table at `base` (`<base>.bodies`, a list of
 * 2): names, models, inertia groups and placement rules into out; their
 * expressions are compiled by load_limb_table. */
static pom_status load_bodies(pom_arch_file *f, const pom_cfg *cfg, const char *base,
                              pom_af_body out[2], pom_error *err) {
  char key[160];
  snprintf(key, sizeof key, "%s.bodies", base);
  if (!pom_cfg_is_list(cfg, key) || pom_cfg_length(cfg, key) != 2)
    return pom_cfg_error(cfg, key, NULL, err,
                         "expected a list of exactly 2 limb bodies (between joints 1-2 and 2-3)");
  for (int b = 0; b < 2; ++b) {
    pom_af_body *bd = &out[b];
    memset(bd, 0, sizeof *bd);
    snprintf(key, sizeof key, "%s.bodies.[%d].name", base, b);
    POM_TRY(pom_cfg_string(cfg, key, bd->name, sizeof bd->name - 2, err));
    if (!pom_expr_identifier(bd->name))
      return pom_cfg_error(cfg, key, NULL, err, "a body name: letters, digits and '_'");
    if (b == 1 && strcmp(bd->name, out[0].name) == 0)
      return pom_cfg_error(cfg, key, NULL, err, "the two bodies need different names");
    static const char *const models[] = {"rigid", "arc", NULL};
    int model = 0;
    snprintf(key, sizeof key, "%s.bodies.[%d].model", base, b);
    POM_TRY(pom_cfg_choice_opt(cfg, key, models, 0, &model, err));
    bd->model = (pom_af_body_model)model;
    bd->value_mass = bd->value_axial = bd->value_density = bd->value_section = -1;
    if (bd->model == POM_AF_BODY_RIGID) {
      snprintf(key, sizeof key, "%s.bodies.[%d].inertia", base, b);
      POM_TRY(pom_cfg_string(cfg, key, bd->group, sizeof bd->group, err));
      if (!pom_expr_identifier(bd->group) || strcmp(bd->group, "platform") == 0)
        return pom_cfg_error(cfg, key, NULL, err,
                             "an inertia group name (letters, digits, '_'; not platform)");
      if (b == 1 && out[0].model == POM_AF_BODY_RIGID && strcmp(bd->group, out[0].group) == 0)
        return pom_cfg_error(cfg, key, NULL, err, "the two bodies need different groups");
      static const char *const rules[] = {"at", "offset", "fraction", NULL};
      int rule = 0;
      snprintf(key, sizeof key, "%s.bodies.[%d].cm", base, b);
      POM_TRY(pom_cfg_choice(cfg, key, rules, &rule, err));
      bd->cm = (pom_af_cm_rule)rule;
      snprintf(key, sizeof key, "%s.bodies.[%d].x_axis", base, b);
      bd->has_x_axis = pom_cfg_has(cfg, key);
    } else {
      snprintf(key, sizeof key, "%s.bodies.[%d].density", base, b);
      POM_TRY(value_index(f, cfg, key, 1, &bd->value_density, err));
      snprintf(key, sizeof key, "%s.bodies.[%d].section", base, b);
      POM_TRY(value_index(f, cfg, key, 1, &bd->value_section, err));
      snprintf(key, sizeof key, "%s.bodies.[%d].point_mass", base, b);
      if (pom_cfg_has(cfg, key)) {
        snprintf(key, sizeof key, "%s.bodies.[%d].point_mass.mass", base, b);
        POM_TRY(value_index(f, cfg, key, 1, &bd->value_mass, err));
        snprintf(key, sizeof key, "%s.bodies.[%d].point_mass.axial_inertia", base, b);
        POM_TRY(value_index(f, cfg, key, 0, &bd->value_axial, err));
      }
    }
  }
  return POM_OK;
}

/* Limb tables after the first describe the same bodies. */
static int same_bodies(const pom_af_body a[2], const pom_af_body b[2]) {
  for (int k = 0; k < 2; ++k)
    if (strcmp(a[k].name, b[k].name) != 0 || a[k].model != b[k].model ||
        strcmp(a[k].group, b[k].group) != 0 || a[k].cm != b[k].cm ||
        a[k].has_x_axis != b[k].has_x_axis || a[k].value_density != b[k].value_density ||
        a[k].value_section != b[k].value_section || a[k].value_mass != b[k].value_mass ||
        a[k].value_axial != b[k].value_axial)
      return 0;
  return 1;
}

/* One limb table at cfg group `base` ("limbs" or "limbs.[1]"); s holds the
 * global scope. */
static pom_status load_limb_table(pom_arch_file *f, const pom_cfg *cfg, const char *base, scope s,
                                  pom_af_limb_table *t, pom_error *err) {
  char key[160];
  add_var(&s, "i", POM_EXPR_SCALAR);
  snprintf(key, sizeof key, "%s.azimuth", base);
  POM_TRY(compile_at(cfg, key, &s, POM_EXPR_SCALAR, &t->azimuth, err));
  add_var(&s, "eta", POM_EXPR_SCALAR);
  add_var(&s, "er", POM_EXPR_VECTOR);
  add_var(&s, "et", POM_EXPR_VECTOR);
  add_var(&s, "ez", POM_EXPR_VECTOR);
  snprintf(key, sizeof key, "%s.let", base);
  POM_TRY(load_lets(cfg, key, &s, t->let, &t->n_lets, err));
  t->n_slots = s.slots;

  /* joints */
  snprintf(key, sizeof key, "%s.joints", base);
  if (!pom_cfg_is_list(cfg, key) || pom_cfg_length(cfg, key) != 3)
    return pom_cfg_error(cfg, key, NULL, err,
                         "expected a list of exactly 3 joints, base to platform ( { type = ...; "
                         "}, ... )");
  int n_act = 0;
  for (int j = 0; j < 3; ++j) {
    pom_af_joint *jt = &t->joint[j];
    snprintf(key, sizeof key, "%s.joints.[%d].name", base, j);
    POM_TRY(pom_cfg_string(cfg, key, jt->name, sizeof jt->name - 2, err));
    snprintf(key, sizeof key, "%s.joints.[%d].type", base, j);
    POM_TRY(joint_type_of(cfg, key, &jt->type, err));
    snprintf(key, sizeof key, "%s.joints.[%d].point", base, j);
    POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &jt->point, err));
    snprintf(key, sizeof key, "%s.joints.[%d].axis", base, j);
    if (jt->type != POM_JOINT_SPHERICAL) {
      POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &jt->axis, err));
    } else if (pom_cfg_has(cfg, key)) {
      return pom_cfg_error(cfg, key, NULL, err, "a spherical joint (S) has no axis");
    }
    snprintf(key, sizeof key, "%s.joints.[%d].axis2", base, j);
    if (jt->type == POM_JOINT_UNIVERSAL) {
      POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &jt->axis2, err));
    } else if (pom_cfg_has(cfg, key)) {
      return pom_cfg_error(cfg, key, NULL, err, "only a universal joint (U) has a second axis");
    }
    snprintf(key, sizeof key, "%s.joints.[%d].actuated", base, j);
    POM_TRY(pom_cfg_bool_opt(cfg, key, 0, &jt->actuated, err));
    if (jt->actuated) {
      ++n_act;
      if (jt->type != pom_act_kind_desc(f->type.actuator)->joint)
        return pom_cfg_error(cfg, key, NULL, err,
                             "the actuated joint of a %s actuator is %s, not %s",
                             pom_act_kind_desc(f->type.actuator)->name,
                             pom_joint_type_name(pom_act_kind_desc(f->type.actuator)->joint),
                             pom_joint_type_name(jt->type));
    }
  }
  snprintf(key, sizeof key, "%s.joints", base);
  if (n_act != 1)
    return pom_cfg_error(cfg, key, NULL, err,
                         "exactly one joint of a limb is actuated (actuated = true), here %d",
                         n_act);

  /* working mode */
  snprintf(key, sizeof key, "%s.branch", base);
  t->branch = 0;
  if (pom_cfg_has(cfg, key)) {
    char b[16];
    long v = 0;
    if (pom_cfg_string_opt(cfg, key, "home", b, sizeof b, NULL) == POM_OK) {
      if (strcmp(b, "home") != 0)
        return pom_cfg_error(cfg, key, NULL, err, "expected \"home\", +1 or -1");
    } else {
      POM_TRY(pom_cfg_int(cfg, key, -1, 1, &v, err));
      if (v == 0) return pom_cfg_error(cfg, key, NULL, err, "expected \"home\", +1 or -1");
      t->branch = (int)v;
    }
  }

  /* bodies: the first table's define them, the others repeat them */
  pom_af_body bodies[2];
  POM_TRY(load_bodies(f, cfg, base, bodies, err));
  if (t == &f->limb[0]) {
    memcpy(f->body, bodies, sizeof bodies);
    int n_groups = 0;
    for (int b = 0; b < 2; ++b)
      if (bodies[b].model == POM_AF_BODY_RIGID) {
        f->inertia_bodies[n_groups].group = f->body[b].group;
        f->inertia_bodies[n_groups].place = (int)f->body[b].cm;
        ++n_groups;
      }
    f->type.n_inertia_bodies = n_groups;
    f->type.inertia_bodies = n_groups ? f->inertia_bodies : NULL;
  } else if (!same_bodies(bodies, f->body)) {
    snprintf(key, sizeof key, "%s.bodies", base);
    return pom_cfg_error(cfg, key, NULL, err,
                         "the three limb tables describe the same bodies (name, model, inertia, "
                         "cm, x_axis given or not, values) as limb 1's");
  }
  for (int b = 0; b < 2; ++b) {
    const pom_af_body *bd = &f->body[b];
    if (bd->model == POM_AF_BODY_RIGID) {
      snprintf(key, sizeof key, "%s.bodies.[%d].from", base, b);
      POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_from[b], err));
      snprintf(key, sizeof key, "%s.bodies.[%d].axis", base, b);
      POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_axis[b], err));
      snprintf(key, sizeof key, "%s.bodies.[%d].x_axis", base, b);
      if (bd->has_x_axis) POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_x[b], err));
      if (bd->cm == POM_AF_CM_OFFSET) {
        snprintf(key, sizeof key, "%s.bodies.[%d].along", base, b);
        POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_to[b], err));
      } else if (bd->cm == POM_AF_CM_FRACTION) {
        snprintf(key, sizeof key, "%s.bodies.[%d].to", base, b);
        POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_to[b], err));
      }
    } else {
      snprintf(key, sizeof key, "%s.bodies.[%d].from", base, b);
      POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_from[b], err));
      snprintf(key, sizeof key, "%s.bodies.[%d].to", base, b);
      POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_to[b], err));
      snprintf(key, sizeof key, "%s.bodies.[%d].radius", base, b);
      POM_TRY(compile_at(cfg, key, &s, POM_EXPR_SCALAR, &t->body_radius[b], err));
      if (bd->value_mass >= 0) {
        snprintf(key, sizeof key, "%s.bodies.[%d].point_mass.at", base, b);
        POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_at[b], err));
      }
      if (bd->value_axial >= 0) {
        snprintf(key, sizeof key, "%s.bodies.[%d].point_mass.axis", base, b);
        POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->body_mass_axis[b], err));
      }
    }
  }
  return POM_OK;
}

static pom_status load_limits(pom_arch_file *f, const pom_cfg *cfg, pom_error *err) {
  char key[160];
  if (!pom_cfg_has(cfg, "limits")) return POM_OK;
  int n = pom_cfg_length(cfg, "limits");
  if (!pom_cfg_is_list(cfg, "limits") || n > POM_KIN_LIM_KINDS - 1)
    return pom_cfg_error(cfg, "limits", NULL, err, "expected a list of at most %d limit kinds",
                         POM_KIN_LIM_KINDS - 1);
  for (int k = 0; k < n; ++k) {
    pom_kin_limit_desc *ld = &f->type.limits[k + 1];
    pom_af_limit *lm = &f->limit[k + 1];
    snprintf(key, sizeof key, "limits.[%d].name", k);
    POM_TRY(pom_cfg_string(cfg, key, f->limit_name[k + 1], sizeof f->limit_name[k + 1], err));
    snprintf(key, sizeof key, "limits.[%d].key", k);
    POM_TRY(pom_cfg_string(cfg, key, f->limit_key[k + 1], sizeof f->limit_key[k + 1], err));
    snprintf(key, sizeof key, "limits.[%d].json", k);
    POM_TRY(pom_cfg_string(cfg, key, f->limit_json[k + 1], sizeof f->limit_json[k + 1], err));
    static const char *const measures[] = {"cone", "distance", "axis_angle", NULL};
    int m = 0;
    snprintf(key, sizeof key, "limits.[%d].measure", k);
    POM_TRY(pom_cfg_choice(cfg, key, measures, &m, err));
    lm->measure = (pom_af_measure)m;
    const char *want = lm->measure == POM_AF_MEASURE_DISTANCE ? "_mm" : "_deg";
    size_t kl = strlen(f->limit_key[k + 1]);
    snprintf(key, sizeof key, "limits.[%d].key", k);
    if (kl < 4 || strcmp(f->limit_key[k + 1] + kl - strlen(want), want) != 0)
      return pom_cfg_error(cfg, key, NULL, err, "a %s limit's key ends in %s", measures[m], want);
    long ja = 0, jb = 0;
    snprintf(key, sizeof key, "limits.[%d].joints", k);
    if (lm->measure == POM_AF_MEASURE_AXIS_ANGLE) {
      snprintf(key, sizeof key, "limits.[%d].joint", k);
      POM_TRY(pom_cfg_int(cfg, key, 1, 3, &ja, err));
      jb = ja;
    } else {
      double jj[2];
      POM_TRY(pom_cfg_reals(cfg, key, 2, 1.0, 1.0, 3.0, jj, err));
      if (jj[0] != floor(jj[0]) || jj[1] != floor(jj[1]) || !(jj[0] < jj[1]))
        return pom_cfg_error(cfg, key, NULL, err,
                             "expected [a, b]: joints a < b of the limb (1, 2, 3) whose points "
                             "bound the segment");
      ja = (long)jj[0];
      jb = (long)jj[1];
    }
    lm->joint_a = (int)ja - 1;
    lm->joint_b = (int)jb - 1;
    static const char *const frames[] = {"fixed", "platform", NULL};
    int fr = 0;
    snprintf(key, sizeof key, "limits.[%d].frame", k);
    if (lm->measure == POM_AF_MEASURE_CONE) {
      POM_TRY(pom_cfg_choice(cfg, key, frames, &fr, err));
    } else if (pom_cfg_has(cfg, key)) {
      return pom_cfg_error(cfg, key, NULL, err, "only a cone has a frame");
    }
    lm->frame_platform = fr;
    static const char *const bounds[] = {"upper", "lower", NULL};
    int lower = 0;
    snprintf(key, sizeof key, "limits.[%d].bound", k);
    POM_TRY(pom_cfg_choice(cfg, key, bounds, &lower, err));
    ld->name = f->limit_name[k + 1];
    ld->key = f->limit_key[k + 1];
    ld->json = f->limit_json[k + 1];
    ld->per_pair = lm->measure != POM_AF_MEASURE_CONE;
    ld->lower = lower;
    ld->unit = lm->measure == POM_AF_MEASURE_DISTANCE ? "mm" : "deg";
    ld->to_display = lm->measure == POM_AF_MEASURE_DISTANCE ? 1e3 : 1.0 / POM_DEG;
    ld->cls =
        lm->measure == POM_AF_MEASURE_CONE ? POM_KIN_LIMCLASS_CONE : POM_KIN_LIMCLASS_INTERFERENCE;
    snprintf(key, sizeof key, "limits.[%d].range", k);
    POM_TRY(read_range(cfg, key, &ld->lo, &ld->hi, err));
    double def;
    snprintf(key, sizeof key, "limits.[%d].default", k);
    POM_TRY(pom_cfg_real(cfg, key, 1.0, ld->lo, ld->hi, &def, err));
    ld->def = def / ld->to_display;
    for (int j = 1; j <= k; ++j)
      if (strcmp(f->limit_key[j], ld->key) == 0 || strcmp(f->limit_json[j], ld->json) == 0) {
        snprintf(key, sizeof key, "limits.[%d].key", k);
        return pom_cfg_error(cfg, key, NULL, err, "a second limit with this key or json name");
      }
  }
  return POM_OK;
}

/* ---- load ----------------------------------------------------------------------- */
static pom_status from_design(pom_kin_arch *arch, const pom_kin_design *d, pom_error *err);

static pom_status load(pom_arch_file *f, const pom_cfg *cfg, pom_error *err) {
  static const char *const top[] = {"format",
                                    "name",
                                    "label",
                                    "description",
                                    "references",
                                    "unreachable",
                                    "actuator",
                                    "central_joint",
                                    "assembly_mode",
                                    "default_stroke_mm",
                                    "default_range_deg",
                                    "scale",
                                    "parameters",
                                    "inertia_values",
                                    "let",
                                    "limbs",
                                    "limits",
                                    NULL};
  scope s;
  memset(&s, 0, sizeof s);
  POM_TRY(load_head(f, cfg, err));
  POM_TRY(load_params(f, cfg, &s, err));
  POM_TRY(load_values(f, cfg, err));
  POM_TRY(load_lets(cfg, "let", &s, f->global, &f->n_globals, err));
  f->global_slots = s.slots;
  if (!pom_cfg_has(cfg, "limbs"))
    return pom_cfg_error(cfg, "limbs", NULL, err,
                         "missing: one limb table { symmetry = \"C3\"; ... } or a list of 3");
  char base[64];
  if (pom_cfg_is_list(cfg, "limbs")) {
    if (pom_cfg_length(cfg, "limbs") != 3)
      return pom_cfg_error(cfg, "limbs", NULL, err,
                           "a list of limb tables holds exactly 3 (one per limb)");
    f->per_limb = 1;
    for (int i = 0; i < 3; ++i) {
      snprintf(base, sizeof base, "limbs.[%d]", i);
      POM_TRY(load_limb_table(f, cfg, base, s, &f->limb[i], err));
      for (int j = 0; j < 3; ++j)
        if (i > 0 && (f->limb[i].joint[j].type != f->limb[0].joint[j].type ||
                      f->limb[i].joint[j].actuated != f->limb[0].joint[j].actuated)) {
          char key[96];
          snprintf(key, sizeof key, "limbs.[%d].joints.[%d].type", i, j);
          return pom_cfg_error(cfg, key, NULL, err,
                               "the three limbs have the same joint types and actuated joint "
                               "(limb 1's joint %d differs)",
                               j + 1);
        }
    }
  } else {
    static const char *const sym[] = {"C3", NULL};
    int k = 0;
    POM_TRY(pom_cfg_choice(cfg, "limbs.symmetry", sym, &k, err));
    POM_TRY(load_limb_table(f, cfg, "limbs", s, &f->limb[0], err));
  }
  POM_TRY(load_limits(f, cfg, err));
  POM_TRY(pom_cfg_check_unknown(cfg, NULL, top, err));

  pom_kin_arch_type *t = &f->type;
  t->name = f->name;
  t->label = f->label;
  t->description = f->description;
  t->unreachable = f->unreachable;
  t->optional_central_joint = f->central == POM_AF_CENTRAL_OPTIONAL;
  t->n_points = 0;
  t->points = NULL;
  t->from_design = from_design;
  return POM_OK;
}

pom_status pom_arch_file_load(pom_arch_file **out, const char *path, pom_error *err) {
  *out = NULL;
  pom_cfg *cfg = NULL;
  POM_TRY(pom_cfg_load(&cfg, path, err));
  pom_arch_file *f = calloc(1, sizeof *f);
  if (!f) {
    pom_cfg_destroy(cfg);
    POM_FAIL(err, POM_ERR_NOMEM, "%s: out of memory", path);
  }
  snprintf(f->path, sizeof f->path, "%s", path);
  pom_status st = load(f, cfg, err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    free(f);
    return st;
  }
  *out = f;
  return POM_OK;
}

void pom_arch_file_destroy(pom_arch_file *f) {
  free(f);
}

const pom_arch_file *pom_arch_file_of(const pom_kin_arch_type *t) {
  if (!t || t->from_design != from_design) return NULL;
  return (const pom_arch_file *)(const void *)t;
}

/* ---- evaluation ------------------------------------------------------------------ */
static pom_status eval_fail(const pom_arch_file *f, const pom_af_expr *x, int limb, pom_error *err,
                            const char *what) {
  char where[32] = "";
  if (limb >= 0) snprintf(where, sizeof where, " (limb %d)", limb + 1);
  POM_FAIL(err, POM_ERR_ARG, "%s:%d: key '%s' = \"%s\"%s: %s", f->path, x->line, x->key, x->text,
           where, what);
}

static pom_status eval_expr(const pom_arch_file *f, const pom_af_expr *x, const double *slots,
                            int limb, double out[3], pom_error *err) {
  if (pom_expr_eval(&x->e, slots, out) != POM_OK)
    return eval_fail(f, x, limb, err,
                     "not finite at this design (a square root of a negative number, acos or "
                     "asin beyond 1, a division by zero?)");
  return POM_OK;
}

/* Evaluates a direction and makes it unit; a zero vector is an error. */
static pom_status eval_unit(const pom_arch_file *f, const pom_af_expr *x, const double *slots,
                            int limb, double out[3], pom_error *err) {
  POM_TRY(eval_expr(f, x, slots, limb, out, err));
  if (!(pom_v3_normalize(out, out) > 0.0))
    return eval_fail(f, x, limb, err, "a zero vector where a direction is needed");
  return POM_OK;
}

#define AF_MAX_SLOTS (POM_KIN_MAX_PARAMS + 1 + 3 * 2 * POM_AF_MAX_LETS + LV_COUNT)

pom_status pom_arch_file_eval(const pom_arch_file *f, const pom_kin_design *d, pom_af_geometry *g,
                              pom_error *err) {
  double slots[AF_MAX_SLOTS], v[3];
  const int np = f->type.n_params;
  memset(g, 0, sizeof *g);
  for (int k = 0; k < np; ++k)
    slots[k] = d->x[k];
  slots[np] = d->scale;
  for (int k = 0; k < f->n_globals; ++k) {
    const pom_af_let *l = &f->global[k];
    POM_TRY(eval_expr(f, &l->value, slots, -1, v, err));
    memcpy(slots + l->slot, v, sizeof(double) * (size_t)l->value.e.kind);
  }
  const int lv = f->global_slots;
  for (int i = 0; i < 3; ++i) {
    const pom_af_limb_table *t = &f->limb[f->per_limb ? i : 0];
    pom_af_limb_num *L = &g->limb[i];
    slots[lv + LV_I] = (double)i;
    POM_TRY(eval_expr(f, &t->azimuth, slots, i, v, err));
    /* C3 symmetry: limb i at the azimuth of limb 1 plus i 120 deg */
    double eta = f->per_limb ? v[0] : v[0] + 2.0 * POM_PI * i / 3.0;
    L->azimuth = eta;
    double *s = slots + lv;
    s[LV_ETA] = eta;
    s[LV_ER] = cos(eta);
    s[LV_ER + 1] = sin(eta);
    s[LV_ER + 2] = 0.0;
    s[LV_ET] = -sin(eta);
    s[LV_ET + 1] = cos(eta);
    s[LV_ET + 2] = 0.0;
    s[LV_EZ] = 0.0;
    s[LV_EZ + 1] = 0.0;
    s[LV_EZ + 2] = 1.0;
    pom_v3_copy(L->er, s + LV_ER);
    for (int k = 0; k < t->n_lets; ++k) {
      const pom_af_let *l = &t->let[k];
      POM_TRY(eval_expr(f, &l->value, slots, i, v, err));
      memcpy(slots + l->slot, v, sizeof(double) * (size_t)l->value.e.kind);
    }
    for (int j = 0; j < 3; ++j) {
      const pom_af_joint *jt = &t->joint[j];
      pom_af_joint_num *J = &L->joint[j];
      J->type = jt->type;
      J->actuated = jt->actuated;
      POM_TRY(eval_expr(f, &jt->point, slots, i, J->point, err));
      if (jt->type != POM_JOINT_SPHERICAL) POM_TRY(eval_unit(f, &jt->axis, slots, i, J->axis, err));
      if (jt->type == POM_JOINT_UNIVERSAL) {
        POM_TRY(eval_unit(f, &jt->axis2, slots, i, J->axis2, err));
        double c = pom_v3_dot(J->axis, J->axis2);
        if (fabs(c) > 1e-9) {
          char what[160];
          snprintf(what, sizeof what,
                   "the second axis of a universal joint is normal to its first (cos = %.3g)", c);
          return eval_fail(f, &jt->axis2, i, err, what);
        }
      }
    }
    L->branch = t->branch;
    for (int b = 0; b < 2; ++b) {
      const pom_af_body *bd = &f->body[b];
      pom_af_body_num *B = &L->body[b];
      B->model = bd->model;
      if (bd->model == POM_AF_BODY_RIGID) {
        POM_TRY(eval_expr(f, &t->body_from[b], slots, i, B->from, err));
        POM_TRY(eval_unit(f, &t->body_axis[b], slots, i, B->axis, err));
        if (bd->has_x_axis) {
          POM_TRY(eval_unit(f, &t->body_x[b], slots, i, B->x_axis, err));
          if (fabs(pom_v3_dot(B->x_axis, B->axis)) > 1e-9)
            return eval_fail(f, &t->body_x[b], i, err,
                             "a body's x axis is normal to its principal z axis");
        }
        if (bd->cm == POM_AF_CM_OFFSET)
          POM_TRY(eval_unit(f, &t->body_to[b], slots, i, B->dir, err));
        if (bd->cm == POM_AF_CM_FRACTION)
          POM_TRY(eval_expr(f, &t->body_to[b], slots, i, B->to, err));
      } else {
        POM_TRY(eval_unit(f, &t->body_from[b], slots, i, B->arc_from, err));
        POM_TRY(eval_unit(f, &t->body_to[b], slots, i, B->arc_to, err));
        POM_TRY(eval_expr(f, &t->body_radius[b], slots, i, v, err));
        if (!(v[0] > 0.0)) return eval_fail(f, &t->body_radius[b], i, err, "a radius is positive");
        B->radius = v[0];
        if (bd->value_mass >= 0) POM_TRY(eval_expr(f, &t->body_at[b], slots, i, B->mass_at, err));
        if (bd->value_axial >= 0)
          POM_TRY(eval_unit(f, &t->body_mass_axis[b], slots, i, B->mass_axis, err));
      }
    }
  }
  return POM_OK;
}

/* ---- the type's from_design --------------------------------------------------------- */
static pom_status from_design(pom_kin_arch *arch, const pom_kin_design *d, pom_error *err) {
  const pom_arch_file *f = pom_arch_file_of(arch->type);
  pom_af_geometry g;
  POM_TRY(pom_arch_file_eval(f, d, &g, err));
  POM_FAIL(err, POM_ERR_INTERNAL, "%s: the numeric limb table is not wired yet", f->name);
}

/* ---- discovery ------------------------------------------------------------------------ */
#ifndef POM_CATALOG_SOURCE_DIR
#define POM_CATALOG_SOURCE_DIR "catalog"
#endif

static int is_dir(const char *path) {
  struct stat sb;
  return path && path[0] && stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

/* The installed layout: PREFIX/bin/program -> PREFIX/share/pomlab/catalog. */
static int installed_dir(char *buf, size_t cap) {
  char exe[4096];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0 || (size_t)n >= sizeof exe - 1) return 0;
  exe[n] = '\0';
  char *slash = strrchr(exe, '/');
  if (!slash) return 0;
  *slash = '\0';
  snprintf(buf, cap, "%s/../share/pomlab/catalog", exe);
  return is_dir(buf);
}

const char *pom_arch_catalog_dir(void) {
  static _Thread_local char found[4200];
  const char *env = getenv("POMLAB_CATALOG");
  if (env && env[0]) return env;
  if (installed_dir(found, sizeof found)) return found;
  if (is_dir(POM_CATALOG_SOURCE_DIR)) return POM_CATALOG_SOURCE_DIR;
  return NULL;
}

static int name_cmp(const void *a, const void *b) {
  return strcmp(*(const char *const *)a, *(const char *const *)b);
}

pom_status pom_arch_catalog_each(const char *dir,
                                 pom_status (*fn)(const char *path, void *user, pom_error *err),
                                 void *user, pom_error *err) {
  enum { MAX_FILES = 64 };
  char names[MAX_FILES][256];
  const char *sorted[MAX_FILES];
  int n = 0;
  DIR *dp = opendir(dir);
  if (!dp)
    POM_FAIL(err, POM_ERR_IO, "%s: cannot open the architecture catalog: %s", dir, strerror(errno));
  for (struct dirent *e = readdir(dp); e; e = readdir(dp)) {
    size_t len = strlen(e->d_name);
    if (len < 6 || len >= sizeof names[0] || strcmp(e->d_name + len - 5, ".arch") != 0) continue;
    if (n == MAX_FILES) {
      closedir(dp);
      POM_FAIL(err, POM_ERR_ARG, "%s: more than %d architecture files", dir, MAX_FILES);
    }
    snprintf(names[n], sizeof names[n], "%s", e->d_name);
    sorted[n] = names[n];
    ++n;
  }
  closedir(dp);
  qsort(sorted, (size_t)n, sizeof sorted[0], name_cmp);
  for (int k = 0; k < n; ++k) {
    char path[4400];
    snprintf(path, sizeof path, "%s/%s", dir, sorted[k]);
    POM_TRY(fn(path, user, err));
  }
  return POM_OK;
}

/* ---- a process's files ------------------------------------------------------------------ */
static pom_status set_add(const char *path, void *user, pom_error *err) {
  pom_arch_file_set *set = user;
  if (set->n == POM_AF_MAX_FILES)
    POM_FAIL(err, POM_ERR_ARG, "%s: more than %d architecture files", path, POM_AF_MAX_FILES);
  pom_arch_file *f = NULL;
  POM_TRY(pom_arch_file_load(&f, path, err));
  for (int k = 0; k < set->n; ++k)
    if (strcmp(set->file[k]->name, f->name) == 0) {
      pom_status st = pom_error_set(err, POM_ERR_ARG, __FILE__, __LINE__,
                                    "%s: architecture name \"%s\" is already given by %s", path,
                                    f->name, set->file[k]->path);
      pom_arch_file_destroy(f);
      return st;
    }
  set->file[set->n++] = f;
  return POM_OK;
}

pom_status pom_arch_file_set_load(pom_arch_file_set *set, const char *catalog_dir,
                                  const char *extra, pom_error *err) {
  memset(set, 0, sizeof *set);
  pom_status st = POM_OK;
  if (catalog_dir) st = pom_arch_catalog_each(catalog_dir, set_add, set, err);
  for (const char *p = extra; st == POM_OK && p && *p;) {
    const char *colon = strchr(p, ':');
    size_t n = colon ? (size_t)(colon - p) : strlen(p);
    char path[4096];
    if (n >= sizeof path) {
      st = pom_error_set(err, POM_ERR_ARG, __FILE__, __LINE__,
                         "an architecture path of %zu characters is too long", n);
      break;
    }
    memcpy(path, p, n);
    path[n] = '\0';
    if (n > 0)
      st = is_dir(path) ? pom_arch_catalog_each(path, set_add, set, err) : set_add(path, set, err);
    p = colon ? colon + 1 : p + n;
  }
  if (st != POM_OK) pom_arch_file_set_free(set);
  return st;
}

void pom_arch_file_set_free(pom_arch_file_set *set) {
  for (int k = 0; k < set->n; ++k)
    pom_arch_file_destroy(set->file[k]);
  set->n = 0;
}
