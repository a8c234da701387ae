/* pom_doe_rowcheck.c - the metrics of a stored row against their physical
 * ranges and the identities the simulation guarantees, checked before a
 * resumed study carries the row into its statistics (docs/results.md,
 * section 5). */
#include "pom_rows.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- ranges -------------------------------------------------------------------- */
/* Metrics that are NaN by definition when an actuator or the platform did
 * not settle, when the target orientation is unknown (no architecture),
 * when the controller has no reference trajectory or when the joints are
 * rigid (the rigid-limit ratio). */
static int may_be_nan(int j) {
  return j == POM_DYN_METRIC_settling_time || j == POM_DYN_METRIC_settling_time_final ||
         j == POM_DYN_METRIC_execution_time || j == POM_DYN_METRIC_pointing_settling_time ||
         j == POM_DYN_METRIC_final_pointing_error || j == POM_DYN_METRIC_tracking_rms_error ||
         j == POM_DYN_METRIC_rigid_limit_ratio || j == POM_DYN_METRIC_joint_dissipation_share;
}

/* Energies with a sign (a source may take energy back, the stored energy may
 * fall); every other energy integrates a non-negative power. */
static int signed_energy(int j) {
  return j == POM_DYN_METRIC_energy || j == POM_DYN_METRIC_energy_total ||
         j == POM_DYN_METRIC_energy_supplied || j == POM_DYN_METRIC_energy_stored_change;
}

/* Signed actuator coordinates (every other one is a magnitude). */
static int signed_coordinate(int j) {
  return j == POM_DYN_METRIC_target || j == POM_DYN_METRIC_final_q;
}

/* "" when value v of metric j fits its unit class; else why not. */
static const char *out_of_range(int j, double v) {
  const pom_dyn_metric_info *mi = pom_dyn_metric(j);
  if (isnan(v)) return may_be_nan(j) ? "" : "is NaN";
  if (!isfinite(v)) return "is not finite";
  switch (mi->unit) {
  case POM_DYN_UNIT_FLAG:
    return v == 0.0 || v == 1.0 ? "" : "is neither 0 nor 1";
  case POM_DYN_UNIT_ENERGY:
    return signed_energy(j) || v >= 0.0 ? "" : "is negative (an integral of a non-negative power)";
  case POM_DYN_UNIT_ACTUATOR:
    return signed_coordinate(j) || v >= 0.0 ? "" : "is negative (a magnitude)";
  case POM_DYN_UNIT_TIME:
  case POM_DYN_UNIT_COUNT:
  case POM_DYN_UNIT_VOLTAGE:
  case POM_DYN_UNIT_LENGTH:
  case POM_DYN_UNIT_ANGLE:
  case POM_DYN_UNIT_RATIO:
  case POM_DYN_UNIT_ANGULAR_RATE:
  case POM_DYN_UNIT_EFFORT:
    return v >= 0.0 ? "" : "is negative";
  }
  return "";
}

/* ---- identities ---------------------------------------------------------------- */
/* The sums and maxima that pom_dyn_simulate forms from other metrics, in the
 * same order (so bit for bit); "" when they hold. */
static const char *broken_identity(const pom_doe_row *row, char *why, size_t cap) {
  double total = 0.0, exec = 0.0;
  for (int a = 0; a < 3; ++a)
    total += row->energy[a];
  if (!(row->energy_total == total)) {
    snprintf(why, cap, "field 'energy_total' = %.17g is not the sum of 'energy' (%.17g)",
             row->energy_total, total);
    return why;
  }
  if (!(row->energy_supplied == row->energy_total)) {
    snprintf(why, cap, "field 'energy_supplied' = %.17g differs from 'energy_total' = %.17g",
             row->energy_supplied, row->energy_total);
    return why;
  }
  for (int a = 0; a < 3; ++a) {
    if ((row->settled[a] == 1) != !isnan(row->settling_time[a])) {
      snprintf(why, cap, "field 'settling_time[%d]' = %.17g contradicts 'settled[%d]' = %d", a,
               row->settling_time[a], a, (int)row->settled[a]);
      return why;
    }
    exec = row->settled[a] ? fmax(exec, row->settling_time[a]) : NAN;
    if (isnan(exec)) break;
  }
  if (!(row->execution_time == exec || (isnan(exec) && isnan(row->execution_time)))) {
    snprintf(why, cap, "field 'execution_time' = %.17g is not the largest settling time (%.17g)",
             row->execution_time, exec);
    return why;
  }
  for (int a = 0; a < 3; ++a)
    if (row->stepinfo_unresolved[a] == 1 && !isnan(row->settling_time_final[a])) {
      snprintf(why, cap,
               "field 'settling_time_final[%d]' = %.17g contradicts 'stepinfo_unresolved[%d]' "
               "= 1",
               a, row->settling_time_final[a], a);
      return why;
    }
  if ((row->pointing_settled == 1) != !isnan(row->pointing_settling_time)) {
    snprintf(why, cap, "field 'pointing_settling_time' = %.17g contradicts 'pointing_settled' = %d",
             row->pointing_settling_time, (int)row->pointing_settled);
    return why;
  }
  return "";
}

int pom_doe_row_check_metrics(const pom_doe_row *row, char *why, size_t cap) {
  /* a failed maneuver's metrics stop where it failed (NaN or partial
   * integrals) and are not reduced: only its flags and counts are checked */
  int ok = row->status == POM_OK;
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    const pom_dyn_metric_info *mi = pom_dyn_metric(j);
    if (!ok && mi->unit != POM_DYN_UNIT_FLAG && mi->unit != POM_DYN_UNIT_COUNT) continue;
    for (int k = 0; k < mi->count; ++k) {
      double v = pom_doe_row_value(row, j, k);
      const char *bad = out_of_range(j, v);
      if (!bad[0]) continue;
      if (mi->count > 1)
        snprintf(why, cap, "field '%s[%d]' = %.17g %s", mi->name, k, v, bad);
      else
        snprintf(why, cap, "field '%s' = %.17g %s", mi->name, v, bad);
      return -1;
    }
  }
  if (ok && broken_identity(row, why, cap)[0]) return -1;
  return 0;
}
