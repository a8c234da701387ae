/* dyn_simulate.c - per-worker CVODE data, one maneuver (BDF + Newton with the
 * formulation's finite-difference Jacobian and linear solver), traces and
 * maneuver metrics (docs/dynamics.md sections 7-8), the same driver for
 * every formulation (section 15). */
#include "dyn_internal.h"
#include "pom_math.h"

#include <cvode/cvode_ls.h>
#include <math.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- helpers ------------------------------------------------------------- */
static double now_seconds(void) {
  struct timespec ts;
  if (timespec_get(&ts, TIME_UTC) != TIME_UTC) return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CVODE reports its failures here instead of printing them. */
static void cvode_error_handler(int code, const char *module, const char *function, char *msg,
                                void *user_data) {
  pom_dyn_data *d = user_data;
  snprintf(d->cvode_msg, sizeof d->cvode_msg, "%s (%s, %s, flag %d)", msg ? msg : "",
           module ? module : "", function ? function : "", code);
}

/* Number of output samples: t_k = min(k dt, horizon), k = 0..K. */
/* CVODE's error weights when some states have no relative term
 * (m->relative): w_i = 1 / (rtol |y_i| [relative_i] + atol_i), the same rule as
 * CVodeSVtolerances otherwise (docs/dynamics-exact.md section 5). */
static int error_weights(N_Vector yv, N_Vector ewt, void *user_data) {
  const pom_dyn_data *d = user_data;
  const pom_dyn_model *m = d->m;
  const double *y = N_VGetArrayPointer(yv), *atol = m->atol, rtol = m->par.solver.rtol;
  const unsigned char *rel = m->relative;
  double *w = N_VGetArrayPointer(ewt);
  for (int i = 0; i < m->n_states; ++i) {
    double tol = (atol[i] + (rel[i] ? rtol * fabs(y[i]) : 0.0)) / d->tol_tighten;
    if (!(tol > 0.0)) return -1; /* CVODE reports an illegal weight */
    w[i] = 1.0 / tol;
  }
  return 0;
}

static int sample_count(const pom_dyn_params *p) {
  double r = p->maneuver.horizon / p->maneuver.output_dt;
  int K = (int)ceil(r - 1e-9 * r);
  return K + 1;
}

static double sample_time(const pom_dyn_params *p, int k) {
  return fmin((double)k * p->maneuver.output_dt, p->maneuver.horizon);
}

/* ---- the formulation's RHS ---------------------------------------------- */
int pom_dyn_eval(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot) {
  d->out_from_roots = 0;
  if (d->setpoint_fn) d->setpoint_fn(d->setpoint_ctx, d->t, d->target);
  return m->form->eval(m, d, y, ydot);
}

double pom_dyn_stored(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  return m->form->stored(m, d, y);
}

int pom_dyn_cvode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data) {
  pom_dyn_data *d = user_data;
  if (d->nls_in) {
    if (d->nls_first) { /* the Newton's residual: CVODE's f vector of this step */
      d->nls_f = ydot;
      d->nls_t = t;
      d->nls_first = 0;
    }
  } else if (d->f_pending) {
    /* CVODES' staggered corrector evaluates f at the converged y into the
     * same vector, only to hand it to the sensitivities' right-hand side,
     * which does not read it (dyn_sens.c): skipped, and marked so that a
     * linear-system setup that does read it evaluates it then */
    d->f_pending = 0;
    if (ydot == d->nls_f && t == d->nls_t) {
      d->f_lazy = ydot;
      ++d->f_skipped;
      return 0;
    }
  }
  if (ydot == d->f_lazy) d->f_lazy = NULL;
  d->t = t;
  ++d->rhs_count;
  if (d->setpoint_fn) d->setpoint_fn(d->setpoint_ctx, t, d->target);
  int r = d->m->form->eval(d->m, d, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  d->last_euler_singular = d->out.euler_singular;
  d->last_nonfinite = d->out.nonfinite;
  d->euler_singular_count += d->out.euler_singular;
  d->nonfinite_count += d->out.nonfinite;
  d->kin_fail_count += d->out.kin_fail;
  return r;
}

int pom_dyn_rhs_if_lazy(pom_dyn_data *d, sunrealtype t, N_Vector y, N_Vector fy) {
  if (!d->f_lazy || fy != d->f_lazy) return 0;
  return pom_dyn_cvode_rhs(t, y, fy, d);
}

/* The state's Newton solve: SUNDIALS' own, marking the converged solve of
 * a staggered sensitivity run (pom_dyn_cvode_rhs). A plain run goes
 * through the same solver with nothing marked: the same arithmetic. */
static int state_newton_solve(SUNNonlinearSolver nls, N_Vector y0, N_Vector ycor, N_Vector w,
                              sunrealtype tol, sunbooleantype setup, void *mem) {
  void *ud = NULL;
  if (CVodeGetUserData(mem, &ud) != CV_SUCCESS || !ud)
    return SUNNonlinSolSolve_Newton(nls, y0, ycor, w, tol, setup, mem);
  pom_dyn_data *d = ud;
  d->nls_in = d->nls_first = 1;
  d->f_pending = 0;
  d->nls_f = NULL;
  int r = SUNNonlinSolSolve_Newton(nls, y0, ycor, w, tol, setup, mem);
  d->nls_in = 0;
  d->f_pending = r == SUN_NLS_SUCCESS && d->sens && d->sens_lazy_f && d->nls_f;
  return r;
}

/* ---- data create / destroy ----------------------------------------------- */
pom_status pom_dyn_data_create(pom_dyn_data **out, const pom_dyn_model *m, pom_error *err) {
  pom_status st = POM_OK;
  pom_dyn_data *d = NULL;
  if (!out || !m) POM_FAIL(err, POM_ERR_ARG, "pom_dyn_data_create: NULL argument");
  *out = NULL;
  d = calloc(1, sizeof *d);
  if (!d) POM_FAIL(err, POM_ERR_NOMEM, "allocating dynamics data");
  d->m = m;
  d->tol_tighten = 1.0;
  const pom_dyn_params *p = &m->par;
  const sunindextype n = m->n_states;
  if (SUNContext_Create(NULL, &d->ctx) != 0)
    POM_FAIL_GOTO(err, POM_ERR_SOLVER, fail, "SUNContext_Create failed");
  d->y = N_VNew_Serial(n, d->ctx);
  d->atol = N_VNew_Serial(n, d->ctx);
  d->ytmp = N_VNew_Serial(n, d->ctx);
  d->ftmp = N_VNew_Serial(n, d->ctx);
  if (!d->y || !d->atol || !d->ytmp || !d->ftmp)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "allocating CVODE vectors (%ld states)", (long)n);
  /* CVODE clones its vectors from y (and atol): they inherit the kernels;
   * ytmp receives CVodeGetDky's interpolation at the settling nodes and trace samples, which
   * runs on its own operations */
  pom_dyn_nvec_fast_ops(d->y);
  pom_dyn_nvec_fast_ops(d->atol);
  pom_dyn_nvec_fast_ops(d->ytmp);
  pom_dyn_nvec_fast_ops(d->ftmp);
  memcpy(N_VGetArrayPointer(d->atol), m->atol, (size_t)n * sizeof(double));
  N_VConst(0.0, d->y);

  d->cvode = CVodeCreate(CV_BDF, d->ctx);
  if (!d->cvode) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "CVodeCreate failed");
  if (CVodeSetErrHandlerFn(d->cvode, cvode_error_handler, d) != CV_SUCCESS ||
      CVodeInit(d->cvode, pom_dyn_cvode_rhs, 0.0, d->y) != CV_SUCCESS ||
      CVodeSVtolerances(d->cvode, p->solver.rtol, d->atol) != CV_SUCCESS ||
      CVodeSetUserData(d->cvode, d) != CV_SUCCESS ||
      (m->relative && CVodeWFtolerances(d->cvode, error_weights) != CV_SUCCESS) ||
      CVodeSetMaxNumSteps(d->cvode, p->solver.max_steps) != CV_SUCCESS ||
      CVodeSetMaxOrd(d->cvode, m->max_order) != CV_SUCCESS ||
      CVodeSetStabLimDet(d->cvode, p->solver.stability_limit_detection ? 1 : 0) != CV_SUCCESS ||
      (p->solver.max_step > 0 && CVodeSetMaxStep(d->cvode, p->solver.max_step) != CV_SUCCESS))
    POM_FAIL_GOTO(err, POM_ERR_SOLVER, fail, "configuring CVODE: %s", d->cvode_msg);
  /* the state's Newton solver: CVODE's default, made here to mark its
   * converged solves (state_newton_solve) */
  d->nls = SUNNonlinSol_Newton(d->y, d->ctx);
  if (!d->nls) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "creating CVODE's Newton solver");
  d->nls->ops->solve = state_newton_solve;
  if (CVodeSetNonlinearSolver(d->cvode, d->nls) != CV_SUCCESS)
    POM_FAIL_GOTO(err, POM_ERR_SOLVER, fail, "attaching the Newton solver: %s", d->cvode_msg);
  /* the rigid path's Newton accuracy at high loop gain (dyn_exact_order.c) */
  if (m->newton_coef > 0.0 && CVodeSetNonlinConvCoef(d->cvode, m->newton_coef) != CV_SUCCESS)
    POM_FAIL_GOTO(err, POM_ERR_SOLVER, fail, "configuring CVODE: %s", d->cvode_msg);

  /* the formulation's scratch, Newton matrix and linear solver */
  POM_TRY_GOTO(m->form->data_init(m, d, err), fail);
  if (m->ctrl->work_create)
    POM_TRY_GOTO(m->ctrl->work_create(&d->ctrl_work, m->ctrl_model, err), fail);
  if (!d->A || !d->LS)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "creating the %s linear solver",
                  pom_dyn_linsol_name(p->solver.linear_solver));
  if (CVodeSetLinearSolver(d->cvode, d->LS, d->A) != CV_SUCCESS ||
      CVodeSetLinSysFn(d->cvode, m->form->linsys) != CV_SUCCESS)
    POM_FAIL_GOTO(err, POM_ERR_SOLVER, fail, "attaching the linear solver: %s", d->cvode_msg);

  d->n_samples = sample_count(p);
  d->yfinal = calloc((size_t)n, sizeof *d->yfinal);
  d->ysave = calloc((size_t)n, sizeof *d->ysave);
  d->peak.buf = calloc((size_t)n, sizeof *d->peak.buf);
  d->jac = calloc((size_t)m->nnz, sizeof *d->jac);
  if (!d->yfinal || !d->ysave || !d->peak.buf || !d->jac)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "allocating final-state buffers");
  POM_TRY_GOTO(pom_dyn_settle_data(d, err), fail);
  *out = d;
  return POM_OK;
