/* dyn_settle.c - settling times located on the integrator's dense output
 * (docs/dynamics.md section 8, docs/results.md sections 1 and 1b): the band
 * functions of every actuator and of the platform's pointing angle watched
 * on CVODE's interpolant over each accepted step, the last return inside a
 * band found by the Illinois method, the stepinfo variant from a per-step
 * record after the run, and the tracking error as a time average by
 * Gauss-Legendre quadrature. Independent of maneuver.output_dt. */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Two-point Gauss-Legendre nodes on [0, 1] (weights 1/2 each): the
 * interior points where every step is looked at (section 8). */
static const double gl_node[2] = {0.21132486540518711775, 0.78867513459481288225};

/* Rows the per-step record starts with (grown geometrically when a
 * maneuver takes more steps; the shipped configs take 140-2500). */
#define DYN_REC_INITIAL 1024

/* ---- root finding -------------------------------------------------------- */
double pom_dyn_illinois(double (*g)(double t, void *ctx), void *ctx, double a, double ga, double b,
                        double gb, double xtol) {
  if (ga == 0.0) return a;
  if (gb == 0.0) return b;
  int side = 0;
  for (int it = 0; it < 200 && fabs(b - a) > xtol; ++it) {
    double c = (a * gb - b * ga) / (gb - ga);
    /* the secant point of a bracket stays inside it but for rounding */
    if (!(c > fmin(a, b) && c < fmax(a, b))) c = 0.5 * (a + b);
    double gc = g(c, ctx);
    if (isnan(gc) || gc == 0.0) return c;
    if ((gc > 0.0) == (gb > 0.0)) {
      b = c, gb = gc;
      if (side == -1) ga *= 0.5; /* a stuck twice: halve its value (Illinois) */
      side = -1;
    } else {
      a = c, ga = gc;
      if (side == +1) gb *= 0.5;
      side = +1;
    }
  }
  double c = (a * gb - b * ga) / (gb - ga);
  return (c >= fmin(a, b) && c <= fmax(a, b)) ? c : 0.5 * (a + b);
}

/* ---- the platform's angles ----------------------------------------------- */
/* Angle (rad) of the rotation between A and B: |rotvec(A^T B)|. */
static double rotation_angle(const double A[9], const double B[9]) {
  double At[9], E[9], rv[3];
  pom_m3_transpose(At, A);
  pom_m3_mul(E, At, B);
  pom_m3_rotvec(rv, E);
  return pom_v3_norm(rv);
}

/* Pointing angle of state y (R receives its platform rotation). */
static double pointing_angle(const pom_dyn_model *m, const pom_dyn_data *d, const double *y,
                             double R[9]) {
  m->form->platform_rotation(m, y, R);
  return d->have_target_rotation ? rotation_angle(d->R_target, R) : NAN;
}

/* ---- band functions on the interpolant ----------------------------------- */
typedef struct {
  const pom_dyn_model *m;
  pom_dyn_data *d;
  int actuator; /* 0..n-1, or -1 for the pointing angle */
  double ref, band;
} band_ctx;

/* g(t) = |e(t)| - band on CVODE's interpolant of the last step. */
static double band_on_interpolant(double t, void *vctx) {
  band_ctx *c = vctx;
  pom_dyn_data *d = c->d;
  if (CVodeGetDky(d->cvode, t, 0, d->ytmp) != CV_SUCCESS) return NAN;
  ++d->settle.evals;
  const double *ys = N_VGetArrayPointer(d->ytmp);
  if (c->actuator >= 0) {
    double q[POM_MECH_MAX_ACTUATORS];
    c->m->form->positions(c->m, ys, q);
    return fabs(q[c->actuator] - c->ref) - c->band;
  }
  double R[9];
  return pointing_angle(c->m, d, ys, R) - c->band;
}

/* One step of one band: g at the step start, the two nodes and the step end
 * (times tn). Outside at the end: the band is left open; outside somewhere
 * before: the last return inside is located on the interpolant between the
 * last node outside and the next one. */
static void band_step(dyn_band *b, const double tn[4], const double g[4], band_ctx *c) {
  int j = -1;
  for (int i = 0; i < 4; ++i)
    if (g[i] > 0.0) j = i;
  if (j < 0) {
    b->outside = 0;
    return;
  }
  if (j == 3) {
    b->outside = 1;
    return;
  }
  double ga = g[j];
  if (j == 0) {
    /* the start value came from the previous step's interpolant: take this
     * step's own (they differ by the local error) */
    ga = band_on_interpolant(tn[0], c);
    if (!(ga > 0.0)) {
      b->t_settle = tn[0];
      b->outside = 0;
      return;
    }
  }
  b->t_settle =
      pom_dyn_illinois(band_on_interpolant, c, tn[j], ga, tn[j + 1], g[j + 1], POM_DYN_SETTLE_XTOL);
  b->outside = 0;
}

