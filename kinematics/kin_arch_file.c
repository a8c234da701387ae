/* kin_arch_file.c - architecture files (pom_arch_file.h, format of
 * docs/architecture-files.md): the loader that checks a file and compiles
 * its expressions, and the evaluation of the expressions at a design. */
#include "pom_arch_file.h"

#include "kin_internal.h"
#include "pom_config.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* pom_joint_type -> pom_limb_joint_type */
static int limb_joint_type(pom_joint_type t) {
  switch (t) {
  case POM_JOINT_REVOLUTE:
    return POM_LIMB_JOINT_R;
  case POM_JOINT_PRISMATIC:
    return POM_LIMB_JOINT_P;
  case POM_JOINT_UNIVERSAL:
    return POM_LIMB_JOINT_U;
  case POM_JOINT_SPHERICAL:
    return POM_LIMB_JOINT_S;
  }
  return POM_LIMB_JOINT_NONE;
}

/* A joint number 1..3 at key (0-based into *j). */
static pom_status read_joint(const pom_cfg *cfg, const char *key, int *j, pom_error *err) {
  long v = 0;
  POM_TRY(pom_cfg_int(cfg, key, 1, 3, &v, err));
  *j = (int)v - 1;
  return POM_OK;
}

/* A direction by joints at key: [a] the axis of joint a (not spherical),
 * [a, b] the unit segment from joint a's point to joint b's (1-based in the
 * file). types: the joint types of limb 1 (all limbs alike). */
static pom_status read_dir(const pom_cfg *cfg, const char *key, const pom_af_limb_table *t,
                           pom_limb_dir *d, pom_error *err) {
  int n = pom_cfg_length(cfg, key);
  double v[2] = {0.0, 0.0};
  if (!pom_cfg_has(cfg, key) || (n != 1 && n != 2))
    return pom_cfg_error(cfg, key, NULL, err,
                         "expected [a] (the axis of joint a) or [a, b] (from joint a's point to "
                         "joint b's), joints 1, 2, 3");
  POM_TRY(pom_cfg_reals(cfg, key, n, 1.0, 1.0, 3.0, v, err));
  if (v[0] != floor(v[0]) || (n == 2 && (v[1] != floor(v[1]) || v[1] == v[0])))
    return pom_cfg_error(cfg, key, NULL, err, "expected whole joint numbers, two different ones");
  d->a = (int)v[0] - 1;
  d->b = n == 2 ? (int)v[1] - 1 : -1;
  if (n == 1 && t->joint[d->a].type == POM_JOINT_SPHERICAL)
    return pom_cfg_error(cfg, key, NULL, err, "joint %d is spherical: it has no axis", d->a + 1);
  return POM_OK;
}

/* One limb table at cfg group `base` ("limbs" or "limbs.[1]"); s holds the
 * global scope. Its joint names and types are the table's when first, else
 * they must equal those of the first. */
