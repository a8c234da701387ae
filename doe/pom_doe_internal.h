/* pom_doe_internal.h - helpers shared by the files of doe/ (not public). */
#ifndef POM_DOE_INTERNAL_H
#define POM_DOE_INTERNAL_H

#include "pom_doe.h"

#include <libconfig.h>

/* ---- config trees (pom_doe_cfgtree.c) ---- */
/* Parses a libconfig file, @include resolved relative to the file. */
pom_status pom_doe_tree_read_file(config_t *tree, const char *path, pom_error *err);
/* Parses text; @include resolved relative to dir (NULL = current folder). */
pom_status pom_doe_tree_read_string(config_t *tree, const char *text, const char *name,
                                    const char *dir, pom_error *err);
/* Merges group src into group dst: groups recursively, everything else
 * replaced. `where` names src in messages. */
pom_status pom_doe_tree_merge(config_setting_t *dst, const config_setting_t *src, const char *where,
                              pom_error *err);
/* Sets the dotted key (groups created as needed) to a number; an existing
 * integer setting takes only integral values. */
pom_status pom_doe_tree_set_number(config_t *tree, const char *key, double value, pom_error *err);
/* Serializes a tree to libconfig text that reads back to identical values
 * (reals with round-trip precision). *text is malloc'ed. */
pom_status pom_doe_tree_write(const config_t *tree, char **text, pom_error *err);

/* ---- keys of a study (pom_doe_study.c) ---- */
/* A sweep factor or uncertain key (`what` = where the config gives it, e.g.
 * "uncertain.[0].key") must be "group.name": POM_ERR_CONFIG naming file,
 * line, what and the key otherwise. */
pom_status pom_doe_check_dotted(const pom_cfg *cfg, const char *what, const char *key,
                                pom_error *err);
/* The same, and its group must be one that candidate cand's evaluator reads
 * (pom_doe_evaluator_reads): a key the model never reads changes nothing. */
pom_status pom_doe_check_model_key(const pom_cfg *cfg, const char *what, const char *key,
                                   const pom_doe_candidate *cand, pom_error *err);

/* ---- results file (pom_doe_results.c) ---- */
typedef struct pom_doe_results pom_doe_results;
/* Takes PATH.lock (refused, nothing touched, while another run holds it),
 * then: with resume, opens PATH.partial (an unfinished run) or else PATH (a
 * finished one) when either exists, and checks that it holds this study;
 * otherwise creates PATH.partial with the provenance and empty rows (their
 * disk space reserved). A finished PATH is resumed from a copy in
 * PATH.partial: PATH itself is only ever replaced whole, by
 * pom_doe_results_end. A file made by a failed start is removed. */
pom_status pom_doe_results_start(pom_doe_results **out, const char *path,
                                 const pom_doe_study *study, int resume, pom_error *err);
/* The same for a file that only keeps the rows for a caller that writes its
 * own file at PATH (pom_doe_run_options.rows_only): resume considers
 * PATH.partial only. */
pom_status pom_doe_results_start_rows(pom_doe_results **out, const char *path,
                                      const pom_doe_study *study, int resume, pom_error *err);
/* 1 when start opened an existing file (its rows are to be loaded). */
int pom_doe_results_resumed(const pom_doe_results *res);
/* The file start opened (PATH.partial). */
const char *pom_doe_results_open_path(const pom_doe_results *res);
/* Checks a stored row of candidate c, maneuver k against the study: done is
 * 0 or 1, and a done row has a pomlab status, a reason only when it failed,
 * and the target maneuver k gives that candidate (bit for bit). Returns 0,
 * or -1 with the inconsistency written to why (cap bytes). */
int pom_doe_results_check_row(const pom_doe_study *study, int c, long k, const pom_doe_row *row,
                              char *why, size_t cap);
/* Writes rows [first, first + n) of candidate c. */
pom_status pom_doe_results_write_rows(pom_doe_results *res, int c, long first, long n,
                                      const pom_doe_row *rows, pom_error *err);
/* Reads rows [first, first + n) of candidate c. */
pom_status pom_doe_results_read(pom_doe_results *res, int c, long first, long n, pom_doe_row *rows,
                                pom_error *err);
pom_status pom_doe_results_flush(pom_doe_results *res, pom_error *err);
/* Ends the run's file (NULL allowed) and releases the lock. The rows file
 * PATH.partial is closed (its rows were flushed as they came) and from then
 * on only read: the report (statistics, comparisons, ranking) is written
 * into a copy, PATH.tmp.<pid>, which is synced and renamed over PATH when
 * complete (PATH.partial is then removed), else over PATH.partial. On any
 * failure nothing is renamed, PATH.partial keeps every finished row (resume
 * it) and err says so. Returns the first failure. */
pom_status pom_doe_results_end(pom_doe_results *res, const pom_doe_study *study,
                               const pom_doe_report *rep, int complete, pom_error *err);
/* Rows only: closes the rows file (its rows stay in PATH.partial) and keeps
 * res and its lock; pom_doe_results_drop_rows then removes PATH.partial once
 * the caller's own file is in place. pom_doe_results_close releases. */
pom_status pom_doe_results_close_rows(pom_doe_results *res, pom_error *err);
pom_status pom_doe_results_drop_rows(pom_doe_results *res, pom_error *err);
/* Closes (NULL allowed) without a report and releases the lock: an
 * unfinished file stays PATH.partial. */
pom_status pom_doe_results_close(pom_doe_results *res, pom_error *err);

/* Resume: records in the opened file that rows from here on come from this
 * program (last_resumed_utc, _version, _git_commit). Called once every stored
 * row passed its check, so a refused file is left as it was. */
pom_status pom_doe_results_mark_resumed(pom_doe_results *res, pom_error *err);

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

/* ---- uncertain parameters (pom_doe_uncertain.c) ---- */
/* Nominal values of the study's uncertain keys per candidate, and the check
 * that both ends of every distribution give a valid candidate (messages
 * name the study file cfg). */
pom_status pom_doe_uncertain_prepare(pom_doe_study *study, const pom_cfg *cfg, pom_error *err);
/* Writes /uncertain (keys, distributions, draws, nominal values). */
pom_status pom_doe_uncertain_write(hid_t file, const pom_doe_study *study, pom_error *err);
/* Resume: the file's /uncertain matches the study (or both have none). */
pom_status pom_doe_uncertain_check(hid_t file, const pom_doe_study *study, const char *path,
                                   pom_error *err);

/* ---- report (pom_doe_report.c) ---- */
/* Compact per-row values kept in memory for the statistics. */
typedef struct {
  int8_t done;     /* 1 when finished */
  int8_t ok;       /* status == POM_OK */
  int8_t settled;  /* every actuator settled */
  int8_t censored; /* ok, and the primary time metric did not settle */
  double time;     /* primary time metric (s); the horizon when censored; NaN when failed */
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
/* Report from cells[c * count + k] (c candidates, count maneuvers each). */
pom_status pom_doe_report_compute(pom_doe_report **out, const pom_doe_study *study,
                                  const pom_doe_cell *cells, pom_error *err);

/* ---- effects (pom_doe_effects.c) ---- */
/* Main effects of the sweep factors and the Pareto front into rep (after
 * the ranking's common-maneuver means are set). */
pom_status pom_doe_effects_compute(pom_doe_report *rep, const pom_doe_study *study,
                                   const pom_doe_cell *cells, pom_error *err);

#endif
