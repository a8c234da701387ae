/* cmd_sensitivity.c - `pomlab sensitivity CFG`: Sobol indices or Morris
 * effects of every candidate of a study file over its uncertain parameters;
 * table or JSON, HDF5 file and bar plot (docs/results.md, section 11). */
#include "cli_opts.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_explore.h"
#include "pom_pipeline.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int pom_cmd_sensitivity(int argc, char **argv) {
  const char *cfg_path = NULL, *out_path = NULL, *only = NULL;
  int json = 0, plots = 1, quiet = 0;
  int threads = 0, resume = 0;
  long stop_after = 0;
  const pom_opt opts[] = {
      {.name = "--candidate",
       .kind = POM_OPT_TEXT,
       .arg = "C",
       .help = "only this candidate of the study (its name as printed, or its position 1..n): "
               "e.g. the winner of a sweep",
       .text = &only},
      {.name = "--threads",
       .kind = POM_OPT_THREADS,
       .arg = "N",
       .help = "worker threads (default: study.threads, else all cores)",
       .ival = &threads},
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "FILE",
       .help = "results file (replaced only once complete; taken before the first run: "
               "FILE.lock, and FILE.partial keeps every run)",
       .text = &out_path},
      {.name = "--resume",
       .kind = POM_OPT_FLAG,
       .help = "continue FILE.partial of an interrupted run (or one whose file could not be "
               "written: then nothing runs again)",
       .flag = &resume,
       .set = 1},
      {.name = "--stop-after",
       .kind = POM_OPT_INT,
       .arg = "N",
       .help = "stop after N more runs (to test --resume)",
       .lval = &stop_after,
       .lo = 1,
       .hi = LONG_MAX},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "JSON on stdout instead of tables",
       .flag = &json,
       .set = 1},
      {.name = "--no-plots",
       .kind = POM_OPT_FLAG,
       .help = "skip the figure",
       .flag = &plots,
       .set = 0},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress bar",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "sensitivity",
      .usage = "CONFIG [options]",
      .about = "Global sensitivity of every candidate of a study file to the parameters of its\n"
               "`uncertain` group: Sobol first-order and total indices with bootstrap intervals\n"
               "(sensitivity.method = \"sobol\", Saltelli design, N (d + 2) runs) or Morris\n"
               "elementary effects (\"morris\", r (d + 1) runs), for one metric of each run\n"
               "(sensitivity.metric, default execution_time). Writes an HDF5 file\n"
               "(sensitivity.output, default results/<name>-sensitivity.h5) and a bar plot\n"
               "beside it (.png).",
      .notes = "Config keys: docs/results.md sections 10 and 11.\n"
               "Exit status: 0 done; 1 runtime failure (e.g. the output cannot be written: the\n"
               "indices are printed all the same; or too few runs succeeded for the indices);\n"
               "2 usage or config error. Stopped by --stop-after: 0 (continue with --resume).",
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
  pom_error err;
  pom_error_clear(&err);
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  pom_doe_sens sens;
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load(&cfg, cfg_path, &err);
  if (st == POM_OK) st = pom_doe_study_load(&study, cfg, pom_pipeline_evaluator_create, NULL, &err);
  if (st == POM_OK && only && pom_doe_study_select(&study, only, &err) != POM_OK) {
    pom_cli_report("sensitivity --candidate", &err);
    pom_cfg_destroy(cfg);
    pom_doe_study_clear(&study);
    return 2;
  }
  if (st == POM_OK) st = pom_doe_sens_load(&sens, cfg, &study, &err);
  int loaded = cfg != NULL;
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_doe_study_clear(&study);
    return loaded ? pom_cli_exit_code(st) : 2;
  }
  /* the job: fidelity, path and memory checks, runs, indices, figure
     (job/pom_job.h) */
  char scripts[1024];
  pom_cli_scripts_dir(scripts, sizeof scripts);
  pom_job_sens_options o;
  memset(&o, 0, sizeof o);
  o.cfg_path = cfg_path;
  o.output = out_path;
  o.json = json;
  o.plots = plots;
  o.quiet = quiet;
  o.threads = threads;
  o.resume = resume;
  o.stop_after = stop_after;
  o.scripts_dir = scripts;
  o.out = stdout;
  o.msg = stderr;
  int code = pom_job_sensitivity(&study, &sens, &o);
  pom_doe_study_clear(&study);
  return code;
}
