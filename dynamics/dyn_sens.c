/* dyn_sens.c - forward sensitivities of one maneuver on the exact path with
 * CVODES (docs/optimize.md, "Design gradients"): the sensitivity right-hand
 * side as a central directional difference between the caller's perturbed
 * models, the settling times' derivatives by the implicit-function theorem
 * at the last band crossing, the energies from the accumulator states, the
 * tracking integral by its quadrature nodes and the final pointing error. */
#include "dyn_internal.h"
#include "pom_dyn_sens.h"
#include "pom_math.h"

#include <cvodes/cvodes.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Gauss-Legendre nodes of the tracking quadrature (dyn_settle.c). */
static const double gl_node[2] = {0.21132486540518711775, 0.78867513459481288225};

/* The per-run workspace (d->sens). */
struct dyn_sens {
  const pom_dyn_sens_spec *spec;
  int n;
  pom_dyn_data *dx[2][POM_DYN_SENS_MAX]; /* scratch data of plus (0) and minus (1) models */
  double Rt[2][POM_DYN_SENS_MAX][9];     /* target orientation of each perturbed model */
  int have_Rt[2][POM_DYN_SENS_MAX];
  N_Vector *yS;    /* [n] sensitivities (CVODES' state for them) */
  N_Vector *ySt;   /* [n] scratch: sensitivities at an interpolated time */
  N_Vector *atolS; /* [n] absolute tolerances of the sensitivities */
  double rtol_s;   /* their relative tolerance */
  int root_dir[2 * POM_MECH_MAX_ACTUATORS];
  int root_info[2 * POM_MECH_MAX_ACTUATORS];
  /* the nominal's saturation pattern since the last restart (+1 at +limit,
   * -1 at -limit, 0 in the linear band), which every perturbed model's
   * evaluation follows (docs/optimize.md 12.1) */
  int mode[POM_MECH_MAX_ACTUATORS];
  long steps_before; /* steps of the integrations before the last restart */
  long restarts;
  long resyncs; /* restarts at a step end whose pattern disagreed with mode */
  /* the corrector's cache per parameter: the (t, y) of the last call, the
   * plus model's rate there and the sensitivity rate it gave */
  double key_t[POM_DYN_SENS_MAX];
  int key_ok[POM_DYN_SENS_MAX];
  double *ykey[POM_DYN_SENS_MAX], *fp_prev[POM_DYN_SENS_MAX], *fs_prev[POM_DYN_SENS_MAX];
  double *ybuf; /* [n_states] perturbed state */
  /* the band roots' last evaluation on d: its (t, y) */
  double roots_t;
  double *roots_y; /* [n_states] */
  double *ydot;    /* [n_states] rate at an interpolated time */
  double pbar[POM_DYN_SENS_MAX];
  long rhs_evals;
  int failed; /* a non-finite difference */
  /* the last crossing of each band: time, rate dg/dt, dt/dp, and the
   * largest later local maximum of g (grazing margin) */
  double t_cross[POM_MECH_MAX_ACTUATORS + 1];
  double rate[POM_MECH_MAX_ACTUATORS + 1];
  double dt[POM_MECH_MAX_ACTUATORS + 1][POM_DYN_SENS_MAX];
  int have_cross[POM_MECH_MAX_ACTUATORS + 1];
  int cross_bad[POM_MECH_MAX_ACTUATORS + 1];    /* a non-finite sensitivity at the crossing */
  double g_prev[POM_MECH_MAX_ACTUATORS + 1][2]; /* two previous band values after the crossing */
  int n_after[POM_MECH_MAX_ACTUATORS + 1];
  double later_max[POM_MECH_MAX_ACTUATORS + 1]; /* largest later local maximum of g */
  /* the largest g since the last crossing, and at a crossing the largest
   * over the excursion it ends (-inf for the first: the move itself) */
  double run_max[POM_MECH_MAX_ACTUATORS + 1];
  double exc_max[POM_MECH_MAX_ACTUATORS + 1];
  /* the tracking integral's derivative */
  double dtrack[POM_DYN_SENS_MAX];
  /* at the horizon */
  double ds_final[POM_DYN_SENS_MAX][POM_MECH_MAX_ACTUATORS]; /* d energy[a]/dp */
  double dtheta_final[POM_DYN_SENS_MAX];
  int have_final;
  /* the peak coil current's derivative at its argmax so far */
  double dpeak[POM_DYN_SENS_MAX];
};

const char *pom_dyn_grad_why_text(pom_dyn_grad_why why) {
  switch (why) {
  case POM_DYN_GRAD_OK:
    return "defined";
  case POM_DYN_GRAD_NEVER_SETTLED:
    return "never settled (censored at the horizon)";
  case POM_DYN_GRAD_SETTLED_AT_START:
    return "settled from the start";
  case POM_DYN_GRAD_GRAZING:
    return "grazing band crossing";
  case POM_DYN_GRAD_TIE:
    return "a tie (two settling times, or two peak currents)";
  case POM_DYN_GRAD_UNKNOWN:
    return "metric undefined";
  case POM_DYN_GRAD_NONFINITE:
    return "non-finite sensitivity";
  case POM_DYN_GRAD_PEAK_EDGE:
    return "peak current at the start or the horizon";
  case POM_DYN_GRAD_PEAK_KINK:
    return "peak current on a kink of the current";
  }
  return "?";
}

void pom_dyn_sens_spec_defaults(pom_dyn_sens_spec *s) {
  memset(s, 0, sizeof *s);
  s->method = POM_DYN_SENS_STAGGERED;
  s->error_control = 1;
  s->peak_current = 1;
  s->noise_margin = POM_DYN_SENS_MARGIN_DEFAULT;
}

/* ---- angles ---------------------------------------------------------------- */
static double rotation_angle(const double A[9], const double B[9]) {
  double At[9], E[9], rv[3];
  pom_m3_transpose(At, A);
  pom_m3_mul(E, At, B);
  pom_m3_rotvec(rv, E);
  return pom_v3_norm(rv);
}

