/* cap_figures.c - the candidate-level capability figures of pom_cap_figures.h:
 * names, units, values and requirements on them (docs/capability.md, "As
 * study responses and constraints"). */
#include "pom_capability.h"

#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  const char *name, *unit, *description;
  int slews;
} figure_info;

#define FIG_INFO_(name, unit, slews, desc, acc) {#name, unit, desc, slews},
static const figure_info figures[POM_CAP_N_FIGURES] = {POM_CAP_FIGURES(FIG_INFO_)};
#undef FIG_INFO_

static int valid(int i) {
  return i >= 0 && i < POM_CAP_N_FIGURES;
}

const char *pom_cap_figure_name(int i) {
  return valid(i) ? figures[i].name : "?";
}
const char *pom_cap_figure_unit(int i) {
  return valid(i) ? figures[i].unit : "?";
}
const char *pom_cap_figure_description(int i) {
  return valid(i) ? figures[i].description : "?";
}
int pom_cap_figure_needs_slews(int i) {
  return valid(i) && figures[i].slews;
}

int pom_cap_figure_index(const char *name) {
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
    if (strcmp(figures[i].name, name) == 0) return i;
  return -1;
}

void pom_cap_figure_list(char *buf, size_t cap) {
  size_t used = 0;
  if (cap) buf[0] = '\0';
  for (int i = 0; i < POM_CAP_N_FIGURES && used < cap; ++i) {
    int w = snprintf(buf + used, cap - used, "%s%s", i ? ", " : "", figures[i].name);
    if (w < 0) break;
    used += (size_t)w;
  }
}

double pom_cap_slew_worst_time(const pom_cap_result *r, double a) {
  double worst = NAN;
  int found = 0;
  for (int k = 0; k < r->n_dirs; ++k)
    for (int j = 0; j < r->slew[k].n; ++j) {
      if (!(fabs(r->slew[k].amplitude[j] - a) <= 1e-9)) continue;
      double t = r->slew[k].slew_time[j];
      if (!isfinite(t) || r->slew[k].status[j] != POM_OK) return NAN; /* unsettled */
      worst = found ? fmax(worst, t) : t;
      found = 1;
    }
  return worst;
}

double pom_cap_figure_value(const pom_cap_result *r, int i) {
  switch (i) {
#define FIG_VALUE_(name, unit, slews, desc, acc)                                                   \
  case POM_CAP_FIG_##name:                                                                         \
    return acc;
    POM_CAP_FIGURES(FIG_VALUE_)
#undef FIG_VALUE_
  default:
    return NAN;
  }
}

void pom_cap_opts_for_figures(pom_cap_opts *o, const int *want, int grid) {
  if (grid > 0) o->grid_points = grid;
  int slews = 0;
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
    slews |= want[i] && figures[i].slews;
  if (!slews) {
    o->slew_directions = 0;
    return;
  }
  o->slew_directions = POM_CAP_MAX_DIRECTIONS;
  o->n_amplitudes = 1;
  o->amplitude[0] = 10.0 * POM_DEG;
}

pom_status pom_cap_requirement_parse(pom_cap_requirement *q, const char *text, pom_error *err) {
  char name[64], list[256];
  const char *s = text;
  size_t n = 0;
  while (*s == ' ')
    ++s;
  while ((s[n] >= 'a' && s[n] <= 'z') || (s[n] >= '0' && s[n] <= '9') || s[n] == '_')
    ++n;
  pom_cap_figure_list(list, sizeof list);
  if (n == 0 || n >= sizeof name)
    POM_FAIL(err, POM_ERR_ARG,
             "'%s': expected \"FIGURE >= NUMBER\" or \"FIGURE <= NUMBER\" (figures: %s)", text,
             list);
  memcpy(name, s, n);
  name[n] = '\0';
  q->figure = pom_cap_figure_index(name);
  if (q->figure < 0)
    POM_FAIL(err, POM_ERR_ARG, "'%s': unknown capability figure '%s' (figures: %s)", text, name,
             list);
  s += n;
  while (*s == ' ')
    ++s;
  if ((s[0] != '>' && s[0] != '<') || s[1] != '=')
    POM_FAIL(err, POM_ERR_ARG, "'%s': expected >= or <= after '%s'", text, name);
  q->at_most = s[0] == '<';
  s += 2;
  char *end = NULL;
  q->bound = strtod(s, &end);
  while (end && *end == ' ')
    ++end;
  if (end == s || !end || *end != '\0' || !isfinite(q->bound))
    POM_FAIL(err, POM_ERR_ARG, "'%s': expected a finite number (SI unit, %s) after the comparison",
             text, figures[q->figure].unit);
  return POM_OK;
}

int pom_cap_requirement_met(const pom_cap_requirement *q, double value) {
  if (isnan(value)) return 0;
  return q->at_most ? value <= q->bound : value >= q->bound;
}

pom_status pom_cap_requirements_load(const pom_cfg *cfg, const char *key, pom_cap_requirement *q,
                                     int max, int *n, pom_error *err) {
  *n = 0;
  if (!pom_cfg_has(cfg, key)) return POM_OK;
  int nq = pom_cfg_length(cfg, key);
  if (nq < 1)
    return pom_cfg_error(cfg, key, NULL, err,
                         "expected a list of requirements [\"FIGURE >= NUMBER\", ...]");
  if (nq > max) return pom_cfg_error(cfg, key, NULL, err, "at most %d requirements", max);
  for (int j = 0; j < nq; ++j) {
    char k[160], text[128];
    pom_error e;
    pom_error_clear(&e);
    snprintf(k, sizeof k, "%s.[%d]", key, j);
    POM_TRY(pom_cfg_string(cfg, k, text, sizeof text, err));
    if (pom_cap_requirement_parse(&q[j], text, &e) != POM_OK)
      return pom_cfg_error(cfg, k, text, err, "%s", e.message);
  }
  pom_cfg_mark_used(cfg, key);
  *n = nq;
  return POM_OK;
}

void pom_cap_requirement_text(char *buf, size_t cap, const pom_cap_requirement *q) {
  snprintf(buf, cap, "%s %s %.6g", pom_cap_figure_name(q->figure),
           q->at_most ? "<=" : ">=", q->bound);
}
