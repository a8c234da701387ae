/* pom_job.h - one owner of a study's steps and outputs: the sequence of a
 * study (tuning and synthesis, the earned fidelity, the runs, the report)
 * and every file it writes (results file, tabular files, summary.md and its
 * figures), checked before any work by one set of path rules, and the text
 * and JSON report. `pomlab study` / `pomlab montecarlo`, the flat C layer
 * (pom_api_study_run) and the Python module all call it (docs/results.md,
 * docs/api.md, docs/python.md).
 *
 * The job prints only to the streams its caller gives it (msg, out; NULL
 * prints nothing) and returns a status with the message in the pom_error,
 * so that the program shows what it always showed and a library caller gets
 * the same refusal as a status. */
#ifndef POM_JOB_H
#define POM_JOB_H

#include "pom_run.h"
#include "pom_explore.h"
#include "pom_progress.h"

#include <signal.h>
#include <stddef.h>
#include <stdio.h>

/* ---- output paths (docs/results.md, "Output paths") ------------------------------- */

/* The files a command reads and writes: no output may be the same file as
 * an input (the config, a file it includes, a candidate's config) or as
 * another output of the run. */
typedef struct pom_job_paths pom_job_paths;

/* An empty list for `command` (its name in messages, e.g. "study"); NULL when
 * out of memory. */
pom_job_paths *pom_job_paths_create(const char *command);

/* Frees; NULL is allowed. */
void pom_job_paths_destroy(pom_job_paths *p);

/* Adds a config file read by the command and every file it @includes (the
 * file is loaded to list them; one that cannot be loaded adds itself only).
 * `what` describes it in messages ("the config", "candidate 'A''s config"). */
void pom_job_paths_config(pom_job_paths *p, const char *path, const char *what);

/* Adds a file the command will write; `what` describes it in messages
 * ("the results file (--out)"). An empty path is ignored. */
void pom_job_paths_output(pom_job_paths *p, const char *path, const char *what);

/* Refuses an output that is the same file as an input or as another output:
 * the same device and inode where both exist, else the same resolved path
 * (symbolic links, "." and ".." followed as far as the path exists). Prints
 * "pomlab COMMAND: ..." on msg (NULL: nothing printed) and records the
 * message in err (may be NULL); returns 2 (POM_ERR_CONFIG in err) for such
 * an output, 1 (POM_ERR_NOMEM) when out of memory, 0 when every output is
 * distinct. */
int pom_job_paths_check(const pom_job_paths *p, FILE *msg, pom_error *err);

/* The check for a command of one config and one output (simulate --out,
 * tradeoff --csv, workspace --map): 0, or 2 / 1 as pom_job_paths_check
 * (printed on msg). A NULL or empty output passes. */
int pom_job_check_output(const char *command, const char *cfg_path, const char *output,
                         const char *what, FILE *msg, pom_error *err);

/* The rule of a tabular file name (--tabular or study.tabular, named by
 * `origin`): FILE.csv, a regular file, not ending in _candidates.csv (the
 * name of the second table, FILE_candidates.csv). Then creates its folder
 * (as --out does) and checks that it can be written there. Prints
 * "pomlab COMMAND: ..." on msg and returns 2 (POM_ERR_CONFIG in err) for a
 * name against the rule, 1 (POM_ERR_IO) for a folder that cannot be created
 * or written, 0 when fine. */
int pom_job_tabular_check(const char *command, const char *origin, const char *csv, FILE *msg,
                          pom_error *err);

/* mkdir -p of the folder part of path; 0 on success, else -1 with errno set
 * and the folder that failed in failed (capacity cap). */
int pom_job_make_parent(const char *path, char *failed, size_t cap);

/* ---- a study's job ----------------------------------------------------------------- */

/* What a caller asks of a study's job. Set every field after
 * pom_job_options_defaults. */
typedef struct {
  const char *command;     /* "study" or "montecarlo": messages and rules (default "study") */
  const char *cfg_path;    /* the config file, an input of the path rules; NULL = study->source */
  pom_doe_run_options run; /* threads, resume, output (NULL = study.output), stop_after, use_mpi */
  const char *tabular;     /* CSV tables of the results (NULL = study.tabular, "" = none) */
  const char *output_key;  /* how the caller named an explicit output in messages
                              (NULL = "--out") */
  const char *tabular_key; /* likewise for an explicit tabular file (NULL = "--tabular") */
  int pipeline;            /* 1: synthesis and tuning (run_in_study), then study.fidelity =
                              "auto", before the runs (a study file) */
  int json;                /* 1: the JSON report on out instead of the Markdown tables */
  int summary;             /* 1: write <output folder>/<stem>/summary.md */
  int plots;               /* 1: PNG figures with scripts/plot_study.py */
  int quiet;               /* 1: no progress bars and no announcement on msg */
  int rank;                /* MPI rank of this process: only rank 0 prints and writes files */
  int signals;             /* 1: SIGINT and SIGTERM stop the runs after the running maneuvers
                              (handlers installed during the runs only: the program) */
  const volatile sig_atomic_t *cancel; /* non-NULL: polled while the runs go; non-zero stops them
                                          after the running maneuvers (another thread sets it) */
  const char *scripts_dir; /* folder of plot_study.py; NULL = the source tree's scripts/ */
  double t_start;          /* pom_progress_now() when the caller's work began; 0 = when the job
                              begins. The reported wall time counts from it. */
  FILE *out;               /* the report (tables or JSON); NULL = none */
  FILE *msg;               /* progress bars, announcements, warnings and refusals; NULL = none */
} pom_job_options;

