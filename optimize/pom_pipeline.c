/* pom_pipeline.c - synthesize -> scale -> tune inside a study's candidate
 * evaluator (docs/optimize.md, section 10). */
#define _XOPEN_SOURCE 700 /* mkdir */
#include "pom_pipeline.h"

#include "pom_h5.h"
#include "pom_kinematics.h"
#include "pom_synth.h"
#include "pom_tune.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>

typedef struct {
  pom_doe_dyn_base base; /* first: the doe dynamics callbacks take this context */
  int synthesized;       /* 1 when the geometry came from the synthesis */
  int tuned;             /* 1 when the gains came from the tuning */
  double d_confirmed;    /* desirability of the synthesized optimum (true kinematics) */
  double tune_criterion; /* tuning criterion at the tuned gains (s) */
} pipe_ctx;

static void ctx_destroy(void *p) {
  pipe_ctx *ctx = p;
  if (!ctx) return;
  pom_dyn_model_destroy(ctx->base.model);
  free(ctx);
}

static pom_status describe(const void *p, hid_t g, pom_error *err) {
  const pipe_ctx *ctx = p;
  POM_TRY(pom_doe_dyn_describe_base(&ctx->base, g, err));
  POM_TRY(pom_h5_attr_int64(g, "pipeline_synthesized", ctx->synthesized, err));
  POM_TRY(pom_h5_attr_int64(g, "pipeline_tuned", ctx->tuned, err));
  if (ctx->base.arch.has_design)
    POM_TRY(pom_h5_attr_double(g, "platform_radius_m", ctx->base.arch.design.scale, err));
  if (ctx->synthesized)
    POM_TRY(pom_h5_attr_double(g, "synthesis_desirability", ctx->d_confirmed, err));
  if (ctx->tuned) POM_TRY(pom_h5_attr_double(g, "tuning_criterion_s", ctx->tune_criterion, err));
  return POM_OK;
}

/* Creates the folders of an output prefix ("results/pipeline_" -> results/)
 * before any work, so a study run from another folder fails at once, not
 * after the synthesis. */
static pom_status make_prefix_dirs(const char *prefix, pom_error *err) {
  char path[1024];
  snprintf(path, sizeof path, "%s", prefix);
  char *slash = strrchr(path, '/');
  if (!slash) return POM_OK;
  *slash = '\0';
  for (char *c = path + 1; *c; ++c) {
    if (*c != '/') continue;
    *c = '\0';
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
      POM_FAIL(err, POM_ERR_IO, "pipeline: cannot create folder '%s' for its outputs", path);
    *c = '/';
  }
  if (path[0] && mkdir(path, 0777) != 0 && errno != EEXIST)
    POM_FAIL(err, POM_ERR_IO, "pipeline: cannot create folder '%s' for its outputs", path);
  return POM_OK;
}

