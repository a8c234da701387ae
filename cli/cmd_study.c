/* cmd_study.c - `pomlab study CFG`: every candidate of a study file on the
 * same maneuvers; results file, tables, verdict, summary and figures
 * (docs/results.md). Under mpirun (built with POM_WITH_MPI) the maneuvers are
 * split over the ranks and rank 0 writes the same file one process would. */
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_pipeline.h"
#include "pom_progress.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef POM_WITH_MPI
#include <mpi.h>
#endif

static void study_usage(FILE *out) {
  fprintf(out, "usage: pomlab study CONFIG [options]\n\n"
               "Runs every candidate of the study file on the same Monte-Carlo maneuvers, writes\n"
               "the HDF5 results file, prints the execution-time and energy tables, the paired\n"
               "comparison and the ranking, and writes DIR/summary.md with PNG figures, where\n"
               "DIR is the results file's path without .h5 (e.g. results/paper/). Candidates\n"
               "that ask for synthesis or tuning (run_in_study) go through them first, with a\n"
               "progress bar per phase; their geometry, gains and records go to DIR too.\n\n"
               "  --threads N      worker threads (default: study.threads, else all cores)\n"
               "  --resume         continue an interrupted results file (same study only)\n"
               "  --out FILE       results file (default: study.output, else results/<name>.h5)\n"
               "  --stop-after N   stop after N more maneuvers (to test --resume)\n"
               "  --tabular FILE   also write FILE (.csv, one row per candidate x maneuver) and\n"
               "                   FILE_candidates.csv (one row per candidate); study.tabular;\n"
               "                   FILE ends in .csv, not in _candidates.csv\n"
               "  --json           JSON report on stdout instead of tables\n"
               "  --no-plots       skip the figures\n"
               "  --no-summary     skip summary.md\n"
               "  --quiet          no progress bar\n"
               "  --help           this text\n\n"
               "Ctrl-C stops after the running maneuvers; everything finished is kept.\n"
               "Config keys: docs/results.md. Times in ms and energies in J in the tables.\n"
               "Exit status: 0 done or stopped by --stop-after (failed maneuvers are counted\n"
               "in the tables, not an error); 130 stopped by Ctrl-C; 1 runtime failure (e.g.\n"
               "the results file cannot be written); 2 usage or config error (also an output\n"
               "that is the same file as an input or as another output).\n");
}

/* Parses a non-negative integer option value. */
static int parse_count(const char *text, long *out) {
  char *end = NULL;
  long v = strtol(text, &end, 10);
  if (!text[0] || *end || v < 0) return -1;
  *out = v;
  return 0;
}

static int study_main(int argc, char **argv, int rank, int size) {
  const char *cfg_path = NULL;
  pom_job_options o;
  pom_job_options_defaults(&o);
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k];
    long v = 0;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      if (rank == 0) study_usage(stdout);
      return 0;
    } else if (strcmp(a, "--threads") == 0 && k + 1 < argc) {
      if (pom_cli_parse_threads(rank == 0 ? "study" : NULL, argv[++k], &o.run.threads) != 0)
        return 2;
    } else if (strcmp(a, "--stop-after") == 0 && k + 1 < argc) {
      if (parse_count(argv[++k], &v) != 0 || v < 1) {
        if (rank == 0) fprintf(stderr, "pomlab study: --stop-after needs a positive integer\n");
        return 2;
      }
      o.run.stop_after = v;
    } else if (strcmp(a, "--out") == 0 && k + 1 < argc) {
      o.run.output = argv[++k];
    } else if (strcmp(a, "--tabular") == 0 && k + 1 < argc) {
      o.tabular = argv[++k];
    } else if (strcmp(a, "--resume") == 0) {
      o.run.resume = 1;
    } else if (strcmp(a, "--json") == 0) {
      o.json = 1;
    } else if (strcmp(a, "--no-plots") == 0) {
      o.plots = 0;
    } else if (strcmp(a, "--no-summary") == 0) {
      o.summary = 0;
    } else if (strcmp(a, "--quiet") == 0) {
      o.quiet = 1;
    } else if (a[0] == '-' || cfg_path) {
      if (rank == 0) {
        fprintf(stderr, "pomlab study: unexpected argument '%s'\n\n", a);
        study_usage(stderr);
      }
      return 2;
    } else {
      cfg_path = a;
    }
  }
  if (!cfg_path) {
    if (rank == 0) study_usage(stderr);
    return 2;
  }
  o.run.use_mpi = size > 1;
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load(&cfg, cfg_path, &err);
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  o.t_start = pom_progress_now();
  /* candidates whose config asks for it are synthesized and tuned first
     (synthesis/tuning.run_in_study, docs/optimize.md 10) */
  if (st == POM_OK) st = pom_doe_study_load(&study, cfg, pom_pipeline_evaluator_create, NULL, &err);
  int loaded = cfg != NULL;
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    if (rank == 0) pom_cli_report("config", &err);
    /* a study file that cannot be read is a config error, as for every command */
    return loaded ? pom_cli_exit_code(st) : 2;
  }
  /* the job: path and memory checks, pipeline, fidelity, runs, report,
     tabular files, summary and figures (job/pom_job.h) */
  char scripts[1024];
  pom_cli_scripts_dir(scripts, sizeof scripts);
  o.command = "study";
  o.cfg_path = cfg_path;
  o.pipeline = 1;
  o.rank = rank;
  o.signals = 1;
  o.scripts_dir = scripts;
  o.out = stdout;
  o.msg = stderr;
  pom_job_result res;
  st = pom_job_run(&study, &o, &res, &err);
  pom_doe_study_clear(&study);
  return pom_job_exit_code(st, &res);
}

int pom_cmd_study(int argc, char **argv) {
#ifdef POM_WITH_MPI
  int provided = 0, rank = 0, size = 1;
  if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    fprintf(stderr, "pomlab study: MPI_Init_thread failed\n");
    return 1;
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1 && provided < MPI_THREAD_FUNNELED) {
    if (rank == 0) fprintf(stderr, "pomlab study: MPI does not provide MPI_THREAD_FUNNELED\n");
    MPI_Finalize();
    return 1;
  }
  int code = study_main(argc, argv, rank, size);
  /* a runtime failure may leave other ranks waiting for this one */
  if (code == 1 && size > 1) MPI_Abort(MPI_COMM_WORLD, 1);
  MPI_Finalize();
  return code;
#else
  return study_main(argc, argv, 0, 1);
#endif
}
