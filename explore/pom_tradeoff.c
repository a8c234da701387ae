/* pom_tradeoff.c - the speed/accuracy sweep of the dynamics engine
 * (docs/tradeoff.md). */
#include "pom_explore.h"

#include "pom_dyn_params_schema.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- options --------------------------------------------------------------- */
void pom_tradeoff_defaults(pom_tradeoff_opts *o) {
  memset(o, 0, sizeof *o);
  o->maneuvers = 3;
  o->repeats = 3;
  const double rt[] = {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  o->n_rtol = (int)(sizeof rt / sizeof rt[0]);
  memcpy(o->rtol, rt, sizeof rt);
  const double kp[] = {1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  o->n_stiffness = (int)(sizeof kp / sizeof kp[0]);
  memcpy(o->stiffness, kp, sizeof kp);
  o->linear_solvers = 1;
  o->scenes = 1;
  o->reference_rtol = 1e-10;
  o->reference_stiffness = 1e9;
  o->reference_rigid = 1;
  o->rigid = 1;
  o->accuracy = 0.01;
  o->max_wall = 20.0;
  o->fidelity_maneuvers = 20;
  o->fidelity_margin = 2.0;
  o->validation_seed = -1;
}

pom_status pom_tradeoff_load(pom_tradeoff_opts *o, const pom_cfg *cfg, pom_error *err) {
  long l = 0;
  POM_TRY(pom_cfg_int_opt(cfg, "tradeoff.maneuvers", 1, 16, o->maneuvers, &l, err));
  o->maneuvers = (int)l;
  POM_TRY(pom_cfg_int_opt(cfg, "tradeoff.repeats", 1, 101, o->repeats, &l, err));
  o->repeats = (int)l;
  if (pom_cfg_has(cfg, "tradeoff.rtol"))
    POM_TRY(pom_cfg_reals_var(cfg, "tradeoff.rtol", POM_TRADEOFF_MAX_VALUES, 1.0, POM_DYN_RTOL_MIN,
                              0.1, o->rtol, &o->n_rtol, err));
  if (pom_cfg_has(cfg, "tradeoff.stiffness_N_per_m"))
    POM_TRY(pom_cfg_reals_var(cfg, "tradeoff.stiffness_N_per_m", POM_TRADEOFF_MAX_VALUES, 1.0, 1.0,
                              POM_DYN_STIFFNESS_MAX, o->stiffness, &o->n_stiffness, err));
  POM_TRY(
      pom_cfg_bool_opt(cfg, "tradeoff.linear_solvers", o->linear_solvers, &o->linear_solvers, err));
  POM_TRY(pom_cfg_bool_opt(cfg, "tradeoff.scenes", o->scenes, &o->scenes, err));
  POM_TRY(pom_cfg_real_opt(cfg, "tradeoff.reference_rtol", 1.0, POM_DYN_RTOL_MIN, 1e-6,
                           o->reference_rtol, &o->reference_rtol, err));
  static const char *const refs[] = {"parasitic", "rigid", NULL};
  int ref = o->reference_rigid;
  POM_TRY(pom_cfg_choice_opt(cfg, "tradeoff.reference", refs, ref, &ref, err));
  o->reference_rigid = ref;
  POM_TRY(pom_cfg_bool_opt(cfg, "tradeoff.rigid", o->rigid, &o->rigid, err));
  POM_TRY(pom_cfg_real_opt(cfg, "tradeoff.reference_stiffness_N_per_m", 1.0, 1.0,
                           POM_DYN_STIFFNESS_MAX, o->reference_stiffness, &o->reference_stiffness,
                           err));
  POM_TRY(pom_cfg_real_opt(cfg, "tradeoff.accuracy_percent", 1e-2, 1e-6, 100.0, o->accuracy,
                           &o->accuracy, err));
  POM_TRY(
      pom_cfg_real_opt(cfg, "tradeoff.max_wall_s", 1.0, 1e-3, 1e5, o->max_wall, &o->max_wall, err));
  POM_TRY(pom_cfg_int_opt(cfg, "tradeoff.fidelity_maneuvers", 0, POM_FIDELITY_MAX_MANEUVERS,
                          o->fidelity_maneuvers, &l, err));
  o->fidelity_maneuvers = (int)l;
  POM_TRY(pom_cfg_real_opt(cfg, "tradeoff.fidelity_margin", 1.0, 1.0, 100.0, o->fidelity_margin,
                           &o->fidelity_margin, err));
  POM_TRY(pom_cfg_int_opt(cfg, "tradeoff.validation_seed", 0, 9007199254740991L, o->validation_seed,
                          &o->validation_seed, err));
  return POM_OK;
}

/* ---- settings ---------------------------------------------------------------- */
/* rtol alone: atol_scale 0 = natural sizes, atol = rtol * natural size on
 * both paths (docs/dynamics.md section 7, docs/dynamics-exact.md section 5,
 * docs/tradeoff.md). */
static void set_rtol(pom_dyn_params *p, double rtol) {
  p->solver.rtol = rtol;
  p->solver.atol_scale = 0.0;
}

static void set_stiffness(pom_dyn_params *p, double k) {
  p->joints.stiffness = k;
  p->joints.angular_stiffness = k;
}

static pom_tradeoff_row *add_row(pom_tradeoff_result *res, const char *family,
                                 const pom_dyn_params *p, const char *fmt, double v) {
  if (res->n_rows >= POM_TRADEOFF_MAX_ROWS) return NULL;
  pom_tradeoff_row *r = &res->row[res->n_rows++];
  memset(r, 0, sizeof *r);
  snprintf(r->family, sizeof r->family, "%s", family);
  snprintf(r->label, sizeof r->label, fmt, v);
  r->params = *p;
  return r;
}

static void build_settings(pom_tradeoff_result *res, const pom_dyn_params *base,
                           const pom_tradeoff_opts *o) {
  pom_dyn_params p = *base;
  /* reference: full fidelity, tight tolerance, stiff joints */
  set_rtol(&p, o->reference_rtol);
  set_stiffness(&p, o->reference_stiffness);
  p.scene.coil_inductance = 1;
  p.scene.limb_inertia = POM_INERTIA_FULL;
  p.scene.universal_joint = 1;
  p.joints.model = o->reference_rigid ? POM_JOINTS_RIGID : POM_JOINTS_PARASITIC;
  add_row(res, "reference", &p, "reference: rtol %.0e", o->reference_rtol);
  if (o->reference_rigid)
    snprintf(res->row[0].label, sizeof res->row[0].label, "reference: rigid, rtol %.0e",
             o->reference_rtol);
  else
    snprintf(res->row[0].label, sizeof res->row[0].label,
             "reference: parasitic, rtol %.0e, k_p %.0e", o->reference_rtol,
             o->reference_stiffness);

  add_row(res, "config", base, "config as given (rtol %.0e)", base->solver.rtol);
  for (int k = 0; k < o->n_rtol; ++k) {
    p = *base;
    set_rtol(&p, o->rtol[k]);
    add_row(res, "rtol", &p, "rtol %.0e", o->rtol[k]);
  }
  for (int k = 0; k < o->n_stiffness; ++k) {
    p = *base;
    set_stiffness(&p, o->stiffness[k]);
    add_row(res, "stiffness", &p, "k_p %.0e", o->stiffness[k]);
  }
  if (o->rigid) {
    /* the exact-constraint path: no k_p, full scene (docs/dynamics-exact.md) */
    const double rr[] = {1e-3, 1e-4, 1e-5, 1e-6, 1e-8};
    for (int k = 0; k < 5; ++k) {
      p = *base;
      p.joints.model = POM_JOINTS_RIGID;
      p.scene.limb_inertia = POM_INERTIA_FULL;
      p.scene.universal_joint = 1;
      set_rtol(&p, rr[k]);
      add_row(res, "rigid", &p, "rigid rtol %.0e", rr[k]);
    }
    const int qs[] = {0, 1, 3}; /* rtol 1e-3, 1e-4, 1e-6 */
    for (int j = 0; j < 3; ++j) {
      const int k = qs[j];
      p = *base;
      p.joints.model = POM_JOINTS_RIGID;
      p.scene.limb_inertia = POM_INERTIA_FULL;
      p.scene.universal_joint = 1;
      p.scene.coil_inductance = 0;
      set_rtol(&p, rr[k]);
      add_row(res, "rigid", &p, "rigid quasi-static rtol %.0e", rr[k]);
    }
  }
  if (o->linear_solvers) {
    p = *base;
    p.solver.linear_solver =
        base->solver.linear_solver == POM_LINSOL_KLU ? POM_LINSOL_DENSE : POM_LINSOL_KLU;
    pom_tradeoff_row *r = add_row(res, "linsol", &p, "linsol %g", 0);
    if (r)
      snprintf(r->label, sizeof r->label, "linear solver %s",
               pom_dyn_linsol_name(p.solver.linear_solver));
  }
  if (o->scenes) {
    p = *base;
    p.scene.coil_inductance = 0;
    add_row(res, "scene", &p, "coil quasi-static%.0s", 0);
    p = *base;
    p.scene.limb_inertia = POM_INERTIA_LUMPED;
    add_row(res, "scene", &p, "limb inertia lumped%.0s", 0);
    p = *base;
    p.scene.universal_joint = 0;
    add_row(res, "scene", &p, "universal joint off%.0s", 0);
    p = *base;
    p.scene.orientation =
        p.scene.orientation == POM_ORIENT_EULER_ZYX ? POM_ORIENT_QUATERNION : POM_ORIENT_EULER_ZYX;
    add_row(res, "scene", &p, "other orientation%.0s", 0);
    p = *base;
    p.scene.bearing_friction = 0;
    add_row(res, "scene", &p, "bearing friction off%.0s", 0);
    p = *base;
    p.scene.gravity = 0;
    add_row(res, "scene", &p, "gravity off%.0s", 0);
    /* the cheap scene with stiffer joints at a few tolerances */
    const double rt[] = {1e-4, 1e-5, 1e-6};
    const double kp[] = {1e6, 1e8};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 3; ++b) {
        p = *base;
        p.scene.coil_inductance = 0;
        p.scene.limb_inertia = POM_INERTIA_LUMPED;
        set_rtol(&p, rt[b]);
        set_stiffness(&p, kp[a]);
        pom_tradeoff_row *r = add_row(res, "combined", &p, "%g", 0);
        if (r)
          snprintf(r->label, sizeof r->label, "quasi-static+lumped rtol %.0e k_p %.0e", rt[b],
                   kp[a]);
      }
  }
}

/* ---- measuring ----------------------------------------------------------------- */
static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double rel_err(double x, double ref) {
  if (!isfinite(x) || !isfinite(ref)) return (isnan(x) && isnan(ref)) ? 0.0 : INFINITY;
  return fabs(x - ref) / fmax(fabs(ref), 1e-300);
}

/* What a setting produced: metrics and actuator traces of every maneuver
 * (kept for the references and, while its errors are computed, for a row). */
typedef struct {
  pom_dyn_metrics mt[16];
  double *q[16]; /* [n[k]][3] (m) */
  int n[16];
} run_data;

static void run_free(run_data *r) {
  for (int k = 0; k < 16; ++k) {
    free(r->q[k]);
    r->q[k] = NULL;
    r->n[k] = 0;
  }
}

/* What every run of the sweep shares. */
typedef struct {
  const pom_kin_arch *arch;
  const pom_mechanism *mech;
  const pom_tradeoff_opts *o;
  const pom_tradeoff_result *res;
} sweep;

/* Runs row->params over the maneuvers: one traced run each, kept in keep,
 * then `repeats` untraced timed runs (row->time = mean over maneuvers of the
 * median). A maneuver that fails (or exceeds max_wall) is recorded in the row
 * (failures, reason) and stops it. Returns POM_OK, POM_ERR_NOMEM, or the
 * engine's status when it refuses the setting (also recorded in the row;
 * *why says why). */
static pom_status measure(const sweep *c, pom_tradeoff_row *row, int repeats, run_data *keep,
                          pom_error *why) {
  pom_status st = POM_OK;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_dyn_trace *tr = NULL;
  double times[101];
  const int n_man = c->res->n_maneuvers;
  pom_error e2;
  pom_error_clear(&e2);
  st = pom_dyn_model_create(&m, c->mech, c->arch, &row->params, why);
  if (st == POM_OK) st = pom_dyn_data_create(&d, m, why);
  if (st == POM_OK) st = pom_dyn_trace_create(&tr, m, why);
  if (st != POM_OK) {
    row->failures = n_man;
    snprintf(row->reason, sizeof row->reason, "%s", why->message);
    goto done;
  }
  row->n_states = pom_dyn_model_n_states(m);
  double time_sum = 0.0, steps_sum = 0.0;
  for (int k = 0; k < n_man && !row->failures; ++k) {
    const double *target = c->res->targets[k];
    pom_dyn_metrics mt;
    int n_t = 0;
    for (int rep = 0; rep <= repeats; ++rep) {
      /* run 0 keeps a trace for the errors; runs 1..repeats are timed */
      pom_error_clear(&e2);
      pom_status s = pom_dyn_simulate(m, d, target, &mt, rep == 0 ? tr : NULL, &e2);
      if (s != POM_OK || mt.wall_time > c->o->max_wall) {
        ++row->failures;
        if (s != POM_OK)
          snprintf(row->reason, sizeof row->reason, "maneuver %d: %s", k, mt.reason);
        else
          snprintf(row->reason, sizeof row->reason,
                   "maneuver %d took %.3g s > tradeoff.max_wall_s = %.3g s", k, mt.wall_time,
                   c->o->max_wall);
        break;
      }
      if (rep > 0) {
        times[n_t++] = mt.wall_time;
        continue;
      }
      steps_sum += (double)mt.steps;
      keep->mt[k] = mt;
      keep->n[k] = tr->n;
      keep->q[k] = malloc((size_t)tr->n * 3 * sizeof(double));
      if (!keep->q[k]) POM_FAIL_GOTO(why, POM_ERR_NOMEM, done, "allocating traces");
      memcpy(keep->q[k], tr->q, (size_t)tr->n * 3 * sizeof(double));
    }
    if (n_t > 0) {
      qsort(times, (size_t)n_t, sizeof times[0], cmp_double);
      time_sum += times[n_t / 2];
    }
  }
  row->time = repeats > 0 ? time_sum / n_man : NAN;
  row->steps = steps_sum / n_man;
done:
  if (row->failures) row->time = NAN;
  pom_dyn_trace_destroy(tr);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return st;
}

/* The settling-time, energy and trajectory errors of run a against run ref
 * (worst over the maneuvers, docs/tradeoff.md section 2); e[3] = largest. */
static void compare(const run_data *a, const run_data *ref, const pom_tradeoff_result *res,
                    double e[4]) {
  e[0] = e[1] = e[2] = 0.0;
  for (int k = 0; k < res->n_maneuvers; ++k) {
    const double *target = res->targets[k];
    e[0] = fmax(e[0], rel_err(a->mt[k].execution_time, ref->mt[k].execution_time));
    e[1] = fmax(e[1], rel_err(a->mt[k].energy_total, ref->mt[k].energy_total));
    double step = fmax(fmax(fabs(target[0]), fabs(target[1])), fabs(target[2]));
    double worst = (a->n[k] == ref->n[k]) ? 0.0 : INFINITY;
    for (int i = 0; i < 3 * a->n[k] && i < 3 * ref->n[k]; ++i)
      worst = fmax(worst, fabs(a->q[k][i] - ref->q[k][i]));
    e[2] = fmax(e[2], step > 0 ? worst / step : worst);
  }
  e[3] = fmax(e[0], fmax(e[1], e[2]));
}

/* Two settings describe the same model when everything but the solver
 * agrees. Only joints and scene are compared, every parameter of those groups
 * in the list (pom_dyn_params_schema.h): build_settings changes nothing else
 * (actuator, controller and maneuver are the config's in every row); the
 * rigid path ignores the parasitic elements (the joints group but its
 * model). */
static int same_model(const pom_dyn_params *a, const pom_dyn_params *b) {
  if (a->joints.model != b->joints.model) return 0;
  const pom_dyn_param_info *s = pom_dyn_param_schema();
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
    int joints = strcmp(s[k].group, "joints") == 0;
    if (!joints && strcmp(s[k].group, "scene") != 0) continue;
    if (joints && a->joints.model != POM_JOINTS_PARASITIC) continue;
    if (pom_dyn_param_value(a, &s[k]) != pom_dyn_param_value(b, &s[k])) return 0;
  }
  return 1;
}

