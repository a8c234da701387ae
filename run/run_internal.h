/* run_internal.h - the results file as the runner uses it (not public). */
#ifndef POM_RUN_INTERNAL_H
#define POM_RUN_INTERNAL_H

#include "pom_run.h"

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

#endif
