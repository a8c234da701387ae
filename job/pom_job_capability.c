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
