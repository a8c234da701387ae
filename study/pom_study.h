/* pom_study.h - what a study is: maneuvers (how they are drawn), the
 * evaluators that run one candidate, candidates and sweep factors loaded
 * from a study file, uncertain parameters and their distributions, and the
 * fidelity each candidate earns (docs/results.md). Nothing here runs a study
 * (run/pom_run.h) or reduces its rows (stats/pom_stats.h).
 *
 * A study = candidates x maneuvers. Maneuver k draws its targets from a
 * generator seeded by (study seed, k) alone, so every candidate sees the same
 * targets (common random numbers) and the result of a maneuver does not
 * depend on the thread or rank that ran it. Work is done by an evaluator: a
 * shared read-only context per candidate plus one worker state per thread;
 * the real evaluator (pom_doe_dyn_evaluator_create) wraps pom_dyn_simulate,
 * tests use cheap analytic ones. */
#ifndef POM_STUDY_H
#define POM_STUDY_H

#include "pom_capability.h"
#include "pom_config.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_dynamics.h"
#include "pom_grad.h" /* design gradients from a config (pom_grad.c) */
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_rows.h"
#include "pom_status.h"

#include <hdf5.h>
#include <stdint.h>

/* ==== uncertain inputs (pom_uncertain.c) ======================================
 * Probability distributions of uncertain inputs and the
 * per-maneuver draws of a study's `uncertain` group (docs/results.md,
 * section 10).
 *
 * A distribution is an op table whose one operation is the inverse CDF: a
 * value is drawn by mapping a uniform u in (0, 1) through it, so Monte-Carlo
 * draws, Sobol/Saltelli designs and Morris grids all go through the same
 * code. Draws of maneuver k come from a generator seeded by (study seed, k)
 * on a stream of their own, so every candidate sees the same draws and the
 * maneuver targets are those of a study without uncertainty. */

/* ---- distributions --------------------------------------------------------- */
typedef struct pom_dist pom_dist;

/* What a distribution kind does. */
typedef struct {
  const char *name; /* config name: "uniform", "normal", ... */
  /* Inverse CDF at u in (0, 1). */
  double (*quantile)(const pom_dist *d, double u);
} pom_dist_ops;

/* One distribution. p[] meaning by kind (config units):
 * uniform (min, max); normal (mean, sd); truncated_normal (mean, sd, min,
 * max); lognormal (median, sigma_ln, min, max) with optional truncation
 * bounds (min = 0, max = inf when absent). */
struct pom_dist {
  const pom_dist_ops *ops;
  double p[4];   /* parameters, above */
  double lo, hi; /* smallest and largest value a draw can take */
};

/* Every registered kind, NULL-terminated (uniform, normal,
 * truncated_normal, lognormal). */
extern const pom_dist_ops *const pom_dist_kinds[];

/* Smallest and largest u a draw uses: draws map 52 random bits to the
 * centres (m + 1/2) 2^-52 (exact doubles), so no draw is 0 or 1. */
#define POM_DIST_U_MIN 0x1.0p-53
#define POM_DIST_U_MAX (1.0 - 0x1.0p-53)

/* Value of d at u; u is clamped into [POM_DIST_U_MIN, POM_DIST_U_MAX]. */
double pom_dist_quantile(const pom_dist *d, double u);

/* A uniform in (0, 1), never 0 or 1, from 64 random bits. */
double pom_dist_u_from_bits(uint64_t bits);

/* Builds a distribution of kind `name` from its parameters (NAN = absent
 * for the optional lognormal bounds); POM_ERR_ARG with a message when the
 * parameters are inconsistent. */
pom_status pom_dist_make(pom_dist *d, const char *name, const double p[4], pom_error *err);

/* Reads a distribution from the group at key (`dist` and its parameters,
 * docs/results.md section 10); messages name file, line and key. */
pom_status pom_dist_load(pom_dist *d, const pom_cfg *cfg, const char *key, pom_error *err);

/* ---- the `uncertain` group ------------------------------------------------- */
#define POM_UNC_MAX     16 /* uncertain parameters at most */
#define POM_UNC_KEY_LEN 64

typedef struct {
  char key[POM_UNC_KEY_LEN]; /* dotted numeric config key, e.g. "actuator.resistance_ohm" */
  pom_dist dist;             /* of the value (config units), or of the factor when relative */
  int relative;              /* 1: value = candidate's nominal value x draw */
  int controller_drawn;      /* 1: a model-based controller's own model takes the draw too; 0
                                (default, `controller = "nominal"`): it keeps the nominal value */
} pom_unc_param;

