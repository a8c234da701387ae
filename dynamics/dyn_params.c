/* dyn_params.c - the dynamics parameters from their one list
 * (pom_dyn_params_schema.h): the table, the defaults, the config loading, the
 * model's check of the same ranges and the accessors the outputs read
 * (docs/config.md, "Dynamics parameters"). */
#include "pom_dyn_params_schema.h"

#include "pom_dyn_ctrl.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Smallest positive solver.atol_scale: the states' relative rounding (an
 * absolute tolerance below it cannot be met) (docs/dynamics.md section 9). */
#define ATOL_SCALE_MIN 1e-15
/* Smallest positive solver.max_step_ms (ms): 1 ns, 1e8 steps per 100 ms. */
#define MAX_STEP_MS_MIN 1e-6

/* ---- names --------------------------------------------------------------- */
const char *const pom_dyn_orient_names[] = {"euler", "quaternion", NULL};
const char *const pom_dyn_linsol_names[] = {"dense", "klu", "structured", NULL};
const char *const pom_dyn_jacobian_names[] = {"analytic", "finite-difference", NULL};
const char *const pom_dyn_joint_model_names[] = {"parasitic", "rigid", NULL};
const char *const pom_dyn_inertia_names[] = {"full", "lumped", NULL};
/* each table lists its enum's values in order: the value is the index */
#define TABLE_LEN(t) (sizeof(t) / sizeof((t)[0]) - 1)
_Static_assert(TABLE_LEN(pom_dyn_orient_names) == POM_ORIENT_QUATERNION + 1,
               "pom_dyn_orient_names follows pom_orient_kind");
_Static_assert(TABLE_LEN(pom_dyn_linsol_names) == POM_LINSOL_STRUCTURED + 1,
               "pom_dyn_linsol_names follows pom_linsol_kind");
_Static_assert(TABLE_LEN(pom_dyn_jacobian_names) == POM_JAC_FINITE_DIFFERENCE + 1,
               "pom_dyn_jacobian_names follows pom_jac_kind");
_Static_assert(TABLE_LEN(pom_dyn_joint_model_names) == POM_JOINTS_RIGID + 1,
               "pom_dyn_joint_model_names follows pom_joint_model");
_Static_assert(TABLE_LEN(pom_dyn_inertia_names) == POM_INERTIA_LUMPED + 1,
               "pom_dyn_inertia_names follows pom_inertia_kind");

/* names from the tables above, indexed by the enum's value; "?" for a value
 * outside the table (never the first name by default) */
const char *pom_dyn_pid_form_name(pom_pid_form f) {
  return pom_cfg_choice_name(pom_dyn_ctrl_pid.options[0].names, (int)f); /* ctrl_pid.c */
}
const char *pom_dyn_orient_name(pom_orient_kind k) {
  return pom_cfg_choice_name(pom_dyn_orient_names, (int)k);
}
const char *pom_dyn_linsol_name(pom_linsol_kind k) {
  return pom_cfg_choice_name(pom_dyn_linsol_names, (int)k);
}
const char *pom_dyn_jacobian_name(pom_jac_kind k) {
  return pom_cfg_choice_name(pom_dyn_jacobian_names, (int)k);
}
const char *pom_dyn_joint_model_name(pom_joint_model k) {
  return pom_cfg_choice_name(pom_dyn_joint_model_names, (int)k);
}
const char *pom_dyn_inertia_name(pom_inertia_kind k) {
  return pom_cfg_choice_name(pom_dyn_inertia_names, (int)k);
}

/* ---- the table ------------------------------------------------------------ */
#define CTYPE_REAL         double
#define CTYPE_KIND_REAL    double
#define CTYPE_LONG         long
#define CTYPE_INT          int
#define CTYPE_BOOL         int
#define CTYPE_ENUM         int /* an enum with small non-negative values */
#define CTYPE_KIND         int
#define NAMES_REAL(a)      NULL
#define NAMES_KIND_REAL(a) NULL
#define NAMES_LONG(a)      NULL
#define NAMES_INT(a)       NULL
#define NAMES_BOOL(a)      NULL
#define NAMES_ENUM(a)      a
#define NAMES_KIND(a)      NULL
#define SLOT_REAL(a)       0
#define SLOT_KIND_REAL(a)  a
#define SLOT_LONG(a)       0
#define SLOT_INT(a)        0
#define SLOT_BOOL(a)       0
#define SLOT_ENUM(a)       0
#define SLOT_KIND(a)       0

