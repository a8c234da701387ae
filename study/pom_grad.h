/* pom_grad.h - design gradients of maneuver metrics with respect to numeric
 * config keys (docs/optimize.md, "Design gradients").
 *
 * A pom_grad holds a config and n design keys (dotted numeric keys such as
 * "geometry.platform_radius_mm", "actuator.resistance_ohm",
 * "controller.kp", "inertia.platform.mass_kg", or an element of a numeric
 * array "inertia.platform.moments_kgm2[2]"). For the current values of the
 * keys it builds the nominal model and, per key, the models at value +- h
 * (h = step), exactly as a study builds a candidate from its config
 * (kinematics, mechanism, dynamics; a model-based controller's own model
 * takes the design values too), and runs maneuvers with forward
 * sensitivities (pom_dyn_sens.h). Only rigid joints (joints.model =
 * "rigid"): POM_ERR_ARG naming the key otherwise.
 *
 * Units: every derivative is per unit of the key AS WRITTEN IN THE CONFIG
 * (per mm for a _mm key, per ohm, per unit of a dimensionless ratio); the
 * metric's unit is SI (s, J, rad).
 *
 * Monte-Carlo: the config's `montecarlo` group draws the maneuvers (same
 * targets as `pomlab montecarlo` with that config) and its optional
 * `uncertain` group perturbs the plant per maneuver as a study does. A
 * design key that is also uncertain: relative = true -> the plant's value is
 * value x draw and the derivative carries the draw; absolute -> the draw
 * replaces the value and the derivative is exactly 0.
 *
 * The models are built from the config's file text with its @includes:
 * values set with pom_cfg_set_number reach the `montecarlo` group (read
 * from cfg) but not the models; move design values with
 * pom_grad_set_values.
 *
 * Library code: never prints (pom_grad_mc_json writes where it is told). Not thread-safe per
 * pom_grad (one per thread). */
#ifndef POM_GRAD_H
#define POM_GRAD_H

#include "pom_config.h"
#include "pom_dyn_sens.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_status.h"

#include <stdint.h>
#include <stdio.h>

#define POM_GRAD_MAX_PARAMS POM_DYN_SENS_MAX
#define POM_GRAD_KEY_LEN    96

/* The metrics that have gradients, in the order of the tables and JSON. */
typedef enum {
  POM_GRAD_ENERGY_TOTAL = 0,
  POM_GRAD_ENERGY_1,
  POM_GRAD_ENERGY_2,
  POM_GRAD_ENERGY_3,
  POM_GRAD_TRACKING_RMS_ERROR,
  POM_GRAD_FINAL_POINTING_ERROR,
  POM_GRAD_SETTLING_TIME_1,
  POM_GRAD_SETTLING_TIME_2,
  POM_GRAD_SETTLING_TIME_3,
  POM_GRAD_EXECUTION_TIME,
  POM_GRAD_POINTING_SETTLING_TIME,
  POM_GRAD_PEAK_CURRENT, /* largest |coil current| (A), docs/optimize.md 12.2 */
  POM_GRAD_N_METRICS
} pom_grad_metric;

/* "energy_total", "energy_1", ..., "pointing_settling_time", "peak_current"
 * (the pom_dyn_metrics field names, one per actuator), static storage. */
const char *pom_grad_metric_name(pom_grad_metric k);
/* The metric's value in a run's metrics (SI). */
double pom_grad_metric_value(const pom_dyn_metrics *mt, pom_grad_metric k);
/* Its gradient in a run's gradients. */
const pom_dyn_dmetric *pom_grad_metric_grad(const pom_dyn_grad *g, pom_grad_metric k);