/* Synthesis of the candidate: the scaled optimum replaces its geometry. */
static pom_status synthesize(pipe_ctx *ctx, const pom_cfg *cfg, const char *prefix,
                             pom_error *err) {
  pom_status st = POM_OK;
  pom_syn_problem *pb = calloc(1, sizeof *pb);
  pom_syn_run *run = NULL;
  if (!pb) POM_FAIL(err, POM_ERR_NOMEM, "pipeline: out of memory");
  POM_TRY_GOTO(pom_syn_load(pb, cfg, err), done);
  POM_TRY_GOTO(pom_syn_begin(&run, pb, err), done);
  POM_TRY_GOTO(pom_syn_finish(run, err), done);
  char path[1024], name[40];
  size_t j = 0;
  for (const char *c = pb->base.name; *c && j + 1 < sizeof name && j < 24; ++c)
    name[j++] = ((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9'))
                    ? *c
                    : '_';
  name[j] = '\0';
  snprintf(path, sizeof path, "%s%s.geometry.cfg", prefix, name);
  POM_TRY_GOTO(pom_syn_write_geometry(run, path, err), done);
  snprintf(path, sizeof path, "%s%s.h5", prefix, name);
  POM_TRY_GOTO(pom_syn_write_h5(run, path, pom_cfg_text(cfg), err), done);
  ctx->base.arch = run->scaled;
  ctx->synthesized = 1;
  ctx->d_confirmed = pom_syn_desirability(pb, run->scaled_resp, NULL);
done:
  if (st != POM_OK) pom_error_prefix(err, "pipeline synthesis");
  pom_syn_destroy(run);
  free(pb);
  return st;
}

static pom_status tune(pipe_ctx *ctx, const pom_cfg *cfg, const char *prefix, pom_error *err) {
  pom_status st = POM_OK;
  pom_tune_problem *pb = calloc(1, sizeof *pb);
  pom_tune_result res;
  if (!pb) POM_FAIL(err, POM_ERR_NOMEM, "pipeline: out of memory");
  POM_TRY_GOTO(pom_tune_load(pb, cfg, err), done);
  /* tune the mechanism the study will run (possibly just synthesized) */
  pb->arch = ctx->base.arch;
  pb->mech = ctx->base.mech;
  pb->params = ctx->base.params;
  POM_TRY_GOTO(pom_tune_run(pb, &res, err), done);
  char path[1024], name[40];
  size_t j = 0;
  for (const char *c = pb->arch.name; *c && j + 1 < sizeof name && j < 24; ++c)
    name[j++] = ((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9'))
                    ? *c
                    : '_';
  name[j] = '\0';
  snprintf(path, sizeof path, "%s%s.controller.cfg", prefix, name);
  POM_TRY_GOTO(pom_tune_write_controller(pb, &res, path, err), done);
  ctx->base.params.controller = res.best;
  ctx->tuned = 1;
  ctx->tune_criterion = res.best_eval.criterion;
done:
  if (st != POM_OK) pom_error_prefix(err, "pipeline tuning");
  free(pb);
  return st;
}

pom_status pom_pipeline_evaluator_create(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                                         pom_error *err) {
  static const char *const scopes_base[] = {"name",    "architecture", "geometry",   "limits",
                                            "inertia", "actuator",     "controller", "joints",
                                            "scene",   "solver",       "maneuver",   NULL};
  const pom_pipeline_options *po = user;
  const char *prefix = (po && po->output_prefix) ? po->output_prefix : "results/pipeline_";
  pom_status st = POM_OK;
  int do_synth = 0, do_tune = 0;
  memset(eval, 0, sizeof *eval);
  POM_TRY(pom_cfg_bool_opt(cfg, "synthesis.run_in_study", 0, &do_synth, err));
  POM_TRY(pom_cfg_bool_opt(cfg, "tuning.run_in_study", 0, &do_tune, err));
  pipe_ctx *ctx = calloc(1, sizeof *ctx);
  if (!ctx) POM_FAIL(err, POM_ERR_NOMEM, "evaluator: out of memory");
  POM_TRY_GOTO(pom_kin_arch_load(&ctx->base.arch, cfg, err), fail);
  if (do_synth || do_tune) POM_TRY_GOTO(make_prefix_dirs(prefix, err), fail);
  if (do_synth) POM_TRY_GOTO(synthesize(ctx, cfg, prefix, err), fail);
  pom_kin_inertia in;
  POM_TRY_GOTO(pom_kin_inertia_load(&in, &ctx->base.arch, cfg, err), fail);
  POM_TRY_GOTO(pom_kin_mechanism_from(&ctx->base.mech, &ctx->base.arch, &in, err), fail);
  pom_dyn_params_defaults(&ctx->base.params);
  POM_TRY_GOTO(pom_dyn_params_load(&ctx->base.params, cfg, err), fail);
  if (do_tune) POM_TRY_GOTO(tune(ctx, cfg, prefix, err), fail);
  {
    const char *scopes[16];
    int n = 0;
    for (; scopes_base[n]; ++n)
      scopes[n] = scopes_base[n];
    if (do_synth) scopes[n++] = "synthesis";
    if (do_tune) scopes[n++] = "tuning";
    scopes[n] = NULL;
    POM_TRY_GOTO(pom_cfg_check_unknown(cfg, scopes, NULL, err), fail);
  }
  POM_TRY_GOTO(pom_doe_mech_actuator_kind(&ctx->base.mech, &eval->actuator_kind, err), fail);
  POM_TRY_GOTO(pom_dyn_model_create(&ctx->base.model, &ctx->base.mech, &ctx->base.arch,
                                    &ctx->base.params, err),
               fail);
  eval->ctx = ctx;
  eval->ctx_destroy = ctx_destroy;
  eval->worker_create = pom_doe_dyn_worker_create;
  eval->worker_destroy = pom_doe_dyn_worker_destroy;
  eval->targets = pom_doe_dyn_targets;
  eval->run = pom_doe_dyn_run;
  eval->describe = describe;
  return POM_OK;
fail:
  ctx_destroy(ctx);
  return st;
}
