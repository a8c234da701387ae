/* pom_explore.h - studies that drive runs to explore a design: global
 * sensitivity (Sobol indices and Morris effects, pom_sensitivity.c; of a
 * study's candidates to its uncertain parameters, pom_doe_sensitivity.c) and
 * the speed-against-accuracy sweep of the dynamics engine (pom_tradeoff.c).
 * They run maneuvers through run/pom_run.h and read the study
 * (study/pom_study.h). */
#ifndef POM_EXPLORE_H
#define POM_EXPLORE_H

#include "pom_config.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_run.h"
#include "pom_status.h"
#include "pom_study.h"

#include <stdint.h>

/* ==== sensitivity indices (pom_sensitivity.c) ================================
 * Global sensitivity of a scalar model output to its
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

/* ==== sensitivity of a study (pom_doe_sensitivity.c) ============================
 * Global sensitivity of a study's candidates to its
 * uncertain parameters: the `sensitivity` group, the design run through
 * the batch runner (threads), the indices and their results file
 * (docs/results.md, section 11). */

typedef enum { POM_DOE_SENS_SOBOL = 0, POM_DOE_SENS_MORRIS = 1 } pom_doe_sens_method;

/* The `sensitivity` group. */
typedef struct {
  pom_doe_sens_method method;
  pom_sens_sobol_opts sobol;     /* method sobol (dim = the uncertain parameters) */
  pom_sens_morris_opts morris;   /* method morris */
  int stat;                      /* the output: statistic pom_dyn_stat_id of each run */
  long per_sample;               /* maneuvers 0..per_sample-1 per design point; y = their mean */
  char output[POM_DOE_PATH_LEN]; /* results file */
} pom_doe_sens;

/* Reads the `sensitivity` group of a study file whose study (with an
 * `uncertain` group) is loaded; unknown keys in the group are errors. */
pom_status pom_doe_sens_load(pom_doe_sens *s, const pom_cfg *cfg, const pom_doe_study *study,
                             pom_error *err);

/* Per candidate: the outputs and the indices. */
typedef struct {
  long rows; /* design points */
  int dim;   /* inputs (the uncertain parameters) */
  double *u; /* [rows][dim] design in (0, 1) */
  double *x; /* [rows][dim] the values drawn (config units, or factors when relative) */
  double *y; /* [n_candidates][rows] outputs (SI) */
  int n_candidates;
  pom_sens_sobol_result *sobol;   /* [n_candidates] (method sobol) */
  pom_sens_morris_result *morris; /* [n_candidates] (method morris) */
  pom_status *status;             /* [n_candidates] of the index computation */
  char (*reason)[256];            /* [n_candidates] why, when status != OK */
  double wall;                    /* s */
  int threads;
} pom_doe_sens_result;

void pom_doe_sens_result_destroy(pom_doe_sens_result *r);

/* Progress callback: units done of total. */
typedef void (*pom_doe_sens_progress)(long done, long total, void *user);

/* How pom_doe_sens_run runs. */
typedef struct {
  int threads;                    /* worker threads; 0 = the study's */
  const char *output;             /* the results file; NULL or "" = none */
  int resume;                     /* 1: continue OUTPUT.partial of an interrupted run */
  long stop_after;                /* stop after this many new runs (0 = run them all) */
  pom_doe_sens_progress progress; /* NULL = none */
  void *user;                     /* for progress */
  volatile int *cancel;           /* polled when not NULL: set, the run stops */
} pom_doe_sens_run_opts;

void pom_doe_sens_run_opts_defaults(pom_doe_sens_run_opts *o);

/* Runs the design on every candidate of study (changed during the call:
 * its uncertain draws come from the design; restored before return),
 * computes the indices and writes the results file. The output is taken
 * before the first run, as `pomlab study` takes its own (docs/results.md
 * "Writing safely"): OUTPUT.lock held for the whole call, every run's row
 * kept in OUTPUT.partial as it finishes (its disk space reserved up front;
 * a resume continues it), OUTPUT written under a temporary name and renamed
 * when complete, then OUTPUT.partial removed. A stopped or cancelled run
 * returns POM_ERR_INTERRUPTED (its rows stay in OUTPUT.partial). *out is
 * set whenever the indices were computed, also when writing the file
 * failed afterwards (the status and err say why; the rows stay in
 * OUTPUT.partial, and a resume writes the file without running again). */
pom_status pom_doe_sens_run(pom_doe_sens_result **out, pom_doe_study *study, const pom_doe_sens *s,
                            const pom_doe_sens_run_opts *o, pom_error *err);

/* Writes the results file: to a temporary name beside path, synced and
 * renamed over path only when complete (the folder synced after). */
pom_status pom_doe_sens_write(const char *path, const pom_doe_study *study, const pom_doe_sens *s,
                              const pom_doe_sens_result *r, pom_error *err);

/* ==== speed against accuracy (pom_tradeoff.c) ==================================
 * Speed against accuracy of the dynamics engine
 * (docs/tradeoff.md): a sweep over formulation, scene options, rtol,
 * parasitic stiffness and linear solver, each setting run on a fixed set of
 * maneuvers (drawn from the study seed) and compared with a tight reference
 * (the model error plus the integration error) and with its own model at a
 * tight tolerance (the integration error alone).
 * Library code: never prints; the caller (cli/cmd_tradeoff.c) shows the
 * table and the recommendation. */

#define POM_TRADEOFF_MAX_VALUES 12
#define POM_TRADEOFF_MAX_ROWS   64

