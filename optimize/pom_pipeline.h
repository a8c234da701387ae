/* pom_pipeline.h - the design pipeline inside a study: for each candidate
 * whose config asks for it, synthesize and scale the geometry
 * (synthesis.run_in_study = true), size it to a target workspace
 * (sizing.run_in_study = true, docs/optimize.md 6c) and tune the gains
 * (tuning.run_in_study = true) before its Monte-Carlo maneuvers run
 * (docs/optimize.md, section 10).
 *
 * Loading a study only reads and checks the configs (the factory below);
 * pom_pipeline_run then does the work, candidate by candidate, reporting
 * progress, and names every file after its candidate. */
#ifndef POM_PIPELINE_H
#define POM_PIPELINE_H

#include "pom_study.h"
#include "pom_status.h"
#include "pom_synth.h"
#include "pom_tune.h"

#define POM_PIPELINE_PATH_LEN 1200

/* Options of pom_pipeline_run and pom_pipeline_prepare. */
typedef struct {
  const char *output_prefix;    /* every per-candidate file is PREFIX<stem>.geometry.cfg,
                                   .controller.cfg, .h5 (the synthesis record); the
                                   folders are created (NULL = "results/pipeline_") */
  int no_files;                 /* 1: write nothing (MPI ranks other than the root) */
  pom_opt_progress_fn progress; /* phases "<candidate> design", "... direct", "... tune", ...;
                                   may be NULL */
  void *progress_user;          /* passed to progress */
} pom_pipeline_options;

/* What the pipeline did for one candidate (read by the CLI's summary). */
typedef struct {
  int synthesized;                           /* 1: the geometry came from the synthesis */
  int sized;                                 /* 1: sized to the target workspace (sizing group) */
  int tuned;                                 /* 1: the gains came from the tuning */
  char stem[POM_DOE_NAME_LEN + 8];           /* file stem of the candidate (unique in the study) */
  char geometry_file[POM_PIPELINE_PATH_LEN]; /* "" when not written */
  char synthesis_file[POM_PIPELINE_PATH_LEN];
  char controller_file[POM_PIPELINE_PATH_LEN];
  pom_kin_arch config_arch; /* the geometry of the candidate's config */
  pom_kin_arch arch;        /* the geometry run (synthesized and scaled, or the config's) */
  /* synthesis */
  double d_surrogate;  /* true desirability of the surrogate optimum (base scale) */
  double d_direct;     /* of the direct search's optimum (NaN when it did not run) */
  int direct_better;   /* 1: the direct search found the better design */
  int written_direct;  /* 1: the direct optimum was scaled and run */
  pom_syn_write write; /* synthesis.write */
  int n_goals;
  pom_syn_resp goal_resp[POM_SYN_N_RESP];
  double goal_r2_pred[POM_SYN_N_RESP]; /* predicted R^2 of each goal's first-stage surface (NaN:
                                          none fitted) */
  int n_negative_r2_pred; /* surfaces (any response, any stage) with predicted R^2 < 0 */
  double synthesis_time;  /* s */
  /* sizing (docs/optimize.md 6c): the geometry's scale set so that the
     actuator travel spans the target workspace */
  double sizing_target; /* target half-width of the regular dexterous workspace (rad) */
  int sizing_scaled;    /* 1: the scale was set (linear actuators); 0: kept and checked */
  double sizing_rdw;    /* RDW half-width of the sized geometry (rad), searched up to the
                           target + one grid step: at least the target */
  double sizing_time;   /* s */
  /* tuning (on the geometry run) */
  int n_tune_maneuvers;
  pom_dyn_controller config_gains, tuned_gains;
  pom_tune_eval config_eval, tuned_eval; /* criterion at the config's and the tuned gains */
  int config_gains_in_box;               /* 1: the config's gains lie inside the tuning bounds, so
                                            tuning never ends above their criterion */
  int config_geometry_evaluated;         /* 1 when synthesized and tuned: the line below is set */
  pom_tune_eval config_geometry_eval;    /* the config's geometry with the config's gains, same
                                            maneuvers and criterion (docs/optimize.md 10) */
  double tuning_time;                    /* s */
  long tuning_evaluations;               /* criterion evaluations of the tuning (both stages, the
                                            config's gains and the result) */
} pom_pipeline_record;

/* Evaluator factory for pom_doe_study_load / pom_doe_study_single: reads and
 * checks the candidate config (its synthesis and tuning groups when switched
 * on). Candidates that ask for neither are ready at once, with exactly the
 * mechanism and gains of their config; the others must go through
 * pom_pipeline_run (or pom_pipeline_prepare) before their first maneuver, or
 * their workers refuse to start. user is unused (may be NULL). */
pom_status pom_pipeline_evaluator_create(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                                         pom_error *err);

/* Synthesizes, scales and tunes one pipeline evaluator as its config asks and
 * builds its dynamics model; files are PREFIX<stem>.*. Does nothing for an
 * evaluator that is ready. */
pom_status pom_pipeline_prepare(pom_doe_evaluator *eval, const char *stem,
                                const pom_pipeline_options *o, pom_error *err);

/* pom_pipeline_prepare for every candidate of the study built with the
 * factory above, each with a unique file stem made from its name (letters and
 * digits kept, other runs of characters '_', never cut; a repeated stem gets
 * "_2", "_3", ...). Errors name the candidate. */
pom_status pom_pipeline_run(pom_doe_study *study, const pom_pipeline_options *o, pom_error *err);

/* The record of a pipeline evaluator; NULL for any other evaluator. */
const pom_pipeline_record *pom_pipeline_record_of(const pom_doe_evaluator *eval);

/* The file stem of a name into out (see pom_pipeline_run). */
void pom_pipeline_stem(char *out, size_t cap, const char *name);

#endif