/* A model integrated tightly: the reference of its rows' integration error. */
typedef struct {
  pom_tradeoff_row row; /* its setting and, if it failed, why */
  run_data data;
} model_ref;

/* The same-model reference of `row` (run now if no earlier row had its
 * model): the row's model at the reference rtol with natural absolute
 * tolerances and the config's linear solver, traced once, not timed. */
static pom_status model_reference(const sweep *c, model_ref *models, int *n_models,
                                  const pom_tradeoff_row *row, const pom_dyn_params *base,
                                  const model_ref **out, pom_error *err) {
  for (int i = 0; i < *n_models; ++i)
    if (same_model(&models[i].row.params, &row->params)) {
      *out = &models[i];
      return POM_OK;
    }
  model_ref *mr = &models[(*n_models)++];
  mr->row.params = row->params;
  set_rtol(&mr->row.params, c->o->reference_rtol);
  mr->row.params.solver.linear_solver = base->solver.linear_solver;
  pom_error why;
  pom_error_clear(&why);
  pom_status st = measure(c, &mr->row, 0, &mr->data, &why);
  if (st == POM_ERR_NOMEM) {
    if (err) *err = why;
    return st;
  }
  *out = mr;
  return POM_OK;
}

/* ---- the recommendation ------------------------------------------------------------- */
/* The rule of docs/tradeoff.md section 9: selected on maneuvers 0..n-1 of
 * the montecarlo seed, validated on as many of another seed; the row of the
 * sweep with the chosen setting is marked. */