/* ---- band functions of a state under one model ---------------------------- */
/* g = |q_a - ref| - settle_band |ref| (a >= 0), or the pointing angle minus
 * its band (a < 0; Rt the model's target orientation). */
static double band_g(const pom_dyn_model *m, const double *tgt, const double *Rt, int a,
                     const double *y) {
  const pom_dyn_maneuver *mv = &m->par.maneuver;
  if (a >= 0) {
    double q[POM_MECH_MAX_ACTUATORS];
    m->form->positions(m, y, q);
    return fabs(q[a] - tgt[a]) - mv->settle_band * fabs(tgt[a]);
  }
  double R[9], I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m->form->platform_rotation(m, y, R);
  double band = fmax(mv->pointing_band, mv->pointing_band_rel * rotation_angle(I, Rt));
  return rotation_angle(Rt, R) - band;
}

/* y + c v into out (n states). */
static void axpy(double *out, const double *y, double c, const double *v, int n) {
  for (int i = 0; i < n; ++i)
    out[i] = y[i] + c * v[i];
}

/* d g / d p_j at state y with sensitivity s: the central directional
 * difference between the perturbed models along (h, h s). */
static double band_dp(struct dyn_sens *w, const pom_dyn_model *m, int a, int j, const double *y,
                      const double *s) {
  const pom_dyn_sens_spec *sp = w->spec;
  const double h = sp->step[j];
  const int n = m->n_states;
  axpy(w->ybuf, y, h, s, n);
  double gp = band_g(sp->plus[j], sp->target_plus[j], w->Rt[0][j], a, w->ybuf);
  axpy(w->ybuf, y, -h, s, n);
  double gm = band_g(sp->minus[j], sp->target_minus[j], w->Rt[1][j], a, w->ybuf);
  return (gp - gm) / (2.0 * h);
}

/* dg/dt of a band function at state y of the nominal model, from the
 * state's own rates, not a difference along y' (docs/optimize.md 12.2, "The
 * crossing rate"): an actuator's g = |q_a - q_a*| - band has dg/dt =
 * sign(q_a - q_a*) q_dot_a with q_dot_a = J_a omega (the model's outputs);
 * the pointing angle theta = |rotvec(R*^T R)| has dtheta/dt = n . R^T omega
 * (n the rotation's unit axis, omega the platform's angular velocity in the
 * fixed frame, the exact path's state). A difference of g along y' over
 * 1e-8 of the horizon rounds at eps times the limb lengths (cm) the IK
 * forms q_a from, whatever q_a's own size: at a band of tens of nanometres,
 * where q_dot_a is small, that reached 1.6e-4 of the rate (case 68 of
 * 12.4). NaN where the model cannot be evaluated (the crossing is then
 * reported undefined). Leaves d->out and d->t at the crossing: the step's
 * pattern check reads the driver's own step-end values (d->u_raw_step). */
static double band_rate(const pom_dyn_model *m, pom_dyn_data *d, int a, const double *y) {
  if (a >= 0) {
    if (pom_dyn_eval(m, d, y, NULL)) return NAN;
    return (d->out.q[a] < d->target[a] ? -1.0 : 1.0) * d->out.q_dot[a];
  }
  int ori, n_ori, om;
  if (!pom_dyn_exact_layout(m, &ori, &n_ori, &om)) return NAN;
  double R[9], E[9], rv[3], wb[3];
  m->form->platform_rotation(m, y, R);
  pom_m3_tmul(E, d->R_target, R);
  pom_m3_rotvec(rv, E);
  const double th = pom_v3_norm(rv);
  if (!(th > 0.0)) return NAN;
  pom_m3_tapply(wb, R, y + om);
  return pom_v3_dot(rv, wb) / th;
}

/* d|i_a|/dp_j at the peak's time ts (inside the last step): the current's
 * central directional difference between the perturbed models along
 * (h, h s), signed as i_a (docs/optimize.md 12.2, the envelope theorem). */
static pom_status peak_dp(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err) {
  struct dyn_sens *w = d->sens;
  const pom_dyn_sens_spec *sp = w->spec;
  const double ts = d->peak.t;
  const int a = d->peak.coil;
  if (CVodeGetDky(d->cvode, ts, 0, d->ytmp) != CV_SUCCESS ||
      CVodeGetSensDky(d->cvode, ts, 0, w->ySt) != CV_SUCCESS)
    POM_FAIL(err, POM_ERR_SOLVER, "CVODES refused the peak current's time %.9g s", ts);
  const double *y = N_VGetArrayPointer(d->ytmp);
  d->t = ts;
  (void)pom_dyn_eval(m, d, y, NULL);
  const double sign = d->out.current[a] < 0.0 ? -1.0 : 1.0;
  for (int j = 0; j < w->n; ++j) {
    const double h = sp->step[j], *sj = N_VGetArrayPointer(w->ySt[j]);
    double i2[2];
    for (int side = 0; side < 2; ++side) {
      pom_dyn_data *dx = w->dx[side][j];
      axpy(w->ybuf, y, side ? -h : h, sj, m->n_states);
      dx->t = ts;
      int r = pom_dyn_eval(side ? sp->minus[j] : sp->plus[j], dx, w->ybuf, NULL);
      i2[side] = r ? NAN : dx->out.current[a];
    }
    w->dpeak[j] = sign * (i2[0] - i2[1]) / (2.0 * h);
  }
  return POM_OK;
}