fail:
  pom_dyn_data_destroy(d);
  return st;
}

void pom_dyn_data_destroy(pom_dyn_data *d) {
  if (!d) return;
  if (d->cvode) CVodeFree(&d->cvode);
  if (d->nls) SUNNonlinSolFree(d->nls);
  if (d->LS) SUNLinSolFree(d->LS);
  if (d->A) SUNMatDestroy(d->A);
  if (d->y) N_VDestroy(d->y);
  if (d->atol) N_VDestroy(d->atol);
  if (d->ytmp) N_VDestroy(d->ytmp);
  if (d->ftmp) N_VDestroy(d->ftmp);
  if (d->ctx) SUNContext_Free(&d->ctx);
  free(d->settle.rec);
  free(d->yfinal);
  free(d->ysave);
  free(d->peak.buf);
  free(d->jac);
  if (d->m) d->m->form->data_free(d);
  if (d->m && d->ctrl_work) d->m->ctrl->work_destroy(d->ctrl_work);
  free(d);
}

/* ---- traces -------------------------------------------------------------- */
pom_status pom_dyn_trace_create(pom_dyn_trace **out, const pom_dyn_model *m, pom_error *err) {
  pom_status st = POM_OK;
  if (!out || !m) POM_FAIL(err, POM_ERR_ARG, "pom_dyn_trace_create: NULL argument");
  *out = NULL;
  pom_dyn_trace *tr = calloc(1, sizeof *tr);
  if (!tr) POM_FAIL(err, POM_ERR_NOMEM, "allocating a trace");
  size_t cap = (size_t)sample_count(&m->par) + 1;
  tr->capacity = (int)cap;
  tr->t = calloc(cap, sizeof(double));
  tr->q = calloc(cap * 3, sizeof(double));
  tr->q_dot = calloc(cap * 3, sizeof(double));
  tr->current = calloc(cap * 3, sizeof(double));
  tr->voltage = calloc(cap * 3, sizeof(double));
  tr->energy = calloc(cap * 3, sizeof(double));
  tr->euler_zyx = calloc(cap * 3, sizeof(double));
  tr->quat = calloc(cap * 4, sizeof(double));
  tr->deflection = calloc(cap, sizeof(double));
  if (!tr->t || !tr->q || !tr->q_dot || !tr->current || !tr->voltage || !tr->energy ||
      !tr->euler_zyx || !tr->quat || !tr->deflection)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "allocating a trace of %zu samples", cap);
  *out = tr;
  return POM_OK;
