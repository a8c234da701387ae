/* pom_codesign.h - co-design of geometry, actuator size and gains on the
 * closed-loop Monte-Carlo metrics (docs/optimize.md section 11, issue 29).
 *
 * Per candidate architecture the variables are config keys (geometry, gains)
 * and one actuator size s (the family law of section 11.2 sets the force or
 * torque constant, resistance, inductance, moving mass and current limit
 * from s). Constraints, the same for every candidate: the required regular
 * dexterous workspace (dexterity floor, strokes and joint limits on the
 * grid of the required cube), the current limit, an envelope; the voltage
 * limit is the drive's saturation. Objectives: a smooth 95th percentile of
 * the pointing settling time and the mean energy over a Monte-Carlo set
 * (with the `uncertain` group's draws). Gradient-based NLopt (SLSQP or MMA)
 * from several starts, COBYLA where the gradient fails; a time-energy front
 * by epsilon-constraint; every optimum re-evaluated on a fresh maneuver set
 * and on the parasitic model. Library code: never prints. */
#ifndef POM_CODESIGN_H
#define POM_CODESIGN_H

#include "pom_config.h"
#include "pom_nlopt.h"
#include "pom_status.h"
#include "pom_study.h"

#include <stdio.h>

#define POM_CDS_MAX_CANDIDATES 16
#define POM_CDS_MAX_VARS       10
#define POM_CDS_MAX_FRONT      8
/* an epsilon point no more than this fraction faster than its start is stuck
 * and starts again from the time optimum (docs/optimize.md 11.5) */
#define POM_CDS_STUCK_TOL      1e-3
#define POM_CDS_MAX_STARTS     8
#define POM_CDS_MAX_HIST       512 /* improvements kept per optimization */
#define POM_CDS_KEY_LEN        96
#define POM_CDS_MAX_SIZED_KEYS 6

/* Variable kinds: a numeric config key, or the actuator size s. */
typedef enum { POM_CDS_VAR_KEY = 0, POM_CDS_VAR_SIZE = 1 } pom_cds_var_kind;

typedef struct {
  pom_cds_var_kind kind;
  char key[POM_CDS_KEY_LEN]; /* dotted config key (config units); "size" for the size */
  double lo, hi;             /* bounds (config units; the size is dimensionless) */
  int log;                   /* 1: searched in log10 */
  double x0;                 /* the candidate config's value (size: 1) */
} pom_cds_var;

/* One key the size law scales: value = nominal x s^exponent. */
typedef struct {
  char key[POM_CDS_KEY_LEN];
  double exponent;
  double nominal; /* the candidate config's value */
} pom_cds_sized_key;

typedef struct {
  char name[POM_DOE_NAME_LEN];
  char config[POM_DOE_PATH_LEN]; /* path of the candidate's config (resolved) */
  int n_vars;
  pom_cds_var var[POM_CDS_MAX_VARS];
  int n_sized; /* keys scaled by the size law (section 11.2) */
  pom_cds_sized_key sized[POM_CDS_MAX_SIZED_KEYS];
  int rotary;            /* 1: rotary actuators (torque constant ~ s^2) */
  double current_limit0; /* A at size 1 (codesign.requirements.current_limit_A) */
  double horizon;        /* s: the config's maneuver horizon; a maneuver of a design the model
                          * refuses counts there, as an unsettled one (section 11.1) */
  double voltage_limit0; /* V: the config's drive saturation and whether its coils have their
                          * inductance: with the size law they give a failed maneuver's worst
                          * energy and peak current (section 11.1, "A failed maneuver") */
  int coil_inductance;
  double nominal_unc[POM_UNC_MAX]; /* the config's value of each uncertain key (NaN absent) */
} pom_cds_candidate;

/* Where the per-maneuver figures and their derivatives come from. */
typedef enum {
  POM_CDS_GRAD_CENTRAL = 0, /* central differences of whole simulations */
  POM_CDS_GRAD_SENS = 1     /* CVODES forward sensitivities (study/pom_grad.h; section 11.5) */
} pom_cds_grad_source;