/* ---- the sensitivity right-hand side ---------------------------------------- */
/* s_j' = J s_j + df/dp_j = (f_{p+h}(y + h s_j) - f_{p-h}(y - h s_j)) / (2 h)
 * (docs/optimize.md 12.1): one evaluation of each perturbed model. The
 * staggered corrector calls this again at the same (t, y) with a corrected
 * s_j; the right-hand side is affine in s_j there, so the later calls add
 * J (s_j - s_prev) as the plus model's difference along the correction,
 * (f_{p+h}(y + h s_j) - f_{p+h}(y + h s_prev)) / h: one evaluation
 * (docs/optimize.md 12.5 derives its error). ydot, CVODES' f(t, y), is not
 * read: the driver skips that evaluation (dyn_simulate.c, sens_lazy_f). */
static int sens_rhs(int Ns, sunrealtype t, N_Vector yv, N_Vector ydot, int iS, N_Vector ySv,
                    N_Vector ySdot, void *user_data, N_Vector tmp1, N_Vector tmp2) {
  (void)Ns;
  (void)ydot;
  pom_dyn_data *d = user_data;
  struct dyn_sens *w = d->sens;
  const pom_dyn_sens_spec *sp = w->spec;
  const int n = d->m->n_states;
  const double h = sp->step[iS];
  const double *y = N_VGetArrayPointer(yv), *s = N_VGetArrayPointer(ySv);
  double *yp = N_VGetArrayPointer(tmp1), *fm = N_VGetArrayPointer(tmp2);
  double *out = N_VGetArrayPointer(ySdot);
  pom_dyn_data *dp = w->dx[0][iS], *dm = w->dx[1][iS];
  double *ykey = w->ykey[iS], *fp_prev = w->fp_prev[iS], *fs_prev = w->fs_prev[iS];
  dp->t = dm->t = t;
  const int again =
      w->key_ok[iS] && w->key_t[iS] == t && memcmp(ykey, y, (size_t)n * sizeof *y) == 0;
  axpy(yp, y, h, s, n);
  int r = pom_dyn_eval(sp->plus[iS], dp, yp, out);
  ++w->rhs_evals;
  if (r) {
    w->key_ok[iS] = 0;
    return 1; /* recoverable: CVODES retries with a smaller step */
  }
  if (again) {
    /* fS(s) = fS(s_prev) + (f_{p+h}(y + h s) - f_{p+h}(y + h s_prev)) / h */
    const double c = 1.0 / h;
    for (int i = 0; i < n; ++i) {
      const double fp = out[i];
      out[i] = fs_prev[i] + (fp - fp_prev[i]) * c;
      fp_prev[i] = fp;
      fs_prev[i] = out[i];
    }
    return 0;
  }
  memcpy(fp_prev, out, (size_t)n * sizeof *out);
  axpy(yp, y, -h, s, n);
  r = pom_dyn_eval(sp->minus[iS], dm, yp, fm);
  ++w->rhs_evals;
  if (r) {
    w->key_ok[iS] = 0;
    return 1;
  }
  const double c = 1.0 / (2.0 * h);
  for (int i = 0; i < n; ++i)
    out[i] = (out[i] - fm[i]) * c;
  memcpy(fs_prev, out, (size_t)n * sizeof *out);
  memcpy(ykey, y, (size_t)n * sizeof *y);
  w->key_t[iS] = t;
  w->key_ok[iS] = 1;
  return 0;
}

/* ---- the saturation's linear band ------------------------------------------------ */
/* The raw voltage enters the linear band |u_raw| < limit in a time that
 * shrinks with the loop gain (2 limit / (K_S K_P |e_dot|) for the PID): a
 * step that jumps over it leaves the sensitivities without the band's
 * contribution, the jump of a discontinuous right-hand side in the limit
 * (docs/optimize.md). Roots of u_raw -+ limit, entering and leaving, restart
 * the integration there so that its first steps resolve the band and no
 * step straddles its corners. */
static int band_roots(sunrealtype t, N_Vector yv, sunrealtype *gout, void *user_data) {
  pom_dyn_data *d = user_data;
  const pom_dyn_model *m = d->m;
  const double lim = m->par.actuator.voltage_limit;
  struct dyn_sens *w = d->sens;
  const double *y = N_VGetArrayPointer(yv);
  d->t = t;
  int r = pom_dyn_eval(m, d, y, NULL);
  for (int a = 0; a < m->n_actuators; ++a) {
    double u = r ? 0.0 : d->out.u_raw[a];
    gout[2 * a] = u - lim;
    gout[2 * a + 1] = u + lim;
  }
  /* the key of d->out (pom_dyn_sens_ops.out_at); a plain re-run inside a
   * sensitivity run (dyn_simulate.c, stepinfo_rerun) keeps the roots with
   * d->sens NULL */
  if (w) {
    d->out_from_roots = 1;
    w->roots_t = t;
    memcpy(w->roots_y, y, (size_t)m->n_states * sizeof *y);
  }
  return 0;
}

static int pom_dyn_sens_out_at(const pom_dyn_model *m, const pom_dyn_data *d, double t,
                               const double *y) {
  const struct dyn_sens *w = d->sens;
  return d->out_from_roots && w->roots_t == t &&
         memcmp(w->roots_y, y, (size_t)m->n_states * sizeof *y) == 0;
}

/* The saturation pattern of a raw voltage u at limit lim, as the clamp has
 * it (at u = +-lim exactly: saturated, the same voltage either way). */
static int sat_mode_of(double u, double lim) {
  return u >= lim ? 1 : (u <= -lim ? -1 : 0);
}

/* Whether u agrees with the pattern mode within MODE_SLACK of the limit (at
 * a root the nominal stands on the corner itself, to the root finding's
 * tolerance, on either side). */
#define MODE_SLACK 1e-6
static int mode_agrees(int mode, double u, double lim) {
  const double slack = MODE_SLACK * lim;
  if (mode > 0) return u >= lim - slack;
  if (mode < 0) return u <= -lim + slack;
  return fabs(u) <= lim + slack;
}

