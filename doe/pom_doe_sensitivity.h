/* pom_doe_sensitivity.h - global sensitivity of a study's candidates to its
 * uncertain parameters: the `sensitivity` group, the design run through
 * the batch runner (threads), the indices and their results file
 * (docs/results.md, section 11). */
#ifndef POM_DOE_SENSITIVITY_H
#define POM_DOE_SENSITIVITY_H

#include "pom_doe.h"
#include "pom_sensitivity.h"

typedef enum { POM_DOE_SENS_SOBOL = 0, POM_DOE_SENS_MORRIS = 1 } pom_doe_sens_method;

/* The `sensitivity` group. */
typedef struct {
  pom_doe_sens_method method;
  pom_sens_sobol_opts sobol;     /* method sobol (dim = the uncertain parameters) */
  pom_sens_morris_opts morris;   /* method morris */
  int stat;                      /* the output: statistic pom_dyn_stat_id of each run */
  long per_sample;               /* maneuvers 0..per_sample-1 per design point; y = their mean */
  char output[POM_DOE_PATH_LEN]; /* results file */
} pom_doe_sens;

/* The config group pom_doe_sens_load reads (`sensitivity`, in a study file),
 * NULL-terminated, static storage. */
const char *const *pom_doe_sens_groups(void);

/* Reads the `sensitivity` group of a study file whose study (with an
 * `uncertain` group) is loaded; unknown keys in the group are errors. */
pom_status pom_doe_sens_load(pom_doe_sens *s, const pom_cfg *cfg, const pom_doe_study *study,
                             pom_error *err);

/* Per candidate: the outputs and the indices. */
typedef struct {
  long rows; /* design points */
  int dim;   /* inputs (the uncertain parameters) */
  double *u; /* [rows][dim] design in (0, 1) */
  double *x; /* [rows][dim] the values drawn (config units, or factors when relative) */
  double *y; /* [n_candidates][rows] outputs (SI) */
  int n_candidates;
  pom_sens_sobol_result *sobol;   /* [n_candidates] (method sobol) */
  pom_sens_morris_result *morris; /* [n_candidates] (method morris) */
  pom_status *status;             /* [n_candidates] of the index computation */
  char (*reason)[256];            /* [n_candidates] why, when status != OK */
  double wall;                    /* s */
  int threads;
} pom_doe_sens_result;

void pom_doe_sens_result_destroy(pom_doe_sens_result *r);

/* Progress callback: units done of total. */
typedef void (*pom_doe_sens_progress)(long done, long total, void *user);

/* How pom_doe_sens_run runs. */
typedef struct {
  int threads;                    /* worker threads; 0 = the study's */
  const char *output;             /* the results file; NULL or "" = none */
  int resume;                     /* 1: continue OUTPUT.partial of an interrupted run */
  long stop_after;                /* stop after this many new runs (0 = run them all) */
  pom_doe_sens_progress progress; /* NULL = none */
  void *user;                     /* for progress */
  volatile int *cancel;           /* polled when not NULL: set, the run stops */
} pom_doe_sens_run_opts;

void pom_doe_sens_run_opts_defaults(pom_doe_sens_run_opts *o);

/* Runs the design on every candidate of study (changed during the call:
 * its uncertain draws come from the design; restored before return),
 * computes the indices and writes the results file. The output is taken
 * before the first run, as `pomlab study` takes its own (docs/results.md
 * "Writing safely"): OUTPUT.lock held for the whole call, every run's row
 * kept in OUTPUT.partial as it finishes (its disk space reserved up front;
 * a resume continues it), OUTPUT written under a temporary name and renamed
 * when complete, then OUTPUT.partial removed. A stopped or cancelled run
 * returns POM_ERR_INTERRUPTED (its rows stay in OUTPUT.partial). *out is
 * set whenever the indices were computed, also when writing the file
 * failed afterwards (the status and err say why; the rows stay in
 * OUTPUT.partial, and a resume writes the file without running again). */
pom_status pom_doe_sens_run(pom_doe_sens_result **out, pom_doe_study *study, const pom_doe_sens *s,
                            const pom_doe_sens_run_opts *o, pom_error *err);

/* Writes the results file: to a temporary name beside path, synced and
 * renamed over path only when complete (the folder synced after). */
pom_status pom_doe_sens_write(const char *path, const pom_doe_study *study, const pom_doe_sens *s,
                              const pom_doe_sens_result *r, pom_error *err);

#endif
