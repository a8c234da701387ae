/* pom_dyn_metrics_schema.c - the table generated from POM_DYN_METRICS_LIST
 * and the units of its unit classes (docs/results.md, section 9). */
#include "pom_dyn_metrics_schema.h"

#include "pom_math.h"

#include <math.h>
#include <stdio.h>

/* ---- the table ----------------------------------------------------------------- */
#define CTYPE_DOUBLE double
#define CTYPE_INT    int
#define CTYPE_LONG   long

/* each declared field exists in pom_dyn_metrics with the declared type and count */
#define CHECK_FIELD(name, type, n, ...)                                                            \
  _Static_assert(sizeof(((pom_dyn_metrics *)0)->name) == (n) * sizeof(CTYPE_##type),               \
                 "metric " #name ": type or count differs from pom_dyn_metrics");
POM_DYN_METRICS_LIST(CHECK_FIELD, CHECK_FIELD)
#undef CHECK_FIELD

#define ENTRY_M(name_, type_, n_, unit_, descr_)                                                   \
  {.name = #name_,                                                                                 \
   .type = POM_DYN_TYPE_##type_,                                                                   \
   .count = n_,                                                                                    \
   .unit = POM_DYN_UNIT_##unit_,                                                                   \
   .description = descr_,                                                                          \
   .offset = offsetof(pom_dyn_metrics, name_),                                                     \
   .reduce = POM_DYN_REDUCE_NONE,                                                                  \
   .combine = POM_DYN_COMBINE_NONE,                                                                \
   .stat = -1,                                                                                     \
   .stat_name = NULL,                                                                              \
   .stat_key = NULL},
#define ENTRY_R(name_, type_, n_, unit_, descr_, over_, combine_, stat_, key_)                     \
  {.name = #name_,                                                                                 \
   .type = POM_DYN_TYPE_##type_,                                                                   \
   .count = n_,                                                                                    \
   .unit = POM_DYN_UNIT_##unit_,                                                                   \
   .description = descr_,                                                                          \
   .offset = offsetof(pom_dyn_metrics, name_),                                                     \
   .reduce = POM_DYN_REDUCE_##over_,                                                               \
   .combine = POM_DYN_COMBINE_##combine_,                                                          \
   .stat = POM_DYN_STAT_##stat_,                                                                   \
   .stat_name = #stat_,                                                                            \
   .stat_key = key_},
static const pom_dyn_metric_info schema[POM_DYN_N_METRICS] = {
    POM_DYN_METRICS_LIST(ENTRY_M, ENTRY_R)};
#undef ENTRY_M
#undef ENTRY_R

/* metric index of each statistic */
#define STAT_IGNORE(...)
#define STAT_METRIC(name, ...) POM_DYN_METRIC_##name,
static const int stat_metric[POM_DYN_N_STATS] = {POM_DYN_METRICS_LIST(STAT_IGNORE, STAT_METRIC)};
#undef STAT_IGNORE
#undef STAT_METRIC

const pom_dyn_metric_info *pom_dyn_metric_schema(void) {
  return schema;
}

const pom_dyn_metric_info *pom_dyn_metric(int j) {
  return j >= 0 && j < POM_DYN_N_METRICS ? &schema[j] : NULL;
}

const pom_dyn_metric_info *pom_dyn_stat_metric(int s) {
  return s >= 0 && s < POM_DYN_N_STATS ? &schema[stat_metric[s]] : NULL;
}

/* ---- units ------------------------------------------------------------------------ */
typedef struct {
  const char *si;      /* SI unit */
  const char *suffix;  /* JSON key suffix ("" = none) */
  const char *display; /* text output unit */
  double factor;       /* SI -> display */
} unit_info;

/* by pom_dyn_unit; the actuator entry is resolved from the kind. The display
 * units are the text convention of docs/conventions.md: ms, mm, deg, J, V. */
static const unit_info units[] = {
    [POM_DYN_UNIT_ACTUATOR] = {.si = "", .suffix = "", .display = "", .factor = 1.0},
    [POM_DYN_UNIT_TIME] = {.si = "s", .suffix = "s", .display = "ms", .factor = 1e3},
    [POM_DYN_UNIT_ENERGY] = {.si = "J", .suffix = "J", .display = "J", .factor = 1.0},
    [POM_DYN_UNIT_VOLTAGE] = {.si = "V", .suffix = "V", .display = "V", .factor = 1.0},
    [POM_DYN_UNIT_LENGTH] = {.si = "m", .suffix = "m", .display = "mm", .factor = 1e3},
    [POM_DYN_UNIT_ANGLE] = {.si = "rad",
                            .suffix = "rad",
                            .display = "deg",
                            .factor = 180.0 / POM_PI},
    [POM_DYN_UNIT_RATIO] = {.si = "1", .suffix = "", .display = "", .factor = 1.0},
    [POM_DYN_UNIT_COUNT] = {.si = "1", .suffix = "", .display = "", .factor = 1.0},
    [POM_DYN_UNIT_FLAG] = {.si = "1", .suffix = "", .display = "", .factor = 1.0},
    [POM_DYN_UNIT_ANGULAR_RATE] = {.si = "rad/s",
                                   .suffix = "rad_per_s",
                                   .display = "deg/s",
                                   .factor = 180.0 / POM_PI},
    [POM_DYN_UNIT_EFFORT] = {.si = "N or N m", .suffix = "", .display = "N or N m", .factor = 1.0},
};
_Static_assert(sizeof units / sizeof units[0] == POM_DYN_UNIT_EFFORT + 1,
               "one entry per unit class");

const char *pom_dyn_metric_unit(const pom_dyn_metric_info *mi, pom_actuator_kind kind) {
  if (mi->unit == POM_DYN_UNIT_ACTUATOR) return pom_act_kind_desc(kind)->si;
  if (mi->unit == POM_DYN_UNIT_EFFORT) return pom_act_kind_desc(kind)->effort;
  return units[mi->unit].si;
}

const char *pom_dyn_metric_display_unit(const pom_dyn_metric_info *mi, pom_actuator_kind kind,
                                        double *factor) {
  if (mi->unit == POM_DYN_UNIT_ACTUATOR) {
    const pom_act_desc *u = pom_act_kind_desc(kind);
    if (factor) *factor = u->to_display;
    return u->display;
  }
  if (mi->unit == POM_DYN_UNIT_EFFORT) { /* N or N m, shown as such */
    if (factor) *factor = 1.0;
    return pom_act_kind_desc(kind)->effort;
  }
  if (factor) *factor = units[mi->unit].factor;
  return units[mi->unit].display;
}

const char *pom_dyn_metric_json_key(const pom_dyn_metric_info *mi, char *buf, size_t cap) {
  const char *suffix = mi->unit == POM_DYN_UNIT_ACTUATOR ? "" : units[mi->unit].suffix;
  snprintf(buf, cap, "%s%s%s", mi->name, suffix[0] ? "_" : "", suffix);
  return buf;
}

/* ---- values ------------------------------------------------------------------------ */
double pom_dyn_metric_value(const pom_dyn_metrics *m, const pom_dyn_metric_info *mi, int k) {
  const char *base = (const char *)m + mi->offset;
  switch (mi->type) {
  case POM_DYN_TYPE_INT:
    return (double)((const int *)(const void *)base)[k];
  case POM_DYN_TYPE_LONG:
    return (double)((const long *)(const void *)base)[k];
  default:
    return ((const double *)(const void *)base)[k];
  }
}

double pom_dyn_combine_values(pom_dyn_combine c, const double *v, int n) {
  if (c == POM_DYN_COMBINE_SUM) {
    double s = 0;
    for (int k = 0; k < n; ++k)
      s = k ? s + v[k] : v[k];
    return s;
  }
  if (c == POM_DYN_COMBINE_MAX) {
    double t = 0;
    for (int k = 0; k < n; ++k)
      t = isfinite(v[k]) && isfinite(t) ? fmax(t, v[k]) : NAN;
    return t;
  }
  return n > 0 ? v[0] : NAN;
}

/* names in enum order (pom_cfg_choice_name: "?" outside the table) */
static const char *const reduce_names[] = {"none", "ok", "settled", NULL};
static const char *const combine_names[] = {"none", "sum", "max", NULL};
_Static_assert(sizeof reduce_names / sizeof reduce_names[0] == POM_DYN_REDUCE_SETTLED + 2,
               "reduce_names follows pom_dyn_reduce");
_Static_assert(sizeof combine_names / sizeof combine_names[0] == POM_DYN_COMBINE_MAX + 2,
               "combine_names follows pom_dyn_combine");

const char *pom_dyn_reduce_name(pom_dyn_reduce r) {
  return pom_cfg_choice_name(reduce_names, (int)r);
}

const char *pom_dyn_combine_name(pom_dyn_combine c) {
  return pom_cfg_choice_name(combine_names, (int)c);
}
