/* pom_pipeline.c - synthesize -> scale -> size -> tune inside a study's
 * candidate evaluator (docs/optimize.md, sections 6c and 10). */
#define _XOPEN_SOURCE 700 /* mkdir */
#include "pom_pipeline.h"

#include "pom_dyn_ctrl.h"
#include "pom_h5.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

typedef struct {
  pom_doe_dyn_base base;   /* first: the doe dynamics callbacks take this context */
  pom_kin_inertia inertia; /* mass properties of the config (rebuilt on a new geometry) */
  pom_syn_problem *synth;  /* the synthesis to run (owned), NULL when none or done */
  pom_syn_problem *sizing; /* the sizing to run (owned, no design variables), NULL when none */
  pom_tune_problem *tune;  /* the tuning to run (owned), NULL when none or done */
  int pending;             /* 1 until pom_pipeline_prepare built the model */
  char *config_text;       /* the resolved config, for the synthesis record (owned) */
  pom_pipeline_record rec; /* what was done */
} pipe_ctx;

static double now_s(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void ctx_destroy(void *p) {
  pipe_ctx *ctx = p;
  if (!ctx) return;
  pom_dyn_model_destroy(ctx->base.model);
  free(ctx->synth);
  free(ctx->sizing);
  free(ctx->tune);
  free(ctx->config_text);
  free(ctx);
}

static pom_status describe(const void *p, hid_t g, pom_error *err) {
  const pipe_ctx *ctx = p;
  const pom_pipeline_record *r = &ctx->rec;
  POM_TRY(pom_doe_dyn_describe_base(&ctx->base, g, err));
  POM_TRY(pom_h5_attr_int64(g, "pipeline_synthesized", r->synthesized, err));
  POM_TRY(pom_h5_attr_int64(g, "pipeline_tuned", r->tuned, err));
  POM_TRY(pom_h5_attr_int64(g, "pipeline_sized", r->sized, err));
  if (r->sized) {
    POM_TRY(pom_h5_attr_double(g, "sizing_target_half_width_rad", r->sizing_target, err));
    POM_TRY(pom_h5_attr_double(g, "sizing_rdw_rad", r->sizing_rdw, err));
    POM_TRY(pom_h5_attr_int64(g, "sizing_scaled", r->sizing_scaled, err));
  }
  if (ctx->base.arch.has_design)
    POM_TRY(pom_h5_attr_double(g, "platform_radius_m", ctx->base.arch.design.scale, err));
  if (r->synthesized) {
    POM_TRY(pom_h5_attr_double(g, "synthesis_desirability", r->d_surrogate, err));
    POM_TRY(pom_h5_attr_string(g, "synthesis_optimum", r->written_direct ? "direct" : "surrogate",
                               err));
  }
  if (r->tuned) POM_TRY(pom_h5_attr_double(g, "tuning_criterion_s", r->tuned_eval.criterion, err));
  return POM_OK;
}

/* Workers of a candidate the pipeline has not prepared would run without a
 * model: refused with a message instead. */
static pom_status worker_create(void **worker, const void *p, pom_error *err) {
  const pipe_ctx *ctx = p;
  if (ctx->pending)
    POM_FAIL(err, POM_ERR_ARG,
             "pipeline: candidate '%s' asks for synthesis or tuning that has not run "
             "(pom_pipeline_run)",
             ctx->base.arch.name);
  return pom_doe_dyn_worker_create(worker, p, err);
}

void pom_pipeline_stem(char *out, size_t cap, const char *name) {
  size_t j = 0;
  for (size_t i = 0; name[i] && j + 1 < cap; ++i) {
    char c = name[i];
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'))
      out[j++] = c;
    else if (j > 0 && out[j - 1] != '_')
      out[j++] = '_';
  }
  while (j > 0 && out[j - 1] == '_')
    --j;
  if (j == 0 && cap > 1) out[j++] = '_'; /* a name of punctuation only */
  if (cap > 0) out[j] = '\0';
}

/* Creates the folders of an output prefix ("results/x/" -> results/x)
 * before any work, so a study fails at once, not after the synthesis. */
static pom_status make_prefix_dirs(const char *prefix, pom_error *err) {
  char path[POM_PIPELINE_PATH_LEN];
  snprintf(path, sizeof path, "%s", prefix);
  char *slash = strrchr(path, '/');
  if (!slash) return POM_OK;
  *slash = '\0';
  for (char *c = path + 1; *c; ++c) {
    if (*c != '/') continue;
    *c = '\0';
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
      POM_FAIL(err, POM_ERR_IO, "pipeline: cannot create folder '%s' for its outputs: %s", path,
               strerror(errno));
    *c = '/';
  }
  if (path[0] && mkdir(path, 0777) != 0 && errno != EEXIST)
    POM_FAIL(err, POM_ERR_IO, "pipeline: cannot create folder '%s' for its outputs: %s", path,
             strerror(errno));
  return POM_OK;
}

/* The sizing group (docs/optimize.md 6c): the target workspace and the
 * scale bracket of pom_syn_scale, with no design variable. The RDW search
 * stops one grid step above the target: whether the target is covered is
 * all the rule asks, and a rotary 3-RRR's full workspace costs up to 30 s. */
static const char *const sizing_groups[] = {"sizing", "workspace", NULL};

static pom_status sizing_load(pom_syn_problem *pb, const pom_kin_arch *arch, const pom_cfg *cfg,
                              pom_error *err) {
  memset(pb, 0, sizeof *pb);
  pb->base = *arch;
  if (!arch->has_design)
    return pom_cfg_error(cfg, "sizing.run_in_study", NULL, err,
                         "the geometry must be in design-parameter form (geometry.mode = "
                         "\"parameters\") to be sized");
  POM_TRY(pom_kin_ws_load(&pb->ws, cfg, err));
  POM_TRY(pom_cfg_real(cfg, "sizing.target_half_width_deg", POM_DEG, 0.1, 80.0,
                       &pb->target_half_width, err));
  if (pb->target_half_width > pb->ws.max_half_width)
    return pom_cfg_error(cfg, "sizing.target_half_width_deg", NULL, err,
                         "exceeds workspace.max_half_width_deg (%.4g deg)",
                         pb->ws.max_half_width / POM_DEG);
  pb->ws.max_half_width = fmin(pb->ws.max_half_width, pb->target_half_width + pb->ws.resolution);
  pb->scale_min = 1e-3;
  pb->scale_max = 0.2;
  pb->scale_rel_tol = 1e-3;
  pb->scale_scan = 24;
  POM_TRY(pom_cfg_real_opt(cfg, "sizing.scale_min_mm", 1e-3, 0.01, 1e5, pb->scale_min,
                           &pb->scale_min, err));
  POM_TRY(pom_cfg_real_opt(cfg, "sizing.scale_max_mm", 1e-3, 0.01, 1e5, pb->scale_max,
                           &pb->scale_max, err));
  if (!(pb->scale_min < pb->scale_max))
    return pom_cfg_error(cfg, "sizing.scale_max_mm", NULL, err, "must exceed scale_min_mm");
  POM_TRY(pom_cfg_real_opt(cfg, "sizing.scale_rel_tol", 1.0, 1e-9, 0.1, pb->scale_rel_tol,
                           &pb->scale_rel_tol, err));
  long scan = pb->scale_scan;
  POM_TRY(pom_cfg_int_opt(cfg, "sizing.scale_scan", 2, 1000, scan, &scan, err));
  pb->scale_scan = (int)scan;
  pom_cfg_mark_used(cfg, "sizing.run_in_study");
  return POM_OK;
}

/* ---- factory ---------------------------------------------------------------- */
pom_status pom_pipeline_evaluator_create(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                                         pom_error *err) {
  (void)user;
  pom_status st = POM_OK;
  int do_synth = 0, do_tune = 0, do_size = 0;
  memset(eval, 0, sizeof *eval);
  POM_TRY(pom_cfg_bool_opt(cfg, "synthesis.run_in_study", 0, &do_synth, err));
  POM_TRY(pom_cfg_bool_opt(cfg, "sizing.run_in_study", 0, &do_size, err));
  POM_TRY(pom_cfg_bool_opt(cfg, "tuning.run_in_study", 0, &do_tune, err));
  pipe_ctx *ctx = calloc(1, sizeof *ctx);
  if (!ctx) POM_FAIL(err, POM_ERR_NOMEM, "evaluator: out of memory");
  POM_TRY_GOTO(pom_kin_arch_load(&ctx->base.arch, cfg, err), fail);
  ctx->rec.config_arch = ctx->base.arch;
  if (do_synth) {
    ctx->synth = calloc(1, sizeof *ctx->synth);
    if (!ctx->synth) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "pipeline: out of memory");
    POM_TRY_GOTO(pom_syn_load(ctx->synth, cfg, err), fail);
    const char *text = pom_cfg_text(cfg);
    if (text) {
      size_t len = strlen(text) + 1;
      ctx->config_text = malloc(len);
      if (!ctx->config_text) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "pipeline: out of memory");
      memcpy(ctx->config_text, text, len);
    }
  }
  if (do_size) {
    ctx->sizing = calloc(1, sizeof *ctx->sizing);
    if (!ctx->sizing) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "pipeline: out of memory");
    POM_TRY_GOTO(sizing_load(ctx->sizing, &ctx->base.arch, cfg, err), fail);
  }
  POM_TRY_GOTO(pom_kin_inertia_load(&ctx->inertia, &ctx->base.arch, cfg, err), fail);
  POM_TRY_GOTO(pom_kin_mechanism_from(&ctx->base.mech, &ctx->base.arch, &ctx->inertia, err), fail);
  pom_dyn_params_defaults(&ctx->base.params);
  POM_TRY_GOTO(pom_dyn_params_load(&ctx->base.params, cfg, err), fail);
  if (do_tune) {
    ctx->tune = calloc(1, sizeof *ctx->tune);
    if (!ctx->tune) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "pipeline: out of memory");
    POM_TRY_GOTO(pom_tune_load(ctx->tune, cfg, err), fail);
  }
  /* every group the candidate's model reads; unknown keys there are errors */
  POM_TRY_GOTO(pom_doe_evaluator_add_groups(eval, pom_kin_model_groups(), err), fail);
  POM_TRY_GOTO(pom_doe_evaluator_add_groups(eval, pom_dyn_param_groups(), err), fail);
  if (do_synth) POM_TRY_GOTO(pom_doe_evaluator_add_groups(eval, pom_syn_groups(), err), fail);
  if (do_tune) POM_TRY_GOTO(pom_doe_evaluator_add_groups(eval, pom_tune_groups(), err), fail);
  if (do_size) POM_TRY_GOTO(pom_doe_evaluator_add_groups(eval, sizing_groups, err), fail);
  POM_TRY_GOTO(pom_cfg_check_unknown(cfg, eval->groups, NULL, err), fail);
  POM_TRY_GOTO(pom_doe_mech_actuator_kind(&ctx->base.mech, &eval->actuator_kind, err), fail);
  ctx->rec.arch = ctx->base.arch;
  ctx->rec.config_gains = ctx->rec.tuned_gains = ctx->base.params.controller;
  ctx->pending = do_synth || do_tune || do_size;
  if (!ctx->pending)
    POM_TRY_GOTO(pom_dyn_model_create(&ctx->base.model, &ctx->base.mech, &ctx->base.arch,
                                      &ctx->base.params, err),
                 fail);
  eval->ctx = ctx;
  eval->ctx_destroy = ctx_destroy;
  eval->worker_create = worker_create;
  eval->worker_destroy = pom_doe_dyn_worker_destroy;
  eval->targets = pom_doe_dyn_targets;
  eval->run = pom_doe_dyn_run;
  eval->describe = describe;
  eval->dyn_base = 1; /* ctx starts with its pom_doe_dyn_base */
  return POM_OK;