static pom_status load_limb_table(pom_arch_file *f, const pom_cfg *cfg, const char *base, scope s,
                                  pom_af_limb_table *t, int first, pom_error *err) {
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

  /* joints */
  snprintf(key, sizeof key, "%s.joints", base);
  if (!pom_cfg_is_list(cfg, key) || pom_cfg_length(cfg, key) != 3)
    return pom_cfg_error(cfg, key, NULL, err,
                         "expected a list of exactly 3 joints, base to platform ( { type = ...; "
                         "}, ... )");
  int n_act = 0;
  for (int j = 0; j < 3; ++j) {
    pom_af_joint *jt = &t->joint[j];
    char name[POM_MECH_NAME_LEN];
    snprintf(key, sizeof key, "%s.joints.[%d].name", base, j);
    POM_TRY(pom_cfg_string(cfg, key, name, sizeof name, err));
    if (!pom_expr_identifier(name) || strlen(name) >= sizeof f->table.joint_name[j])
      return pom_cfg_error(cfg, key, NULL, err,
                           "a joint name: letters, digits and '_', at most %zu characters (the "
                           "mechanism appends the limb number)",
                           sizeof f->table.joint_name[j] - 1);
    if (first) {
      snprintf(f->table.joint_name[j], sizeof f->table.joint_name[j], "%s", name);
    } else if (strcmp(name, f->table.joint_name[j]) != 0) {
      return pom_cfg_error(cfg, key, NULL, err,
                           "the three limbs name their joints alike (limb "
                           "1's joint %d is %s)",
                           j + 1, f->table.joint_name[j]);
    }
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
    jt->has_axis2 = pom_cfg_has(cfg, key);
    if (jt->has_axis2 && jt->type != POM_JOINT_UNIVERSAL)
      return pom_cfg_error(cfg, key, NULL, err, "only a universal joint (U) has a second axis");
    if (jt->has_axis2) POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &jt->axis2, err));
    snprintf(key, sizeof key, "%s.joints.[%d].actuated", base, j);
    POM_TRY(pom_cfg_bool_opt(cfg, key, 0, &jt->actuated, err));
    if (jt->actuated) {
      ++n_act;
      const pom_act_desc *u = pom_act_kind_desc(f->type.actuator);
      if (jt->type != u->joint)
        return pom_cfg_error(cfg, key, NULL, err,
                             "the actuated joint of a %s actuator is %s, not %s", u->name,
                             pom_joint_type_name(u->joint), pom_joint_type_name(jt->type));
    }
  }
  snprintf(key, sizeof key, "%s.joints", base);
  if (n_act != 1)
    return pom_cfg_error(cfg, key, NULL, err,
                         "exactly one joint of a limb is actuated (actuated = true), here %d",
                         n_act);
  if (!first)
    for (int j = 0; j < 3; ++j)
      if (t->joint[j].type != f->limb[0].joint[j].type ||
          t->joint[j].actuated != f->limb[0].joint[j].actuated) {
        snprintf(key, sizeof key, "%s.joints.[%d].type", base, j);
        return pom_cfg_error(cfg, key, NULL, err,
                             "the three limbs have the same joint types and actuated joint "
                             "(limb 1's joint %d differs)",
                             j + 1);
      }
  /* a chain the numerics solve: the kernels of kinematics/pom_limb.h (its
   * header comment; finish refuses any other) */
  static const struct {
    pom_joint_type j[3];
    int actuated;
  } kernels[] = {
      {{POM_JOINT_REVOLUTE, POM_JOINT_REVOLUTE, POM_JOINT_REVOLUTE}, 0},
      {{POM_JOINT_PRISMATIC, POM_JOINT_SPHERICAL, POM_JOINT_SPHERICAL}, 0},
      {{POM_JOINT_REVOLUTE, POM_JOINT_SPHERICAL, POM_JOINT_SPHERICAL}, 0},
      {{POM_JOINT_SPHERICAL, POM_JOINT_PRISMATIC, POM_JOINT_SPHERICAL}, 1},
      {{POM_JOINT_UNIVERSAL, POM_JOINT_PRISMATIC, POM_JOINT_SPHERICAL}, 1},
      {{POM_JOINT_REVOLUTE, POM_JOINT_UNIVERSAL, POM_JOINT_UNIVERSAL}, 0},
      {{POM_JOINT_UNIVERSAL, POM_JOINT_PRISMATIC, POM_JOINT_UNIVERSAL}, 1},
  };
  int known = 0;
  for (size_t k = 0; k < sizeof kernels / sizeof kernels[0]; ++k)
    known |= kernels[k].j[0] == t->joint[0].type && kernels[k].j[1] == t->joint[1].type &&
             kernels[k].j[2] == t->joint[2].type && t->joint[kernels[k].actuated].actuated;
  if (!known)
    return pom_cfg_error(cfg, key, NULL, err,
                         "no inverse-kinematics kernel solves this chain with this actuated "
                         "joint: R-R-R (axes through O), P-S-S, R-S-S and R-U-U actuated at "
                         "joint 1; S-P-S, U-P-S and U-P-U actuated at joint 2 "
                         "(docs/architecture-files.md 1)");

  /* footprint point and working mode */
  snprintf(key, sizeof key, "%s.motor", base);
  t->has_motor = pom_cfg_has(cfg, key);
  if (t->has_motor) POM_TRY(compile_at(cfg, key, &s, POM_EXPR_VECTOR, &t->motor, err));
  snprintf(key, sizeof key, "%s.branch", base);
  t->branch = 0.0;
  if (pom_cfg_has(cfg, key)) {
    char b[16];
    long v = 0;
    if (pom_cfg_string_opt(cfg, key, "home", b, sizeof b, NULL) == POM_OK) {
      if (strcmp(b, "home") != 0)
        return pom_cfg_error(cfg, key, NULL, err, "expected \"home\", +1 or -1");
    } else {
      POM_TRY(pom_cfg_int(cfg, key, -1, 1, &v, err));
      if (v == 0) return pom_cfg_error(cfg, key, NULL, err, "expected \"home\", +1 or -1");
      t->branch = (double)v;
    }
  }
  return POM_OK;
}

