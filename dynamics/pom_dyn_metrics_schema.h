/* pom_dyn_metrics_schema.h - the one list of maneuver metrics
 * (docs/results.md, section 9).
 *
 * Every field of pom_dyn_metrics that an output shows (the HDF5 maneuvers
 * table, `pomlab simulate --json`, the study/montecarlo JSON, the per-metric
 * text table of `pomlab simulate`, summary.md's metric listing and the
 * per-candidate statistics) is declared ONCE in POM_DYN_METRICS_LIST; every
 * output is generated from it. Adding a metric = one line here plus its field
 * in pom_dyn_metrics and its computation in dynamics/.
 *
 * A line is either
 *   M(name, type, n, unit, description)                      not reduced, or
 *   R(name, type, n, unit, description, over, combine, stat, stat_key)
 *                                   reduced to per-candidate statistics, where
 *   name     the field of pom_dyn_metrics, of the doe row and of the HDF5
 *            compound (never renamed: files and scripts use it);
 *   type     DOUBLE (double), INT (int; int32 in rows), LONG (long; int64);
 *   n        1 (scalar) or 3 (per actuator);
 *   unit     a unit class (pom_dyn_unit below): ACTUATOR is the actuator
 *            coordinate, m or rad, and EFFORT the actuator's effort, N or N m,
 *            both resolved per candidate from its actuators;
 *   over     OK (maneuvers that did not fail, value finite) or SETTLED
 *            (maneuvers that settled);
 *   combine  NONE (scalar), SUM or MAX (per-actuator values combined first;
 *            MAX is NaN when any is not finite);
 *   stat     name of the statistic (/statistics/<stat> in HDF5, a member of
 *            pom_doe_candidate_stats);
 *   stat_key its key in the study JSON.
 * The order of the lines is the order of the HDF5 compound's fields. */
#ifndef POM_DYN_METRICS_SCHEMA_H
#define POM_DYN_METRICS_SCHEMA_H

#include "pom_dynamics.h"
#include "pom_mechanism.h"

#include <stddef.h>

