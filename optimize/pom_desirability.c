/* pom_desirability.c - Derringer-Suich desirability (docs/optimize.md, section 3). */
#include "pom_desirability.h"

#include <math.h>

pom_desir_spec pom_desir_make(pom_desir_goal goal, double low, double target, double high) {
  pom_desir_spec s;
  s.goal = goal;
  s.low = low;
  s.target = target;
  s.high = high;
  s.shape_low = 1.0;
  s.shape_high = 1.0;
  s.importance = 1.0;
  return s;
}

pom_status pom_desir_validate(const pom_desir_spec *s, const char *what, pom_error *err) {
  if (!isfinite(s->low) || !isfinite(s->high) || !(s->low < s->high))
    POM_FAIL(err, POM_ERR_ARG, "desirability of %s: bounds [%g, %g] must be finite with low < high",
             what, s->low, s->high);
  if (s->goal == POM_DESIR_TARGET && !(s->low < s->target && s->target < s->high))
    POM_FAIL(err, POM_ERR_ARG, "desirability of %s: target %g must lie strictly inside [%g, %g]",
             what, s->target, s->low, s->high);
  if (!(s->shape_low > 0.0) || !(s->shape_high > 0.0) || !isfinite(s->shape_low) ||
      !isfinite(s->shape_high))
    POM_FAIL(err, POM_ERR_ARG, "desirability of %s: shapes %g, %g must be positive", what,
             s->shape_low, s->shape_high);
  if (!(s->importance > 0.0) || !isfinite(s->importance))
    POM_FAIL(err, POM_ERR_ARG, "desirability of %s: importance %g must be positive", what,
             s->importance);
  if ((int)s->goal < POM_DESIR_MAXIMIZE || (int)s->goal > POM_DESIR_TARGET)
    POM_FAIL(err, POM_ERR_ARG, "desirability of %s: unknown goal %d", what, (int)s->goal);
  return POM_OK;
}

double pom_desir_individual(const pom_desir_spec *s, double y) {
  if (!isfinite(y)) return 0.0;
  switch (s->goal) {
  case POM_DESIR_MAXIMIZE:
    if (y <= s->low) return 0.0;
    if (y >= s->high) return 1.0;
    return pow((y - s->low) / (s->high - s->low), s->shape_low);
  case POM_DESIR_MINIMIZE:
    if (y <= s->low) return 1.0;
    if (y >= s->high) return 0.0;
    return pow((s->high - y) / (s->high - s->low), s->shape_low);
  case POM_DESIR_TARGET:
    if (y <= s->low || y >= s->high) return 0.0;
    if (y <= s->target) return pow((y - s->low) / (s->target - s->low), s->shape_low);
    return pow((s->high - y) / (s->high - s->target), s->shape_high);
  }
  return 0.0;
}

double pom_desir_overall(int m, const pom_desir_spec specs[], const double y[], double d[]) {
  double wsum = 0.0, logsum = 0.0;
  int zero = 0;
  for (int i = 0; i < m; ++i) {
    double di = pom_desir_individual(&specs[i], y[i]);
    if (d) d[i] = di;
    wsum += specs[i].importance;
    if (di <= 0.0)
      zero = 1;
    else
      logsum += specs[i].importance * log(di);
  }
  if (m < 1 || zero) return 0.0;
  return exp(logsum / wsum);
}
