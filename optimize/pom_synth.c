/* pom_synth.c - kinematic synthesis: design, responses, surfaces,
 * desirability optimum, confirmation, direct optimization and scaling
 * (docs/optimize.md, sections 5-7). */
#include "pom_synth.h"

#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- names and units ---------------------------------------------------- */
static const char *const resp_names[POM_SYN_N_RESP + 1] = {
    "rdw_deg",      "gci",    "min_dexterity", "footprint", "cone",
    "interference", "stroke", "unreachable",   NULL};

const char *pom_syn_var_name(const pom_syn_problem *pb, int i) {
  if (i < 0 || i >= pb->n_vars || !pb->base.type) return "?";
  return pb->base.type->params[pb->var[i]].key;
}
const char *pom_syn_resp_name(pom_syn_resp r) {
  return (r >= 0 && r < POM_SYN_N_RESP) ? resp_names[r] : "?";
}
double pom_syn_var_unit(const pom_syn_problem *pb, int i) {
  if (i < 0 || i >= pb->n_vars || !pb->base.type) return 1.0;
  return 1.0 / pb->base.type->params[pb->var[i]].to_si;
}
double pom_syn_resp_unit(pom_syn_resp r) {
  return r == POM_SYN_RESP_RDW ? 1.0 / POM_DEG : 1.0;
}

static double now_s(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* ---- defaults and config ------------------------------------------------ */
void pom_syn_defaults(pom_syn_problem *pb) {
  memset(pb, 0, sizeof *pb);
  pom_kin_ws_defaults(&pb->ws);
  pb->region_half_width = 10.0 * POM_DEG;
  pb->region_resolution = 1.0 * POM_DEG;
  pom_design_defaults(&pb->design);
  pb->holdout_points = 8;
  pom_rsm_defaults(&pb->rsm);
  pom_opt_defaults(&pb->surrogate_opt);
  pb->surrogate_opt.global_max_evals = 4000;
  pom_opt_defaults(&pb->direct_opt);
  pb->direct = 1;
  pb->direct_opt.global_max_evals = 150;
  pb->direct_opt.local = POM_OPT_LOCAL_SBPLX;
  pb->direct_opt.local_max_evals = 100;
  pb->direct_opt.local_xtol_rel = 1e-4;
  pb->target_half_width = 10.0 * POM_DEG;
  pb->scale_min = 1e-3;
  pb->scale_max = 0.2;
  pb->scale_rel_tol = 1e-3;
  pb->scale_scan = 24;
  pb->refine_stages = 0;
  pb->refine_shrink = 0.5;
  pb->scale_optimum = 1;
  pb->write = POM_SYN_WRITE_SURROGATE;
}

static const char *const write_names[] = {"surrogate", "direct", "best", NULL};

const char *pom_syn_write_name(pom_syn_write w) {
  return (w >= POM_SYN_WRITE_SURROGATE && w <= POM_SYN_WRITE_BEST) ? write_names[w] : "?";
}

static pom_status load_opt(const pom_cfg *cfg, const char *group, pom_opt_options *o,
                           pom_error *err) {
  static const char *const globals[] = {"none", "crs2", "direct_l", "isres", "esch", NULL};
  static const char *const locals[] = {"none", "bobyqa", "neldermead", "sbplx", "cobyla", NULL};
  char key[128];
  int g = (int)o->global, l = (int)o->local;
  long v = 0;
  snprintf(key, sizeof key, "%s.global", group);
  POM_TRY(pom_cfg_choice_opt(cfg, key, globals, g, &g, err));
  o->global = (pom_opt_global)g;
  snprintf(key, sizeof key, "%s.local", group);
  POM_TRY(pom_cfg_choice_opt(cfg, key, locals, l, &l, err));
  o->local = (pom_opt_local)l;
  snprintf(key, sizeof key, "%s.global_max_evals", group);
  POM_TRY(pom_cfg_int_opt(cfg, key, 1, 10000000, o->global_max_evals, &o->global_max_evals, err));
  snprintf(key, sizeof key, "%s.local_max_evals", group);
  POM_TRY(pom_cfg_int_opt(cfg, key, 1, 10000000, o->local_max_evals, &o->local_max_evals, err));
  snprintf(key, sizeof key, "%s.local_xtol_rel", group);
  POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, 0.0, 1.0, o->local_xtol_rel, &o->local_xtol_rel, err));
  snprintf(key, sizeof key, "%s.seed", group);
  POM_TRY(pom_cfg_int_opt(cfg, key, 0, 2147483647L, (long)o->seed, &v, err));
  o->seed = (unsigned long)v;
  snprintf(key, sizeof key, "%s.max_time_s", group);
  POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, 0.0, 1e6, o->max_time, &o->max_time, err));
  return POM_OK;
}

