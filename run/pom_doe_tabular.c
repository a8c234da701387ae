/* pom_doe_tabular.c - a study's results as plain CSV tables, in the manner of
 * Dakota's tabular data (docs/results.md, "Tabular results"): one row per
 * candidate x maneuver, one row per candidate. The maneuver rows are read
 * back from the results file a block at a time, so memory does not grow
 * with the number of maneuvers. */
#define _POSIX_C_SOURCE 200809L
#include "pom_run.h"
#include "pom_io.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define READ_BLOCK 256 /* maneuver rows read at a time */

/* ---- per-maneuver columns beside the metrics ------------------------------------ */
/* A column of the maneuver table that is not a metric of the schema: a
 * property of maneuver k (its drawn values) or of the candidate's row.
 * Columns are written in table order, between `maneuver` and the metrics;
 * `applies` says whether the study has it (NULL = always). Add a line to
 * add a column. */
typedef struct {
  const char *name; /* CSV header (name_unit) */
  int (*applies)(const pom_doe_study *study);
  double (*value)(const pom_doe_study *study, int c, const pom_doe_maneuver *mv,
                  const pom_doe_row *row);
} tabular_column;

static int orientation_space(const pom_doe_study *study) {
  return study->maneuvers.space == POM_DOE_SPACE_ORIENTATION;
}

static double tilt_azimuth(const pom_doe_study *s, int c, const pom_doe_maneuver *mv,
                           const pom_doe_row *row) {
  (void)s, (void)c, (void)row;
  return mv->orient[0];
}
static double tilt(const pom_doe_study *s, int c, const pom_doe_maneuver *mv,
                   const pom_doe_row *row) {
  (void)s, (void)c, (void)row;
  return mv->orient[1];
}
static double torsion(const pom_doe_study *s, int c, const pom_doe_maneuver *mv,
                      const pom_doe_row *row) {
  (void)s, (void)c, (void)row;
  return mv->orient[2];
}

static const tabular_column maneuver_columns[] = {
    {.name = "tilt_azimuth_rad", .applies = orientation_space, .value = tilt_azimuth},
    {.name = "tilt_rad", .applies = orientation_space, .value = tilt},
    {.name = "torsion_rad", .applies = orientation_space, .value = torsion},
};
#define N_MANEUVER_COLUMNS ((int)(sizeof maneuver_columns / sizeof maneuver_columns[0]))

/* ---- CSV helpers ------------------------------------------------------------------ */
/* A text field, always quoted ("" inside). */
static void csv_text(FILE *f, const char *s) {
  fputc('"', f);
  for (; *s; ++s) {
    if (*s == '"') fputc('"', f);
    fputc(*s, f);
  }
  fputc('"', f);
}

/* A number with round-trip precision; NaN and infinities as pandas and
 * MATLAB read them. */
static void csv_number(FILE *f, double v) {
  if (isnan(v))
    fputs(",NaN", f);
  else if (isinf(v))
    fputs(v > 0 ? ",Inf" : ",-Inf", f);
  else
    fprintf(f, ",%.17g", v);
}

/* Header of a metric's value k: name[_actuator][_unit], the unit as in
 * `pomlab simulate --json` (none for actuator coordinates, counts, flags,
 * ratios: see the actuator_unit column). */
static void metric_header(FILE *f, const pom_dyn_metric_info *mi, int k) {
  char key[128];
  pom_dyn_metric_json_key(mi, key, sizeof key);
  const char *unit = strncmp(key, mi->name, strlen(mi->name)) == 0 ? key + strlen(mi->name) : "";
  if (mi->count == 3)
    fprintf(f, ",%s_%d%s", mi->name, k + 1, unit);
  else
    fprintf(f, ",%s%s", mi->name, unit);
}

/* The leading columns shared by both tables: candidate, its index, factors. */
static void lead_header(FILE *f, const pom_doe_study *study) {
  fputs("candidate,candidate_index", f);
  for (int j = 0; j < study->n_factors; ++j)
    fprintf(f, ",%s", study->factor_key[j]);
}

static void lead_values(FILE *f, const pom_doe_study *study, int c) {
  const pom_doe_candidate *cand = &study->candidates[c];
  csv_text(f, cand->name);
  fprintf(f, ",%d", c);
  for (int j = 0; j < study->n_factors; ++j)
    csv_number(f, j < cand->n_factors ? cand->factor_value[j] : NAN);
}

