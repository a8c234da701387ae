/* cmd_montecarlo.c - `pomlab montecarlo CFG`: N random maneuvers of the one
 * mechanism a config describes (its optional `montecarlo` group sets the
 * protocol; docs/results.md). */
#include "cli_opts.h"
#include "pom_job.h"
#include "pom_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int pom_cmd_montecarlo(int argc, char **argv) {
  const char *cfg_path = NULL, *out = "", *tabular = "";
  /* --n and --seed set the config's keys, checked by the config's ranges */
  const char *n_text = NULL, *seed_text = NULL;
  int threads = 0, json = 0, quiet = 0;
  const pom_opt opts[] = {
      {.name = "--n",
       .kind = POM_OPT_NUMBER,
       .arg = "N",
       .key = "montecarlo.maneuvers",
       .help = "number of maneuvers",
       .text = &n_text},
      {.name = "--seed",
       .kind = POM_OPT_NUMBER,
       .arg = "S",
       .key = "montecarlo.seed",
       .help = "study seed",
       .text = &seed_text},
      {.name = "--threads",
       .kind = POM_OPT_THREADS,
       .arg = "N",
       .help = "worker threads (default: all cores)",
       .ival = &threads},
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "FILE",
       .help = "also write an HDF5 results file, and summary.md with figures in FILE's path "
               "without .h5 (as pomlab study)",
       .text = &out},
      {.name = "--tabular",
       .kind = POM_OPT_TEXT,
       .arg = "FILE",
       .help = "also write FILE (.csv, one row per maneuver) and FILE_candidates.csv "
               "(statistics); needs --out",
       .text = &tabular},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "JSON on stdout (SI units)",
       .flag = &json,
       .set = 1},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress bar",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "montecarlo",
      .usage = "CONFIG [options]",
      .about =
          "Random maneuvers of one mechanism: from rest at mid-stroke to targets drawn as the\n"
          "config's `montecarlo` group says (default: the paper's 1000 maneuvers, uniform\n"
          "within +-3 mm per actuator). Prints the execution-time and energy statistics.",
      .notes = "Times in ms and energies in J in the tables. Exit status: 0 done (failed\n"
               "maneuvers are counted, not an error); 1 runtime failure; 2 usage or config\n"
               "error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &cfg_path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!cfg_path) {
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  pom_cfg *cfg = pom_cli_load_config(cfg_path);
  if (!cfg) return 2;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = POM_OK;
  if (pom_cfg_has(cfg, "candidates") || pom_cfg_has(cfg, "study")) {
    fprintf(stderr, "pomlab montecarlo: %s is a study file; run it with `pomlab study`\n",
            cfg_path);
    pom_cfg_destroy(cfg);
    return 2;
  }
  const char *const *const own[] = {pom_doe_montecarlo_groups(), NULL};
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  st = pom_cli_opts_apply(&spec, cfg, &err); /* --n, --seed */
  if (st == POM_OK)
    st = pom_doe_study_single(&study, cfg, pom_doe_dyn_evaluator_create, NULL, &err);
  if (st == POM_OK) st = pom_cli_check_unknown(cfg, own, &err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_doe_study_clear(&study);
    return pom_cli_exit_code(st);
  }
  char scripts[1024];
  pom_cli_scripts_dir(scripts, sizeof scripts);
  pom_job_options o;
  pom_job_options_defaults(&o);
  o.command = "montecarlo";
  o.cfg_path = cfg_path;
  o.run.threads = threads;
  o.run.output = out;
  o.json = json;
  o.quiet = quiet;
  o.tabular = tabular;
  o.summary = out[0] != '\0';
  o.plots = out[0] != '\0';
  o.signals = 1;
  o.scripts_dir = scripts;
  o.out = stdout;
  o.msg = stderr;
  pom_job_result res;
  st = pom_job_run(&study, &o, &res, &err);
  pom_doe_study_clear(&study);
  return pom_job_exit_code(st, &res);
}
