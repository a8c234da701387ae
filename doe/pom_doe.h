/* pom_doe.h - Monte-Carlo design of experiments: maneuvers, candidates,
 * the batch runner (threads; MPI when built with it), the HDF5 results file
 * and the statistics that rank candidates (docs/results.md).
 *
 * A study = candidates x maneuvers. Maneuver k draws its targets from a
 * generator seeded by (study seed, k) alone, so every candidate sees the same
 * targets (common random numbers) and the result of a maneuver does not
 * depend on the thread or rank that ran it. Work is done by an evaluator: a
 * shared read-only context per candidate plus one worker state per thread;
 * the real evaluator (pom_doe_dyn_evaluator_create) wraps pom_dyn_simulate,
 * tests use cheap analytic ones. */
#ifndef POM_DOE_H
#define POM_DOE_H

#include "pom_config.h"
#include "pom_doe_stats.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_dynamics.h"
#include "pom_fidelity.h"
#include "pom_status.h"
#include "pom_uncertain.h"

#include <hdf5.h>
#include <stdint.h>

/* ---- maneuvers ------------------------------------------------------------ */
typedef enum {
  POM_DOE_SPACE_JOINT = 0,      /* targets drawn per actuator (the paper) */
  POM_DOE_SPACE_ORIENTATION = 1 /* tilt/torsion drawn, mapped to actuators by IK */
} pom_doe_space;

typedef enum {
  POM_DOE_DIST_UNIFORM = 0, /* uniform in [-range, +range] */
  POM_DOE_DIST_NORMAL = 1   /* normal(0, sigma) truncated to [-range, +range] */
} pom_doe_dist;

/* The config names of pom_doe_space ("joint", "orientation") and
 * pom_doe_dist ("uniform", "normal") values, in enum order, NULL-terminated:
 * pom_cfg_choice reads them, pom_cfg_choice_name writes them. */
extern const char *const pom_doe_space_names[];
extern const char *const pom_doe_dist_names[];

/* How maneuvers are drawn: the `montecarlo` config group. */
typedef struct {
  long count;                /* maneuvers per candidate */
  uint64_t seed;             /* study seed */
  pom_doe_space space;       /* joint or orientation space */
  pom_doe_dist distribution; /* of each joint target (joint space) */
  double range;              /* joint: targets within +-range of mid-stroke (m or rad) */
  double sigma;              /* joint, normal: standard deviation (m or rad) */
  const char *range_suffix;  /* suffix of the keys that gave range and sigma, an actuator kind's
                                key_suffix ("_mm": range_mm, sigma_mm; "_deg"); NULL: none, the
                                paper's +-3 mm (prismatic only) */
  double tilt_max;           /* orientation: largest tilt angle (rad) */
  double torsion_max;        /* orientation: largest |torsion| angle (rad) */
} pom_doe_maneuvers;

/* The paper's protocol: 1000 maneuvers, joint space, uniform within +-3 mm,
 * seed 20120708. */
void pom_doe_maneuvers_defaults(pom_doe_maneuvers *mv);

/* Reads the `montecarlo` group of cfg over the defaults (absent = defaults).
 * range_mm/sigma_mm are stored in m, range_deg/sigma_deg in rad; mixing the
 * two sets is an error. */
pom_status pom_doe_maneuvers_load(pom_doe_maneuvers *mv, const pom_cfg *cfg, pom_error *err);

/* The config group pom_doe_maneuvers_load reads (`montecarlo`),
 * NULL-terminated, static storage. */
const char *const *pom_doe_montecarlo_groups(void);

/* Checks the maneuvers against the actuator kinds of a study's candidates
 * (kinds[n]); cfg is the file that holds the `montecarlo` group (named in
 * messages). Joint space needs one kind for every candidate (the
 * orientation space is the fair comparison across kinds) and range keys in
 * that kind's unit (_mm prismatic, _deg revolute, and no default for
 * revolute). POM_ERR_CONFIG with the file, key and the right key. */
pom_status pom_doe_maneuvers_check_kinds(const pom_doe_maneuvers *mv,
                                         const pom_actuator_kind *kinds, int n, const pom_cfg *cfg,
                                         pom_error *err);

/* 1 when the kinds[n] are not all the same. */
int pom_doe_kinds_mixed(const pom_actuator_kind *kinds, int n);