/* ---- the watch ----------------------------------------------------------- */
pom_status pom_dyn_settle_data(pom_dyn_data *d, pom_error *err) {
  pom_status st = POM_OK;
  d->settle.rec = calloc((size_t)DYN_REC_INITIAL * DYN_REC_WIDTH, sizeof(double));
  if (!d->settle.rec) POM_FAIL(err, POM_ERR_NOMEM, "allocating the settling record");
  d->settle.rec_cap = DYN_REC_INITIAL;
  return st;
}

void pom_dyn_settle_begin(const pom_dyn_model *m, pom_dyn_data *d, const double *y0) {
  const pom_dyn_params *p = &m->par;
  dyn_settle *s = &d->settle;
  s->t_prev = 0.0;
  s->track_int = 0.0;
  s->track_ok = m->ctrl->reference_rotation != NULL;
  s->evals = 0;
  s->interior_steps = 0;
  double *row = s->rec;
  row[DYN_REC_T] = row[DYN_REC_H] = 0.0;
  for (int a = 0; a < m->n_actuators; ++a) {
    dyn_band *b = &s->act[a];
    double q0 = d->out.q[a];
    b->ref = d->target[a];
    b->band = p->maneuver.settle_band * fabs(b->ref);
    /* a zero step has no band: settled from the start; a setpoint within
     * DYN_ZERO_STEP of the stroke is one (an orientation about a limb's axis
     * turns into a setpoint of rounding size through a generic IK) */
    b->active = fabs(b->ref) > DYN_ZERO_STEP * m->act[a].stroke && b->ref != 0.0;
    b->t_settle = 0.0;
    b->outside = b->active && fabs(q0 - b->ref) > b->band;
    s->q_prev[a] = q0;
    s->qd_prev[a] = d->out.q_dot[a];
    for (int i = 0; i < 3; ++i)
      row[DYN_REC_Q + i * POM_MECH_MAX_ACTUATORS + a] = q0;
  }
  s->rec_n = 1;
  double R[9], I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  s->theta_prev = s->theta_end = pointing_angle(m, d, y0, R);
  dyn_band *b = &s->point;
  b->ref = 0.0;
  b->active = d->have_target_rotation;
  b->band = b->active ? fmax(p->maneuver.pointing_band,
                             p->maneuver.pointing_band_rel * rotation_angle(I, d->R_target))
                      : 0.0;
  b->t_settle = 0.0;
  b->outside = b->active && s->theta_prev > b->band;
}

