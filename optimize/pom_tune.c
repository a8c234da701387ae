/* pom_tune.c - gain tuning of any controller type (the gains its
 * descriptors mark tunable), one criterion for every architecture
 * (docs/optimize.md, section 9). */
#include "pom_tune.h"
#include "pom_dyn_ctrl.h"
#include "pom_io.h"

#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* A setpoint within this fraction of the stroke of mid-stroke is no step (an
 * orientation of zero turns into setpoints of rounding size through the IK). */
#define TUNE_ZERO_STEP 1e-12
/* Criterion values within this relative spread are one value: the rounding of
 * a sum of a few settling times, far below any real difference between gains. */
#define TUNE_FLAT_REL 1e-12

const char *pom_tune_var_name(pom_tune_var v) {
  return ((int)v >= 0 && (int)v < pom_dyn_ctrl_pid.n_gains) ? pom_dyn_ctrl_pid.gains[v].key : "?";
}

/* The controller type's default search: its gains marked search_default,
 * with their default bounds. */
static void default_variables(pom_tune_problem *pb) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(&pb->params.controller);
  pb->n_vars = 0;
  for (int k = 0; k < t->n_gains; ++k) {
    const pom_dyn_gain_desc *g = &t->gains[k];
    if (!g->tunable || !g->search_default) continue;
    pb->var[pb->n_vars] = (pom_tune_var)k;
    pb->lo[pb->n_vars] = g->search_lo;
    pb->hi[pb->n_vars] = g->search_hi;
    pb->log_scale[pb->n_vars] = g->log_search;
    ++pb->n_vars;
  }
}

/* "kp 1.2e4 V/V, kd_s 0.003 s" for messages: the tuned gains of c. */
static void gains_text(char *buf, size_t cap, const pom_tune_problem *pb,
                       const pom_dyn_controller *c) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(c);
  size_t len = 0;
  buf[0] = '\0';
  for (int k = 0; k < t->n_gains && len < cap; ++k) {
    int w = snprintf(buf + len, cap - len, "%s%s %.6g %s", k ? ", " : "", t->gains[k].key,
                     pom_dyn_ctrl_gain(c, k), t->gains[k].unit);
    if (w < 0) break;
    len += (size_t)w;
  }
  (void)pb;
}

static double now_s(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The default maneuver set (mm): the extreme corners of the Monte-Carlo
 * cube, mixed-sign, uneven and small steps (a small step's 2 % band exposes
 * a soft loop's steady-state error), identical for every architecture. */
#define N_DEFAULT_MANEUVERS 7
static const double default_targets_mm[N_DEFAULT_MANEUVERS][3] = {
    {3.0, 3.0, 3.0},   {-3.0, -3.0, -3.0}, {3.0, -3.0, 0.0}, {-2.0, 1.0, 3.0},
    {1.5, -2.5, -1.0}, {0.5, 2.0, -2.0},   {0.2, -0.1, -3.0}};

void pom_tune_defaults(pom_tune_problem *pb) {
  memset(pb, 0, sizeof *pb);
  pom_dyn_params_defaults(&pb->params);
  default_variables(pb); /* the PID's: kp in [1e2, 1e5] and kd_s in [5e-4, 2e-2], in log */
  pb->n_maneuvers = N_DEFAULT_MANEUVERS;
  snprintf(pb->maneuvers_where, sizeof pb->maneuvers_where, "the tuning maneuvers");
  for (int m = 0; m < N_DEFAULT_MANEUVERS; ++m)
    for (int i = 0; i < 3; ++i)
      pb->target[m][i] = default_targets_mm[m][i] * 1e-3;
  pb->overshoot_max = 0.05;
  pb->saturation_time_max = 0.02;
  pb->penalty_weight = pb->params.maneuver.horizon;
  pom_opt_defaults(&pb->opt);
  pb->opt.global = POM_OPT_GLOBAL_DIRECT_L;
  pb->opt.global_max_evals = 40;
  pb->opt.local = POM_OPT_LOCAL_BOBYQA;
  pb->opt.local_max_evals = 40;
  pb->opt.local_xtol_rel = 1e-3;
}

static pom_status load_opt(const pom_cfg *cfg, pom_opt_options *o, pom_error *err) {
  static const char *const globals[] = {"none", "crs2", "direct_l", "isres", "esch", NULL};
  static const char *const locals[] = {"none", "bobyqa", "neldermead", "sbplx", "cobyla", NULL};
  int g = (int)o->global, l = (int)o->local;
  long v = 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "tuning.optimizer.global", globals, g, &g, err));
  o->global = (pom_opt_global)g;
  POM_TRY(pom_cfg_choice_opt(cfg, "tuning.optimizer.local", locals, l, &l, err));
  o->local = (pom_opt_local)l;
  POM_TRY(pom_cfg_int_opt(cfg, "tuning.optimizer.global_max_evals", 1, 1000000, o->global_max_evals,
                          &o->global_max_evals, err));
  POM_TRY(pom_cfg_int_opt(cfg, "tuning.optimizer.local_max_evals", 1, 1000000, o->local_max_evals,
                          &o->local_max_evals, err));
  POM_TRY(pom_cfg_real_opt(cfg, "tuning.optimizer.local_xtol_rel", 1.0, 0.0, 1.0, o->local_xtol_rel,
                           &o->local_xtol_rel, err));
  POM_TRY(pom_cfg_int_opt(cfg, "tuning.optimizer.seed", 0, 2147483647L, (long)o->seed, &v, err));
  o->seed = (unsigned long)v;
  /* the multi-start local stage (docs/optimize.md 9): off by default */
  POM_TRY(pom_cfg_int_opt(cfg, "tuning.optimizer.local_starts", 1, POM_OPT_MAX_STARTS,
                          o->local_starts, &v, err));
  o->local_starts = (int)v;
  POM_TRY(pom_cfg_real_opt(cfg, "tuning.optimizer.local_start_separation", 1.0, 1e-3, 1.0,
                           o->local_start_separation, &o->local_start_separation, err));
  return POM_OK;
}