/* ---- the two tables ------------------------------------------------------------------ */
static pom_status write_maneuvers(FILE *f, const pom_doe_study *study, const char *results,
                                  pom_doe_row *block, pom_error *err) {
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  lead_header(f, study);
  fputs(",maneuver", f);
  for (int j = 0; j < N_MANEUVER_COLUMNS; ++j)
    if (!maneuver_columns[j].applies || maneuver_columns[j].applies(study))
      fprintf(f, ",%s", maneuver_columns[j].name);
  for (int j = 0; j < study->uncertain.n; ++j)
    fprintf(f, ",drawn:%s", study->uncertain.param[j].key);
  fputs(",actuator_unit", f);
  for (int j = 0; j < POM_DYN_N_METRICS; ++j)
    for (int k = 0; k < schema[j].count; ++k)
      metric_header(f, &schema[j], k);
  fputs(",status,reason\n", f);
  long m = study->maneuvers.count;
  for (int c = 0; c < study->n_candidates; ++c) {
    const char *unit = pom_act_kind_desc(study->candidates[c].eval.actuator_kind)->si;
    for (long k0 = 0; k0 < m; k0 += READ_BLOCK) {
      long n = m - k0 < READ_BLOCK ? m - k0 : READ_BLOCK;
      POM_TRY(pom_doe_results_read_rows(results, c, k0, n, block, err));
      for (long i = 0; i < n; ++i) {
        const pom_doe_row *row = &block[i];
        if (!row->done) continue; /* an interrupted study: only what finished */
        pom_doe_maneuver mv;
        pom_doe_maneuver_draw(&mv, &study->maneuvers, k0 + i);
        lead_values(f, study, c);
        fprintf(f, ",%ld", k0 + i);
        for (int j = 0; j < N_MANEUVER_COLUMNS; ++j)
          if (!maneuver_columns[j].applies || maneuver_columns[j].applies(study))
            csv_number(f, maneuver_columns[j].value(study, c, &mv, row));
        /* the values this candidate ran with (docs/results.md section 10) */
        double x[POM_UNC_MAX];
        pom_unc_draws(&study->uncertain, k0 + i, x);
        for (int j = 0; j < study->uncertain.n; ++j)
          csv_number(f, study->uncertain.param[j].relative
                            ? x[j] * study->uncertain_nominal[c * study->uncertain.n + j]
                            : x[j]);
        fprintf(f, ",%s", unit);
        for (int j = 0; j < POM_DYN_N_METRICS; ++j)
          for (int k = 0; k < schema[j].count; ++k)
            csv_number(f, pom_doe_row_value(row, j, k));
        fprintf(f, ",%d,", (int)row->status);
        csv_text(f, row->reason);
        fputc('\n', f);
      }
    }
  }
  return POM_OK;
}

static void write_candidates(FILE *f, const pom_doe_study *study, const pom_doe_report *rep) {
  static const char *const fields[POM_DOE_STATS_FIELDS] = {"n",      "max", "mean", "min", "sigma",
                                                           "median", "p05", "p25",  "p75", "p95"};
  lead_header(f, study);
  fputs(",actuator_unit,done,ok,failed,unsettled,censored", f);
  for (int s = 0; s < POM_DYN_N_STATS; ++s)
    for (int j = 0; j < POM_DOE_STATS_FIELDS; ++j)
      fprintf(f, ",%s_%s", pom_dyn_stat_metric(s)->stat_key, fields[j]);
  /* study.capability: one column per figure asked (SI), then whether the
     requirements hold */
  for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
    if (study->capability_want[i]) fprintf(f, ",capability_%s", pom_cap_figure_name(i));
  if (study->n_requirements > 0) fputs(",capability_met", f);
  fputc('\n', f);
  for (int c = 0; c < study->n_candidates; ++c) {
    const pom_doe_candidate_stats *cs = &rep->cand[c];
    lead_values(f, study, c);
    fprintf(f, ",%s,%ld,%ld,%ld,%ld,%ld",
            pom_act_kind_desc(study->candidates[c].eval.actuator_kind)->si, cs->n_done,
            cs->n_done - cs->n_failed, cs->n_failed, cs->n_unsettled, cs->n_censored);
    for (int s = 0; s < POM_DYN_N_STATS; ++s) {
      double v[POM_DOE_STATS_FIELDS];
      pom_doe_stats_flatten(v, &cs->stat[s]);
      for (int j = 0; j < POM_DOE_STATS_FIELDS; ++j)
        csv_number(f, v[j]);
    }
    const pom_doe_candidate *cand = &study->candidates[c];
    for (int i = 0; i < POM_CAP_N_FIGURES; ++i)
      if (study->capability_want[i])
        csv_number(f, cand->capability_done ? cand->capability[i] : NAN);
    if (study->n_requirements > 0)
      fprintf(f, ",%s", cand->capability_done ? (cand->capability_met ? "1" : "0") : "");
    fputc('\n', f);
  }
}

/* ---- files ------------------------------------------------------------------------- */
void pom_doe_tabular_candidates_path(char *out, size_t cap, const char *csv) {
  size_t n = strlen(csv);
  if (n > 4 && strcmp(csv + n - 4, ".csv") == 0)
    snprintf(out, cap, "%.*s_candidates.csv", (int)(n - 4), csv);
  else
    snprintf(out, cap, "%s_candidates.csv", csv);
}

pom_status pom_doe_tabular_write(const pom_doe_study *study, const pom_doe_report *rep,
                                 const char *results, const char *csv, pom_error *err) {
  pom_status st = POM_OK;
  char cand_path[POM_DOE_PATH_LEN + 32];
  pom_io_file w[2];
  memset(w, 0, sizeof w);
  pom_doe_row *block = NULL;
  if (!results || !results[0])
    POM_FAIL(err, POM_ERR_ARG,
             "tabular results '%s' need a results file (the maneuver rows are read back from it)",
             csv);
  pom_doe_tabular_candidates_path(cand_path, sizeof cand_path, csv);
  block = malloc(READ_BLOCK * sizeof *block);
  if (!block) POM_FAIL(err, POM_ERR_NOMEM, "tabular: out of memory");
  /* both tables are written beside their names (core/pom_io.h) and renamed
   * once both are complete, so a failure leaves no half-written table */
  st = pom_io_create(&w[0], csv, err);
  if (st == POM_OK) st = pom_io_create(&w[1], cand_path, err);
  if (st == POM_OK) st = write_maneuvers(w[0].f, study, results, block, err);
  if (st == POM_OK) write_candidates(w[1].f, study, rep);
  /* both complete before either is renamed: never a new table beside an old one */
  if (st == POM_OK) st = pom_io_commit_all(w, 2, err);
  pom_io_abort(&w[0]);
  pom_io_abort(&w[1]);
  free(block);
  return st;
}