typedef enum { POM_CDS_ALG_SLSQP = 0, POM_CDS_ALG_MMA = 1, POM_CDS_ALG_COBYLA = 2 } pom_cds_alg;

typedef struct {
  char name[POM_DOE_NAME_LEN];
  char source[POM_DOE_PATH_LEN];
  char output[POM_DOE_PATH_LEN];
  char *config_text;           /* the codesign file's text, owned */
  pom_doe_maneuvers maneuvers; /* montecarlo group */
  pom_unc uncertain;           /* uncertain group (n = 0: none) */
  /* requirements, the same for every candidate */
  double ws_half_width; /* rad: required regular dexterous workspace (Euler cube half-width) */
  int ws_grid;          /* poses per Euler angle of the constraint grid (odd) */
  double dexterity_min; /* floor on 1/kappa over that grid */
  double envelope;      /* m: largest distance of a joint from O at home */
  double time_max;      /* s: bound on the smooth p95 at every front point (a settled design) */
  double quantile;      /* 0.95 */
  double bandwidth;     /* s: kernel width of the smooth quantile */
  /* optimizer */
  pom_cds_alg alg;
  pom_cds_alg fallback; /* derivative-free (COBYLA) */
  int max_evals;        /* per optimization */
  double xtol_rel;
  double fd_step;       /* central-difference step in the unit box */
  int starts;           /* multi-start count for the time optimum */
  int front_points;     /* epsilon-constraint points (including both ends), >= 2 */
  uint64_t reeval_seed; /* fresh maneuver set */
  long reeval_count;
  int threads;
  pom_cds_grad_source grad;
  int n_candidates;
  pom_cds_candidate cand[POM_CDS_MAX_CANDIDATES];
} pom_cds_problem;

/* The top-level names of a codesign file, NULL-terminated. */
const char *const *pom_cds_groups(void);

/* Loads a codesign file (docs/optimize.md 11.4); every error names file,
 * line, key and value. Each candidate's config is checked by building it
 * at its nominal design and at both ends of every variable. */
pom_status pom_cds_load(pom_cds_problem *pb, const pom_cfg *cfg, pom_error *err);
void pom_cds_clear(pom_cds_problem *pb);

/* Figures of a design on a maneuver set. */
typedef struct {
  /* a failed maneuver (a refused design's: every one) counts at the drive's
   * worst case, section 11.1: time at the horizon, energy n V^2 T / R, peak
   * current sqrt of that over 2 L */
  double p95;       /* smooth quantile of the pointing time (s); unsettled at the horizon */
  double p95_plain; /* the empirical quantile (order statistic, s) */
  double energy;    /* mean expended energy over the n maneuvers (J) */
  double i_peak;    /* largest coil current (A) */
  double i_limit;   /* the size law's current limit (A) */
  double kin;       /* kinematic margin: <= 0 holds (workspace grid: dexterity, strokes, limits) */
  double envelope;  /* largest joint distance from O at home (m) */
  int failed;       /* maneuvers that failed (unreachable, solver, stroke) */
  int unsettled;    /* maneuvers that did not settle */
  int n;            /* maneuvers */
  long simulations; /* maneuvers simulated for this evaluation */
} pom_cds_figures;

/* Evaluates design x (config units, candidate c) on maneuvers 0..n-1 of
 * seed, rigid (parasitic = 0) or parasitic joints. */
pom_status pom_cds_evaluate(const pom_cds_problem *pb, int c, const double *x, uint64_t seed,
                            long n, int parasitic, pom_cds_figures *out, pom_error *err);

/* The smooth quantile of section 11.3: q with (1/n) sum Phi((q - t_i)/h) = p,
 * and dq/dt_i in w (may be NULL). */
double pom_cds_smooth_quantile(const double *t, int n, double p, double h, double *w);

/* The size law (section 11.2): value of a key of exponent e at size s. */
double pom_cds_size_law(double nominal, double exponent, double s);