/* each declared member exists in pom_dyn_params with the size of its type */
#define CHECK_FIELD(group, key, json, member, type, ...)                                           \
  _Static_assert(sizeof(((pom_dyn_params *)0)->member) == sizeof(CTYPE_##type),                    \
                 "parameter " #member ": type differs from pom_dyn_params");
POM_DYN_PARAMS_LIST(CHECK_FIELD)
#undef CHECK_FIELD

#define ENTRY(group_, key_, json_, member, type_, arg, to_si_, unit_, lo_, hi_, def_, h5_,         \
              meaning_)                                                                            \
  {.group = #group_,                                                                               \
   .key = key_,                                                                                    \
   .json = json_,                                                                                  \
   .offset = offsetof(pom_dyn_params, member),                                                     \
   .type = POM_DYN_PARAM_##type_,                                                                  \
   .names = NAMES_##type_(arg),                                                                    \
   .slot = SLOT_##type_(arg),                                                                      \
   .to_si = to_si_,                                                                                \
   .unit = unit_,                                                                                  \
   .lo = (double)(lo_),                                                                            \
   .hi = (double)(hi_),                                                                            \
   .def = (double)(def_),                                                                          \
   .h5 = h5_,                                                                                      \
   .meaning = meaning_},
static const pom_dyn_param_info schema[POM_DYN_N_PARAMS] = {POM_DYN_PARAMS_LIST(ENTRY)};
#undef ENTRY

const pom_dyn_param_info *pom_dyn_param_schema(void) {
  return schema;
}

/* ---- values --------------------------------------------------------------- */
/* The members are reached by offset; memcpy keeps the accesses typed. */
static void *field(pom_dyn_params *p, const pom_dyn_param_info *pi) {
  return (char *)p + pi->offset;
}
static const void *cfield(const pom_dyn_params *p, const pom_dyn_param_info *pi) {
  return (const char *)p + pi->offset;
}

static int is_real(const pom_dyn_param_info *pi) {
  return pi->type == POM_DYN_PARAM_REAL || pi->type == POM_DYN_PARAM_KIND_REAL;
}

double pom_dyn_param_value(const pom_dyn_params *p, const pom_dyn_param_info *pi) {
  double d;
  long l;
  int i;
  if (is_real(pi)) {
    memcpy(&d, cfield(p, pi), sizeof d);
    return d;
  }
  if (pi->type == POM_DYN_PARAM_LONG) {
    memcpy(&l, cfield(p, pi), sizeof l);
    return (double)l;
  }
  memcpy(&i, cfield(p, pi), sizeof i);
  return (double)i;
}

static long long_value(const pom_dyn_params *p, const pom_dyn_param_info *pi) {
  long l;
  int i;
  if (pi->type == POM_DYN_PARAM_LONG) {
    memcpy(&l, cfield(p, pi), sizeof l);
    return l;
  }
  memcpy(&i, cfield(p, pi), sizeof i);
  return i;
}

static void set_real(pom_dyn_params *p, const pom_dyn_param_info *pi, double v) {
  memcpy(field(p, pi), &v, sizeof v);
}
static void set_int(pom_dyn_params *p, const pom_dyn_param_info *pi, long v) {
  if (pi->type == POM_DYN_PARAM_LONG) {
    memcpy(field(p, pi), &v, sizeof v);
  } else {
    int i = (int)v;
    memcpy(field(p, pi), &i, sizeof i);
  }
}

/* ---- names of a parameter -------------------------------------------------- */
/* the descriptor's key and unit of a KIND_REAL's slot */
static const char *kind_key(const pom_act_desc *k, int slot) {
  const char *key[3] = {k->constant_key, k->friction_key, k->gain_key};
  return key[slot];
}
static const char *kind_unit(const pom_act_desc *k, int slot) {
  const char *unit[3] = {k->constant_unit, k->friction_unit, k->gain_unit};
  return unit[slot];
}

const char *pom_dyn_param_json_key(const pom_dyn_param_info *pi, pom_actuator_kind kind) {
  if (pi->type != POM_DYN_PARAM_KIND_REAL) return pi->json;
  const pom_act_desc *k = pom_act_kind_desc(kind);
  return k ? kind_key(k, pi->slot) : NULL;
}

const char *pom_dyn_param_unit(const pom_dyn_param_info *pi, pom_actuator_kind kind) {
  if (pi->type != POM_DYN_PARAM_KIND_REAL) return pi->unit;
  const pom_act_desc *k = pom_act_kind_desc(kind);
  return k ? kind_unit(k, pi->slot) : NULL;
}

const char *pom_dyn_param_key(const pom_dyn_param_info *pi, pom_actuator_kind kind, char *buf,
                              size_t cap) {
  const char *key =
      pi->type == POM_DYN_PARAM_KIND_REAL ? pom_dyn_param_json_key(pi, kind) : pi->key;
  if (!key) return NULL;
  snprintf(buf, cap, "%s.%s", pi->group, key);
  return buf;
}

const char *pom_dyn_param_h5_name(const pom_dyn_param_info *pi, pom_actuator_kind kind, char *buf,
                                  size_t cap) {
  if (pi->type != POM_DYN_PARAM_KIND_REAL) {
    snprintf(buf, cap, "%s", pi->h5);
    return buf;
  }
  const char *key = pom_dyn_param_json_key(pi, kind);
  if (!key) return NULL;
  snprintf(buf, cap, "%s_%s", pi->group, key);
  return buf;
}

const char *pom_dyn_param_choice(const pom_dyn_params *p, const pom_dyn_param_info *pi) {
  if (pi->type == POM_DYN_PARAM_ENUM) return pom_cfg_choice_name(pi->names, (int)long_value(p, pi));
  if (pi->type == POM_DYN_PARAM_KIND) {
    const pom_act_desc *k = pom_act_kind_desc((pom_actuator_kind)long_value(p, pi));
    return k ? k->name : "?";
  }
  return NULL;
}

const char *pom_dyn_param_format(const pom_dyn_params *p, const pom_dyn_param_info *pi, char *buf,
                                 size_t cap) {
  switch (pi->type) {
  case POM_DYN_PARAM_REAL:
  case POM_DYN_PARAM_KIND_REAL:
    snprintf(buf, cap, "%g", pom_dyn_param_value(p, pi) / pi->to_si);
    break;
  case POM_DYN_PARAM_LONG:
  case POM_DYN_PARAM_INT:
    snprintf(buf, cap, "%ld", long_value(p, pi));
    break;
  case POM_DYN_PARAM_BOOL:
    snprintf(buf, cap, "%s", long_value(p, pi) ? "true" : "false");
    break;
  case POM_DYN_PARAM_ENUM:
  case POM_DYN_PARAM_KIND:
    snprintf(buf, cap, "%s", pom_dyn_param_choice(p, pi));
    break;
  }
  return buf;
}

const char *pom_dyn_param_format_default(const pom_dyn_param_info *pi, char *buf, size_t cap) {
  pom_dyn_params d;
  pom_dyn_params_defaults(&d);
  return pom_dyn_param_format(&d, pi, buf, cap);
}

/* ---- defaults ------------------------------------------------------------ */
void pom_dyn_params_defaults(pom_dyn_params *p) {
  memset(p, 0, sizeof *p);
  /* the PID with the 3P-S-S/S reference gains, ideal form (its descriptors'
   * defaults; docs/PARAMETERS.md controller-form note) */
  pom_dyn_ctrl_set_defaults(&p->controller, &pom_dyn_ctrl_pid);
  /* the list's defaults: the reference actuator of docs/PARAMETERS.md (a) */
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
    if (is_real(&schema[k]))
      set_real(p, &schema[k], schema[k].def);
    else
      set_int(p, &schema[k], (long)schema[k].def);
  }
}

