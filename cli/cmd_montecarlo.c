/* cmd_montecarlo.c - `pomlab montecarlo CFG`: N random maneuvers of the one
 * mechanism a config describes (its optional `montecarlo` group sets the
 * protocol; docs/results.md). */
#include "pom_job.h"
#include "pom_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void montecarlo_usage(FILE *out) {
  fprintf(out,
          "usage: pomlab montecarlo CONFIG [options]\n\n"
          "Random maneuvers of one mechanism: from rest at mid-stroke to targets drawn as the\n"
          "config's `montecarlo` group says (default: the paper's 1000 maneuvers, uniform\n"
          "within +-3 mm per actuator). Prints the execution-time and energy statistics.\n\n"
          "  --n N           number of maneuvers (overrides montecarlo.maneuvers)\n"
          "  --seed S        study seed (overrides montecarlo.seed)\n"
          "  --threads N     worker threads (default: all cores)\n"
          "  --out FILE      also write an HDF5 results file, and summary.md with figures\n"
          "                  in FILE's path without .h5 (as pomlab study)\n"
          "  --tabular FILE  also write FILE (.csv, one row per maneuver) and\n"
          "                  FILE_candidates.csv (statistics); needs --out\n"
          "  --json          JSON on stdout (SI units)\n"
          "  --quiet         no progress bar\n"
          "  --help          this text\n\n"
          "Times in ms and energies in J in the tables. Exit status: 0 done (failed\n"
          "maneuvers are counted, not an error); 1 runtime failure; 2 usage or config\n"
          "error.\n");
}

int pom_cmd_montecarlo(int argc, char **argv) {
  const char *cfg_path = NULL, *out = "", *tabular = "";
  /* --n and --seed set the config's keys, checked by the config's ranges */
  const char *n_text = NULL, *seed_text = NULL;
  int threads = 0, json = 0, quiet = 0;
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k];
    int has_val = k + 1 < argc;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      montecarlo_usage(stdout);
      return 0;
    } else if (strcmp(a, "--n") == 0 && has_val) {
      n_text = argv[++k];
    } else if (strcmp(a, "--seed") == 0 && has_val) {
      seed_text = argv[++k];
    } else if (strcmp(a, "--threads") == 0 && has_val) {
      if (pom_cli_parse_threads("montecarlo", argv[++k], &threads) != 0) return 2;
    } else if (strcmp(a, "--out") == 0 && has_val) {
      out = argv[++k];
    } else if (strcmp(a, "--tabular") == 0 && has_val) {
      tabular = argv[++k];
    } else if (strcmp(a, "--json") == 0) {
      json = 1;
    } else if (strcmp(a, "--quiet") == 0) {
      quiet = 1;
    } else if (a[0] == '-' || cfg_path) {
      fprintf(stderr, "pomlab montecarlo: unexpected or incomplete argument '%s'\n\n", a);
      montecarlo_usage(stderr);
      return 2;
    } else {
      cfg_path = a;
    }
  }
  if (!cfg_path) {
    montecarlo_usage(stderr);
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
  if (n_text) st = pom_cfg_set_number(cfg, "montecarlo.maneuvers", n_text, "--n", &err);
  if (st == POM_OK && seed_text)
    st = pom_cfg_set_number(cfg, "montecarlo.seed", seed_text, "--seed", &err);
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
