/* pom_api.h - a flat entry layer over the pomlab modules for bindings
 * (python/pomlab, through ctypes) and small programs: opaque handles, plain
 * arrays of doubles in SI units, and the module's pom_error for failures
 * (docs/api.md section 3).
 *
 * Everything here composes the public module calls (pom_config.h,
 * pom_kinematics.h, pom_dynamics.h, pom_run.h, pom_pipeline.h) the way the
 * `pomlab` commands do, without printing and without a process exit. No
 * function keeps state between calls: handles are owned by the caller, one
 * handle per thread. */
#ifndef POM_API_H
#define POM_API_H

#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_status.h"

#include <stddef.h>

/* Version of the library ("0.1.0") and the git commit it was built from;
 * static strings. */
const char *pom_api_version(void);
const char *pom_api_git_commit(void);

/* Makes the third-party libraries report instead of ending or printing:
 * GSL's default error handler (which aborts the process) off, HDF5's
 * automatic error printing off (pom_h5_quiet). Process-wide settings of
 * those libraries, idempotent; call it once before the first call from a
 * host that must survive any failure (the Python module does at import). */
void pom_api_quiet_handlers(void);

/* Size in bytes of the public struct called `name` ("pom_error",
 * "pom_kin_pose", "pom_kin_fk_info", "pom_kin_ws_result",
 * "pom_api_study_opts"); 0 for any other name. Bindings that mirror a struct
 * compare its size with this before using it. */
size_t pom_api_struct_size(const char *name);

/* ---- the NULL rule ----------------------------------------------------------- *
 * Every function of this header (and the pom_cfg_* calls of docs/api.md
 * section 3 that a binding uses) takes NULL in any pointer argument without
 * crashing: a NULL that stands for an object or an input (a handle, a
 * config, a key, a path, a text, an array to fill) is refused, with
 * POM_ERR_ARG and err's message when the function returns a pom_status,
 * else with its "nothing" value (NULL for a pointer, 0 for a count or a
 * size, NaN for a number, no effect for a void function); an output its
 * comment calls optional may be NULL, and `err` always may
 * (docs/api.md section 2; tests/test_api_null.c calls every function so). */

/* ---- checks shared with the program ------------------------------------------- */

/* Largest worker-thread count (the range of study.threads and of the
 * program's --threads). */
#define POM_API_THREADS_MAX 1024

/* Every top-level config name any pomlab command understands, assembled
 * from the lists the libraries export (pom_kin_model_groups(),
 * pom_dyn_param_groups(), pom_doe_study_groups(), ...) into g. */
pom_status pom_api_known_groups(pom_cfg_groups *g, pom_error *err);

/* The unknown-key check of a command: unknown keys under the groups of
 * `scopes` (a NULL-terminated array of the libraries' NULL-terminated group
 * lists: the groups the command reads), any top-level name no command
 * understands (pom_api_known_groups), then every override (pom_cfg_set_*)
 * that nobody read (pom_cfg_check_overrides; those under the top-level
 * names of `later`, NULL = none, are left to a later call that reads them).
 * Call it once the command's readers have run. */
pom_status pom_api_check_keys(const pom_cfg *cfg, const char *const *const scopes[],
                              const char *const *later, pom_error *err);

/* A worker-thread count: 0 (the study's study.threads, else every core) or
 * 1..POM_API_THREADS_MAX; POM_ERR_ARG naming `origin` (e.g. "--threads";
 * NULL = "threads") and the value otherwise. */
pom_status pom_api_check_threads(long threads, const char *origin, pom_error *err);

/* ---- registries ------------------------------------------------------------ */

/* Registers the architecture files (docs/architecture-files.md section 4:
 * the shipped catalog and $POMLAB_ARCHITECTURES) once per process; later
 * calls do nothing. pom_api_arch_create, pom_api_sim_create and the study
 * runs call it themselves, and pom_api_arch_type_info(0, ...) too; call it
 * first, before any thread, to see a broken file's message at once (err
 * may be NULL). Not thread-safe on its first call. */
pom_status pom_api_register_architecture_files(pom_error *err);

/* Registered architecture k (0-based, pom_kin_arch_type_at): its config name
 * ("3PSS"), label ("3P-S-S/S") and actuator kind ("prismatic" or "revolute") into
 * the pointers (static strings; any may be NULL). POM_ERR_ARG when k is out
 * of range. */
