/* pom_syn_print.h - a kinematic synthesis as text and JSON: what `pomlab
 * synth` prints (docs/optimize.md). The caller chooses the stream. */
#ifndef POM_SYN_PRINT_H
#define POM_SYN_PRINT_H

#include "pom_synth.h"

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

#endif
