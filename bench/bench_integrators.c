/* bench_integrators.c - work against precision of the parasitic path's
 * integrator (issue 20 item 2): CVODE BDF as shipped (pom_dyn_simulate)
 * against ARKode ARKStep DIRK/ESDIRK methods with the same RHS, the same
 * analytic Jacobian and the same KLU linear solver (the formulation's linsys
 * callback, A = I - gamma J), both on the same 0.1 ms output grid.
 *
 * usage: bench_integrators CONFIG [key=value ...]
 *   n=20              maneuvers: targets 0..n-1 that `pomlab montecarlo CONFIG`
 *                     draws (the config's montecarlo group and seed; targets
 *                     outside the stroke are skipped as the montecarlo does)
 *   methods=LIST      comma list of bdf and the ARKode tables below
 *                     (default bdf,esdirk324,sdirk534,esdirk436,ark548,esdirk547)
 *   rtols=LIST        the ladder, natural-size tolerances (solver.atol_scale
 *                     0: atol = rtol x natural size, docs/dynamics.md
 *                     section 7); default 1e-4,1e-5,1e-6,1e-7,1e-8
 *   shipped=1         also run each method at the config's own solver.rtol
 *                     and solver.atol_scale (the shipped 1e-6 / 1e-3)
 *   ref=1e-10         reference: CVODE BDF at this rtol (natural sizes)
 *   ref2=1e-9         second reference to check that the first converged (0: skip)
 *   repeats=3         CPU: minimum over this many passes, methods alternated
 *   interp=lagrange   ARKode's dense output: lagrange or hermite
 *   predictor=P nlscoef=C lsetup=S jacfreq=J degree=D
 *                     ARKStep's predictor method, nonlinear convergence
 *                     coefficient, Newton-matrix and Jacobian update
 *                     frequencies, interpolant degree (absent: ARKode's
 *                     defaults)
 *   hist=1            step distribution around the first saturation exit
 *   check=1           exit 1 unless, for every method, the largest error of
 *                     the settling times and of the energies falls below
 *                     0.3 x its value at the previous rung of the ladder
 *                     (ctest; give rungs a factor 100 apart)
 *   q=3,-3,3          one maneuver at these setpoints (mm) instead of the draw
 *   grind=1           one pass, no reference, no table: for callgrind
 *                     (--toggle-collect=integrate_one)
 *
 * Errors are relative, per actuator and maneuver, against the reference:
 * settling time (2 % band; CVODE's runs from the driver's dense-output
 * watch, ARKode's from its own dense output on a 1 us grid, linear
 * interpolation of the last exit: ~1e-10 s, the same accuracy; the timed
 * passes sample no grid, as the driver without a trace) and source energy int u i dt at the horizon
 * (the accumulator state). Steps, RHS evaluations, Jacobians, factorizations and Newton iterations
 * are per maneuver (exact); CPU is the minimum over the passes of the processor time per maneuver.
 * bench/README.md, "Issue 20 item 2", has the measured tables. */
#include "dyn_internal.h"
#include "pom_run.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_butcher_dirk.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if defined(__GNUC__)
#define BENCH_NOINLINE __attribute__((noinline))
#else
#define BENCH_NOINLINE
#endif

typedef struct {
  const char *name;
  int table; /* ARKODE_DIRKTableID, -1 for CVODE BDF */
} method_desc;

static const method_desc methods_known[] = {
    {"bdf", -1},
    {"ark324", ARKODE_ARK324L2SA_DIRK_4_2_3},
    {"sdirk534", ARKODE_SDIRK_5_3_4},
    {"ark436", ARKODE_ARK436L2SA_DIRK_6_3_4},
    {"ark437", ARKODE_ARK437L2SA_DIRK_7_3_4},
    {"ark548", ARKODE_ARK548L2SA_DIRK_8_4_5},
    {"ark548b", ARKODE_ARK548L2SAb_DIRK_8_4_5},
    {"esdirk324", ARKODE_ESDIRK324L2SA_4_2_3},
    {"esdirk325", ARKODE_ESDIRK325L2SA_5_2_3},
    {"esdirk32i5", ARKODE_ESDIRK32I5L2SA_5_2_3},
    {"esdirk436", ARKODE_ESDIRK436L2SA_6_3_4},
    {"esdirk43i6", ARKODE_ESDIRK43I6L2SA_6_3_4},
    {"qesdirk436", ARKODE_QESDIRK436L2SA_6_3_4},
    {"esdirk437", ARKODE_ESDIRK437L2SA_7_3_4},
    {"esdirk547", ARKODE_ESDIRK547L2SA_7_4_5},
    {"esdirk547b", ARKODE_ESDIRK547L2SA2_7_4_5},
};
#define N_KNOWN ((int)(sizeof methods_known / sizeof methods_known[0]))

