/* pom_doe_dyn.c - the real evaluator: one candidate = architecture +
 * mechanism + dynamics model; each worker owns a pom_dyn_data. */
#include "pom_study.h"
#include "pom_dyn_ctrl.h"
#include "pom_dyn_params_schema.h"
#include "pom_h5.h"
#include "pom_kinematics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef pom_doe_dyn_base dyn_ctx;

static void ctx_destroy(void *p) {
  dyn_ctx *ctx = p;
  if (!ctx) return;
  pom_dyn_model_destroy(ctx->model);
  free(ctx);
}

pom_status pom_doe_dyn_worker_create(void **worker, const void *p, pom_error *err) {
  const pom_doe_dyn_base *ctx = p;
  pom_dyn_data *d = NULL;
  POM_TRY(pom_dyn_data_create(&d, ctx->model, err));
  *worker = d;
  return POM_OK;
}

void pom_doe_dyn_worker_destroy(void *worker) {
  pom_dyn_data_destroy(worker);
}

pom_status pom_doe_mech_actuator_kind(const pom_mechanism *mech, pom_actuator_kind *kind,
                                      pom_error *err) {
  if (mech->n_actuators < 1) POM_FAIL(err, POM_ERR_ARG, "the mechanism has no actuator");
  *kind = mech->actuator[0].kind;
  for (int a = 1; a < mech->n_actuators; ++a)
    if (mech->actuator[a].kind != *kind)
      POM_FAIL(err, POM_ERR_ARG,
               "actuator %d is %s but actuator 1 is %s: the actuators of one mechanism must share "
               "a kind (one unit for targets, strokes and ranges)",
               a + 1, pom_act_kind_desc(mech->actuator[a].kind)->kind_name,
               pom_act_kind_desc(*kind)->kind_name);
  return POM_OK;
}

static pom_actuator_kind kind_of(const pom_doe_dyn_base *ctx) {
  return ctx->mech.n_actuators > 0 ? ctx->mech.actuator[0].kind : POM_ACT_PRISMATIC;
}

/* Joint targets must lie inside the stroke: the maneuver fails otherwise. */
static pom_status check_stroke(const pom_doe_dyn_base *ctx, const double q[3], pom_error *err) {
  const pom_act_desc *u = pom_act_kind_desc(kind_of(ctx));
  double half = 0.5 * ctx->arch.stroke, f = u->to_display;
  for (int i = 0; i < 3; ++i)
    if (!(fabs(q[i]) <= half))
      POM_FAIL(err, POM_ERR_LIMIT,
               "target of actuator %d = %.4g %s is outside the stroke +-%.4g %s", i + 1, q[i] * f,
               u->display, half * f, u->display);
  return POM_OK;
}

pom_status pom_doe_dyn_targets(const void *p, const pom_doe_maneuver *mv, double q[3],
                               pom_error *err) {
  const pom_doe_dyn_base *ctx = p;
  POM_TRY(pom_kin_inverse(&ctx->arch, mv->R, q, err));
  return check_stroke(ctx, q, err);
}

pom_status pom_doe_dyn_run(const void *p, void *worker, const double target[3],
                           pom_dyn_metrics *out, pom_error *err) {
  const pom_doe_dyn_base *ctx = p;
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
  /* the model has no end stops: a loop that runs away past the stroke is a
   * recorded failure (docs/results.md section 1) */
  return pom_doe_check_final_stroke_kind(out, ctx->arch.stroke, kind_of(ctx), err);
}

pom_status pom_doe_dyn_describe_base(const pom_doe_dyn_base *ctx, hid_t g, pom_error *err) {
  POM_TRY(pom_h5_attr_string(g, "architecture", pom_kin_arch_name(&ctx->arch), err));
  const pom_act_desc *u = pom_act_kind_desc(kind_of(ctx));
  /* stroke in the actuator's SI unit; stroke_m kept for prismatic files */
  POM_TRY(pom_h5_attr_double(g, "stroke", ctx->arch.stroke, err));
  if (u->legacy_keys) POM_TRY(pom_h5_attr_double(g, "stroke_m", ctx->arch.stroke, err));
  POM_TRY(pom_h5_attr_string(g, "actuator_kind", u->kind_name, err));
  POM_TRY(pom_doe_describe_dyn_params(g, &ctx->params, err));
  POM_TRY(pom_h5_attr_int64(g, "model_states", pom_dyn_model_n_states(ctx->model), err));
  return POM_OK;
}

static pom_status describe(const void *p, hid_t g, pom_error *err) {
  return pom_doe_dyn_describe_base(p, g, err);
}

pom_status pom_doe_dyn_evaluator_create(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                                        pom_error *err) {
  (void)user;
  return pom_doe_dyn_evaluator_create_ex(eval, cfg, NULL, err);
}

/* The model a model-based controller believes in, from ctrl_cfg, into a
 * model of the plant in ctx (docs/control.md section 1). */
