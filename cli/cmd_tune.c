/* cmd_tune.c - `pomlab tune CFG [CFG ...]`: PID gains by one criterion for
 * every architecture (docs/optimize.md section 9). */
#include "pom_dyn_ctrl.h"
#include "cli_kin.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_pipeline.h"
#include "pom_progress.h"
#include "pom_tune.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CFGS 4

static void usage(FILE *out) {
  fprintf(out, "usage: pomlab tune CFG [CFG ...] [--out PREFIX] [--json] [--quiet]\n\n"
               "Tunes the PID gains of each config by the same criterion: mean execution time\n"
               "over a fixed maneuver set, with penalties beyond the overshoot and saturation\n"
               "limits (docs/optimize.md). Writes PREFIX<name>.controller.cfg, a `controller`\n"
               "group for simulate/montecarlo/study. PREFIX defaults to results/tune_.\n\n"
               "  --out PREFIX  output path prefix (its folder must exist)\n"
               "  --json        JSON on stdout (SI: gains kp V/V, ki_per_s 1/s, kd_s s;\n"
               "                times s)\n"
               "  --quiet       no progress on stderr (criterion evaluations done, at most\n"
               "                the stages' evaluation limits)\n"
               "  --help        this text\n\n"
               "Config keys: the `tuning` group (docs/optimize.md section 9). Exit status:\n"
               "0 ok; 1 a simulation failed or the file cannot be written; 2 usage or\n"
               "config error.\n");
}

static const char *jn(char *buf, double v) {
  if (isfinite(v))
    snprintf(buf, 32, "%.10g", v);
  else
    snprintf(buf, 32, "null");
  return buf;
}

static void print_eval(const char *what, const pom_dyn_controller *c, const pom_tune_eval *e) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(c);
  printf("  %-8s", what);
  for (int k = 0; k < t->n_gains; ++k)
    printf(" %s %-10.5g %s", t->gains[k].key, pom_dyn_ctrl_gain(c, k), t->gains[k].unit);
  printf(" | criterion %8.3f ms  mean exec %7.3f ms  max exec %7.3f ms  overshoot %6.2f %%  "
         "saturation %6.3f ms  unsettled %d  energy %.4g J\n",
         e->criterion * 1e3, e->mean_execution * 1e3, e->max_execution * 1e3,
         e->max_overshoot * 100.0, e->max_saturation * 1e3, e->unsettled, e->mean_energy);
}

/* The progress bar (or log lines) on stderr, in criterion evaluations. */
static void on_progress(void *user, const char *phase, long done, long total) {
  (void)phase; /* "tune" */
  pom_progress *bar = user;
  bar->total = total;
  pom_progress_update(bar, done);
}

