/* syn_print.c - a kinematic synthesis as text and JSON (pom_opt_print.h;
 * what `pomlab synth` prints, docs/optimize.md). */
#include "pom_opt_print.h"

#include "pom_json.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const anova_names[POM_RSM_N_ROWS] = {
    "model", "linear", "square", "interaction", "residual", "lack of fit", "pure error", "total"};

/* A number in fmt, or a right-aligned "-" of the same width when it is not
   finite (a row without that statistic). */
static void fmt_or_dash(char *buf, size_t cap, const char *fmt, double v) {
  if (isfinite(v)) {
    snprintf(buf, cap, fmt, v);
  } else {
    int width = atoi(fmt + 1);
    snprintf(buf, cap, "%*s", width, "-");
  }
}

/* Surfaces that predict new runs worse than the runs' own mean (predicted
 * R^2 < 0, docs/optimize.md 2.2), in every stage: the optimum on them is a
 * guess the confirmation and the direct search must check. */
void pom_syn_fit_warnings(FILE *out, const pom_syn_run *run) {
  int stage = 0;
  for (const pom_syn_run *s = run; s; s = s->refined, ++stage)
    for (int r = 0; r < POM_SYN_N_RESP; ++r)
      if (s->fitted[r] && s->fit[r].r2_pred < 0.0)
        fprintf(out,
                "  warning: stage %d surface of %s has a negative predicted R2 (%.4f): it predicts "
                "left-out runs worse than their mean; rely on the confirmation and the direct "
                "search, or narrow the box (refine_stages)\n",
                stage, pom_syn_resp_name((pom_syn_resp)r), s->fit[r].r2_pred);
}

/* The capability floor (synthesis.capability_require): each optimum checked,
 * each requirement with its value and bound, and what was written. */
static void cap_text(FILE *out, const pom_syn_run *run) {
  const pom_syn_cap *c = &run->pb->cap;
  if (run->n_cap_checks == 0) return;
  fprintf(out,
          "\ncapability floor (synthesis.capability_require; the scaled geometry with the "
          "config's inertia, actuator and controller, %d x %d x %d poses):\n",
          c->grid, c->grid, c->grid);
  for (int k = 0; k < run->n_cap_checks; ++k) {
    const pom_syn_cap_check *ck = &run->cap_check[k];
    fprintf(out, "  %s optimum (D = %.4f), platform radius %.4f mm: %s\n",
            ck->direct ? "direct-search" : "surrogate", ck->d, ck->scale * 1e3,
            ck->all_met ? "meets every requirement" : "does NOT meet them");
    for (int j = 0; j < c->n; ++j) {
      const pom_cap_requirement *q = &c->req[j];
      double v = ck->value[q->figure];
      fprintf(out, "    %s = ", pom_cap_figure_name(q->figure));
      if (isnan(v))
        fprintf(out, "n/a (not computed)");
      else
        fprintf(out, "%.6g %s", v, pom_cap_figure_unit(q->figure));
      fprintf(out, ", required %s %.6g %s: %s\n", q->at_most ? "<=" : ">=", q->bound,
              pom_cap_figure_unit(q->figure), ck->met[j] ? "holds" : "FAILS");
    }
    if (ck->note[0]) fprintf(out, "    (%s)\n", ck->note);
  }
  if (run->cap_switched)
    fprintf(out, "  the %s optimum meets the floor: it is the one written (the %s one fails)\n",
            run->written_direct ? "direct-search" : "surrogate",
            run->written_direct ? "surrogate" : "direct-search");
  else if (!run->cap_met)
    fprintf(out,
            "  NO optimum meets the floor: the %s one is written for inspection; exit "
            "status 1\n",
            run->written_direct ? "direct-search" : "surrogate");
}

