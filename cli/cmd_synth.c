/* cmd_synth.c - `pomlab synth CFG [CFG ...]`: kinematic synthesis of one or
 * more architectures (docs/optimize.md), side by side when several. */
#include "cli_kin.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_pipeline.h"
#include "pom_math.h"
#include "pom_progress.h"
#include "pom_synth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CFGS 4

static void usage(FILE *out) {
  fprintf(out,
          "usage: pomlab synth CFG [CFG ...] [--out PREFIX] [--no-direct] [--json] [--quiet]\n\n"
          "Kinematic synthesis by response surfaces and desirability (docs/optimize.md).\n"
          "Each CFG needs architecture, geometry (mode = \"parameters\"), limits, workspace\n"
          "and synthesis groups. Writes PREFIX<name>.geometry.cfg (the scaled geometry, a\n"
          "`geometry` group for simulate/montecarlo/study) and PREFIX<name>.h5 (design,\n"
          "fits, optimum, confirmation). PREFIX defaults to results/synth_.\n\n"
          "  --out PREFIX  output path prefix (its folder must exist)\n"
          "  --no-direct   skip the direct NLopt search on the true kinematics\n"
          "                (synthesis.direct.enabled = false)\n"
          "  --json        JSON on stdout (variables and responses in their config units)\n"
          "  --quiet       no progress bar\n"
          "  --help        this text\n\n"
          "Exit status: 0 ok; 1 a run failed or a file cannot be written; 2 usage or\n"
          "config error.\n");
}

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
static void print_fit_warnings(FILE *out, const pom_syn_run *run) {
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

static void print_human(const pom_syn_run *run, const char *geo_path, const char *h5_path) {
  const pom_syn_problem *pb = run->pb;
  int k = pb->n_vars;
  printf("== %s (%s)\n", pb->base.name, pom_kin_arch_name(&pb->base));
  printf("design: %s, %d runs (alpha %.4g), %d degenerate, %.3f s\n",
         pom_design_kind_name(run->design->kind), run->n_runs, run->design->alpha,
         run->n_degenerate, run->design_time);
  printf("variables:");
  for (int i = 0; i < k; ++i)
    printf("  %s in [%.4g, %.4g]", pom_syn_var_name(pb, i), pb->lo[i] * pom_syn_var_unit(pb, i),
           pb->hi[i] * pom_syn_var_unit(pb, i));
  printf("\n\nfits (full quadratic, coded units):\n");
  printf("  %-14s %8s %8s %8s %20s %10s %10s %9s\n", "response", "R2", "R2adj", "R2pred",
         "lack-of-fit p", "hold rmse", "hold maxab", "in PI");
  for (int r = 0; r < POM_SYN_N_RESP; ++r) {
    double u = pom_syn_resp_unit((pom_syn_resp)r);
    if (!run->fitted[r]) {
      printf("  %-14s constant over the design: %.6g\n", pom_syn_resp_name((pom_syn_resp)r),
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
    printf("  %-14s %8.4f %8.4f %8.4f %20s %10.4g %10.4g %9.2f\n",
           pom_syn_resp_name((pom_syn_resp)r), f->r2, f->r2_adj, f->r2_pred, lof, c->rmse * u,
           c->max_abs * u, c->within_pi);
  }
  print_fit_warnings(stdout, run);
  /* ANOVA of the first goal's surface */
  pom_syn_resp g0 = pb->goal_resp[0];
  if (run->fitted[g0]) {
    const pom_rsm_fit *f = &run->fit[g0];
    /* the fit is in internal units (rad for rdw_deg): shown in the response's
       printed unit, like the table above (F and p do not depend on it) */
    double u0 = pom_syn_resp_unit(g0);
    printf("\nANOVA of %s (sums of squares in its unit squared, coefficients per coded unit):\n"
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
      printf("  %-12s %12.5g %5.0f %12s %10s %10s\n", anova_names[r], a->ss * u0 * u0, a->df, ms,
             fv, pv);
    }
    printf("  coefficients: ");
    for (int j = 0; j < f->p; ++j) {
      char nm[16];
      pom_rsm_term_name(f->k, j, nm, sizeof nm);
      printf("%s%s %.4g (se %.2g)", j ? ", " : "", nm, f->beta[j] * u0, f->se[j] * u0);
    }
    printf("\n");
  }
  printf("\noptimum on the surfaces (D = %.4f predicted, %.4f confirmed):\n ", run->d_predicted,
         run->d_confirmed);
  for (int i = 0; i < k; ++i)
    printf(" %s = %.5g", pom_syn_var_name(pb, i), run->x_opt[i] * pom_syn_var_unit(pb, i));
  printf("\n  %-14s %12s %12s %12s\n", "response", "predicted", "confirmed", "error");
  for (int r = 0; r < POM_SYN_N_RESP; ++r) {
    double u = pom_syn_resp_unit((pom_syn_resp)r);
    printf("  %-14s %12.5g %12.5g %12.3g\n", pom_syn_resp_name((pom_syn_resp)r),
           run->predicted[r] * u, run->confirmed[r] * u,
           (run->predicted[r] - run->confirmed[r]) * u);
  }
  if (run->refined) {
    printf("\nsequential refinement (best: stage %d):\n  %-6s %5s", run->best_stage, "stage",
           "runs");
    for (int i = 0; i < k; ++i)
      printf(" %24s", pom_syn_var_name(pb, i));
    printf(" %9s %9s %9s\n", "R2pred", "D pred", "D true");
    int s = 0;
    for (const pom_syn_run *r = run; r; r = r->refined, ++s) {
      printf("  %-6d %5d", s, r->n_runs);
      for (int i = 0; i < k; ++i) {
        double u = pom_syn_var_unit(pb, i);
        char box[64];
        snprintf(box, sizeof box, "%.4g [%.4g, %.4g]", r->stage_x_opt[i] * u, r->pb->lo[i] * u,
                 r->pb->hi[i] * u);
        printf(" %24s", box);
      }
      pom_syn_resp g = pb->goal_resp[0];
      printf(" %9.4f %9.4f %9.4f\n", r->fitted[g] ? r->fit[g].r2_pred : NAN, r->stage_d_predicted,
             r->stage_d_confirmed);
    }
    printf("  (R2pred of the first goal's surface, %s)\n", pom_syn_resp_name(pb->goal_resp[0]));
  }
  printf("  surrogate route: %ld true evaluations (design, held-out and confirmation runs of every "
         "stage), %ld surface evaluations in the first stage, %.3f s\n",
         run->true_evals, run->surrogate.evals_global + run->surrogate.evals_local,
         run->surrogate_time);
  if (run->direct_done) {
    printf("\ndirect optimization on the true kinematics (D = %.4f):\n ", run->d_direct);
    for (int i = 0; i < k; ++i)
      printf(" %s = %.5g", pom_syn_var_name(pb, i), run->x_direct[i] * pom_syn_var_unit(pb, i));
    printf("\n  %ld true evaluations (%ld global %s, %ld local %s), %.3f s\n",
           run->direct.evals_global + run->direct.evals_local, run->direct.evals_global,
           pom_opt_result_name(run->direct.result_global), run->direct.evals_local,
           pom_opt_result_name(run->direct.result_local), run->direct.wall_time);
  }
  if (run->direct_better)
    printf("\nthe direct search found a better design than the surrogate: D = %.4f against %.4f "
           "(true kinematics at the base scale); %s\n",
           run->d_direct, run->d_confirmed,
           run->written_direct ? "it is the one written"
                               : "the surrogate's is written (synthesis.write = \"surrogate\"; "
                                 "\"direct\" or \"best\" writes the direct one)");
  printf("\nscaled the %s optimum (synthesis.write = \"%s\") to the %.4g mm stroke for +-%.3g "
         "deg: platform radius %.4f mm (%d workspace evaluations)\n",
         run->written_direct ? "direct-search" : "surrogate", pom_syn_write_name(pb->write),
         pb->base.stroke * 1e3, pb->target_half_width / POM_DEG, run->scale * 1e3,
         run->scale_evals);
  printf("  wrote %s and %s\n\n", geo_path, h5_path);
}

static void print_side_by_side(pom_syn_run *const runs[], int n) {
  printf("== side by side (scaled geometries)\n  %-26s", "");
  for (int c = 0; c < n; ++c)
    printf(" %16s", pom_kin_arch_name(&runs[c]->pb->base));
  printf("\n  %-26s", "platform radius (mm)");
  for (int c = 0; c < n; ++c)
    printf(" %16.4f", runs[c]->scale * 1e3);
  printf("\n  %-26s", "footprint radius (mm)");
  for (int c = 0; c < n; ++c)
    printf(" %16.4f", runs[c]->scaled_resp[POM_SYN_RESP_FOOTPRINT] * runs[c]->scale * 1e3);
  for (int r = 0; r < POM_SYN_N_RESP; ++r) {
    if (r == POM_SYN_RESP_FOOTPRINT) continue;
    printf("\n  %-26s", pom_syn_resp_name((pom_syn_resp)r));
    for (int c = 0; c < n; ++c)
      printf(" %16.5g", runs[c]->scaled_resp[r] * pom_syn_resp_unit((pom_syn_resp)r));
  }
  printf("\n  %-26s", "desirability (true)");
  for (int c = 0; c < n; ++c)
    printf(" %16.4f", pom_syn_desirability(runs[c]->pb, runs[c]->scaled_resp, NULL));
  printf("\n");
}

/* A JSON number, or null for NaN/Inf (absent values). */
static const char *jn(char *buf, double v) {
  if (isfinite(v))
    snprintf(buf, 32, "%.10g", v);
  else
    snprintf(buf, 32, "null");
  return buf;
}

static void print_json(pom_syn_run *const runs[], int n, char paths[][2][512]) {
  char b1[32], b2[32], b3[32], b4[32], b5[32], b6[32], b7[32];
  printf("{\"synth\": [");
  for (int c = 0; c < n; ++c) {
    const pom_syn_run *run = runs[c];
    const pom_syn_problem *pb = run->pb;
    /* the name comes from the config: escaped (a quote made invalid JSON) */
    printf("%s{\"name\": ", c ? ", " : "");
    pom_json_string(stdout, pb->base.name);
    printf(", \"architecture\": \"%s\", \"runs\": %d, \"degenerate\": %d,",
           pom_kin_arch_name(&pb->base), run->n_runs, run->n_degenerate);
    printf(" \"variables\": {");
    for (int i = 0; i < pb->n_vars; ++i)
      printf("%s\"%s\": {\"optimum\": %s, \"direct\": %s}", i ? ", " : "", pom_syn_var_name(pb, i),
             jn(b1, run->x_opt[i] * pom_syn_var_unit(pb, i)),
             jn(b2, run->direct_done ? run->x_direct[i] * pom_syn_var_unit(pb, i) : NAN));
    printf("}, \"responses\": {");
    for (int r = 0; r < POM_SYN_N_RESP; ++r) {
      double u = pom_syn_resp_unit((pom_syn_resp)r);
      int f = run->fitted[r];
      printf("%s\"%s\": {\"predicted\": %s, \"confirmed\": %s, \"scaled\": %s, "
             "\"r2\": %s, \"r2_adj\": %s, \"r2_pred\": %s, \"holdout_rmse\": %s}",
             r ? ", " : "", pom_syn_resp_name((pom_syn_resp)r), jn(b1, run->predicted[r] * u),
             jn(b2, run->confirmed[r] * u), jn(b3, run->scaled_resp[r] * u),
             jn(b4, f ? run->fit[r].r2 : NAN), jn(b5, f ? run->fit[r].r2_adj : NAN),
             jn(b6, f ? run->fit[r].r2_pred : NAN),
             jn(b7, f && run->n_holdout ? run->check[r].rmse * u : NAN));
    }
    printf("}, \"desirability_predicted\": %s, \"desirability_confirmed\": %s,",
           jn(b1, run->d_predicted), jn(b2, run->d_confirmed));
    printf(" \"surrogate\": {\"true_evals\": %d, \"surface_evals\": %ld, \"time_s\": %s},",
           (int)run->true_evals, run->surrogate.evals_global + run->surrogate.evals_local,
           jn(b1, run->surrogate_time));
    if (run->direct_done)
      printf(" \"direct\": {\"desirability\": %s, \"true_evals\": %ld, \"time_s\": %s},",
             jn(b1, run->d_direct), run->direct.evals_global + run->direct.evals_local,
             jn(b2, run->direct.wall_time));
    printf(" \"direct_better\": %s, \"written\": \"%s\",", run->direct_better ? "true" : "false",
           run->written_direct ? "direct" : "surrogate");
    printf(" \"platform_radius_mm\": %s, \"geometry_file\": ", jn(b1, run->scale * 1e3));
    pom_json_string(stdout, paths[c][0]);
    printf(", \"h5_file\": ");
    pom_json_string(stdout, paths[c][1]);
    printf("}");
  }
  printf("]}\n");
}

int pom_cmd_synth(int argc, char **argv) {
  const char *cfg_paths[MAX_CFGS];
  int ncfg = 0, json = 0, no_direct = 0, quiet = 0;
  const char *prefix = "results/synth_";
  for (int a = 1; a < argc; ++a) {
    if (strcmp(argv[a], "--help") == 0 || strcmp(argv[a], "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(argv[a], "--json") == 0) {
      json = 1;
    } else if (strcmp(argv[a], "--no-direct") == 0) {
      no_direct = 1;
    } else if (strcmp(argv[a], "--quiet") == 0) {
      quiet = 1;
    } else if (strcmp(argv[a], "--out") == 0 && a + 1 < argc) {
      prefix = argv[++a];
    } else if (argv[a][0] == '-') {
      fprintf(stderr, "pomlab synth: unknown option '%s'\n", argv[a]);
      usage(stderr);
      return 2;
    } else if (ncfg < MAX_CFGS) {
      cfg_paths[ncfg++] = argv[a];
    } else {
      fprintf(stderr, "pomlab synth: at most %d configs\n", MAX_CFGS);
      return 2;
    }
  }
  if (ncfg == 0) {
    usage(stderr);
    return 2;
  }

  /* the geometry, the workspace and the synthesis; inertia etc. belong to
   * other commands */
  const char *const *const scopes[] = {pom_kin_arch_groups(), pom_kin_ws_groups(), pom_syn_groups(),
                                       NULL};
  pom_cfg *cfgs[MAX_CFGS] = {NULL};
  pom_syn_problem *pbs = calloc(MAX_CFGS, sizeof *pbs);
  pom_syn_run *runs[MAX_CFGS] = {NULL};
  char paths[MAX_CFGS][2][512];
  int code = 0;
  pom_error err;
  pom_error_clear(&err);
  if (!pbs) {
    fprintf(stderr, "pomlab synth: out of memory\n");
    return 1;
  }
  for (int c = 0; c < ncfg; ++c) {
    cfgs[c] = pom_cli_load_config(cfg_paths[c]);
    if (!cfgs[c]) {
      code = 2;
      goto out;
    }
    pom_status st = pom_syn_load(&pbs[c], cfgs[c], &err);
    if (st == POM_OK) {
      /* inertia etc. belong to other commands: accept but do not check them */
      st = pom_cli_check_unknown(cfgs[c], scopes, &err);
    }
    if (st != POM_OK) {
      pom_cli_report("synth", &err);
      code = pom_cli_exit_code(st);
      goto out;
    }
    if (no_direct && pbs[c].write == POM_SYN_WRITE_DIRECT) {
      fprintf(stderr, "pomlab synth: --no-direct contradicts synthesis.write = \"direct\" in %s\n",
              cfg_paths[c]);
      code = 2;
      goto out;
    }
    if (no_direct) pbs[c].direct = 0;
    char name[256]; /* the whole name, file-name safe (no truncation) */
    pom_pipeline_stem(name, sizeof name, pbs[c].base.name);
    snprintf(paths[c][0], sizeof paths[c][0], "%s%s.geometry.cfg", prefix, name);
    snprintf(paths[c][1], sizeof paths[c][1], "%s%s.h5", prefix, name);
    /* two configs of one name would write the same files, the second over
     * the first: refused before any work */
    for (int d = 0; d < c; ++d)
      if (strcmp(paths[d][0], paths[c][0]) == 0) {
        pom_cli_refuse_shared_output("synth", cfg_paths[d], cfg_paths[c], paths[c][0]);
        code = 2;
        goto out;
      }
  }
  /* no output may overwrite a config or a file it includes */
  pom_job_paths *pp = pom_job_paths_create("synth");
  for (int c = 0; c < ncfg; ++c)
    pom_job_paths_config(pp, cfg_paths[c], "the config");
  for (int c = 0; c < ncfg; ++c) {
    pom_job_paths_output(pp, paths[c][0], "the geometry file (--out PREFIX + name)");
    pom_job_paths_output(pp, paths[c][1], "the synthesis record (--out PREFIX + name)");
  }
  code = pom_job_paths_check(pp, stderr, NULL);
  pom_job_paths_destroy(pp);
  if (code) goto out;
  for (int c = 0; c < ncfg; ++c) {
    pom_status st = pom_syn_begin(&runs[c], &pbs[c], &err);
    if (st == POM_OK) {
      pom_progress bar;
      char label[48];
      snprintf(label, sizeof label, "design %s", pom_kin_arch_name(&pbs[c].base));
      pom_progress_init(&bar, quiet ? NULL : stderr, label, runs[c]->n_runs, 0, 0);
      int remaining = 1;
      while (st == POM_OK && remaining > 0) {
        st = pom_syn_step(runs[c], &remaining, &err);
        pom_progress_update(&bar, runs[c]->next);
      }
      pom_progress_finish(&bar, runs[c]->next);
    }
    if (st == POM_OK) st = pom_syn_finish(runs[c], &err);
    if (st == POM_OK) st = pom_syn_write_geometry(runs[c], paths[c][0], &err);
    if (st == POM_OK) st = pom_syn_write_h5(runs[c], paths[c][1], pom_cfg_text(cfgs[c]), &err);
    if (st != POM_OK) {
      pom_cli_report("synth", &err);
      code = pom_cli_exit_code(st);
      goto out;
    }
    if (!json)
      print_human(runs[c], paths[c][0], paths[c][1]);
    else
      print_fit_warnings(stderr, runs[c]);
  }
  if (json)
    print_json(runs, ncfg, paths);
  else if (ncfg > 1)
    print_side_by_side(runs, ncfg);
out:
  for (int c = 0; c < MAX_CFGS; ++c) {
    pom_syn_destroy(runs[c]);
    pom_cfg_destroy(cfgs[c]);
  }
  free(pbs);
  return code;
}
