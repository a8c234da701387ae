/* pom_job_pipeline.c - progress and report of the design pipeline
 * (docs/optimize.md section 10, docs/results.md). */
#include "pom_dyn_ctrl.h"
#include "pom_job.h"

#include "pom_math.h"
#include "pom_pipeline.h"

#include <math.h>
#include <string.h>

/* ---- progress ------------------------------------------------------------------ */
void pom_job_phases_init(pom_job_phases *p, FILE *out) {
  memset(p, 0, sizeof *p);
  p->out = out;
}

void pom_job_phases_end(pom_job_phases *p) {
  if (!p->phase[0]) return;
  pom_progress_finish(&p->bar, p->done);
  p->phase[0] = '\0';
}

void pom_job_phases_report(void *user, const char *phase, long done, long total) {
  pom_job_phases *p = user;
  if (!p->out) return;
  if (strcmp(p->phase, phase) != 0) {
    pom_job_phases_end(p);
    snprintf(p->phase, sizeof p->phase, "%s", phase);
    pom_progress_init(&p->bar, p->out, phase, total, 0, 0);
  }
  if (total > p->bar.total) p->bar.total = total;
  p->done = done;
  pom_progress_update(&p->bar, done);
}

/* ---- report ---------------------------------------------------------------------- */
/* "key value (config value)" for every design parameter that differs, and
 * the platform radius, into buf. */
static void geometry_text(char *buf, size_t cap, const pom_pipeline_record *r) {
  const pom_kin_arch_type *t = r->arch.type;
  size_t used = 0;
  buf[0] = '\0';
  if (!r->arch.has_design || !r->config_arch.has_design) {
    snprintf(buf, cap, "(not in design-parameter form)");
    return;
  }
  int w = snprintf(buf, cap, "%s %.4g (config %.4g)", t->scale_key, r->arch.design.scale * 1e3,
                   r->config_arch.design.scale * 1e3);
  if (w > 0) used = (size_t)w < cap ? (size_t)w : cap - 1;
  for (int k = 0; k < t->n_params; ++k) {
    double v = r->arch.design.x[k] / t->params[k].to_si;
    double v0 = r->config_arch.design.x[k] / t->params[k].to_si;
    if (v == v0) continue;
    w = snprintf(buf + used, cap - used, ", %s %.4g (%.4g)", t->params[k].key, v, v0);
    if (w > 0) used += (size_t)w < cap - used ? (size_t)w : cap - used - 1;
  }
}

/* Why the synthesized, tuned candidate is slower or faster than its
 * config's geometry, from the figures the pipeline computed. */
static void geometry_effect(FILE *out, const char *name, const pom_pipeline_record *r) {
  const pom_tune_eval *base = &r->config_geometry_eval, *syn = &r->tuned_eval;
  double gap = syn->criterion - base->criterion;
  fprintf(out,
          "- %s, geometry against tuning: on the %d tuning maneuvers the config's own geometry "
          "with the config's gains scores %.2f ms (mean execution %.2f ms); the synthesized "
          "geometry scores %.2f ms with the config's gains and %.2f ms tuned (mean execution "
          "%.2f ms). ",
          name, r->n_tune_maneuvers, base->criterion * 1e3, base->mean_execution * 1e3,
          r->config_eval.criterion * 1e3, syn->criterion * 1e3, syn->mean_execution * 1e3);
  if (gap > 0.0 && !r->config_gains_in_box)
    fprintf(out,
            "The config's gains lie outside the tuning bounds, so this does not bound what tuning "
            "the config's geometry would reach; the synthesized candidate is %.2f ms slower than "
            "the config's geometry with the config's gains.\n",
            gap * 1e3);
  else if (gap > 0.0)
    fprintf(out,
            "Tuning keeps the config's gains when it finds nothing better, so tuning the "
            "config's geometry would score at most %.2f ms: the synthesized geometry is slower by "
            "at least %.2f ms (%.0f %%), a cost of the geometry, not of the tuning. The synthesis "
            "optimizes workspace, dexterity and footprint only; the dynamics of the geometry "
            "(inertia reflected to the actuators) are not among its goals.\n",
            base->criterion * 1e3, gap * 1e3, 100.0 * gap / base->criterion);
  else
    fprintf(out,
            "The synthesized, tuned geometry is %.2f ms faster than the config's geometry with "
            "the config's gains on these maneuvers.\n",
            -gap * 1e3);
}