/* The two limb bodies (`bodies`, a list of 2, chain order) into the
 * table's body rules and the type's inertia groups. */
static pom_status load_bodies(pom_arch_file *f, const pom_cfg *cfg, pom_error *err) {
  char key[160];
  const pom_af_limb_table *t = &f->limb[0];
  if (!pom_cfg_is_list(cfg, "bodies") || pom_cfg_length(cfg, "bodies") != 2)
    return pom_cfg_error(cfg, "bodies", NULL, err,
                         "expected a list of exactly 2 limb bodies (between joints 1-2 and 2-3)");
  int n_groups = 0, n_arcs = 0;
  for (int b = 0; b < 2; ++b) {
    pom_limb_body *bd = &f->table.body[b];
    memset(bd, 0, sizeof *bd);
    bd->cm_dir = bd->z_dir = bd->x_dir = (pom_limb_dir){-1, -1};
    bd->group = bd->arc_a = bd->arc_b = -1;
    bd->v_density = bd->v_section = bd->v_point_mass = bd->v_rotor = -1;
    bd->point_joint = bd->rotor_joint = -1;
    snprintf(key, sizeof key, "bodies.[%d].name", b);
    POM_TRY(pom_cfg_string(cfg, key, bd->name, sizeof bd->name, err));
    if (!pom_expr_identifier(bd->name) || strlen(bd->name) + 2 >= sizeof bd->name)
      return pom_cfg_error(cfg, key, NULL, err,
                           "a body name: letters, digits and '_', at most %zu characters (the "
                           "mechanism appends the limb number)",
                           sizeof bd->name - 3);
    if (b == 1 && strcmp(bd->name, f->table.body[0].name) == 0)
      return pom_cfg_error(cfg, key, NULL, err, "the two bodies need different names");
    static const char *const models[] = {"rigid", "arc", NULL};
    int model = 0;
    snprintf(key, sizeof key, "bodies.[%d].model", b);
    POM_TRY(pom_cfg_choice_opt(cfg, key, models, 0, &model, err));
    if (model == 0) {
      char *group = f->body_group[b];
      snprintf(key, sizeof key, "bodies.[%d].inertia", b);
      POM_TRY(pom_cfg_string(cfg, key, group, sizeof f->body_group[b], err));
      if (!pom_expr_identifier(group) || strcmp(group, "platform") == 0)
        return pom_cfg_error(cfg, key, NULL, err,
                             "an inertia group name (letters, digits, '_'; not platform)");
      if (n_groups == 1 && strcmp(group, f->inertia_bodies[0].group) == 0)
        return pom_cfg_error(cfg, key, NULL, err, "the two bodies need different groups");
      bd->model = POM_LIMB_MASS_GROUP;
      bd->group = n_groups;
      static const char *const rules[] = {"at", "offset", "fraction", NULL};
      int rule = 0;
      snprintf(key, sizeof key, "bodies.[%d].cm", b);
      POM_TRY(pom_cfg_choice(cfg, key, rules, &rule, err));
      bd->place = rule;
      if (rule == 1) {
        snprintf(key, sizeof key, "bodies.[%d].from", b);
        POM_TRY(read_joint(cfg, key, &bd->cm_from, err));
        snprintf(key, sizeof key, "bodies.[%d].along", b);
        POM_TRY(read_dir(cfg, key, t, &bd->cm_dir, err));
      } else if (rule == 2) {
        snprintf(key, sizeof key, "bodies.[%d].between", b);
        POM_TRY(read_dir(cfg, key, t, &bd->cm_dir, err));
        if (bd->cm_dir.b < 0)
          return pom_cfg_error(cfg, key, NULL, err, "a fraction lies between two joints [a, b]");
        bd->cm_from = bd->cm_dir.a;
      }
      snprintf(key, sizeof key, "bodies.[%d].axis", b);
      POM_TRY(read_dir(cfg, key, t, &bd->z_dir, err));
      snprintf(key, sizeof key, "bodies.[%d].x_axis", b);
      if (pom_cfg_has(cfg, key)) POM_TRY(read_dir(cfg, key, t, &bd->x_dir, err));
      f->inertia_bodies[n_groups].group = group;
      f->inertia_bodies[n_groups].place = rule;
      ++n_groups;
    } else {
      bd->model = POM_LIMB_MASS_ARC;
      ++n_arcs;
      snprintf(key, sizeof key, "bodies.[%d].arc", b);
      POM_TRY(read_dir(cfg, key, t, &bd->cm_dir, err));
      if (bd->cm_dir.b < 0 || t->joint[bd->cm_dir.b].type == POM_JOINT_SPHERICAL)
        return pom_cfg_error(cfg, key, NULL, err,
                             "an arc joins the axes of two joints [a, b] (not spherical)");
      bd->arc_a = bd->cm_dir.a;
      bd->arc_b = bd->cm_dir.b;
      bd->cm_dir = (pom_limb_dir){-1, -1};
      snprintf(key, sizeof key, "bodies.[%d].density", b);
      POM_TRY(value_index(f, cfg, key, 1, &bd->v_density, err));
      snprintf(key, sizeof key, "bodies.[%d].section", b);
      POM_TRY(value_index(f, cfg, key, 1, &bd->v_section, err));
      snprintf(key, sizeof key, "bodies.[%d].point_mass", b);
      if (pom_cfg_has(cfg, key)) {
        snprintf(key, sizeof key, "bodies.[%d].point_mass.mass", b);
        POM_TRY(value_index(f, cfg, key, 1, &bd->v_point_mass, err));
        snprintf(key, sizeof key, "bodies.[%d].point_mass.joint", b);
        POM_TRY(read_joint(cfg, key, &bd->point_joint, err));
        if (t->joint[bd->point_joint].type == POM_JOINT_SPHERICAL)
          return pom_cfg_error(cfg, key, NULL, err,
                               "the point mass sits at arc_radius times the joint's axis: not a "
                               "spherical joint");
      }
      snprintf(key, sizeof key, "bodies.[%d].rotor", b);
      if (pom_cfg_has(cfg, key)) {
        snprintf(key, sizeof key, "bodies.[%d].rotor.inertia", b);
        POM_TRY(value_index(f, cfg, key, 1, &bd->v_rotor, err));
        snprintf(key, sizeof key, "bodies.[%d].rotor.joint", b);
        POM_TRY(read_joint(cfg, key, &bd->rotor_joint, err));
        if (t->joint[bd->rotor_joint].type == POM_JOINT_SPHERICAL)
          return pom_cfg_error(cfg, key, NULL, err,
                               "a rotor turns about a joint's axis: not a "
                               "spherical joint");
      }
    }
  }
  f->type.n_inertia_bodies = n_groups;
  f->type.inertia_bodies = n_groups ? f->inertia_bodies : NULL;
  if (n_arcs && !f->has_arc_radius)
    return pom_cfg_error(cfg, "arc_radius", NULL, err,
                         "missing: arc bodies need their radius (an expression, m)");
  if (!n_arcs && f->has_arc_radius)
    return pom_cfg_error(cfg, "arc_radius", NULL, err, "no arc body uses it");
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
    pom_limb_measure *lm = &f->table.measure[k + 1];
    snprintf(key, sizeof key, "limits.[%d].name", k);
    POM_TRY(pom_cfg_string(cfg, key, f->limit_name[k + 1], sizeof f->limit_name[k + 1], err));
    snprintf(key, sizeof key, "limits.[%d].key", k);
    POM_TRY(pom_cfg_string(cfg, key, f->limit_key[k + 1], sizeof f->limit_key[k + 1], err));
    snprintf(key, sizeof key, "limits.[%d].json", k);
    POM_TRY(pom_cfg_string(cfg, key, f->limit_json[k + 1], sizeof f->limit_json[k + 1], err));
    static const char *const measures[] = {"cone", "distance", "axis_angle", "arm_angle", NULL};
    int m = 0;
    snprintf(key, sizeof key, "limits.[%d].measure", k);
    POM_TRY(pom_cfg_choice(cfg, key, measures, &m, err));
    f->limit_line[k + 1] = pom_cfg_line(cfg, key);
    const char *want = m == 1 ? "_mm" : "_deg";
    size_t kl = strlen(f->limit_key[k + 1]);
    snprintf(key, sizeof key, "limits.[%d].key", k);
    if (kl < 5 || strcmp(f->limit_key[k + 1] + kl - strlen(want), want) != 0)
      return pom_cfg_error(cfg, key, NULL, err, "a %s limit's key ends in %s", measures[m], want);
    if (m >= 2) {
      snprintf(key, sizeof key, "limits.[%d].joint", k);
      POM_TRY(read_joint(cfg, key, &lm->a, err));
      lm->b = -1;
      if (f->limb[0].joint[lm->a].type == POM_JOINT_SPHERICAL)
        return pom_cfg_error(cfg, key, NULL, err, "joint %d is spherical: it has no axis",
                             lm->a + 1);
      if (m == 3 && f->limb[0].joint[lm->a].type == POM_JOINT_PRISMATIC)
        return pom_cfg_error(cfg, key, NULL, err,
                             "joint %d is prismatic: an arm angle is the azimuth of a joint "
                             "axis that turns with the actuator",
                             lm->a + 1);
      for (int l = 0; m == 3 && l < (f->per_limb ? 3 : 1); ++l)
        for (int j = 0; j < 3; ++j)
          if (f->limb[l].joint[j].actuated && f->limb[l].joint[j].type != POM_JOINT_REVOLUTE) {
            snprintf(key, sizeof key, "limits.[%d].measure", k);
            return pom_cfg_error(cfg, key, NULL, err,
                                 "an arm angle is measured between revolute actuators turning "
                                 "about the z axis; joint %d of the limbs is actuated and not "
                                 "revolute",
                                 j + 1);
          }
    } else {
      double jj[2];
      snprintf(key, sizeof key, "limits.[%d].joints", k);
      POM_TRY(pom_cfg_reals(cfg, key, 2, 1.0, 1.0, 3.0, jj, err));
      if (jj[0] != floor(jj[0]) || jj[1] != floor(jj[1]) || !(jj[0] < jj[1]))
        return pom_cfg_error(cfg, key, NULL, err,
                             "expected [a, b]: joints a < b of the limb (1, 2, 3) whose points "
                             "bound the segment");
      lm->a = (int)jj[0] - 1;
      lm->b = (int)jj[1] - 1;
    }
    static const char *const frames[] = {"fixed", "platform", NULL};
    int fr = 0;
    snprintf(key, sizeof key, "limits.[%d].frame", k);
    if (m == 0) {
      POM_TRY(pom_cfg_choice(cfg, key, frames, &fr, err));
    } else if (pom_cfg_has(cfg, key)) {
      return pom_cfg_error(cfg, key, NULL, err, "only a cone has a frame");
    }
    lm->kind = m == 0   ? (fr ? POM_LIMB_MEASURE_CONE_PLATFORM : POM_LIMB_MEASURE_CONE_FIXED)
               : m == 1 ? POM_LIMB_MEASURE_DISTANCE
               : m == 2 ? POM_LIMB_MEASURE_AXIS_ANGLE
                        : POM_LIMB_MEASURE_ARM_ANGLE;
    static const char *const bounds[] = {"upper", "lower", NULL};
    int lower = 0;
    snprintf(key, sizeof key, "limits.[%d].bound", k);
    POM_TRY(pom_cfg_choice(cfg, key, bounds, &lower, err));
    ld->name = f->limit_name[k + 1];
    ld->key = f->limit_key[k + 1];
    ld->json = f->limit_json[k + 1];
    ld->per_pair = m != 0;
    ld->lower = lower;
    ld->unit = m == 1 ? "mm" : "deg";
    ld->to_display = m == 1 ? 1e3 : 1.0 / POM_DEG;
    ld->cls = m == 0 ? POM_KIN_LIMCLASS_CONE : POM_KIN_LIMCLASS_INTERFERENCE;
    snprintf(key, sizeof key, "limits.[%d].range", k);
    POM_TRY(read_range(cfg, key, &ld->lo, &ld->hi, err));
    if (m == 3 && (ld->lo < 0.0 || ld->hi > 360.0))
      return pom_cfg_error(cfg, key, NULL, err,
                           "an arm angle lies in [0, 360] deg: the range [%g, %g] leaves it",
                           ld->lo, ld->hi);
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
                                    "arc_radius",
                                    "limbs",
                                    "bodies",
                                    "limits",
                                    NULL};
  scope s;
  memset(&s, 0, sizeof s);
  POM_TRY(load_head(f, cfg, err));
  POM_TRY(load_params(f, cfg, &s, err));
  POM_TRY(load_values(f, cfg, err));
  POM_TRY(load_lets(cfg, "let", &s, f->global, &f->n_globals, err));
  f->has_arc_radius = pom_cfg_has(cfg, "arc_radius");
  if (f->has_arc_radius)
    POM_TRY(compile_at(cfg, "arc_radius", &s, POM_EXPR_SCALAR, &f->arc_radius, err));
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
      POM_TRY(load_limb_table(f, cfg, base, s, &f->limb[i], i == 0, err));
    }
  } else {
    static const char *const sym[] = {"C3", NULL};
    int k = 0;
    POM_TRY(pom_cfg_choice(cfg, "limbs.symmetry", sym, &k, err));
    POM_TRY(load_limb_table(f, cfg, "limbs", s, &f->limb[0], 1, err));
  }
  POM_TRY(load_bodies(f, cfg, err));
  POM_TRY(load_limits(f, cfg, err));
  POM_TRY(pom_cfg_check_unknown(cfg, NULL, top, err));
  f->table.central = f->central == POM_AF_CENTRAL_S      ? 1
                     : f->central == POM_AF_CENTRAL_NONE ? 0
                                                         : -1;

  pom_kin_arch_type *t = &f->type;
  t->name = f->name;
  t->label = f->label;
  t->description = f->description;
  t->unreachable = f->unreachable;
  t->optional_central_joint = f->central == POM_AF_CENTRAL_OPTIONAL;
  t->n_points = 0;
  t->points = NULL;
  t->data_size = sizeof(pom_limb_table);
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