/* The uncertain parameters of a study and where unit k's draws come from. */
typedef struct {
  int n; /* parameters (0 = no uncertainty) */
  pom_unc_param param[POM_UNC_MAX];
  uint64_t seed; /* study seed (montecarlo.seed) */
  /* Design mode (pomlab sensitivity): unit k uses design row k / per_row
   * and maneuver k % per_row instead of random draws. */
  const double *design; /* [design_rows][n] u values in (0, 1), not owned; NULL = random */
  long design_rows;
  long per_row; /* maneuvers per design row */
} pom_unc;

/* Reads the optional `uncertain` list of cfg (absent: n = 0). seed is the
 * study seed. Only the distributions are checked here; the keys are checked
 * against each candidate by pom_doe_uncertain_check (pom_doe.h). */
pom_status pom_unc_load(pom_unc *unc, const pom_cfg *cfg, uint64_t seed, pom_error *err);

/* Unit k's maneuver index and u values u[n] in (0, 1): random mode, the
 * maneuver is k and u comes from a generator seeded by (seed, stream of
 * the uncertain draws + k); design mode, as said above. */
void pom_unc_unit(const pom_unc *unc, long k, long *maneuver, double *u);

/* Draws (distribution values) of unit k: x[n]. */
void pom_unc_draws(const pom_unc *unc, long k, double *x);

/* ==== fidelity earned per candidate (pom_fidelity.c) ===========================
 * The fidelity earned per candidate (docs/tradeoff.md section 9,
 * docs/results.md section 12): the cheapest setting of the dynamics engine
 * (joint model, coil model, tolerance) whose execution time and expended
 * energy stay within an accuracy of a tight reference, chosen on one set of
 * maneuvers with a margin and validated on another (drawn from a different
 * seed), whose measured errors are recorded as the setting's bound.
 * The one rule behind `study.fidelity = "auto"` and `pomlab tradeoff`'s
 * recommendation. Library code: never prints. */

#define POM_FIDELITY_MAX_MANEUVERS 1000 /* per set */
#define POM_FIDELITY_LABEL_LEN     64

/* One rung of the ladder: rigid joints (full limb inertia, universal
 * joints), the coil model and rtol (natural absolute tolerances). */
typedef struct {
  char label[POM_FIDELITY_LABEL_LEN]; /* e.g. "rigid, quasi-static coil, rtol 1e-04" */
  int coil_inductance;                /* 1: inductive coil (L di/dt); 0: quasi-static */
  double rtol;                        /* CVODE relative tolerance */
} pom_fidelity_setting;

/* The ladder, cheapest first (docs/tradeoff.md section 9); *n gets its
 * length. Static storage. */
const pom_fidelity_setting *pom_fidelity_ladder(int *n);

/* Sets p to rung s: rigid joints, full limb inertia, universal joints on,
 * s's coil model, rtol = s->rtol with natural absolute tolerances
 * (atol_scale 0). Everything else (actuator, gains, gravity, friction,
 * horizon, linear solver) stays p's. */
void pom_fidelity_apply(pom_dyn_params *p, const pom_fidelity_setting *s);

/* The reference of the rule: p with rigid joints, full scene, inductive coil
 * at rtol `rtol` (natural absolute tolerances). */
void pom_fidelity_reference(pom_dyn_params *p, double rtol);

/* Options of the rule. */
typedef struct {
  double accuracy;       /* relative accuracy asked on execution time and energy (0.01 = 1 %) */
  double margin;         /* the selection set must meet accuracy / margin (>= 1; default 2) */
  int n_select;          /* maneuvers of the selection set (default 20) */
  int n_validate;        /* maneuvers of the validation set (default 20) */
  double reference_rtol; /* rtol of the reference (default 1e-8) */
} pom_fidelity_opts;

/* Defaults: 1 %, margin 2, 20 + 20 maneuvers, reference rtol 1e-8. */
void pom_fidelity_defaults(pom_fidelity_opts *o);

/* What the rule chose and what it measured. Errors are relative, the worst
 * over the maneuvers the reference finished. */
typedef struct {
  int rung;                                 /* index in the ladder of the choice */
  pom_fidelity_setting setting;             /* the choice */
  int met;                                  /* 1: validated within the accuracy; 0: no rung was,
                                               the choice is the ladder's last (most accurate)
                                               rung and its bound is what it measured */
  double accuracy, margin;                  /* as asked */
  double select_time, select_energy;        /* the choice's errors on the selection set */
  double bound_time, bound_energy;          /* on the validation set: the recorded bound */
  int n_select, n_validate;                 /* maneuvers compared in each set */
  int tried;                                /* rungs run on the selection set */
  int validated;                            /* rungs run on the validation set */
  double steps, reference_steps;            /* mean CVODE steps per validation maneuver */
  double wall;                              /* s spent by the rule (references included) */
  char failure[POM_FIDELITY_LABEL_LEN * 2]; /* why the last rejected rung failed a maneuver,
                                               "" if none did */
} pom_fidelity_result;

