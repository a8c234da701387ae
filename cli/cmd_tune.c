/* cmd_tune.c - `pomlab tune CFG [CFG ...]`: PID gains by one criterion for
 * every architecture (docs/optimize.md section 9). */
#include "cli_opts.h"
#include "pom_dyn_ctrl.h"
#include "cli_kin.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_pipeline.h"
#include "pom_progress.h"
#include "pom_opt_print.h"
#include "pom_tune.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CFGS 4

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
  const pom_opt opts[] = {
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "PREFIX",
       .help = "output path prefix (its folder must exist)",
       .text = &prefix},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "JSON on stdout (SI: gains kp V/V, ki_per_s 1/s, kd_s s; times s)",
       .flag = &json,
       .set = 1},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress on stderr (criterion evaluations done, at most the stages' "
               "evaluation limits)",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "tune",
      .usage = "CFG [CFG ...] [--out PREFIX] [--json] [--quiet]",
      .about = "Tunes the PID gains of each config by the same criterion: mean execution time\n"
               "over a fixed maneuver set, with penalties beyond the overshoot and saturation\n"
               "limits (docs/optimize.md). Writes PREFIX<name>.controller.cfg, a `controller`\n"
               "group for simulate/montecarlo/study. PREFIX defaults to results/tune_.",
      .notes = "Config keys: the `tuning` group (docs/optimize.md section 9). Exit status:\n"
               "0 ok; 1 a simulation failed or the file cannot be written; 2 usage or\n"
               "config error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = cfg_paths,
      .max_args = MAX_CFGS,
      .n_args = &ncfg};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (ncfg == 0) {
    pom_cli_opts_usage(&spec, stderr);
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
    if (!json) pom_tune_report_text(stdout, &pbs[c], &res[c], paths[c]);
  }
  if (code == 0 && json) pom_tune_report_json(stdout, pbs, res, ncfg, paths);
  free(pbs);
  free(res);
  return code;
}