fail:
  ctx_destroy(ctx);
  memset(eval, 0, sizeof *eval);
  return st;
}

const pom_pipeline_record *pom_pipeline_record_of(const pom_doe_evaluator *eval) {
  if (!eval || eval->ctx_destroy != ctx_destroy || !eval->ctx) return NULL;
  return &((const pipe_ctx *)eval->ctx)->rec;
}

/* ---- the work ----------------------------------------------------------------- */
/* Forwards a phase of the synthesis or tuning as "<stem> <phase>". */
typedef struct {
  const pom_pipeline_options *o;
  const char *stem;
} relay;

static void relay_progress(void *user, const char *phase, long done, long total) {
  const relay *r = user;
  char label[POM_DOE_NAME_LEN + 40];
  snprintf(label, sizeof label, "%s %s", r->stem, phase);
  r->o->progress(r->o->progress_user, label, done, total);
}

/* The synthesis: the scaled optimum (synthesis.write) replaces the geometry. */
static pom_status synthesize(pipe_ctx *ctx, const pom_pipeline_options *o, relay *rl,
                             pom_error *err) {
  pom_status st = POM_OK;
  pom_syn_run *run = NULL;
  pom_pipeline_record *r = &ctx->rec;
  double t0 = now_s();
  POM_TRY_GOTO(pom_syn_begin(&run, ctx->synth, err), done);
  if (o->progress) {
    run->progress = relay_progress;
    run->progress_user = rl;
  }
  POM_TRY_GOTO(pom_syn_finish(run, err), done);
  if (run->n_cap_checks > 0 && !run->cap_met) {
    /* the capability floor (synthesis.capability_require) holds for no
     * optimum: the study would run a design that fails it */
    char why[1024];
    pom_syn_cap_failure(run, why, sizeof why);
    POM_FAIL_GOTO(err, POM_ERR_LIMIT, done, "no optimum meets synthesis.capability_require: %s",
                  why);
  }
  if (!o->no_files) {
    snprintf(r->geometry_file, sizeof r->geometry_file, "%s%s.geometry.cfg", o->output_prefix,
             r->stem);
    snprintf(r->synthesis_file, sizeof r->synthesis_file, "%s%s.h5", o->output_prefix, r->stem);
    POM_TRY_GOTO(pom_syn_write_geometry(run, r->geometry_file, err), done);
    POM_TRY_GOTO(pom_syn_write_h5(run, r->synthesis_file, ctx->config_text, err), done);
  }
  ctx->base.arch = run->scaled;
  r->arch = run->scaled;
  r->synthesized = 1;
  r->d_surrogate = run->d_confirmed;
  r->d_direct = run->direct_done ? run->d_direct : NAN;
  r->direct_better = run->direct_better;
  r->written_direct = run->written_direct;
  r->write = ctx->synth->write;
  r->n_goals = ctx->synth->n_goals;
  for (int g = 0; g < r->n_goals; ++g) {
    pom_syn_resp resp = ctx->synth->goal_resp[g];
    r->goal_resp[g] = resp;
    r->goal_r2_pred[g] = run->fitted[resp] ? run->fit[resp].r2_pred : NAN;
  }
  for (const pom_syn_run *s = run; s; s = s->refined)
    for (int k = 0; k < POM_SYN_N_RESP; ++k)
      r->n_negative_r2_pred += s->fitted[k] && s->fit[k].r2_pred < 0.0;
  /* the mechanism of the new geometry, with the config's mass properties */
  POM_TRY_GOTO(pom_kin_mechanism_from(&ctx->base.mech, &ctx->base.arch, &ctx->inertia, err), done);
  r->synthesis_time = now_s() - t0;
done:
  if (st != POM_OK) pom_error_prefix(err, "pipeline synthesis");
  pom_syn_destroy(run);
  return st;
}