static pom_status load_design_opts(const pom_cfg *cfg, pom_design_options *d, pom_error *err) {
  static const char *const kinds[] = {"full_factorial", "ccd_face", "ccd_rotatable",
                                      "box_behnken",    "lhs",      NULL};
  int kind = (int)d->kind;
  long v = 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "synthesis.design.kind", kinds, kind, &kind, err));
  d->kind = (pom_design_kind)kind;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.design.levels", 2, 20, d->levels, &v, err));
  d->levels = (int)v;
  POM_TRY(
      pom_cfg_int_opt(cfg, "synthesis.design.center_points", 0, 100, d->center_points, &v, err));
  d->center_points = (int)v;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.design.replicates", 1, 100, d->replicates, &v, err));
  d->replicates = (int)v;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.design.lhs_points", 2, 100000, d->lhs_points, &v, err));
  d->lhs_points = (int)v;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.design.lhs_candidates", 1, 1000000, d->lhs_candidates, &v,
                          err));
  d->lhs_candidates = (int)v;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.design.seed", 0, 2147483647L, (long)d->seed, &v, err));
  d->seed = (uint64_t)v;
  return POM_OK;
}

pom_status pom_syn_load(pom_syn_problem *pb, const pom_cfg *cfg, pom_error *err) {
  static const char *const goals[] = {"maximize", "minimize", "target", NULL};
  char key[160];
  pom_syn_defaults(pb);
  POM_TRY(pom_kin_arch_load(&pb->base, cfg, err));
  if (!pb->base.has_design)
    return pom_cfg_error(cfg, "geometry.mode", NULL, err,
                         "synthesis needs the design-parameter form (mode = \"parameters\")");
  POM_TRY(pom_kin_ws_load(&pb->ws, cfg, err));
  if (!pom_cfg_has(cfg, "synthesis"))
    return pom_cfg_error(cfg, "synthesis", NULL, err,
                         "missing: expected a group { variables = (...); goals = (...); }");

  /* variables */
  int nv = pom_cfg_length(cfg, "synthesis.variables");
  if (nv < 1 || nv > POM_SYN_N_VARS)
    return pom_cfg_error(cfg, "synthesis.variables", NULL, err,
                         "expected a list of 1..%d groups { name = ...; min = ...; max = ...; }",
                         POM_SYN_N_VARS);
  pb->n_vars = nv;
  const pom_kin_arch_type *type = pb->base.type;
  for (int i = 0; i < nv; ++i) {
    char name[64];
    int id = -1;
    snprintf(key, sizeof key, "synthesis.variables.[%d].name", i);
    POM_TRY(pom_cfg_string(cfg, key, name, sizeof name, err));
    for (int k = 0; k < type->n_params; ++k)
      if (type->params[k].synth && strcmp(type->params[k].key, name) == 0) id = k;
    if (id < 0) {
      char list[512] = "";
      size_t used = 0;
      for (int k = 0; k < type->n_params; ++k) {
        if (!type->params[k].synth) continue;
        int w = snprintf(list + used, sizeof list - used, "%s%s", used ? ", " : "",
                         type->params[k].key);
        if (w > 0 && (size_t)w < sizeof list - used) used += (size_t)w;
      }
      return pom_cfg_error(cfg, key, name, err,
                           "not a design variable of the %s; expected one of: %s", type->name,
                           list);
    }
    for (int j = 0; j < i; ++j)
      if (pb->var[j] == id) return pom_cfg_error(cfg, key, name, err, "variable listed twice");
    pb->var[i] = id;
    const pom_kin_param_desc *pd = &type->params[id];
    snprintf(key, sizeof key, "synthesis.variables.[%d].min", i);
    POM_TRY(pom_cfg_real(cfg, key, pd->to_si, pd->lo, pd->hi, &pb->lo[i], err));
    snprintf(key, sizeof key, "synthesis.variables.[%d].max", i);
    POM_TRY(pom_cfg_real(cfg, key, pd->to_si, pd->lo, pd->hi, &pb->hi[i], err));
    if (!(pb->lo[i] < pb->hi[i])) return pom_cfg_error(cfg, key, NULL, err, "max must exceed min");
  }

  /* goals */
  int ng = pom_cfg_length(cfg, "synthesis.goals");
  if (ng < 1 || ng > POM_SYN_N_RESP)
    return pom_cfg_error(cfg, "synthesis.goals", NULL, err,
                         "expected a list of 1..%d groups { response = ...; goal = ...; low = ...; "
                         "high = ...; }",
                         POM_SYN_N_RESP);
  pb->n_goals = ng;
  for (int i = 0; i < ng; ++i) {
    int r = 0, g = 0;
    snprintf(key, sizeof key, "synthesis.goals.[%d].response", i);
    POM_TRY(pom_cfg_choice(cfg, key, resp_names, &r, err));
    pb->goal_resp[i] = (pom_syn_resp)r;
    double to_si = 1.0 / pom_syn_resp_unit((pom_syn_resp)r);
    pom_desir_spec *s = &pb->goal[i];
    *s = pom_desir_make(POM_DESIR_MAXIMIZE, 0.0, 0.0, 1.0);
    snprintf(key, sizeof key, "synthesis.goals.[%d].goal", i);
    POM_TRY(pom_cfg_choice(cfg, key, goals, &g, err));
    s->goal = (pom_desir_goal)g;
    snprintf(key, sizeof key, "synthesis.goals.[%d].low", i);
    POM_TRY(pom_cfg_real(cfg, key, to_si, -1e6, 1e6, &s->low, err));
    snprintf(key, sizeof key, "synthesis.goals.[%d].high", i);
    POM_TRY(pom_cfg_real(cfg, key, to_si, -1e6, 1e6, &s->high, err));
    snprintf(key, sizeof key, "synthesis.goals.[%d].target", i);
    if (s->goal == POM_DESIR_TARGET)
      POM_TRY(pom_cfg_real(cfg, key, to_si, -1e6, 1e6, &s->target, err));
    snprintf(key, sizeof key, "synthesis.goals.[%d].shape_low", i);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, 1e-3, 1e3, 1.0, &s->shape_low, err));
    snprintf(key, sizeof key, "synthesis.goals.[%d].shape_high", i);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, 1e-3, 1e3, 1.0, &s->shape_high, err));
    snprintf(key, sizeof key, "synthesis.goals.[%d].importance", i);
    POM_TRY(pom_cfg_real_opt(cfg, key, 1.0, 1e-3, 1e3, 1.0, &s->importance, err));
    pom_error sub;
    pom_error_clear(&sub);
    if (pom_desir_validate(s, resp_names[r], &sub) != POM_OK) {
      snprintf(key, sizeof key, "synthesis.goals.[%d]", i);
      return pom_cfg_error(cfg, key, NULL, err, "%s", sub.message);
    }
  }

  POM_TRY(load_design_opts(cfg, &pb->design, err));
  int in_study = 0; /* read by the study pipeline (pom_pipeline.h) */
  POM_TRY(pom_cfg_bool_opt(cfg, "synthesis.run_in_study", 0, &in_study, err));
  long v = 0;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.holdout_points", 0, 10000, pb->holdout_points, &v, err));
  pb->holdout_points = (int)v;
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.region_half_width_deg", POM_DEG, 0.01, 80.0,
                           pb->region_half_width, &pb->region_half_width, err));
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.region_resolution_deg", POM_DEG, 0.01, 20.0,
                           pb->region_resolution, &pb->region_resolution, err));
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.confidence", 1.0, 0.5, 0.9999, pb->rsm.confidence,
                           &pb->rsm.confidence, err));
  POM_TRY(load_opt(cfg, "synthesis.optimizer", &pb->surrogate_opt, err));
  POM_TRY(pom_cfg_bool_opt(cfg, "synthesis.direct.enabled", pb->direct, &pb->direct, err));
  POM_TRY(load_opt(cfg, "synthesis.direct", &pb->direct_opt, err));
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.target_half_width_deg", POM_DEG, 0.1, 80.0,
                           pb->target_half_width, &pb->target_half_width, err));
  if (pb->target_half_width > pb->ws.max_half_width)
    return pom_cfg_error(cfg, "synthesis.target_half_width_deg", NULL, err,
                         "exceeds the workspace search limit workspace.max_half_width (%g deg)",
                         pb->ws.max_half_width / POM_DEG);
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.scale_min_mm", 1e-3, 0.01, 1e5, pb->scale_min,
                           &pb->scale_min, err));
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.scale_max_mm", 1e-3, 0.01, 1e5, pb->scale_max,
                           &pb->scale_max, err));
  if (!(pb->scale_min < pb->scale_max))
    return pom_cfg_error(cfg, "synthesis.scale_max_mm", NULL, err, "must exceed scale_min_mm");
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.scale_rel_tol", 1.0, 1e-9, 0.1, pb->scale_rel_tol,
                           &pb->scale_rel_tol, err));
  long stages = pb->refine_stages;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.refine_stages", 0, 5, stages, &stages, err));
  pb->refine_stages = (int)stages;
  POM_TRY(pom_cfg_real_opt(cfg, "synthesis.refine_shrink", 1.0, 0.05, 0.95, pb->refine_shrink,
                           &pb->refine_shrink, err));
  int wr = (int)pb->write;
  POM_TRY(pom_cfg_choice_opt(cfg, "synthesis.write", write_names, wr, &wr, err));
  pb->write = (pom_syn_write)wr;
  if (pb->write == POM_SYN_WRITE_DIRECT && !pb->direct)
    return pom_cfg_error(cfg, "synthesis.write", "direct", err,
                         "needs the direct search (synthesis.direct.enabled = true)");
  long scan = pb->scale_scan;
  POM_TRY(pom_cfg_int_opt(cfg, "synthesis.scale_scan", 2, 1000, scan, &scan, err));
  pb->scale_scan = (int)scan;
  return pom_syn_cap_load(&pb->cap, &pb->base, cfg, err);
}