pom_status pom_dyn_settle_step(const pom_dyn_model *m, pom_dyn_data *d, double t, const double *y,
                               pom_error *err) {
  pom_status st = POM_OK;
  dyn_settle *s = &d->settle;
  const int na = m->n_actuators;
  const int need_rotation = s->point.active || s->track_ok;
  const double t0 = s->t_prev, h = t - t0;
  double tn[4] = {t0, t0 + gl_node[0] * h, t0 + gl_node[1] * h, t};
  double qn[4][POM_MECH_MAX_ACTUATORS], theta[4] = {s->theta_prev, NAN, NAN, NAN};
  double R[9], Rref[9];
  for (int a = 0; a < na; ++a) {
    qn[0][a] = s->q_prev[a];
    qn[3][a] = d->out.q[a];
  }
  if (s->point.active) theta[3] = pointing_angle(m, d, y, R);
  /* The interior nodes matter only when some band is inside at the step's
   * end (a return inside to locate, or an excursion between two inside
   * ends) or when the tracking integral runs. While every band is outside
   * at the end, the settling times are at least t whatever the interior
   * does; the record then takes the cubic Hermite of the step's end values
   * and rates, O(h^4) like the cubic through four interpolant values
   * (docs/dynamics.md section 8). On the parasitic path this skips the
   * saturated sweeps and the ringing before settling, most of the steps. */
  int interior = s->track_ok;
  for (int a = 0; a < na && !interior; ++a)
    interior = s->act[a].active && fabs(qn[3][a] - s->act[a].ref) <= s->act[a].band;
  if (!interior && s->point.active) interior = theta[3] <= s->point.band;
  if (interior) {
    ++s->interior_steps;
    /* the two interior nodes on the interpolant: positions, pointing angle
     * and the tracking integrand (Gauss-Legendre, weight h/2 each) */
    for (int j = 1; j <= 2; ++j) {
      if (CVodeGetDky(d->cvode, tn[j], 0, d->ytmp) != CV_SUCCESS)
        POM_FAIL(err, POM_ERR_SOLVER, "CVodeGetDky refused t = %.9g s in the step [%.9g, %.9g] s",
                 tn[j], t0, t);
      ++s->evals;
      const double *ys = N_VGetArrayPointer(d->ytmp);
      m->form->positions(m, ys, qn[j]);
      if (!need_rotation) continue;
      theta[j] = pointing_angle(m, d, ys, R);
      if (s->track_ok) {
        if (m->ctrl->reference_rotation(&m->par.controller, m->ctrl_model, d->ctrl_work, tn[j],
                                        d->target, Rref)) {
          double e = rotation_angle(Rref, R);
          s->track_int += 0.5 * h * e * e;
        } else {
          s->track_ok = 0;
        }
      }
    }
  } else {
    /* cubic Hermite of the ends: every band is outside at t, so these values
     * serve only the record */
    for (int j = 1; j <= 2; ++j) {
      double x = gl_node[j - 1], x2 = x * x, x3 = x2 * x;
      double h00 = 2 * x3 - 3 * x2 + 1, h10 = x3 - 2 * x2 + x, h01 = -2 * x3 + 3 * x2,
             h11 = x3 - x2;
      for (int a = 0; a < na; ++a)
        qn[j][a] =
            h00 * qn[0][a] + h10 * h * s->qd_prev[a] + h01 * qn[3][a] + h11 * h * d->out.q_dot[a];
      theta[j] = theta[3]; /* not read: the pointing band is outside at both ends or inactive */
    }
  }

  for (int a = 0; a < na; ++a) {
    dyn_band *b = &s->act[a];
    if (!b->active) continue;
    double g[4];
    for (int i = 0; i < 4; ++i)
      g[i] = fabs(qn[i][a] - b->ref) - b->band;
    band_ctx c = {m, d, a, b->ref, b->band};
    band_step(b, tn, g, &c);
  }
  if (s->point.active) {
    double g[4];
    for (int i = 0; i < 4; ++i)
      g[i] = theta[i] - s->point.band;
    band_ctx c = {m, d, -1, 0.0, s->point.band};
    band_step(&s->point, tn, g, &c);
  }

  /* the record row of this step (the final-value variant, max |q|) */
  if (s->rec_n >= s->rec_cap) {
    long cap = 2 * s->rec_cap;
    double *r = realloc(s->rec, (size_t)cap * DYN_REC_WIDTH * sizeof(double));
    if (!r) POM_FAIL(err, POM_ERR_NOMEM, "growing the settling record to %ld steps", cap);
    s->rec = r;
    s->rec_cap = cap;
  }
  double *row = s->rec + s->rec_n * DYN_REC_WIDTH;
  row[DYN_REC_T] = t;
  row[DYN_REC_H] = h;
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < na; ++a)
      row[DYN_REC_Q + i * POM_MECH_MAX_ACTUATORS + a] = qn[i + 1][a];
  ++s->rec_n;
  s->t_prev = t;
  for (int a = 0; a < na; ++a)
    s->q_prev[a] = qn[3][a], s->qd_prev[a] = d->out.q_dot[a];
  s->theta_prev = s->theta_end = theta[3];
  return st;
}

/* ---- the final-value variant from the record ----------------------------- */
/* q of actuator a at node i (0 = the step start, 1-2 interior, 3 the end) of
 * record row r >= 1, and the node's time. */
static double rec_q(const dyn_settle *s, long r, int i, int a, double *t) {
  const double *row = s->rec + r * DYN_REC_WIDTH;
  if (i == 0) {
    const double *prev = row - DYN_REC_WIDTH;
    *t = prev[DYN_REC_T];
    return prev[DYN_REC_Q + 2 * POM_MECH_MAX_ACTUATORS + a];
  }
  *t = i == 3 ? row[DYN_REC_T] : row[DYN_REC_T] - row[DYN_REC_H] + gl_node[i - 1] * row[DYN_REC_H];
  return row[DYN_REC_Q + (i - 1) * POM_MECH_MAX_ACTUATORS + a];
}