pom_status pom_tune_load(pom_tune_problem *pb, const pom_cfg *cfg, pom_error *err) {
  char key[128];
  pom_tune_defaults(pb);
  POM_TRY(pom_kin_arch_load(&pb->arch, cfg, err));
  POM_TRY(pom_kin_mechanism_build(&pb->mech, &pb->arch, cfg, err));
  POM_TRY(pom_dyn_params_load(&pb->params, cfg, err));
  pb->penalty_weight = pb->params.maneuver.horizon;
  default_variables(pb); /* the loaded controller type's */
  snprintf(pb->maneuvers_where, sizeof pb->maneuvers_where,
           "%s: the default tuning maneuvers (no tuning.maneuvers_* key)", pom_cfg_path(cfg));
  if (!pom_cfg_has(cfg, "tuning")) return POM_OK; /* every tuning key has a default */

  /* the names tuning.variables may use: the type's tunable gains */
  const pom_dyn_ctrl_type *ct = pom_dyn_ctrl_of(&pb->params.controller);
  const char *var_names[POM_DYN_CTRL_MAX_GAINS + 1];
  int var_gain[POM_DYN_CTRL_MAX_GAINS], n_tunable = 0;
  char names_text[256] = "";
  for (int k = 0; k < ct->n_gains; ++k) {
    if (!ct->gains[k].tunable) continue;
    size_t len = strlen(names_text);
    snprintf(names_text + len, sizeof names_text - len, "%s\"%s\"", n_tunable ? "|" : "",
             ct->gains[k].key);
    var_gain[n_tunable] = k;
    var_names[n_tunable++] = ct->gains[k].key;
  }
  var_names[n_tunable] = NULL;
  int nv = pom_cfg_length(cfg, "tuning.variables");
  if (pom_cfg_has(cfg, "tuning.variables")) {
    if (nv < 1 || nv > n_tunable)
      return pom_cfg_error(cfg, "tuning.variables", NULL, err,
                           "expected 1..%d groups { name = %s; min = ...; max = ...; log = "
                           "true|false; } (the tunable gains of controller %s)",
                           n_tunable, names_text, ct->name);
    pb->n_vars = nv;
    for (int i = 0; i < nv; ++i) {
      int id = 0;
      snprintf(key, sizeof key, "tuning.variables.[%d].name", i);
      POM_TRY(pom_cfg_choice(cfg, key, var_names, &id, err));
      id = var_gain[id];
      for (int j = 0; j < i; ++j)
        if ((int)pb->var[j] == id)
          return pom_cfg_error(cfg, key, ct->gains[id].key, err, "gain listed twice");
      pb->var[i] = (pom_tune_var)id;
      snprintf(key, sizeof key, "tuning.variables.[%d].min", i);
      POM_TRY(pom_cfg_real(cfg, key, 1.0, ct->gains[id].lo, ct->gains[id].hi, &pb->lo[i], err));
      snprintf(key, sizeof key, "tuning.variables.[%d].max", i);
      POM_TRY(pom_cfg_real(cfg, key, 1.0, ct->gains[id].lo, ct->gains[id].hi, &pb->hi[i], err));
      if (!(pb->lo[i] < pb->hi[i]))
        return pom_cfg_error(cfg, key, NULL, err, "max must exceed min");
      snprintf(key, sizeof key, "tuning.variables.[%d].log", i);
      POM_TRY(pom_cfg_bool_opt(cfg, key, ct->gains[id].log_search, &pb->log_scale[i], err));
      if (pb->log_scale[i] && !(pb->lo[i] > 0.0)) {
        snprintf(key, sizeof key, "tuning.variables.[%d].min", i);
        return pom_cfg_error(cfg, key, NULL, err, "a log-scaled gain needs min > 0");
      }
    }
  }
  /* Tuning maneuvers: actuator setpoints in the actuator's display unit
   * (maneuvers_mm for linear, maneuvers_deg for rotary actuators) or platform
   * orientations (maneuvers_euler_deg, ZYX, deg) turned into setpoints by the
   * candidate's IK: the same platform motions for every architecture, the
   * fair criterion when candidates mix actuator kinds (docs/optimize.md 9). */
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(pb->arch.type));
  char own[64], other[64];
  snprintf(own, sizeof own, "tuning.maneuvers%s", u->key_suffix);
  const char *euler = "tuning.maneuvers_euler_deg";
  for (int k = 0; k < POM_ACT_KINDS; ++k) {
    snprintf(other, sizeof other, "tuning.maneuvers%s",
             pom_act_kind_desc((pom_actuator_kind)k)->key_suffix);
    if (strcmp(other, own) != 0 && pom_cfg_has(cfg, other))
      return pom_cfg_error(cfg, other, NULL, err,
                           "the %s's actuators are %s (q in %s): use %s, or %s for platform "
                           "orientations",
                           pom_kin_type_label(pb->arch.type), u->kind_name, u->display, own + 7,
                           euler + 7);
  }
  if (pom_cfg_has(cfg, own) && pom_cfg_has(cfg, euler))
    return pom_cfg_error(cfg, euler, NULL, err, "give either %s or %s, not both", own + 7,
                         euler + 7);
  const char *mkey = pom_cfg_has(cfg, euler) ? euler : pom_cfg_has(cfg, own) ? own : NULL;
  if (!mkey && u->angular) {
    /* the linear defaults through the 15 mm/rad lever of the isotropic
     * linear designs: 3 mm -> 0.2 rad */
    for (int m = 0; m < pb->n_maneuvers; ++m)
      for (int i = 0; i < 3; ++i)
        pb->target[m][i] = default_targets_mm[m][i] * 1e-3 / 0.015;
  }
  if (mkey) {
    int nm = pom_cfg_length(cfg, mkey);
    if (nm < 1 || nm > POM_TUNE_MAX_MANEUVERS)
      return pom_cfg_error(cfg, mkey, NULL, err,
                           "expected a list of 1..%d triples ( [a, b, c], ... )",
                           POM_TUNE_MAX_MANEUVERS);
    pb->n_maneuvers = nm;
    double half = 0.5 * pb->arch.stroke * u->to_display;
    for (int m = 0; m < nm; ++m) {
      snprintf(key, sizeof key, "%s.[%d]", mkey, m);
      if (mkey == euler) {
        double e[3], R[9];
        POM_TRY(pom_cfg_reals(cfg, key, 3, POM_DEG, -89.0, 89.0, e, err));
        pom_euler_zyx_to_matrix(R, e);
        pom_error sub;
        pom_error_clear(&sub);
        if (pom_kin_inverse(&pb->arch, R, pb->target[m], &sub) != POM_OK)
          return pom_cfg_error(cfg, key, NULL, err, "orientation not reachable: %s", sub.message);
        for (int i = 0; i < 3; ++i)
          if (fabs(pb->target[m][i]) > 0.5 * pb->arch.stroke)
            return pom_cfg_error(cfg, key, NULL, err,
                                 "actuator %d would go to %.6g %s, outside +-%.6g %s", i + 1,
                                 pb->target[m][i] * u->to_display, u->display, half, u->display);
      } else {
        POM_TRY(pom_cfg_reals(cfg, key, 3, 1.0 / u->to_display, -half, half, pb->target[m], err));
      }
    }
    snprintf(pb->maneuvers_where, sizeof pb->maneuvers_where, "%s:%d: key '%s'", pom_cfg_path(cfg),
             pom_cfg_line(cfg, mkey), mkey);
    /* a set of zero steps has the same criterion at every gain set (nothing
     * moves, nothing settles later): the search would return an arbitrary
     * point of the box as "tuned" gains */
    int moves = 0;
    for (int m = 0; m < nm; ++m)
      for (int i = 0; i < 3; ++i)
        moves |= fabs(pb->target[m][i]) > TUNE_ZERO_STEP * pb->arch.stroke;
    if (!moves)
      return pom_cfg_error(cfg, mkey, NULL, err,
                           "no maneuver moves an actuator (every setpoint is mid-stroke): the "
                           "criterion is the same for every gain set, so tuning cannot tell gains "
                           "apart; give maneuvers that move the actuators");
  }
  POM_TRY(pom_cfg_real_opt(cfg, "tuning.overshoot_max_percent", 1e-2, 0.0, 1000.0,
                           pb->overshoot_max, &pb->overshoot_max, err));
  POM_TRY(pom_cfg_real_opt(cfg, "tuning.saturation_time_max_ms", 1e-3, 0.0, 1e7,
                           pb->saturation_time_max, &pb->saturation_time_max, err));
  POM_TRY(pom_cfg_real_opt(cfg, "tuning.penalty_weight_ms", 1e-3, 0.0, 1e9, pb->penalty_weight,
                           &pb->penalty_weight, err));
  POM_TRY(load_opt(cfg, &pb->opt, err));
  int in_study = 0; /* read by the study pipeline (pom_pipeline.h) */
  POM_TRY(pom_cfg_bool_opt(cfg, "tuning.run_in_study", 0, &in_study, err));
  return POM_OK;
}