/* The sizing rule (docs/optimize.md 6c): a candidate with linear actuators
 * whose scale sets its kinematics gets the largest scale whose regular
 * dexterous workspace covers the target (pom_syn_scale: the stroke spans the
 * target); any other keeps its scale, which changes none of its angles, and
 * must cover the target as it is. Runs after a synthesis, on its geometry. */
static pom_status size_geometry(pipe_ctx *ctx, pom_error *err) {
  pom_status st = POM_OK;
  pom_syn_problem *pb = ctx->sizing;
  pom_pipeline_record *r = &ctx->rec;
  double t0 = now_s();
  double x[POM_SYN_N_VARS] = {0.0};
  pb->base = ctx->base.arch;
  const pom_kin_arch_type *t = pb->base.type;
  double scale = pb->base.design.scale;
  r->sizing_scaled = pom_kin_type_actuator(t) == POM_ACT_PRISMATIC && t->scale_sets_kinematics;
  if (r->sizing_scaled) POM_TRY_GOTO(pom_syn_scale(pb, x, &scale, NULL, err), done);
  pom_kin_arch arch;
  pom_kin_ws_result ws;
  POM_TRY_GOTO(pom_syn_arch(pb, x, scale, &arch, err), done);
  POM_TRY_GOTO(pom_kin_workspace(&arch, &pb->ws, &ws, err), done);
  if (ws.half_width < pb->target_half_width - 1e-9 * pb->ws.resolution)
    POM_FAIL_GOTO(err, POM_ERR_LIMIT, done,
                  "the %s's regular dexterous workspace is +-%.3g deg, short of the target "
                  "+-%.3g deg (sizing.target_half_width_deg); its %s actuators' range is fixed "
                  "and its scale (%s) changes none of its angles, so no sizing reaches it",
                  t->label, ws.half_width / POM_DEG, pb->target_half_width / POM_DEG,
                  pom_kin_type_actuator(t) == POM_ACT_PRISMATIC ? "linear" : "rotary",
                  t->scale_key);
  ctx->base.arch = arch;
  r->arch = arch;
  r->sized = 1;
  r->sizing_target = pb->target_half_width;
  r->sizing_rdw = ws.half_width;
  POM_TRY_GOTO(pom_kin_mechanism_from(&ctx->base.mech, &ctx->base.arch, &ctx->inertia, err), done);
  r->sizing_time = now_s() - t0;
done:
  if (st != POM_OK) pom_error_prefix(err, "pipeline sizing");
  return st;
}