typedef struct {
  /* h_j = rel_step x |value_j|, or rel_step x abs_floor_j when the value is
   * 0 (abs_floor given per key, default 1; along a direction:
   * pom_grad_step): the step of the model
   * differences inside the sensitivities (docs/optimize.md: rounding
   * O(eps/h) against the saturation's narrow linear band, which a larger
   * step straddles: 3e-6 measured best) */
  double rel_step;                       /* default 3e-6 */
  double abs_floor[POM_GRAD_MAX_PARAMS]; /* default 1 (config units) */
  pom_dyn_sens_method method;            /* default staggered */
  int error_control;                     /* 1 (default): the sensitivities enter the error
                                            test; the key gradient.sens_error_test ("on",
                                            "off"), when present, replaces it */
  int rigid_joints;          /* 1: joints.model = "rigid" whatever the config's text says (the
                                co-design's rigid evaluation); default 0 */
  int peak_current;          /* 1 (default): the peak coil current and its derivative (three more
                                evaluations per step); 0: NaN and undefined */
  double sens_noise_margin;  /* the sensitivities' accuracy: their relative tolerance is
                                max(rtol, margin eps / rel_step) (pom_dyn_sens_spec.noise_margin,
                                docs/optimize.md 12.4); default POM_DYN_SENS_MARGIN_DEFAULT (3e2);
                                the config key gradient.sens_noise_margin, when present, replaces
                                it */
  double quantile;           /* the smooth robust statistic of the times over a Monte-Carlo set
                                (pom_grad_montecarlo): the kernel-smoothed quantile of
                                docs/optimize.md 11.3 at this probability, in [0.01, 0.99]; default
                                0.95; the key gradient.quantile replaces it */
  double quantile_bandwidth; /* its kernel's bandwidth (s) > 0; default 1e-3 (the co-design's
                                bandwidth_ms); the key gradient.quantile_bandwidth_ms (ms)
                                replaces it */
  double solver_rtol;        /* > 0: every run's solver.rtol instead of the config's (the
                                whole-run differences of `pomlab gradient --check` run tighter
                                than the file; the caller checks it as solver.rtol is checked);
                                0 (default): the config's */
} pom_grad_options;

void pom_grad_options_defaults(pom_grad_options *o);

/* The config key of the sensitivities' noise margin (`pomlab gradient
 * --sens-margin`), read by pom_grad_create from cfg (so a command-line value
 * set with pom_cfg_set_number reaches it) and checked against
 * [POM_DYN_SENS_MARGIN_MIN, POM_DYN_SENS_MARGIN_MAX]. */
#define POM_GRAD_KEY_NOISE_MARGIN "gradient.sens_noise_margin"
/* Whether the sensitivities enter CVODES' error test (`pomlab gradient
 * --sens-error-test`): "on" (default) or "off", read by pom_grad_create from
 * cfg into error_control as the noise margin is. Off, the state's steps
 * carry them: as accurate at a tight solver.rtol for far fewer steps, less
 * accurate at a loose one (docs/optimize.md 12.5, "The error test"). */
#define POM_GRAD_KEY_ERROR_TEST "gradient.sens_error_test"
/* The smooth quantile's probability and bandwidth (ms) (`pomlab gradient
 * --quantile`, `--bandwidth-ms`), read and checked as the noise margin. */
#define POM_GRAD_KEY_QUANTILE     "gradient.quantile"
#define POM_GRAD_KEY_BANDWIDTH    "gradient.quantile_bandwidth_ms"
#define POM_GRAD_QUANTILE_MIN     0.01
#define POM_GRAD_QUANTILE_MAX     0.99
#define POM_GRAD_BANDWIDTH_MIN_MS 1e-3
#define POM_GRAD_BANDWIDTH_MAX_MS 1e3

/* The top-level config names pom_grad_create reads beyond the models' and
 * the Monte-Carlo's: {"gradient", NULL}. */
const char *const *pom_grad_groups(void);

typedef struct pom_grad pom_grad;

/* Reads the config (its kinematics and dynamics groups as a study's
 * candidate, `montecarlo` and `uncertain` when present) and the keys' current
 * values; each key must be numeric in cfg (POM_ERR_CONFIG naming file, key
 * and value otherwise; an integer key is taken as a real), n in
 * 1..POM_GRAD_MAX_PARAMS, no key twice. Builds the models (POM_ERR_CONFIG or
 * POM_ERR_ARG when the design or a perturbed one is invalid, naming the key).
 * The caller owns *out (pom_grad_destroy). */
pom_status pom_grad_create(pom_grad **out, const pom_cfg *cfg, const char *const *keys, int n,
                           const pom_grad_options *o, pom_error *err);
void pom_grad_destroy(pom_grad *g);

/* Parameters along directions (docs/optimize.md 12.1): n_keys keys whose
 * values the design sets (pom_grad_set_values moves them all), and
 * n_params parameters a_j, each a direction in the keys' space:
 * dirs[j * n_keys + m] = d key_m / d a_j (config units of key m per unit of
 * a_j). The derivatives are with respect to the a_j: dM/da_j = sum_m
 * dirs[j][m] dM/dkey_m, taken in ONE sensitivity parameter per direction
 * (e.g. the actuator size law's tangent over its keys). A key no direction
 * moves is set but not differentiated (an uncertain draw); a zero direction
 * has derivative 0 and costs nothing. dirs NULL: the identity (n_params =
 * n_keys, parameter j is key j: pom_grad_create). */