static pom_status recommend(pom_tradeoff_result *res, const pom_kin_arch *arch,
                            const pom_mechanism *mech, const pom_dyn_params *base,
                            const pom_doe_maneuvers *mv, const pom_tradeoff_opts *o,
                            pom_error *err) {
  res->recommended = -1;
  const int n = o->fidelity_maneuvers;
  if (n < 1) return POM_OK;
  res->select_seed = mv->seed;
  res->validation_seed = o->validation_seed >= 0 ? (uint64_t)o->validation_seed : mv->seed + 1;
  if (res->validation_seed == res->select_seed)
    POM_FAIL(err, POM_ERR_CONFIG,
             "tradeoff.validation_seed = %llu is the montecarlo seed: the validation set must "
             "come from a different seed",
             (unsigned long long)res->validation_seed);
  double(*sel)[3] = calloc((size_t)n, sizeof *sel), (*val)[3] = calloc((size_t)n, sizeof *val);
  pom_status st = POM_OK;
  if (!sel || !val) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "tradeoff: out of memory");
  int n_sel = 0, n_val = 0;
  pom_doe_maneuver_targets(sel, &n_sel, mv, res->select_seed, n, arch);
  pom_doe_maneuver_targets(val, &n_val, mv, res->validation_seed, n, arch);
  res->n_select_drawn = res->n_validation_drawn = n;
  if (n_sel < 1 || n_val < 1)
    POM_FAIL_GOTO(err, POM_ERR_LIMIT, done,
                  "tradeoff: none of the %d maneuvers of a seed lies in the stroke", n);
  pom_fidelity_opts fo;
  pom_fidelity_defaults(&fo);
  fo.accuracy = o->accuracy;
  fo.margin = o->fidelity_margin;
  fo.n_select = n_sel;
  fo.n_validate = n_val;
  fo.reference_rtol = o->reference_rtol;
  POM_TRY_GOTO(pom_fidelity_select(&res->fidelity, arch, mech, base, (const double(*)[3])sel, n_sel,
                                   (const double(*)[3])val, n_val, &fo, err),
               done);
  res->fidelity_ran = 1;
  pom_dyn_params chosen = *base;
  pom_fidelity_apply(&chosen, &res->fidelity.setting);
  for (int r = 1; r < res->n_rows && res->recommended < 0; ++r) {
    const pom_dyn_params *q = &res->row[r].params;
    if (q->joints.model == chosen.joints.model &&
        q->scene.coil_inductance == chosen.scene.coil_inductance &&
        q->scene.limb_inertia == chosen.scene.limb_inertia &&
        q->scene.universal_joint == chosen.scene.universal_joint &&
        q->solver.rtol == chosen.solver.rtol && q->solver.atol_scale == chosen.solver.atol_scale &&
        q->solver.linear_solver == chosen.solver.linear_solver && same_model(q, &chosen))
      res->recommended = r;
  }