/* One optimum of the front. */
typedef struct {
  int done;
  double eps;                      /* energy bound (J), NaN for the unconstrained ends */
  int objective;                   /* 0 time, 1 energy */
  double x[POM_CDS_MAX_VARS];      /* config units */
  pom_cds_figures opt;             /* the optimizer's figures (optimization set) */
  pom_cds_figures fresh;           /* re-evaluated: fresh set, rigid */
  pom_cds_figures fresh_parasitic; /* fresh set, parasitic joints */
  double rdw_deg;                  /* pom_kin_workspace at the optimum (pom_cds_rdw_below) */
  int feasible;                    /* constraints hold at the optimizer's figures */
  int fallback_used;               /* COBYLA ran */
  long simulations;                /* spent by this optimization */
  long evaluations;
  long sens_runs;      /* gradient = "sensitivity": maneuvers run with sensitivities */
  int sens_params;     /* sensitivity parameters of each such run (the free variables) */
  long sens_fallbacks; /* evaluations whose gradient fell back to differences */
  char sens_why[160];  /* the last fallback's reason ("" when none) */
  long peak_rows;      /* per-maneuver current rows (one per maneuver and gradient, section
                          11.5) from that maneuver's peak current derivative */
  long peak_fallbacks; /* such rows by differences of that maneuver alone (2n runs): its peak
                          derivative undefined (a kink, an edge, a tie) near active */
  long peak_held;      /* such rows held at the size law's limit alone: undefined, and the
                          maneuver's constraint more than 20 % from active */
  char peak_why[160];  /* the last current-row fallback's reason */
  long fallback_sims;  /* simulations spent on differences (both kinds of fallback) */
  int nlopt_result;
  int restarted;   /* an epsilon point stuck on its start ran again from the time optimum
                      (section 11.5): 1 the first run kept, 2 the second; 0 not */
  double cpu;      /* process CPU time of this optimization (s) */
  double cpu_sens; /* of which inside the sensitivity runs (s) */
  /* the search's record, one entry per improvement of the best feasible
   * objective: after hist_sims[i] simulations (hist_sens[i] of them with
   * sensitivities) and hist_cpu[i] s of process CPU it was hist_best[i] (s
   * or J); hist_full: an improvement came after the record was full (the
   * record then ends early). Not kept by the journal. */
  int n_hist, hist_full;
  long hist_sims[POM_CDS_MAX_HIST];
  long hist_sens[POM_CDS_MAX_HIST];
  double hist_cpu[POM_CDS_MAX_HIST];
  double hist_best[POM_CDS_MAX_HIST];
} pom_cds_point;

typedef struct {
  pom_cds_figures nominal;       /* the config's design, optimization set */
  pom_cds_figures nominal_fresh; /* and fresh set */
  int n_points;
  pom_cds_point point[POM_CDS_MAX_FRONT]; /* [0] time optimum, [n-1] energy optimum */
  double hypervolume;                     /* of the re-evaluated front (s J), common reference */
  long simulations;
} pom_cds_cand_result;

typedef struct {
  pom_cds_cand_result cand[POM_CDS_MAX_CANDIDATES];
  double ref_time, ref_energy; /* hypervolume reference point */
  long simulations;            /* in the optimizations */
  long other_simulations;      /* the config designs' figures and the re-evaluations */
  double wall;
  int resumed_tasks; /* tasks read from the journal */
} pom_cds_result;

/* Progress: phase (candidate and task), done of total evaluations. */
typedef void (*pom_cds_progress_fn)(void *user, const char *phase, long done, long total);

/* Runs the co-design of every candidate. journal (may be NULL) is the path of
 * the resume journal: finished tasks are appended, synced, and a resumed run
 * (resume = 1) skips those it finds (the journal must belong to this
 * problem). */
pom_status pom_cds_run(const pom_cds_problem *pb, const char *journal, int resume,
                       pom_cds_progress_fn progress, void *user, pom_cds_result *res,
                       pom_error *err);

/* One optimization from x0 (NULL: the config's design) on the optimization
 * set: objective 0 time, 1 energy; eps = energy bound (NaN: none); free[v]
 * = 0 keeps variable v at x0 (NULL: all free); alg as given. */
pom_status pom_cds_optimize(const pom_cds_problem *pb, int c, const double *x0, int objective,
                            double eps, const int *free_vars, pom_cds_alg alg, pom_cds_point *pt,
                            pom_error *err);