/* ---- geometry and responses --------------------------------------------- */
pom_status pom_syn_arch(const pom_syn_problem *pb, const double x[], double scale,
                        pom_kin_arch *arch, pom_error *err) {
  pom_kin_design d = pb->base.design;
  d.scale = scale;
  for (int i = 0; i < pb->n_vars; ++i)
    d.x[pb->var[i]] = x[i];
  POM_TRY(pom_kin_arch_from_design(arch, pb->base.type, &d, err));
  snprintf(arch->name, sizeof arch->name, "%s", pb->base.name);
  arch->stroke = pb->base.stroke;
  arch->central_joint = pb->base.central_joint;
  memcpy(arch->limit_bound, pb->base.limit_bound, sizeof arch->limit_bound);
  return POM_OK;
}

pom_status pom_syn_responses(const pom_syn_problem *pb, const pom_kin_arch *arch, double resp[],
                             pom_error *err) {
  pom_kin_ws_result ws;
  POM_TRY(pom_kin_workspace(arch, &pb->ws, &ws, err));
  resp[POM_SYN_RESP_RDW] = fmax(ws.half_width, 0.0);
  resp[POM_SYN_RESP_FOOTPRINT] = arch->type->footprint(arch) / arch->design.scale;

  /* Region cube, midpoint rule with the invariant measure cos(theta)
     (docs/optimize.md 5.2). */
  double a = pb->region_half_width;
  int m = (int)ceil(2.0 * a / pb->region_resolution - 1e-9);
  if (m < 1) m = 1;
  double h = 2.0 * a / m;
  double wsum = 0.0, w_cone = 0.0, w_dist = 0.0, w_stroke = 0.0, w_unreach = 0.0;
  double w_usable = 0.0, dex_usable = 0.0, dex_min = INFINITY;
  unsigned cone_bits = 0, dist_bits = 0, stroke_bits = 0;
  for (int k = 0; k < 3; ++k) {
    stroke_bits |= 1u << (POM_KIN_LIM_STROKE + k);
    for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
      pom_kin_limit_class cls = arch->type->limits[kind].cls;
      if (cls == POM_KIN_LIMCLASS_CONE) cone_bits |= 1u << (3 * kind + k);
      if (cls == POM_KIN_LIMCLASS_INTERFERENCE) dist_bits |= 1u << (3 * kind + k);
    }
  }
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        double e[3] = {-a + (i + 0.5) * h, -a + (j + 0.5) * h, -a + (k + 0.5) * h};
        double R[9], w = cos(e[1]);
        pom_kin_pose pose;
        pom_euler_zyx_to_matrix(R, e);
        pom_status st = pom_kin_pose_evaluate(arch, R, &pose, NULL);
        wsum += w;
        if (st == POM_ERR_UNREACHABLE || !pose.reachable) {
          w_unreach += w;
          dex_min = 0.0;
          continue;
        }
        if (st != POM_OK && st != POM_ERR_LIMIT)
          POM_FAIL(err, st, "region pose (%g, %g, %g) deg: %s", e[0] / POM_DEG, e[1] / POM_DEG,
                   e[2] / POM_DEG, pom_strerror(st));
        dex_min = fmin(dex_min, pose.dexterity);
        if (pose.violations & cone_bits) w_cone += w;
        if (pose.violations & dist_bits) w_dist += w;
        if (pose.violations & stroke_bits) w_stroke += w;
        if (pose.violations == 0) {
          w_usable += w;
          dex_usable += w * pose.dexterity;
        }
      }
  resp[POM_SYN_RESP_GCI] = w_usable > 0.0 ? dex_usable / w_usable : 0.0;
  resp[POM_SYN_RESP_MIN_DEXTERITY] = dex_min;
  resp[POM_SYN_RESP_CONE] = w_cone / wsum;
  resp[POM_SYN_RESP_INTERFERENCE] = w_dist / wsum;
  resp[POM_SYN_RESP_STROKE] = w_stroke / wsum;
  resp[POM_SYN_RESP_UNREACHABLE] = w_unreach / wsum;
  for (int r = 0; r < POM_SYN_N_RESP; ++r)
    if (!isfinite(resp[r]))
      POM_FAIL(err, POM_ERR_NONFINITE, "response %s is %g", resp_names[r], resp[r]);
  return POM_OK;
}