/* The tuning, on the mechanism the study will run (possibly just
 * synthesized). After a synthesis, the config's own geometry with the
 * config's gains is scored by the same criterion: tuning never does worse
 * than the config's gains, so that score bounds what tuning the config's
 * geometry would reach, and the difference is the geometry's (item of
 * docs/optimize.md 10). */
static pom_status tune(pipe_ctx *ctx, const pom_pipeline_options *o, relay *rl, pom_error *err) {
  pom_status st = POM_OK;
  pom_tune_problem *pb = ctx->tune;
  pom_tune_result res;
  pom_pipeline_record *r = &ctx->rec;
  double t0 = now_s();
  if (r->synthesized) {
    /* pb still holds the config's geometry and mechanism */
    POM_TRY_GOTO(pom_tune_evaluate(pb, &pb->params.controller, &r->config_geometry_eval, err),
                 done);
    r->config_geometry_evaluated = 1;
  }
  pb->arch = ctx->base.arch;
  pb->mech = ctx->base.mech;
  pb->params = ctx->base.params;
  if (o->progress) {
    pb->progress = relay_progress;
    pb->progress_user = rl;
  }
  POM_TRY_GOTO(pom_tune_run(pb, &res, err), done);
  r->config_gains_in_box = 1;
  for (int i = 0; i < pb->n_vars; ++i) {
    double g = pom_dyn_ctrl_gain(&res.initial, (int)pb->var[i]);
    r->config_gains_in_box &= g >= pb->lo[i] && g <= pb->hi[i];
  }
  if (!o->no_files) {
    snprintf(r->controller_file, sizeof r->controller_file, "%s%s.controller.cfg", o->output_prefix,
             r->stem);
    POM_TRY_GOTO(pom_tune_write_controller(pb, &res, r->controller_file, err), done);
  }
  ctx->base.params.controller = res.best;
  r->tuned = 1;
  r->n_tune_maneuvers = pb->n_maneuvers;
  r->config_gains = res.initial;
  r->config_eval = res.initial_eval;
  r->tuned_gains = res.best;
  r->tuned_eval = res.best_eval;
  r->tuning_time = now_s() - t0;
  r->tuning_evaluations = res.opt.evals_global + res.opt.evals_local + 2;
done:
  if (st != POM_OK) pom_error_prefix(err, "pipeline tuning");
  return st;
}