#define MAX_LIST 24
#define N_BINS   4 /* before the first exit, 0-0.5 ms after, 0.5-5 ms, the rest */

/* per-maneuver outcome of one integration */
typedef struct {
  int ok;
  double ts[3], E[3];
  long steps, attempts, rhs, jacs, setups, newton, etf, ncf;
  long bins[N_BINS];
} outcome;

/* one (method, tolerance) combination with its own model, data, integrator */
typedef struct {
  const method_desc *md;
  double rtol, atol_scale;
  int shipped;
  pom_dyn_model *m;
  pom_dyn_data *d;
  void *ark;
  char msg[256];
  outcome *res;  /* [n] */
  double cpu;    /* min over passes of CPU per maneuver (s) */
  double *steps; /* scratch: step times of one maneuver (hist) */
  long steps_cap;
  double *qs; /* [n_qs][3] ARKode runs: q on the BENCH_GRID_DT grid */
  int n_qs;
} run;

/* ARKode's settling times come from its dense output on this grid (s) */
#define BENCH_GRID_DT 1e-6

static double cpu_seconds(void) {
  return (double)clock() / (double)CLOCKS_PER_SEC;
}

static void ark_error_handler(int code, const char *module, const char *function, char *msg,
                              void *user_data) {
  run *r = user_data;
  snprintf(r->msg, sizeof r->msg, "%s (%s, %s, flag %d)", msg ? msg : "", module ? module : "",
           function ? function : "", code);
}

/* ARKode's linear-system callback: A = M - gamma J with M = I, the
 * formulation's CVODE callback (A = I - gamma J) with the mass matrix
 * argument dropped; the same Jacobian, reuse flag and fill. */
static int ark_linsys(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, SUNMatrix M,
                      sunbooleantype jok, sunbooleantype *jcur, sunrealtype gamma, void *user_data,
                      N_Vector tmp1, N_Vector tmp2, N_Vector tmp3) {
  (void)M;
  const pom_dyn_data *d = user_data;
  return d->m->form->linsys(t, y, fy, A, jok, jcur, gamma, user_data, tmp1, tmp2, tmp3);
}

static double grid_time(const pom_dyn_params *p, int k) {
  return fmin((double)k * BENCH_GRID_DT, p->maneuver.horizon);
}

/* Settling time of actuator a from the grid qs (n samples): the last exit
 * from the band settle_band |r| by linear interpolation; NaN when the last
 * sample is outside; 0 for a zero step (as the driver, docs/dynamics.md 8). */
static double grid_settling(const pom_dyn_params *p, const double *qs, int n, int a, double r) {
  double band = p->maneuver.settle_band * fabs(r);
  if (r == 0.0) return 0.0;
  int last = -1;
  for (int k = 0; k < n; ++k)
    if (fabs(qs[3 * k + a] - r) > band) last = k;
  if (last < 0) return 0.0;
  if (last == n - 1) return NAN;
  double e0 = qs[3 * last + a] - r, e1 = qs[3 * (last + 1) + a] - r;
  double edge = e0 > 0 ? band : -band;
  double tau = fmin(fmax((e0 - edge) / (e0 - e1), 0.0), 1.0);
  double t0 = grid_time(p, last), t1 = grid_time(p, last + 1);
  return t0 + tau * (t1 - t0);
}

static int bin_of(double t, double t_exit) {
  if (!(t_exit >= 0) || t < t_exit) return 0;
  if (t < t_exit + 0.5e-3) return 1;
  if (t < t_exit + 5e-3) return 2;
  return 3;
}

/* The counts pom_dyn_simulate resets at the start of a maneuver. */
static void reset_counts(pom_dyn_data *d, const double target[3]) {
  for (int a = 0; a < d->m->n_actuators; ++a)
    d->target[a] = target[a];
  d->rhs_count = d->jac_rhs_count = d->jac_count = 0;
  d->jac_valid = 0;
  d->last_euler_singular = d->last_nonfinite = 0;
  d->euler_singular_count = d->nonfinite_count = d->kin_fail_count = 0;
}

