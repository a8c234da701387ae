/* pom_tune.h - PID gain tuning by one criterion for every architecture
 * (docs/optimize.md, section 9).
 *
 * The criterion is the mean execution time over a small fixed set of
 * maneuvers (actuator setpoints from mid-stroke), plus penalties for
 * overshoot and saturation time beyond their limits. It never looks at the
 * architecture: the same config group applied to the 3PSS and the 3SPS tunes
 * both by the identical procedure. A simulation failure stops the optimizer
 * (nlopt_force_stop) and is returned as the status; it is never priced. */
#ifndef POM_TUNE_H
#define POM_TUNE_H

#include "pom_config.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_nlopt.h"
#include "pom_status.h"

#define POM_TUNE_MAX_MANEUVERS 32

/* A tuned gain: the index of a gain of the controller's type
 * (pom_dyn_ctrl.h). The PID's three have names here. */
typedef enum {
  POM_TUNE_KP = 0,                         /* PID controller.kp (V/V) */
  POM_TUNE_KI = 1,                         /* PID controller.ki_per_s (1/s) */
  POM_TUNE_KD = 2,                         /* PID controller.kd_s (s) */
  POM_TUNE_N_VARS = POM_DYN_CTRL_MAX_GAINS /* the most gains a controller type has */
} pom_tune_var;

/* Config name of gain v of the PID ("kp", "ki_per_s", "kd_s"; "?" otherwise). */
const char *pom_tune_var_name(pom_tune_var v);

/* The tuning problem (const during a run). */
typedef struct {
  pom_kin_arch arch;     /* geometry and limits */
  pom_mechanism mech;    /* bodies, joints, actuators */
  pom_dyn_params params; /* dynamics parameters; the tuned gains replace the controller's */
  int n_vars;            /* gains tuned, 1..3 */
  pom_tune_var var[POM_TUNE_N_VARS];
  double lo[POM_TUNE_N_VARS], hi[POM_TUNE_N_VARS]; /* bounds (SI) */
  int log_scale[POM_TUNE_N_VARS]; /* 1: searched in log10 of the gain (bounds > 0) */
  int n_maneuvers;
  double target[POM_TUNE_MAX_MANEUVERS][3]; /* actuator setpoints from mid-stroke (m) */
  double overshoot_max; /* allowed overshoot, fraction of each actuator's step (default 0.05) */
  double saturation_time_max; /* allowed time at the voltage limit per actuator (s, default 0.02) */
  double penalty_weight;      /* s per unit of relative excess (default: the horizon) */
  pom_opt_options opt;
  char maneuvers_where[320];    /* where the maneuvers come from, for messages: "FILE:LINE: key
                                   'tuning.maneuvers_mm'" or "FILE: the default tuning ..." */
  pom_opt_progress_fn progress; /* phase "tune", one unit per criterion evaluation; may be NULL */
  void *progress_user;          /* passed to progress */
} pom_tune_problem;

/* Criterion and its parts at one gain set. */
typedef struct {
  double criterion;      /* mean execution time + penalties (s) */
  double mean_execution; /* mean execution time, unsettled maneuvers counted at the horizon (s) */
  double max_execution;  /* largest execution time (s) */
  double max_overshoot;  /* largest overshoot over maneuvers and actuators (fraction of step) */
  double max_saturation; /* largest saturation time (s) */
  double mean_energy;    /* mean expended energy (J) */
  int unsettled;         /* maneuvers that did not settle within the horizon */
  double sim_time;       /* wall time of the simulations (s) */
} pom_tune_eval;

/* Defaults (docs/optimize.md 9): the maneuver set, limits and optimizer. */
void pom_tune_defaults(pom_tune_problem *pb);

/* The config group pom_tune_load reads (`tuning`), NULL-terminated, static
 * storage. */
const char *const *pom_tune_groups(void);

/* Loads the mechanism (`architecture`, `geometry`, `limits`, `inertia`), the
 * dynamics groups and `tuning` (docs/optimize.md 9). */
pom_status pom_tune_load(pom_tune_problem *pb, const pom_cfg *cfg, pom_error *err);

/* Criterion at the given controller (the other parameters from pb). A
 * failed simulation returns its status with err naming the maneuver. */
pom_status pom_tune_evaluate(const pom_tune_problem *pb, const pom_dyn_controller *ctl,
                             pom_tune_eval *out, pom_error *err);

/* Result of a tuning run. */
typedef struct {
  pom_dyn_controller initial; /* gains of the config */
  pom_tune_eval initial_eval; /* criterion there */
  pom_dyn_controller best;    /* tuned gains */
  pom_tune_eval best_eval;    /* criterion there */
  pom_opt_result opt;         /* NLopt record (x in search units) */
  long simulations;           /* maneuvers simulated in all */
} pom_tune_result;

/* Minimizes the criterion with NLopt. A criterion that cannot tell gains
 * apart (the same value at every gain set the search tries: no maneuver
 * moves, or none settles and nothing is penalised) is refused with
 * POM_ERR_CONFIG naming pb->maneuvers_where: no gains are tuned. */
pom_status pom_tune_run(const pom_tune_problem *pb, pom_tune_result *res, pom_error *err);

/* Writes the tuned gains as a libconfig `controller` group to path. */
pom_status pom_tune_write_controller(const pom_tune_problem *pb, const pom_tune_result *res,
                                     const char *path, pom_error *err);

#endif