/* clang-format off */
#define POM_DYN_METRICS_LIST(M, R)                                                                 \
  M(target, DOUBLE, 3, ACTUATOR, "setpoint of each actuator from mid-stroke")                      \
  M(settling_time, DOUBLE, 3, TIME,                                                                \
    "last time outside the band of settle_band times the step about the setpoint (NaN when unsettled)")   \
  M(settled, INT, 3, FLAG, "1 when inside its band at the horizon")                                \
  R(settling_time_final, DOUBLE, 3, TIME,                                                          \
    "settling time by MATLAB stepinfo (band about the final value)", OK, MAX,                      \
    execution_time_final, "execution_time_stepinfo_s")                                             \
  R(execution_time, DOUBLE, 1, TIME,                                                               \
    "largest settling time (NaN when failed or unsettled)", SETTLED, NONE, execution_time,         \
    "execution_time_s")                                                                            \
  M(energy, DOUBLE, 3, ENERGY, "signed int u i dt of each actuator's source")                      \
  R(energy_positive, DOUBLE, 3, ENERGY, "int max(u i, 0) dt", OK, SUM, energy_positive,            \
    "energy_positive_J")                                                                           \
  R(energy_total, DOUBLE, 1, ENERGY, "expended energy: sum of energy", OK, NONE, energy,           \
    "energy_J")                                                                                    \
  M(peak_voltage, DOUBLE, 3, VOLTAGE, "largest |u| of the drive")                                  \
  M(saturation_time, DOUBLE, 3, TIME, "time with |u| at the voltage limit")                        \
  M(final_q, DOUBLE, 3, ACTUATOR, "actuator coordinate at the horizon, from mid-stroke")           \
  M(max_deflection, DOUBLE, 1, LENGTH, "largest linear parasitic deflection")                      \
  M(energy_balance_error, DOUBLE, 1, RATIO,                                                        \
    "|supplied - dissipated - stored change| / energy_balance_scale")                              \
  M(steps, LONG, 1, COUNT, "solver steps")                                                         \
  M(rhs_evals, LONG, 1, COUNT, "right-hand side evaluations")                                      \
  M(jac_evals, LONG, 1, COUNT, "Jacobian evaluations")                                             \
  M(newton_iters, LONG, 1, COUNT, "Newton iterations")                                             \
  M(error_test_fails, LONG, 1, COUNT, "error-test failures")                                       \
  M(wall_time, DOUBLE, 1, TIME, "wall-clock time (differs between identical runs)")                \
  M(max_abs_q, DOUBLE, 3, ACTUATOR, "largest |q| over the integrator's steps")                            \
  M(max_angular_deflection, DOUBLE, 1, ANGLE, "largest angular parasitic deflection")              \
  M(energy_supplied, DOUBLE, 1, ENERGY, "sum over the sources of int u i dt")                      \
  M(energy_dissipated, DOUBLE, 1, ENERGY, "coil + bearing + parasitic dampers")                    \
  M(energy_stored_change, DOUBLE, 1, ENERGY, "stored energy, end minus start")                     \
  M(energy_coil, DOUBLE, 3, ENERGY, "int R_c i^2 dt")                                              \
  M(energy_bearing, DOUBLE, 3, ENERGY, "int b q_dot^2 dt")                                         \
  M(energy_parasitic, DOUBLE, 1, ENERGY, "int of the parasitic damper powers")                     \
  M(energy_balance_scale, DOUBLE, 1, ENERGY, "denominator of energy_balance_error")                \
  M(jac_rhs_evals, LONG, 1, COUNT, "RHS evaluations inside Jacobians")                             \
  M(linsol_setups, LONG, 1, COUNT, "Newton matrix factorizations")                                 \
  M(nonlin_conv_fails, LONG, 1, COUNT, "Newton convergence failures")                              \
  M(last_step, DOUBLE, 1, TIME, "last internal step size")                                       \
  M(horizon, DOUBLE, 1, TIME, "the maneuver's horizon: unsettled times are censored there")       \
  R(pointing_settling_time, DOUBLE, 1, TIME,                                                       \
    "last time the platform was outside the pointing band about the target orientation "          \
    "(NaN when unsettled or the target orientation is unknown)", OK, NONE, pointing_time,         \
    "pointing_settling_time_s")                                                                    \
  M(pointing_settled, INT, 1, FLAG, "1 when the pointing error is inside its band at the horizon") \
  M(final_pointing_error, DOUBLE, 1, ANGLE,                                                        \
    "angle between the platform and the target orientation at the horizon (NaN when unknown)")    \
  M(peak_angular_rate, DOUBLE, 1, ANGULAR_RATE, "largest |omega| of the platform")                \
  M(peak_effort, DOUBLE, 3, EFFORT, "largest |K_m i - b q_dot| of each actuator (force or torque)") \
  M(tracking_rms_error, DOUBLE, 1, ANGLE,                                                          \
    "RMS angle between the platform and the controller's reference (NaN without a trajectory)")  \
  M(stepinfo_unresolved, INT, 3, FLAG,                                                             \
    "1 when the stepinfo band lies below what the integration resolves (settling_time_final NaN)") \
  M(rigid_limit_ratio, DOUBLE, 1, RATIO,                                                           \
    "1/(omega_low T_E)^2: lowest joint frequency against the drive's energy duration; "          \
    "above 1e-2 not at the rigid limit (NaN on rigid joints)")                                      \
  M(joint_dissipation_share, DOUBLE, 1, RATIO,                                                     \
    "parasitic damper energy over the drive's positive mechanical work; "                          \
    "above 2e-4 not at the rigid limit (NaN on rigid joints)")
/* clang-format on */

/* Unit classes of metrics. */
typedef enum {
  POM_DYN_UNIT_ACTUATOR = 0, /* the actuator coordinate: m (prismatic) or rad (revolute) */
  POM_DYN_UNIT_TIME,         /* s */
  POM_DYN_UNIT_ENERGY,       /* J */
  POM_DYN_UNIT_VOLTAGE,      /* V */
  POM_DYN_UNIT_LENGTH,       /* m (not an actuator coordinate) */
  POM_DYN_UNIT_ANGLE,        /* rad (not an actuator coordinate) */
  POM_DYN_UNIT_RATIO,        /* dimensionless */
  POM_DYN_UNIT_COUNT,        /* a count */
  POM_DYN_UNIT_FLAG,         /* 0 or 1 */
  POM_DYN_UNIT_ANGULAR_RATE, /* rad/s */
  POM_DYN_UNIT_EFFORT        /* the actuator's effort: N (prismatic) or N m (revolute) */
} pom_dyn_unit;