/* The rule (docs/tradeoff.md section 9): runs the reference on both sets of
 * targets (actuator coordinates, m or rad: sel[n_sel], val[n_val]), then
 * walks the ladder cheapest first: a rung is chosen when its worst error in
 * execution time and in energy on the selection set is at most
 * accuracy / margin and, on the validation set, at most accuracy. A
 * maneuver the reference does not finish is left out; one the rung does not
 * finish (where the reference did) rejects the rung; an execution time that
 * does not settle is censored at the horizon. POM_ERR_SOLVER when the
 * reference finishes none of a set's maneuvers. */
pom_status pom_fidelity_select(pom_fidelity_result *res, const pom_kin_arch *arch,
                               const pom_mechanism *mech, const pom_dyn_params *base,
                               const double (*sel)[3], int n_sel, const double (*val)[3], int n_val,
                               const pom_fidelity_opts *o, pom_error *err);

/* The worst relative errors e[0] (execution time) and e[1] (energy) of
 * setting p against reference ref on targets q[n] (rule as above); *n_used
 * gets the maneuvers the reference finished (may be NULL). */
pom_status pom_fidelity_measure(double e[2], int *n_used, const pom_kin_arch *arch,
                                const pom_mechanism *mech, const pom_dyn_params *p,
                                const pom_dyn_params *ref, const double (*q)[3], int n,
                                pom_error *err);

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
  int capability_done;          /* 1: pom_doe_capability_run filled the line below */
  double capability[POM_CAP_N_FIGURES]; /* the figures of pom_cap_figures.h (SI; NaN: not
                                           computed or not asked) */
  int capability_met;                   /* 1: every study.capability_require holds */
} pom_doe_candidate;

typedef enum { POM_DOE_RANK_TIME = 0, POM_DOE_RANK_ENERGY = 1 } pom_doe_rank_by;

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
  /* study.capability (docs/capability.md, "As study responses and constraints"): per-candidate
   * capability figures computed before the maneuvers, columns of every output */
  int capability_n;                       /* figures asked (0: none, the default) */
  int capability_want[POM_CAP_N_FIGURES]; /* 1: figure i asked (or required) */
  int capability_grid;                    /* study.capability_grid_points (default 3) */
  int n_requirements;                     /* study.capability_require entries */
  pom_cap_requirement requirement[POM_CAP_N_FIGURES * 2];
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

/* study.capability: each candidate's capability figures (pom_cap_run on its
 * model, rigid joints, the study's coarse grid; slews only when a slew
 * figure is asked), and whether it meets study.capability_require. progress
 * (may be NULL) after each candidate. Nothing when capability_n is 0.
 * POM_ERR_CONFIG for a candidate whose evaluator is not a dynamics one. */
pom_status pom_doe_capability_run(pom_doe_study *study,
                                  void (*progress)(void *user, const pom_doe_candidate *cand,
                                                   int done, int total),
                                  void *user, pom_error *err);

/* Writes candidate c's figures as attributes "capability:<name>" (SI, NaN:
 * not computed) and capability_met of group g; nothing when not computed. */
pom_status pom_doe_capability_describe(const pom_doe_study *study, int c, hid_t g, pom_error *err);

/* Frees everything a study owns (NULL allowed); leaves it zeroed. */
void pom_doe_study_clear(pom_doe_study *study);

/* Keeps one candidate of a loaded study, chosen by its exact name or by its
 * 1-based position ("3"), and releases the others (their uncertain nominal
 * values follow). POM_ERR_ARG naming the value and the candidates when none
 * matches. */
pom_status pom_doe_study_select(pom_doe_study *study, const char *which, pom_error *err);

/* ---- the uncertain group in a results file (pom_doe_uncertain.c) ---- */
/* Writes /uncertain (keys, distributions, draws, nominal values). */
pom_status pom_doe_uncertain_write(hid_t file, const pom_doe_study *study, pom_error *err);
/* Resume: the file's /uncertain matches the study (or both have none). */
pom_status pom_doe_uncertain_check(hid_t file, const pom_doe_study *study, const char *path,
                                   pom_error *err);

/* ---- config groups of the explore library (pom_doe_groups.c, no dependencies) ---- */
/* The config group pom_doe_sens_load reads (`sensitivity`, in a study file),
 * NULL-terminated, static storage. */
const char *const *pom_doe_sens_groups(void);

/* The config group pom_tradeoff_load reads (`tradeoff`), NULL-terminated,
 * static storage. */
const char *const *pom_tradeoff_groups(void);

#endif
