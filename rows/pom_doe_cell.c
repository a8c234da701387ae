/* pom_doe_cell.c - the compact per-maneuver cell the statistics, the report
 * and the main effects read (docs/results.md section 4). */
#include "pom_rows.h"

#include <math.h>

/* The per-maneuver value of each statistic: its metric combined over the
 * actuators, kept when the maneuver counts for it (ok, or settled) and the
 * value is finite; NaN otherwise. */
void pom_doe_cell_from_row(pom_doe_cell *cell, const pom_doe_row *row,
                           pom_doe_time_metric time_metric) {
  cell->done = (int8_t)(row->done != 0);
  cell->ok = (int8_t)(row->done && row->status == POM_OK);
  cell->settled = (int8_t)(cell->ok && row->settled[0] && row->settled[1] && row->settled[2] &&
                           isfinite(row->execution_time));
  /* the primary time: an unsettled maneuver is right-censored at its
   * horizon, never dropped (docs/results.md section 4) */
  double t =
      time_metric == POM_DOE_TIME_POINTING ? row->pointing_settling_time : row->execution_time;
  int settled =
      time_metric == POM_DOE_TIME_POINTING ? cell->ok && row->pointing_settled == 1 : cell->settled;
  cell->censored = (int8_t)(cell->ok && !(settled && isfinite(t)));
  cell->rigid_limit =
      (int8_t)(!cell->ok ? -1
                         : pom_dyn_rigid_limit_flag(
                               pom_doe_row_value(row, POM_DYN_METRIC_rigid_limit_ratio, 0),
                               pom_doe_row_value(row, POM_DYN_METRIC_joint_dissipation_share, 0)));
  /* a row without a horizon (an evaluator that does not set it) cannot be
   * censored: its unsettled time stays out, as before the censoring */
  double horizon = row->horizon > 0 ? row->horizon : NAN;
  cell->time = !cell->ok ? NAN : cell->censored ? horizon : t;
  for (int s = 0; s < POM_DYN_N_STATS; ++s) {
    const pom_dyn_metric_info *mi = pom_dyn_stat_metric(s);
    int j = (int)(mi - pom_dyn_metric_schema());
    double v[3];
    for (int k = 0; k < mi->count; ++k)
      v[k] = pom_doe_row_value(row, j, k);
    double x = pom_dyn_combine_values(mi->combine, v, mi->count);
    int counts = mi->reduce == POM_DYN_REDUCE_SETTLED ? cell->settled : cell->ok && isfinite(x);
    cell->stat[s] = counts ? x : NAN;
  }
}

int pom_doe_cell_usable(const pom_doe_cell *cell, pom_doe_metric metric) {
  return metric == POM_DOE_METRIC_TIME ? cell->ok && isfinite(cell->time) : cell->ok;
}

/* The chosen metrics of the paired comparison and the ranking, read through
 * the schema's statistics. */
double pom_doe_cell_value(const pom_doe_cell *cell, pom_doe_metric metric) {
  return metric == POM_DOE_METRIC_TIME ? cell->time : cell->stat[POM_DYN_STAT_energy];
}