/* ---- relations between parameters ------------------------------------------- */
/* The checks that involve two parameters, shared by loading (with the file's
 * line) and the model: the config key of the first broken one and why, or
 * NULL when all hold. */
static const char *relation_broken(const pom_dyn_params *p, char *why, size_t cap) {
  const pom_dyn_maneuver *m = &p->maneuver;
  if (p->scene.coil_inductance && !(p->actuator.inductance > 0)) {
    snprintf(why, cap, "must be > 0 when scene.coil_inductance is on");
    return "actuator.inductance_H";
  }
  if (m->output_dt > m->horizon) {
    snprintf(why, cap, "must not exceed maneuver.horizon_ms (%g ms)", m->horizon * 1e3);
    return "maneuver.output_dt_ms";
  }
  if (m->horizon / m->output_dt > 1e7) {
    snprintf(why, cap, "more than 1e7 trace samples over the horizon; raise output_dt_ms");
    return "maneuver.output_dt_ms";
  }
  return NULL;
}

/* ---- loading ------------------------------------------------------------- */
/* actuator.kind chooses the units of the KIND_REAL keys; the other kinds'
 * keys are refused by name (docs/config.md) */
static pom_status load_kind(pom_dyn_params *p, const pom_dyn_param_info *pi, const pom_cfg *cfg,
                            const char *key, pom_error *err) {
  const char *names[POM_ACT_KINDS + 1];
  for (int k = 0; k < POM_ACT_KINDS; ++k)
    names[k] = pom_act_kind_desc((pom_actuator_kind)k)->name;
  names[POM_ACT_KINDS] = NULL;
  int idx = pom_act_kind_desc(p->actuator.kind) ? (int)p->actuator.kind : 0;
  POM_TRY(pom_cfg_choice_opt(cfg, key, names, idx, &idx, err));
  set_int(p, pi, idx);
  const pom_act_desc *kind = pom_act_kind_desc(p->actuator.kind);
  char own[96], other[96];
  for (int o = 0; o < POM_ACT_KINDS; ++o)
    for (int k = 0; k < POM_DYN_N_PARAMS && o != idx; ++k)
      if (schema[k].type == POM_DYN_PARAM_KIND_REAL &&
          pom_cfg_has(cfg,
                      pom_dyn_param_key(&schema[k], (pom_actuator_kind)o, other, sizeof other)))
        return pom_cfg_error(
            cfg, other, NULL, err, "is a key of a %s actuator but actuator.kind = \"%s\": use %s",
            names[o], kind->name, pom_dyn_param_key(&schema[k], kind->kind, own, sizeof own));
  return POM_OK;
}

