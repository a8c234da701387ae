/* pom_opt_print.h - the optimizations' results as text and JSON: what
 * `pomlab synth` (a kinematic synthesis) and `pomlab tune` (a controller's
 * gains) print (docs/optimize.md). The caller chooses the stream. */
#ifndef POM_OPT_PRINT_H
#define POM_OPT_PRINT_H

#include "pom_synth.h"
#include "pom_tune.h"

#include <stdio.h>

/* One run: design, fits (ANOVA), optimum, confirmation, the direct search,
 * the scaling, and the files written (geo_path, h5_path). */
void pom_syn_report_text(FILE *out, const pom_syn_run *run, const char *geo_path,
                         const char *h5_path);

/* A warning line per fitted surface with a negative predicted R2 (every
 * refinement stage). */
void pom_syn_fit_warnings(FILE *out, const pom_syn_run *run);

/* The scaled geometries of n runs side by side. */
void pom_syn_compare_text(FILE *out, pom_syn_run *const runs[], int n);

/* n runs as one JSON object {"synth": [...]}; paths[c] = {geometry file, h5
 * file} of run c. Values in their config units. */
void pom_syn_report_json(FILE *out, pom_syn_run *const runs[], int n, char paths[][2][512]);

/* ---- tuning (tune_print.c) -------------------------------------------------------- */
/* One tuning: the protocol, the config's and the tuned gains with their
 * criteria, the search's cost, and the gains file written (path). */
void pom_tune_report_text(FILE *out, const pom_tune_problem *pb, const pom_tune_result *r,
                          const char *path);

/* n tunings as one JSON object {"tune": [...]} (SI); paths[c] is run c's
 * gains file. */
void pom_tune_report_json(FILE *out, const pom_tune_problem *pbs, const pom_tune_result *res, int n,
                          char paths[][512]);

#endif