static void degenerate_responses(double resp[]) {
  resp[POM_SYN_RESP_RDW] = 0.0;
  resp[POM_SYN_RESP_GCI] = 0.0;
  resp[POM_SYN_RESP_MIN_DEXTERITY] = 0.0;
  resp[POM_SYN_RESP_FOOTPRINT] = 0.0;
  resp[POM_SYN_RESP_CONE] = 0.0;
  resp[POM_SYN_RESP_INTERFERENCE] = 0.0;
  resp[POM_SYN_RESP_STROKE] = 0.0;
  resp[POM_SYN_RESP_UNREACHABLE] = 1.0;
}

pom_status pom_syn_evaluate(const pom_syn_problem *pb, const double x[], double resp[],
                            int *degenerate, pom_error *err) {
  pom_kin_arch arch;
  pom_error sub;
  pom_error_clear(&sub);
  if (degenerate) *degenerate = 0;
  pom_status st = pom_syn_arch(pb, x, pb->base.design.scale, &arch, &sub);
  if (st == POM_ERR_ARG) {
    /* No assembly or a singular Jacobian at home: no workspace at all. */
    degenerate_responses(resp);
    if (degenerate) *degenerate = 1;
    return POM_OK;
  }
  if (st != POM_OK) {
    if (err) *err = sub;
    return st;
  }
  return pom_syn_responses(pb, &arch, resp, err);
}

double pom_syn_desirability(const pom_syn_problem *pb, const double resp[], double d[]) {
  double y[POM_SYN_N_RESP];
  for (int i = 0; i < pb->n_goals; ++i)
    y[i] = resp[pb->goal_resp[i]];
  return pom_desir_overall(pb->n_goals, pb->goal, y, d);
}

/* ---- run: begin and step ------------------------------------------------ */
void pom_syn_destroy(pom_syn_run *run) {
  if (!run) return;
  pom_syn_destroy(run->refined);
  free(run->refined_pb);
  pom_design_destroy(run->design);
  free(run->x);
  free(run->resp);
  free(run->holdout_x);
  free(run->holdout_resp);
  free(run);
}