static pom_status model_with_controller(dyn_ctx *ctx, const pom_cfg *ctrl_cfg, pom_error *err) {
  if (!ctrl_cfg || !pom_dyn_ctrl_of(&ctx->params.controller)->model_create)
    return pom_dyn_model_create(&ctx->model, &ctx->mech, &ctx->arch, &ctx->params, err);
  pom_kin_arch arch;
  pom_mechanism *mech = malloc(sizeof *mech);
  pom_dyn_params par;
  if (!mech) POM_FAIL(err, POM_ERR_NOMEM, "evaluator: out of memory");
  pom_status st = pom_kin_arch_load(&arch, ctrl_cfg, err);
  if (st == POM_OK) st = pom_kin_mechanism_build(mech, &arch, ctrl_cfg, err);
  pom_dyn_params_defaults(&par);
  if (st == POM_OK) st = pom_dyn_params_load(&par, ctrl_cfg, err);
  if (st == POM_OK)
    st = pom_dyn_model_create_ex(&ctx->model, &ctx->mech, &ctx->arch, &ctx->params, mech, &arch,
                                 &par, err);
  free(mech);
  return st;
}

pom_status pom_doe_dyn_evaluator_create_ex(pom_doe_evaluator *eval, const pom_cfg *cfg,
                                           const pom_cfg *ctrl_cfg, pom_error *err) {
  pom_status st = POM_OK;
  memset(eval, 0, sizeof *eval);
  /* every group the model reads; unknown keys there are errors */
  POM_TRY(pom_doe_evaluator_add_groups(eval, pom_kin_model_groups(), err));
  POM_TRY(pom_doe_evaluator_add_groups(eval, pom_dyn_param_groups(), err));
  dyn_ctx *ctx = calloc(1, sizeof *ctx);
  if (!ctx) POM_FAIL(err, POM_ERR_NOMEM, "evaluator: out of memory");
  POM_TRY_GOTO(pom_kin_arch_load(&ctx->arch, cfg, err), fail);
  POM_TRY_GOTO(pom_kin_mechanism_build(&ctx->mech, &ctx->arch, cfg, err), fail);
  pom_dyn_params_defaults(&ctx->params);
  POM_TRY_GOTO(pom_dyn_params_load(&ctx->params, cfg, err), fail);
  POM_TRY_GOTO(pom_cfg_check_unknown(cfg, eval->groups, NULL, err), fail);
  POM_TRY_GOTO(pom_doe_mech_actuator_kind(&ctx->mech, &eval->actuator_kind, err), fail);
  POM_TRY_GOTO(model_with_controller(ctx, ctrl_cfg, err), fail);
  eval->ctx = ctx;
  eval->ctx_destroy = ctx_destroy;
  eval->worker_create = pom_doe_dyn_worker_create;
  eval->worker_destroy = pom_doe_dyn_worker_destroy;
  eval->targets = pom_doe_dyn_targets;
  eval->run = pom_doe_dyn_run;
  eval->describe = describe;
  eval->dyn_base = 1;
  return POM_OK;
fail:
  ctx_destroy(ctx);
  memset(eval, 0, sizeof *eval);
  return st;
}

/* ---- end of stroke ------------------------------------------------------------- */
pom_status pom_doe_check_final_stroke(pom_dyn_metrics *out, double stroke, pom_error *err) {
  return pom_doe_check_final_stroke_kind(out, stroke, POM_ACT_PRISMATIC, err);
}

pom_status pom_doe_check_final_stroke_kind(pom_dyn_metrics *out, double stroke,
                                           pom_actuator_kind kind, pom_error *err) {
  if (out->status != POM_OK) return POM_OK; /* already a recorded failure */
  const pom_act_desc *u = pom_act_kind_desc(kind);
  double half = 0.5 * stroke, f = u->to_display;
  for (int i = 0; i < 3; ++i) {
    if (!(fabs(out->final_q[i]) <= half)) {
      out->status = POM_ERR_LIMIT;
      snprintf(out->reason, sizeof out->reason,
               "actuator %d ended outside its stroke: q = %.4g %s at the horizon (stroke +-%.4g "
               "%s; the model has no end stops)",
               i + 1, out->final_q[i] * f, u->display, half * f, u->display);
      return pom_error_set(err, POM_ERR_LIMIT, __FILE__, __LINE__, "%s", out->reason);
    }
    /* an excursion past the stroke that came back is just as impossible */
    if (!(out->max_abs_q[i] <= half)) {
      out->status = POM_ERR_LIMIT;
      snprintf(out->reason, sizeof out->reason,
               "actuator %d left its stroke during the maneuver: |q| reached %.4g %s (stroke "
               "+-%.4g %s; the model has no end stops)",
               i + 1, out->max_abs_q[i] * f, u->display, half * f, u->display);
      return pom_error_set(err, POM_ERR_LIMIT, __FILE__, __LINE__, "%s", out->reason);
    }
  }
  return POM_OK;
}

/* ---- candidate provenance ------------------------------------------------------ */
pom_status pom_doe_describe_dyn_params(hid_t g, const pom_dyn_params *par, pom_error *err) {
  POM_TRY(pom_dyn_params_h5_describe(g, par, err));             /* every parameter of the list */
  if (pom_dyn_ctrl_of(&par->controller) == &pom_dyn_ctrl_pid) { /* the names before types */
    POM_TRY(pom_h5_attr_double(g, "controller_ki", par->controller.ki, err));
    POM_TRY(pom_h5_attr_double(g, "controller_kd", par->controller.kd, err));
  }
  return POM_OK;
}
