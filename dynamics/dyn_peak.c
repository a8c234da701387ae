/* dyn_peak.c - the peak coil current of a maneuver, max over the coils and
 * the horizon of |i(t)|, located on CVODE's interpolant so that its value is
 * a smooth function of the design where the maximum is interior and its
 * design derivative is the current's sensitivity at the argmax (the
 * envelope theorem, docs/optimize.md 12.2). Watched only when asked: the
 * rate of every coil's current is the flux state's rate over L (inductive
 * coils), or a directional difference along the state's rate, three
 * evaluations per accepted step (quasi-static coils). */
#include "dyn_internal.h"

#include <math.h>
#include <string.h>

/* Time step of the rate by central differences along (1, y') (a fraction of
 * the horizon), as the settling crossing's rate (dyn_sens.c): truncation
 * ~ i''' eps^2, rounding ~ 1e-16 |i| / eps. */
#define PEAK_RATE_EPS 1e-8

/* A located maximum is a kink of i(t) when, a millionth of the step away on
 * either side, the rate is still above this share of the bracket's rates
 * (smooth: about 1e-6 of them; a jump of di/dt: of their order). */
#define PEAK_KINK_SHARE 1e-3

/* A maximum this share of the horizon or closer to a corner of a saturated
 * voltage is a kink of max |i| in the design (docs/optimize.md 12.2): the
 * current's rate jumps at the corner (a quasi-static coil's i = (u - K_m
 * q')/R_c, u's corner in i, every coil's q'' through the coupling), and a
 * smooth maximum nanoseconds after it is the maximum only while the corner
 * moves by less than that distance; the corner moves ~1.4e-3 s per unit
 * relative change of a design value (3S-P-S/S case 39 of test_grad_random),
 * 1.4e-5 T at a change of 1e-3. */
#define PEAK_CORNER_GAP 1e-4

/* The currents at (t, y) into i[]: 0, or 1 when the evaluation failed. */
static int currents(const pom_dyn_model *m, pom_dyn_data *d, double t, const double *y, double *i) {
  d->t = t;
  int r = pom_dyn_eval(m, d, y, NULL);
  for (int a = 0; a < m->n_actuators; ++a)
    i[a] = d->out.current[a];
  return r || d->out.nonfinite;
}

/* 1 when every coil's current is its flux state over L (an inductive coil,
 * dyn_actuator.c): then i and di/dt come from the state and its rate. */
static int inductive(const pom_dyn_model *m) {
  for (int a = 0; a < m->n_actuators; ++a)
    if (m->act[a].flux_state < 0) return 0;
  return 1;
}

/* |i| and r = sign(i) di/dt of every coil at (t, y) with rate yd. An
 * inductive coil: i = lambda / L as the law computes it, di/dt = lambda' / L
 * exactly, no evaluation; a quasi-static one, i = (u - K_m q') / R_c: the
 * central difference along (1, yd), three evaluations. 0, or 1 when an
 * evaluation failed or a value is not finite. */
static int rates(const pom_dyn_model *m, pom_dyn_data *d, double t, const double *y,
                 const double *yd, double *absi, double *r) {
  if (inductive(m)) {
    const double L = m->par.actuator.inductance;
    int bad = 0;
    for (int a = 0; a < m->n_actuators; ++a) {
      const int k = m->act[a].flux_state;
      const double i = y[k] / L;
      absi[a] = fabs(i);
      r[a] = (i < 0.0 ? -1.0 : 1.0) * (yd[k] / L);
      bad |= !isfinite(i) || !isfinite(r[a]);
    }
    return bad;
  }
  const int n = m->n_states;
  const double eps = PEAK_RATE_EPS * m->par.maneuver.horizon;
  double *buf = d->peak.buf;
  double i0[POM_MECH_MAX_ACTUATORS], ip[POM_MECH_MAX_ACTUATORS], im[POM_MECH_MAX_ACTUATORS];
  int bad = currents(m, d, t, y, i0);
  for (int k = 0; k < n; ++k)
    buf[k] = y[k] + eps * yd[k];
  bad |= currents(m, d, t + eps, buf, ip);
  for (int k = 0; k < n; ++k)
    buf[k] = y[k] - eps * yd[k];
  bad |= currents(m, d, t - eps, buf, im);
  for (int a = 0; a < m->n_actuators; ++a) {
    absi[a] = fabs(i0[a]);
    r[a] = (i0[a] < 0.0 ? -1.0 : 1.0) * (ip[a] - im[a]) / (2.0 * eps);
  }
  return bad;
}

/* The same at time t inside the last step, from the interpolant. */
static int rates_at(const pom_dyn_model *m, pom_dyn_data *d, double t, double *absi, double *r) {
  if (CVodeGetDky(d->cvode, t, 0, d->ytmp) != CV_SUCCESS ||
      CVodeGetDky(d->cvode, t, 1, d->ftmp) != CV_SUCCESS)
    return 1;
  return rates(m, d, t, N_VGetArrayPointer(d->ytmp), N_VGetArrayPointer(d->ftmp), absi, r);
}

/* A candidate for the maximum. */
static void offer(dyn_peak *pk, double v, double t, int coil, dyn_peak_where where) {
  if (v > pk->value) {
    pk->second = pk->value;
    pk->value = v;
    pk->t = t;
    pk->coil = coil;
    pk->where = where;
    pk->improved = 1;
  } else {
    pk->second = fmax(pk->second, v);
  }
}

