/* pom_synth.h - kinematic synthesis of one architecture by response-surface
 * methodology: a designed experiment over the dimensionless design
 * parameters, quadratic surfaces of the kinematic responses, Derringer-Suich
 * desirability maximized on the surfaces with NLopt, a confirmation run of
 * the true kinematics, the same problem solved directly on the true
 * kinematics, and the scaling of the optimum to the actuator stroke
 * (docs/optimize.md, sections 5-7).
 *
 * Driver (docs/STYLE.md 15): pom_syn_begin() builds the design;
 * pom_syn_step() evaluates one design run (call until it returns 0 runs
 * left); pom_syn_finish() fits, optimizes, confirms and scales. */
#ifndef POM_SYNTH_H
#define POM_SYNTH_H

#include "pom_capability.h"
#include "pom_config.h"
#include "pom_design.h"
#include "pom_desirability.h"
#include "pom_kinematics.h"
#include "pom_nlopt.h"
#include "pom_arch.h"
#include "pom_rsm.h"
#include "pom_status.h"

/* Design variables are the architecture's design parameters marked `synth`
 * in its type table (pom_arch.h): pb->var[i] is the index of variable i in
 * type->params and in pom_kin_design.x. */
#define POM_SYN_N_VARS POM_KIN_MAX_PARAMS

/* Kinematic responses of one geometry. */
typedef enum {
  POM_SYN_RESP_RDW = 0,           /* regular dexterous workspace: Euler-cube half-width (rad) */
  POM_SYN_RESP_GCI = 1,           /* global conditioning index over the region */
  POM_SYN_RESP_MIN_DEXTERITY = 2, /* smallest 1/kappa over the region (0 where unreachable) */
  POM_SYN_RESP_FOOTPRINT =
      3,                 /* radius of the ground-side joints over the stroke / platform radius */
  POM_SYN_RESP_CONE = 4, /* measure fraction of region poses beyond a joint cone */
  POM_SYN_RESP_INTERFERENCE = 5, /* measure fraction of region poses with limbs too close */
  POM_SYN_RESP_STROKE = 6,       /* measure fraction of region poses beyond the stroke */
  POM_SYN_RESP_UNREACHABLE = 7,  /* measure fraction of region poses that cannot be assembled */
  POM_SYN_N_RESP = 8
} pom_syn_resp;

const char *pom_syn_resp_name(pom_syn_resp r);
double pom_syn_resp_unit(pom_syn_resp r);

/* Which optimum is scaled and written (synthesis.write). */
typedef enum {
  POM_SYN_WRITE_SURROGATE = 0, /* the optimum on the surfaces, confirmed (default) */
  POM_SYN_WRITE_DIRECT = 1,    /* the direct search's optimum (needs direct.enabled) */
  POM_SYN_WRITE_BEST = 2       /* the one of the two with the higher true desirability */
} pom_syn_write;

/* Config name of a choice ("surrogate", "direct", "best"). */
const char *pom_syn_write_name(pom_syn_write w);

/* A capability floor on the scaled optimum (synthesis.capability_require,
 * docs/optimize.md 6b): the figures of capability/pom_cap_figures.h on the
 * full mechanism (the scaled geometry, the config's inertia, actuator,
 * controller and capability groups), checked on the final optima, not
 * inside the optimizers. */
#define POM_SYN_MAX_CAP_REQUIRE 8
typedef struct {
  int n; /* requirements (0: no check, the default) */
  pom_cap_requirement req[POM_SYN_MAX_CAP_REQUIRE];
  int want[POM_CAP_N_FIGURES]; /* 1: figure computed (the required ones) */
  int grid;                    /* synthesis.capability_grid_points, odd (default 3) */
  pom_kin_inertia inertia;     /* the config's mass properties (rebuilt on the new geometry) */
  pom_dyn_params params;       /* the config's actuator, controller, joints, scene, solver */
  pom_cap_opts opts;           /* the config's capability group, cut to the figures asked */
} pom_syn_cap;