/* The perturbed models' evaluations follow w->mode from now on. */
static void freeze_modes(struct dyn_sens *w, int na) {
  for (int side = 0; side < 2; ++side)
    for (int j = 0; j < w->n; ++j) {
      pom_dyn_data *dx = w->dx[side][j];
      dx->sat_frozen = 1;
      for (int a = 0; a < na; ++a)
        dx->sat_mode[a] = w->mode[a];
    }
}

/* CVODES restarted at t from the state and sensitivities there. */
static pom_status sens_reinit(const pom_dyn_model *m, pom_dyn_data *d, double t, pom_error *err) {
  struct dyn_sens *w = d->sens;
  double tret = t;
  long steps = 0;
  (void)CVodeGetNumSteps(d->cvode, &steps);
  w->steps_before += steps;
  int ism = w->spec->method == POM_DYN_SENS_SIMULTANEOUS ? CV_SIMULTANEOUS : CV_STAGGERED;
  if (CVodeGetSens(d->cvode, &tret, w->yS) != CV_SUCCESS ||
      CVodeReInit(d->cvode, t, d->y) != CV_SUCCESS ||
      CVodeSensReInit(d->cvode, ism, w->yS) != CV_SUCCESS ||
      CVodeSetStopTime(d->cvode, m->par.maneuver.horizon) != CV_SUCCESS)
    POM_FAIL(err, POM_ERR_SOLVER, "restarting the sensitivities at t = %.9g s: %s", t,
             d->cvode_msg);
  memset(w->key_ok, 0, sizeof w->key_ok); /* the corrector's cache: a new start */
  return POM_OK;
}

/* At a root of band_roots: the pattern of the actuators whose raw voltage
 * crossed a limit follows the crossing's direction (u_raw - limit rising:
 * +limit entered; falling: left; u_raw + limit rising: -limit left;
 * falling: entered), then the restart. */
static pom_status pom_dyn_sens_restart(const pom_dyn_model *m, pom_dyn_data *d, double t,
                                       pom_error *err) {
  struct dyn_sens *w = d->sens;
  const int na = m->n_actuators;
  if (CVodeGetRootInfo(d->cvode, w->root_info) != CV_SUCCESS)
    POM_FAIL(err, POM_ERR_SOLVER, "reading the roots at t = %.9g s: %s", t, d->cvode_msg);
  for (int a = 0; a < na; ++a) {
    if (w->root_info[2 * a]) w->mode[a] = w->root_info[2 * a] > 0 ? 1 : 0;
    if (w->root_info[2 * a + 1]) w->mode[a] = w->root_info[2 * a + 1] > 0 ? 0 : -1;
  }
  freeze_modes(w, na);
  ++w->restarts;
  return sens_reinit(m, d, t, err);
}

/* ---- hooks of the driver (dyn_simulate.c) ------------------------------------ */
static pom_status pom_dyn_sens_begin(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err) {
  struct dyn_sens *w = d->sens;
  const pom_dyn_sens_spec *sp = w->spec;
  for (int j = 0; j < w->n; ++j)
    N_VConst(0.0, w->yS[j]); /* the maneuver starts at rest at home whatever p is */
  for (int a = 0; a < m->n_actuators; ++a) {
    /* u_raw -+ limit through 0 either way: entering the band and leaving it
     * (docs/optimize.md 12.1: a step across the exit corner left 8e-5 on
     * the peak current's sensitivity, measured) */
    w->root_dir[2 * a] = 0;
    w->root_dir[2 * a + 1] = 0;
  }
  w->steps_before = 0;
  w->restarts = 0;
  memset(w->key_ok, 0, sizeof w->key_ok);
  int ism = sp->method == POM_DYN_SENS_SIMULTANEOUS ? CV_SIMULTANEOUS : CV_STAGGERED;
  if (CVodeSensInit1(d->cvode, w->n, ism, sens_rhs, w->yS) != CV_SUCCESS ||
      CVodeSetSensParams(d->cvode, NULL, w->pbar, NULL) != CV_SUCCESS ||
      CVodeSensSVtolerances(d->cvode, w->rtol_s, w->atolS) != CV_SUCCESS ||
      CVodeSetSensErrCon(d->cvode, sp->error_control ? SUNTRUE : SUNFALSE) != CV_SUCCESS ||
      CVodeRootInit(d->cvode, 2 * m->n_actuators, band_roots) != CV_SUCCESS ||
      CVodeSetRootDirection(d->cvode, w->root_dir) != CV_SUCCESS ||
      CVodeSetNoInactiveRootWarn(d->cvode) != CV_SUCCESS)
    POM_FAIL(err, POM_ERR_SOLVER, "configuring CVODES' sensitivities: %s", d->cvode_msg);
  for (int k = 0; k <= m->n_actuators; ++k) {
    w->have_cross[k] = w->cross_bad[k] = 0;
    w->n_after[k] = 0;
    w->later_max[k] = -INFINITY;
    w->run_max[k] = w->exc_max[k] = -INFINITY;
  }
  memset(w->dtrack, 0, sizeof w->dtrack);
  w->have_final = 0;
  /* the saturation pattern at rest at home, the nominal's clamp there */
  w->resyncs = 0;
  d->t = 0.0;
  (void)pom_dyn_eval(m, d, N_VGetArrayPointer(d->y), NULL);
  for (int a = 0; a < m->n_actuators; ++a)
    w->mode[a] = sat_mode_of(d->out.u_raw[a], m->par.actuator.voltage_limit);
  freeze_modes(w, m->n_actuators);
  return POM_OK;
}

/* Records the derivative of band k's crossing at t* (k = n_actuators: the
 * pointing band, model index a = -1); before: the largest band value at this
 * step's nodes before t* (-inf: none). */
