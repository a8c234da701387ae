/* pom_job_capability.c - the capability figures of each candidate
 * (study.capability, docs/capability.md "As study responses and
 * constraints") in the report, summary.md and the JSON report. */
#include "pom_job.h"

#include <math.h>
#include <stdio.h>

void pom_job_capability_report(FILE *out, const pom_doe_study *study) {
  if (study->capability_n == 0) return;
  fprintf(out,
          "\n### Capability per candidate (study.capability; rigid joints, %d x %d x %d poses "
          "over the workspace)\n\n| candidate",
          study->capability_grid, study->capability_grid, study->capability_grid);
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
    if (study->capability_want[i])
      fprintf(out, " | %s (%s)", pom_cap_figure_name(i), pom_cap_figure_unit(i));
  if (study->n_requirements > 0) fprintf(out, " | requirements");
  fprintf(out, " |\n|---");
  for (int i = 0; i < study->capability_n + (study->n_requirements > 0); ++i)
    fprintf(out, "|---");
  fprintf(out, "|\n");
  for (int c = 0; c < study->n_candidates; ++c) {
    const pom_doe_candidate *cand = &study->candidates[c];
    fprintf(out, "| %s", cand->name);
    for (int i = 0; i < POM_CAP_N_FIGURES; ++i) {
      if (!study->capability_want[i]) continue;
      double v = cand->capability_done ? cand->capability[i] : NAN;
      if (isnan(v))
        fprintf(out, " | n/a");
      else
        fprintf(out, " | %.5g", v);
    }
    if (study->n_requirements > 0)
      fprintf(out, " | %s",
              !cand->capability_done ? "n/a"
              : cand->capability_met ? "met"
                                     : "**not met**");
    fprintf(out, " |\n");
  }
  if (study->n_requirements > 0) {
    fprintf(out, "\nRequirements (study.capability_require; a figure not computed, n/a, does "
                 "not meet one):");
    for (int j = 0; j < study->n_requirements; ++j) {
      const pom_cap_requirement *q = &study->requirement[j];
      fprintf(out, "%s %s %s %.6g %s", j ? "," : "", pom_cap_figure_name(q->figure),
              q->at_most ? "<=" : ">=", q->bound, pom_cap_figure_unit(q->figure));
    }
    fprintf(out, ".\n");
  }
  fprintf(out, "\nn/a: not computed (docs/capability.md).\n");
}

void pom_job_capability_json(FILE *out, const pom_doe_study *study, const pom_doe_candidate *cand) {
  if (study->capability_n == 0) return;
  fprintf(out, ", \"capability\": {");
  int first = 1;
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i) {
    if (!study->capability_want[i]) continue;
    double v = cand->capability_done ? cand->capability[i] : NAN;
    fprintf(out, "%s\"%s\": ", first ? "" : ", ", pom_cap_figure_name(i));
    if (isfinite(v))
      fprintf(out, "%.17g", v);
    else
      fprintf(out, "null");
    first = 0;
  }
  fprintf(out, "}");
  if (study->n_requirements > 0)
    fprintf(out, ", \"capability_met\": %s",
            !cand->capability_done ? "null"
            : cand->capability_met ? "true"
                                   : "false");
}

static double figure_of(const pom_doe_candidate *cand, int i) {
  return cand->capability_done ? cand->capability[i] : NAN;
}