/* One optimum checked against the floor. */
typedef struct {
  int direct;                       /* 1: the direct search's optimum; 0: the surrogate's */
  double x[POM_SYN_N_VARS];         /* design point (SI) */
  double d;                         /* its true desirability at the base scale */
  double scale;                     /* platform radius it was scaled to (m; NaN: not scaled) */
  double value[POM_CAP_N_FIGURES];  /* the figures asked (SI; NaN: not computed) */
  int met[POM_SYN_MAX_CAP_REQUIRE]; /* per requirement */
  int all_met;                      /* every requirement holds */
  char note[256];                   /* why it was not evaluated, or "" */
} pom_syn_cap_check;

/* The synthesis problem of one architecture (const during a run). */
typedef struct pom_syn_problem pom_syn_problem;
struct pom_syn_problem {
  pom_kin_arch base;       /* architecture, limits and the base design (has_design = 1) */
  int n_vars;              /* design variables, 1..POM_RSM_MAX_K */
  int var[POM_SYN_N_VARS]; /* index of variable i in base.type->params */
  double lo[POM_SYN_N_VARS], hi[POM_SYN_N_VARS]; /* bounds (SI: rad or ratio) */
  pom_kin_ws_opts ws;                            /* regular dexterous workspace settings */
  double region_half_width; /* Euler cube of the GCI, min dexterity and violation fractions (rad) */
  double region_resolution; /* largest cell of that cube (rad) */
  int n_goals;              /* responses in the desirability */
  pom_syn_resp goal_resp[POM_SYN_N_RESP];
  pom_desir_spec goal[POM_SYN_N_RESP]; /* bounds in SI (rad for rdw) */
  pom_design_options design;
  int holdout_points; /* LHS runs for the held-out check of the surfaces (0 = none) */
  pom_rsm_options rsm;
  pom_opt_options surrogate_opt; /* maximization of D on the surfaces */
  int direct;                    /* 1: also solve on the true kinematics */
  pom_opt_options direct_opt;
  double target_half_width;    /* workspace the stroke must cover after scaling (rad) */
  double scale_min, scale_max; /* bracket of the platform radius (m) */
  double scale_rel_tol;        /* relative tolerance of the scale bisection */
  int scale_scan;              /* log-spaced radii scanned down from scale_max before bisecting */
  int refine_stages;    /* sequential designs in a box shrunk about the optimum (default 0) */
  double refine_shrink; /* each stage's box width / the previous one's (default 0.5) */
  int scale_optimum;    /* 1: scale the optimum to the stroke in pom_syn_finish (default 1) */
  pom_syn_write write;  /* which optimum is scaled and written (default surrogate) */
  pom_syn_cap cap;      /* capability floor on the scaled optimum (cap.n = 0: none) */
};

/* Config name of variable i of pb ("limb_lean_deg") and the factor from SI
 * to its config unit (1/POM_DEG for angles, else 1). */
const char *pom_syn_var_name(const pom_syn_problem *pb, int i);
double pom_syn_var_unit(const pom_syn_problem *pb, int i);
/* Config name of a response ("rdw_deg") and the factor from SI to its unit. */

/* Defaults (docs/optimize.md 7); base is left zero. */
void pom_syn_defaults(pom_syn_problem *pb);

/* The config group pom_syn_load reads (`synthesis`), NULL-terminated, static
 * storage. */
const char *const *pom_syn_groups(void);

/* Loads `architecture`, `geometry` (mode "parameters"), `limits`,
 * `workspace` and `synthesis` (docs/optimize.md 7). */
pom_status pom_syn_load(pom_syn_problem *pb, const pom_cfg *cfg, pom_error *err);

/* Reads synthesis.capability_require and synthesis.capability_grid_points
 * and, when there are requirements, the model they need (inertia for the
 * architecture of base, the dynamics groups, capability) into c;
 * pom_syn_load calls it (pom_synth_cap.c). */
pom_status pom_syn_cap_load(pom_syn_cap *c, const pom_kin_arch *base, const pom_cfg *cfg,
                            pom_error *err);

/* Geometry of design point x[n_vars] (SI) at platform radius scale (m), with
 * the base limits. POM_ERR_ARG when the design is degenerate. */
