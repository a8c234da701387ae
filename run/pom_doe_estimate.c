/* pom_doe_estimate.c - what a study or a sensitivity analysis will cost,
 * known before it runs (docs/results.md, "Cost, announced before the
 * work"). The sizes follow the allocations of pom_doe_run.c (cells and the
 * unit list), pom_doe_report.c (per-maneuver scratch), pom_doe_results.c
 * (targets) and pom_doe_uncertain.c (draws). */
#define _POSIX_C_SOURCE 200809L
#include "pom_run.h"
#include "run_internal.h"
#include "pom_progress.h"

#include <math.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* Memory that does not grow with the runs: threads' solver states, HDF5's
 * caches, the program itself (bytes; a round figure, not a measurement). */
#define FIXED_BYTES (64.0 * 1024 * 1024)

/* Doubles the report keeps per maneuver: two value columns, four of
 * scratch, one of order (pom_doe_report.c), and the effects' column. */
#define REPORT_DOUBLES_PER_MANEUVER 8.0

void pom_doe_cost_study(pom_doe_cost *c, const pom_doe_study *study, int with_file) {
  double nc = (double)study->n_candidates, m = (double)study->maneuvers.count;
  double n_unc = (double)study->uncertain.n;
  memset(c, 0, sizeof *c);
  c->runs = nc * m;
  /* a cell and an entry of the unit list per run (pom_doe_run.c) */
  c->per_run = (double)sizeof(pom_doe_cell) + (double)sizeof(long);
  /* per maneuver: the targets written to the file, the draws (twice on a
   * resume: stored and drawn), the report's columns */
  double per_maneuver = 8.0 * (3.0 + 2.0 * n_unc + REPORT_DOUBLES_PER_MANEUVER);
  c->memory = FIXED_BYTES + c->per_run * c->runs + per_maneuver * m;
  if (with_file)
    c->file = (double)sizeof(pom_doe_row) * c->runs + 8.0 * (3.0 + n_unc) * m + 1024.0 * 1024.0;
}

void pom_doe_cost_sensitivity(pom_doe_cost *c, const pom_doe_study *study, long rows,
                              long per_sample, int dim) {
  double nc = (double)study->n_candidates, r = (double)rows, d = (double)dim;
  memset(c, 0, sizeof *c);
  c->runs = nc * r * (double)per_sample;
  c->per_run = (double)sizeof(pom_doe_cell) + (double)sizeof(long);
  /* the design u and the values x [rows][dim], the outputs y [nc][rows] and
   * the indices' scratch per row (pom_doe_sensitivity.c, pom_sensitivity.c) */
  c->memory = FIXED_BYTES + c->per_run * c->runs + 8.0 * (2.0 * r * d + nc * r + 2.0 * r);
  c->file = 8.0 * (2.0 * r * d + nc * r) + 1024.0 * 1024.0;
}

double pom_doe_memory_limit(void) {
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  double bytes = pages > 0 && page > 0 ? (double)pages * (double)page : INFINITY;
  struct rlimit rl;
  if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY && (double)rl.rlim_cur < bytes)
    bytes = (double)rl.rlim_cur;
  return bytes;
}

pom_status pom_doe_calibrate(double *seconds_per_run, const pom_doe_study *study, pom_error *err) {
  *seconds_per_run = NAN;
  int nc = study->n_candidates;
  if (nc < 1 || study->maneuvers.count < 1) return POM_OK;
  /* the first, the middle and the last candidate (a sweep's extremes), each
   * as a study of its own: its uncertain nominals come along */
  int picks[3] = {0, nc / 2, nc - 1}, n_picks = nc >= 3 ? 3 : nc;
  long per = study->maneuvers.count < 2 ? study->maneuvers.count : 2;
  double spent = 0.0;
  long runs = 0;
  for (int j = 0; j < n_picks; ++j) {
    int c = picks[j];
    pom_doe_study one = *study;
    one.candidates = &study->candidates[c];
    one.n_candidates = 1;
    if (study->uncertain_nominal && study->uncertain.n > 0)
      one.uncertain_nominal = study->uncertain_nominal + (size_t)c * (size_t)study->uncertain.n;
    one.maneuvers.count = per;
    pom_doe_run_options opt;
    pom_doe_run_options_defaults(&opt);
    opt.output = "";
    opt.threads = 1;
    double t0 = pom_progress_now();
    pom_doe_run *run = NULL;
    pom_status st = pom_doe_run_begin(&run, &one, &opt, err);
    int finished = 0;
    while (st == POM_OK && !finished)
      st = pom_doe_run_step(run, &finished, err);
    if (st == POM_OK) st = pom_doe_run_end(run, NULL, err);
    pom_doe_run_destroy(run);
    POM_TRY(st);
    spent += pom_progress_now() - t0;
    runs += per;
  }
  *seconds_per_run = runs > 0 ? spent / (double)runs : NAN;
  return POM_OK;
}