void pom_syn_report_text(FILE *out, const pom_syn_run *run, const char *geo_path,
                         const char *h5_path) {
  const pom_syn_problem *pb = run->pb;
  int k = pb->n_vars;
  fprintf(out, "== %s (%s)\n", pb->base.name, pom_kin_arch_name(&pb->base));
  fprintf(out, "design: %s, %d runs (alpha %.4g), %d degenerate, %.3f s\n",
          pom_design_kind_name(run->design->kind), run->n_runs, run->design->alpha,
          run->n_degenerate, run->design_time);
  fprintf(out, "variables:");
  for (int i = 0; i < k; ++i)
    fprintf(out, "  %s in [%.4g, %.4g]", pom_syn_var_name(pb, i),
            pb->lo[i] * pom_syn_var_unit(pb, i), pb->hi[i] * pom_syn_var_unit(pb, i));
  fprintf(out, "\n\nfits (full quadratic, coded units):\n");
  fprintf(out, "  %-14s %8s %8s %8s %20s %10s %10s %9s\n", "response", "R2", "R2adj", "R2pred",
          "lack-of-fit p", "hold rmse", "hold maxab", "in PI");
  for (int r = 0; r < POM_SYN_N_RESP; ++r) {
    double u = pom_syn_resp_unit((pom_syn_resp)r);
    if (!run->fitted[r]) {
      fprintf(out, "  %-14s constant over the design: %.6g\n", pom_syn_resp_name((pom_syn_resp)r),
              run->resp[r] * u);
      continue;
    }
    const pom_rsm_fit *f = &run->fit[r];
    const pom_rsm_check *c = &run->check[r];
    char lof[40];
    const char *note = pom_rsm_lack_of_fit_note(f);
    if (note)
      snprintf(lof, sizeof lof, "n/a (%s)", note);
    else
      snprintf(lof, sizeof lof, "%.3g", f->anova[POM_RSM_ROW_LACK_OF_FIT].p);
    fprintf(out, "  %-14s %8.4f %8.4f %8.4f %20s %10.4g %10.4g %9.2f\n",
            pom_syn_resp_name((pom_syn_resp)r), f->r2, f->r2_adj, f->r2_pred, lof, c->rmse * u,
            c->max_abs * u, c->within_pi);
  }
  pom_syn_fit_warnings(out, run);
  /* ANOVA of the first goal's surface */
  pom_syn_resp g0 = pb->goal_resp[0];
  if (run->fitted[g0]) {
    const pom_rsm_fit *f = &run->fit[g0];
    /* the fit is in internal units (rad for rdw_deg): shown in the response's
       printed unit, like the table above (F and p do not depend on it) */
    double u0 = pom_syn_resp_unit(g0);
    fprintf(out,
            "\nANOVA of %s (sums of squares in its unit squared, coefficients per coded unit):\n"
            "  %-12s %12s %5s %12s %10s %10s\n",
            pom_syn_resp_name(g0), "source", "SS", "df", "MS", "F", "p");
    for (int r = 0; r < POM_RSM_N_ROWS; ++r) {
      const pom_rsm_anova_row *a = &f->anova[r];
      if ((r == POM_RSM_ROW_LACK_OF_FIT || r == POM_RSM_ROW_PURE_ERROR) && !f->has_lack_of_fit)
        continue;
      /* rows without a test (residual, total, zero pure error) show "-", not nan */
      char ms[32], fv[32], pv[32];
      fmt_or_dash(ms, sizeof ms, "%12.5g", a->ms * u0 * u0);
      fmt_or_dash(fv, sizeof fv, "%10.4g", a->f);
      fmt_or_dash(pv, sizeof pv, "%10.3g", a->p);
      fprintf(out, "  %-12s %12.5g %5.0f %12s %10s %10s\n", anova_names[r], a->ss * u0 * u0, a->df,
              ms, fv, pv);
    }
    fprintf(out, "  coefficients: ");
    for (int j = 0; j < f->p; ++j) {
      char nm[16];
      pom_rsm_term_name(f->k, j, nm, sizeof nm);
      fprintf(out, "%s%s %.4g (se %.2g)", j ? ", " : "", nm, f->beta[j] * u0, f->se[j] * u0);
    }
    fprintf(out, "\n");
  }
  fprintf(out, "\noptimum on the surfaces (D = %.4f predicted, %.4f confirmed):\n ",
          run->d_predicted, run->d_confirmed);
  for (int i = 0; i < k; ++i)
    fprintf(out, " %s = %.5g", pom_syn_var_name(pb, i), run->x_opt[i] * pom_syn_var_unit(pb, i));
  fprintf(out, "\n  %-14s %12s %12s %12s\n", "response", "predicted", "confirmed", "error");
  for (int r = 0; r < POM_SYN_N_RESP; ++r) {
    double u = pom_syn_resp_unit((pom_syn_resp)r);
    fprintf(out, "  %-14s %12.5g %12.5g %12.3g\n", pom_syn_resp_name((pom_syn_resp)r),
            run->predicted[r] * u, run->confirmed[r] * u,
            (run->predicted[r] - run->confirmed[r]) * u);
  }
  if (run->refined) {
    fprintf(out, "\nsequential refinement (best: stage %d):\n  %-6s %5s", run->best_stage, "stage",
            "runs");
    for (int i = 0; i < k; ++i)
      fprintf(out, " %24s", pom_syn_var_name(pb, i));
    fprintf(out, " %9s %9s %9s\n", "R2pred", "D pred", "D true");
    int s = 0;
    for (const pom_syn_run *r = run; r; r = r->refined, ++s) {
      fprintf(out, "  %-6d %5d", s, r->n_runs);
      for (int i = 0; i < k; ++i) {
        double u = pom_syn_var_unit(pb, i);
        char box[64];
        snprintf(box, sizeof box, "%.4g [%.4g, %.4g]", r->stage_x_opt[i] * u, r->pb->lo[i] * u,
                 r->pb->hi[i] * u);
        fprintf(out, " %24s", box);
      }
      pom_syn_resp g = pb->goal_resp[0];
      fprintf(out, " %9.4f %9.4f %9.4f\n", r->fitted[g] ? r->fit[g].r2_pred : NAN,
              r->stage_d_predicted, r->stage_d_confirmed);
    }
    fprintf(out, "  (R2pred of the first goal's surface, %s)\n",
            pom_syn_resp_name(pb->goal_resp[0]));
  }
  fprintf(
      out,
      "  surrogate route: %ld true evaluations (design, held-out and confirmation runs of every "
      "stage), %ld surface evaluations in the first stage, %.3f s\n",
      run->true_evals, run->surrogate.evals_global + run->surrogate.evals_local,
      run->surrogate_time);
  if (run->direct_done) {
    fprintf(out, "\ndirect optimization on the true kinematics (D = %.4f):\n ", run->d_direct);
    for (int i = 0; i < k; ++i)
      fprintf(out, " %s = %.5g", pom_syn_var_name(pb, i),
              run->x_direct[i] * pom_syn_var_unit(pb, i));
    fprintf(out, "\n  %ld true evaluations (%ld global %s, %ld local %s), %.3f s\n",
            run->direct.evals_global + run->direct.evals_local, run->direct.evals_global,
            pom_opt_result_name(run->direct.result_global), run->direct.evals_local,
            pom_opt_result_name(run->direct.result_local), run->direct.wall_time);
  }
  if (run->direct_better)
    fprintf(out,
            "\nthe direct search found a better design than the surrogate: D = %.4f against %.4f "
            "(true kinematics at the base scale); %s\n",
            run->d_direct, run->d_confirmed,
            run->written_direct ? "it is the one written"
                                : "the surrogate's is written (synthesis.write = \"surrogate\"; "
                                  "\"direct\" or \"best\" writes the direct one)");
  fprintf(out,
          "\nscaled the %s optimum (synthesis.write = \"%s\") to the %.4g mm stroke for +-%.3g "
          "deg: platform radius %.4f mm (%d workspace evaluations)\n",
          run->written_direct ? "direct-search" : "surrogate", pom_syn_write_name(pb->write),
          pb->base.stroke * 1e3, pb->target_half_width / POM_DEG, run->scale * 1e3,
          run->scale_evals);
  cap_text(out, run);
  fprintf(out, "  wrote %s and %s\n\n", geo_path, h5_path);
}

