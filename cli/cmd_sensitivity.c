/* cmd_sensitivity.c - `pomlab sensitivity CFG`: Sobol indices or Morris
 * effects of every candidate of a study file over its uncertain parameters;
 * table or JSON, HDF5 file and bar plot (docs/results.md, section 11). */
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_doe_sensitivity.h"
#include "pom_pipeline.h"
#include "pom_progress.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void usage(FILE *out) {
  fprintf(out, "usage: pomlab sensitivity CONFIG [options]\n\n"
               "Global sensitivity of every candidate of a study file to the parameters of its\n"
               "`uncertain` group: Sobol first-order and total indices with bootstrap intervals\n"
               "(sensitivity.method = \"sobol\", Saltelli design, N (d + 2) runs) or Morris\n"
               "elementary effects (\"morris\", r (d + 1) runs), for one metric of each run\n"
               "(sensitivity.metric, default execution_time). Writes an HDF5 file\n"
               "(sensitivity.output, default results/<name>-sensitivity.h5) and a bar plot\n"
               "beside it (.png).\n\n"
               "  --candidate C only this candidate of the study (its name as printed, or its\n"
               "                position 1..n): e.g. the winner of a sweep\n"
               "  --threads N   worker threads (default: study.threads, else all cores)\n"
               "  --out FILE    results file (replaced only once complete; taken before the\n"
               "                first run: FILE.lock, and FILE.partial keeps every run)\n"
               "  --resume      continue FILE.partial of an interrupted run (or one whose\n"
               "                file could not be written: then nothing runs again)\n"
               "  --stop-after N stop after N more runs (to test --resume)\n"
               "  --json        JSON on stdout instead of tables\n"
               "  --no-plots    skip the figure\n"
               "  --quiet       no progress bar\n"
               "  --help        this text\n\n"
               "Config keys: docs/results.md sections 10 and 11.\n"
               "Exit status: 0 done; 1 runtime failure (e.g. the output cannot be written: the\n"
               "indices are printed all the same; or too few runs succeeded for the indices);\n"
               "2 usage or config error. Stopped by --stop-after: 0 (continue with --resume).\n");
}

/* A positive count for --stop-after; -1 when text is not one. */
static long parse_positive(const char *text) {
  char *end = NULL;
  errno = 0;
  long v = strtol(text, &end, 10);
  return text[0] && !*end && errno == 0 && v >= 1 ? v : -1;
}

int pom_cmd_sensitivity(int argc, char **argv) {
  const char *cfg_path = NULL, *out_path = NULL, *only = NULL;
  int json = 0, plots = 1, quiet = 0;
  int threads = 0, resume = 0;
  long stop_after = 0;
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(a, "--threads") == 0 && k + 1 < argc) {
      if (pom_cli_parse_threads("sensitivity", argv[++k], &threads) != 0) return 2;
    } else if (strcmp(a, "--out") == 0 && k + 1 < argc) {
      out_path = argv[++k];
    } else if (strcmp(a, "--resume") == 0) {
      resume = 1;
    } else if (strcmp(a, "--stop-after") == 0 && k + 1 < argc) {
      stop_after = parse_positive(argv[++k]);
      if (stop_after < 1) {
        fprintf(stderr, "pomlab sensitivity: --stop-after needs a positive integer, not '%s'\n",
                argv[k]);
        return 2;
      }
    } else if (strcmp(a, "--candidate") == 0 && k + 1 < argc) {
      only = argv[++k];
    } else if (strcmp(a, "--json") == 0) {
      json = 1;
    } else if (strcmp(a, "--no-plots") == 0) {
      plots = 0;
    } else if (strcmp(a, "--quiet") == 0) {
      quiet = 1;
    } else if (a[0] == '-' || cfg_path) {
      fprintf(stderr, "pomlab sensitivity: unexpected argument '%s'\n\n", a);
      usage(stderr);
      return 2;
    } else {
      cfg_path = a;
    }
  }
  if (!cfg_path) {
    usage(stderr);
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