void pom_job_capability_exclusions(FILE *out, const pom_doe_study *study,
                                   const pom_doe_report *rep) {
  if (study->n_requirements == 0) return;
  int nc = rep->n_candidates, nr = rep->n_ranked;
  if (nr == nc) {
    fprintf(out, "Every candidate meets study.capability_require: all %d compete.\n\n", nc);
    return;
  }
  if (nr == 0)
    fprintf(out, "**No candidate meets study.capability_require: nothing is ranked** (no "
                 "comparison, Friedman test, ranking, verdict or Pareto front).\n\n");
  fprintf(out,
          "Excluded from the comparisons, the ranking, the verdict, the Pareto front and the "
          "heat map (study.capability_require not met; their statistics and the main effects "
          "keep them): %d of %d candidates\n\n",
          nc - nr, nc);
  for (int c = 0; c < nc; ++c) {
    if (rep->ranked[c]) continue;
    const pom_doe_candidate *cand = &study->candidates[c];
    fprintf(out, "- %s:", cand->name);
    for (int j = 0, first = 1; j < study->n_requirements; ++j) {
      const pom_cap_requirement *q = &study->requirement[j];
      double v = figure_of(cand, q->figure);
      if (pom_cap_requirement_met(q, v)) continue;
      char val[48];
      if (isnan(v))
        snprintf(val, sizeof val, "n/a (not computed)");
      else
        snprintf(val, sizeof val, "%.6g %s", v, pom_cap_figure_unit(q->figure));
      fprintf(out, "%s %s = %s, required %s %.6g %s", first ? "" : ";",
              pom_cap_figure_name(q->figure), val, q->at_most ? "<=" : ">=", q->bound,
              pom_cap_figure_unit(q->figure));
      first = 0;
    }
    fprintf(out, "\n");
  }
  fprintf(out, "\n");
}

void pom_job_capability_excluded_json(FILE *out, const pom_doe_study *study,
                                      const pom_doe_report *rep) {
  if (study->n_requirements == 0) return;
  fprintf(out, ",\n  \"excluded\": [");
  for (int c = 0, n = 0; c < rep->n_candidates; ++c) {
    if (rep->ranked[c]) continue;
    const pom_doe_candidate *cand = &study->candidates[c];
    fprintf(out, "%s\n    {\"name\": \"", n++ ? "," : "");
    for (const char *p = cand->name; *p; ++p) { /* names are checked identifiers; escape anyway */
      if (*p == '"' || *p == '\\') fputc('\\', out);
      fputc(*p, out);
    }
    fprintf(out, "\", \"failed\": [");
    for (int j = 0, k = 0; j < study->n_requirements; ++j) {
      const pom_cap_requirement *q = &study->requirement[j];
      double v = figure_of(cand, q->figure);
      if (pom_cap_requirement_met(q, v)) continue;
      char text[96];
      pom_cap_requirement_text(text, sizeof text, q);
      fprintf(out, "%s{\"requirement\": \"%s\", \"figure\": \"%s\", \"value\": ", k++ ? ", " : "",
              text, pom_cap_figure_name(q->figure));
      if (isfinite(v))
        fprintf(out, "%.17g", v);
      else
        fprintf(out, "null");
      fprintf(out, ", \"op\": \"%s\", \"bound\": %.17g}", q->at_most ? "<=" : ">=", q->bound);
    }
    fprintf(out, "]}");
  }
  fprintf(out, "%s]", rep->n_ranked < rep->n_candidates ? "\n  " : "");
}

void pom_job_capability_effects(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  if (rep->n_cap_effects == 0) return;
  fprintf(out, "\n### Main effects on the capability figures (mean over each level's candidates; "
               "one value per candidate, so their range, not an interval)\n\n"
               "| factor | level | figure | unit | candidates | computed | mean | min | max |\n"
               "|---|---:|---|---|---:|---:|---:|---:|---:|\n");
  for (int j = 0; j < rep->n_cap_effects; ++j) {
    const pom_doe_cap_effect *e = &rep->cap_effects[j];
    char lv[64], v[3][32];
    if (e->lo == e->hi)
      snprintf(lv, sizeof lv, "%.6g", e->lo);
    else
      snprintf(lv, sizeof lv, "%.4g-%.4g", e->lo, e->hi);
    const double x[3] = {e->mean, e->min, e->max};
    for (int k = 0; k < 3; ++k)
      if (isfinite(x[k]))
        snprintf(v[k], sizeof v[k], "%.5g", x[k]);
      else
        snprintf(v[k], sizeof v[k], "n/a");
    fprintf(out, "| %s | %s | %s | %s | %d | %d | %s | %s | %s |\n", study->factor_label[e->factor],
            lv, pom_cap_figure_name(e->figure), pom_cap_figure_unit(e->figure), e->n_candidates,
            e->n, v[0], v[1], v[2]);
  }
}