/* g(t) = |P(t) - ref| - band with P the cubic through a step's 4 nodes. */
typedef struct {
  double t[4], q[4], ref, band;
} cubic_ctx;

static double band_on_cubic(double t, void *vctx) {
  const cubic_ctx *c = vctx;
  double P = 0.0;
  for (int i = 0; i < 4; ++i) {
    double L = 1.0;
    for (int k = 0; k < 4; ++k)
      if (k != i) L *= (t - c->t[k]) / (c->t[i] - c->t[k]);
    P += L * c->q[i];
  }
  return fabs(P - c->ref) - c->band;
}

/* dP/dt of the cubic through a step's 4 nodes (the Lagrange form). */
static double cubic_slope(const cubic_ctx *c, double t) {
  double dP = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) {
      if (k == i) continue;
      double L = 1.0 / (c->t[i] - c->t[k]);
      for (int j = 0; j < 4; ++j)
        if (j != i && j != k) L *= (t - c->t[j]) / (c->t[i] - c->t[j]);
      dP += L * c->q[i];
    }
  return dP;
}

/* The crossing on the cubic c from node ia to ia + 1; *slope receives
 * |dq/dt| there. */
static double cubic_crossing(const cubic_ctx *c, int ia, double *slope) {
  cubic_ctx *cc = (cubic_ctx *)c;
  double tc = pom_dyn_illinois(band_on_cubic, cc, c->t[ia], band_on_cubic(c->t[ia], cc),
                               c->t[ia + 1], band_on_cubic(c->t[ia + 1], cc), POM_DYN_SETTLE_XTOL);
  *slope = fabs(cubic_slope(c, tc));
  return tc;
}

/* Last time |q_a - yf| > band over the record (0 when never), located on
 * the cubic through the step's four nodes (O(h^4), section 8); *slope
 * receives |dq_a/dt| at the crossing (0 when there is none). */
static double record_last_exit(const dyn_settle *s, int a, double yf, double band, double *slope) {
  double t;
  *slope = 0.0;
  for (long r = s->rec_n - 1; r >= 1; --r)
    for (int i = 3; i >= 1; --i) {
      if (!(fabs(rec_q(s, r, i, a, &t) - yf) > band)) continue;
      /* outside at node i of row r: the crossing lies before the next node,
       * on row r (i < 3) or on row r + 1 (i = 3) */
      long rr = i < 3 ? r : r + 1;
      int ia = i < 3 ? i : 0;
      if (rr >= s->rec_n) return -1.0;
      cubic_ctx c = {.ref = yf, .band = band};
      for (int k = 0; k < 4; ++k)
        c.q[k] = rec_q(s, rr, k, a, &c.t[k]);
      return cubic_crossing(&c, ia, slope);
    }
  /* only the start (row 0) is outside: the crossing lies in the first step */
  if (s->rec_n > 1 && fabs(s->rec[DYN_REC_Q + a] - yf) > band) {
    cubic_ctx c = {.ref = yf, .band = band};
    for (int k = 0; k < 4; ++k)
      c.q[k] = rec_q(s, 1, k, a, &c.t[k]);
    return cubic_crossing(&c, 0, slope);
  }
  return 0.0;
}

/* ---- what the integration resolves --------------------------------------- */
/* res[a]: the error the integrator's error test lets each actuator position
 * carry at the state y (docs/results.md section 1c): every state i may be off
 * by its tolerance tol_i = atol_i + rtol |y_i| (rtol only where the state has
 * a relative term, m->relative), and a position is a function of the state
 * (the formulation's positions op), so res_a = sum_i |q_a(y + tol_i e_i) -
 * q_a(y)|, the first-order bound carried through the positions by one
 * perturbed evaluation per state. States the positions do not read (the
 * accumulators) add nothing. work holds n_states doubles. */
void pom_dyn_position_resolution(const pom_dyn_model *m, const double *y, double *work,
                                 double res[3]) {
  pom_dyn_position_resolution_tight(m, y, work, 1.0, res);
}