/* Defaults: command "study", no files beyond the study's own, no report, no
 * messages, summary and plots on, rank 0. */
void pom_job_options_defaults(pom_job_options *o);

/* What a job did. */
typedef struct {
  long done, total; /* candidate-maneuvers finished (this run and before) and planned */
  int interrupted;  /* 1: stopped by a signal or *cancel (the rest is resumable) */
  int threads;      /* worker threads used */
  int ranks;        /* MPI ranks used */
  double wall;      /* seconds since opts.t_start */
  char results[POM_DOE_PATH_LEN + 16]; /* the results file written: the output, or its
                                          .partial when unfinished ("" = none) */
  char summary[POM_DOE_PATH_LEN + 16]; /* summary.md written ("" = none) */
} pom_job_result;

/* The whole job of a loaded study: the path rules and the memory check
 * (pom_job_check), then with opts->pipeline the synthesis and tuning and the
 * earned fidelity (pom_job_prepare), the announcement of a long run, the
 * runs, the report on opts->out, the tabular files and summary.md with its
 * figures (pom_job_execute). res (may be NULL) receives what was done. The
 * status is the first failure; an interrupted job returns POM_OK with
 * res->interrupted set. */
pom_status pom_job_run(pom_doe_study *study, const pom_job_options *o, pom_job_result *res,
                       pom_error *err);

/* The checks before any work: no output may overwrite an input or another
 * output (results file, its .partial, summary.md, the two tables), the
 * tabular file's name rule and folder, and a study whose tables cannot fit
 * in this machine's memory is refused with the keys that size it. */
pom_status pom_job_check(const pom_doe_study *study, const pom_job_options *o, pom_error *err);

/* Synthesis and tuning of the candidates that ask for them (their files
 * beside the summary), then study.fidelity = "auto": each candidate's
 * setting, after its tuning (docs/results.md section 12). */
pom_status pom_job_prepare(pom_doe_study *study, const pom_job_options *o, pom_error *err);

/* Announces on msg, before the work, a run expected to last over 10 s or
 * to need over 1 GB of memory or of file: its runs, memory, file size and
 * time, the time per run measured on a few runs first (pom_doe_calibrate).
 * Nothing when quiet; a failed calibration only leaves the time out. */
void pom_job_announce(const pom_doe_study *study, const pom_job_options *o);

/* The runs (progress bar on msg, signals or *cancel honoured), then the
 * report on out, the tabular files, summary.md and its figures. */
pom_status pom_job_execute(const pom_doe_study *study, const pom_job_options *o,
                           pom_job_result *res, pom_error *err);

/* The program's exit code for a job's status and result: 0 done (or stopped
 * by stop_after), 130 interrupted, 2 a config or argument error (also a
 * refused output path), 1 any other failure. */
int pom_job_exit_code(pom_status st, const pom_job_result *res);

/* ---- the report ---------------------------------------------------------------------- */

/* Prints the tables, comparisons and verdict as Markdown. */
void pom_job_print_report(FILE *out, const pom_doe_study *study, const pom_doe_report *rep);

/* Prints the report as JSON (SI units), as `pomlab study --json`. */
void pom_job_print_json(FILE *out, const pom_doe_study *study, const pom_doe_report *rep);

/* Prints the fidelity each candidate earned (study.fidelity = "auto") as a
 * Markdown table with the validated bound beside the means (rep may be
 * NULL: no means); nothing otherwise. pom_job_fidelity.c. */
void pom_job_fidelity_report(FILE *out, const pom_doe_study *study, const pom_doe_report *rep);

/* Appends `, "fidelity": {...}` (setting, met, errors, bound) to a
 * candidate's JSON object when study.fidelity = "auto" chose its setting. */
void pom_job_fidelity_json(FILE *out, const pom_doe_candidate *cand);

/* Prints each candidate's capability figures (study.capability) and whether
 * it meets study.capability_require as a Markdown table; nothing when the
 * study asks for none. pom_job_capability.c. */
void pom_job_capability_report(FILE *out, const pom_doe_study *study);

/* Appends `, "capability": {name: value or null, ...}` (SI) and
 * `"capability_met"` (with requirements) to a candidate's JSON object when
 * the study asks for capability figures. */
void pom_job_capability_json(FILE *out, const pom_doe_study *study, const pom_doe_candidate *cand);

/* With study.capability_require: which candidates the ranking excluded and
 * by which requirement (the figure's value and the bound), or that every
 * one competes, or that none does and nothing is ranked. Nothing without
 * requirements. */
void pom_job_capability_exclusions(FILE *out, const pom_doe_study *study,
                                   const pom_doe_report *rep);

