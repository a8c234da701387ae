/* pom_doe_estimate.h - what a study or a sensitivity analysis will cost,
 * known before it runs: the number of runs, the memory of the runner's
 * tables, the size of the results file, and the time per run measured on a
 * few runs (docs/results.md, "Cost, announced before the work"). */
#ifndef POM_DOE_ESTIMATE_H
#define POM_DOE_ESTIMATE_H

#include "pom_doe.h"

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