pom_status pom_api_arch_type_info(int k, const char **name, const char **label,
                                  const char **actuator_kind);

/* Registered controller type k (pom_dyn_ctrl_type_at): its `controller.type`
 * value ("pid"), label and one-line description (static strings; any may be
 * NULL). POM_ERR_ARG when k is out of range. */
pom_status pom_api_ctrl_type_info(int k, const char **name, const char **label,
                                  const char **description);

/* ---- kinematics ------------------------------------------------------------ */

/* Loads the architecture of cfg (pom_kin_arch_load) into a new heap copy the
 * caller frees with pom_api_arch_destroy. Unknown keys in the groups the
 * kinematics reads (name, architecture, geometry, limits), unknown top-level
 * names and overrides nobody read are errors, as in `pomlab ik`
 * (pom_api_check_keys; the overrides of the `workspace` group are left to
 * pom_api_workspace). */
pom_status pom_api_arch_create(pom_kin_arch **out, const pom_cfg *cfg, pom_error *err);

/* Frees an architecture from pom_api_arch_create; NULL allowed. */
void pom_api_arch_destroy(pom_kin_arch *arch);

/* The SI unit of the actuator coordinate of arch ("m" or "rad"), and the
 * factor from it to the display unit of the commands (1000 for mm, 180/pi for
 * deg) when to_display is not NULL. Static string. */
const char *pom_api_arch_actuator_unit(const pom_kin_arch *arch, double *to_display);

/* The JSON key of limit kind `kind` (1..3) of arch's type (as in `pomlab ik
 * --json`) and the factor from SI to the unit that JSON uses (to_display may
 * be NULL); NULL when the type has no such limit. */
const char *pom_api_arch_limit_key(const pom_kin_arch *arch, int kind, double *to_display);

/* The regular dexterous workspace and global conditioning index as `pomlab
 * workspace` computes them: the `workspace` group of cfg over the defaults,
 * then pom_kin_workspace into *res and pom_kin_gci over the cube of
 * workspace.gci_half_width_deg (0 = the workspace found). out[0] = GCI,
 * out[1] = usable measure fraction, out[2] = the GCI cube's half-width (rad).
 * POM_ERR_UNREACHABLE when the home pose itself fails. */
pom_status pom_api_workspace(const pom_kin_arch *arch, const pom_cfg *cfg, pom_kin_ws_result *res,
                             double out[3], pom_error *err);

/* ---- one maneuver ----------------------------------------------------------- */

/* A mechanism ready to simulate: architecture, mechanism, dynamics
 * parameters, model and data (and traces when asked), built once from a
 * config. One per thread. */
typedef struct pom_api_sim pom_api_sim;

/* Builds the simulation of cfg as `pomlab simulate` does (unknown keys in the
 * groups it reads, unknown top-level names and overrides it does not read,
 * such as montecarlo.* or workspace.*, are errors: pom_api_check_keys). traces = 1 also allocates
 * the traces of every run. The caller frees *out with pom_api_sim_destroy. */
pom_status pom_api_sim_create(pom_api_sim **out, const pom_cfg *cfg, int traces, pom_error *err);

/* Frees a simulation; NULL allowed. */
void pom_api_sim_destroy(pom_api_sim *sim);

/* Runs one maneuver from rest at mid-stroke to target (SI: m or rad per
 * actuator). POM_ERR_ARG (nothing run) when a target lies outside the
 * stroke. A numerical failure is returned and also kept with the metrics
 * (pom_api_sim_status); the metrics and traces of the run stay readable
 * either way. */
pom_status pom_api_sim_run(pom_api_sim *sim, const double target[3], pom_error *err);

/* Name of the mechanism (config `name`), half the stroke (SI), and the status
 * and reason of the last run (reason "" when it succeeded, and may be NULL);
 * static or owned by sim. For a NULL sim: NULL, NaN, and POM_ERR_ARG. */
const char *pom_api_sim_name(const pom_api_sim *sim);
double pom_api_sim_half_stroke(const pom_api_sim *sim);
pom_status pom_api_sim_status(const pom_api_sim *sim, const char **reason);