pom_status pom_syn_arch(const pom_syn_problem *pb, const double x[], double scale,
                        pom_kin_arch *arch, pom_error *err);

/* All responses of one geometry into resp[POM_SYN_N_RESP]. */
pom_status pom_syn_responses(const pom_syn_problem *pb, const pom_kin_arch *arch, double resp[],
                             pom_error *err);

/* Responses of design point x at the base scale. A degenerate design (no
 * assembly or a singular Jacobian at home) has no workspace: rdw, gci and
 * min dexterity 0, unreachable fraction 1, *degenerate = 1 (may be NULL). */
pom_status pom_syn_evaluate(const pom_syn_problem *pb, const double x[], double resp[],
                            int *degenerate, pom_error *err);

/* Overall desirability of a response vector; d[n_goals] (may be NULL)
 * receives the individual values. */
double pom_syn_desirability(const pom_syn_problem *pb, const double resp[], double d[]);

/* State and results of one synthesis run. */
typedef struct pom_syn_run_ {
  const pom_syn_problem *pb;
  pom_design *design; /* coded design (owned) */
  int n_runs;         /* design runs */
  int next;           /* next run to evaluate */
  double *x;          /* [n_runs * n_vars] natural design points (SI) */
  double *resp;       /* [n_runs * POM_SYN_N_RESP] responses */
  int n_degenerate;   /* degenerate design runs */
  double design_time; /* s spent evaluating the design */
  /* surfaces */
  int fitted[POM_SYN_N_RESP]; /* 1 when a surface was fitted (0: constant response) */
  pom_rsm_fit fit[POM_SYN_N_RESP];
  int n_holdout;
  double *holdout_x;                   /* [n_holdout * n_vars] (SI) */
  double *holdout_resp;                /* [n_holdout * POM_SYN_N_RESP] */
  pom_rsm_check check[POM_SYN_N_RESP]; /* surfaces against the held-out runs */
  /* optimum on the surfaces, and its confirmation */
  double x_opt[POM_SYN_N_VARS];     /* SI */
  double predicted[POM_SYN_N_RESP]; /* surfaces at x_opt */
  double confirmed[POM_SYN_N_RESP]; /* true kinematics at x_opt */
  double d_predicted, d_confirmed;  /* overall desirability, predicted and true */
  pom_opt_result surrogate;         /* NLopt on the surfaces */
  double surrogate_time;            /* s: design + fits + optimization + confirmation */
  /* the same problem directly on the true kinematics */
  int direct_done;
  double x_direct[POM_SYN_N_VARS];
  double direct_resp[POM_SYN_N_RESP];
  double d_direct;
  pom_opt_result direct;
  /* scaling of the chosen optimum (pb->write) to the stroke */
  int direct_better;                  /* 1: the direct optimum has the higher true desirability */
  int written_direct;                 /* 1: the direct optimum was scaled (and is written) */
  double x_written[POM_SYN_N_VARS];   /* the design point scaled (SI) */
  double d_written;                   /* its true desirability at the base scale */
  double scale;                       /* platform radius (m) */
  pom_kin_arch scaled;                /* the scaled geometry */
  double scaled_resp[POM_SYN_N_RESP]; /* its responses */
  int scale_evals;                    /* workspace evaluations of the bisection */
  int scaled_done;                    /* 1 when the scaling ran */
  /* the capability floor (pb->cap.n > 0): the optimum chosen by pb->write is
     checked; when it fails and the other optimum exists, that one is scaled
     and checked, and written instead when it meets the floor */
  int n_cap_checks;               /* 0: no floor; 1 or 2 */
  pom_syn_cap_check cap_check[2]; /* in the order checked */
  int cap_met;                    /* 1: the written optimum meets every requirement */
  int cap_switched;               /* 1: the other optimum was written because it meets them */
  /* sequential refinement: stage k + 1 is a new design in a box shrunk about
     the optimum of stage k; x_opt, predicted, confirmed and the
     desirabilities above are those of the best confirmed stage */
  struct pom_syn_run_ *refined;       /* next stage (owned), NULL when none */
  pom_syn_problem *refined_pb;        /* its problem (owned) */
  int best_stage;                     /* 0 = this run's own design, k = k-th refinement */
  double stage_x_opt[POM_SYN_N_VARS]; /* this stage's own optimum on its surfaces (SI) */
  double stage_d_predicted;           /* and its desirability, predicted and true */
  double stage_d_confirmed;
  long true_evals;              /* true-kinematics evaluations of the surrogate route, all stages */
  pom_opt_progress_fn progress; /* phases "design", "held-out", "refine", "direct",
                                   "scale"; may be NULL; set after pom_syn_begin */
  void *progress_user;          /* passed to progress */
  long direct_evals_seen;       /* direct-search evaluations so far (progress) */
} pom_syn_run;