pom_status pom_pipeline_prepare(pom_doe_evaluator *eval, const char *stem,
                                const pom_pipeline_options *o, pom_error *err) {
  pipe_ctx *ctx = eval->ctx_destroy == ctx_destroy ? eval->ctx : NULL;
  if (!ctx || !ctx->pending) return POM_OK;
  pom_pipeline_options opts;
  memset(&opts, 0, sizeof opts);
  if (o) opts = *o;
  if (!opts.output_prefix) opts.output_prefix = "results/pipeline_";
  snprintf(ctx->rec.stem, sizeof ctx->rec.stem, "%s", stem);
  if (!opts.no_files) POM_TRY(make_prefix_dirs(opts.output_prefix, err));
  relay rl = {&opts, ctx->rec.stem};
  if (ctx->synth) POM_TRY(synthesize(ctx, &opts, &rl, err));
  if (ctx->sizing) POM_TRY(size_geometry(ctx, err));
  if (ctx->tune) POM_TRY(tune(ctx, &opts, &rl, err));
  ctx->rec.arch = ctx->base.arch;
  POM_TRY(pom_dyn_model_create(&ctx->base.model, &ctx->base.mech, &ctx->base.arch,
                               &ctx->base.params, err));
  free(ctx->synth);
  free(ctx->sizing);
  free(ctx->tune);
  ctx->synth = NULL;
  ctx->sizing = NULL;
  ctx->tune = NULL;
  ctx->pending = 0;
  return POM_OK;
}