static pom_status crossing(const pom_dyn_model *m, pom_dyn_data *d, int k, int a, double ts,
                           double before, pom_error *err) {
  struct dyn_sens *w = d->sens;
  if (CVodeGetDky(d->cvode, ts, 0, d->ytmp) != CV_SUCCESS ||
      CVodeGetSensDky(d->cvode, ts, 0, w->ySt) != CV_SUCCESS)
    POM_FAIL(err, POM_ERR_SOLVER, "CVODES refused the crossing time %.9g s", ts);
  const double *y = N_VGetArrayPointer(d->ytmp);
  d->t = ts;
  const double rate = band_rate(m, d, a, y);
  w->t_cross[k] = ts;
  w->rate[k] = rate;
  /* the excursion outside the band this crossing ends: its largest sampled
   * value (a re-entry: every crossing but the first follows an exit) */
  w->exc_max[k] = w->have_cross[k] ? fmax(w->run_max[k], before) : -INFINITY;
  w->run_max[k] = -INFINITY;
  w->have_cross[k] = 1;
  w->cross_bad[k] = 0;
  w->n_after[k] = 0;
  w->later_max[k] = -INFINITY;
  for (int j = 0; j < w->n; ++j) {
    double dg = band_dp(w, m, a, j, y, N_VGetArrayPointer(w->ySt[j]));
    w->dt[k][j] = -dg / rate;
    if (!isfinite(w->dt[k][j])) w->cross_bad[k] = 1;
  }
  return POM_OK;
}

/* A band value after the last crossing: a local maximum of g among three
 * consecutive values is a later excursion toward the band edge. */
static void after_crossing(struct dyn_sens *w, int k, double g) {
  if (!w->have_cross[k]) return;
  w->run_max[k] = fmax(w->run_max[k], g);
  if (w->n_after[k] >= 2 && w->g_prev[k][1] > w->g_prev[k][0] && w->g_prev[k][1] >= g)
    w->later_max[k] = fmax(w->later_max[k], w->g_prev[k][1]);
  w->g_prev[k][0] = w->g_prev[k][1];
  w->g_prev[k][1] = g;
  ++w->n_after[k];
}

static pom_status pom_dyn_sens_step(const pom_dyn_model *m, pom_dyn_data *d, double t0, double t,
                                    const double *t_settle_before, int point_before_valid,
                                    double point_before, pom_error *err) {
  struct dyn_sens *w = d->sens;
  const pom_dyn_sens_spec *sp = w->spec;
  const dyn_settle *s = &d->settle;
  const int na = m->n_actuators;
  /* crossings located in this step, with the band values at the step's
   * interior nodes before them (the record holds the positions) */
  const double *row = s->rec + (s->rec_n - 1) * DYN_REC_WIDTH;
  for (int a = 0; a < na; ++a) {
    const dyn_band *b = &s->act[a];
    if (!b->active || b->t_settle == t_settle_before[a]) continue;
    double before = -INFINITY;
    for (int i = 0; i < 2; ++i)
      if (t0 + gl_node[i] * (t - t0) < b->t_settle)
        before =
            fmax(before, fabs(row[DYN_REC_Q + i * POM_MECH_MAX_ACTUATORS + a] - b->ref) - b->band);
    POM_TRY(crossing(m, d, a, a, b->t_settle, before, err));
  }
  if (s->point.active && point_before_valid && s->point.t_settle != point_before) {
    /* the pointing angle is not recorded at the nodes: interpolated */
    double before = -INFINITY;
    for (int i = 0; i < 2; ++i) {
      const double ti = t0 + gl_node[i] * (t - t0);
      if (!(ti < s->point.t_settle)) continue;
      if (CVodeGetDky(d->cvode, ti, 0, d->ytmp) != CV_SUCCESS)
        POM_FAIL(err, POM_ERR_SOLVER, "CVODES refused t = %.9g s", ti);
      before = fmax(before, band_g(m, d->target, d->R_target, -1, N_VGetArrayPointer(d->ytmp)));
    }
    POM_TRY(crossing(m, d, na, -1, s->point.t_settle, before, err));
  }
  /* a new peak current located in this step (dyn_peak.c ran before) */
  if (d->peak.improved && sp->peak_current) POM_TRY(peak_dp(m, d, err));
  /* the band values after the crossings, at this step's end and interior
   * nodes (the record holds the positions; the pointing angle at the end) */
  for (int a = 0; a < na; ++a) {
    const dyn_band *b = &s->act[a];
    if (!b->active || !w->have_cross[a]) continue;
    for (int i = 0; i < 3; ++i) {
      double ti = i == 2 ? t : t0 + gl_node[i] * (t - t0);
      if (ti <= w->t_cross[a]) continue;
      double q = row[DYN_REC_Q + i * POM_MECH_MAX_ACTUATORS + a];
      after_crossing(w, a, fabs(q - b->ref) - b->band);
    }
  }
  if (s->point.active && w->have_cross[na] && t > w->t_cross[na])
    after_crossing(w, na, s->theta_end - s->point.band);
  /* the tracking integral's derivative at the interior nodes */
  if (s->track_ok && m->ctrl->reference_rotation) {
    const double h = t - t0;
    for (int i = 0; i < 2; ++i) {
      double tn = t0 + gl_node[i] * h;
      if (CVodeGetDky(d->cvode, tn, 0, d->ytmp) != CV_SUCCESS ||
          CVodeGetSensDky(d->cvode, tn, 0, w->ySt) != CV_SUCCESS)
        POM_FAIL(err, POM_ERR_SOLVER, "CVODES refused t = %.9g s", tn);
      const double *y = N_VGetArrayPointer(d->ytmp);
      for (int j = 0; j < w->n; ++j) {
        const double hj = sp->step[j], *sj = N_VGetArrayPointer(w->ySt[j]);
        double e2[2];
        for (int side = 0; side < 2; ++side) {
          const pom_dyn_model *mx = side ? sp->minus[j] : sp->plus[j];
          pom_dyn_data *dx = w->dx[side][j];
          const double *tg = side ? sp->target_minus[j] : sp->target_plus[j];
          double R[9], Rref[9];
          axpy(w->ybuf, y, side ? -hj : hj, sj, m->n_states);
          mx->form->platform_rotation(mx, w->ybuf, R);
          e2[side] = NAN;
          if (mx->ctrl->reference_rotation(&mx->par.controller, mx->ctrl_model, dx->ctrl_work, tn,
                                           tg, Rref)) {
            double e = rotation_angle(Rref, R);
            e2[side] = e * e;
          }
        }
        w->dtrack[j] += 0.5 * h * (e2[0] - e2[1]) / (2.0 * hj);
      }
    }
  }
  /* the pattern at the step's end against the nominal's clamp: a pair of
   * crossings inside one step is a sign change that the root finding does
   * not see; the perturbed models then follow the nominal again from here */
  d->t = t;
  const double lim = m->par.actuator.voltage_limit;
  int agree = 1;
  for (int a = 0; a < na; ++a) /* the driver's evaluation at (t, y_n) */
    if (!mode_agrees(w->mode[a], d->u_raw_step[a], lim)) {
      w->mode[a] = sat_mode_of(d->u_raw_step[a], lim);
      agree = 0;
    }
  if (!agree) {
    freeze_modes(w, na);
    ++w->resyncs;
    POM_TRY(sens_reinit(m, d, t, err));
  }
  return POM_OK;
}

