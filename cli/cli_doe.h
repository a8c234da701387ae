/* cli_doe.h - what `pomlab study` and `pomlab montecarlo` share: running a
 * study with a progress bar and Ctrl-C handling, the paper's tables, the
 * verdict, summary.md and the figures. */
#ifndef POM_CLI_DOE_H
#define POM_CLI_DOE_H

#include "cli_outputs.h"
#include "pom_run.h"
#include "pom_explore.h"

#include <stdio.h>

typedef struct {
  pom_doe_run_options run; /* threads, resume, output, stop_after, use_mpi */
  int json;                /* 1: JSON report on stdout instead of tables */
  int summary;             /* 1: write <output folder>/<stem>/summary.md */
  int plots;               /* 1: PNG figures with scripts/plot_study.py */
  int quiet;               /* 1: no progress bar */
  const char *tabular;     /* CSV tables of the results (NULL = study.tabular, "" = none) */
  double t_start;          /* pom_progress_now() when the command's work began (the pipeline);
                              0 = when the run begins. The reported wall time counts from it. */
  /* Extra Markdown section after the candidates (stdout and summary.md); may be NULL. */
  void (*report_extra)(FILE *out, const pom_doe_study *study);
} pom_cli_doe_opts;

/* Runs the study and reports; returns the exit code (0 ok, 1 failure,
 * 130 interrupted). Only the root rank prints. */
int pom_cli_doe_execute(const pom_doe_study *study, const pom_cli_doe_opts *o);

/* The study's inputs as a list for `command`: the config at cfg_path, every
 * candidate's config and the files they include. NULL when out of memory;
 * the caller adds the outputs, checks (pom_cli_paths_check) and destroys. */
pom_cli_paths *pom_cli_doe_inputs(const char *command, const char *cfg_path,
                                  const pom_doe_study *study);

/* Checks a study's or Monte-Carlo run's output paths before any work: the
 * tabular file's name rule and folder (pom_cli_tabular_check), and that no
 * output (results file, its .partial, summary.md, the two tables) is an
 * input or another output. Returns 0, else the exit code; prints only when
 * `report` (the root rank). */
int pom_cli_doe_check_paths(const char *command, const char *cfg_path, const pom_doe_study *study,
                            const pom_cli_doe_opts *o, int report);

/* Refuses a run whose tables cannot fit in this machine's memory: exit 2
 * (a config error) with the size needed, the number of runs and the keys
 * that set them, before any work; 0 when it fits. Prints only when
 * `report`. */
int pom_cli_doe_check_memory(const char *command, const pom_doe_study *study,
                             const pom_cli_doe_opts *o, int report);

/* Announces on stderr, before the work, a run expected to last over 10 s or
 * to need over 1 GB of memory or of file: its runs, memory, file size and
 * time, the time per run measured on a few runs first (pom_doe_calibrate).
 * Nothing when quiet; a failed calibration only leaves the time out. */
void pom_cli_doe_announce(const char *command, const pom_doe_study *study,
                          const pom_cli_doe_opts *o);

/* Before a sensitivity analysis of study (sens loaded, its output set;
 * out_given: the output came from --out; plots: the figure will be made):
 * refuses an output that is the same file as an input or the other output
 * (exit 2), a run whose tables cannot fit in memory (exit 2, with the keys
 * that size it), and announces a long or large one unless quiet. Returns 0
 * when it may run, else the exit code (the message printed). */
int pom_cli_doe_sens_check(const char *cfg_path, const pom_doe_study *study,
                           const pom_doe_sens *sens, int out_given, int plots, int threads,
                           int quiet);

/* Prints on stderr why each candidate of r has no indices; returns how many
 * have them (0: nothing is to be written). */
int pom_cli_doe_sens_failures(const pom_doe_study *study, const pom_doe_sens_result *r,
                              const char *output);

/* Prints the tables, comparisons and verdict as Markdown. */
void pom_cli_doe_print_report(FILE *out, const pom_doe_study *study, const pom_doe_report *rep);

/* Prints the fidelity each candidate earned (study.fidelity = "auto") as a
 * Markdown table with the validated bound beside the means (rep may be
 * NULL: no means); nothing otherwise. cli_fidelity.c. */
void pom_cli_doe_fidelity_report(FILE *out, const pom_doe_study *study, const pom_doe_report *rep);

/* Appends `, "fidelity": {...}` (setting, met, errors, bound) to a
 * candidate's JSON object when study.fidelity = "auto" chose its setting. */
void pom_cli_doe_fidelity_json(FILE *out, const pom_doe_candidate *cand);

/* Prints the report as JSON (SI units). */
void pom_cli_doe_print_json(FILE *out, const pom_doe_study *study, const pom_doe_report *rep);

/* The folder of the summary and figures of results file `output`
 * (results/paper.h5 -> results/paper). */
void pom_cli_doe_summary_dir(char *dir, size_t cap, const char *output);

/* The actuator kind of the study's candidates (the first one's) and
 * *mixed = 1 when they do not all share it. */
pom_actuator_kind pom_cli_doe_study_kind(const pom_doe_study *study, int *mixed);

/* Runs /usr/bin/python3 scripts/NAME A1 A2 (the source tree's scripts);
 * returns its exit status, -1 when it could not run. */
int pom_cli_run_script(const char *name, const char *a1, const char *a2);

#endif