void pom_syn_compare_text(FILE *out, pom_syn_run *const runs[], int n) {
  fprintf(out, "== side by side (scaled geometries)\n  %-26s", "");
  for (int c = 0; c < n; ++c)
    fprintf(out, " %16s", pom_kin_arch_name(&runs[c]->pb->base));
  fprintf(out, "\n  %-26s", "platform radius (mm)");
  for (int c = 0; c < n; ++c)
    fprintf(out, " %16.4f", runs[c]->scale * 1e3);
  fprintf(out, "\n  %-26s", "footprint radius (mm)");
  for (int c = 0; c < n; ++c)
    fprintf(out, " %16.4f", runs[c]->scaled_resp[POM_SYN_RESP_FOOTPRINT] * runs[c]->scale * 1e3);
  for (int r = 0; r < POM_SYN_N_RESP; ++r) {
    if (r == POM_SYN_RESP_FOOTPRINT) continue;
    fprintf(out, "\n  %-26s", pom_syn_resp_name((pom_syn_resp)r));
    for (int c = 0; c < n; ++c)
      fprintf(out, " %16.5g", runs[c]->scaled_resp[r] * pom_syn_resp_unit((pom_syn_resp)r));
  }
  fprintf(out, "\n  %-26s", "desirability (true)");
  for (int c = 0; c < n; ++c)
    fprintf(out, " %16.4f", pom_syn_desirability(runs[c]->pb, runs[c]->scaled_resp, NULL));
  fprintf(out, "\n");
}

