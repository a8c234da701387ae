/* pom_pipeline.c - synthesize -> scale -> tune inside a study's candidate
 * evaluator (docs/optimize.md, section 10). */
#include "pom_pipeline.h"

#include "pom_h5.h"
#include "pom_kinematics.h"
#include "pom_synth.h"
#include "pom_tune.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  pom_kin_arch arch;     /* geometry and limits (synthesized when asked) */
  pom_mechanism mech;    /* bodies, joints, actuators */
  pom_dyn_params params; /* with the tuned gains when asked */
  pom_dyn_model *model;  /* shared read-only by the workers */
  int synthesized;       /* 1 when the geometry came from the synthesis */
  int tuned;             /* 1 when the gains came from the tuning */
  double d_confirmed;    /* desirability of the synthesized optimum (true kinematics) */
  double tune_criterion; /* tuning criterion at the tuned gains (s) */
} pipe_ctx;

static void ctx_destroy(void *p) {
  pipe_ctx *ctx = p;
  if (!ctx) return;
  pom_dyn_model_destroy(ctx->model);
  free(ctx);
}

static pom_status worker_create(void **worker, const void *p, pom_error *err) {
  const pipe_ctx *ctx = p;
  pom_dyn_data *d = NULL;
  POM_TRY(pom_dyn_data_create(&d, ctx->model, err));
  *worker = d;
  return POM_OK;
}

static void worker_destroy(void *worker) {
  pom_dyn_data_destroy(worker);
}

static pom_status check_stroke(const pipe_ctx *ctx, const double q[3], pom_error *err) {
  double half = 0.5 * ctx->arch.stroke;
  for (int i = 0; i < 3; ++i)
    if (!(fabs(q[i]) <= half))
      POM_FAIL(err, POM_ERR_LIMIT,
               "target of actuator %d = %.4g mm is outside the stroke +-%.4g mm", i + 1, q[i] * 1e3,
               half * 1e3);
  return POM_OK;
}

static pom_status targets(const void *p, const pom_doe_maneuver *mv, double q[3], pom_error *err) {
  const pipe_ctx *ctx = p;
  POM_TRY(pom_kin_inverse(&ctx->arch, mv->R, q, err));
  return check_stroke(ctx, q, err);
}

static pom_status run(const void *p, void *worker, const double target[3], pom_dyn_metrics *out,
                      pom_error *err) {
  const pipe_ctx *ctx = p;
  pom_status st = check_stroke(ctx, target, err);
  if (st != POM_OK) {
    memset(out, 0, sizeof *out);
    for (int i = 0; i < 3; ++i)
      out->target[i] = target[i];
    out->status = st;
    snprintf(out->reason, sizeof out->reason, "%s", err ? err->message : "outside the stroke");
    return st;
  }
  st = pom_dyn_simulate(ctx->model, worker, target, out, NULL, err);
  if (st != POM_OK) return st;
  return pom_doe_check_final_stroke(out, ctx->arch.stroke, err);
}

static pom_status describe(const void *p, hid_t g, pom_error *err) {
  const pipe_ctx *ctx = p;
  const pom_dyn_params *par = &ctx->params;
  POM_TRY(pom_h5_attr_string(g, "architecture", pom_kin_arch_name(ctx->arch.type), err));
  POM_TRY(pom_h5_attr_double(g, "stroke_m", ctx->arch.stroke, err));
  POM_TRY(pom_h5_attr_int64(g, "pipeline_synthesized", ctx->synthesized, err));
  POM_TRY(pom_h5_attr_int64(g, "pipeline_tuned", ctx->tuned, err));
  if (ctx->arch.has_design)
    POM_TRY(pom_h5_attr_double(g, "platform_radius_m", ctx->arch.design.scale, err));
  if (ctx->synthesized)
    POM_TRY(pom_h5_attr_double(g, "synthesis_desirability", ctx->d_confirmed, err));
  if (ctx->tuned) POM_TRY(pom_h5_attr_double(g, "tuning_criterion_s", ctx->tune_criterion, err));
  POM_TRY(pom_doe_describe_dyn_params(g, par, err));
  POM_TRY(pom_h5_attr_int64(g, "model_states", pom_dyn_model_n_states(ctx->model), err));
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
  ctx->arch = run->scaled;
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
  pb->arch = ctx->arch;
  pb->mech = ctx->mech;
  pb->params = ctx->params;
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
  ctx->params.controller = res.best;
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
  POM_TRY_GOTO(pom_kin_arch_load(&ctx->arch, cfg, err), fail);
  if (do_synth) POM_TRY_GOTO(synthesize(ctx, cfg, prefix, err), fail);
  pom_kin_inertia in;
  POM_TRY_GOTO(pom_kin_inertia_load(&in, &ctx->arch, cfg, err), fail);
  POM_TRY_GOTO(pom_kin_mechanism_from(&ctx->mech, &ctx->arch, &in, err), fail);
  pom_dyn_params_defaults(&ctx->params);
  POM_TRY_GOTO(pom_dyn_params_load(&ctx->params, cfg, err), fail);
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
  POM_TRY_GOTO(pom_dyn_model_create_ex(&ctx->model, &ctx->mech, &ctx->arch, &ctx->params, err),
               fail);
  eval->ctx = ctx;
  eval->ctx_destroy = ctx_destroy;
  eval->worker_create = worker_create;
  eval->worker_destroy = worker_destroy;
  eval->targets = targets;
  eval->run = run;
  eval->describe = describe;
  return POM_OK;
fail:
  ctx_destroy(ctx);
  return st;
}