/* One drawn maneuver. */
typedef struct {
  long index;       /* k */
  double q[3];      /* joint space: actuator targets from mid-stroke (m) */
  double orient[3]; /* orientation space: tilt azimuth, tilt, torsion (rad) */
  double R[9];      /* orientation space: target rotation R = Rz(a) Ry(t) Rz(s - a) */
} pom_doe_maneuver;

/* Draws maneuver k from a generator seeded by (mv->seed, k) only. */
void pom_doe_maneuver_draw(pom_doe_maneuver *out, const pom_doe_maneuvers *mv, long k);

/* Actuator targets (m or rad) of maneuvers 0 .. n-1 of protocol mv drawn
 * with `seed` in place of mv->seed (mv's space, range and distribution; an
 * orientation mapped by arch's inverse kinematics). Those arch cannot reach
 * or that lie outside its stroke are left out: *n_out <= n gets the number
 * kept in q[n]. */
void pom_doe_maneuver_targets(double (*q)[3], int *n_out, const pom_doe_maneuvers *mv,
                              uint64_t seed, int n, const pom_kin_arch *arch);

/* ---- evaluators -------------------------------------------------------------- */
#define POM_DOE_MAX_GROUPS 16 /* top-level config names one evaluator reads */

/* Runs maneuvers of one candidate. ctx is shared read-only by every worker;
 * each worker thread owns one state made by worker_create. */
typedef struct {
  void *ctx; /* shared state (owned: ctx_destroy frees it) */
  /* Creates one worker's state (e.g. a pom_dyn_data). */
  pom_status (*worker_create)(void **worker, const void *ctx, pom_error *err);
  void (*worker_destroy)(void *worker);
  /* Actuator targets (m) of an orientation-space maneuver (IK plus stroke
   * check); NULL when the evaluator only supports joint space. */
  pom_status (*targets)(const void *ctx, const pom_doe_maneuver *mv, double q[3], pom_error *err);
  /* Runs one maneuver to `target` (m). A failed maneuver sets out->status and
   * out->reason (and may return the status); the runner records it and goes
   * on. */
  pom_status (*run)(const void *ctx, void *worker, const double target[3], pom_dyn_metrics *out,
                    pom_error *err);
  /* Writes provenance (solver settings, gains, ...) as attributes of group;
   * may be NULL. */
  pom_status (*describe)(const void *ctx, hid_t group, pom_error *err);
  void (*ctx_destroy)(void *ctx);
  /* Kind of the candidate's actuators (unit of targets, strokes, ranges and
   * of the ACTUATOR metrics); zero-initialised = prismatic. */
  pom_actuator_kind actuator_kind;
  /* Top-level config names the evaluator reads (NULL-terminated, names in
   * static storage; pom_doe_evaluator_add_groups). A setting anywhere else
   * changes no maneuver: a study refuses it as a sweep factor, an uncertain
   * key or an override group. groups[0] == NULL: the evaluator does not
   * say (no such check). */
  const char *groups[POM_DOE_MAX_GROUPS + 1];
  /* 1: ctx starts with a pom_doe_dyn_base (the dynamics evaluators), so its
   * fidelity can be set (pom_doe_fidelity_run); 0 otherwise */
  int dyn_base;
} pom_doe_evaluator;

/* Appends the NULL-terminated names (e.g. pom_kin_model_groups()) to
 * eval->groups; POM_ERR_INTERNAL beyond POM_DOE_MAX_GROUPS in all. */
pom_status pom_doe_evaluator_add_groups(pom_doe_evaluator *eval, const char *const *names,
                                        pom_error *err);

/* 1 when eval reads the top-level name `group` (or does not say what it
 * reads), 0 otherwise. */
int pom_doe_evaluator_reads(const pom_doe_evaluator *eval, const char *group);

/* Frees an evaluator's context (eval may be NULL or empty). */
void pom_doe_evaluator_clear(pom_doe_evaluator *eval);

/* Makes the evaluator of one candidate from its resolved config. `user` is
 * passed through. The factory checks its own keys (unknown keys included). */
typedef pom_status (*pom_doe_evaluator_factory)(pom_doe_evaluator *eval, const pom_cfg *cfg,
                                                void *user, pom_error *err);