/* ---- criterion ------------------------------------------------------------ */

/* Largest overshoot of actuator a beyond its setpoint, as a fraction of its
 * step from mid-stroke; 0 for a zero step (within TUNE_ZERO_STEP of the
 * stroke: no relative overshoot defined). */
static double overshoot(const pom_dyn_trace *tr, int a, double target, double stroke) {
  if (fabs(target) <= TUNE_ZERO_STEP * stroke || target == 0.0) return 0.0;
  double s = target > 0.0 ? 1.0 : -1.0, worst = 0.0;
  for (int k = 0; k < tr->n; ++k)
    worst = fmax(worst, s * (tr->q[3 * k + a] - target));
  return worst / fabs(target);
}

pom_status pom_tune_evaluate(const pom_tune_problem *pb, const pom_dyn_controller *ctl,
                             pom_tune_eval *out, pom_error *err) {
  pom_status st = POM_OK;
  pom_dyn_model *model = NULL;
  pom_dyn_data *data = NULL;
  pom_dyn_trace *trace = NULL;
  pom_dyn_params p = pb->params;
  p.controller = *ctl;
  memset(out, 0, sizeof *out);
  double t0 = now_s();
  POM_TRY_GOTO(pom_dyn_model_create(&model, &pb->mech, &pb->arch, &p, err), done);
  POM_TRY_GOTO(pom_dyn_data_create(&data, model, err), done);
  POM_TRY_GOTO(pom_dyn_trace_create(&trace, model, err), done);
  double horizon = p.maneuver.horizon, penalty = 0.0;
  const pom_act_desc *tu = pom_act_kind_desc(pom_kin_type_actuator(pb->arch.type));
  for (int m = 0; m < pb->n_maneuvers; ++m) {
    pom_dyn_metrics mt;
    st = pom_dyn_simulate(model, data, pb->target[m], &mt, trace, err);
    if (st != POM_OK) {
      char gains[256];
      gains_text(gains, sizeof gains, pb, ctl);
      pom_error_prefix(err, "maneuver %d to (%.4g, %.4g, %.4g) %s with %s", m + 1,
                       pb->target[m][0] * tu->to_display, pb->target[m][1] * tu->to_display,
                       pb->target[m][2] * tu->to_display, tu->display, gains);
      goto done;
    }
    /* An unsettled maneuver is censored at the horizon (docs/optimize.md 9). */
    double te = isfinite(mt.execution_time) ? mt.execution_time : horizon;
    if (!isfinite(mt.execution_time)) out->unsettled++;
    double os = 0.0, sat = 0.0;
    for (int a = 0; a < 3; ++a) {
      os = fmax(os, overshoot(trace, a, pb->target[m][a], pb->arch.stroke));
      sat = fmax(sat, mt.saturation_time[a]);
    }
    out->mean_execution += te / pb->n_maneuvers;
    out->max_execution = fmax(out->max_execution, te);
    out->max_overshoot = fmax(out->max_overshoot, os);
    out->max_saturation = fmax(out->max_saturation, sat);
    out->mean_energy += mt.energy_total / pb->n_maneuvers;
    if (os > pb->overshoot_max) penalty += (os - pb->overshoot_max) / fmax(pb->overshoot_max, 1e-3);
    if (sat > pb->saturation_time_max)
      penalty += (sat - pb->saturation_time_max) / fmax(pb->saturation_time_max, horizon * 1e-3);
  }
  out->criterion = out->mean_execution + pb->penalty_weight * penalty / pb->n_maneuvers;
  if (!isfinite(out->criterion)) {
    char gains[256];
    gains_text(gains, sizeof gains, pb, ctl);
    POM_FAIL_GOTO(err, POM_ERR_NONFINITE, done, "tuning criterion is %g at %s", out->criterion,
                  gains);
  }
done:
  out->sim_time = now_s() - t0;
  pom_dyn_trace_destroy(trace);
  pom_dyn_data_destroy(data);
  pom_dyn_model_destroy(model);
  return st;
}