fail:
  pom_dyn_trace_destroy(tr);
  return st;
}

void pom_dyn_trace_destroy(pom_dyn_trace *tr) {
  if (!tr) return;
  free(tr->t);
  free(tr->q);
  free(tr->q_dot);
  free(tr->current);
  free(tr->voltage);
  free(tr->energy);
  free(tr->euler_zyx);
  free(tr->quat);
  free(tr->deflection);
  free(tr);
}

/* ---- one maneuver -------------------------------------------------------- */
/* Records trace sample k from state y (outputs must be evaluated). */
static void record_sample(const pom_dyn_model *m, pom_dyn_data *d, int k, double t, const double *y,
                          pom_dyn_trace *tr) {
  const dyn_outputs *o = &d->out;
  if (k >= tr->capacity) return;
  tr->t[k] = t;
  for (int a = 0; a < 3; ++a) {
    int on = a < m->n_actuators;
    tr->q[3 * k + a] = on ? o->q[a] : 0.0;
    tr->q_dot[3 * k + a] = on ? o->q_dot[a] : 0.0;
    tr->current[3 * k + a] = on ? o->current[a] : 0.0;
    tr->voltage[3 * k + a] = on ? o->voltage[a] : 0.0;
    tr->energy[3 * k + a] = on ? y[m->act[a].acc_state + DYN_ACC_SOURCE] : 0.0;
  }
  double R[9];
  m->form->platform_rotation(m, y, R);
  (void)pom_euler_zyx_from_matrix(tr->euler_zyx + 3 * k, R); /* angles valid even if singular */
  pom_quat_from_matrix(tr->quat + 4 * k, R);
  tr->deflection[k] = o->max_lin_deflection;
  tr->n = k + 1;
}