/* Shared by the dynamics evaluators (the one below and the study pipeline's):
 * a maneuver that ends with an actuator outside +-stroke/2 (stroke in the
 * unit of kind: m or rad), or
 * whose |q| exceeded it on the output grid (max_abs_q), is physically
 * impossible (the model has no end stops) and becomes a failure:
 * out->status = POM_ERR_LIMIT with the reason set (docs/results.md, section
 * 1). Returns POM_ERR_LIMIT (err set) when it made the maneuver a failure,
 * POM_OK otherwise (also when out->status already records a failure). */
pom_status pom_doe_check_final_stroke_kind(pom_dyn_metrics *out, double stroke,
                                           pom_actuator_kind kind, pom_error *err);
/* pom_doe_check_final_stroke_kind for prismatic actuators (stroke in m). */
pom_status pom_doe_check_final_stroke(pom_dyn_metrics *out, double stroke, pom_error *err);

/* Writes a candidate's dynamics settings (controller, scene, joints, solver,
 * maneuver) as attributes of group g (docs/results.md, section 5). */
pom_status pom_doe_describe_dyn_params(hid_t g, const pom_dyn_params *par, pom_error *err);

/* The dynamics part of a candidate evaluator, shared by the evaluator below
 * and by wrappers that build the candidate differently (the optimize
 * pipeline): a wrapper puts it FIRST in its context struct, so the
 * pom_doe_dyn_* callbacks below accept that context as their ctx. */
typedef struct {
  pom_kin_arch arch;     /* geometry and limits (orientation-space targets, stroke) */
  pom_mechanism mech;    /* bodies, joints, actuators */
  pom_dyn_params params; /* as simulated */
  pom_dyn_model *model;  /* shared read-only by the workers */
} pom_doe_dyn_base;

/* Evaluator callbacks on a context that starts with a pom_doe_dyn_base: one
 * pom_dyn_data per worker; joint targets from IK and refused outside the
 * stroke; pom_dyn_simulate, then pom_doe_check_final_stroke. */
pom_status pom_doe_dyn_worker_create(void **worker, const void *ctx, pom_error *err);
void pom_doe_dyn_worker_destroy(void *worker);
pom_status pom_doe_dyn_targets(const void *ctx, const pom_doe_maneuver *mv, double q[3],
                               pom_error *err);
pom_status pom_doe_dyn_run(const void *ctx, void *worker, const double target[3],
                           pom_dyn_metrics *out, pom_error *err);

/* The kind shared by every actuator of mech (POM_ERR_ARG when they differ
 * or there is none). */
pom_status pom_doe_mech_actuator_kind(const pom_mechanism *mech, pom_actuator_kind *kind,
                                      pom_error *err);

/* Writes the base's architecture, stroke, dynamics settings and state count
 * as attributes of group g. */
pom_status pom_doe_dyn_describe_base(const pom_doe_dyn_base *base, hid_t g, pom_error *err);

/* The real evaluator: architecture, mechanism and dynamics model from cfg
 * (kinematics and dynamics groups; unknown keys in them rejected). */
/* pom_doe_dyn_evaluator_create with the config a model-based controller's
 * own model is built from (ctrl_cfg; NULL: cfg's): the plant from cfg (an
 * uncertain draw), the controller's belief from the nominal candidate. */
pom_status pom_doe_dyn_evaluator_create_ex(pom_doe_evaluator *eval, const pom_cfg *cfg,
                                           const pom_cfg *ctrl_cfg, pom_error *err);
pom_status pom_doe_dyn_evaluator_create(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                                        pom_error *err);

/* ---- study -------------------------------------------------------------------- */
#define POM_DOE_NAME_LEN    128
#define POM_DOE_PATH_LEN    1024
#define POM_DOE_MAX_FACTORS 8

typedef struct {
  char name[POM_DOE_NAME_LEN];   /* label in tables and the results file */
  char source[POM_DOE_PATH_LEN]; /* config file the candidate starts from */
  char *resolved;                /* resolved config text (base + overrides), owned */
  int n_factors;                 /* sweep factors applied (0 for listed candidates) */
  char factor_key[POM_DOE_MAX_FACTORS][POM_DOE_NAME_LEN]; /* dotted keys */
  double factor_value[POM_DOE_MAX_FACTORS];               /* values set (config units) */
  pom_doe_evaluator eval;                                 /* owned */
  int fidelity_chosen;          /* 1: study.fidelity = "auto" set this candidate's setting */
  pom_fidelity_result fidelity; /* what it chose and measured (when fidelity_chosen) */
} pom_doe_candidate;

