/* pom_fidelity.c - the cheapest setting that earns an accuracy, chosen on one
 * set of maneuvers and validated on another (docs/tradeoff.md section 9). */
#include "pom_study.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- the ladder ----------------------------------------------------------------- */
/* Cheapest first, by CVODE steps per maneuver on the shipped configs
 * (docs/tradeoff.md section 8: quasi-static 176 / 256 / 456 steps at rtol
 * 1e-3 / 1e-4 / 1e-6, inductive 520 / 661 / 961 / 1943 at 1e-3 ... 1e-6).
 * Only the rigid path: the parasitic one is both slower and further from
 * the rigid reference at every k_p (docs/tradeoff.md section 5). */
static const pom_fidelity_setting ladder[] = {
    {.label = "rigid, quasi-static coil, rtol 1e-3", .coil_inductance = 0, .rtol = 1e-3},
    {.label = "rigid, quasi-static coil, rtol 1e-4", .coil_inductance = 0, .rtol = 1e-4},
    {.label = "rigid, quasi-static coil, rtol 1e-5", .coil_inductance = 0, .rtol = 1e-5},
    {.label = "rigid, quasi-static coil, rtol 1e-6", .coil_inductance = 0, .rtol = 1e-6},
    {.label = "rigid, inductive coil, rtol 1e-3", .coil_inductance = 1, .rtol = 1e-3},
    {.label = "rigid, inductive coil, rtol 1e-4", .coil_inductance = 1, .rtol = 1e-4},
    {.label = "rigid, inductive coil, rtol 1e-5", .coil_inductance = 1, .rtol = 1e-5},
    {.label = "rigid, inductive coil, rtol 1e-6", .coil_inductance = 1, .rtol = 1e-6},
    {.label = "rigid, inductive coil, rtol 1e-7", .coil_inductance = 1, .rtol = 1e-7},
};

const pom_fidelity_setting *pom_fidelity_ladder(int *n) {
  *n = (int)(sizeof ladder / sizeof ladder[0]);
  return ladder;
}

void pom_fidelity_apply(pom_dyn_params *p, const pom_fidelity_setting *s) {
  p->joints.model = POM_JOINTS_RIGID;
  p->scene.limb_inertia = POM_INERTIA_FULL;
  p->scene.universal_joint = 1;
  p->scene.coil_inductance = s->coil_inductance;
  p->solver.rtol = s->rtol;
  p->solver.atol_scale = 0.0;
}

void pom_fidelity_reference(pom_dyn_params *p, double rtol) {
  const pom_fidelity_setting ref = {.label = "reference", .coil_inductance = 1, .rtol = rtol};
  pom_fidelity_apply(p, &ref);
}

void pom_fidelity_defaults(pom_fidelity_opts *o) {
  memset(o, 0, sizeof *o);
  o->accuracy = 0.01;
  o->margin = 2.0;
  o->n_select = 20;
  o->n_validate = 20;
  o->reference_rtol = 1e-8;
}

