/* cli_pipeline.h - what the user sees of the design pipeline: progress bars
 * of the synthesis and tuning phases, and the per-candidate table of
 * synthesized geometry and tuned gains (docs/optimize.md section 10). */
#ifndef POM_CLI_PIPELINE_H
#define POM_CLI_PIPELINE_H

#include "pom_run.h"
#include "pom_progress.h"

#include <stdio.h>

/* One progress bar per phase: a new phase label ends the previous bar. */
typedef struct {
  FILE *out;       /* NULL: no bars */
  char phase[128]; /* label of the open bar, "" when none */
  long done;       /* last count of the open bar */
  pom_progress bar;
} pom_cli_phases;

void pom_cli_phases_init(pom_cli_phases *p, FILE *out);

/* A pom_opt_progress_fn: user is a pom_cli_phases. */
void pom_cli_phases_report(void *user, const char *phase, long done, long total);

/* Ends the open bar. */
void pom_cli_phases_end(pom_cli_phases *p);

/* Writes the "Pipeline" section (Markdown) for the candidates the pipeline
 * synthesized or tuned: geometry, gains, criterion, the synthesis choice and
 * warnings, and where the files are. Nothing when no candidate went through
 * it. */
void pom_cli_pipeline_report(FILE *out, const pom_doe_study *study);

#endif
