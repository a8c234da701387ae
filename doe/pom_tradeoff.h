/* pom_tradeoff.h - speed against accuracy of the dynamics engine
 * (docs/tradeoff.md): a sweep over formulation, scene options, rtol,
 * parasitic stiffness and linear solver, each setting run on a fixed set of
 * maneuvers (drawn from the study seed) and compared with a tight reference
 * (the model error plus the integration error) and with its own model at a
 * tight tolerance (the integration error alone).
 * Library code: never prints; the caller (cli/cmd_tradeoff.c) shows the
 * table and the recommendation. */
#ifndef POM_TRADEOFF_H
#define POM_TRADEOFF_H

#include "pom_config.h"
#include "pom_doe.h"
#include "pom_dynamics.h"
#include "pom_fidelity.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

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

/* The config group pom_tradeoff_load reads (`tradeoff`), NULL-terminated,
 * static storage. */
const char *const *pom_tradeoff_groups(void);

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