/* ---- optimization ---------------------------------------------------------- */
typedef struct {
  const pom_tune_problem *pb;
  long simulations;
  pom_tune_eval last;
  long evals;                /* criterion evaluations so far (progress) */
  long searched;             /* criterion evaluations of the search */
  double crit_min, crit_max; /* the criterion's range over them (s) */
} tune_ctx;

/* Criterion evaluations of a run at most: the config's gains, the global
   search, the local search from each of its starts, the result. */
static long max_evals(const pom_tune_problem *pb) {
  long starts = pb->opt.global != POM_OPT_GLOBAL_NONE ? pb->opt.local_starts : 1;
  return 2 + (long)pb->opt.global_max_evals * (pb->opt.global != POM_OPT_GLOBAL_NONE) +
         starts * (long)pb->opt.local_max_evals * (pb->opt.local != POM_OPT_LOCAL_NONE);
}

static void report(tune_ctx *c) {
  ++c->evals;
  if (c->pb->progress) c->pb->progress(c->pb->progress_user, "tune", c->evals, max_evals(c->pb));
}

static void search_to_controller(const pom_tune_problem *pb, const double z[],
                                 pom_dyn_controller *c) {
  *c = pb->params.controller;
  for (int i = 0; i < pb->n_vars; ++i) {
    double g = pb->log_scale[i] ? pow(10.0, z[i]) : z[i];
    *pom_dyn_ctrl_gain_ptr(c, (int)pb->var[i]) = g;
  }
}