pom_status pom_arch_file_eval(const pom_arch_file *f, const pom_kin_design *d, pom_limb_table *tb,
                              pom_error *err) {
  double slots[AF_MAX_SLOTS], v[3];
  const int np = f->type.n_params;
  *tb = f->table;
  for (int k = 0; k < np; ++k)
    slots[k] = d->x[k];
  slots[np] = d->scale;
  for (int k = 0; k < f->n_globals; ++k) {
    const pom_af_let *l = &f->global[k];
    POM_TRY(eval_expr(f, &l->value, slots, -1, v, err));
    memcpy(slots + l->slot, v, sizeof(double) * (size_t)l->value.e.kind);
  }
  if (f->has_arc_radius) {
    POM_TRY(eval_expr(f, &f->arc_radius, slots, -1, v, err));
    if (!(v[0] > 0.0)) return eval_fail(f, &f->arc_radius, -1, err, "a radius is positive");
    tb->arc_radius = v[0];
  }
  const int lv = f->global_slots;
  for (int i = 0; i < 3; ++i) {
    const pom_af_limb_table *t = &f->limb[f->per_limb ? i : 0];
    pom_limb *L = &tb->limb[i];
    slots[lv + LV_I] = (double)i;
    POM_TRY(eval_expr(f, &t->azimuth, slots, i, v, err));
    /* C3 symmetry: limb i at the azimuth of limb 1 plus i 120 deg */
    double eta = f->per_limb ? v[0] : v[0] + 2.0 * POM_PI * i / 3.0;
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
    for (int k = 0; k < t->n_lets; ++k) {
      const pom_af_let *l = &t->let[k];
      POM_TRY(eval_expr(f, &l->value, slots, i, v, err));
      memcpy(slots + l->slot, v, sizeof(double) * (size_t)l->value.e.kind);
    }
    for (int j = 0; j < 3; ++j) {
      const pom_af_joint *jt = &t->joint[j];
      pom_limb_joint *J = &L->joint[j];
      J->type = limb_joint_type(jt->type);
      if (jt->actuated) L->actuated = j;
      POM_TRY(eval_expr(f, &jt->point, slots, i, J->point, err));
      if (jt->type != POM_JOINT_SPHERICAL) POM_TRY(eval_unit(f, &jt->axis, slots, i, J->axis, err));
      if (jt->has_axis2) {
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
    if (t->has_motor) POM_TRY(eval_expr(f, &t->motor, slots, i, L->motor, err));
  }
  /* an arm angle (Orbita's gamma) is an azimuth about z: coaxial actuators */
  for (int k = 1; k < POM_KIN_LIM_KINDS; ++k) {
    if (tb->measure[k].kind != POM_LIMB_MEASURE_ARM_ANGLE) continue;
    for (int i = 0; i < 3; ++i) {
      const double *a = tb->limb[i].joint[tb->limb[i].actuated].axis;
      if (hypot(a[0], a[1]) > 1e-9 * fabs(a[2]))
        POM_FAIL(err, POM_ERR_ARG,
                 "%s:%d: key 'limits.[%d].measure' = \"arm_angle\" (limb %d): an arm angle "
                 "needs coaxial actuators, every actuated axis on the z axis; this design puts "
                 "limb %d's at (%.6g, %.6g, %.6g)",
                 f->path, f->limit_line[k], k - 1, i + 1, i + 1, a[0], a[1], a[2]);
    }
  }
  return POM_OK;
}

/* ---- the type's from_design --------------------------------------------------------- */
static pom_status from_design(pom_kin_arch *arch, const pom_kin_design *d, pom_error *err) {
  const pom_arch_file *f = pom_arch_file_of(arch->type);
  if (!f) POM_FAIL(err, POM_ERR_INTERNAL, "from_design of an architecture file on another type");
  return pom_arch_file_eval(f, d, POM_LIMB_TABLE(arch), err);
}