/* One maneuver with ARKStep: the loop of pom_dyn_simulate_ex (one step at a
 * time, the outputs evaluated at every step, the grid from the dense output),
 * then the same settling metrics and the accumulators at the horizon. */
static int ark_maneuver(run *r, const double target[3], double t_exit, outcome *o) {
  const pom_dyn_model *m = r->m;
  pom_dyn_data *d = r->d;
  const pom_dyn_params *p = &m->par;
  double *y = N_VGetArrayPointer(d->y), *ys = N_VGetArrayPointer(d->ytmp);
  reset_counts(d, target);
  m->form->initial(m, y, NULL);
  if (ARKStepReInit(r->ark, NULL, pom_dyn_cvode_rhs, 0.0, d->y) != ARK_SUCCESS ||
      ARKStepSetStopTime(r->ark, p->maneuver.horizon) != ARK_SUCCESS)
    return -1;
  const int n = r->n_qs;
  if (o) m->form->positions(m, y, r->qs);
  int k = 1;
  long n_steps = 0;
  double t = 0.0;
  while (t < p->maneuver.horizon) {
    if (n_steps++ >= p->solver.max_steps) return -1;
    int flag = ARKStepEvolve(r->ark, p->maneuver.horizon, d->y, &t, ARK_ONE_STEP);
    if (flag < 0 || m->form->near_singular(m, y)) return -1;
    d->t = t;
    pom_dyn_eval(m, d, y, NULL); /* as the driver: extremes at every step */
    if (!o) continue;            /* the timed passes: no grid, as the driver without a trace */
    ++o->bins[bin_of(t, t_exit)];
    while (k < n && grid_time(p, k) <= t) {
      if (ARKStepGetDky(r->ark, grid_time(p, k), 0, d->ytmp) != ARK_SUCCESS) return -1;
      m->form->positions(m, ys, r->qs + 3 * k);
      ++k;
    }
  }
  if (!o) return 0;
  for (int a = 0; a < m->n_actuators; ++a) {
    o->ts[a] = grid_settling(p, r->qs, n, a, target[a]);
    o->E[a] = y[m->act[a].acc_state + DYN_ACC_SOURCE];
  }
  long v = 0;
  if (ARKStepGetNumSteps(r->ark, &v) == ARK_SUCCESS) o->steps = v;
  if (ARKStepGetNumStepAttempts(r->ark, &v) == ARK_SUCCESS) o->attempts = v;
  if (ARKStepGetNumErrTestFails(r->ark, &v) == ARK_SUCCESS) o->etf = v;
  if (ARKStepGetNumLinSolvSetups(r->ark, &v) == ARK_SUCCESS) o->setups = v;
  if (ARKStepGetNumNonlinSolvIters(r->ark, &v) == ARK_SUCCESS) o->newton = v;
  if (ARKStepGetNumNonlinSolvConvFails(r->ark, &v) == ARK_SUCCESS) o->ncf = v;
  o->rhs = d->rhs_count;
  o->jacs = d->jac_count;
  o->ok = 1;
  return 0;
}

/* The step times of CVODE on the data's own integrator (pom_dyn_simulate's
 * settings): the step distribution of the shipped driver. Returns the step
 * count (to be checked against pom_dyn_simulate's) or -1. */
static long cvode_step_bins(run *r, const double target[3], double t_exit, long bins[N_BINS]) {
  pom_dyn_data *d = r->d;
  const pom_dyn_model *m = r->m;
  double h = m->par.maneuver.horizon, t = 0.0;
  reset_counts(d, target);
  m->form->initial(m, N_VGetArrayPointer(d->y), NULL);
  if (CVodeReInit(d->cvode, 0.0, d->y) != CV_SUCCESS || CVodeSetStopTime(d->cvode, h) != CV_SUCCESS)
    return -1;
  long n = 0;
  while (t < h) {
    if (CVode(d->cvode, h, d->y, &t, CV_ONE_STEP) < 0) return -1;
    ++bins[bin_of(t, t_exit)];
    ++n;
  }
  return n;
}

static int integrate_one(run *r, const double target[3], double t_exit, outcome *o);