static void track_extremes(const pom_dyn_model *m, const pom_dyn_data *d, pom_dyn_metrics *mt) {
  for (int a = 0; a < m->n_actuators; ++a) {
    mt->peak_voltage[a] = fmax(mt->peak_voltage[a], fabs(d->out.voltage[a]));
    mt->peak_effort[a] = fmax(mt->peak_effort[a], fabs(d->out.effort[a]));
  }
  mt->peak_angular_rate = fmax(mt->peak_angular_rate, d->out.platform_rate);
  mt->max_deflection = fmax(mt->max_deflection, d->out.max_lin_deflection);
  mt->max_angular_deflection = fmax(mt->max_angular_deflection, d->out.max_ang_deflection);
}

static pom_status fail_status(pom_dyn_data *d, int flag, double t, pom_dyn_metrics *mt,
                              pom_error *err) {
  pom_status st;
  if (d->below_min_dexterity)
    st = pom_error_set(err, POM_ERR_SINGULAR, __FILE__, __LINE__,
                       "rigid joints: the platform reached a near-singular pose at t = %.6g s "
                       "(1/kappa(J) <= 3/kappa_F(J) = %.3g < solver.min_dexterity = %g)",
                       t, d->out.dexterity_bound, d->m->par.solver.min_dexterity);
  else if (d->last_euler_singular || d->euler_singular_count > 0)
    st = pom_error_set(err, POM_ERR_EULER_SINGULAR, __FILE__, __LINE__,
                       "a body reached |cos pitch| < %g at t = %.6g s; use scene.orientation = "
                       "\"quaternion\"",
                       d->m->par.scene.euler_cos_min, t);
  else if (d->kin_fail_count > 0)
    st = pom_error_set(err, POM_ERR_UNREACHABLE, __FILE__, __LINE__,
                       "rigid joints: the mechanism cannot be assembled at the platform "
                       "orientation reached at t = %.6g s (a limb out of reach or singular)",
                       t);
  else if (d->last_nonfinite || d->nonfinite_count > 0)
    st = pom_error_set(err, POM_ERR_NONFINITE, __FILE__, __LINE__,
                       "non-finite state derivative at t = %.6g s", t);
  else if (flag == CV_TOO_MUCH_WORK) { /* dyn_diagnose.c names what holds the steps down */
    char why[sizeof err->message];
    pom_dyn_max_steps_reason(d->m, t, why, sizeof why);
    st = pom_error_set(err, POM_ERR_SOLVER, __FILE__, __LINE__, "%s", why);
  } else
    st = d->m->form->solver_failure(d->m, d, t, err); /* the formulation says more */
  mt->status = st;
  if (err)
    snprintf(mt->reason, sizeof mt->reason, "%s", err->message);
  else
    snprintf(mt->reason, sizeof mt->reason, "%s at t = %.6g s", pom_strerror(st), t);
  return st;
}

/* The dexterity floor (docs/dynamics-exact.md section 3): 1 when the outputs
 * just evaluated put the pose below solver.min_dexterity. A formulation that
 * does not measure it leaves NaN, which never trips it; 0 turns it off. */
static int below_dexterity_floor(const pom_dyn_model *m, pom_dyn_data *d) {
  const double dex_min = m->par.solver.min_dexterity;
  d->below_min_dexterity = dex_min > 0.0 && d->out.dexterity_bound < dex_min;
  return d->below_min_dexterity;
}

static void solver_stats(pom_dyn_data *d, pom_dyn_metrics *mt) {
  long v = 0;
  if (CVodeGetNumSteps(d->cvode, &v) == CV_SUCCESS) mt->steps = v;
  mt->jac_evals = d->jac_count;
  if (CVodeGetNumNonlinSolvIters(d->cvode, &v) == CV_SUCCESS) mt->newton_iters = v;
  if (CVodeGetNumErrTestFails(d->cvode, &v) == CV_SUCCESS) mt->error_test_fails = v;
  if (CVodeGetNumLinSolvSetups(d->cvode, &v) == CV_SUCCESS) mt->linsol_setups = v;
  if (CVodeGetNumNonlinSolvConvFails(d->cvode, &v) == CV_SUCCESS) mt->nonlin_conv_fails = v;
  double h = 0;
  if (CVodeGetLastStep(d->cvode, &h) == CV_SUCCESS) mt->last_step = h;
  mt->rhs_evals = d->rhs_count;
  mt->jac_rhs_evals = d->jac_rhs_count;
}

/* A failed maneuver reports what it did not compute as NaN, never as the 0
 * it was initialised with (docs/results.md section 1d). Stopped before the
 * horizon (reached_end 0): the integrals and the audit (energies,
 * saturation time), the end values (final q, final pointing error) and what
 * the end makes of the steps (max |q|, the tracking average); nothing
 * watched (watched 0: refused, or failed at home): the extremes too. Kept:
 * the extremes over the steps taken (up to the failure time in reason), the
 * solver's counters (the work done), target and horizon (the inputs); the
 * times and flags are unset by the caller. */