pom_status pom_syn_begin(pom_syn_run **out, const pom_syn_problem *pb, pom_error *err) {
  pom_status st = POM_OK;
  *out = NULL;
  if (pb->n_vars < 1 || pb->n_vars > POM_RSM_MAX_K)
    POM_FAIL(err, POM_ERR_ARG, "synthesis: %d variables, expected 1..%d", pb->n_vars,
             POM_RSM_MAX_K);
  pom_syn_run *run = calloc(1, sizeof *run);
  if (!run) POM_FAIL(err, POM_ERR_NOMEM, "synthesis: out of memory");
  run->pb = pb;
  POM_TRY_GOTO(pom_design_create(&run->design, pb->n_vars, &pb->design, err), fail);
  run->n_runs = run->design->n;
  run->x = malloc(sizeof(double) * (size_t)run->n_runs * (size_t)pb->n_vars);
  run->resp = malloc(sizeof(double) * (size_t)run->n_runs * POM_SYN_N_RESP);
  if (!run->x || !run->resp) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "synthesis: out of memory");
  pom_design_decode(run->design, pb->lo, pb->hi, run->x);
  *out = run;
  return POM_OK;
fail:
  pom_syn_destroy(run);
  return st;
}

static pom_status cap_filter(pom_syn_run *run, pom_error *err); /* below */

static void report(const pom_syn_run *run, const char *phase, long done, long total) {
  if (run->progress) run->progress(run->progress_user, phase, done, total);
}

pom_status pom_syn_step(pom_syn_run *run, int *remaining, pom_error *err) {
  const pom_syn_problem *pb = run->pb;
  if (run->next < run->n_runs) {
    double t0 = now_s();
    int degenerate = 0;
    int r = run->next;
    POM_TRY(pom_syn_evaluate(pb, run->x + r * pb->n_vars, run->resp + r * POM_SYN_N_RESP,
                             &degenerate, err));
    run->n_degenerate += degenerate;
    run->next++;
    run->design_time += now_s() - t0;
    report(run, run->pb->scale_optimum ? "design" : "refine", run->next, run->n_runs);
  }
  if (remaining) *remaining = run->n_runs - run->next;
  return POM_OK;
}

/* ---- objectives ----------------------------------------------------------- */
typedef struct {
  const pom_syn_run *run;
  double constant[POM_SYN_N_RESP]; /* value of responses without a surface */
} surrogate_ctx;

static void predict_all(const surrogate_ctx *c, const double u[], double resp[]) {
  for (int r = 0; r < POM_SYN_N_RESP; ++r)
    resp[r] = c->run->fitted[r] ? pom_rsm_predict(&c->run->fit[r], u, NULL) : c->constant[r];
}

static pom_status surrogate_objective(void *ctx, const double u[], double *f, pom_error *err) {
  const surrogate_ctx *c = ctx;
  double resp[POM_SYN_N_RESP];
  (void)err;
  predict_all(c, u, resp);
  *f = pom_syn_desirability(c->run->pb, resp, NULL);
  return POM_OK;
}

typedef struct {
  const pom_syn_problem *pb;
  double alpha;
  pom_syn_run *run; /* progress */
} direct_ctx;

static void coded_to_x(const pom_syn_problem *pb, double alpha, const double u[], double x[]) {
  for (int i = 0; i < pb->n_vars; ++i)
    x[i] = pom_design_to_natural(u[i], alpha, pb->lo[i], pb->hi[i]);
}

static pom_status direct_objective(void *ctx, const double u[], double *f, pom_error *err) {
  const direct_ctx *c = ctx;
  double x[POM_SYN_N_VARS], resp[POM_SYN_N_RESP];
  coded_to_x(c->pb, c->alpha, u, x);
  POM_TRY(pom_syn_evaluate(c->pb, x, resp, NULL, err));
  *f = pom_syn_desirability(c->pb, resp, NULL);
  const pom_opt_options *o = &c->pb->direct_opt;
  report(c->run, "direct", ++c->run->direct_evals_seen,
         (long)o->global_max_evals * (o->global != POM_OPT_GLOBAL_NONE) +
             (long)o->local_max_evals * (o->local != POM_OPT_LOCAL_NONE));
  return POM_OK;
}

/* ---- sequential refinement -------------------------------------------------- */
/* Stage k + 1: the same design kind in a box refine_shrink times as wide,
 * centred on the confirmed optimum of stage k and moved inside stage k's box
 * (docs/optimize.md 7.1). The best confirmed stage wins. */