static pom_status load_one(pom_dyn_params *p, const pom_dyn_param_info *pi, const pom_cfg *cfg,
                           pom_error *err) {
  char key[96];
  double v = 0.0;
  long l = 0;
  int i = 0;
  pom_dyn_param_key(pi, p->actuator.kind, key, sizeof key);
  switch (pi->type) {
  case POM_DYN_PARAM_REAL:
  case POM_DYN_PARAM_KIND_REAL:
    POM_TRY(
        pom_cfg_real_opt(cfg, key, pi->to_si, pi->lo, pi->hi, pom_dyn_param_value(p, pi), &v, err));
    set_real(p, pi, v);
    break;
  case POM_DYN_PARAM_LONG:
  case POM_DYN_PARAM_INT:
    POM_TRY(pom_cfg_int_opt(cfg, key, (long)pi->lo, (long)pi->hi, long_value(p, pi), &l, err));
    set_int(p, pi, l);
    break;
  case POM_DYN_PARAM_BOOL:
    POM_TRY(pom_cfg_bool_opt(cfg, key, (int)long_value(p, pi), &i, err));
    set_int(p, pi, i);
    break;
  case POM_DYN_PARAM_ENUM:
    POM_TRY(pom_cfg_choice_opt(cfg, key, pi->names, (int)long_value(p, pi), &i, err));
    set_int(p, pi, i); /* the enum values are the table indices */
    break;
  case POM_DYN_PARAM_KIND:
    POM_TRY(load_kind(p, pi, cfg, key, err));
    break;
  }
  return POM_OK;
}

/* ---- the absolute tolerances a model uses ---------------------------------- */
/* docs/dynamics.md section 7: the scale rule's atol follows rtol below the
 * line atol_scale = 1e3 rtol. The margin keeps pairs on the line (1e-7 and
 * 1e-4: 1e3 x 1e-7 rounds one ulp below 1e-4) as they are. */
double pom_dyn_atol_scale_used(const pom_dyn_solver *s) {
  const double follow = POM_DYN_ATOL_PER_RTOL * s->rtol;
  if (!(s->atol_scale > 0.0)) return s->atol_scale;
  return follow < s->atol_scale * (1.0 - 1e-9) ? follow : s->atol_scale;
}