static void unset_not_computed(pom_dyn_metrics *mt, int reached_end, int watched) {
  if (!reached_end) {
    for (int a = 0; a < 3; ++a) {
      mt->energy[a] = mt->energy_positive[a] = mt->saturation_time[a] = NAN;
      mt->energy_coil[a] = mt->energy_bearing[a] = NAN;
      mt->final_q[a] = mt->max_abs_q[a] = NAN;
    }
    mt->energy_total = mt->energy_supplied = mt->energy_dissipated = NAN;
    mt->energy_stored_change = mt->energy_parasitic = NAN;
    mt->energy_balance_scale = mt->energy_balance_error = NAN;
    mt->final_pointing_error = mt->tracking_rms_error = mt->rigid_limit_ratio = NAN;
    mt->joint_dissipation_share = NAN;
  }
  if (!watched) {
    for (int a = 0; a < 3; ++a)
      mt->peak_voltage[a] = mt->peak_effort[a] = NAN;
    mt->peak_angular_rate = mt->max_deflection = mt->max_angular_deflection = NAN;
  }
}

/* CVODE's tolerances divided by tighten (1 restores the model's). */
static int set_tolerances(const pom_dyn_model *m, pom_dyn_data *d, double tighten) {
  d->tol_tighten = tighten;
  double *atol = N_VGetArrayPointer(d->atol);
  for (int i = 0; i < m->n_states; ++i)
    atol[i] = m->atol[i] / tighten;
  if (CVodeSVtolerances(d->cvode, m->par.solver.rtol / tighten, d->atol) != CV_SUCCESS) return -1;
  if (m->relative && CVodeWFtolerances(d->cvode, error_weights) != CV_SUCCESS) return -1;
  return 0;
}

/* A stepinfo crossing the run's tolerances do not resolve (settle metrics:
 * settle.stepinfo_need[a] > 1) is located again: the maneuver is integrated
 * once more with every tolerance divided by POM_DYN_STEPINFO_SAFETY x the
 * largest shortfall, when that stays within POM_DYN_STEPINFO_MAX_TIGHTEN and
 * rtol POM_DYN_STEPINFO_MIN_RTOL; the re-run's stepinfo times replace the
 * first run's where it resolves them, every other metric stays the first
 * run's. Its work is added to the counters (docs/results.md section 1c).
 * What is still unresolved stays NaN with stepinfo_unresolved = 1. */
static void stepinfo_rerun(const pom_dyn_model *m, pom_dyn_data *d, const double target[3],
                           const pom_dyn_initial *init, pom_dyn_metrics *mt) {
  double need = 0.0;
  double need_a[POM_MECH_MAX_ACTUATORS];
  for (int a = 0; a < m->n_actuators; ++a) {
    need_a[a] = d->settle.stepinfo_need[a];
    if (mt->stepinfo_unresolved[a]) need = fmax(need, need_a[a]);
  }
  if (!(need > 1.0)) return;
  double tighten = fmax(2.0, POM_DYN_STEPINFO_SAFETY * need);
  if (!(tighten <= POM_DYN_STEPINFO_MAX_TIGHTEN &&
        m->par.solver.rtol / tighten >= POM_DYN_STEPINFO_MIN_RTOL))
    return; /* beyond the cap: flagged */
  pom_dyn_metrics *m2 = malloc(sizeof *m2);
  if (!m2) return; /* flagged, as unresolved */
  memcpy(d->ysave, d->yfinal, (size_t)m->n_states * sizeof(double));
  pom_status st2 = POM_ERR_SOLVER;
  /* a sensitivity run's re-run is plain: its sensitivities stay the first
   * run's (they were read at the horizon) */
  struct dyn_sens *sens = d->sens;
  const int peak_on = d->peak.on; /* and the peak current stays the first run's */
  d->sens = NULL;
  d->peak.on = 0;
  if (sens) pom_dyn_sens_ops.off(d);
  if (set_tolerances(m, d, tighten) == 0)
    st2 = pom_dyn_simulate_ex(m, d, target, init, m2, NULL, NULL);
  d->sens = sens;
  d->peak.on = peak_on;
  if (set_tolerances(m, d, 1.0) != 0) st2 = POM_ERR_SOLVER; /* cannot happen: as configured */
  memcpy(d->yfinal, d->ysave, (size_t)m->n_states * sizeof(double));
  /* the re-run is the more accurate integration: every stepinfo time it
   * resolves is taken from it, the ones the first run resolved too (their
   * crossing may be as far off: section 1c, measured) */
  if (st2 == POM_OK)
    for (int a = 0; a < m->n_actuators; ++a)
      if (!m2->stepinfo_unresolved[a]) {
        mt->settling_time_final[a] = m2->settling_time_final[a];
        mt->stepinfo_unresolved[a] = 0;
      }
  mt->steps += m2->steps;
  mt->rhs_evals += m2->rhs_evals;
  mt->jac_rhs_evals += m2->jac_rhs_evals;
  mt->jac_evals += m2->jac_evals;
  mt->newton_iters += m2->newton_iters;
  mt->error_test_fails += m2->error_test_fails;
  mt->linsol_setups += m2->linsol_setups;
  mt->nonlin_conv_fails += m2->nonlin_conv_fails;
  free(m2);
}