typedef enum { POM_DOE_RANK_TIME = 0, POM_DOE_RANK_ENERGY = 1 } pom_doe_rank_by;

/* The primary time metric of the paired comparisons, the Friedman test, the
 * ranking, the main effects and the Pareto front (study.time_metric;
 * docs/results.md section 4): the largest per-actuator settling time (the
 * paper's execution time) or the platform's pointing settling time. */
typedef enum {
  POM_DOE_TIME_EXECUTION = 0, /* execution_time: joint-space studies by default */
  POM_DOE_TIME_POINTING = 1   /* pointing_settling_time: orientation-space studies by default */
} pom_doe_time_metric;

typedef struct {
  char name[POM_DOE_NAME_LEN];     /* study name (file stem) */
  char source[POM_DOE_PATH_LEN];   /* study config path */
  char output[POM_DOE_PATH_LEN];   /* results file path */
  char *config_text;               /* the study file's text, owned */
  int threads;                     /* 0 = all cores */
  double alpha;                    /* significance level of the verdict (two-sided) */
  double confidence;               /* level of the paired interval (default 0.95) */
  pom_doe_rank_by rank_by;         /* primary ranking metric */
  pom_doe_time_metric time_metric; /* primary time metric (resolved from "auto") */
  char tabular[POM_DOE_PATH_LEN];  /* study.tabular: CSV file of rows ("" = none) */
  /* sweep factors, shared by every candidate of a sweep (0 for a list) */
  int n_factors;
  char factor_key[POM_DOE_MAX_FACTORS][POM_DOE_NAME_LEN];   /* dotted config keys */
  char factor_label[POM_DOE_MAX_FACTORS][POM_DOE_NAME_LEN]; /* short: the key's last part */
  long factor_levels[POM_DOE_MAX_FACTORS]; /* grid levels; 0 for a Latin hypercube */
  pom_doe_maneuvers maneuvers;
  int n_candidates;
  pom_doe_candidate *candidates; /* [n_candidates], owned */
  pom_unc uncertain;             /* the `uncertain` group (n = 0: none) */
  double *uncertain_nominal;     /* [n_candidates][uncertain.n] each key's value in the
                                    candidate's config (NaN when absent), owned */
  /* study.fidelity = "auto" (docs/results.md section 12): each candidate's
   * setting chosen by the rule of pom_fidelity.h, selected on maneuvers of
   * fidelity_seed, validated on the study's own first maneuvers */
  int fidelity_auto;          /* 1: "auto"; 0: "config" (the candidates' settings as given) */
  pom_fidelity_opts fidelity; /* accuracy, margin, set sizes, reference rtol */
  uint64_t fidelity_seed;     /* seed of the selection set (not montecarlo.seed) */
} pom_doe_study;

/* The top-level names a study file holds (`name`, `montecarlo`, `study`,
 * `candidates`, `uncertain`: what pom_doe_study_load reads), NULL-terminated,
 * static storage. */
const char *const *pom_doe_study_groups(void);

/* Loads a study file: `name`, `montecarlo`, `study` and `candidates`
 * (docs/results.md). Every candidate's config is resolved and handed to
 * factory; unknown keys are rejected. Nothing runs. Free with
 * pom_doe_study_clear. */
pom_status pom_doe_study_load(pom_doe_study *study, const pom_cfg *cfg,
                              pom_doe_evaluator_factory factory, void *user, pom_error *err);

/* A one-candidate study from an ordinary mechanism config (its optional
 * `montecarlo` group gives the maneuvers): `pomlab montecarlo`. */
pom_status pom_doe_study_single(pom_doe_study *study, const pom_cfg *cfg,
                                pom_doe_evaluator_factory factory, void *user, pom_error *err);

/* Candidate c's evaluator with the uncertain keys set to the draws x[]
 * (times the nominal values for relative parameters): its resolved config
 * with the values set, read by pom_doe_dyn_evaluator_create, so a drawn
 * value is validated like the key in a file. Clear with
 * pom_doe_evaluator_clear. */