static void pom_dyn_sens_end(const pom_dyn_model *m, pom_dyn_data *d) {
  struct dyn_sens *w = d->sens;
  const pom_dyn_sens_spec *sp = w->spec;
  double tret = 0.0;
  if (CVodeGetSens(d->cvode, &tret, w->yS) != CV_SUCCESS) return;
  const double *y = N_VGetArrayPointer(d->y);
  for (int j = 0; j < w->n; ++j) {
    const double *sj = N_VGetArrayPointer(w->yS[j]);
    for (int a = 0; a < m->n_actuators; ++a)
      w->ds_final[j][a] = sj[m->act[a].acc_state + DYN_ACC_SOURCE];
    w->dtheta_final[j] = NAN;
    if (d->have_target_rotation && w->have_Rt[0][j] && w->have_Rt[1][j]) {
      /* the angle between the platform and each perturbed model's own
       * target orientation, along (h, h s) */
      const double h = sp->step[j];
      double R[9];
      axpy(w->ybuf, y, h, sj, m->n_states);
      sp->plus[j]->form->platform_rotation(sp->plus[j], w->ybuf, R);
      double tp = rotation_angle(w->Rt[0][j], R);
      axpy(w->ybuf, y, -h, sj, m->n_states);
      sp->minus[j]->form->platform_rotation(sp->minus[j], w->ybuf, R);
      double tm = rotation_angle(w->Rt[1][j], R);
      w->dtheta_final[j] = (tp - tm) / (2.0 * h);
    }
  }
  w->have_final = 1;
}

static void pom_dyn_sens_off(pom_dyn_data *d) {
  (void)CVodeSensToggleOff(d->cvode);
}

const dyn_sens_ops pom_dyn_sens_ops = {
    .begin = pom_dyn_sens_begin,
    .step = pom_dyn_sens_step,
    .end = pom_dyn_sens_end,
    .restart = pom_dyn_sens_restart,
    .out_at = pom_dyn_sens_out_at,
    .off = pom_dyn_sens_off,
};

/* ---- the run ------------------------------------------------------------------ */
static void ws_free(struct dyn_sens *w) {
  if (!w) return;
  for (int side = 0; side < 2; ++side)
    for (int j = 0; j < POM_DYN_SENS_MAX; ++j)
      pom_dyn_data_destroy(w->dx[side][j]);
  if (w->yS) N_VDestroyVectorArray(w->yS, w->n);
  if (w->ySt) N_VDestroyVectorArray(w->ySt, w->n);
  if (w->atolS) N_VDestroyVectorArray(w->atolS, w->n);
  for (int j = 0; j < POM_DYN_SENS_MAX; ++j) {
    free(w->ykey[j]);
    free(w->fp_prev[j]);
    free(w->fs_prev[j]);
  }
  free(w->ybuf);
  free(w->ydot);
  free(w->roots_y);
  free(w);
}

static pom_status check_spec(const pom_dyn_model *m, const pom_dyn_sens_spec *sp, pom_error *err) {
  if (m->form != &pom_dyn_form_exact)
    POM_FAIL(err, POM_ERR_ARG,
             "design gradients need the exact formulation (joints.model = \"rigid\"); this model "
             "is %s",
             m->form->name);
  if (!(sp->n >= 1 && sp->n <= POM_DYN_SENS_MAX))
    POM_FAIL(err, POM_ERR_ARG, "design gradients: %d parameters (1 to %d)", sp->n,
             POM_DYN_SENS_MAX);
  if (!(sp->noise_margin >= POM_DYN_SENS_MARGIN_MIN && sp->noise_margin <= POM_DYN_SENS_MARGIN_MAX))
    POM_FAIL(err, POM_ERR_ARG, "design gradients: noise margin %g outside [%g, %g]",
             sp->noise_margin, POM_DYN_SENS_MARGIN_MIN, POM_DYN_SENS_MARGIN_MAX);
  for (int j = 0; j < sp->n; ++j) {
    if (!(sp->step[j] > 0.0 && isfinite(sp->step[j])))
      POM_FAIL(err, POM_ERR_ARG, "design gradients: parameter %d has step %g (must be > 0)", j + 1,
               sp->step[j]);
    for (int side = 0; side < 2; ++side) {
      const pom_dyn_model *x = side ? sp->minus[j] : sp->plus[j];
      if (!x || x->form != m->form || x->n_states != m->n_states ||
          x->n_actuators != m->n_actuators || x->ctrl != m->ctrl ||
          x->body_states != m->body_states)
        POM_FAIL(err, POM_ERR_ARG,
                 "design gradients: the %s model of parameter %d is missing or not of the "
                 "nominal model's formulation, state layout and controller type",
                 side ? "minus" : "plus", j + 1);
    }
  }
  return POM_OK;
}