done:
  free(sel);
  free(val);
  return st;
}

/* ---- the sweep ------------------------------------------------------------------ */
pom_status pom_tradeoff_run(const pom_kin_arch *arch, const pom_mechanism *mech,
                            const pom_dyn_params *base, const pom_doe_maneuvers *mv,
                            const pom_tradeoff_opts *o, pom_tradeoff_result *res,
                            pom_tradeoff_progress progress, void *user, pom_error *err) {
  if (!arch || !mech || !base || !mv || !o || !res)
    POM_FAIL(err, POM_ERR_ARG, "pom_tradeoff_run: NULL argument");
  if (o->maneuvers < 1 || o->maneuvers > 16 || o->repeats < 1 || o->repeats > 100)
    POM_FAIL(err, POM_ERR_ARG, "tradeoff: maneuvers %d must be in 1..16, repeats %d in 1..100",
             o->maneuvers, o->repeats);
  if (mv->space != POM_DOE_SPACE_JOINT)
    POM_FAIL(err, POM_ERR_ARG, "tradeoff: montecarlo.space must be \"joint\"");
  memset(res, 0, sizeof *res);
  res->recommended = -1;
  res->n_maneuvers = o->maneuvers;
  for (int k = 0; k < o->maneuvers; ++k) {
    pom_doe_maneuver man;
    pom_doe_maneuver_draw(&man, mv, k);
    memcpy(res->targets[k], man.q, sizeof man.q);
  }
  build_settings(res, base, o);
  const sweep c = {arch, mech, o, res};
  /* models[0] is the reference row's own model: the rows of the reference
   * model get their integration error against it */
  model_ref *models = calloc(POM_TRADEOFF_MAX_ROWS, sizeof *models);
  run_data *cur = calloc(1, sizeof *cur);
  pom_status st = POM_OK;
  if (!models || !cur) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "allocating the references");
  pom_tradeoff_row *r0 = &res->row[0];
  st = measure(&c, r0, o->repeats, &models[0].data, err);
  if (st != POM_OK) goto done;
  if (r0->failures)
    POM_FAIL_GOTO(err, POM_ERR_SOLVER, done, "the reference failed: %s", r0->reason);
  models[0].row = *r0;
  int n_models = 1;
  if (progress) progress(user, r0, 1, res->n_rows);
  for (int r = 1; r < res->n_rows; ++r) {
    pom_tradeoff_row *w = &res->row[r];
    const model_ref *mr = NULL;
    st = model_reference(&c, models, &n_models, w, base, &mr, err);
    if (st != POM_OK) goto done;
    pom_error why;
    pom_error_clear(&why);
    st = measure(&c, w, o->repeats, cur, &why);
    if (st == POM_ERR_NOMEM) {
      if (err) *err = why;
      goto done;
    }
    st = POM_OK;
    double e[4] = {INFINITY, INFINITY, INFINITY, INFINITY}, ei[4];
    memcpy(ei, e, sizeof e);
    if (!w->failures) compare(cur, &models[0].data, res, e);
    if (mr->row.failures) {
      ei[0] = ei[1] = ei[2] = ei[3] = NAN;
      snprintf(w->int_reason, sizeof w->int_reason, "the same model at rtol %.0e failed: %s",
               o->reference_rtol, mr->row.reason);
    } else if (!w->failures) {
      compare(cur, &mr->data, res, ei);
    }
    w->err_settle = e[0], w->err_energy = e[1], w->err_traj = e[2], w->err_max = e[3];
    w->int_settle = ei[0], w->int_energy = ei[1], w->int_traj = ei[2], w->int_max = ei[3];
    run_free(cur);
    if (progress) progress(user, w, r + 1, res->n_rows);
  }
  res->n_models = n_models;
  st = recommend(res, arch, mech, base, mv, o, err);
done:
  if (models)
    for (int i = 0; i < POM_TRADEOFF_MAX_ROWS; ++i)
      run_free(&models[i].data);
  if (cur) run_free(cur);
  free(models);
  free(cur);
  return st;
}

int pom_tradeoff_recommend(const pom_tradeoff_result *res, double accuracy) {
  int best = -1;
  for (int r = 1; r < res->n_rows; ++r) {
    const pom_tradeoff_row *w = &res->row[r];
    if (w->failures || !(w->err_max <= accuracy) || !isfinite(w->time)) continue;
    if (best < 0 || w->time < res->row[best].time) best = r;
  }
  return best;
}