pom_status pom_doe_uncertain_evaluator(pom_doe_evaluator *eval, const pom_doe_study *study, int c,
                                       const double *x, pom_error *err);

/* study.fidelity = "auto": for each candidate, the rule of pom_fidelity.h on
 * its nominal model (selection: maneuvers 0..n_select-1 of fidelity_seed;
 * validation: the study's maneuvers 0..n_validate-1, those it reaches), then
 * the choice applied: its model rebuilt with it, its resolved config
 * (results file, uncertain draws) given the setting's keys, the result kept
 * in the candidate. progress (may be NULL) is called after each candidate.
 * Does nothing when fidelity_auto is 0. POM_ERR_CONFIG for a candidate whose
 * evaluator is not a dynamics one. */
pom_status pom_doe_fidelity_run(pom_doe_study *study,
                                void (*progress)(void *user, const pom_doe_candidate *cand,
                                                 int done, int total),
                                void *user, pom_error *err);

/* Writes the fidelity attributes of candidate c (fidelity_setting,
 * fidelity_error_time, fidelity_error_energy, ...; docs/results.md section
 * 5) to group g; nothing when the fidelity was not chosen. */
pom_status pom_doe_fidelity_describe(const pom_doe_study *study, int c, hid_t g, pom_error *err);

/* Frees everything a study owns (NULL allowed); leaves it zeroed. */
void pom_doe_study_clear(pom_doe_study *study);

/* Keeps one candidate of a loaded study, chosen by its exact name or by its
 * 1-based position ("3"), and releases the others (their uncertain nominal
 * values follow). POM_ERR_ARG naming the value and the candidates when none
 * matches. */
pom_status pom_doe_study_select(pom_doe_study *study, const char *which, pom_error *err);

/* ---- results rows ------------------------------------------------------------ */
#define POM_DOE_REASON_LEN 160

/* Row field types of the metric types (ints are stored as int32, longs as
 * int64) and the shape of scalar (1) and per-actuator (3) metrics. */
#define POM_DOE_ROWTYPE_DOUBLE double
#define POM_DOE_ROWTYPE_INT    int32_t
#define POM_DOE_ROWTYPE_LONG   int64_t
#define POM_DOE_ROWDIM_1
#define POM_DOE_ROWDIM_3                       [3]
#define POM_DOE_ROW_FIELD_(name, type, n, ...) POM_DOE_ROWTYPE_##type name POM_DOE_ROWDIM_##n;

/* One maneuver of one candidate, as stored in the results file: done,
 * status, reason, then every metric of POM_DYN_METRICS_LIST
 * (pom_dyn_metrics_schema.h) in list order and SI units (actuator
 * coordinates in m or rad: the candidate's actuator_unit). */
typedef struct {
  int32_t done;                    /* 1 once computed (0 rows are not yet run) */
  int32_t status;                  /* pom_status of the maneuver (0 ok) */
  char reason[POM_DOE_REASON_LEN]; /* failure reason, "" when ok */
  POM_DYN_METRICS_LIST(POM_DOE_ROW_FIELD_, POM_DOE_ROW_FIELD_)
} pom_doe_row;

/* offsetof(pom_doe_row, <metric>) of metric j (pom_dyn_metric_id). */
size_t pom_doe_row_offset(int j);

/* Value k of metric j in a row, as a double. */
double pom_doe_row_value(const pom_doe_row *row, int j, int k);

/* Converts evaluator metrics to a row (done = 1). */
void pom_doe_row_from_metrics(pom_doe_row *row, const pom_dyn_metrics *m);

/* The file an unfinished run of results path `path` is in: "PATH.partial"
 * (renamed to PATH when every maneuver is done; docs/results.md). */
void pom_doe_results_partial_path(char *buf, size_t cap, const char *path);

/* Reads rows [first, first + n) of candidate c from a results file. */
pom_status pom_doe_results_read_rows(const char *path, int c, long first, long n, pom_doe_row *rows,
                                     pom_error *err);

/* ---- report -------------------------------------------------------------------- */
#define POM_DOE_STAT_IGNORE_(...)
#define POM_DOE_STAT_FIELD_(name, type, n, unit, descr, over, combine, stat, key)                  \
  pom_doe_stats stat;