static void undefined(pom_dyn_dmetric *g, int n, pom_dyn_grad_why why) {
  g->defined = 0;
  g->why = why;
  for (int j = 0; j < POM_DYN_SENS_MAX; ++j)
    g->d[j] = j < n ? NAN : 0.0;
}

static void defined(pom_dyn_dmetric *g, int n, const double *d) {
  g->defined = 1;
  g->why = POM_DYN_GRAD_OK;
  for (int j = 0; j < POM_DYN_SENS_MAX; ++j)
    g->d[j] = j < n ? d[j] : 0.0;
  for (int j = 0; j < n; ++j)
    if (!isfinite(d[j])) undefined(g, n, POM_DYN_GRAD_NONFINITE);
}

/* A settling time's derivative from band k (its band b, settled flag and
 * time ts as the metrics have them). */
static void settling_grad(pom_dyn_dmetric *g, const struct dyn_sens *w, int k, int active,
                          int settled, double ts, double band, double horizon) {
  const int n = w->n;
  if (!settled || isnan(ts)) {
    undefined(g, n, POM_DYN_GRAD_NEVER_SETTLED);
  } else if (!active || ts == 0.0 || !w->have_cross[k]) {
    undefined(g, n, POM_DYN_GRAD_SETTLED_AT_START);
  } else if (w->cross_bad[k]) {
    undefined(g, n, POM_DYN_GRAD_NONFINITE);
  } else if (!(fabs(w->rate[k]) >= POM_DYN_GRAD_GRAZE * band / horizon) ||
             w->later_max[k] > -POM_DYN_GRAD_GRAZE_MARGIN * band ||
             (w->exc_max[k] > -INFINITY && w->exc_max[k] <= POM_DYN_GRAD_GRAZE_MARGIN * band)) {
    undefined(g, n, POM_DYN_GRAD_GRAZING);
  } else {
    defined(g, n, w->dt[k]);
  }
}