/* One maneuver of run r (o NULL: no bookkeeping, the timed passes). */
BENCH_NOINLINE int integrate_one(run *r, const double target[3], double t_exit, outcome *o) {
  if (r->md->table >= 0) return ark_maneuver(r, target, t_exit, o);
  pom_dyn_metrics mt;
  pom_error err;
  pom_error_clear(&err);
  if (pom_dyn_simulate(r->m, r->d, target, &mt, NULL, &err) != POM_OK) {
    snprintf(r->msg, sizeof r->msg, "%s", err.message);
    return -1;
  }
  if (!o) return 0;
  for (int a = 0; a < r->m->n_actuators; ++a) {
    o->ts[a] = mt.settling_time[a];
    o->E[a] = mt.energy[a];
  }
  o->steps = o->attempts = mt.steps;
  o->attempts += mt.error_test_fails + mt.nonlin_conv_fails;
  o->etf = mt.error_test_fails;
  o->ncf = mt.nonlin_conv_fails;
  o->rhs = mt.rhs_evals;
  o->jacs = mt.jac_evals;
  o->setups = mt.linsol_setups;
  o->newton = mt.newton_iters;
  o->ok = 1;
  return 0;
}

/* ARKStep options away from its defaults (0 / negative: default) */
typedef struct {
  int interp;        /* ARK_INTERP_LAGRANGE or ARK_INTERP_HERMITE */
  int predictor;     /* ARKStepSetPredictorMethod */
  double nlscoef;    /* ARKStepSetNonlinConvCoef */
  int lsetup_freq;   /* ARKStepSetLSetupFrequency */
  long jac_freq;     /* ARKStepSetJacEvalFrequency */
  int interp_degree; /* ARKStepSetInterpolantDegree */
} ark_opts;

static pom_status run_create(run *r, const pom_mechanism *mech, const pom_kin_arch *arch,
                             const pom_dyn_params *base, const ark_opts *ao, int n,
                             pom_error *err) {
  pom_dyn_params par = *base;
  par.solver.rtol = r->rtol;
  par.solver.atol_scale = r->atol_scale;
  pom_status st = POM_OK;
  POM_TRY(pom_dyn_model_create(&r->m, mech, arch, &par, err));
  POM_TRY(pom_dyn_data_create(&r->d, r->m, err));
  r->res = calloc((size_t)n, sizeof *r->res);
  if (!r->res) POM_FAIL(err, POM_ERR_NOMEM, "allocating results");
  if (r->md->table < 0) return POM_OK;
  if (r->m->relative)
    POM_FAIL(err, POM_ERR_ARG, "the model has absolute-only error weights: not benched here");
  pom_dyn_data *d = r->d;
  r->n_qs = (int)lround(par.maneuver.horizon / BENCH_GRID_DT) + 1;
  r->qs = calloc((size_t)r->n_qs * 3, sizeof *r->qs);
  if (!r->qs) POM_FAIL(err, POM_ERR_NOMEM, "allocating the %d-sample grid", r->n_qs);
  r->ark = ARKStepCreate(NULL, pom_dyn_cvode_rhs, 0.0, d->y, d->ctx);
  if (!r->ark) POM_FAIL(err, POM_ERR_NOMEM, "ARKStepCreate failed");
  if (ARKStepSetErrHandlerFn(r->ark, ark_error_handler, r) != ARK_SUCCESS ||
      ARKStepSetInterpolantType(r->ark, ao->interp) != ARK_SUCCESS ||
      (ao->interp_degree > 0 &&
       ARKStepSetInterpolantDegree(r->ark, ao->interp_degree) != ARK_SUCCESS) ||
      ARKStepSetTableNum(r->ark, (ARKODE_DIRKTableID)r->md->table, ARKODE_ERK_NONE) !=
          ARK_SUCCESS ||
      ARKStepSVtolerances(r->ark, r->rtol, d->atol) != ARK_SUCCESS ||
      ARKStepSetUserData(r->ark, d) != ARK_SUCCESS ||
      ARKStepSetMaxNumSteps(r->ark, par.solver.max_steps) != ARK_SUCCESS ||
      ARKStepSetLinearSolver(r->ark, d->LS, d->A) != ARK_SUCCESS ||
      ARKStepSetLinSysFn(r->ark, ark_linsys) != ARK_SUCCESS ||
      (ao->predictor > 0 && ARKStepSetPredictorMethod(r->ark, ao->predictor) != ARK_SUCCESS) ||
      (ao->nlscoef > 0 && ARKStepSetNonlinConvCoef(r->ark, ao->nlscoef) != ARK_SUCCESS) ||
      (ao->lsetup_freq > 0 && ARKStepSetLSetupFrequency(r->ark, ao->lsetup_freq) != ARK_SUCCESS) ||
      (ao->jac_freq > 0 && ARKStepSetJacEvalFrequency(r->ark, ao->jac_freq) != ARK_SUCCESS))
    POM_FAIL(err, POM_ERR_SOLVER, "configuring ARKStep %s: %s", r->md->name, r->msg);
  /* the error handler's user data is the run; the RHS's is the data */
  return st;
}