pom_status pom_grad_create_dirs(pom_grad **out, const pom_cfg *cfg, const char *const *keys,
                                int n_keys, const double *dirs, int n_params,
                                const pom_grad_options *o, pom_error *err);

int pom_grad_n_params(const pom_grad *g); /* parameters (directions) */
int pom_grad_n_keys(const pom_grad *g);   /* keys (= parameters without directions) */
const char *pom_grad_key(const pom_grad *g, int m);
double pom_grad_value(const pom_grad *g, int m); /* key m's current value (config units) */
/* Parameter j's current step h_j and scale pbar_j (units of a_j; config
 * units of the key without directions): pbar_j = min over the keys m the
 * direction moves of |value_m| / |dirs[j][m]| (abs_floor_m for a value 0),
 * h_j = rel_step pbar_j: no key moves by more than rel_step of itself. 0
 * for a zero direction. */
double pom_grad_step(const pom_grad *g, int j);
double pom_grad_scale(const pom_grad *g, int j);
double pom_grad_dir(const pom_grad *g, int j, int m); /* dirs[j][m] */

/* Turns the peak coil current's watch and derivative on or off for the next
 * runs (pom_grad_options.peak_current; the co-design turns it on at every
 * sensitivity point, whose peak current figure it is, docs/optimize.md
 * 11.5). */
void pom_grad_watch_peak_current(pom_grad *g, int on);

/* Moves the design to values[n_keys] (config units) and rebuilds the
 * models; on failure (a value the key's own validation refuses, an
 * unassemblable design) the previous design stays and the status names the
 * key. */
pom_status pom_grad_set_values(pom_grad *g, const double *values, pom_error *err);
/* The same, with the directions replaced by dirs (n_params x n_keys, as in
 * pom_grad_create_dirs; NULL: unchanged); on failure both stay. */
pom_status pom_grad_set_point(pom_grad *g, const double *values, const double *dirs,
                              pom_error *err);

/* The nominal design at the current values: geometry (IK, workspace,
 * constraints), parameters and model. Valid until the next set_values. */
const pom_kin_arch *pom_grad_arch(const pom_grad *g);
const pom_dyn_params *pom_grad_params(const pom_grad *g);
const pom_dyn_model *pom_grad_model(const pom_grad *g);

/* One maneuver of the nominal plant (no uncertain draws) with gradients:
 * to actuator setpoints q (m or rad; the same for every perturbed model),
 * or to the platform orientation R (setpoints by each model's own IK, so
 * that d(setpoints)/d(geometry) enters). The status is the maneuver's
 * (metrics and gradients filled as pom_dyn_simulate_sens says); a target
 * outside the stroke or unreachable: POM_ERR_LIMIT / POM_ERR_UNREACHABLE
 * with metrics->status set. */
pom_status pom_grad_maneuver_joint(pom_grad *g, const double q[3], pom_dyn_metrics *mt,
                                   pom_dyn_grad *gr, pom_error *err);
pom_status pom_grad_maneuver_orientation(pom_grad *g, const double R[9], pom_dyn_metrics *mt,
                                         pom_dyn_grad *gr, pom_error *err);

/* ---- Monte-Carlo ------------------------------------------------------------------ */
typedef struct {
  long count;    /* maneuvers; 0 = the config's montecarlo.maneuvers */
  int seed_set;  /* 1: seed replaces montecarlo.seed (a fresh maneuver set) */
  uint64_t seed; /* (targets and uncertain draws both follow it) */
  int plain_fd;  /* 1: every gradient by central differences of whole simulations
                    instead (the check; 2n + 1 plain runs per maneuver) */
} pom_grad_mc_options;

void pom_grad_mc_options_defaults(pom_grad_mc_options *o);

typedef struct {
  int n_params;
  long n;                   /* maneuvers run */
  long n_finished;          /* of which finished (status POM_OK) */
  pom_dyn_metrics *metrics; /* [n] per maneuver (owned) */
  pom_dyn_grad *grads;      /* [n] per maneuver (owned) */
  /* means over the finished maneuvers, and their gradients: defined only
   * when every maneuver finished and every one's derivative is defined
   * (a never-settled time censors the mean); otherwise why = the first
   * maneuver's reason (a failed maneuver: POM_DYN_GRAD_UNKNOWN) and
   * n_defined counts those that were */
  double mean[POM_GRAD_N_METRICS];
  pom_dyn_dmetric dmean[POM_GRAD_N_METRICS];
  long n_defined[POM_GRAD_N_METRICS];
  /* the smooth quantile (options quantile, quantile_bandwidth) of each time
   * metric (the settling times, execution time, pointing settling time; NaN
   * and undefined for the others) and its gradient sum_i w_i dt_i/dp
   * (docs/optimize.md 12.3): defined under the means' rule (every maneuver
   * finished with its derivative defined: a censored time censors it) */
  double quantile_p, quantile_bandwidth; /* (s) */
  double quantile[POM_GRAD_N_METRICS];
  pom_dyn_dmetric dquantile[POM_GRAD_N_METRICS];
  /* how the gradients were computed: plain_fd as in the options, the
   * relative step (the sensitivities' differencing or the whole-run
   * differences') and the runs' solver.rtol */
  int plain_fd;
  double rel_step;
  double solver_rtol;
} pom_grad_mc_result;