static pom_status refine(pom_syn_run *run, pom_error *err) {
  const pom_syn_problem *pb = run->pb;
  pom_syn_problem *sub = malloc(sizeof *sub);
  if (!sub) POM_FAIL(err, POM_ERR_NOMEM, "synthesis refinement: out of memory");
  *sub = *pb;
  run->refined_pb = sub;
  sub->refine_stages = pb->refine_stages - 1;
  sub->direct = 0;
  sub->scale_optimum = 0;
  sub->design.seed = pb->design.seed + 1;
  for (int i = 0; i < pb->n_vars; ++i) {
    double w = (pb->hi[i] - pb->lo[i]) * pb->refine_shrink;
    double lo = run->x_opt[i] - 0.5 * w, hi = run->x_opt[i] + 0.5 * w;
    if (lo < pb->lo[i]) {
      lo = pb->lo[i];
      hi = lo + w;
    }
    if (hi > pb->hi[i]) {
      hi = pb->hi[i];
      lo = hi - w;
    }
    sub->lo[i] = lo;
    sub->hi[i] = hi;
  }
  POM_TRY(pom_syn_begin(&run->refined, sub, err));
  run->refined->progress = run->progress;
  run->refined->progress_user = run->progress_user;
  POM_TRY(pom_syn_finish(run->refined, err));
  const pom_syn_run *r2 = run->refined;
  run->true_evals += r2->true_evals;
  if (r2->d_confirmed > run->d_confirmed) {
    memcpy(run->x_opt, r2->x_opt, sizeof run->x_opt);
    memcpy(run->predicted, r2->predicted, sizeof run->predicted);
    memcpy(run->confirmed, r2->confirmed, sizeof run->confirmed);
    run->d_predicted = r2->d_predicted;
    run->d_confirmed = r2->d_confirmed;
    run->best_stage = 1 + r2->best_stage;
  }
  return POM_OK;
}

/* ---- finish --------------------------------------------------------------- */
pom_status pom_syn_finish(pom_syn_run *run, pom_error *err) {
  const pom_syn_problem *pb = run->pb;
  const int k = pb->n_vars;
  pom_status st = POM_OK;
  double *y = NULL, *uh = NULL;
  int remaining = 0;
  do {
    POM_TRY(pom_syn_step(run, &remaining, err));
  } while (remaining > 0);
  double t0 = now_s();

  /* Surfaces: one per response that varies over the design. */
  y = malloc(sizeof(double) * (size_t)run->n_runs);
  if (!y) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "synthesis: out of memory");
  surrogate_ctx sc;
  memset(&sc, 0, sizeof sc);
  sc.run = run;
  for (int r = 0; r < POM_SYN_N_RESP; ++r) {
    double ymin = INFINITY, ymax = -INFINITY;
    for (int i = 0; i < run->n_runs; ++i) {
      y[i] = run->resp[i * POM_SYN_N_RESP + r];
      ymin = fmin(ymin, y[i]);
      ymax = fmax(ymax, y[i]);
    }
    if (ymax == ymin) {
      run->fitted[r] = 0;
      sc.constant[r] = ymin;
      continue;
    }
    POM_TRY_GOTO(
        pom_rsm_fit_quadratic(&run->fit[r], k, run->n_runs, run->design->coded, y, &pb->rsm, err),
        fail_fit);
    run->fitted[r] = 1;
    continue;
  fail_fit:
    pom_error_prefix(err, "surface of %s", resp_names[r]);
    goto done;
  }

  /* Held-out check on a separate Latin hypercube (its own seed). */
  if (pb->holdout_points > 0) {
    pom_design_options ho;
    pom_design_defaults(&ho);
    ho.kind = POM_DESIGN_LHS;
    ho.center_points = 0;
    ho.lhs_points = pb->holdout_points < 2 ? 2 : pb->holdout_points;
    ho.seed = pb->design.seed + 7919;
    pom_design *hd = NULL;
    POM_TRY_GOTO(pom_design_create(&hd, k, &ho, err), done);
    run->n_holdout = hd->n;
    run->holdout_x = malloc(sizeof(double) * (size_t)hd->n * (size_t)k);
    run->holdout_resp = malloc(sizeof(double) * (size_t)hd->n * POM_SYN_N_RESP);
    uh = malloc(sizeof(double) * (size_t)hd->n * (size_t)k);
    if (!run->holdout_x || !run->holdout_resp || !uh) {
      pom_design_destroy(hd);
      POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "synthesis: out of memory");
    }
    pom_design_decode(hd, pb->lo, pb->hi, run->holdout_x);
    pom_design_destroy(hd);
    /* coded units of the fitted design for the same natural points */
    for (int i = 0; i < run->n_holdout * k; ++i)
      uh[i] =
          pom_design_to_coded(run->holdout_x[i], run->design->alpha, pb->lo[i % k], pb->hi[i % k]);
    for (int i = 0; i < run->n_holdout; ++i) {
      POM_TRY_GOTO(pom_syn_evaluate(pb, run->holdout_x + i * k,
                                    run->holdout_resp + i * POM_SYN_N_RESP, NULL, err),
                   done);
      report(run, "held-out", i + 1, run->n_holdout);
    }
    double *yh = malloc(sizeof(double) * (size_t)run->n_holdout);
    if (!yh) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "synthesis: out of memory");
    for (int r = 0; r < POM_SYN_N_RESP; ++r) {
      if (!run->fitted[r]) continue;
      for (int i = 0; i < run->n_holdout; ++i)
        yh[i] = run->holdout_resp[i * POM_SYN_N_RESP + r];
      pom_rsm_validate(&run->fit[r], run->n_holdout, uh, yh, pb->rsm.confidence, &run->check[r]);
    }
    free(yh);
  }

  /* Desirability on the surfaces, in the design's coded box. */
  {
    double lo[POM_SYN_N_VARS], hi[POM_SYN_N_VARS], u[POM_SYN_N_VARS];
    for (int i = 0; i < k; ++i) {
      lo[i] = -run->design->alpha;
      hi[i] = run->design->alpha;
    }
    POM_TRY_GOTO(pom_opt_maximize(k, lo, hi, NULL, surrogate_objective, &sc, &pb->surrogate_opt,
                                  &run->surrogate, err),
                 surrogate_failed);
    memcpy(u, run->surrogate.x, sizeof(double) * (size_t)k);
    coded_to_x(pb, run->design->alpha, u, run->x_opt);
    predict_all(&sc, u, run->predicted);
    run->d_predicted = pom_syn_desirability(pb, run->predicted, NULL);
    /* Confirmation on the true kinematics. */
    POM_TRY_GOTO(pom_syn_evaluate(pb, run->x_opt, run->confirmed, NULL, err), done);
    run->d_confirmed = pom_syn_desirability(pb, run->confirmed, NULL);
  }
  run->true_evals = run->n_runs + run->n_holdout + 1;
  memcpy(run->stage_x_opt, run->x_opt, sizeof run->x_opt);
  run->stage_d_predicted = run->d_predicted;
  run->stage_d_confirmed = run->d_confirmed;
  if (pb->refine_stages > 0) {
    st = refine(run, err);
    if (st != POM_OK) {
      pom_error_prefix(err, "refinement stage");
      goto done;
    }
  }
  run->surrogate_time = run->design_time + (now_s() - t0);

  /* The same problem directly on the true kinematics. */
  if (pb->direct) {
    double lo[POM_SYN_N_VARS], hi[POM_SYN_N_VARS];
    for (int i = 0; i < k; ++i) {
      lo[i] = -1.0;
      hi[i] = 1.0;
    }
    direct_ctx dc = {pb, 1.0, run};
    POM_TRY_GOTO(pom_opt_maximize(k, lo, hi, NULL, direct_objective, &dc, &pb->direct_opt,
                                  &run->direct, err),
                 direct_failed);
    coded_to_x(pb, 1.0, run->direct.x, run->x_direct);
    POM_TRY_GOTO(pom_syn_evaluate(pb, run->x_direct, run->direct_resp, NULL, err), done);
    run->d_direct = pom_syn_desirability(pb, run->direct_resp, NULL);
    run->direct_done = 1;
  }

  /* Scale the chosen optimum to the stroke (synthesis.write): both
     desirabilities are true ones at the base scale, so "best" compares like
     with like. */
  if (!pb->scale_optimum) goto done;
  run->direct_better = run->direct_done && run->d_direct > run->d_confirmed;
  run->written_direct =
      pb->write == POM_SYN_WRITE_DIRECT || (pb->write == POM_SYN_WRITE_BEST && run->direct_better);
  if (run->written_direct && !run->direct_done)
    POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                  "synthesis.write = \"direct\" needs the direct search, which did not run");
  memcpy(run->x_written, run->written_direct ? run->x_direct : run->x_opt, sizeof run->x_written);
  run->d_written = run->written_direct ? run->d_direct : run->d_confirmed;
  report(run, "scale", 0, 1);
  POM_TRY_GOTO(pom_syn_scale(pb, run->x_written, &run->scale, &run->scale_evals, err),
               scale_failed);
  report(run, "scale", 1, 1);
  POM_TRY_GOTO(pom_syn_arch(pb, run->x_written, run->scale, &run->scaled, err), done);
  POM_TRY_GOTO(pom_syn_responses(pb, &run->scaled, run->scaled_resp, err), done);
  run->scaled_done = 1;
  /* the capability floor on the final optima (synthesis.capability_require) */
  POM_TRY_GOTO(cap_filter(run, err), done);
  goto done;