pom_status pom_pipeline_run(pom_doe_study *study, const pom_pipeline_options *o, pom_error *err) {
  int n = study->n_candidates;
  char(*stems)[POM_DOE_NAME_LEN + 8] = calloc(n > 0 ? (size_t)n : 1, sizeof *stems);
  if (!stems) POM_FAIL(err, POM_ERR_NOMEM, "pipeline: out of memory");
  pom_status st = POM_OK;
  for (int c = 0; c < n && st == POM_OK; ++c) {
    char base[POM_DOE_NAME_LEN];
    pom_pipeline_stem(base, sizeof base, study->candidates[c].name);
    snprintf(stems[c], sizeof stems[c], "%s", base);
    /* distinct candidate names can share a stem ("a b", "a/b"): number them */
    for (int suffix = 2;; ++suffix) {
      int taken = 0;
      for (int e = 0; e < c && !taken; ++e)
        taken = strcmp(stems[e], stems[c]) == 0;
      if (!taken) break;
      snprintf(stems[c], sizeof stems[c], "%s_%d", base, suffix);
    }
    st = pom_pipeline_prepare(&study->candidates[c].eval, stems[c], o, err);
    if (st != POM_OK) pom_error_prefix(err, "candidate '%s'", study->candidates[c].name);
  }
  free(stems);
  return st;
}
