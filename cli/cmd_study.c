/* cmd_study.c - `pomlab study CFG`: every candidate of a study file on the
 * same maneuvers; results file, tables, verdict, summary and figures
 * (docs/results.md). Under mpirun (built with POM_WITH_MPI) the maneuvers are
 * split over the ranks and rank 0 writes the same file one process would. */
#include "cli_opts.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_pipeline.h"
#include "pom_progress.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef POM_WITH_MPI
#include <mpi.h>
#endif

static int study_main(int argc, char **argv, int rank, int size) {
  const char *cfg_path = NULL;
  pom_job_options o;
  pom_job_options_defaults(&o);
  const pom_opt opts[] = {
      {.name = "--threads",
       .kind = POM_OPT_THREADS,
       .arg = "N",
       .help = "worker threads (default: study.threads, else all cores)",
       .ival = &o.run.threads},
      {.name = "--resume",
       .kind = POM_OPT_FLAG,
       .help = "continue an interrupted results file (same study only)",
       .flag = &o.run.resume,
       .set = 1},
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "FILE",
       .help = "results file (default: study.output, else results/<name>.h5)",
       .text = &o.run.output},
      {.name = "--stop-after",
       .kind = POM_OPT_INT,
       .arg = "N",
       .help = "stop after N more maneuvers (to test --resume)",
       .lval = &o.run.stop_after,
       .lo = 1,
       .hi = LONG_MAX},
      {.name = "--tabular",
       .kind = POM_OPT_TEXT,
       .arg = "FILE",
       .help = "also write FILE (.csv, one row per candidate x maneuver) and FILE_candidates.csv "
               "(one row per candidate); study.tabular; FILE ends in .csv, not in _candidates.csv",
       .text = &o.tabular},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "JSON report on stdout instead of tables",
       .flag = &o.json,
       .set = 1},
      {.name = "--no-plots",
       .kind = POM_OPT_FLAG,
       .help = "skip the figures",
       .flag = &o.plots,
       .set = 0},
      {.name = "--no-summary",
       .kind = POM_OPT_FLAG,
       .help = "skip summary.md",
       .flag = &o.summary,
       .set = 0},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress bar",
       .flag = &o.quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "study",
      .usage = "CONFIG [options]",
      .about = "Runs every candidate of the study file on the same Monte-Carlo maneuvers, writes\n"
               "the HDF5 results file, prints the execution-time and energy tables, the paired\n"
               "comparison and the ranking, and writes DIR/summary.md with PNG figures, where\n"
               "DIR is the results file's path without .h5 (e.g. results/paper/). Candidates\n"
               "that ask for synthesis or tuning (run_in_study) go through them first, with a\n"
               "progress bar per phase; their geometry, gains and records go to DIR too.",
      .notes = "Ctrl-C stops after the running maneuvers; everything finished is kept.\n"
               "Config keys: docs/results.md. Times in ms and energies in J in the tables.\n"
               "Exit status: 0 done or stopped by --stop-after (failed maneuvers are counted\n"
               "in the tables, not an error); 130 stopped by Ctrl-C; 1 runtime failure (e.g.\n"
               "the results file cannot be written); 2 usage or config error (also an output\n"
               "that is the same file as an input or as another output).",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &cfg_path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, rank != 0);
  if (prc >= 0) return prc;
  if (!cfg_path) {
    if (rank == 0) pom_cli_opts_usage(&spec, stderr);
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
