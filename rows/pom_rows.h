/* pom_rows.h - the row of one maneuver of one candidate, as the results file
 * stores it and everything above reads it: the row layout (every metric of
 * the dynamics schema), its checks, and the compact per-maneuver cell the
 * statistics and the report work on (docs/results.md, section 5).
 * The bottom of the study libraries: it reads only the dynamics schema. */
#ifndef POM_ROWS_H
#define POM_ROWS_H

#include "pom_dyn_metrics_schema.h"
#include "pom_dynamics.h"
#include "pom_status.h"

#include <stddef.h>
#include <stdint.h>

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

/* ---- stored rows (pom_doe_rowcheck.c) ---- */
/* Checks the metrics of a done row: every value finite (NaN only where it
 * means "unsettled") and in its unit class's range (flags 0 or 1; counts,
 * times, magnitudes and dissipated energies >= 0), and for a maneuver that
 * succeeded the identities of pom_dyn_simulate (energy_total = sum of
 * energy, energy_supplied = energy_total, execution_time = the largest
 * settling time, settled exactly when its settling time is a number); a
 * failed row's flags and counts only. 0 when it holds; -1 with the field,
 * its value and the rule in why (cap bytes). */
int pom_doe_row_check_metrics(const pom_doe_row *row, char *why, size_t cap);

/* ---- cells (pom_doe_cell.c) ---- */
/* The primary time metric of the paired comparisons, the Friedman test, the
 * ranking, the main effects and the Pareto front (study.time_metric;
 * docs/results.md section 4): the largest per-actuator settling time (the
 * paper's execution time) or the platform's pointing settling time. */
typedef enum {
  POM_DOE_TIME_EXECUTION = 0, /* execution_time: joint-space studies by default */
  POM_DOE_TIME_POINTING = 1   /* pointing_settling_time: orientation-space studies by default */
} pom_doe_time_metric;

typedef enum { POM_DOE_METRIC_TIME = 0, POM_DOE_METRIC_ENERGY = 1 } pom_doe_metric;

/* Compact per-row values kept in memory for the statistics. */
typedef struct {
  int8_t done;        /* 1 when finished */
  int8_t ok;          /* status == POM_OK */
  int8_t settled;     /* every actuator settled */
  int8_t censored;    /* ok, and the primary time metric did not settle */
  int8_t rigid_limit; /* the parasitic model's validity rule (docs/dynamics.md section 13b): 1
                         flagged, 0 at its rigid limit, -1 not measured (rigid joints, failed) */
  double time;        /* primary time metric (s); the horizon when censored; NaN when failed */
  double stat[POM_DYN_N_STATS]; /* per reduced metric (pom_dyn_stat_id): the value its statistics
                                   use (combined over actuators), NaN when it does not count */
} pom_doe_cell;

void pom_doe_cell_from_row(pom_doe_cell *cell, const pom_doe_row *row,
                           pom_doe_time_metric time_metric);
/* 1 when the cell counts for the metric: the maneuver did not fail (an
 * unsettled time counts, censored at its horizon). */
int pom_doe_cell_usable(const pom_doe_cell *cell, pom_doe_metric metric);
/* The cell's value of a compared metric (the primary time, censored at the
 * horizon, or energy). */
double pom_doe_cell_value(const pom_doe_cell *cell, pom_doe_metric metric);

#endif
