/* pom_pipeline.h - the design pipeline inside a study: for each candidate
 * whose config asks for it, synthesize and scale the geometry
 * (synthesis.run_in_study = true) and tune the gains
 * (tuning.run_in_study = true) before its Monte-Carlo maneuvers run
 * (docs/optimize.md, section 10). */
#ifndef POM_PIPELINE_H
#define POM_PIPELINE_H

#include "pom_doe.h"
#include "pom_status.h"

/* Options of the pipeline evaluator (the `user` pointer of the factory). */
typedef struct {
  const char *output_prefix; /* where the geometry/controller fragments and the synthesis
                                record go: PREFIX<name>.geometry.cfg, .controller.cfg, .h5
                                (NULL = "results/pipeline_") */
} pom_pipeline_options;

/* Evaluator factory for pom_doe_study_load / pom_doe_study_single: the
 * real dynamics evaluator of the candidate config, after the synthesis and
 * tuning it asks for. Candidates that ask for neither get exactly the
 * mechanism and gains of their config. user may be NULL or a
 * pom_pipeline_options. */
pom_status pom_pipeline_evaluator_create(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                                         pom_error *err);

#endif