/* Builds the design and allocates the run. The caller owns *out. */
pom_status pom_syn_begin(pom_syn_run **out, const pom_syn_problem *pb, pom_error *err);

/* Evaluates the next design run; *remaining receives the runs still to do. */
pom_status pom_syn_step(pom_syn_run *run, int *remaining, pom_error *err);

/* Held-out runs, fits, optimum on the surfaces, confirmation, direct
 * optimization (if asked) and scaling of the optimum pb->write chooses.
 * Reports progress through run->progress when set. */
pom_status pom_syn_finish(pom_syn_run *run, pom_error *err);

/* Frees; NULL allowed. */
void pom_syn_destroy(pom_syn_run *run);

/* The capability floor (docs/optimize.md 6b). pom_syn_finish checks it after
 * the scaling when pb->cap.n > 0: the written optimum, then the other one
 * when it fails (see pom_syn_run). pom_synth_cap.c evaluates: */
/* ck for the optimum x (SI) of true desirability d; figures NaN. */
void pom_syn_cap_check_start(pom_syn_cap_check *ck, int direct, const double *x, double d);
/* The figures of the scaled geometry arch (its mechanism from c->inertia,
 * pom_cap_run with c's parameters and options over the workspace ws) into
 * ck and the verdict per requirement. A capability run that fails leaves
 * the figures NaN (not met) with a note; fails only on out of memory. */
pom_status pom_syn_cap_check_arch(const pom_syn_cap *c, const pom_kin_ws_opts *ws,
                                  const pom_kin_arch *arch, pom_syn_cap_check *ck, pom_error *err);
/* ck not evaluated (why in its note): every requirement unmet. */
void pom_syn_cap_check_unevaluated(const pom_syn_cap *c, pom_syn_cap_check *ck, const char *why);
/* One line naming, per check, each failed requirement with its value and
 * bound ("surrogate optimum: bw_worst_hz = 53.3 Hz, required >= 100 Hz"). */
void pom_syn_cap_failure_text(const pom_syn_cap *c, const pom_syn_cap_check *checks, int n,
                              char *buf, size_t cap);
/* The same for run's checks. */
void pom_syn_cap_failure(const pom_syn_run *run, char *buf, size_t cap);

/* Finds the largest platform radius in [scale_min, scale_max] at which the
 * regular dexterous workspace of design point x still covers
 * target_half_width: a log-spaced scan down from scale_max, then bisection
 * on log scale (docs/optimize.md 6). POM_ERR_LIMIT when no scanned radius
 * covers it. */
pom_status pom_syn_scale(const pom_syn_problem *pb, const double x[], double *scale, int *evals,
                         pom_error *err);

/* Writes the scaled geometry as a libconfig `geometry` group (mode
 * "parameters", the form pom_kin_arch_load reads) to path, with a header
 * comment. POM_ERR_ARG when the run has not been scaled (scaled_done = 0). */
pom_status pom_syn_write_geometry(const pom_syn_run *run, const char *path, pom_error *err);

/* Writes the HDF5 record of the run (design, responses, fits, optimum,
 * confirmation, direct solution, scaling) to path. config_text may be NULL. */
pom_status pom_syn_write_h5(const pom_syn_run *run, const char *path, const char *config_text,
                            pom_error *err);

#endif