surrogate_failed:
  pom_error_prefix(err, "optimum on the surfaces");
  goto done;
direct_failed:
  pom_error_prefix(err, "direct optimization");
  goto done;
scale_failed:
  pom_error_prefix(err, "scaling the optimum");
done:
  free(y);
  free(uh);
  return st;
}

/* ---- the capability floor (docs/optimize.md 6b) ----------------------------------- */
/* The optimum pb->write chose, as scaled, is checked; when it fails and the
 * direct search found another point, that one is scaled and checked, and
 * written when it meets the floor. pom_synth_cap.c evaluates. */
static pom_status cap_filter(pom_syn_run *run, pom_error *err) {
  const pom_syn_problem *pb = run->pb;
  run->n_cap_checks = 0;
  run->cap_met = 0;
  run->cap_switched = 0;
  if (pb->cap.n == 0 || !run->scaled_done) return POM_OK;
  int other = run->direct_done; /* a second optimum exists */
  if (other) other = memcmp(run->x_opt, run->x_direct, sizeof(double) * (size_t)pb->n_vars) != 0;
  pom_syn_cap_check *a = &run->cap_check[run->n_cap_checks++];
  pom_syn_cap_check_start(a, run->written_direct, run->x_written, run->d_written);
  a->scale = run->scale;
  report(run, "capability", 0, 1 + other);
  POM_TRY(pom_syn_cap_check_arch(&pb->cap, &pb->ws, &run->scaled, a, err));
  report(run, "capability", 1, 1 + other);
  run->cap_met = a->all_met;
  if (a->all_met || !other) return POM_OK;
  pom_syn_cap_check *b = &run->cap_check[run->n_cap_checks++];
  int direct = !a->direct;
  pom_syn_cap_check_start(b, direct, direct ? run->x_direct : run->x_opt,
                          direct ? run->d_direct : run->d_confirmed);
  pom_error e;
  pom_error_clear(&e);
  int evals = 0;
  pom_kin_arch arch;
  pom_status st = pom_syn_scale(pb, b->x, &b->scale, &evals, &e);
  if (st == POM_OK) st = pom_syn_arch(pb, b->x, b->scale, &arch, &e);
  if (st != POM_OK) {
    char why[sizeof b->note];
    snprintf(why, sizeof why, "not scaled to the stroke: %s", e.message);
    b->scale = NAN;
    pom_syn_cap_check_unevaluated(&pb->cap, b, why);
    report(run, "capability", 2, 2);
    return POM_OK;
  }
  POM_TRY(pom_syn_cap_check_arch(&pb->cap, &pb->ws, &arch, b, err));
  report(run, "capability", 2, 2);
  if (!b->all_met) return POM_OK;
  run->written_direct = b->direct;
  memcpy(run->x_written, b->x, sizeof run->x_written);
  run->d_written = b->d;
  run->scale = b->scale;
  run->scaled = arch;
  run->scale_evals += evals;
  POM_TRY(pom_syn_responses(pb, &run->scaled, run->scaled_resp, err));
  run->cap_met = 1;
  run->cap_switched = 1;
  return POM_OK;
}