static pom_status peak_begin(const pom_dyn_model *m, pom_dyn_data *d, const double *y0,
                             pom_error *err) {
  dyn_peak *pk = &d->peak;
  pk->value = pk->second = -1.0;
  pk->t_corner = -INFINITY;
  pk->t = 0.0;
  pk->coil = 0;
  pk->where = DYN_PEAK_START;
  /* the rate at t = 0 from the right-hand side */
  double *yd = N_VGetArrayPointer(d->ftmp);
  d->t = 0.0;
  double absi[POM_MECH_MAX_ACTUATORS];
  if (pom_dyn_eval(m, d, y0, yd) || rates(m, d, 0.0, y0, yd, absi, pk->r_prev))
    POM_FAIL(err, POM_ERR_SOLVER, "peak current: the evaluation at t = 0 failed");
  for (int a = 0; a < m->n_actuators; ++a)
    offer(pk, absi[a], 0.0, a, DYN_PEAK_START);
  pk->improved = 0;
  return POM_OK;
}

typedef struct {
  const pom_dyn_model *m;
  pom_dyn_data *d;
  int coil;
} rate_ctx;

static double rate_of_coil(double t, void *ctx) {
  rate_ctx *c = ctx;
  double absi[POM_MECH_MAX_ACTUATORS], r[POM_MECH_MAX_ACTUATORS];
  return rates_at(c->m, c->d, t, absi, r) ? NAN : r[c->coil];
}

static pom_status peak_step(const pom_dyn_model *m, pom_dyn_data *d, double t0, double t,
                            pom_error *err) {
  dyn_peak *pk = &d->peak;
  pk->improved = 0;
  double absi[POM_MECH_MAX_ACTUATORS], r[POM_MECH_MAX_ACTUATORS];
  /* at the step's end the state is CVODES' y_n itself (the interpolant
   * there, bit for bit); only its rate is interpolated */
  if (CVodeGetDky(d->cvode, t, 1, d->ftmp) != CV_SUCCESS ||
      rates(m, d, t, N_VGetArrayPointer(d->y), N_VGetArrayPointer(d->ftmp), absi, r))
    POM_FAIL(err, POM_ERR_SOLVER, "peak current: the evaluation at t = %.9g s failed", t);
  for (int a = 0; a < m->n_actuators; ++a) {
    /* |i| rising at the step's start, not at its end: a maximum inside */
    if (!(pk->r_prev[a] > 0.0 && r[a] <= 0.0)) continue;
    rate_ctx c = {m, d, a};
    double ts = pom_dyn_illinois(rate_of_coil, &c, t0, pk->r_prev[a], t, r[a], POM_DYN_SETTLE_XTOL);
    double ai[POM_MECH_MAX_ACTUATORS], ri[POM_MECH_MAX_ACTUATORS];
    double rl[POM_MECH_MAX_ACTUATORS], rr[POM_MECH_MAX_ACTUATORS];
    const double delta = 1e-6 * (t - t0);
    if (!isfinite(ts) || rates_at(m, d, fmax(ts - delta, t0), ai, rl) ||
        rates_at(m, d, fmin(ts + delta, t), ai, rr) || rates_at(m, d, ts, ai, ri))
      POM_FAIL(err, POM_ERR_SOLVER, "peak current: the evaluation near t = %.9g s failed", ts);
    const double scale = PEAK_KINK_SHARE * fmax(fabs(pk->r_prev[a]), fabs(r[a]));
    const int kink = (fabs(rl[a]) > scale && fabs(rr[a]) > scale) ||
                     ts - pk->t_corner <= PEAK_CORNER_GAP * m->par.maneuver.horizon;
    offer(pk, ai[a], ts, a, kink ? DYN_PEAK_KINK : DYN_PEAK_INTERIOR);
  }
  memcpy(pk->r_prev, r, sizeof r);
  d->t = t;
  return POM_OK;
}

static pom_status peak_end(const pom_dyn_model *m, pom_dyn_data *d, double t, const double *y,
                           pom_error *err) {
  dyn_peak *pk = &d->peak;
  double absi[POM_MECH_MAX_ACTUATORS];
  if (currents(m, d, t, y, absi))
    POM_FAIL(err, POM_ERR_SOLVER, "peak current: the evaluation at the horizon failed");
  const int improved = pk->improved;
  for (int a = 0; a < m->n_actuators; ++a)
    offer(pk, fabs(absi[a]), t, a, DYN_PEAK_END);
  pk->improved = improved;
  return POM_OK;
}

static void peak_corner(const pom_dyn_model *m, pom_dyn_data *d, double t) {
  dyn_peak *pk = &d->peak;
  pk->t_corner = t;
  /* a maximum found before the corner, within the gap */
  if (pk->where == DYN_PEAK_INTERIOR && t - pk->t <= PEAK_CORNER_GAP * m->par.maneuver.horizon)
    pk->where = DYN_PEAK_KINK;
}

const dyn_peak_ops pom_dyn_peak_ops = {
    .begin = peak_begin,
    .step = peak_step,
    .end = peak_end,
    .corner = peak_corner,
};