static void run_destroy(run *r) {
  if (r->ark) ARKStepFree(&r->ark);
  pom_dyn_data_destroy(r->d);
  pom_dyn_model_destroy(r->m);
  free(r->res);
  free(r->qs);
}

static int parse_list(const char *s, char items[][32], int max) {
  int n = 0;
  while (*s && n < max) {
    size_t len = strcspn(s, ",");
    if (len >= 32) len = 31;
    memcpy(items[n], s, len);
    items[n][len] = '\0';
    ++n;
    s += strcspn(s, ",");
    if (*s == ',') ++s;
  }
  return n;
}

/* Relative errors of a run against the reference: max and rms over the
 * settled actuators with a non-zero reference; *miss counts maneuvers that
 * failed or whose settled/unsettled state differs. */
static void errors(const run *r, const outcome *ref, int n, int n_act, double *ts_max,
                   double *ts_rms, double *E_max, double *E_rms, int *miss) {
  double s2 = 0, e2 = 0;
  long ns = 0, ne = 0;
  *ts_max = *E_max = 0;
  *miss = 0;
  for (int k = 0; k < n; ++k) {
    const outcome *o = &r->res[k], *f = &ref[k];
    if (!f->ok) continue;
    if (!o->ok) {
      ++*miss;
      continue;
    }
    for (int a = 0; a < n_act; ++a) {
      if (isnan(o->ts[a]) != isnan(f->ts[a])) {
        ++*miss;
      } else if (!isnan(f->ts[a]) && f->ts[a] > 0) {
        double e = fabs(o->ts[a] - f->ts[a]) / f->ts[a];
        *ts_max = fmax(*ts_max, e);
        s2 += e * e;
        ++ns;
      }
      if (f->E[a] != 0) {
        double e = fabs(o->E[a] - f->E[a]) / fabs(f->E[a]);
        *E_max = fmax(*E_max, e);
        e2 += e * e;
        ++ne;
      }
    }
  }
  *ts_rms = ns ? sqrt(s2 / (double)ns) : 0;
  *E_rms = ne ? sqrt(e2 / (double)ne) : 0;
}

/* First exit from saturation (s) of maneuver target at the reference: the
 * earliest sample at which one actuator's voltage is inside the limit after
 * a sample at it; -1 when no drive saturates. */