pom_status pom_dyn_simulate_ex(const pom_dyn_model *m, pom_dyn_data *d, const double target[3],
                               const pom_dyn_initial *init, pom_dyn_metrics *mt, pom_dyn_trace *tr,
                               pom_error *err) {
  if (!m || !d || !target || !mt || d->m != m)
    POM_FAIL(err, POM_ERR_ARG, "pom_dyn_simulate: NULL argument or data of another model");
  const pom_dyn_params *p = &m->par;
  double t0_wall = now_seconds();
  memset(mt, 0, sizeof *mt);
  mt->horizon = p->maneuver.horizon;
  mt->pointing_settling_time = mt->final_pointing_error = mt->tracking_rms_error = NAN;
  mt->rigid_limit_ratio = mt->joint_dissipation_share = NAN;
  mt->peak_current = NAN;
  for (int a = 0; a < 3; ++a)
    mt->target[a] = target[a];
  for (int a = 0; a < 3; ++a)
    if (!isfinite(target[a])) {
      /* reported in the metrics too, as every refusal (docs/dynamics.md 8) */
      mt->status =
          pom_error_set(err, POM_ERR_ARG, __FILE__, __LINE__, "target %d is not finite", a + 1);
      snprintf(mt->reason, sizeof mt->reason, "target %d is not finite", a + 1);
      unset_not_computed(mt, 0, 0);
      mt->execution_time = NAN;
      for (int k = 0; k < 3; ++k)
        mt->settling_time[k] = mt->settling_time_final[k] = NAN;
      return mt->status;
    }
  /* a target outside the actuator's stroke is refused before any work
   * (docs/dynamics.md section 14); stroke 0 = not limited. Reported in the
   * display unit of the actuator kind (mm or deg) */
  const pom_act_desc *kind = pom_act_kind_desc(p->actuator.kind);
  const double f = kind->to_display;
  for (int a = 0; a < m->n_actuators; ++a) {
    double half = 0.5 * m->act[a].stroke;
    if (half > 0 && !(fabs(target[a]) <= half)) {
      pom_status st = pom_error_set(err, POM_ERR_LIMIT, __FILE__, __LINE__,
                                    "target of actuator %d = %.10g %s is outside its stroke "
                                    "+-%.10g %s",
                                    a + 1, target[a] * f, kind->display, half * f, kind->display);
      mt->status = st;
      snprintf(mt->reason, sizeof mt->reason, "target of actuator %d = %.10g %s outside the stroke",
               a + 1, target[a] * f, kind->display);
      unset_not_computed(mt, 0, 0);
      mt->execution_time = NAN;
      for (int k = 0; k < 3; ++k)
        mt->settling_time[k] = mt->settling_time_final[k] = NAN;
      return st;
    }
  }
  for (int a = 0; a < m->n_actuators; ++a)
    d->target[a] = target[a];
  d->rhs_count = d->jac_rhs_count = d->jac_count = 0;
  d->jac_valid = 0;
  d->last_euler_singular = d->last_nonfinite = 0;
  d->euler_singular_count = d->nonfinite_count = 0;
  d->kin_fail_count = 0;
  d->below_min_dexterity = 0;
  d->cvode_msg[0] = '\0';
  d->have_final = 0;
  d->f_pending = 0;
  d->f_lazy = NULL;
  d->f_skipped = 0;
  if (tr) tr->n = 0, tr->n_actuators = m->n_actuators;
  /* the target orientation: FK of the setpoints on the home branch, where
   * the architecture is known (docs/results.md section 1b) */
  d->have_target_rotation = m->has_arch && pom_kin_forward(&m->arch, d->target, NULL, NULL,
                                                           d->R_target, NULL, NULL) == POM_OK;
  double *y = N_VGetArrayPointer(d->y);
  double *ys = N_VGetArrayPointer(d->ytmp);
  m->form->initial(m, y, init);
  double E0 = m->form->stored(m, d, y);
  pom_status st = POM_OK;
  int watched = 0; /* the extremes were looked at (from t = 0 on) */
  if (CVodeReInit(d->cvode, 0.0, d->y) != CV_SUCCESS ||
      CVodeSetStopTime(d->cvode, p->maneuver.horizon) != CV_SUCCESS) {
    st = fail_status(d, CV_ILL_INPUT, 0.0, mt, err);
    goto finish;
  }
  if (d->sens) { /* design gradients (dyn_sens.c) */
    st = pom_dyn_sens_ops.begin(m, d, err);
    if (st != POM_OK) {
      mt->status = st;
      snprintf(mt->reason, sizeof mt->reason, "%s", err ? err->message : pom_strerror(st));
      goto finish;
    }
  }
  d->t = 0.0;
  pom_dyn_eval(m, d, y, NULL);
  if (below_dexterity_floor(m, d)) { /* a design singular at home */
    st = fail_status(d, CV_SUCCESS, 0.0, mt, err);
    goto finish;
  }
  if (tr) record_sample(m, d, 0, 0.0, y, tr);
  pom_dyn_settle_begin(m, d, y);
  pom_dyn_validity_begin(m, d);
  track_extremes(m, d, mt);
  watched = 1;
  if (d->peak.on) { /* the peak coil current (dyn_peak.c), when asked */
    st = pom_dyn_peak_ops.begin(m, d, y, err);
    if (st != POM_OK) {
      mt->status = st;
      snprintf(mt->reason, sizeof mt->reason, "%s", err ? err->message : pom_strerror(st));
      goto finish;
    }
  }

  /* the trace's grid, sampled from the interpolant only when a trace is
   * kept; the metrics come from the steps (docs/dynamics.md section 8) */
  int k = 1;
  long n_steps = 0;
  double sens_ts[POM_MECH_MAX_ACTUATORS], sens_tp = 0.0, sens_t0 = 0.0;
  double t = 0.0;
  while (t < p->maneuver.horizon) {
    /* one internal step at a time: CVODE's own mxstep counts per call, so
     * solver.max_steps is enforced here over the whole maneuver */
    if (n_steps++ >= p->solver.max_steps) {
      st = fail_status(d, CV_TOO_MUCH_WORK, t, mt, err);
      goto finish;
    }
    if (p->solver.max_wall > 0 && (n_steps & 15) == 0 &&
        now_seconds() - t0_wall > p->solver.max_wall) {
      /* wall-clock budget (docs/dynamics.md section 14) */
      st = pom_error_set(err, POM_ERR_SOLVER, __FILE__, __LINE__,
                         "wall-clock budget solver.max_wall_s = %g s exhausted at t = %.6g s "
                         "after %ld steps",
                         p->solver.max_wall, t, n_steps);
      mt->status = st;
      snprintf(mt->reason, sizeof mt->reason, "wall-clock budget %g s exhausted at t = %.6g s",
               p->solver.max_wall, t);
      goto finish;
    }
    const double t_start = t;
    int flag = CVode(d->cvode, p->maneuver.horizon, d->y, &t, CV_ONE_STEP);
    if (flag < 0) {
      st = fail_status(d, flag, t, mt, err);
      goto finish;
    }
    if (m->form->near_singular(m, y)) {
      d->last_euler_singular = 1;
      st = fail_status(d, CV_RHSFUNC_FAIL, t, mt, err);
      goto finish;
    }
    /* extremes at every internal step (in a sensitivity run, the band
     * roots' evaluation at the same (t, y) when it was the last) */
    d->t = t;
    if (!(d->sens && pom_dyn_sens_ops.out_at(m, d, t, y))) pom_dyn_eval(m, d, y, NULL);
    if (d->sens) memcpy(d->u_raw_step, d->out.u_raw, sizeof d->u_raw_step);
    if (below_dexterity_floor(m, d)) {
      st = fail_status(d, CV_SUCCESS, t, mt, err);
      goto finish;
    }
    track_extremes(m, d, mt);
    pom_dyn_validity_step(m, d, t);
    if (d->sens) { /* the band times before the watch: the crossings it locates */
      for (int a = 0; a < m->n_actuators; ++a)
        sens_ts[a] = d->settle.act[a].t_settle;
      sens_tp = d->settle.point.t_settle;
      sens_t0 = d->settle.t_prev;
    }
    st = pom_dyn_settle_step(m, d, t, y, err);
    if (st == POM_OK && d->peak.on) st = pom_dyn_peak_ops.step(m, d, t_start, t, err);
    if (st == POM_OK && d->sens)
      st = pom_dyn_sens_ops.step(m, d, sens_t0, t, sens_ts, 1, sens_tp, err);
    if (st != POM_OK) {
      mt->status = st;
      snprintf(mt->reason, sizeof mt->reason, "%s", err ? err->message : pom_strerror(st));
      goto finish;
    }
    if (d->sens && flag == CV_ROOT_RETURN) {
      if (d->peak.on) pom_dyn_peak_ops.corner(m, d, t);
      st = pom_dyn_sens_ops.restart(m, d, t, err);
      if (st != POM_OK) {
        mt->status = st;
        snprintf(mt->reason, sizeof mt->reason, "%s", err ? err->message : pom_strerror(st));
        goto finish;
      }
    }
    while (tr && k < d->n_samples && sample_time(p, k) <= t) {
      double tk = sample_time(p, k);
      if (CVodeGetDky(d->cvode, tk, 0, d->ytmp) != CV_SUCCESS) {
        st = fail_status(d, CV_BAD_T, tk, mt, err);
        goto finish;
      }
      d->t = tk;
      pom_dyn_eval(m, d, ys, NULL);
      track_extremes(m, d, mt);
      record_sample(m, d, k, tk, ys, tr);
      ++k;
    }
  }

  if (d->peak.on) {
    st = pom_dyn_peak_ops.end(m, d, t, y, err);
    if (st != POM_OK) {
      mt->status = st;
      snprintf(mt->reason, sizeof mt->reason, "%s", err ? err->message : pom_strerror(st));
      goto finish;
    }
    mt->peak_current = d->peak.value;
  }
  /* energy audit at the horizon (docs/dynamics.md section 6) */
  if (d->sens) pom_dyn_sens_ops.end(m, d);
  memcpy(d->yfinal, y, (size_t)m->n_states * sizeof(double));
  d->have_final = 1;
  {
    double pos = 0.0;
    for (int a = 0; a < m->n_actuators; ++a) {
      const double *acc = y + m->act[a].acc_state;
      mt->energy[a] = acc[DYN_ACC_SOURCE];
      mt->energy_positive[a] = acc[DYN_ACC_SOURCE_POS];
      mt->saturation_time[a] = acc[DYN_ACC_SATURATED];
      mt->energy_coil[a] = acc[DYN_ACC_COIL];
      mt->energy_bearing[a] = acc[DYN_ACC_BEARING];
      mt->energy_total += mt->energy[a];
      mt->energy_dissipated += acc[DYN_ACC_COIL] + acc[DYN_ACC_BEARING];
      pos += acc[DYN_ACC_SOURCE_POS];
    }
    mt->energy_parasitic = y[m->acc_parasitic];
    mt->energy_dissipated += mt->energy_parasitic;
    mt->energy_supplied = mt->energy_total;
    double E1 = m->form->stored(m, d, y);
    mt->energy_stored_change = E1 - E0;
    double scale = fmax(fmax(pos, mt->energy_dissipated), fmax(fabs(E0), fabs(E1)));
    mt->energy_balance_scale = scale;
    double imbalance = mt->energy_supplied - mt->energy_dissipated - mt->energy_stored_change;
    mt->energy_balance_error = scale > 0 ? fabs(imbalance) / scale : 0.0;
  }
  pom_dyn_settle_metrics(m, d, mt);
  mt->rigid_limit_ratio = pom_dyn_validity_ratio(m, d);
  mt->joint_dissipation_share = pom_dyn_validity_share(m, d, mt->energy_parasitic);
  if (p->solver.max_balance_error > 0 &&
      !(mt->energy_balance_error <= p->solver.max_balance_error)) {
    /* the audit exposes an inaccurate (too loose) or unstable integration
     * that still looks plausible (docs/dynamics.md section 14) */
    st = pom_error_set(err, POM_ERR_UNSTABLE, __FILE__, __LINE__,
                       "energy audit does not close: balance error %.3g > solver.max_balance_error "
                       "= %.3g (integration too loose or unstable; tighten solver.rtol)",
                       mt->energy_balance_error, p->solver.max_balance_error);
    mt->status = st;
    snprintf(mt->reason, sizeof mt->reason,
             "energy audit does not close: balance error %.3g > %.3g; tighten solver.rtol",
             mt->energy_balance_error, p->solver.max_balance_error);
  }
  for (int a = 0; a < m->n_actuators; ++a)
    if (!isfinite(mt->energy[a]) || !isfinite(mt->final_q[a])) {
      st = pom_error_set(err, POM_ERR_NONFINITE, __FILE__, __LINE__,
                         "non-finite metrics for actuator %d", a + 1);
      mt->status = st;
      snprintf(mt->reason, sizeof mt->reason, "non-finite metrics for actuator %d", a + 1);
    }
finish:
  solver_stats(d, mt);
  if (st == POM_OK && d->tol_tighten == 1.0) stepinfo_rerun(m, d, target, init, mt);
  mt->wall_time = now_seconds() - t0_wall;
  if (st != POM_OK) {
    unset_not_computed(mt, d->have_final, watched);
    mt->execution_time = NAN;
    mt->peak_current = NAN;
    mt->pointing_settled = 0;
    mt->pointing_settling_time = NAN;
    for (int a = 0; a < 3; ++a) {
      mt->settled[a] = 0;
      mt->settling_time[a] = mt->settling_time_final[a] = NAN;
    }
  }
  return st;
}