/* ---- running a set ---------------------------------------------------------------- */
static double now_s(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Runs p on targets q[n] into mt[n] (a failed maneuver is recorded in its
 * metrics' status and reason). Errors only for setup (model, data). */
static pom_status run_set(pom_dyn_metrics *mt, const pom_kin_arch *arch, const pom_mechanism *mech,
                          const pom_dyn_params *p, const double (*q)[3], int n, pom_error *err) {
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_status st = pom_dyn_model_create(&m, mech, arch, p, err);
  if (st == POM_OK) st = pom_dyn_data_create(&d, m, err);
  for (int k = 0; k < n && st == POM_OK; ++k) {
    pom_error e;
    pom_error_clear(&e);
    if (pom_dyn_simulate(m, d, q[k], &mt[k], NULL, &e) != POM_OK && mt[k].status == POM_OK)
      mt[k].status = POM_ERR_SOLVER;
  }
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return st;
}

/* An execution time that never settled counts as the horizon (right-censored,
 * as the study's censoring treats it). */
static double censored_time(const pom_dyn_metrics *m, double horizon) {
  return isfinite(m->execution_time) ? m->execution_time : horizon;
}

/* Worst relative errors of a against ref (e[0] time, e[1] energy) over the
 * maneuvers ref finished; *n_used gets their number, *bad the first maneuver
 * a failed where ref did not (-1 if none). */
static void compare(double e[2], int *n_used, int *bad, const pom_dyn_metrics *a,
                    const pom_dyn_metrics *ref, int n, double horizon) {
  e[0] = e[1] = 0.0;
  *n_used = 0;
  *bad = -1;
  for (int k = 0; k < n; ++k) {
    if (ref[k].status != POM_OK) continue;
    ++*n_used;
    if (a[k].status != POM_OK) {
      e[0] = e[1] = INFINITY;
      if (*bad < 0) *bad = k;
      continue;
    }
    double tr = censored_time(&ref[k], horizon), ta = censored_time(&a[k], horizon);
    e[0] = fmax(e[0], fabs(ta - tr) / tr);
    double er = ref[k].energy_total;
    double de = fabs(a[k].energy_total - er) / fabs(er);
    e[1] = fmax(e[1], isfinite(de) ? de : INFINITY);
  }
}

static double mean_steps(const pom_dyn_metrics *mt, int n) {
  double s = 0.0;
  int used = 0;
  for (int k = 0; k < n; ++k)
    if (mt[k].status == POM_OK) s += (double)mt[k].steps, ++used;
  return used ? s / used : NAN;
}

pom_status pom_fidelity_measure(double e[2], int *n_used, const pom_kin_arch *arch,
                                const pom_mechanism *mech, const pom_dyn_params *p,
                                const pom_dyn_params *ref, const double (*q)[3], int n,
                                pom_error *err) {
  if (n < 1 || n > POM_FIDELITY_MAX_MANEUVERS)
    POM_FAIL(err, POM_ERR_ARG, "fidelity: %d maneuvers, expected 1..%d", n,
             POM_FIDELITY_MAX_MANEUVERS);
  pom_dyn_metrics *a = calloc((size_t)n, sizeof *a), *r = calloc((size_t)n, sizeof *r);
  pom_status st = POM_OK;
  if (!a || !r) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "fidelity: out of memory");
  POM_TRY_GOTO(run_set(r, arch, mech, ref, q, n, err), done);
  POM_TRY_GOTO(run_set(a, arch, mech, p, q, n, err), done);
  int used = 0, bad = -1;
  compare(e, &used, &bad, a, r, n, ref->maneuver.horizon);
  if (n_used) *n_used = used;
done:
  free(a);
  free(r);
  return st;
}

/* ---- the rule ----------------------------------------------------------------------- */
pom_status pom_fidelity_select(pom_fidelity_result *res, const pom_kin_arch *arch,
                               const pom_mechanism *mech, const pom_dyn_params *base,
                               const double (*sel)[3], int n_sel, const double (*val)[3], int n_val,
                               const pom_fidelity_opts *o, pom_error *err) {
  if (!res || !arch || !mech || !base || !sel || !val || !o)
    POM_FAIL(err, POM_ERR_ARG, "pom_fidelity_select: NULL argument");
  if (n_sel < 1 || n_val < 1 || n_sel > POM_FIDELITY_MAX_MANEUVERS ||
      n_val > POM_FIDELITY_MAX_MANEUVERS)
    POM_FAIL(err, POM_ERR_ARG,
             "fidelity: %d selection and %d validation maneuvers, expected 1..%d each", n_sel,
             n_val, POM_FIDELITY_MAX_MANEUVERS);
  if (!(o->accuracy > 0) || !(o->margin >= 1))
    POM_FAIL(err, POM_ERR_ARG, "fidelity: accuracy %g must be > 0 and margin %g >= 1", o->accuracy,
             o->margin);
  memset(res, 0, sizeof *res);
  res->accuracy = o->accuracy;
  res->margin = o->margin;
  const double t0 = now_s(), horizon = base->maneuver.horizon;
  int n_rungs = 0;
  const pom_fidelity_setting *lad = pom_fidelity_ladder(&n_rungs);
  pom_dyn_metrics *rs = calloc((size_t)n_sel, sizeof *rs), *rv = calloc((size_t)n_val, sizeof *rv);
  pom_dyn_metrics *as = calloc((size_t)n_sel, sizeof *as), *av = calloc((size_t)n_val, sizeof *av);
  pom_status st = POM_OK;
  if (!rs || !rv || !as || !av) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "fidelity: out of memory");
  pom_dyn_params ref = *base;
  pom_fidelity_reference(&ref, o->reference_rtol);
  POM_TRY_GOTO(run_set(rs, arch, mech, &ref, sel, n_sel, err), done);
  POM_TRY_GOTO(run_set(rv, arch, mech, &ref, val, n_val, err), done);
  res->reference_steps = mean_steps(rv, n_val);
  res->rung = -1;
  for (int r = 0; r < n_rungs && res->rung < 0; ++r) {
    pom_dyn_params p = *base;
    pom_fidelity_apply(&p, &lad[r]);
    double es[2], ev[2];
    int used_s = 0, used_v = 0, bad = -1;
    ++res->tried;
    POM_TRY_GOTO(run_set(as, arch, mech, &p, sel, n_sel, err), done);
    compare(es, &used_s, &bad, as, rs, n_sel, horizon);
    if (used_s == 0)
      POM_FAIL_GOTO(err, POM_ERR_SOLVER, done,
                    "fidelity: the reference (rigid, inductive coil, rtol %.0e) finished none of "
                    "the %d selection maneuvers",
                    o->reference_rtol, n_sel);
    if (bad >= 0)
      snprintf(res->failure, sizeof res->failure, "%s: selection maneuver %d: %.60s", lad[r].label,
               bad, as[bad].reason);
    const int last = r == n_rungs - 1;
    if (!(fmax(es[0], es[1]) <= o->accuracy / o->margin) && !last) continue;
    ++res->validated;
    POM_TRY_GOTO(run_set(av, arch, mech, &p, val, n_val, err), done);
    compare(ev, &used_v, &bad, av, rv, n_val, horizon);
    if (used_v == 0)
      POM_FAIL_GOTO(err, POM_ERR_SOLVER, done,
                    "fidelity: the reference (rigid, inductive coil, rtol %.0e) finished none of "
                    "the %d validation maneuvers",
                    o->reference_rtol, n_val);
    if (bad >= 0)
      snprintf(res->failure, sizeof res->failure, "%s: validation maneuver %d: %.60s", lad[r].label,
               bad, av[bad].reason);
    res->met = fmax(es[0], es[1]) <= o->accuracy / o->margin && fmax(ev[0], ev[1]) <= o->accuracy;
    if (!res->met && !last) continue;
    /* chosen: the first rung that passed both sets, else the last rung
     * with what it measured */
    res->rung = r;
    res->setting = lad[r];
    res->select_time = es[0], res->select_energy = es[1];
    res->bound_time = ev[0], res->bound_energy = ev[1];
    res->n_select = used_s, res->n_validate = used_v;
    res->steps = mean_steps(av, n_val);
  }
  res->wall = now_s() - t0;
done:
  free(rs);
  free(rv);
  free(as);
  free(av);
  return st;
}