void pom_job_pipeline_report(FILE *out, const pom_doe_study *study) {
  int any = 0;
  for (int c = 0; c < study->n_candidates; ++c) {
    const pom_pipeline_record *r = pom_pipeline_record_of(&study->candidates[c].eval);
    any |= r && (r->synthesized || r->tuned || r->sized);
  }
  if (!any) return;
  fprintf(out,
          "### Pipeline: synthesized geometry and tuned gains\n\n"
          "| candidate | geometry run (config's value in brackets) | controller and gains (SI) "
          "| tuning criterion (ms): config gains -> tuned | time (s): synthesis, "
          "tuning |\n|---|---|---|---|---|\n");
  for (int c = 0; c < study->n_candidates; ++c) {
    const pom_pipeline_record *r = pom_pipeline_record_of(&study->candidates[c].eval);
    if (!r || !(r->synthesized || r->tuned || r->sized)) continue;
    char geo[1024] = "config's";
    if (r->synthesized || r->sized) geometry_text(geo, sizeof geo, r);
    char crit[96] = "-";
    if (r->tuned)
      snprintf(crit, sizeof crit, "%.2f -> %.2f", r->config_eval.criterion * 1e3,
               r->tuned_eval.criterion * 1e3);
    const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(&r->tuned_gains);
    char gains[512];
    int len = snprintf(gains, sizeof gains, "%s:", t->name);
    for (int k = 0; k < t->n_gains && len >= 0 && (size_t)len < sizeof gains; ++k)
      len += snprintf(gains + len, sizeof gains - (size_t)len, "%s %s %.5g", k ? "," : "",
                      t->gains[k].key, pom_dyn_ctrl_gain(&r->tuned_gains, k));
    fprintf(out, "| %s | %s | %s%s | %s | %.1f, %.1f |\n", study->candidates[c].name, geo, gains,
            r->tuned ? " (tuned)" : " (config's)", crit, r->synthesis_time + r->sizing_time,
            r->tuning_time);
  }
  fprintf(out, "\n");
  for (int c = 0; c < study->n_candidates; ++c) {
    const pom_pipeline_record *r = pom_pipeline_record_of(&study->candidates[c].eval);
    const char *name = study->candidates[c].name;
    if (!r || !(r->synthesized || r->tuned || r->sized)) continue;
    if (r->sized)
      fprintf(out,
              "- %s, sizing (docs/optimize.md 6c): %s %.4g mm (config %.4g mm), %s; its regular "
              "dexterous workspace covers the target +-%.4g deg (searched to +-%.4g deg).\n",
              name, r->arch.type->scale_key, r->arch.design.scale * 1e3,
              r->config_arch.design.scale * 1e3,
              r->sizing_scaled ? "the largest whose stroke covers the target (linear actuators)"
                               : "kept (rotary actuators: no scale changes their angles)",
              r->sizing_target / POM_DEG, r->sizing_rdw / POM_DEG);
    if (r->synthesized) {
      fprintf(out,
              "- %s, synthesis: the %s optimum is run (synthesis.write = \"%s\"); true "
              "desirability at the base scale %.4f surrogate",
              name, r->written_direct ? "direct-search" : "surrogate", pom_syn_write_name(r->write),
              r->d_surrogate);
      if (isfinite(r->d_direct)) fprintf(out, ", %.4f direct search", r->d_direct);
      fprintf(out, ".");
      if (r->direct_better && !r->written_direct)
        fprintf(out, " The direct search found a better design; synthesis.write = \"best\" or "
                     "\"direct\" runs it.");
      fprintf(out, " Predicted R2 of the goal surfaces:");
      for (int g = 0; g < r->n_goals; ++g)
        fprintf(out, "%s %s %.3f", g ? "," : "", pom_syn_resp_name(r->goal_resp[g]),
                r->goal_r2_pred[g]);
      fprintf(out, ".");
      if (r->n_negative_r2_pred > 0)
        fprintf(out,
                " **Warning:** %d surface(s) predict left-out runs worse than their mean "
                "(predicted R2 < 0; `pomlab synth` names them).",
                r->n_negative_r2_pred);
      fprintf(out, "\n");
    }
    if (r->config_geometry_evaluated) geometry_effect(out, name, r);
    fprintf(out, "- %s, files:", name);
    const char *files[3] = {r->geometry_file, r->synthesis_file, r->controller_file};
    int n = 0;
    for (int f = 0; f < 3; ++f)
      if (files[f][0]) fprintf(out, "%s `%s`", n++ ? "," : "", files[f]);
    fprintf(out, "%s\n", n ? "" : " none written");
  }
  fprintf(out, "\n");
}