static pom_status objective(void *vctx, const double z[], double *f, pom_error *err) {
  tune_ctx *c = vctx;
  pom_dyn_controller ctl;
  search_to_controller(c->pb, z, &ctl);
  POM_TRY(pom_tune_evaluate(c->pb, &ctl, &c->last, err));
  c->simulations += c->pb->n_maneuvers;
  c->crit_min = c->searched ? fmin(c->crit_min, c->last.criterion) : c->last.criterion;
  c->crit_max = c->searched ? fmax(c->crit_max, c->last.criterion) : c->last.criterion;
  c->searched++;
  report(c);
  *f = -c->last.criterion; /* the driver maximizes */
  return POM_OK;
}

pom_status pom_tune_run(const pom_tune_problem *pb, pom_tune_result *res, pom_error *err) {
  memset(res, 0, sizeof *res);
  tune_ctx c;
  memset(&c, 0, sizeof c);
  c.pb = pb;
  res->initial = pb->params.controller;
  POM_TRY(pom_tune_evaluate(pb, &res->initial, &res->initial_eval, err));
  c.simulations = pb->n_maneuvers;
  report(&c);
  double lo[POM_TUNE_N_VARS], hi[POM_TUNE_N_VARS], z0[POM_TUNE_N_VARS];
  for (int i = 0; i < pb->n_vars; ++i) {
    lo[i] = pb->log_scale[i] ? log10(pb->lo[i]) : pb->lo[i];
    hi[i] = pb->log_scale[i] ? log10(pb->hi[i]) : pb->hi[i];
    double g = pom_dyn_ctrl_gain(&res->initial, (int)pb->var[i]);
    z0[i] = pb->log_scale[i] ? (g > 0.0 ? log10(g) : lo[i]) : g;
  }
  pom_status st = pom_opt_maximize(pb->n_vars, lo, hi, z0, objective, &c, &pb->opt, &res->opt, err);
  res->simulations = c.simulations;
  if (st != POM_OK) return pom_error_prefix(err, "gain tuning");
  /* the same criterion everywhere the search looked: it cannot tell gains
   * apart, and its "optimum" is wherever it stopped */
  if (c.searched >= 2 && c.crit_max - c.crit_min <= TUNE_FLAT_REL * fabs(c.crit_max))
    POM_FAIL(err, POM_ERR_CONFIG,
             "%s: the tuning criterion is %.6g ms at every one of the %ld gain sets the search "
             "tried: it cannot tell gains apart (no maneuver moves, or none settles within "
             "maneuver.horizon_ms and no limit is exceeded), so nothing is tuned; give "
             "maneuvers that move the actuators and settle",
             pb->maneuvers_where, c.crit_max * 1e3, c.searched);
  search_to_controller(pb, res->opt.x, &res->best);
  POM_TRY(pom_tune_evaluate(pb, &res->best, &res->best_eval, err));
  res->simulations += pb->n_maneuvers;
  c.evals = max_evals(pb) - 1; /* the last unit, also when the searches stopped early */
  report(&c);
  /* Keep the config's gains when the search found nothing better. */
  if (res->initial_eval.criterion < res->best_eval.criterion) {
    int inside = 1;
    for (int i = 0; i < pb->n_vars; ++i)
      inside &= z0[i] >= lo[i] && z0[i] <= hi[i];
    if (inside) {
      res->best = res->initial;
      res->best_eval = res->initial_eval;
    }
  }
  return POM_OK;
}

