/* pom_run.h - running a study and storing it: the batch runner (threads;
 * MPI when built with it), the HDF5 results file, the tabular (CSV) files and
 * what a run will cost, known before it runs (docs/results.md,
 * "Execution", "Results file", "Tabular results", "Cost, announced before
 * the work"). It reads the study (study/pom_study.h), keeps rows
 * (rows/pom_rows.h) and reduces them with the report (stats/pom_stats.h). */
#ifndef POM_RUN_H
#define POM_RUN_H

#include "pom_rows.h"
#include "pom_stats.h"
#include "pom_status.h"
#include "pom_study.h"

#include <stddef.h>

/* ---- results file (pom_doe_results.c) ---- */
/* The file an unfinished run of results path `path` is in: "PATH.partial"
 * (renamed to PATH when every maneuver is done; docs/results.md). */
void pom_doe_results_partial_path(char *buf, size_t cap, const char *path);

/* Reads rows [first, first + n) of candidate c from a results file. */
pom_status pom_doe_results_read_rows(const char *path, int c, long first, long n, pom_doe_row *rows,
                                     pom_error *err);

/* ---- runner -------------------------------------------------------------------- */
typedef struct {
  int threads;          /* worker threads; 0 = study->threads, then all cores */
  long stop_after;      /* stop once this many new units finished (0 = run to the end) */
  int resume;           /* 1: continue an existing results file (must match the study) */
  const char *output;   /* results file; NULL = study->output; "" = no file */
  int queue_capacity;   /* finished rows buffered before workers wait (default 64) */
  double poll_interval; /* step() returns at least this often (s, default 0.1) */
  int use_mpi;          /* 1: split units over MPI ranks (needs POM_WITH_MPI) */
  int rows_only;        /* 1: the results file only keeps the rows, for a caller that
                           writes its own file at `output` (pomlab sensitivity): the
                           run works in OUTPUT.partial and resumes only that one;
                           pom_doe_run_end writes no report and renames nothing (see
                           pom_doe_run_rows_done) */
} pom_doe_run_options;

void pom_doe_run_options_defaults(pom_doe_run_options *o);

typedef struct pom_doe_run pom_doe_run;

/* Starts a run: opens/creates the results file (on rank 0), works out what is
 * left to do, starts the workers (pom_doe_run_prepare, then
 * pom_doe_run_start). On failure *out is NULL. */
pom_status pom_doe_run_begin(pom_doe_run **out, const pom_doe_study *study,
                             const pom_doe_run_options *opt, pom_error *err);

/* Everything pom_doe_run_begin does before the first maneuver, without
 * starting a worker: the results file opened or created on rank 0 (none when
 * opt->output is ""), the finished units found, the work split, each
 * worker's evaluator states created. The caller owns *out (NULL on failure):
 * pom_doe_run_start sets it going, pom_doe_run_destroy frees it either way.
 * The study fuzzer (tests/fuzz) checks a setup with it. */
pom_status pom_doe_run_prepare(pom_doe_run **out, const pom_doe_study *study,
                               const pom_doe_run_options *opt, pom_error *err);

/* Starts the workers of a prepared run (once; POM_ERR_ARG the second time). */
pom_status pom_doe_run_start(pom_doe_run *run, pom_error *err);

/* Waits up to poll_interval for finished maneuvers, stores them (results file
 * flushed) and sets *finished = 1 once nothing is left to do (or the run was
 * cancelled and the workers stopped). */
pom_status pom_doe_run_step(pom_doe_run *run, int *finished, pom_error *err);

/* Asks the workers to stop after their current maneuver (safe to call from
 * the thread that drives the run; a signal handler should set a flag that the
 * driver turns into this call). */
void pom_doe_run_cancel(pom_doe_run *run);

/* Units (candidate x maneuver) finished in total, finished before this run
 * began (resume) and in the whole study. */
long pom_doe_run_done(const pom_doe_run *run);
long pom_doe_run_start_done(const pom_doe_run *run);
long pom_doe_run_total(const pom_doe_run *run);
/* 1 on the rank that writes and reports (always 1 without MPI). */
int pom_doe_run_is_root(const pom_doe_run *run);
/* Worker threads in use on this rank. */
int pom_doe_run_threads(const pom_doe_run *run);
/* MPI ranks sharing the run (1 without MPI). */
int pom_doe_run_ranks(const pom_doe_run *run);