/* A JSON number, or null for NaN/Inf (absent values). */
static const char *jn(char *buf, double v) {
  if (isfinite(v))
    snprintf(buf, 32, "%.10g", v);
  else
    snprintf(buf, 32, "null");
  return buf;
}

/* "capability": {"requirements": [...], "checks": [...], "met", "switched"},
 * or nothing without a floor. SI values, null where not computed. */
static void cap_json(FILE *out, const pom_syn_run *run) {
  const pom_syn_cap *c = &run->pb->cap;
  char b1[32], b2[32], text[96];
  if (run->n_cap_checks == 0) return;
  fprintf(out, " \"capability\": {\"grid_points\": %d, \"requirements\": [", c->grid);
  for (int j = 0; j < c->n; ++j) {
    pom_cap_requirement_text(text, sizeof text, &c->req[j]);
    fprintf(out, "%s\"%s\"", j ? ", " : "", text);
  }
  fprintf(out, "], \"checks\": [");
  for (int k = 0; k < run->n_cap_checks; ++k) {
    const pom_syn_cap_check *ck = &run->cap_check[k];
    fprintf(out, "%s{\"optimum\": \"%s\", \"desirability\": %s, \"platform_radius_mm\": %s, ",
            k ? ", " : "", ck->direct ? "direct" : "surrogate", jn(b1, ck->d),
            jn(b2, ck->scale * 1e3));
    fprintf(out, "\"met\": %s, \"requirements\": [", ck->all_met ? "true" : "false");
    for (int j = 0; j < c->n; ++j) {
      const pom_cap_requirement *q = &c->req[j];
      pom_cap_requirement_text(text, sizeof text, q);
      fprintf(out,
              "%s{\"requirement\": \"%s\", \"figure\": \"%s\", \"value\": %s, \"op\": "
              "\"%s\", \"bound\": %s, \"met\": %s}",
              j ? ", " : "", text, pom_cap_figure_name(q->figure), jn(b1, ck->value[q->figure]),
              q->at_most ? "<=" : ">=", jn(b2, q->bound), ck->met[j] ? "true" : "false");
    }
    fprintf(out, "], \"note\": ");
    pom_json_string(out, ck->note);
    fprintf(out, "}");
  }
  fprintf(out, "], \"met\": %s, \"switched\": %s},", run->cap_met ? "true" : "false",
          run->cap_switched ? "true" : "false");
}