/* Statistics of one candidate: one pom_doe_stats per reduced metric of
 * POM_DYN_METRICS_LIST, by name (execution_time, energy, energy_positive,
 * execution_time_final, ...) or as stat[pom_dyn_stat_id]. */
typedef struct {
  long n_done;      /* maneuvers finished */
  long n_failed;    /* status != ok */
  long n_unsettled; /* ok but some actuator never settled */
  long n_censored;  /* ok but the primary time metric did not settle within the horizon: its
                       value is censored at the horizon (docs/results.md section 4) */
  union {
    pom_doe_stats stat[POM_DYN_N_STATS];
    struct {
      POM_DYN_METRICS_LIST(POM_DOE_STAT_IGNORE_, POM_DOE_STAT_FIELD_)
    };
  };
} pom_doe_candidate_stats;

typedef enum { POM_DOE_METRIC_TIME = 0, POM_DOE_METRIC_ENERGY = 1 } pom_doe_metric;

typedef struct {
  int a, b;              /* candidate indices; differences are a - b (a < b when every pair is
                            compared, a = the metric's best candidate otherwise) */
  pom_doe_metric metric; /* which response */
  pom_doe_paired test;   /* on maneuvers where both are ok; an unsettled time counts censored at
                            its horizon */
  long censored_a;       /* time: pairs in which a's value is censored (0 for energy) */
  long censored_b;       /* time: pairs in which b's value is censored */
  double p_holm;         /* Wilcoxon p adjusted by Holm over the comparisons of this metric */
} pom_doe_comparison;

/* The main effect of one level of a sweep factor on one response: per
 * maneuver, the mean over the level's candidates that can use it; then the
 * mean over the maneuvers and its t interval (study.confidence). */
typedef struct {
  int factor;            /* index into study->factor_key */
  int level;             /* 0-based, ascending factor values */
  double lo, hi;         /* factor values of the level (equal unless binned) */
  int n_candidates;      /* candidates at this level */
  pom_doe_metric metric; /* response */
  long n;                /* maneuvers averaged */
  long n_censored;       /* time: censored values among those averaged */
  double mean;           /* SI (s or J) */
  double ci_low, ci_high;
} pom_doe_effect;

/* Up to this many candidates every pair is compared; beyond, the best of
 * each metric against each other one (docs/results.md, section 4). */
#define POM_DOE_ALL_PAIRS_MAX 4

typedef struct {
  int n_candidates;
  long n_maneuvers;
  pom_doe_candidate_stats *cand; /* [n_candidates] */
  int all_pairs;                 /* 1: every pair compared; 0: the best against each other */
  int n_comparisons;
  pom_doe_comparison *cmp;             /* [n_comparisons]: both metrics */
  pom_doe_friedman_result friedman[2]; /* per pom_doe_metric, over the common maneuvers */
  long friedman_censored;              /* censored time values among the Friedman blocks */
  int *rank_time;        /* [n_candidates] candidate indices, best (lowest mean) first */
  int *rank_energy;      /* [n_candidates] */
  double *mean_time;     /* [n_candidates] mean primary time over the common maneuvers, unsettled
                            ones censored at the horizon: the restricted mean (s) */
  long *censored_common; /* [n_candidates] censored times among the common maneuvers */
  double *mean_energy;   /* [n_candidates] mean expended energy over the common maneuvers (J) */
  double alpha;          /* level used for "significant" */
  int n_effects;
  pom_doe_effect *effects; /* [n_effects] main effects: factor-major, then metric, then level */
  int *pareto;             /* [n_candidates] 1 on the Pareto front of (mean_time, mean_energy) */
} pom_doe_report;

/* The levels of sweep factor f: its distinct values (ascending) when there
 * are at most 12, else 8 equal-width bins of its range (a Latin hypercube).
 * level_of[c] gets each candidate's level, lo/hi[l] (n_candidates doubles
 * each) the level's value range. Returns the number of levels, -1 when out
 * of memory. */
int pom_doe_factor_levels(const pom_doe_study *study, int f, int *level_of, double *lo, double *hi);

void pom_doe_report_destroy(pom_doe_report *r);

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

#endif