/* The `tradeoff` config group (docs/tradeoff.md, keys). */
typedef struct {
  int maneuvers;                             /* maneuvers 0..n-1 of the montecarlo seed */
  int repeats;                               /* timing repeats per maneuver (median) */
  double rtol[POM_TRADEOFF_MAX_VALUES];      /* rtol sweep at the configured stiffness */
  int n_rtol;                                /* entries of rtol */
  double stiffness[POM_TRADEOFF_MAX_VALUES]; /* k_p sweep (N/m and N m/rad) at solver.rtol */
  int n_stiffness;                           /* entries of stiffness */
  int linear_solvers;                        /* 1: also the other linear solver at solver.rtol */
  int scenes;                                /* 1: one row per reduced scene option */
  double reference_rtol;                     /* rtol of the reference and of every row's same-model
                                                reference (natural absolute tolerances, atol_scale 0) */
  int reference_rigid;        /* 1: the reference is the rigid path (joints.model = rigid) */
  int rigid;                  /* 1: rows of the rigid path (rtol sweep, quasi-static coil) */
  double reference_stiffness; /* k_p of the reference (N/m and N m/rad) */
  double accuracy;            /* relative accuracy asked for the recommendation */
  int fidelity_maneuvers;     /* the recommendation's rule (docs/tradeoff.md section 9): maneuvers
                                 of its selection set (montecarlo seed) and of its validation
                                 set; 0: no recommendation */
  double fidelity_margin;     /* the selection set must meet accuracy / margin */
  long validation_seed;       /* seed of the validation set; -1: the montecarlo seed + 1 */
  double max_wall;            /* s: a setting whose maneuver takes longer is
                                 abandoned (counted as failed) */
} pom_tradeoff_opts;

/* Defaults: 3 maneuvers, 3 repeats, rtol 1e-2..1e-8, k_p 1e3..1e9, both
 * linear solvers, scene rows on, rigid-path rows on, reference = the rigid
 * path at rtol 1e-10 (the parasitic one at k_p 1e9 if asked), accuracy
 * 1 %, 20 s per maneuver at most; the recommendation on 20 + 20 maneuvers
 * with margin 2, validation seed = montecarlo seed + 1. */
void pom_tradeoff_defaults(pom_tradeoff_opts *o);

/* Reads the `tradeoff` group over the defaults (absent = defaults). */
pom_status pom_tradeoff_load(pom_tradeoff_opts *o, const pom_cfg *cfg, pom_error *err);

/* One setting and what it measured. Errors are the worst over the maneuvers
 * (and actuators), relative to the reference; a failed maneuver makes them
 * +Inf. */
typedef struct {
  char label[96];  /* e.g. "rtol 1e-04", "scene: coil quasi-static" */
  char family[16]; /* "reference", "config", "rtol", "stiffness", "linsol", "scene", "combined" */
  pom_dyn_params params; /* the parameters it ran with */
  int n_states;          /* ODE states of its model */
  double time;           /* s per maneuver: median over repeats, mean over maneuvers */
  double steps;          /* CVODE steps per maneuver (mean) */
  double err_settle;     /* max |t_exec - t_exec,ref| / t_exec,ref */
  double err_energy;     /* max |E - E_ref| / |E_ref| (total expended energy) */
  double err_traj;       /* max_t |q_i(t) - q_i,ref(t)| / max_i |step_i| */
  double err_max;        /* largest of the three */
  /* integration error: the same three errors against the same model (every
   * setting but the solver's) integrated at reference_rtol with natural
   * absolute tolerances; NaN when that tight run failed (int_reason) */
  double int_settle, int_energy, int_traj;
  double int_max;       /* largest of the three */
  int failures;         /* maneuvers that failed (status != POM_OK) */
  char reason[256];     /* first failure reason, "" if none */
  char int_reason[256]; /* why the same-model reference failed, "" if it ran */
} pom_tradeoff_row;

typedef struct {
  int n_rows;
  pom_tradeoff_row row[POM_TRADEOFF_MAX_ROWS]; /* row 0: the reference, row 1: the config */
  double targets[16][3];                       /* the maneuvers' targets (m) */
  int n_maneuvers;
  int recommended;  /* row index of the rule's choice (fidelity), -1 if no row has its setting
                       or the rule did not run */
  int fidelity_ran; /* 1: fidelity holds the recommendation by the rule */
  pom_fidelity_result fidelity; /* the rule's choice, selection errors and validated bound */
  uint64_t select_seed, validation_seed;  /* the seeds of its two sets */
  int n_select_drawn, n_validation_drawn; /* maneuvers drawn for each set (those the mechanism
                                             reaches are used: fidelity.n_select, n_validate) */
  int n_models; /* distinct models, each integrated once at reference_rtol */
} pom_tradeoff_result;

/* Progress callback (may be NULL): called after each setting with its row. */
typedef void (*pom_tradeoff_progress)(void *user, const pom_tradeoff_row *row, int done, int total);

/* Runs the sweep on mech (built from arch) with base parameters `base` (the config's), the
 * maneuvers of mv. res is filled (caller-owned, large: allocate it). A
 * setting that fails is recorded, not fatal; only setup failures return an
 * error. */
pom_status pom_tradeoff_run(const pom_kin_arch *arch, const pom_mechanism *mech,
                            const pom_dyn_params *base, const pom_doe_maneuvers *mv,
                            const pom_tradeoff_opts *o, pom_tradeoff_result *res,
                            pom_tradeoff_progress progress, void *user, pom_error *err);

/* Index of the cheapest row (not the reference) whose err_max <= accuracy on
 * the sweep's maneuvers and with no failure; -1 when none. These rows are
 * marked "ok"; the recommendation is the rule's (fidelity), which also
 * validates on maneuvers it did not select on. */
int pom_tradeoff_recommend(const pom_tradeoff_result *res, double accuracy);

#endif
