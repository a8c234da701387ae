/* pom_nlopt.h - bound-constrained maximization with NLopt: a seeded global
 * stage, then a local polish from the best point found (docs/optimize.md,
 * section 4).
 *
 * The objective reports failure through its status; the driver then stops
 * NLopt with nlopt_force_stop and returns that status: a failed evaluation is
 * never turned into a fake objective value. */
#ifndef POM_NLOPT_H
#define POM_NLOPT_H

#include "pom_status.h"

#define POM_OPT_MAX_DIM    16 /* largest number of variables */
#define POM_OPT_MAX_STARTS 16 /* most starts of the local stage */

/* Objective: writes f(x) to *f. Non-OK status (with err filled) aborts the
 * optimization; a non-finite *f with POM_OK is reported as POM_ERR_NONFINITE. */
typedef pom_status (*pom_opt_objective)(void *ctx, const double x[], double *f, pom_error *err);

typedef enum {
  POM_OPT_GLOBAL_NONE = 0,     /* skip the global stage */
  POM_OPT_GLOBAL_CRS2 = 1,     /* controlled random search with local mutation (seeded) */
  POM_OPT_GLOBAL_DIRECT_L = 2, /* locally biased DIRECT (deterministic) */
  POM_OPT_GLOBAL_ISRES = 3,    /* improved stochastic ranking evolution strategy (seeded) */
  POM_OPT_GLOBAL_ESCH = 4      /* evolutionary (seeded) */
} pom_opt_global;

typedef enum {
  POM_OPT_LOCAL_NONE = 0,
  POM_OPT_LOCAL_BOBYQA = 1,
  POM_OPT_LOCAL_NELDERMEAD = 2,
  POM_OPT_LOCAL_SBPLX = 3,
  POM_OPT_LOCAL_COBYLA = 4
} pom_opt_local;

/* Options; pom_opt_defaults() fills them. */
typedef struct {
  pom_opt_global global;  /* default CRS2 */
  long global_max_evals;  /* default 2000 */
  double global_ftol_rel; /* relative f tolerance of the global stage, 0 = off (default 1e-8) */
  pom_opt_local local;    /* default BOBYQA */
  long local_max_evals;   /* default 500 */
  double local_xtol_rel;  /* default 1e-8 */
  double local_ftol_abs;  /* default 1e-12 */
  double max_time;        /* s per stage, 0 = unlimited (default 0) */
  unsigned long
      seed;       /* seed of NLopt's generator for the stochastic global stages (default 2385) */
  int population; /* 0 = NLopt's default */
  /* Multi-start local stage (docs/optimize.md, section 4): the local stage
   * runs from the best `local_starts` global-stage points that lie at least
   * `local_start_separation` of the box apart (in some variable, each
   * variable measured as a fraction of its box width) and the best point of
   * all is kept. 1 (the default) runs it once from the global stage's best
   * point; without a global stage there is one start, x0. */
  int local_starts;              /* default 1 */
  double local_start_separation; /* fraction of the box, (0, 1] (default 0.1) */
} pom_opt_options;

/* Outcome. */
typedef struct {
  int n;                     /* variables */
  double x[POM_OPT_MAX_DIM]; /* best point found */
  double f;                  /* objective there */
  long evals_global;         /* objective calls of each stage */
  long evals_local;          /* (every local run together) */
  int local_runs;            /* local runs made (1 unless local_starts > 1; 0 = none) */
  int local_best_run;        /* the run that found the best point (0-based), -1 when the
                                global stage's best point stayed best or no local run */
  int result_global;         /* nlopt_result of each stage (0 = stage not run) */
  int result_local;          /* (of local run local_best_run, else of the first) */
  double wall_time;          /* s, both stages */
} pom_opt_result;

void pom_opt_defaults(pom_opt_options *opts);

/* Name of an nlopt_result code ("NLOPT_XTOL_REACHED"). */
const char *pom_opt_result_name(int nlopt_result);

/* Maximizes f over the box lo[n] <= x <= hi[n] (n <= POM_OPT_MAX_DIM) from
 * x0[n] (NULL = box centre). On success res holds the best point. An NLopt
 * failure is POM_ERR_NLOPT with NLopt's message; an objective failure
 * returns the objective's status (res then holds the best point so far). */
pom_status pom_opt_maximize(int n, const double lo[], const double hi[], const double x0[],
                            pom_opt_objective f, void *ctx, const pom_opt_options *opts,
                            pom_opt_result *res, pom_error *err);

/* Progress of a long optimization (STYLE.md 15; the caller draws, the
 * library never prints): `phase` names the work, done of total units
 * finished (total is an upper bound where an optimizer may stop early).
 * Called from the thread that runs the optimization. */
typedef void (*pom_opt_progress_fn)(void *user, const char *phase, long done, long total);

#endif