/* Stops the workers, computes the report from every finished maneuver (on
 * the root: *report, owned by the caller; elsewhere NULL), closes the rows
 * file and writes statistics, comparisons and ranking into a copy of it,
 * which replaces the results file only when it is complete and whole
 * (docs/results.md, "Writing safely"). With rows_only: closes the rows file
 * and keeps it (and the lock on the output) for the caller. */
pom_status pom_doe_run_end(pom_doe_run *run, pom_doe_report **report, pom_error *err);

/* After pom_doe_run_end, on the root: the value that statistic `stat`
 * (pom_dyn_stat_id) of candidate c takes from unit k (NaN when the unit is
 * not done or does not count: failed, or unsettled for time metrics). */
double pom_doe_run_value(const pom_doe_run *run, int c, long k, int stat);

/* With rows_only, on the root after pom_doe_run_end, once the caller's own
 * file is in place at the output: removes OUTPUT.partial, whose rows are no
 * longer needed. The lock on the output is held until pom_doe_run_destroy. */
pom_status pom_doe_run_rows_done(pom_doe_run *run, pom_error *err);

/* Frees a run (joins workers if still running); NULL allowed. */
void pom_doe_run_destroy(pom_doe_run *run);

/* Convenience: begin, step to the end, end. */
pom_status pom_doe_run_all(const pom_doe_study *study, const pom_doe_run_options *opt,
                           pom_doe_report **report, pom_error *err);

/* ---- tabular results (pom_doe_tabular.c) ------------------------------------- */
/* Writes the study as two CSV tables (docs/results.md, "Tabular results"):
 * csv, one row per finished candidate x maneuver (candidate, factors,
 * maneuver, its drawn values, actuator_unit, every metric of the schema,
 * status, reason), and pom_doe_tabular_candidates_path(csv), one row per
 * candidate (factors, counts, every statistic). The rows are read from the
 * results file `results` a block at a time. Both files are written under a
 * temporary name and renamed only once both are complete, so a failure
 * leaves the earlier pair as it was. POM_ERR_ARG without a results file, POM_ERR_IO on a failed
 * write. */
pom_status pom_doe_tabular_write(const pom_doe_study *study, const pom_doe_report *rep,
                                 const char *results, const char *csv, pom_error *err);

/* The per-candidate table beside csv: "x.csv" -> "x_candidates.csv" (any other
 * name gets "_candidates.csv" appended). */
void pom_doe_tabular_candidates_path(char *out, size_t cap, const char *csv);

/* ---- cost (pom_doe_estimate.c) ---- */
/* A run's cost; every size in bytes. */
typedef struct {
  double runs;    /* candidate x maneuver evaluations */
  double per_run; /* bytes of memory per run (the runner's tables) */
  double memory;  /* bytes of memory at the peak: per_run x runs plus what grows with the
                     maneuvers, the design and the report */
  double file;    /* bytes of the results file (0: no file) */
} pom_doe_cost;

/* The cost of running every candidate of study on its maneuvers, with a
 * results file when with_file. */
void pom_doe_cost_study(pom_doe_cost *c, const pom_doe_study *study, int with_file);

/* The cost of a sensitivity analysis of study: rows design points of dim
 * inputs, per_sample maneuvers each, for every candidate, and its results
 * file. */
void pom_doe_cost_sensitivity(pom_doe_cost *c, const pom_doe_study *study, long rows,
                              long per_sample, int dim);

/* Bytes of memory one process of this machine can have: the physical
 * memory, or a smaller address-space limit (ulimit -v). */
double pom_doe_memory_limit(void);

/* Seconds one worker thread spends per run, measured on maneuvers 0 and 1
 * of up to three candidates (the first, the middle and the last), without a
 * results file; candidates' set-up included, so a slight overestimate. */
pom_status pom_doe_calibrate(double *seconds_per_run, const pom_doe_study *study, pom_error *err);

#endif