void pom_syn_report_json(FILE *out, pom_syn_run *const runs[], int n, char paths[][2][512]) {
  char b1[32], b2[32], b3[32], b4[32], b5[32], b6[32], b7[32];
  fprintf(out, "{\"synth\": [");
  for (int c = 0; c < n; ++c) {
    const pom_syn_run *run = runs[c];
    const pom_syn_problem *pb = run->pb;
    /* the name comes from the config: escaped (a quote made invalid JSON) */
    fprintf(out, "%s{\"name\": ", c ? ", " : "");
    pom_json_string(out, pb->base.name);
    fprintf(out, ", \"architecture\": \"%s\", \"runs\": %d, \"degenerate\": %d,",
            pom_kin_arch_name(&pb->base), run->n_runs, run->n_degenerate);
    fprintf(out, " \"variables\": {");
    for (int i = 0; i < pb->n_vars; ++i)
      fprintf(out, "%s\"%s\": {\"optimum\": %s, \"direct\": %s}", i ? ", " : "",
              pom_syn_var_name(pb, i), jn(b1, run->x_opt[i] * pom_syn_var_unit(pb, i)),
              jn(b2, run->direct_done ? run->x_direct[i] * pom_syn_var_unit(pb, i) : NAN));
    fprintf(out, "}, \"responses\": {");
    for (int r = 0; r < POM_SYN_N_RESP; ++r) {
      double u = pom_syn_resp_unit((pom_syn_resp)r);
      int f = run->fitted[r];
      fprintf(out,
              "%s\"%s\": {\"predicted\": %s, \"confirmed\": %s, \"scaled\": %s, "
              "\"r2\": %s, \"r2_adj\": %s, \"r2_pred\": %s, \"holdout_rmse\": %s}",
              r ? ", " : "", pom_syn_resp_name((pom_syn_resp)r), jn(b1, run->predicted[r] * u),
              jn(b2, run->confirmed[r] * u), jn(b3, run->scaled_resp[r] * u),
              jn(b4, f ? run->fit[r].r2 : NAN), jn(b5, f ? run->fit[r].r2_adj : NAN),
              jn(b6, f ? run->fit[r].r2_pred : NAN),
              jn(b7, f && run->n_holdout ? run->check[r].rmse * u : NAN));
    }
    fprintf(out, "}, \"desirability_predicted\": %s, \"desirability_confirmed\": %s,",
            jn(b1, run->d_predicted), jn(b2, run->d_confirmed));
    fprintf(out, " \"surrogate\": {\"true_evals\": %d, \"surface_evals\": %ld, \"time_s\": %s},",
            (int)run->true_evals, run->surrogate.evals_global + run->surrogate.evals_local,
            jn(b1, run->surrogate_time));
    if (run->direct_done)
      fprintf(out, " \"direct\": {\"desirability\": %s, \"true_evals\": %ld, \"time_s\": %s},",
              jn(b1, run->d_direct), run->direct.evals_global + run->direct.evals_local,
              jn(b2, run->direct.wall_time));
    fprintf(out, " \"direct_better\": %s, \"written\": \"%s\",",
            run->direct_better ? "true" : "false", run->written_direct ? "direct" : "surrogate");
    cap_json(out, run);
    fprintf(out, " \"platform_radius_mm\": %s, \"geometry_file\": ", jn(b1, run->scale * 1e3));
    pom_json_string(out, paths[c][0]);
    fprintf(out, ", \"h5_file\": ");
    pom_json_string(out, paths[c][1]);
    fprintf(out, "}");
  }
  fprintf(out, "]}\n");
}