pom_status pom_dyn_simulate_sens(const pom_dyn_model *m, pom_dyn_data *d, const double target[3],
                                 const pom_dyn_sens_spec *sp, pom_dyn_metrics *mt, pom_dyn_grad *gr,
                                 pom_error *err) {
  if (!m || !d || !target || !sp || !mt || !gr || d->m != m)
    POM_FAIL(err, POM_ERR_ARG, "pom_dyn_simulate_sens: NULL argument or data of another model");
  POM_TRY(check_spec(m, sp, err));
  pom_status st = POM_OK;
  const int n = sp->n;
  memset(gr, 0, sizeof *gr);
  gr->n_params = n;
  struct dyn_sens *w = calloc(1, sizeof *w);
  if (!w) POM_FAIL(err, POM_ERR_NOMEM, "allocating the sensitivity workspace");
  w->spec = sp;
  w->n = n;
  /* the sensitivities' relative tolerance: the state's, but not below what
   * the differencing resolves: rounding leaves eps / (h_j / pbar_j) of
   * each right-hand side in s_j', and the error test must stay the noise
   * margin above it or it chases the noise (docs/optimize.md 12.1, 12.4) */
  w->rtol_s = m->par.solver.rtol;
  for (int j = 0; j < n; ++j) {
    double pb = sp->scale[j] > 0.0 ? sp->scale[j] : 1e4 * sp->step[j];
    w->rtol_s = fmax(w->rtol_s, sp->noise_margin * DBL_EPSILON * pb / sp->step[j]);
  }
  w->yS = N_VCloneVectorArray(n, d->y);
  w->ySt = N_VCloneVectorArray(n, d->y);
  w->atolS = N_VCloneVectorArray(n, d->y);
  w->ybuf = calloc((size_t)m->n_states, sizeof *w->ybuf);
  w->ydot = calloc((size_t)m->n_states, sizeof *w->ydot);
  w->roots_y = calloc((size_t)m->n_states, sizeof *w->roots_y);
  if (!w->yS || !w->ySt || !w->atolS || !w->ybuf || !w->ydot || !w->roots_y)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "allocating the sensitivity workspace");
  for (int j = 0; j < n; ++j) {
    w->ykey[j] = malloc((size_t)m->n_states * sizeof(double));
    w->fp_prev[j] = malloc((size_t)m->n_states * sizeof(double));
    w->fs_prev[j] = malloc((size_t)m->n_states * sizeof(double));
    if (!w->ykey[j] || !w->fp_prev[j] || !w->fs_prev[j])
      POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "allocating the sensitivity workspace");
  }
  for (int j = 0; j < n; ++j) {
    /* the error test scales s_j by a parameter magnitude (CVODES' pbar): the
     * caller's step over the relative step a design layer would take */
    w->pbar[j] = sp->scale[j] > 0.0 ? sp->scale[j] : 1e4 * sp->step[j];
    double *at = N_VGetArrayPointer(w->atolS[j]);
    for (int i = 0; i < m->n_states; ++i)
      at[i] = m->atol[i] * (w->rtol_s / m->par.solver.rtol) / w->pbar[j];
    /* only what a gradient reads or what feeds back enters the error test:
     * the accumulators of positive energy, coil and bearing losses and
     * saturated time feed nothing back (zero columns of J) and no gradient
     * is taken of them (docs/optimize.md 12.5) */
    for (int a = 0; a < m->n_actuators; ++a) {
      at[m->act[a].acc_state + DYN_ACC_SOURCE_POS] = 1e30;
      at[m->act[a].acc_state + DYN_ACC_COIL] = 1e30;
      at[m->act[a].acc_state + DYN_ACC_BEARING] = 1e30;
      at[m->act[a].acc_state + DYN_ACC_SATURATED] = 1e30;
    }
    for (int side = 0; side < 2; ++side) {
      const pom_dyn_model *x = side ? sp->minus[j] : sp->plus[j];
      const double *tg = side ? sp->target_minus[j] : sp->target_plus[j];
      POM_TRY_GOTO(pom_dyn_data_create(&w->dx[side][j], x, err), done);
      for (int a = 0; a < 3; ++a)
        w->dx[side][j]->target[a] = tg[a];
      w->have_Rt[side][j] = x->has_arch && pom_kin_forward(&x->arch, tg, NULL, NULL, w->Rt[side][j],
                                                           NULL, NULL) == POM_OK;
    }
  }
  d->sens = w;
  const int peak_on = d->peak.on;
  if (sp->peak_current) d->peak.on = 1; /* the peak current's derivative needs its argmax */
  /* the staggered corrector's f at the converged y feeds only sens_rhs's
   * ydot, which is not read: skipped (dyn_simulate.c, docs/optimize.md 12.5) */
  d->sens_lazy_f = sp->method == POM_DYN_SENS_STAGGERED;
  st = pom_dyn_simulate_ex(m, d, target, NULL, mt, NULL, err);
  d->sens_lazy_f = 0;
  d->peak.on = peak_on;
  d->sens = NULL;
  (void)CVodeRootInit(d->cvode, 0, NULL);
  mt->steps += w->steps_before;
  gr->restarts = w->restarts;
  gr->resyncs = w->resyncs;
  CVodeSensFree(d->cvode);
  gr->sens_rhs_evals = w->rhs_evals;

  /* the gradients */
  const double horizon = m->par.maneuver.horizon;
  const int na = m->n_actuators;
  pom_dyn_dmetric *all[] = {&gr->energy_total,
                            &gr->energy[0],
                            &gr->energy[1],
                            &gr->energy[2],
                            &gr->tracking_rms_error,
                            &gr->final_pointing_error,
                            &gr->settling_time[0],
                            &gr->settling_time[1],
                            &gr->settling_time[2],
                            &gr->execution_time,
                            &gr->pointing_settling_time,
                            &gr->peak_current};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k)
    undefined(all[k], n, POM_DYN_GRAD_UNKNOWN);
  if (st != POM_OK || mt->status != POM_OK || !w->have_final) goto done;
  double v[POM_DYN_SENS_MAX];
  for (int j = 0; j < n; ++j) {
    v[j] = 0.0;
    for (int a = 0; a < na; ++a)
      v[j] += w->ds_final[j][a];
  }
  defined(&gr->energy_total, n, v);
  for (int a = 0; a < na; ++a) {
    for (int j = 0; j < n; ++j)
      v[j] = w->ds_final[j][a];
    defined(&gr->energy[a], n, v);
  }
  if (isfinite(mt->final_pointing_error)) defined(&gr->final_pointing_error, n, w->dtheta_final);
  if (isfinite(mt->tracking_rms_error) && mt->tracking_rms_error > 0.0) {
    /* rms = sqrt(I / T): d rms = dI / (2 T rms), T the horizon reached */
    const double T = d->settle.t_prev;
    for (int j = 0; j < n; ++j)
      v[j] = w->dtrack[j] / (2.0 * T * mt->tracking_rms_error);
    defined(&gr->tracking_rms_error, n, v);
  }
  const dyn_settle *s = &d->settle;
  for (int a = 0; a < na; ++a) {
    settling_grad(&gr->settling_time[a], w, a, s->act[a].active, mt->settled[a],
                  mt->settling_time[a], s->act[a].band, horizon);
    gr->crossing_rate[a] = w->have_cross[a] ? w->rate[a] : 0.0;
  }
  if (s->point.active) {
    settling_grad(&gr->pointing_settling_time, w, na, 1, mt->pointing_settled,
                  mt->pointing_settling_time, s->point.band, horizon);
    gr->pointing_crossing_rate = w->have_cross[na] ? w->rate[na] : 0.0;
  }
  /* execution time: the derivative of the actuator whose time is the max */
  {
    int arg = -1, any_unsettled = 0;
    for (int a = 0; a < na; ++a) {
      if (!mt->settled[a]) any_unsettled = 1;
      if (mt->settling_time[a] >= 0.0 && (arg < 0 || mt->settling_time[a] > mt->settling_time[arg]))
        arg = a;
    }
    int tie = 0;
    for (int a = 0; a < na && arg >= 0; ++a)
      if (a != arg && fabs(mt->settling_time[a] - mt->settling_time[arg]) <= 1e-12 * horizon)
        tie = 1;
    if (any_unsettled || arg < 0)
      undefined(&gr->execution_time, n, POM_DYN_GRAD_NEVER_SETTLED);
    else if (mt->settling_time[arg] == 0.0)
      undefined(&gr->execution_time, n, POM_DYN_GRAD_SETTLED_AT_START);
    else if (tie)
      undefined(&gr->execution_time, n, POM_DYN_GRAD_TIE);
    else
      gr->execution_time = gr->settling_time[arg];
  }
  /* the peak current: s_i at an interior argmax (docs/optimize.md 12.2) */
  if (sp->peak_current) {
    const dyn_peak *pk = &d->peak;
    gr->peak_time = pk->t;
    gr->peak_coil = pk->coil;
    if (!(pk->value > 0.0) || pk->where == DYN_PEAK_START || pk->where == DYN_PEAK_END)
      undefined(&gr->peak_current, n, POM_DYN_GRAD_PEAK_EDGE);
    else if (pk->where == DYN_PEAK_KINK)
      undefined(&gr->peak_current, n, POM_DYN_GRAD_PEAK_KINK);
    else if (pk->value - pk->second <= POM_DYN_PEAK_TIE * pk->value)
      undefined(&gr->peak_current, n, POM_DYN_GRAD_TIE);
    else
      defined(&gr->peak_current, n, w->dpeak);
  }
done:
  d->sens = NULL;
  ws_free(w);
  return st;
}