pom_status pom_dyn_simulate(const pom_dyn_model *m, pom_dyn_data *d, const double target[3],
                            pom_dyn_metrics *metrics, pom_dyn_trace *trace, pom_error *err) {
  return pom_dyn_simulate_ex(m, d, target, NULL, metrics, trace, err);
}

/* ---- end-of-run queries -------------------------------------------------- */
void pom_dyn_data_watch_peak_current(pom_dyn_data *d, int on) {
  d->peak.on = on != 0;
}

void pom_dyn_set_setpoint_path(pom_dyn_data *d, pom_dyn_setpoint_fn fn, void *ctx) {
  d->setpoint_fn = fn;
  d->setpoint_ctx = ctx;
}

pom_status pom_dyn_body_pose(const pom_dyn_model *m, const pom_dyn_data *d, int k, double R[9],
                             double x[3], pom_error *err) {
  if (!m || !d || k < 1 || k >= POM_MECH_MAX_BODIES || m->slot_of_mech[k] < 0)
    POM_FAIL(err, POM_ERR_ARG, "pom_dyn_body_pose: body %d is not a moving body", k);
  if (!d->have_final) POM_FAIL(err, POM_ERR_ARG, "pom_dyn_body_pose: no finished simulation");
  return m->form->body_pose(m, d->yfinal, k, R, x, err);
}

double pom_dyn_stored_energy(const pom_dyn_model *m, pom_dyn_data *d) {
  if (!d->have_final) return NAN;
  return m->form->stored(m, d, d->yfinal);
}
