/* pom_sensitivity.h - global sensitivity of a scalar model output to its
 * inputs: Sobol first-order and total indices (Saltelli sampling,
 * Saltelli-2010 and Jansen estimators, bootstrap confidence intervals) and
 * Morris elementary effects (mu*, mu, sigma) (docs/results.md, section 11).
 *
 * Three steps so that the model runs can go anywhere (a loop, the batch
 * runner's threads): make the design (points u in the unit cube, one row
 * per model run), evaluate y per row, compute the indices from y. Inputs
 * are u values; a caller maps them to its inputs through their
 * distributions (pom_dist_quantile), so the indices are those of inputs
 * with these distributions. pom_sens_*_run do all three with a callback. */
#ifndef POM_SENSITIVITY_H
#define POM_SENSITIVITY_H

#include "pom_status.h"

#include <stdint.h>

#define POM_SENS_MAX_DIM 20 /* inputs at most (2 x 20 = GSL's Sobol limit of 40) */

/* ---- Sobol indices ------------------------------------------------------------ */
typedef enum {
  POM_SENS_QMC = 0,   /* Sobol low-discrepancy points (GSL), first point skipped */
  POM_SENS_RANDOM = 1 /* independent uniforms from (seed, row) */
} pom_sens_sampling;

typedef struct {
  int dim;                    /* inputs, 1..POM_SENS_MAX_DIM */
  long n_base;                /* base samples N; the design has N (dim + 2) rows */
  pom_sens_sampling sampling; /* of the base matrices A and B */
  uint64_t seed;              /* random sampling and the bootstrap */
  int bootstrap;              /* bootstrap resamples (0 = no intervals) */
  double confidence;          /* level of the percentile intervals, e.g. 0.95 */
} pom_sens_sobol_opts;

/* dim = 1, n_base = 512, QMC, seed 1, 1000 resamples, 0.95. */
void pom_sens_sobol_defaults(pom_sens_sobol_opts *o);

/* Rows of the Sobol design: n_base (dim + 2). */
long pom_sens_sobol_rows(const pom_sens_sobol_opts *o);

/* Fills u[rows][dim] in (0, 1): base sample j is the block of rows
 * j (dim + 2) + {0: A_j, 1: B_j, 2 + i: A_j with input i from B_j}. */
pom_status pom_sens_sobol_design(double *u, const pom_sens_sobol_opts *o, pom_error *err);

typedef struct {
  int dim;
  long n_used;     /* base samples whose dim + 2 outputs were all finite */
  long n_failed;   /* base samples dropped for a non-finite output */
  double mean;     /* of the outputs f(A), f(B) */
  double variance; /* of the outputs f(A), f(B) (divisor 2n - 1) */
  double S1[POM_SENS_MAX_DIM], S1_low[POM_SENS_MAX_DIM], S1_high[POM_SENS_MAX_DIM];
  double ST[POM_SENS_MAX_DIM], ST_low[POM_SENS_MAX_DIM], ST_high[POM_SENS_MAX_DIM];
  double confidence; /* of the intervals (NaN bounds without bootstrap) */
} pom_sens_sobol_result;

/* Indices from the outputs y[rows] of the design: S_i = mean(f(B) (f(AB_i)
 * - f(A))) / V (Saltelli et al. 2010), ST_i = mean((f(A) - f(AB_i))^2) / (2
 * V) (Jansen 1999), V the variance of f(A) and f(B); percentile bootstrap
 * intervals over resampled base samples. POM_ERR_ARG when fewer than 2 base
 * samples are usable or the output does not vary. */
pom_status pom_sens_sobol_indices(pom_sens_sobol_result *r, const double *y,
                                  const pom_sens_sobol_opts *o, pom_error *err);

/* ---- Morris elementary effects ----------------------------------------------- */
typedef struct {
  int dim;           /* inputs */
  long trajectories; /* r; the design has r (dim + 1) rows */
  int levels;        /* p, even, >= 2: u on the grid (l + 1/2) / p */
  uint64_t seed;
} pom_sens_morris_opts;

/* dim = 1, 20 trajectories, 4 levels, seed 1. */
void pom_sens_morris_defaults(pom_sens_morris_opts *o);

long pom_sens_morris_rows(const pom_sens_morris_opts *o);

/* Fills u[rows][dim]: trajectory t is the block of rows t (dim + 1) + s,
 * each row one input away from the previous one by a jump of p/2 levels
 * (Delta u = 1/2), inputs in a random order. */
pom_status pom_sens_morris_design(double *u, const pom_sens_morris_opts *o, pom_error *err);

typedef struct {
  int dim;
  long n_effects[POM_SENS_MAX_DIM]; /* finite elementary effects per input */
  double mu_star[POM_SENS_MAX_DIM]; /* mean |EE| (per unit of u) */
  double mu[POM_SENS_MAX_DIM];      /* mean EE */
  double sigma[POM_SENS_MAX_DIM];   /* standard deviation of EE (divisor n - 1) */
} pom_sens_morris_result;

/* Elementary effects EE = (y(after) - y(before)) / (u(after) - u(before))
 * from the outputs y[rows] of the design u; effects with a non-finite y are
 * dropped (counted in n_effects). */
pom_status pom_sens_morris_effects(pom_sens_morris_result *r, const double *u, const double *y,
                                   const pom_sens_morris_opts *o, pom_error *err);

/* ---- all in one, with a model callback ---------------------------------------- */
/* y = f(u[dim]); a non-finite y is a failed run. */
typedef double (*pom_sens_fn)(const double *u, void *user);

pom_status pom_sens_sobol_run(pom_sens_sobol_result *r, pom_sens_fn f, void *user,
                              const pom_sens_sobol_opts *o, pom_error *err);
pom_status pom_sens_morris_run(pom_sens_morris_result *r, pom_sens_fn f, void *user,
                               const pom_sens_morris_opts *o, pom_error *err);

#endif
