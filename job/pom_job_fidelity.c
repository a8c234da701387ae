/* pom_job_fidelity.c - the fidelity each candidate earned (study.fidelity =
 * "auto", docs/results.md section 12): its setting, the errors it was
 * selected and validated with, and the validated bound beside the means it
 * affects. */
#include "pom_job.h"

#include <math.h>
#include <stdio.h>

void pom_job_fidelity_report(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  if (!study->fidelity_auto) return;
  const pom_fidelity_opts *o = &study->fidelity;
  fprintf(out,
          "\n### Fidelity earned per candidate (study.fidelity = \"auto\", accuracy %g %%)\n\n"
          "Each candidate runs the cheapest setting of the ladder (docs/tradeoff.md section 9) "
          "whose worst errors in execution time and energy against the rigid reference "
          "(inductive coil, rtol %.0e) are within %g %% / %g = %.3g %% on %d maneuvers of seed "
          "%llu (selection) and within %g %% on the study's first %d maneuvers (held out, seed "
          "%llu). The bound is the worst error measured on the held-out set; it applies to every "
          "maneuver's time and energy, hence to their means.\n\n"
          "| candidate | setting | selection error (time / energy) | mean execution time (ms) "
          "| its bound | mean energy (J) | its bound | cost (s) |\n"
          "|---|---|---|---|---|---|---|---|\n",
          o->accuracy * 100.0, o->reference_rtol, o->accuracy * 100.0, o->margin,
          o->accuracy / o->margin * 100.0, o->n_select, (unsigned long long)study->fidelity_seed,
          o->accuracy * 100.0, o->n_validate, (unsigned long long)study->maneuvers.seed);
  for (int c = 0; c < study->n_candidates; ++c) {
    const pom_doe_candidate *cand = &study->candidates[c];
    if (!cand->fidelity_chosen) continue;
    const pom_fidelity_result *f = &cand->fidelity;
    double t = rep ? rep->cand[c].execution_time.mean : NAN;
    double e = rep ? rep->cand[c].energy.mean : NAN;
    fprintf(out, "| %s | %s%s | %.2f %% / %.2f %% | %.4g | ±%.2f %% | %.4g | ±%.2f %% | %.1f |\n",
            cand->name, f->setting.label, f->met ? "" : " (**accuracy not met**)",
            100.0 * f->select_time, 100.0 * f->select_energy, t * 1e3, 100.0 * f->bound_time, e,
            100.0 * f->bound_energy, f->wall);
  }
}

void pom_job_fidelity_json(FILE *out, const pom_doe_candidate *cand) {
  if (!cand->fidelity_chosen) return;
  const pom_fidelity_result *f = &cand->fidelity;
  fprintf(out,
          ", \"fidelity\": {\"setting\": \"%s\", \"met\": %s, \"accuracy\": %.6g, "
          "\"margin\": %.6g, \"selection_error_time\": %.6g, \"selection_error_energy\": %.6g, "
          "\"error_time\": %.6g, \"error_energy\": %.6g, \"selection_maneuvers\": %d, "
          "\"validation_maneuvers\": %d}",
          f->setting.label, f->met ? "true" : "false", f->accuracy, f->margin, f->select_time,
          f->select_energy, f->bound_time, f->bound_energy, f->n_select, f->n_validate);
}