/* Appends `, "excluded": [{"name", "failed": [{"requirement", "figure",
 * "value", "bound", "op"}]}]` after the JSON report's ranking when the study
 * has requirements (an empty list when every candidate competes). */
void pom_job_capability_excluded_json(FILE *out, const pom_doe_study *study,
                                      const pom_doe_report *rep);

/* The main effects of the sweep factors on the asked capability figures
 * (mean over each level's candidates and their range) as a Markdown table;
 * nothing without factors or figures. */
void pom_job_capability_effects(FILE *out, const pom_doe_study *study, const pom_doe_report *rep);

/* Writes the "Pipeline" section (Markdown) for the candidates the pipeline
 * synthesized or tuned: geometry, gains, criterion, the synthesis choice and
 * warnings, and where the files are. Nothing when no candidate went through
 * it. pom_job_pipeline.c. */
void pom_job_pipeline_report(FILE *out, const pom_doe_study *study);

/* The folder of the summary and figures of results file `output`
 * (results/paper.h5 -> results/paper). */
void pom_job_summary_dir(char *dir, size_t cap, const char *output);

/* The actuator kind of the study's candidates (the first one's) and
 * *mixed = 1 when they do not all share it. */
pom_actuator_kind pom_job_study_kind(const pom_doe_study *study, int *mixed);

/* Runs /usr/bin/python3 DIR/NAME A1 A2 (DIR: scripts_dir, NULL = the source
 * tree's scripts/); returns its exit status, -1 when it could not run (said
 * on msg). */
int pom_job_run_script(const char *scripts_dir, const char *name, const char *a1, const char *a2,
                       FILE *msg);

/* "about 3.2 min" for a number of seconds (NaN: "unknown time"). */
const char *pom_job_duration_text(char *buf, size_t cap, double s);

/* "2.4 GB" for a number of bytes (powers of 1000). */
const char *pom_job_bytes_text(char *buf, size_t cap, double bytes);

/* ---- phases of the pipeline ------------------------------------------------------------ */

/* One progress bar per phase: a new phase label ends the previous bar. */
typedef struct {
  FILE *out;       /* NULL: no bars */
  char phase[128]; /* label of the open bar, "" when none */
  long done;       /* last count of the open bar */
  pom_progress bar;
} pom_job_phases;

void pom_job_phases_init(pom_job_phases *p, FILE *out);

/* A pom_opt_progress_fn: user is a pom_job_phases. */
void pom_job_phases_report(void *user, const char *phase, long done, long total);

/* Ends the open bar. */
void pom_job_phases_end(pom_job_phases *p);

/* ---- sensitivity --------------------------------------------------------------------------- */

/* The study's inputs as a list for `command`: the config at cfg_path, every
 * candidate's config and the files they include. NULL when out of memory;
 * the caller adds the outputs, checks (pom_job_paths_check) and destroys. */
pom_job_paths *pom_job_inputs(const char *command, const char *cfg_path,
                              const pom_doe_study *study);

/* Before a sensitivity analysis of study (sens loaded, its output set;
 * out_given: the output came from --out; plots: the figure will be made):
 * refuses an output that is the same file as an input or the other output
 * (exit 2), a run whose tables cannot fit in memory (exit 2, with the keys
 * that size it), and announces a long or large one unless quiet. Returns 0
 * when it may run, else the exit code (the message printed on msg, which
 * must not be NULL). */
int pom_job_sens_check(const char *cfg_path, const pom_doe_study *study, const pom_doe_sens *sens,
                       int out_given, int plots, int threads, int quiet, FILE *msg);

/* Prints on msg (not NULL) why each candidate of r has no indices; returns
 * how many have them (0: nothing is to be written). */
int pom_job_sens_failures(const pom_doe_study *study, const pom_doe_sens_result *r,
                          const char *output, FILE *msg);

/* What `pomlab sensitivity` asks of a sensitivity analysis's job. */
typedef struct {
  const char *cfg_path;    /* the study file (an input of the path rules) */
  const char *output;      /* results file given by the caller (--out); NULL = sensitivity.output */
  int json;                /* 1: the indices as JSON on out instead of tables */
  int plots;               /* 1: the bar plot beside the output (.png) */
  int quiet;               /* 1: no progress bar and no announcement */
  int threads;             /* worker threads; 0 = study.threads, then every core */
  int resume;              /* 1: continue OUTPUT.partial */
  long stop_after;         /* stop after this many more runs (0 = none) */
  const char *scripts_dir; /* folder of plot_sensitivity.py; NULL = the source tree's scripts/ */
  FILE *out;               /* the indices (not NULL) */
  FILE *msg;               /* progress, announcements, refusals and failures (not NULL) */
} pom_job_sens_options;

/* The job of a loaded sensitivity analysis (study and sens as loaded; the
 * earned fidelity is set here): checks, runs, indices, figure. Returns the
 * program's exit code: 0 done (or stopped by stop_after), 1 a runtime
 * failure or a candidate without indices (the indices of the others printed
 * all the same), 2 a config error or a refused output. pom_job_sens.c. */
int pom_job_sensitivity(pom_doe_study *study, pom_doe_sens *sens, const pom_job_sens_options *o);

#endif