/* The config's maneuvers (montecarlo group, o's count and seed) with the
 * uncertain draws, each with gradients (or, plain_fd, central differences
 * of whole simulations). Serial. The caller frees r (pom_grad_mc_free). */
pom_status pom_grad_montecarlo(pom_grad *g, const pom_grad_mc_options *o, pom_grad_mc_result *r,
                               pom_error *err);
void pom_grad_mc_free(pom_grad_mc_result *r);

/* Writes a Monte-Carlo result as JSON (SI; derivatives per config unit of
 * each key; an undefined gradient is null with its reason under
 * "undefined"): config, keys, values, per maneuver status, target, metrics,
 * gradient, undefined, peak_current_at (the peak coil current's time, s, and
 * coil from 1; null and 0 without one) (and "check": check's whole-run
 * differences when check is not NULL), finished, mean, mean_gradient, mean_gradient_defined_in,
 * quantile (p, bandwidth_s, value, gradient, undefined: the times' smooth quantile),
 * method (how r's gradients were computed: "sensitivities" or "whole-run differences",
 * rel_step, solver_rtol) and, with check, check_method (the same of check's).
 * What `pomlab gradient --json` prints and the Python module returns. */
void pom_grad_mc_json(FILE *out, const char *cfg_path, const pom_grad *g,
                      const pom_grad_mc_result *r, const pom_grad_mc_result *check);

/* ---- the check ------------------------------------------------------------------- */
/* Central differences of whole simulations of one maneuver (joint q or
 * orientation R, exactly one non-NULL) at a_j +- dh_j, i.e. the keys at
 * value +- dh_j dirs[j] (dh: units of a_j, config units of the key without
 * directions; NULL = the current steps): fd->d[j] of every metric, defined
 * when both runs finished and the metric is finite in both (0 for a zero
 * direction). mt receives the nominal
 * run's metrics. 2n + 1 plain simulations. */
pom_status pom_grad_fd_maneuver(pom_grad *g, const double *q, const double *R, const double *dh,
                                pom_dyn_metrics *mt, pom_dyn_grad *fd, pom_error *err);

/* ---- the honest reference (docs/optimize.md 12.4) ------------------------------------ */
/* The whole-run reference of one metric's gradient: central differences at
 * the steps H, H/2 and H/4 of each key, Richardson-extrapolated from the two
 * smallest, with an estimate of its own error and a test of whether the
 * metric is differentiable at all between value - H and value + H. */
typedef struct {
  double d[POM_GRAD_MAX_PARAMS];   /* the reference derivative (metric unit per key unit); NaN
                                      where undefined */
  double err[POM_GRAD_MAX_PARAMS]; /* its estimated error (same unit): the Richardson pair's
                                      disagreement plus the runs' integration error over the
                                      step; for a kink, the spread of the differences */
  int kink[POM_GRAD_MAX_PARAMS];   /* 1: not differentiable at this step: the central
                                      differences do not follow the h^2 law, or the forward and
                                      backward differences at H/4 disagree beyond what the
                                      curvature and the integration error explain */
  int defined;                     /* 1: every run finished and the metric is finite in all */
} pom_grad_ref;

/* The reference of every metric (ref[POM_GRAD_N_METRICS]) of one maneuver
 * (joint q or orientation R, exactly one non-NULL) at the steps H[j] (> 0;
 * units of a_j, the key's config units without directions), H[j]/2 and H[j]/4
 * along each direction; run_error[POM_GRAD_N_METRICS] is each
 * metric's relative integration error in one run, the part of it that is
 * not smooth in the design (docs/optimize.md 12.4 measures it at rtol
 * 1e-12). mt receives the nominal run's metrics. 6n + 1 plain simulations. */
pom_status pom_grad_reference(pom_grad *g, const double *q, const double *R, const double *H,
                              const double *run_error, pom_dyn_metrics *mt, pom_grad_ref *ref,
                              pom_error *err);

#endif
