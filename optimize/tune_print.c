/* tune_print.c - a controller tuning as text and JSON (pom_opt_print.h;
 * what `pomlab tune` prints, docs/optimize.md section 9). */
#include "pom_opt_print.h"

#include "pom_dyn_ctrl.h"
#include "pom_json.h"

#include <math.h>

static const char *jn(char *buf, double v) {
  if (isfinite(v))
    snprintf(buf, 32, "%.10g", v);
  else
    snprintf(buf, 32, "null");
  return buf;
}

static void print_eval(FILE *out, const char *what, const pom_dyn_controller *c,
                       const pom_tune_eval *e) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(c);
  fprintf(out, "  %-8s", what);
  for (int k = 0; k < t->n_gains; ++k)
    fprintf(out, " %s %-10.5g %s", t->gains[k].key, pom_dyn_ctrl_gain(c, k), t->gains[k].unit);
  fprintf(out,
          " | criterion %8.3f ms  mean exec %7.3f ms  max exec %7.3f ms  overshoot %6.2f %%  "
          "saturation %6.3f ms  unsettled %d  energy %.4g J\n",
          e->criterion * 1e3, e->mean_execution * 1e3, e->max_execution * 1e3,
          e->max_overshoot * 100.0, e->max_saturation * 1e3, e->unsettled, e->mean_energy);
}

void pom_tune_report_text(FILE *out, const pom_tune_problem *pb, const pom_tune_result *r,
                          const char *path) {
  fprintf(out, "== %s (%s): %d maneuvers, overshoot limit %.3g %%, saturation limit %.4g ms\n",
          pb->arch.name, pom_kin_arch_name(&pb->arch), pb->n_maneuvers, pb->overshoot_max * 100.0,
          pb->saturation_time_max * 1e3);
  print_eval(out, "config", &r->initial, &r->initial_eval);
  print_eval(out, "tuned", &r->best, &r->best_eval);
  fprintf(out, "  %ld criterion evaluations (%ld global %s, %ld local %s",
          r->opt.evals_global + r->opt.evals_local, r->opt.evals_global,
          pom_opt_result_name(r->opt.result_global), r->opt.evals_local,
          pom_opt_result_name(r->opt.result_local));
  /* the multi-start local stage (tuning.optimizer.local_starts > 1) */
  if (r->opt.local_runs > 1 && r->opt.local_best_run >= 0)
    fprintf(out, " from %d starts, the best from start %d", r->opt.local_runs,
            r->opt.local_best_run + 1);
  else if (r->opt.local_runs > 1)
    fprintf(out, " from %d starts, none better than the global stage", r->opt.local_runs);
  fprintf(out, "), %ld simulations, %.2f s\n  wrote %s\n\n", r->simulations, r->opt.wall_time,
          path);
}

void pom_tune_report_json(FILE *out, const pom_tune_problem *pbs, const pom_tune_result *res, int n,
                          char paths[][512]) {
  char b[8][32], g[32];
  fprintf(out, "{\"tune\": [");
  for (int c = 0; c < n; ++c) {
    const pom_tune_eval *e = &res[c].best_eval;
    /* name (from the config) and file escaped: a quote made invalid JSON */
    fprintf(out, "%s{\"name\": ", c ? ", " : "");
    pom_json_string(out, pbs[c].arch.name);
    /* the gains by their config keys (the PID: kp, ki_per_s, kd_s) */
    const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(&res[c].best);
    fprintf(out, ", \"architecture\": \"%s\", \"controller\": ", pom_kin_arch_name(&pbs[c].arch));
    pom_json_string(out, t->name);
    for (int k = 0; k < t->n_gains; ++k) {
      fprintf(out, ", ");
      pom_json_string(out, t->gains[k].key);
      fprintf(out, ": %s", jn(g, pom_dyn_ctrl_gain(&res[c].best, k)));
    }
    fprintf(out,
            ", \"criterion_s\": %s, \"mean_execution_s\": %s, \"max_overshoot\": %s, "
            "\"max_saturation_s\": %s, \"unsettled\": %d, \"initial_criterion_s\": %s, "
            "\"evaluations\": %ld, \"simulations\": %ld, \"file\": ",
            jn(b[3], e->criterion), jn(b[4], e->mean_execution), jn(b[5], e->max_overshoot),
            jn(b[6], e->max_saturation), e->unsettled, jn(b[7], res[c].initial_eval.criterion),
            res[c].opt.evals_global + res[c].opt.evals_local, res[c].simulations);
    pom_json_string(out, paths[c]);
    fprintf(out, "}");
  }
  fprintf(out, "]}\n");
}