/* The same with every tolerance divided by tighten (a stepinfo re-run). */
void pom_dyn_position_resolution_tight(const pom_dyn_model *m, const double *y, double *work,
                                       double tighten, double res[3]) {
  const double rtol = m->par.solver.rtol;
  double q0[POM_MECH_MAX_ACTUATORS], q1[POM_MECH_MAX_ACTUATORS];
  m->form->positions(m, y, q0);
  for (int a = 0; a < 3; ++a)
    res[a] = 0.0;
  memcpy(work, y, (size_t)m->n_states * sizeof(double));
  for (int i = 0; i < m->n_states; ++i) {
    double tol = m->atol[i] + (!m->relative || m->relative[i] ? rtol * fabs(y[i]) : 0.0);
    if (!(tol > 0.0 && tol < 1e20)) continue; /* an unchecked accumulator (atol 1e30) */
    tol /= tighten;
    work[i] = y[i] + tol;
    m->form->positions(m, work, q1);
    work[i] = y[i];
    for (int a = 0; a < m->n_actuators; ++a)
      if (isfinite(q1[a] - q0[a])) res[a] += fabs(q1[a] - q0[a]);
  }
}

/* ---- metrics ------------------------------------------------------------- */
double pom_dyn_stepinfo_time_tol(double rtol) {
  return fmax(rtol * POM_DYN_STEPINFO_TIME_SCALE, POM_DYN_STEPINFO_TIME_FLOOR);
}

void pom_dyn_settle_metrics(const pom_dyn_model *m, pom_dyn_data *d, pom_dyn_metrics *mt) {
  const pom_dyn_params *p = &m->par;
  dyn_settle *s = &d->settle;
  /* the resolution of each position at the horizon, where the stepinfo band
   * sits (section 1c), under the tolerances this run used (tightened by
   * d->tol_tighten in a stepinfo re-run); the end state is d->yfinal,
   * d->ytmp is free */
  double res[3];
  pom_dyn_position_resolution_tight(m, d->yfinal, N_VGetArrayPointer(d->ytmp), d->tol_tighten, res);
  const double t_tol = pom_dyn_stepinfo_time_tol(p->solver.rtol);
  mt->execution_time = 0.0;
  for (int a = 0; a < 3; ++a) {
    mt->settling_time[a] = mt->settling_time_final[a] = 0.0;
    mt->settled[a] = 1;
    mt->stepinfo_unresolved[a] = 0;
    s->stepinfo_need[a] = 0.0;
  }
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_band *b = &s->act[a];
    double ts = !b->active ? 0.0 : b->outside ? -1.0 : b->t_settle;
    mt->settled[a] = ts >= 0.0;
    mt->settling_time[a] = ts >= 0.0 ? ts : NAN;
    /* stepinfo variant: band = settle_band * max |q - q_final| over every
     * node of every step */
    double yf = s->q_prev[a], peak = 0.0, qmax = 0.0, t;
    for (long r = 0; r < s->rec_n; ++r)
      for (int i = 1; i <= 3; ++i) {
        double q = r == 0 ? s->rec[DYN_REC_Q + a] : rec_q(s, r, i, a, &t);
        peak = fmax(peak, fabs(q - yf));
        qmax = fmax(qmax, fabs(q));
      }
    mt->max_abs_q[a] = qmax;
    double band_final = p->maneuver.settle_band * peak;
    double slope = 0.0;
    double tf = peak > 0 ? record_last_exit(s, a, yf, band_final, &slope) : 0.0;
    mt->settling_time_final[a] = tf >= 0 ? tf : NAN;
    /* what the error test resolves of this position must resolve the band
     * (res <= band) and place its crossing within the stated error of a
     * time (res / |dq/dt| <= t_tol); otherwise the time is integration
     * noise, not a result (section 1c): the factor by which the tolerances
     * fall short is kept for a re-run (pom_dyn_simulate_ex) */
    double need = band_final < res[a] ? res[a] / fmax(band_final, 1e-300) : 0.0;
    if (tf > 0.0) need = fmax(need, slope > 0.0 ? res[a] / (slope * t_tol) : INFINITY);
    if (need > 1.0) {
      mt->settling_time_final[a] = NAN;
      mt->stepinfo_unresolved[a] = 1;
      s->stepinfo_need[a] = need;
    }
    mt->final_q[a] = yf;
    if (!mt->settled[a])
      mt->execution_time = NAN;
    else if (!isnan(mt->execution_time))
      mt->execution_time = fmax(mt->execution_time, ts);
  }
  /* the tracking error: a time average over the horizon (docs/results.md 1b) */
  mt->tracking_rms_error = s->track_ok && s->t_prev > 0 ? sqrt(s->track_int / s->t_prev) : NAN;
  if (!s->point.active) return;
  double tp = s->point.outside ? -1.0 : s->point.t_settle;
  mt->pointing_settled = tp >= 0.0;
  mt->pointing_settling_time = tp >= 0.0 ? tp : NAN;
  mt->final_pointing_error = s->theta_end;
}