pom_status pom_dyn_params_load(pom_dyn_params *p, const pom_cfg *cfg, pom_error *err) {
  const char *const *groups = pom_dyn_param_groups();
  for (int g = 0; groups[g]; ++g) {
    if (strcmp(groups[g], "controller") == 0) {
      POM_TRY(pom_dyn_ctrl_load(&p->controller, cfg, err)); /* the type, its options and gains */
      continue;
    }
    for (int k = 0; k < POM_DYN_N_PARAMS; ++k)
      if (strcmp(schema[k].group, groups[g]) == 0) POM_TRY(load_one(p, &schema[k], cfg, err));
  }
  char why[160];
  const char *key = relation_broken(p, why, sizeof why);
  if (key) return pom_cfg_error(cfg, key, NULL, err, "%s", why);
  /* 0 or at least ATOL_SCALE_MIN: below it the absolute tolerances are under
   * the rounding of the states (or zero), and CVODE fails at t = 0 in its own
   * words ("Initial ewt has component(s) equal to zero") */
  if (p->solver.atol_scale > 0.0 && p->solver.atol_scale < ATOL_SCALE_MIN)
    return pom_cfg_error(cfg, "solver.atol_scale", NULL, err,
                         "expected 0 (natural sizes) or a value in [%g, 1]: below %g the absolute "
                         "tolerances are under the rounding of the states",
                         ATOL_SCALE_MIN, ATOL_SCALE_MIN);
  /* 0 (unlimited) or at least MAX_STEP_MS_MIN: a smaller bound needs more
   * than 1e8 steps per 100 ms, and one near 1e-320 makes 1 / h overflow */
  if (p->solver.max_step > 0.0 && p->solver.max_step < MAX_STEP_MS_MIN * 1e-3)
    return pom_cfg_error(cfg, "solver.max_step_ms", NULL, err,
                         "expected 0 (unlimited) or a value in [%g, 1e+06] ms: a smaller step "
                         "bound cannot reach the horizon (more than 1e8 steps per 100 ms)",
                         MAX_STEP_MS_MIN);
  return POM_OK;
}

/* ---- the model's check ------------------------------------------------------ */
static int names_count(const char *const *names) {
  int n = 0;
  while (names[n])
    ++n;
  return n;
}

pom_status pom_dyn_params_check(const pom_dyn_params *p, pom_error *err) {
  const pom_act_desc *kind = pom_act_kind_desc(p->actuator.kind);
  if (!kind) {
    /* "neither linear nor rotary": the names of the kinds */
    char names[128] = "";
    size_t used = 0;
    for (int k = 0; k < POM_ACT_KINDS && used < sizeof names; ++k) {
      int w = snprintf(names + used, sizeof names - used, "%s%s", k ? " nor " : "",
                       pom_act_kind_desc((pom_actuator_kind)k)->name);
      used += w > 0 ? (size_t)w : 0;
    }
    POM_FAIL(err, POM_ERR_ARG, "actuator kind %d is neither %s", (int)p->actuator.kind, names);
  }
  /* every value in the range loading checks (in SI: the loader's value
   * times to_si, so a value loading accepts is accepted here) */
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
    const pom_dyn_param_info *pi = &schema[k];
    char key[96], text[64];
    pom_dyn_param_key(pi, kind->kind, key, sizeof key);
    double v = pom_dyn_param_value(p, pi);
    int ok = 1;
    switch (pi->type) {
    case POM_DYN_PARAM_REAL:
    case POM_DYN_PARAM_KIND_REAL:
      ok = v >= pi->lo * pi->to_si && v <= pi->hi * pi->to_si; /* NaN refused */
      break;
    case POM_DYN_PARAM_LONG:
    case POM_DYN_PARAM_INT:
      ok = v >= pi->lo && v <= pi->hi;
      break;
    case POM_DYN_PARAM_BOOL:
      ok = v == 0.0 || v == 1.0;
      break;
    case POM_DYN_PARAM_ENUM:
      ok = v >= 0.0 && v < (double)names_count(pi->names);
      break;
    case POM_DYN_PARAM_KIND:
      break; /* checked above */
    }
    if (!ok) {
      if (pi->type == POM_DYN_PARAM_BOOL || pi->type == POM_DYN_PARAM_ENUM)
        POM_FAIL(err, POM_ERR_ARG, "%s = %g is not one of its values", key, v);
      POM_FAIL(err, POM_ERR_ARG, "%s = %s outside [%g, %g] %s", key,
               pom_dyn_param_format(p, pi, text, sizeof text), pi->lo, pi->hi,
               pom_dyn_param_unit(pi, kind->kind));
    }
  }
  POM_TRY(pom_dyn_ctrl_check(&p->controller, err)); /* the type's ranges, as loading checks */
  char why[160];
  const char *key = relation_broken(p, why, sizeof why);
  if (key) POM_FAIL(err, POM_ERR_ARG, "%s %s", key, why);
  return POM_OK;
}