static double first_exit(const pom_dyn_model *m, pom_dyn_data *d, pom_dyn_trace *tr,
                         const double target[3], pom_error *err) {
  pom_dyn_metrics mt;
  if (pom_dyn_simulate(m, d, target, &mt, tr, err) != POM_OK) return -2;
  double lim = m->par.actuator.voltage_limit * (1 - 1e-9);
  for (int k = 1; k < tr->n; ++k)
    for (int a = 0; a < m->n_actuators; ++a)
      if (fabs(tr->voltage[3 * (k - 1) + a]) >= lim && fabs(tr->voltage[3 * k + a]) < lim)
        return tr->t[k];
  return -1;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr,
            "usage: %s CONFIG [n=N] [methods=bdf,esdirk436,...] [rtols=1e-4,...] "
            "[shipped=0|1] [ref=RTOL] [ref2=RTOL] [repeats=R] [interp=lagrange|hermite] "
            "[hist=0|1] [check=0|1] [q=q1,q2,q3] [grind=0|1]\n",
            argv[0]);
    return 2;
  }
  int n_req = 20, repeats = 3, shipped = 1, hist = 1, check = 0, grind = 0;
  ark_opts ao = {ARK_INTERP_LAGRANGE, 0, 0.0, 0, 0, 0};
  double ref_rtol = 1e-10, ref2_rtol = 1e-9, q_one[3] = {0, 0, 0};
  int have_q = 0;
  char mlist[MAX_LIST][32], rlist[MAX_LIST][32];
  int n_methods = parse_list("bdf,esdirk324,sdirk534,esdirk436,ark548,esdirk547", mlist, MAX_LIST);
  int n_rtols = parse_list("1e-4,1e-5,1e-6,1e-7,1e-8", rlist, MAX_LIST);
  for (int i = 2; i < argc; ++i) {
    const char *eq = strchr(argv[i], '=');
    if (!eq) {
      fprintf(stderr, "bench_integrators: expected key=value, got '%s'\n", argv[i]);
      return 2;
    }
    const char *v = eq + 1;
    size_t kl = (size_t)(eq - argv[i]);
#define KEY(s) (kl == strlen(s) && strncmp(argv[i], s, kl) == 0)
    if (KEY("n"))
      n_req = atoi(v);
    else if (KEY("methods"))
      n_methods = parse_list(v, mlist, MAX_LIST);
    else if (KEY("rtols"))
      n_rtols = parse_list(v, rlist, MAX_LIST);
    else if (KEY("shipped"))
      shipped = atoi(v);
    else if (KEY("ref"))
      ref_rtol = atof(v);
    else if (KEY("ref2"))
      ref2_rtol = atof(v);
    else if (KEY("repeats"))
      repeats = atoi(v);
    else if (KEY("interp"))
      ao.interp = strcmp(v, "hermite") == 0 ? ARK_INTERP_HERMITE : ARK_INTERP_LAGRANGE;
    else if (KEY("predictor"))
      ao.predictor = atoi(v);
    else if (KEY("nlscoef"))
      ao.nlscoef = atof(v);
    else if (KEY("lsetup"))
      ao.lsetup_freq = atoi(v);
    else if (KEY("jacfreq"))
      ao.jac_freq = atol(v);
    else if (KEY("degree"))
      ao.interp_degree = atoi(v);
    else if (KEY("hist"))
      hist = atoi(v);
    else if (KEY("check"))
      check = atoi(v);
    else if (KEY("q")) {
      if (sscanf(v, "%lf,%lf,%lf", &q_one[0], &q_one[1], &q_one[2]) != 3) return 2;
      have_q = 1;
    } else if (KEY("grind"))
      grind = atoi(v);
    else {
      fprintf(stderr, "bench_integrators: unknown key in '%s'\n", argv[i]);
      return 2;
    }
#undef KEY
  }
  if (n_req < 1 || repeats < 1) return 2;
  if (grind) hist = 0, repeats = 1, check = 0;

  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_params par;
  pom_doe_maneuvers mv;
  double(*target)[3] = calloc((size_t)n_req, sizeof *target);
  double *t_exit = calloc((size_t)n_req, sizeof *t_exit);
  run *runs = calloc((size_t)(n_methods * (n_rtols + 1)), sizeof *runs);
  run ref, ref2;
  memset(&ref, 0, sizeof ref);
  memset(&ref2, 0, sizeof ref2);
  pom_dyn_trace *tr = NULL;
  int n_runs = 0, n = 0, rc = 1;
  const method_desc bdf = methods_known[0];
  if (!mech || !target || !t_exit || !runs) goto done;
  if (pom_cfg_load(&cfg, argv[1], &err) != POM_OK ||
      pom_kin_arch_load(&arch, cfg, &err) != POM_OK ||
      pom_kin_mechanism_build(mech, &arch, cfg, &err) != POM_OK)
    goto fail;
  pom_dyn_params_defaults(&par);
  pom_doe_maneuvers_defaults(&mv);
  if (pom_dyn_params_load(&par, cfg, &err) != POM_OK ||
      pom_doe_maneuvers_load(&mv, cfg, &err) != POM_OK)
    goto fail;
  if (have_q) {
    for (int a = 0; a < 3; ++a)
      target[0][a] = 1e-3 * q_one[a];
    n = 1;
  } else {
    pom_doe_maneuver_targets(target, &n, &mv, mv.seed, n_req, &arch);
  }
  if (n < 1) {
    fprintf(stderr, "bench_integrators: no target inside the stroke\n");
    goto done;
  }

  /* the runs: every method at every rtol of the ladder, then the shipped pair */
  for (int i = 0; i < n_methods; ++i) {
    const method_desc *md = NULL;
    for (int j = 0; j < N_KNOWN; ++j)
      if (strcmp(mlist[i], methods_known[j].name) == 0) md = &methods_known[j];
    if (!md) {
      fprintf(stderr, "bench_integrators: unknown method '%s'\n", mlist[i]);
      goto done;
    }
    for (int j = 0; j <= n_rtols; ++j) {
      if (j == n_rtols && !shipped) break;
      run *r = &runs[n_runs++];
      r->md = md;
      r->shipped = j == n_rtols;
      r->rtol = r->shipped ? par.solver.rtol : atof(rlist[j]);
      r->atol_scale = r->shipped ? par.solver.atol_scale : 0.0;
      if (run_create(r, mech, &arch, &par, &ao, n, &err) != POM_OK) goto fail;
    }
  }

  if (!grind) {
    /* the reference(s): CVODE BDF at natural tolerances */
    ref.md = ref2.md = &bdf;
    ref.rtol = ref_rtol;
    ref2.rtol = ref2_rtol;
    if (run_create(&ref, mech, &arch, &par, &ao, n, &err) != POM_OK ||
        pom_dyn_trace_create(&tr, ref.m, &err) != POM_OK)
      goto fail;
    for (int k = 0; k < n; ++k) {
      t_exit[k] = first_exit(ref.m, ref.d, tr, target[k], &err);
      if (t_exit[k] < -1.5) goto fail;
      if (integrate_one(&ref, target[k], t_exit[k], &ref.res[k]) != 0) goto fail_run_ref;
    }
    if (ref2_rtol > 0) {
      if (run_create(&ref2, mech, &arch, &par, &ao, n, &err) != POM_OK) goto fail;
      for (int k = 0; k < n; ++k)
        if (integrate_one(&ref2, target[k], t_exit[k], &ref2.res[k]) != 0) goto fail_run_ref;
    }
  }

  /* bookkeeping pass (counts, metrics, step bins), then the timed passes
   * with the runs alternated */
  if (!grind)
    for (int i = 0; i < n_runs; ++i) {
      run *r = &runs[i];
      for (int k = 0; k < n; ++k) {
        outcome *o = &r->res[k];
        if (integrate_one(r, target[k], t_exit[k], o) != 0) {
          fprintf(stderr, "bench_integrators: %s rtol %g maneuver %d failed: %s\n", r->md->name,
                  r->rtol, k, r->msg);
          o->ok = 0;
          continue;
        }
        if (hist && r->md->table < 0) {
          long ns = cvode_step_bins(r, target[k], t_exit[k], o->bins);
          if (ns != o->steps) {
            fprintf(stderr, "bench_integrators: CVODE loop took %ld steps, the driver %ld\n", ns,
                    o->steps);
            goto done;
          }
        }
      }
    }
  for (int i = 0; i < n_runs; ++i)
    runs[i].cpu = INFINITY;
  for (int pass = 0; pass < repeats; ++pass)
    for (int i = 0; i < n_runs; ++i) {
      run *r = &runs[i];
      double c0 = cpu_seconds();
      for (int k = 0; k < n; ++k)
        (void)integrate_one(r, target[k], -1, NULL);
      r->cpu = fmin(r->cpu, (cpu_seconds() - c0) / n);
    }
  if (grind) {
    printf("grind: %d run(s) x %d maneuver(s), CPU %.3f ms per maneuver\n", n_runs, n,
           runs[0].cpu * 1e3);
    rc = 0;
    goto done;
  }

  /* report */
  int n_act = ref.m->n_actuators;
  printf("# %s, %s: %d maneuvers (montecarlo seed %llu, targets 0..%d), reference CVODE BDF "
         "rtol %.0e (natural atol), ARKode interpolant %s\n",
         argv[1], arch.name, n, (unsigned long long)mv.seed, n_req - 1, ref_rtol,
         ao.interp == ARK_INTERP_LAGRANGE ? "Lagrange" : "Hermite");
  if (ref2_rtol > 0) {
    double a, b, c, e;
    int miss;
    errors(&ref2, ref.res, n, n_act, &a, &b, &c, &e, &miss);
    printf("# reference check: rtol %.0e against %.0e: settling time max %.2e rms %.2e, energy "
           "max %.2e rms %.2e, %d mismatches\n",
           ref2_rtol, ref_rtol, a, b, c, e, miss);
  }
  printf("\n| method | rtol | steps | attempts | RHS | Jacobians | factorizations | Newton | CPU "
         "ms | ts err max | ts err rms | E err max | E err rms | fails |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int i = 0; i < n_runs; ++i) {
    run *r = &runs[i];
    double tm, tr2, em, er;
    int miss;
    errors(r, ref.res, n, n_act, &tm, &tr2, &em, &er, &miss);
    double s[6] = {0};
    int ok = 0;
    for (int k = 0; k < n; ++k) {
      const outcome *o = &r->res[k];
      if (!o->ok) continue;
      ++ok;
      s[0] += (double)o->steps, s[1] += (double)o->attempts, s[2] += (double)o->rhs;
      s[3] += (double)o->jacs, s[4] += (double)o->setups, s[5] += (double)o->newton;
    }
    if (ok)
      for (int j = 0; j < 6; ++j)
        s[j] /= ok;
    char rt[32];
    if (r->shipped)
      snprintf(rt, sizeof rt, "%.0e, atol_scale %.0e", r->rtol, r->atol_scale);
    else
      snprintf(rt, sizeof rt, "%.0e", r->rtol);
    printf("| %s | %s | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.2f | %.1e | %.1e | %.1e | "
           "%.1e | %d |\n",
           r->md->name, rt, s[0], s[1], s[2], s[3], s[4], s[5], r->cpu * 1e3, tm, tr2, em, er,
           miss);
  }
  if (hist) {
    printf("\nsteps per maneuver by phase (first saturation exit t_x at the reference):\n\n");
    printf("| method | rtol | before t_x | t_x .. +0.5 ms | +0.5 .. +5 ms | after +5 ms |\n");
    printf("|---|---|---|---|---|---|\n");
    for (int i = 0; i < n_runs; ++i) {
      run *r = &runs[i];
      double b[N_BINS] = {0};
      int ok = 0;
      for (int k = 0; k < n; ++k)
        if (r->res[k].ok) {
          ++ok;
          for (int j = 0; j < N_BINS; ++j)
            b[j] += (double)r->res[k].bins[j];
        }
      printf("| %s | %.0e%s | %.0f | %.0f | %.0f | %.0f |\n", r->md->name, r->rtol,
             r->shipped ? " (shipped)" : "", b[0] / fmax(ok, 1), b[1] / fmax(ok, 1),
             b[2] / fmax(ok, 1), b[3] / fmax(ok, 1));
    }
  }
  rc = 0;
  if (check) {
    /* along each method's ladder, every rung's largest error below 0.3 x the
     * previous rung's, for the settling times and for the energies: a
     * reference no better than the tight rungs, or a metric taken from the
     * wrong place, stops the decrease */
    for (int i = 1; i < n_runs; ++i) {
      run *lo = &runs[i - 1], *hi = &runs[i];
      if (lo->md != hi->md || lo->shipped || hi->shipped) continue;
      double t0, t1, e0, e1, dummy;
      int m0, m1;
      errors(lo, ref.res, n, n_act, &t0, &dummy, &e0, &dummy, &m0);
      errors(hi, ref.res, n, n_act, &t1, &dummy, &e1, &dummy, &m1);
      int pass = m0 == 0 && m1 == 0 && t1 < 0.3 * t0 && e1 < 0.3 * e0;
      printf("check %s: rtol %.0e -> %.0e: settling-time error %.2e -> %.2e, energy error %.2e "
             "-> %.2e: %s\n",
             lo->md->name, lo->rtol, hi->rtol, t0, t1, e0, e1, pass ? "ok" : "FAIL");
      if (!pass) rc = 1;
    }
  }
  goto done;
fail_run_ref:
  fprintf(stderr, "bench_integrators: the reference failed: %s\n", ref.msg);
  goto done;
fail:
  fprintf(stderr, "bench_integrators: %s\n", err.message);
done:
  for (int i = 0; i < n_runs; ++i)
    run_destroy(&runs[i]);
  run_destroy(&ref);
  run_destroy(&ref2);
  pom_dyn_trace_destroy(tr);
  pom_cfg_destroy(cfg);
  free(mech);
  free(target);
  free(t_exit);
  free(runs);
  return rc;
}