void pom_syn_cap_failure(const pom_syn_run *run, char *buf, size_t cap) {
  pom_syn_cap_failure_text(&run->pb->cap, run->cap_check, run->n_cap_checks, buf, cap);
}

/* ---- scaling ---------------------------------------------------------------- */
static pom_status rdw_at(const pom_syn_problem *pb, const double x[], double scale, double *hw,
                         pom_error *err) {
  pom_kin_arch arch;
  pom_kin_ws_result ws;
  POM_TRY(pom_syn_arch(pb, x, scale, &arch, err));
  POM_TRY(pom_kin_workspace(&arch, &pb->ws, &ws, err));
  *hw = ws.half_width;
  return POM_OK;
}

pom_status pom_syn_scale(const pom_syn_problem *pb, const double x[], double *scale, int *evals,
                         pom_error *err) {
  /* The workspace is a multiple of the grid step: a target on the grid needs
     only round-off slack, and a target between two steps needs the upper one
     (half a step of slack accepted a workspace below the target). */
  const double need = pb->target_half_width - 1e-9 * pb->ws.resolution;
  const double ratio = pb->scale_max / pb->scale_min;
  if (!pb->base.type->scale_sets_kinematics) {
    /* Angles alone fix this architecture's kinematics: the scale (e.g. the
     * 3-RRR link radius) changes no workspace, so the base scale is kept and
     * the target is only checked (docs/extending.md, docs/optimize.md 6). */
    double hw0 = 0.0;
    POM_TRY(rdw_at(pb, x, pb->base.design.scale, &hw0, err));
    if (evals) *evals = 1;
    if (hw0 < need)
      POM_FAIL(err, POM_ERR_LIMIT,
               "the %s's workspace is +-%.3g deg, short of the target +-%.3g deg; its scale (%s) "
               "does not change the kinematics, so no scaling can reach it",
               pb->base.type->label, hw0 / POM_DEG, pb->target_half_width / POM_DEG,
               pb->base.type->scale_key);
    *scale = pb->base.design.scale;
    return POM_OK;
  }
  double hw = 0.0, best_hw = -INFINITY, best_scale = pb->scale_max;
  int n = 0;
  /* Scan down from the largest radius on a log grid: the workspace grows as
     the radius shrinks (the stroke turns the platform further) until the
     clearance or the dexterity limits take over, so the first radius that
     covers the target brackets the largest one (docs/optimize.md 6). */
  double covered = NAN, not_covered = NAN;
  for (int s = 0; s <= pb->scale_scan; ++s) {
    double sc = pb->scale_max * pow(ratio, -(double)s / pb->scale_scan);
    POM_TRY(rdw_at(pb, x, sc, &hw, err));
    ++n;
    if (hw > best_hw) {
      best_hw = hw;
      best_scale = sc;
    }
    if (hw >= need) {
      covered = sc;
      break;
    }
    not_covered = sc;
  }
  if (evals) *evals = n;
  if (isnan(covered))
    POM_FAIL(err, POM_ERR_LIMIT,
             "no platform radius in [%.4g, %.4g] mm gives the target workspace of +-%.3g deg; "
             "the best is +-%.3g deg at %.4g mm (limited by dexterity, cones or clearance)",
             pb->scale_min * 1e3, pb->scale_max * 1e3, pb->target_half_width / POM_DEG,
             best_hw / POM_DEG, best_scale * 1e3);
  if (isnan(not_covered)) {
    *scale = covered; /* the largest radius allowed already covers it */
    return POM_OK;
  }
  /* Bisection in log(radius): covered at lo, not at hi. */
  double lo = covered, hi = not_covered;
  while (hi / lo - 1.0 > pb->scale_rel_tol) {
    double mid = sqrt(lo * hi);
    POM_TRY(rdw_at(pb, x, mid, &hw, err));
    ++n;
    if (hw >= need)
      lo = mid;
    else
      hi = mid;
  }
  *scale = lo;
  if (evals) *evals = n;
  return POM_OK;
}