int pom_cmd_tune(int argc, char **argv) {
  const char *cfg_paths[MAX_CFGS];
  int ncfg = 0, json = 0, quiet = 0;
  const char *prefix = "results/tune_";
  for (int a = 1; a < argc; ++a) {
    if (strcmp(argv[a], "--help") == 0 || strcmp(argv[a], "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(argv[a], "--quiet") == 0) {
      quiet = 1;
    } else if (strcmp(argv[a], "--json") == 0) {
      json = 1;
    } else if (strcmp(argv[a], "--out") == 0 && a + 1 < argc) {
      prefix = argv[++a];
    } else if (argv[a][0] == '-') {
      fprintf(stderr, "pomlab tune: unknown option '%s'\n", argv[a]);
      usage(stderr);
      return 2;
    } else if (ncfg < MAX_CFGS) {
      cfg_paths[ncfg++] = argv[a];
    } else {
      fprintf(stderr, "pomlab tune: at most %d configs\n", MAX_CFGS);
      return 2;
    }
  }
  if (ncfg == 0) {
    usage(stderr);
    return 2;
  }
  /* the model's groups and tuning's */
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_dyn_param_groups(),
                                       pom_tune_groups(), NULL};
  pom_tune_problem *pbs = calloc(MAX_CFGS, sizeof *pbs);
  pom_tune_result *res = calloc(MAX_CFGS, sizeof *res);
  char paths[MAX_CFGS][512];
  int code = 0;
  pom_error err;
  pom_error_clear(&err);
  if (!pbs || !res) {
    fprintf(stderr, "pomlab tune: out of memory\n");
    free(pbs);
    free(res);
    return 1;
  }
  for (int c = 0; c < ncfg && code == 0; ++c) {
    pom_cfg *cfg = pom_cli_load_config(cfg_paths[c]);
    if (!cfg) {
      code = 2;
      break;
    }
    pom_status st = pom_tune_load(&pbs[c], cfg, &err);
    if (st == POM_OK) st = pom_cli_check_unknown(cfg, scopes, &err);
    pom_cfg_destroy(cfg);
    if (st != POM_OK) {
      pom_cli_report("tune", &err);
      code = pom_cli_exit_code(st);
      break;
    }
    char name[256]; /* the whole name, file-name safe (no truncation) */
    pom_pipeline_stem(name, sizeof name, pbs[c].arch.name);
    snprintf(paths[c], sizeof paths[c], "%s%s.controller.cfg", prefix, name);
    /* two configs of one name would write the same file, the second over
     * the first: refused before any work */
    for (int d = 0; d < c && code == 0; ++d)
      if (strcmp(paths[d], paths[c]) == 0) {
        pom_cli_refuse_shared_output("tune", cfg_paths[d], cfg_paths[c], paths[c]);
        code = 2;
      }
  }
  /* no gains file may overwrite a config or a file it includes */
  if (code == 0) {
    pom_job_paths *pp = pom_job_paths_create("tune");
    for (int c = 0; c < ncfg; ++c)
      pom_job_paths_config(pp, cfg_paths[c], "the config");
    for (int c = 0; c < ncfg; ++c)
      pom_job_paths_output(pp, paths[c], "the gains file (--out PREFIX + name)");
    code = pom_job_paths_check(pp, stderr, NULL);
    pom_job_paths_destroy(pp);
  }
  for (int c = 0; c < ncfg && code == 0; ++c) {
    pom_progress bar;
    char label[64];
    snprintf(label, sizeof label, "tune %s", cfg_paths[c]);
    pom_progress_init(&bar, quiet ? NULL : stderr, label, 1, 0, 0);
    pbs[c].progress = on_progress;
    pbs[c].progress_user = &bar;
    pom_status st = pom_tune_run(&pbs[c], &res[c], &err);
    pom_progress_finish(&bar, bar.total);
    if (st == POM_OK) st = pom_tune_write_controller(&pbs[c], &res[c], paths[c], &err);
    if (st != POM_OK) {
      pom_cli_report("tune", &err);
      code = pom_cli_exit_code(st);
      break;
    }
    if (!json) {
      printf("== %s (%s): %d maneuvers, overshoot limit %.3g %%, saturation limit %.4g ms\n",
             pbs[c].arch.name, pom_kin_arch_name(&pbs[c].arch), pbs[c].n_maneuvers,
             pbs[c].overshoot_max * 100.0, pbs[c].saturation_time_max * 1e3);
      print_eval("config", &res[c].initial, &res[c].initial_eval);
      print_eval("tuned", &res[c].best, &res[c].best_eval);
      printf("  %ld criterion evaluations (%ld global %s, %ld local %s), %ld simulations, "
             "%.2f s\n  wrote %s\n\n",
             res[c].opt.evals_global + res[c].opt.evals_local, res[c].opt.evals_global,
             pom_opt_result_name(res[c].opt.result_global), res[c].opt.evals_local,
             pom_opt_result_name(res[c].opt.result_local), res[c].simulations, res[c].opt.wall_time,
             paths[c]);
    }
  }
  if (code == 0 && json) {
    char b[8][32], g[32];
    printf("{\"tune\": [");
    for (int c = 0; c < ncfg; ++c) {
      const pom_tune_eval *e = &res[c].best_eval;
      /* name (from the config) and file escaped: a quote made invalid JSON */
      printf("%s{\"name\": ", c ? ", " : "");
      pom_json_string(stdout, pbs[c].arch.name);
      /* the gains by their config keys (the PID: kp, ki_per_s, kd_s) */
      const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(&res[c].best);
      printf(", \"architecture\": \"%s\", \"controller\": ", pom_kin_arch_name(&pbs[c].arch));
      pom_json_string(stdout, t->name);
      for (int k = 0; k < t->n_gains; ++k) {
        printf(", ");
        pom_json_string(stdout, t->gains[k].key);
        printf(": %s", jn(g, pom_dyn_ctrl_gain(&res[c].best, k)));
      }
      printf(", \"criterion_s\": %s, \"mean_execution_s\": %s, \"max_overshoot\": %s, "
             "\"max_saturation_s\": %s, \"unsettled\": %d, \"initial_criterion_s\": %s, "
             "\"evaluations\": %ld, \"simulations\": %ld, \"file\": ",
             jn(b[3], e->criterion), jn(b[4], e->mean_execution), jn(b[5], e->max_overshoot),
             jn(b[6], e->max_saturation), e->unsettled, jn(b[7], res[c].initial_eval.criterion),
             res[c].opt.evals_global + res[c].opt.evals_local, res[c].simulations);
      pom_json_string(stdout, paths[c]);
      printf("}");
    }
    printf("]}\n");
  }
  free(pbs);
  free(res);
  return code;
}