typedef enum { POM_DYN_TYPE_DOUBLE = 0, POM_DYN_TYPE_INT, POM_DYN_TYPE_LONG } pom_dyn_metric_type;
typedef enum { POM_DYN_REDUCE_NONE = 0, POM_DYN_REDUCE_OK, POM_DYN_REDUCE_SETTLED } pom_dyn_reduce;
typedef enum { POM_DYN_COMBINE_NONE = 0, POM_DYN_COMBINE_SUM, POM_DYN_COMBINE_MAX } pom_dyn_combine;

/* Metric ids (POM_DYN_METRIC_<name>) in list order, and their count. */
#define POM_DYN_METRIC_ID_(name, ...) POM_DYN_METRIC_##name,
typedef enum {
  POM_DYN_METRICS_LIST(POM_DYN_METRIC_ID_, POM_DYN_METRIC_ID_) POM_DYN_N_METRICS
} pom_dyn_metric_id;

/* Statistic ids (POM_DYN_STAT_<stat>) of the reduced metrics, in list order. */
#define POM_DYN_STAT_IGNORE_(...)
#define POM_DYN_STAT_ID_(name, type, n, unit, descr, over, combine, stat, key) POM_DYN_STAT_##stat,
typedef enum {
  POM_DYN_METRICS_LIST(POM_DYN_STAT_IGNORE_, POM_DYN_STAT_ID_) POM_DYN_N_STATS
} pom_dyn_stat_id;

/* One metric as declared. */
typedef struct {
  const char *name;         /* field name (pom_dyn_metrics, doe row, HDF5 compound) */
  pom_dyn_metric_type type; /* of the pom_dyn_metrics field */
  int count;                /* 1 scalar, 3 per actuator */
  pom_dyn_unit unit;        /* unit class */
  const char *description;  /* one line, for attributes and listings */
  size_t offset;            /* offsetof(pom_dyn_metrics, name) */
  pom_dyn_reduce reduce;    /* how it becomes per-candidate statistics */
  pom_dyn_combine combine;  /* per-actuator values combined before reducing */
  int stat;                 /* pom_dyn_stat_id, -1 when not reduced */
  const char *stat_name;    /* /statistics/<stat_name>; NULL when not reduced */
  const char *stat_key;     /* study JSON key; NULL when not reduced */
} pom_dyn_metric_info;

/* The table of every metric, [POM_DYN_N_METRICS] in list order (static). */
const pom_dyn_metric_info *pom_dyn_metric_schema(void);

/* Metric j (NULL outside [0, POM_DYN_N_METRICS)), and the metric that stat s
 * reduces (NULL outside [0, POM_DYN_N_STATS)). */
const pom_dyn_metric_info *pom_dyn_metric(int j);
const pom_dyn_metric_info *pom_dyn_stat_metric(int s);

/* SI unit of a metric's values ("s", "J", "m", "rad", "1", ...; the actuator
 * coordinate's SI unit of kind for POM_DYN_UNIT_ACTUATOR). Static storage. */
const char *pom_dyn_metric_unit(const pom_dyn_metric_info *mi, pom_actuator_kind kind);

/* Unit of a metric in text output ("ms", "mJ", "mm", "deg", ...) and the
 * factor from SI to it. */
const char *pom_dyn_metric_display_unit(const pom_dyn_metric_info *mi, pom_actuator_kind kind,
                                        double *factor);

/* JSON key of `pomlab simulate --json`: name + "_" + SI unit for fixed units
 * (e.g. "execution_time_s", "energy_J"); the bare name for counts, flags,
 * ratios and actuator coordinates (their unit is given as actuator_unit).
 * Writes into buf (cap bytes) and returns it. */
const char *pom_dyn_metric_json_key(const pom_dyn_metric_info *mi, char *buf, size_t cap);

/* Value k (0..count-1) of a metric in m as a double (ints and longs
 * converted). */
double pom_dyn_metric_value(const pom_dyn_metrics *m, const pom_dyn_metric_info *mi, int k);

/* n values combined as c says: SUM in order, MAX (NaN when any value is not
 * finite), NONE the first value. */
double pom_dyn_combine_values(pom_dyn_combine c, const double *v, int n);

/* Short names: "none", "ok",
 * "settled"; "none", "sum", "max". */
const char *pom_dyn_reduce_name(pom_dyn_reduce r);
const char *pom_dyn_combine_name(pom_dyn_combine c);

#endif