pom_status pom_tune_write_controller(const pom_tune_problem *pb, const pom_tune_result *res,
                                     const char *path, pom_error *err) {
  pom_io_file w;
  POM_TRY(pom_io_create(&w, path, err));
  FILE *f = w.f;
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(&res->best);
  fprintf(
      f,
      "# %s gains tuned by pomlab tune for \"%s\" (%s):\n"
      "# mean execution time %.4g ms over %d fixed maneuvers (largest overshoot\n"
      "# %.3g %%, largest saturation time %.4g ms, %d unsettled); criterion\n"
      "# %.6g ms (config gains: %.6g ms).\n",
      t->label, pb->arch.name, pom_kin_arch_name(&pb->arch), res->best_eval.mean_execution * 1e3,
      pb->n_maneuvers, res->best_eval.max_overshoot * 100.0, res->best_eval.max_saturation * 1e3,
      res->best_eval.unsettled, res->best_eval.criterion * 1e3, res->initial_eval.criterion * 1e3);
  /* the type, its options and every gain: the file alone sets the controller */
  fprintf(f, "controller = {\n  type = \"%s\";\n", t->name);
  for (int k = 0; k < t->n_options; ++k)
    fprintf(f, "  %s = \"%s\";\n", t->options[k].key, pom_dyn_ctrl_option_name(&res->best, k));
  for (int k = 0; k < t->n_gains; ++k)
    fprintf(f, "  %s = %.9g;\n", t->gains[k].key, pom_dyn_ctrl_gain(&res->best, k));
  fprintf(f, "};\n");
  return pom_io_commit(&w, err);
}