/* The grid-slice check (section 11.6): time objective over an n x n grid of
 * variables v1, v2 (others at the config's design), feasible points only,
 * and the gradient-based optimum with only v1, v2 free. */
typedef struct {
  double grid_best, grid_x1, grid_x2; /* best smooth p95 (s) on the grid and where */
  double opt_best, opt_x1, opt_x2;    /* the optimizer's */
  long grid_simulations, opt_simulations;
  int grid_feasible;
} pom_cds_slice;

/* The efficiency check (section 11.8): the time optimum of candidate c from
 * the config's design by the gradient-based algorithm and by COBYLA with
 * `budget` evaluations, on the same maneuvers. For each method and each
 * target (the best final objective of the two; COBYLA's final objective)
 * the simulations, sensitivity runs and CPU until its best feasible
 * objective first came within rel_tol of the target (from the points'
 * records). sens_cost: the plain-run equivalents of one sensitivity run in
 * the gradient-based run (its CPU per sensitivity run over COBYLA's CPU per
 * plain run; NaN without sensitivity runs). */
typedef struct {
  int reached;    /* 1 reached; 0 not within the run; -1 unknown (record full) */
  long sims;      /* simulations counted until then (sensitivity runs included) */
  long sens_runs; /* of which with sensitivities */
  double cpu;     /* process CPU of the optimization until then (s) */
} pom_cds_reach;

typedef struct {
  pom_cds_point grad, dfree;
  long grad_sims;
  double grad_best, dfree_best;
  double target; /* min(grad_best, dfree_best), s; NaN: none feasible */
  pom_cds_reach grad_to_target, dfree_to_target;
  pom_cds_reach grad_to_dfree, dfree_to_dfree; /* to COBYLA's final objective */
  double sens_cost;
} pom_cds_efficiency;

/* When the record of p first came within rel_tol of target (section 11.8). */
void pom_cds_first_within(const pom_cds_point *p, double target, double rel_tol, pom_cds_reach *r);

pom_status pom_cds_efficiency_run(const pom_cds_problem *pb, int c, int budget, double rel_tol,
                                  pom_cds_efficiency *out, pom_error *err);

pom_status pom_cds_grid_slice(const pom_cds_problem *pb, int c, int v1, int v2, int n,
                              pom_cds_slice *out, pom_error *err);

/* Whether figures f meet the requirement set as the optimizer tests it
 * (kinematic margin, current, envelope, no failure, time bound; no energy
 * bound). */
int pom_cds_feasible(const pom_cds_problem *pb, const pom_cds_figures *f);

/* Whether the true regular dexterous workspace at front point p (its
 * rdw_deg, pom_kin_workspace on the candidate's workspace.resolution grid,
 * a multiple of it) is below the required half-width (to 1e-9 deg). On a
 * feasible point: the workspace_grid^3 poses of g_kin passed but the dense
 * grid does not reach the requirement (for a requirement between two grid
 * steps, the RDW is the step below it). Only reported (docs/optimize.md
 * 11.6); the optimizer never sees it. */
int pom_cds_rdw_below(const pom_cds_problem *pb, const pom_cds_point *p);

/* The 1-D sweeps of candidate c (docs/optimize.md 11.6): for every variable
 * v, the config's design with variable v alone at n points evenly spaced
 * across its box (in log10 on a log axis), on the optimization set, rigid.
 * xs[v * n + j] receives the value, figs[v * n + j] its figures (arrays of
 * n_vars * n). */
pom_status pom_cds_sweep(const pom_cds_problem *pb, int c, int n, double *xs, pom_cds_figures *figs,
                         pom_error *err);

/* Writes the results file: to PATH.tmp.PID, synced, renamed over path only
 * when every write succeeded. */
pom_status pom_cds_write_h5(const pom_cds_problem *pb, const pom_cds_result *res, const char *path,
                            pom_error *err);

/* The report (text) and the fronts as an SVG figure. */
void pom_cds_report_text(FILE *out, const pom_cds_problem *pb, const pom_cds_result *res);
pom_status pom_cds_write_svg(const pom_cds_problem *pb, const pom_cds_result *res, const char *path,
                             pom_error *err);

#endif