/* Number of metrics of the schema (pom_dyn_metrics_schema.h), the JSON key
 * of metric j ("execution_time_s") into buf, its width (1 or 3) and whether
 * it is a count or a flag (1) rather than a real (0). Key NULL and width 0
 * when j is out of range. */
int pom_api_metric_count(void);
const char *pom_api_metric_key(int j, char *buf, size_t cap);
int pom_api_metric_width(int j);
int pom_api_metric_is_integer(int j);

/* Values of metric j after the last run into v (width doubles, SI; NaN when
 * undefined). Returns the width, 0 for a bad j. */
int pom_api_sim_metric(const pom_api_sim *sim, int j, double v[3]);

/* Samples in the traces of the last run (0 without traces), and the column
 * `name` of them ("t", "q", "q_dot", "current", "voltage", "energy",
 * "euler_zyx", "quat", "deflection"): row-major [samples][*width], owned by
 * sim and valid until its next run. NULL for an unknown name or without
 * traces. */
int pom_api_sim_samples(const pom_api_sim *sim);
const double *pom_api_sim_trace(const pom_api_sim *sim, const char *name, int *width);

/* ---- Monte-Carlo runs and studies ------------------------------------------------ */

/* Options of pom_api_study_run. */
typedef struct {
  int montecarlo;      /* 1: cfg describes one mechanism (`pomlab montecarlo`); 0: a study file */
  int threads;         /* worker threads, 0..POM_API_THREADS_MAX; 0 = study.threads, else every
                          core */
  int resume;          /* 1: continue an interrupted results file of the same study */
  const char *output;  /* HDF5 results file to write (required) */
  const char *tabular; /* CSV of the rows, one per candidate x maneuver, and its
                          _candidates.csv (NULL or "" = none) */
  int summary;         /* 1: summary.md in the folder of output without .h5, as the program */
  int plots;           /* 1: its figures too (scripts/plot_study.py; /usr/bin/python3 with h5py
                          and matplotlib) */
  const volatile int *cancel; /* NULL, or a flag another thread may set to non-zero: the runs
                                 stop after the running maneuvers, the finished ones stay in
                                 output.partial (resume = 1 continues), POM_ERR_INTERRUPTED */
} pom_api_study_opts;

/* Defaults: a study, every core, no resume, no files, no summary, no cancel. */
void pom_api_study_defaults(pom_api_study_opts *o);

/* Runs a Monte-Carlo run or a whole study through the same job as `pomlab
 * study` / `pomlab montecarlo` (job/pom_job.h): the output-path rules first
 * (no output may be an input, such as the config or a file it includes, or
 * another output: POM_ERR_CONFIG naming both paths, nothing written), then
 * for a study file synthesis and tuning when candidates ask for them (their
 * files in the folder of `output` without .h5) and study.fidelity = "auto",
 * the runs into the results file, the tabular files and, when asked,
 * summary.md with its figures (docs/results.md). *done and *total (may be
 * NULL) receive the candidate-maneuvers finished and planned. Stopped by
 * *cancel: POM_ERR_INTERRUPTED, the results kept in output.partial. */
pom_status pom_api_study_run(const pom_cfg *cfg, const pom_api_study_opts *o, long *done,
                             long *total, pom_error *err);

/* pom_api_study_run, and *json (may be NULL) receives the report as
 * `pomlab study --json` prints it (malloc'd: release with pom_api_free;
 * NULL when the run failed or was interrupted). */
pom_status pom_api_study_run_json(const pom_cfg *cfg, const pom_api_study_opts *o, long *done,
                                  long *total, char **json, pom_error *err);

/* Design gradients (study/pom_grad.h, docs/optimize.md section 12) of the
 * Monte-Carlo maneuvers of a single-mechanism config with joints.model =
 * "rigid": keys[n] its numeric design keys, maneuvers the count (0 = the
 * config's montecarlo.maneuvers); *json (malloc'd: pom_api_free) receives
 * what `pomlab gradient --json` prints. */
pom_status pom_api_gradient_json(const pom_cfg *cfg, const char *const *keys, int n, long maneuvers,
                                 char **json, pom_error *err);

/* Frees memory the layer returned (pom_api_study_run_json's report); NULL
 * is allowed. */
void pom_api_free(void *p);

#endif
