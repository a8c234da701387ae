/* pom_codesign_opt.c - the co-design's optimizations: gradients of the
 * Monte-Carlo figures, SLSQP/MMA with a COBYLA fallback, multi-start, the
 * epsilon-constraint front, re-evaluation, the resume journal and the
 * grid-slice check (docs/optimize.md section 11). */
#define _POSIX_C_SOURCE 200809L /* fileno, fsync */
#include "codesign_internal.h"
#include "pom_rng.h"

#include <nlopt.h>

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* ---- the unit box ------------------------------------------------------------------ */
static double to_x(const pom_cds_var *v, double u) {
  if (v->log) return pow(10.0, log10(v->lo) + u * (log10(v->hi) - log10(v->lo)));
  return v->lo + u * (v->hi - v->lo);
}

static double to_u(const pom_cds_var *v, double x) {
  if (v->log) return (log10(x) - log10(v->lo)) / (log10(v->hi) - log10(v->lo));
  return (x - v->lo) / (v->hi - v->lo);
}

/* The scalar figures the optimizer sees: [0] p95 (s), [1] energy (J),
 * [2] kinematic margin, [3] current i_peak / i_limit - 1, [4] envelope /
 * required - 1, [5] failed maneuvers, [6] p95 / time_max - 1. */
#define NQ 7

static void quantities(const pom_cds_problem *pb, const pom_cds_figures *f, double q[NQ]) {
  q[0] = f->p95;
  q[1] = f->energy;
  q[2] = f->kin;
  q[3] = f->i_limit > 0 ? f->i_peak / f->i_limit - 1.0 : 0.0;
  q[4] = f->envelope / pb->envelope - 1.0;
  q[5] = (double)f->failed;
  q[6] = f->p95 / pb->time_max - 1.0;
}

/* ---- one optimization -------------------------------------------------------------- */
typedef struct {
  const pom_cds_problem *pb;
  int c;
  int n_free;
  int map[POM_CDS_MAX_VARS]; /* free variable i -> candidate variable */
  double x_fixed[POM_CDS_MAX_VARS];
  int objective;
  double eps;   /* energy bound (J) or NaN */
  double t_ref; /* objective scales */
  double e_ref;
  /* cache of the last point */
  int have;
  int have_grad;
  double u[POM_CDS_MAX_VARS];
  double q[NQ];
  double g[NQ][POM_CDS_MAX_VARS];
  int grad_undefined; /* the censoring or a failure changed across the difference */
  pom_cds_figures fig;
  /* best feasible point */
  int have_best;
  double best_obj;
  double best_u[POM_CDS_MAX_VARS];
  pom_cds_figures best_fig;
  long simulations, evaluations;
  /* gradient = "sensitivity": the engine (one per optimization, i.e. per
   * thread), its runs and the evaluations that fell back to differences */
  pom_grad *gr;
  /* spec: this NLopt run is gradient-based with the sensitivity source:
   * every point it evaluates is a sensitivity run (its figures and its
   * gradient in one), and the current constraint is split per maneuver
   * (docs/optimize.md 11.5, "One run per point" and "The current rows") */
  int spec;
  long nm;                         /* maneuvers of the optimization set */
  double *pk;                      /* [nm] each maneuver's peak current at the cached point (A) */
  double (*gpk)[POM_CDS_MAX_VARS]; /* [nm] d(pk_k / I_max(s) - 1)/du (have_grad) */
  int *pk_src;      /* [nm] where row k came from: 0 the derivative, 1 differences, 2 held */
  int sens_refused; /* the sensitivity run refused the point sens_refused_u */
  double sens_refused_u[POM_CDS_MAX_VARS];
  long sens_runs, sens_fallbacks;
  int sens_params;
  char sens_why[160];
  long peak_rows, peak_fallbacks, peak_held, fallback_sims;
  char peak_why[160];
  double cpu0, cpu_sens; /* process CPU at the start; spent in sensitivity runs */
  int n_hist, hist_full;
  long hist_sims[POM_CDS_MAX_HIST];
  long hist_sens[POM_CDS_MAX_HIST];
  double hist_cpu[POM_CDS_MAX_HIST];
  double hist_best[POM_CDS_MAX_HIST];
  pom_status status;
  pom_error *err;
  nlopt_opt opt;
} opt_ctx;

/* The process's CPU time (s): the efficiency record's clock (section 11.8). */
static double cpu_now(void) {
  struct timespec ts;
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return NAN;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* oc for candidate c of pb started at x0 (config units; NULL: the config's
 * design), the variables with free_vars[v] != 0 free (NULL: all), the
 * objective (0 time, 1 energy) and the energy bound eps (NaN: none); u0
 * receives the start in the unit box of the free variables. */
static void opt_ctx_init(opt_ctx *oc, const pom_cds_problem *pb, int c, const double *x0,
                         const int *free_vars, int objective, double eps, double *u0,
                         pom_error *err) {
  const pom_cds_candidate *cd = &pb->cand[c];
  memset(oc, 0, sizeof *oc);
  oc->pb = pb;
  oc->c = c;
  oc->objective = objective;
  oc->eps = eps;
  oc->err = err;
  oc->status = POM_OK;
  oc->cpu0 = cpu_now();
  oc->nm = pb->maneuvers.count;
  oc->pk = calloc((size_t)oc->nm, sizeof *oc->pk);
  oc->gpk = calloc((size_t)oc->nm, sizeof *oc->gpk);
  oc->pk_src = calloc((size_t)oc->nm, sizeof *oc->pk_src);
  if (!oc->pk || !oc->gpk || !oc->pk_src)
    oc->status = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "codesign: out of memory");
  for (int v = 0; v < cd->n_vars; ++v) {
    double xv = x0 ? x0[v] : cd->var[v].x0;
    oc->x_fixed[v] = xv;
    if (free_vars && !free_vars[v]) continue;
    u0[oc->n_free] = fmin(1.0, fmax(0.0, to_u(&cd->var[v], xv)));
    oc->map[oc->n_free++] = v;
  }
}

static void opt_ctx_free(opt_ctx *oc) {
  pom_grad_destroy(oc->gr);
  oc->gr = NULL;
  free(oc->pk);
  free(oc->gpk);
  free(oc->pk_src);
  oc->pk = NULL;
  oc->gpk = NULL;
  oc->pk_src = NULL;
}

static void design_of(const opt_ctx *oc, const double *u, double *x) {
  const pom_cds_candidate *cd = &oc->pb->cand[oc->c];
  memcpy(x, oc->x_fixed, sizeof(double) * POM_CDS_MAX_VARS);
  for (int i = 0; i < oc->n_free; ++i) {
    double ui = fmin(1.0, fmax(0.0, u[i]));
    x[oc->map[i]] = to_x(&cd->var[oc->map[i]], ui);
  }
}

static double objective_of(const opt_ctx *oc, const double q[NQ]) {
  return oc->objective == 0 ? q[0] / oc->t_ref : q[1] / oc->e_ref;
}

static int feasible_q(const opt_ctx *oc, const double q[NQ]) {
  const double tol = 1e-6;
  if (q[2] > tol || q[3] > tol || q[4] > tol || q[5] > 0.5 || q[6] > tol) return 0;
  if (isfinite(oc->eps) && q[1] > oc->eps * (1 + tol)) return 0;
  return 1;
}

/* The figures at u and, when want_grad, their gradients in the unit box.
 * THE one place the gradient source is chosen (docs/optimize.md 11.5):
 * central differences of whole Monte-Carlo evaluations (pb->grad ==
 * POM_CDS_GRAD_CENTRAL), or (POM_CDS_GRAD_SENS) sens_point: one
 * sensitivity run per maneuver gives the point's figures and the time,
 * energy and current rows together; the static rows by differences of the
 * static figures; whole-simulation differences wherever a derivative is
 * undefined. */
static pom_status point_cd(opt_ctx *oc, const double *u, int want_grad);

/* The best feasible point and the efficiency record (section 11.8), after
 * the evaluation of u (figures in oc->fig, oc->q; simulations counted). */
static void record_best(opt_ctx *oc, const double *u) {
  const int n = oc->n_free;
  double obj = objective_of(oc, oc->q);
  if (feasible_q(oc, oc->q) && (!oc->have_best || obj < oc->best_obj)) {
    oc->have_best = 1;
    oc->best_obj = obj;
    memcpy(oc->best_u, u, sizeof(double) * (size_t)n);
    oc->best_fig = oc->fig;
  }
  if (oc->have_best) {
    double b = oc->objective == 0 ? oc->best_fig.p95 : oc->best_fig.energy;
    if (oc->n_hist == 0 || b < oc->hist_best[oc->n_hist - 1]) {
      if (oc->n_hist < POM_CDS_MAX_HIST) {
        oc->hist_sims[oc->n_hist] = oc->simulations;
        oc->hist_sens[oc->n_hist] = oc->sens_runs;
        oc->hist_cpu[oc->n_hist] = cpu_now() - oc->cpu0;
        oc->hist_best[oc->n_hist++] = b;
      } else {
        oc->hist_full = 1;
      }
    }
  }
}

/* Maneuver k's current row by whole-simulation differences of that
 * maneuver alone (2n plain runs): rows[i] = d(P_k / I_max(s) - 1)/du_i.
 * A difference across which the maneuver fails marks the gradient
 * undefined (the COBYLA fallback, 11.5). */
static pom_status peak_row_fd(opt_ctx *oc, const double *u, long k, double *rows) {
  const pom_cds_problem *pb = oc->pb;
  const int n = oc->n_free;
  double xs[2 * POM_CDS_MAX_VARS * POM_CDS_MAX_VARS];
  double span[POM_CDS_MAX_VARS];
  memset(xs, 0, sizeof xs);
  for (int i = 0; i < n; ++i) {
    double up[POM_CDS_MAX_VARS];
    double hh = fmin(pb->fd_step, 1.0 - u[i]), hl = fmin(pb->fd_step, u[i]);
    memcpy(up, u, sizeof(double) * (size_t)n);
    up[i] = u[i] + hh;
    design_of(oc, up, xs + (2 * i) * POM_CDS_MAX_VARS);
    up[i] = u[i] - hl;
    design_of(oc, up, xs + (2 * i + 1) * POM_CDS_MAX_VARS);
    span[i] = hh + hl;
  }
  pom_cds_figures figs[2 * POM_CDS_MAX_VARS];
  double peaks[2 * POM_CDS_MAX_VARS];
  POM_TRY(
      pom_cds_evaluate_peaks(pb, oc->c, xs, 2 * n, pb->maneuvers.seed, k, 1, figs, peaks, oc->err));
  for (int d = 0; d < 2 * n; ++d) {
    oc->simulations += figs[d].simulations;
    oc->fallback_sims += figs[d].simulations;
    if (figs[d].failed) oc->grad_undefined = 1;
  }
  for (int i = 0; i < n; ++i) {
    double cp = peaks[2 * i] / figs[2 * i].i_limit - 1.0;
    double cm = peaks[2 * i + 1] / figs[2 * i + 1].i_limit - 1.0;
    rows[i] = (cp - cm) / span[i];
  }
  return POM_OK;
}

/* One point by the sensitivity engine (gradient = "sensitivity"): every
 * maneuver of the optimization set once with sensitivities, which gives
 * the point's figures (the same aggregation as a plain evaluation, the
 * peak current located) and, from the same runs: dt_k/du_i = (dt_k/dx_v)
 * (dx_v/du_i), one sensitivity parameter per design variable
 * (pom_cds_sens_maneuvers), dT95/du = sum_k w_k dt_k/du (the smooth
 * quantile's weights), dE/du the mean of de_k/du; kinematic margin,
 * envelope and the size law's current limit by differences of the static
 * figures (no simulation). The current rows, one per maneuver (the split
 * constraint c_k = P_k / I_max(s) - 1 <= 0, 11.5): dc_k/du = (dP_k/du) /
 * I_max + P_k d(1/I_max)/du, dP_k/du the peak's derivative (envelope
 * theorem, 12.2); where it is undefined (a kink, an edge, a tie of coils
 * or of local maxima), within 20 % of active that maneuver's row comes
 * from differences of that maneuver alone (peak_fallbacks), farther its
 * peak is held (only the limit moves; peak_held). The aggregate row q3
 * (the largest peak; pom_cds_gradient_at) is the row of the maneuver with
 * the largest peak. *ok = 0: a maneuver has no figures or no time or
 * energy derivative (why in sens_why); nothing written but the counts. */
static pom_status sens_point(opt_ctx *oc, const double *u, int *ok) {
  const pom_cds_problem *pb = oc->pb;
  const pom_cds_candidate *cd = &pb->cand[oc->c];
  const int n = oc->n_free;
  const long nm = oc->nm;
  *ok = 0;
  double x[POM_CDS_MAX_VARS];
  design_of(oc, u, x);
  const size_t row = sizeof(double[POM_CDS_MAX_VARS]);
  double *t =
      malloc((size_t)nm * (3 * sizeof(double) + 3 * row + sizeof(int) + sizeof(pom_dyn_grad_why)));
  if (!t) POM_FAIL(oc->err, POM_ERR_NOMEM, "codesign: out of memory");
  double *e = t + nm, *w = e + nm;
  double(*dt)[POM_CDS_MAX_VARS] = (double(*)[POM_CDS_MAX_VARS])(w + nm);
  double(*de)[POM_CDS_MAX_VARS] = dt + nm;
  double(*dip)[POM_CDS_MAX_VARS] = de + nm;
  int *ip_ok = (int *)(void *)(dip + nm);
  pom_dyn_grad_why *ip_why = (pom_dyn_grad_why *)(void *)(ip_ok + nm);
  double *ip = oc->pk;
  pom_cds_sens_peak peak = {ip, dip, ip_ok, ip_why};
  int active[POM_CDS_MAX_VARS] = {0};
  for (int i = 0; i < n; ++i)
    active[oc->map[i]] = 1;
  int good = 0;
  pom_cds_figures fig;
  memset(&fig, 0, sizeof fig);
  const double cpu_s0 = cpu_now();
  pom_status st =
      pom_cds_sens_maneuvers(pb, oc->c, x, active, pb->maneuvers.seed, nm, &oc->gr, t, e, dt, de,
                             &peak, &fig, &good, oc->sens_why, sizeof oc->sens_why, oc->err);
  oc->cpu_sens += cpu_now() - cpu_s0;
  oc->sens_runs += nm;
  oc->sens_params = n;
  oc->simulations += nm; /* counted as simulations too (hist_sims) */
  if (st != POM_OK || !good) {
    oc->have = 0; /* oc->pk was overwritten */
    free(t);
    return st;
  }
  ++oc->evaluations;
  memcpy(oc->u, u, sizeof(double) * (size_t)n);
  oc->have = 1;
  oc->have_grad = 1;
  oc->grad_undefined = 0;
  oc->fig = fig;
  quantities(pb, &fig, oc->q);
  pom_cds_smooth_quantile(t, (int)nm, pb->quantile, pb->bandwidth, w);
  double gs[NQ][POM_CDS_MAX_VARS];
  memset(gs, 0, sizeof gs);
  for (int i = 0; i < n; ++i) {
    int v = oc->map[i];
    double dxdu = pom_cds_dx_du(&cd->var[v], x[v]);
    for (long k = 0; k < nm; ++k) {
      gs[0][i] += w[k] * dt[k][v] * dxdu;
      gs[1][i] += de[k][v] * dxdu / (double)nm;
    }
    gs[6][i] = gs[0][i] / pb->time_max;
  }
  /* the static rows, and d(1/I_max)/du for the current rows */
  double dinv[POM_CDS_MAX_VARS];
  for (int i = 0; i < n; ++i) {
    double h = pb->fd_step;
    double hh = fmin(h, 1.0 - u[i]), hl = fmin(h, u[i]);
    double up[POM_CDS_MAX_VARS], xp[POM_CDS_MAX_VARS], xm[POM_CDS_MAX_VARS];
    memcpy(up, u, sizeof(double) * (size_t)n);
    up[i] = u[i] + hh;
    design_of(oc, up, xp);
    up[i] = u[i] - hl;
    design_of(oc, up, xm);
    pom_cds_figures fp = oc->fig, fm = oc->fig;
    pom_cds_static_figures(pb, oc->c, xp, &fp);
    pom_cds_static_figures(pb, oc->c, xm, &fm);
    double qp[NQ], qm[NQ];
    quantities(pb, &fp, qp);
    quantities(pb, &fm, qm);
    for (int k = 2; k <= 4; ++k)
      gs[k][i] = (qp[k] - qm[k]) / (hh + hl);
    dinv[i] = (1.0 / fp.i_limit - 1.0 / fm.i_limit) / (hh + hl);
  }
  /* the current rows, one per maneuver */
  const double ilim = oc->fig.i_limit;
  long k1 = 0;
  for (long k = 0; k < nm; ++k) {
    if (ip[k] > ip[k1]) k1 = k;
    for (int i = 0; i < n; ++i)
      oc->gpk[k][i] = ip[k] * dinv[i]; /* the limit's part */
    oc->pk_src[k] = ip_ok[k] ? 0 : ip[k] / ilim - 1.0 > -0.2 ? 1 : 2;
    if (ip_ok[k]) {
      for (int i = 0; i < n; ++i) {
        int v = oc->map[i];
        oc->gpk[k][i] += dip[k][v] * pom_cds_dx_du(&cd->var[v], x[v]) / ilim;
      }
      ++oc->peak_rows;
    } else if (ip[k] / ilim - 1.0 > -0.2) {
      snprintf(oc->peak_why, sizeof oc->peak_why, "maneuver %ld: %s", k,
               pom_dyn_grad_why_text(ip_why[k]));
      ++oc->peak_fallbacks;
      st = peak_row_fd(oc, u, k, oc->gpk[k]);
      if (st != POM_OK) break;
    } else {
      ++oc->peak_held; /* more than 20 % from active: the peak held, the limit moves */
    }
  }
  free(t);
  POM_TRY(st);
  for (int i = 0; i < n; ++i)
    gs[3][i] = oc->gpk[k1][i];
  memcpy(oc->g, gs, sizeof gs);
  record_best(oc, u);
  *ok = 1;
  return POM_OK;
}

static pom_status point(opt_ctx *oc, const double *u, int want_grad) {
  const int n = oc->n_free;
  if (oc->have && memcmp(u, oc->u, sizeof(double) * (size_t)n) == 0 &&
      (!want_grad || oc->have_grad))
    return POM_OK;
  if (oc->pb->grad != POM_CDS_GRAD_SENS) return point_cd(oc, u, want_grad);
  /* one sensitivity run per maneuver gives the figures and the gradient:
   * at every point that asks for a gradient, and at every point of a
   * gradient-based run (SLSQP's line search asks for none, then for the
   * gradient at the point it accepts: one run serves both, and every value
   * that run sees comes from the same integration, 11.5) */
  const int refused =
      oc->sens_refused && memcmp(u, oc->sens_refused_u, sizeof(double) * (size_t)n) == 0;
  if ((want_grad || oc->spec) && !refused) {
    int ok = 0;
    POM_TRY(sens_point(oc, u, &ok));
    if (ok) return POM_OK;
    oc->sens_refused = 1;
    memcpy(oc->sens_refused_u, u, sizeof(double) * (size_t)n);
  }
  if (!want_grad) return point_cd(oc, u, 0);
  /* a derivative undefined: this evaluation's gradient by differences */
  ++oc->sens_fallbacks;
  oc->have_grad = 0;
  long sims0 = oc->simulations;
  POM_TRY(point_cd(oc, u, 1));
  oc->fallback_sims += oc->simulations - sims0;
  return POM_OK;
}

static pom_status point_cd(opt_ctx *oc, const double *u, int want_grad) {
  const int n = oc->n_free;
  if (oc->have && memcmp(u, oc->u, sizeof(double) * (size_t)n) == 0 &&
      (!want_grad || oc->have_grad))
    return POM_OK;
  const pom_cds_problem *pb = oc->pb;
  int nd = want_grad ? 1 + 2 * n : 1;
  double xs[(1 + 2 * POM_CDS_MAX_VARS) * POM_CDS_MAX_VARS];
  double up[(1 + 2 * POM_CDS_MAX_VARS)][POM_CDS_MAX_VARS];
  memset(xs, 0, sizeof xs);
  for (int d = 0; d < nd; ++d)
    memcpy(up[d], u, sizeof(double) * (size_t)n);
  double h_lo[POM_CDS_MAX_VARS], h_hi[POM_CDS_MAX_VARS];
  for (int i = 0; i < n && want_grad; ++i) {
    /* central where the box allows, one-sided against a bound */
    double h = pb->fd_step;
    h_hi[i] = fmin(h, 1.0 - u[i]);
    h_lo[i] = fmin(h, u[i]);
    if (h_hi[i] <= 0 && h_lo[i] <= 0) h_hi[i] = h; /* cannot happen in [0, 1] */
    up[1 + 2 * i][i] = u[i] + h_hi[i];
    up[2 + 2 * i][i] = u[i] - h_lo[i];
  }
  for (int d = 0; d < nd; ++d)
    design_of(oc, up[d], xs + d * POM_CDS_MAX_VARS);
  pom_cds_figures figs[1 + 2 * POM_CDS_MAX_VARS];
  /* with every maneuver's (sampled) peak: the split current constraints of
   * the sensitivity source and pom_cds_gradient_at's per-maneuver rows; the
   * figures are those of pom_cds_evaluate_many (the same runs, the same
   * aggregation) */
  double *peaks = malloc((size_t)nd * (size_t)oc->nm * sizeof *peaks);
  if (!peaks) POM_FAIL(oc->err, POM_ERR_NOMEM, "codesign: out of memory");
  pom_status st = pom_cds_evaluate_peaks(pb, oc->c, xs, nd, pb->maneuvers.seed, 0, oc->nm, figs,
                                         peaks, oc->err);
  for (long k = 0; k < oc->nm && st == POM_OK; ++k) {
    oc->pk[k] = peaks[k];
    oc->pk_src[k] = 1;
    for (int i = 0; i < n && want_grad; ++i) {
      double cp = peaks[(1 + 2 * i) * oc->nm + k] / figs[1 + 2 * i].i_limit - 1.0;
      double cm = peaks[(2 + 2 * i) * oc->nm + k] / figs[2 + 2 * i].i_limit - 1.0;
      oc->gpk[k][i] = (cp - cm) / (h_hi[i] + h_lo[i]);
    }
  }
  free(peaks);
  POM_TRY(st);
  for (int d = 0; d < nd; ++d)
    oc->simulations += figs[d].simulations;
  ++oc->evaluations;
  memcpy(oc->u, u, sizeof(double) * (size_t)n);
  oc->have = 1;
  oc->have_grad = want_grad;
  oc->fig = figs[0];
  quantities(pb, &figs[0], oc->q);
  oc->grad_undefined = 0;
  if (want_grad) {
    for (int i = 0; i < n; ++i) {
      double qp[NQ], qm[NQ];
      quantities(pb, &figs[1 + 2 * i], qp);
      quantities(pb, &figs[2 + 2 * i], qm);
      double span = h_hi[i] + h_lo[i];
      for (int k = 0; k < NQ; ++k)
        oc->g[k][i] = (qp[k] - qm[k]) / span;
      oc->g[5][i] = 0.0; /* a count: no derivative */
      if (figs[1 + 2 * i].unsettled != figs[0].unsettled ||
          figs[2 + 2 * i].unsettled != figs[0].unsettled ||
          figs[1 + 2 * i].failed != figs[0].failed || figs[2 + 2 * i].failed != figs[0].failed)
        oc->grad_undefined = 1;
    }
  }
  record_best(oc, u);
  return POM_OK;
}

static double nl_fail(opt_ctx *oc, pom_status st) {
  oc->status = st;
  nlopt_force_stop(oc->opt);
  return HUGE_VAL;
}

static double nl_objective(unsigned n, const double *u, double *grad, void *data) {
  opt_ctx *oc = data;
  if (oc->status != POM_OK) return HUGE_VAL;
  pom_status st = point(oc, u, grad != NULL);
  if (st != POM_OK) return nl_fail(oc, st);
  int k = oc->objective == 0 ? 0 : 1;
  double scale = oc->objective == 0 ? oc->t_ref : oc->e_ref;
  if (grad)
    for (unsigned i = 0; i < n; ++i)
      grad[i] = oc->g[k][i] / scale;
  return objective_of(oc, oc->q);
}

/* Constraint m: 0 kinematics, 1 current, 2 envelope, 3 failures, 4 time
 * bound, 5 energy bound; k >= 0: the current constraint of maneuver k alone
 * (split, oc->spec). */
typedef struct {
  opt_ctx *oc;
  int m;
  long k;
} con_data;

static double nl_constraint(unsigned n, const double *u, double *grad, void *data) {
  con_data *cdt = data;
  opt_ctx *oc = cdt->oc;
  if (oc->status != POM_OK) return HUGE_VAL;
  pom_status st = point(oc, u, grad != NULL);
  if (st != POM_OK) return nl_fail(oc, st);
  if (cdt->k >= 0) {
    /* maneuver k's current: P_k / I_max(s) - 1 (11.5, "The current rows") */
    if (grad)
      for (unsigned i = 0; i < n; ++i)
        grad[i] = oc->gpk[cdt->k][i];
    return oc->fig.i_limit > 0 ? oc->pk[cdt->k] / oc->fig.i_limit - 1.0 : 0.0;
  }
  int k = cdt->m == 5 ? 1 : cdt->m == 4 ? 6 : 2 + cdt->m;
  double scale = cdt->m == 5 ? oc->eps : 1.0;
  double off = cdt->m == 5 ? 1.0 : 0.0;
  if (cdt->m == 3) off = 0.5; /* failures: <= 0.5 means none */
  if (grad)
    for (unsigned i = 0; i < n; ++i)
      grad[i] = oc->g[k][i] / scale;
  return oc->q[k] / scale - off;
}

static nlopt_algorithm alg_of(pom_cds_alg a) {
  switch (a) {
  case POM_CDS_ALG_MMA:
    return NLOPT_LD_MMA;
  case POM_CDS_ALG_COBYLA:
    return NLOPT_LN_COBYLA;
  default:
    return NLOPT_LD_SLSQP;
  }
}

/* One NLopt run from u (in/out). */
static int run_nlopt(opt_ctx *oc, pom_cds_alg alg, double *u, int max_evals) {
  const int n = oc->n_free;
  nlopt_opt opt = nlopt_create(alg_of(alg), (unsigned)n);
  if (!opt) return NLOPT_OUT_OF_MEMORY;
  oc->opt = opt;
  double lo[POM_CDS_MAX_VARS], hi[POM_CDS_MAX_VARS];
  for (int i = 0; i < n; ++i) {
    lo[i] = 0.0;
    hi[i] = 1.0;
  }
  nlopt_set_lower_bounds(opt, lo);
  nlopt_set_upper_bounds(opt, hi);
  nlopt_set_min_objective(opt, nl_objective, oc);
  /* the sensitivity source in a gradient-based run: every point by one
   * sensitivity run per maneuver, the current constraint one per maneuver */
  oc->spec = oc->pb->grad == POM_CDS_GRAD_SENS && alg != POM_CDS_ALG_COBYLA;
  int nc = isfinite(oc->eps) ? 6 : 5;
  long ncd = nc + (oc->spec ? oc->nm : 0);
  con_data *cd = malloc((size_t)ncd * sizeof *cd);
  if (!cd) {
    nlopt_destroy(opt);
    oc->opt = NULL;
    return NLOPT_OUT_OF_MEMORY;
  }
  long ic = 0;
  for (int m = 0; m < nc; ++m) {
    if (m == 1 && oc->spec) {
      for (long k = 0; k < oc->nm; ++k) {
        cd[ic] = (con_data){oc, 1, k};
        nlopt_add_inequality_constraint(opt, nl_constraint, &cd[ic++], 1e-6);
      }
      continue;
    }
    cd[ic] = (con_data){oc, m, -1};
    nlopt_add_inequality_constraint(opt, nl_constraint, &cd[ic++], 1e-6);
  }
  nlopt_set_maxeval(opt, max_evals);
  if (oc->pb->xtol_rel > 0) nlopt_set_xtol_rel(opt, oc->pb->xtol_rel);
  if (alg == POM_CDS_ALG_COBYLA) {
    double step[POM_CDS_MAX_VARS];
    for (int i = 0; i < n; ++i)
      step[i] = 0.1;
    nlopt_set_initial_step(opt, step);
  }
  double f = 0;
  nlopt_result r = nlopt_optimize(opt, u, &f);
  nlopt_destroy(opt);
  free(cd);
  oc->opt = NULL;
  oc->spec = 0;
  return (int)r;
}

pom_status pom_cds_optimize(const pom_cds_problem *pb, int c, const double *x0, int objective,
                            double eps, const int *free_vars, pom_cds_alg alg, pom_cds_point *pt,
                            pom_error *err) {
  const pom_cds_candidate *cd = &pb->cand[c];
  opt_ctx oc;
  double u[POM_CDS_MAX_VARS];
  opt_ctx_init(&oc, pb, c, x0, free_vars, objective, eps, u, err);
  if (oc.status != POM_OK || oc.n_free < 1) {
    opt_ctx_free(&oc);
    if (oc.status != POM_OK) return oc.status;
    POM_FAIL(err, POM_ERR_ARG, "codesign: no free variable");
  }
  /* scales: the figures at the start (positive); with the sensitivity
   * source and a gradient-based algorithm the start is its first point
   * (it asks for the gradient there): one sensitivity run serves both */
  oc.spec = pb->grad == POM_CDS_GRAD_SENS && alg != POM_CDS_ALG_COBYLA;
  pom_status st0 = point(&oc, u, oc.spec);
  oc.spec = 0;
  if (st0 != POM_OK) {
    opt_ctx_free(&oc);
    return st0;
  }
  oc.t_ref = oc.q[0] > 0 ? oc.q[0] : 1e-3;
  oc.e_ref = oc.q[1] > 0 ? oc.q[1] : 1e-3;
  double u_start[POM_CDS_MAX_VARS];
  memcpy(u_start, u, sizeof u_start);
  memset(pt, 0, sizeof *pt);
  pt->objective = objective;
  pt->eps = eps;
  int r = run_nlopt(&oc, alg, u, pb->max_evals);
  if (oc.status != POM_OK) {
    opt_ctx_free(&oc);
    return oc.status;
  }
  pt->nlopt_result = r;
  /* derivative-free fallback: the gradient method failed, found nothing
   * feasible, or ended where the censoring makes the gradient undefined */
  int need_fb = alg != POM_CDS_ALG_COBYLA &&
                ((r < 0 && r != NLOPT_ROUNDOFF_LIMITED) || !oc.have_best || oc.grad_undefined);
  if (need_fb) {
    double u2[POM_CDS_MAX_VARS];
    memcpy(u2, oc.have_best ? oc.best_u : u_start, sizeof u2);
    int r2 = run_nlopt(&oc, POM_CDS_ALG_COBYLA, u2, pb->max_evals);
    if (oc.status != POM_OK) {
      opt_ctx_free(&oc);
      return oc.status;
    }
    pt->fallback_used = 1;
    pt->nlopt_result = r2;
  }
  double ub[POM_CDS_MAX_VARS];
  if (oc.have_best) {
    memcpy(ub, oc.best_u, sizeof ub);
    pt->opt = oc.best_fig;
    pt->feasible = 1;
  } else {
    /* nothing feasible: the last point, marked infeasible */
    memcpy(ub, oc.u, sizeof ub);
    pt->opt = oc.fig;
    pt->feasible = 0;
  }
  design_of(&oc, ub, pt->x);
  for (int v = cd->n_vars; v < POM_CDS_MAX_VARS; ++v)
    pt->x[v] = 0.0;
  pt->simulations = oc.simulations;
  pt->evaluations = oc.evaluations;
  pt->sens_runs = oc.sens_runs;
  pt->sens_params = oc.sens_params;
  pt->sens_fallbacks = oc.sens_fallbacks;
  snprintf(pt->sens_why, sizeof pt->sens_why, "%s", oc.sens_why);
  pt->peak_rows = oc.peak_rows;
  pt->peak_fallbacks = oc.peak_fallbacks;
  pt->peak_held = oc.peak_held;
  snprintf(pt->peak_why, sizeof pt->peak_why, "%s", oc.peak_why);
  pt->fallback_sims = oc.fallback_sims;
  opt_ctx_free(&oc);
  pt->cpu = cpu_now() - oc.cpu0;
  pt->cpu_sens = oc.cpu_sens;
  pt->n_hist = oc.n_hist;
  pt->hist_full = oc.hist_full;
  memcpy(pt->hist_sims, oc.hist_sims, sizeof oc.hist_sims);
  memcpy(pt->hist_sens, oc.hist_sens, sizeof oc.hist_sens);
  memcpy(pt->hist_cpu, oc.hist_cpu, sizeof oc.hist_cpu);
  memcpy(pt->hist_best, oc.hist_best, sizeof oc.hist_best);
  pt->done = 1;
  return POM_OK;
}

/* ---- journal (resume) --------------------------------------------------------------- */
static uint64_t fnv1a(const char *s) {
  uint64_t h = 1469598103934665603ULL;
  for (; *s; ++s) {
    h ^= (unsigned char)*s;
    h *= 1099511628211ULL;
  }
  return h;
}

typedef struct {
  int c, task;
  pom_cds_point pt;
} journal_entry;

/* the time starts, the energy optimum, the epsilon points and their second
 * starts (from the time optimum) */
#define MAX_TASKS (POM_CDS_MAX_STARTS + 2 * POM_CDS_MAX_FRONT)

static pom_status journal_append(const char *path, int c, int task, const pom_cds_point *pt, int nv,
                                 pom_error *err) {
  FILE *f = fopen(path, "a");
  if (!f) POM_FAIL(err, POM_ERR_IO, "cannot open the journal '%s': %s", path, strerror(errno));
  int ok = fprintf(f, "task %d %d %d %d %d %ld %ld %a", c, task, pt->feasible, pt->fallback_used,
                   pt->nlopt_result, pt->simulations, pt->evaluations, pt->eps) > 0;
  for (int v = 0; v < nv && ok; ++v)
    ok = fprintf(f, " %a", pt->x[v]) > 0;
  ok = ok && fprintf(f, "\n") > 0;
  ok = ok && fflush(f) == 0 && fsync(fileno(f)) == 0;
  if (fclose(f) != 0) ok = 0;
  if (!ok) POM_FAIL(err, POM_ERR_IO, "cannot write the journal '%s': %s", path, strerror(errno));
  return POM_OK;
}

static pom_status journal_start(const char *path, uint64_t hash, pom_error *err) {
  FILE *f = fopen(path, "w");
  if (!f) POM_FAIL(err, POM_ERR_IO, "cannot create the journal '%s': %s", path, strerror(errno));
  int ok = fprintf(f, "pomlab codesign journal 1 %016llx\n", (unsigned long long)hash) > 0;
  ok = ok && fflush(f) == 0 && fsync(fileno(f)) == 0;
  if (fclose(f) != 0) ok = 0;
  if (!ok) POM_FAIL(err, POM_ERR_IO, "cannot write the journal '%s': %s", path, strerror(errno));
  return POM_OK;
}

/* Reads the finished tasks; refuses a journal of another problem. */
static pom_status journal_read(const char *path, uint64_t hash, const pom_cds_problem *pb,
                               journal_entry *e, int cap, int *n, pom_error *err) {
  *n = 0;
  FILE *f = fopen(path, "r");
  if (!f) return POM_OK; /* nothing to resume */
  char line[4096];
  pom_status st = POM_OK;
  unsigned long long h = 0;
  if (!fgets(line, sizeof line, f) || sscanf(line, "pomlab codesign journal 1 %llx", &h) != 1) {
    fclose(f);
    POM_FAIL(err, POM_ERR_IO, "'%s' is not a codesign journal: remove it to start again", path);
  }
  if ((uint64_t)h != hash) {
    fclose(f);
    POM_FAIL(err, POM_ERR_CONFIG,
             "'%s' belongs to another codesign file (or an edited one): it cannot be resumed; "
             "remove it or run without --resume",
             path);
  }
  int lineno = 1;
  while (fgets(line, sizeof line, f)) {
    ++lineno;
    if (!strchr(line, '\n')) break; /* a torn last line (interrupted write): ignored */
    journal_entry je;
    memset(&je, 0, sizeof je);
    char *p = line;
    int used = 0;
    if (sscanf(p, "task %d %d %d %d %d %ld %ld %la%n", &je.c, &je.task, &je.pt.feasible,
               &je.pt.fallback_used, &je.pt.nlopt_result, &je.pt.simulations, &je.pt.evaluations,
               &je.pt.eps, &used) != 8 ||
        je.c < 0 || je.c >= pb->n_candidates || je.task < 0 || je.task >= MAX_TASKS) {
      st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__,
                         "%s:%d: not a task line of this problem", path, lineno);
      break;
    }
    p += used;
    for (int v = 0; v < pb->cand[je.c].n_vars && st == POM_OK; ++v) {
      if (sscanf(p, " %la%n", &je.pt.x[v], &used) != 1)
        st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__,
                           "%s:%d: variable %d of candidate '%s' missing", path, lineno, v + 1,
                           pb->cand[je.c].name);
      p += used;
    }
    if (st != POM_OK) break;
    je.pt.done = 1;
    if (*n < cap) e[(*n)++] = je;
  }
  fclose(f);
  return st;
}

/* ---- the run ------------------------------------------------------------------------ */
static const journal_entry *find_task(const journal_entry *e, int n, int c, int task) {
  for (int i = n - 1; i >= 0; --i)
    if (e[i].c == c && e[i].task == task) return &e[i];
  return NULL;
}

typedef struct {
  pom_cds_progress_fn fn;
  void *user;
  long done, total;
} progress_state;

/* A task: optimize, or take it from the journal (then its figures are
 * recomputed from x, which is deterministic). */
static pom_status task(const pom_cds_problem *pb, int c, int t, const double *x0, int objective,
                       double eps, const journal_entry *je, int nj, const char *journal,
                       progress_state *ps, pom_cds_point *pt, int *resumed, pom_error *err) {
  const journal_entry *j = find_task(je, nj, c, t);
  if (j) {
    *pt = j->pt;
    POM_TRY(
        pom_cds_evaluate(pb, c, pt->x, pb->maneuvers.seed, pb->maneuvers.count, 0, &pt->opt, err));
    pt->objective = objective;
    ++*resumed;
  } else {
    POM_TRY(pom_cds_optimize(pb, c, x0, objective, eps, NULL, pb->alg, pt, err));
    if (journal) POM_TRY(journal_append(journal, c, t, pt, pb->cand[c].n_vars, err));
  }
  ps->done += pb->max_evals;
  if (ps->fn) {
    char phase[POM_DOE_NAME_LEN + 32];
    snprintf(phase, sizeof phase, "%s", pb->cand[c].name);
    ps->fn(ps->user, phase, ps->done, ps->total);
  }
  return POM_OK;
}

static double pt_obj(const pom_cds_point *p, int objective) {
  return objective == 0 ? p->opt.p95 : p->opt.energy;
}

/* 2-D hypervolume (minimization) of points (t, e) against (rt, re). */
static double hypervolume(const double *t, const double *e, int n, double rt, double re) {
  int idx[POM_CDS_MAX_FRONT];
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (t[i] < rt && e[i] < re) idx[m++] = i;
  for (int i = 1; i < m; ++i)
    for (int j = i; j > 0 && t[idx[j - 1]] > t[idx[j]]; --j) {
      int tmp = idx[j];
      idx[j] = idx[j - 1];
      idx[j - 1] = tmp;
    }
  /* a staircase: sorted by time, each non-dominated point adds the slab
   * between its energy and the previous point's */
  double hv = 0.0, e_cur = re;
  for (int i = 0; i < m; ++i) {
    double ti = t[idx[i]], ei = e[idx[i]];
    if (ei >= e_cur) continue; /* dominated */
    hv += (rt - ti) * (e_cur - ei);
    e_cur = ei;
  }
  return hv;
}

pom_status pom_cds_run(const pom_cds_problem *pb, const char *journal, int resume,
                       pom_cds_progress_fn progress, void *user, pom_cds_result *res,
                       pom_error *err) {
  memset(res, 0, sizeof *res);
  double t0 = 0;
  {
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    t0 = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
  }
  uint64_t hash = fnv1a(pb->config_text);
  /* the gradient source may come from the command line (--gradient), which
   * the file's text does not show: a journal of the other source is
   * another problem (central differences keep the file's own hash) */
  if (pb->grad == POM_CDS_GRAD_SENS) hash = fnv1a("gradient = sensitivity") ^ (hash * 31u);
  journal_entry *je = calloc(POM_CDS_MAX_CANDIDATES * MAX_TASKS, sizeof *je);
  if (!je) POM_FAIL(err, POM_ERR_NOMEM, "codesign: out of memory");
  int nj = 0;
  pom_status st = POM_OK;
  if (journal && resume)
    st = journal_read(journal, hash, pb, je, POM_CDS_MAX_CANDIDATES * MAX_TASKS, &nj, err);
  if (st == POM_OK && journal && nj == 0) st = journal_start(journal, hash, err);
  progress_state ps = {progress, user, 0,
                       (long)pb->n_candidates * (pb->starts + pb->front_points - 1) *
                           pb->max_evals};
  for (int c = 0; c < pb->n_candidates && st == POM_OK; ++c) {
    const pom_cds_candidate *cd = &pb->cand[c];
    pom_cds_cand_result *cr = &res->cand[c];
    double x0[POM_CDS_MAX_VARS] = {0};
    for (int v = 0; v < cd->n_vars; ++v)
      x0[v] = cd->var[v].x0;
    st = pom_cds_evaluate(pb, c, x0, pb->maneuvers.seed, pb->maneuvers.count, 0, &cr->nominal, err);
    if (st != POM_OK) {
      pom_error_prefix(err, "candidate '%s' at its config's design", cd->name);
      break;
    }
    /* time optimum: multi-start (the config's design, then seeded points) */
    pom_rng rng;
    pom_rng_seed(&rng, pb->maneuvers.seed, 7000u + (uint64_t)c);
    pom_cds_point best;
    memset(&best, 0, sizeof best);
    for (int s = 0; s < pb->starts && st == POM_OK; ++s) {
      double xs[POM_CDS_MAX_VARS] = {0};
      for (int v = 0; v < cd->n_vars; ++v)
        xs[v] = s == 0 ? x0[v] : to_x(&cd->var[v], 0.1 + 0.8 * pom_rng_uniform(&rng));
      pom_cds_point p;
      st = task(pb, c, s, xs, 0, NAN, je, nj, journal, &ps, &p, &res->resumed_tasks, err);
      if (st != POM_OK) break;
      cr->simulations += p.simulations;
      if (!best.done || (p.feasible && !best.feasible) ||
          (p.feasible == best.feasible && pt_obj(&p, 0) < pt_obj(&best, 0)))
        best = p;
    }
    if (st != POM_OK) break;
    const int K = pb->front_points;
    cr->n_points = K;
    cr->point[0] = best;
    /* energy optimum from the time optimum */
    pom_cds_point pe;
    st = task(pb, c, pb->starts, best.x, 1, NAN, je, nj, journal, &ps, &pe, &res->resumed_tasks,
              err);
    if (st != POM_OK) break;
    cr->simulations += pe.simulations;
    cr->point[K - 1] = pe;
    /* epsilon-constraint: minimize time with energy <= eps_k, from the
     * energy optimum's side (each start meets its bound: the previous
     * point's energy is below the next, larger, bound) */
    double e_hi = best.opt.energy, e_lo = pe.opt.energy;
    const pom_cds_point *prev = &pe;
    for (int k = K - 2; k >= 1 && st == POM_OK; --k) {
      double eps = e_hi - (e_hi - e_lo) * k / (K - 1);
      pom_cds_point *p = &cr->point[k];
      st = task(pb, c, pb->starts + k, prev->x, 0, eps, je, nj, journal, &ps, p,
                &res->resumed_tasks, err);
      if (st != POM_OK) break;
      p->eps = eps;
      cr->simulations += p->simulations;
      /* stuck on its start (docs/optimize.md 11.5): no feasible design at
       * least 0.1 % faster than the start, whose energy leaves the bound
       * slack. A second start from the time optimum, on the bound's other
       * side; the better of the two is the front point. */
      if (!(p->feasible && p->opt.p95 < (1.0 - POM_CDS_STUCK_TOL) * prev->opt.p95)) {
        pom_cds_point q;
        ps.total += pb->max_evals;
        st = task(pb, c, pb->starts + K - 1 + k, best.x, 0, eps, je, nj, journal, &ps, &q,
                  &res->resumed_tasks, err);
        if (st != POM_OK) break;
        q.eps = eps;
        cr->simulations += q.simulations;
        long sims = p->simulations + q.simulations, evals = p->evaluations + q.evaluations;
        int take = (q.feasible && !p->feasible) ||
                   (q.feasible == p->feasible && pt_obj(&q, 0) < pt_obj(p, 0));
        if (take) *p = q;
        p->restarted = take ? 2 : 1;
        p->simulations = sims;
        p->evaluations = evals;
      }
      prev = p;
    }
    if (st != POM_OK) break;
    /* honest figures: a fresh maneuver set, rigid and parasitic */
    st = pom_cds_evaluate(pb, c, x0, pb->reeval_seed, pb->reeval_count, 0, &cr->nominal_fresh, err);
    for (int k = 0; k < K && st == POM_OK; ++k) {
      pom_cds_point *p = &cr->point[k];
      st = pom_cds_evaluate(pb, c, p->x, pb->reeval_seed, pb->reeval_count, 0, &p->fresh, err);
      if (st == POM_OK)
        st = pom_cds_evaluate(pb, c, p->x, pb->reeval_seed, pb->reeval_count, 1,
                              &p->fresh_parasitic, err);
      if (st == POM_OK) st = pom_cds_rdw_deg(pb, c, p->x, &p->rdw_deg, err);
    }
    if (st != POM_OK) pom_error_prefix(err, "candidate '%s', re-evaluation", cd->name);
    res->simulations += cr->simulations;
    res->other_simulations += cr->nominal.simulations + cr->nominal_fresh.simulations;
    for (int k = 0; k < K; ++k)
      res->other_simulations +=
          cr->point[k].fresh.simulations + cr->point[k].fresh_parasitic.simulations;
  }
  free(je);
  if (st != POM_OK) return st;
  /* hypervolume of every re-evaluated front against one reference: 1.1 x the
   * worst time and energy over all fronts and the config designs */
  double rt = 0, re = 0;
  for (int c = 0; c < pb->n_candidates; ++c) {
    const pom_cds_cand_result *cr = &res->cand[c];
    rt = fmax(rt, cr->nominal_fresh.p95);
    re = fmax(re, cr->nominal_fresh.energy);
    for (int k = 0; k < cr->n_points; ++k) {
      rt = fmax(rt, cr->point[k].fresh.p95);
      re = fmax(re, cr->point[k].fresh.energy);
    }
  }
  res->ref_time = 1.1 * rt;
  res->ref_energy = 1.1 * re;
  for (int c = 0; c < pb->n_candidates; ++c) {
    pom_cds_cand_result *cr = &res->cand[c];
    double t[POM_CDS_MAX_FRONT], e[POM_CDS_MAX_FRONT];
    int m = 0;
    for (int k = 0; k < cr->n_points; ++k)
      if (cr->point[k].feasible) {
        t[m] = cr->point[k].fresh.p95;
        e[m++] = cr->point[k].fresh.energy;
      }
    cr->hypervolume = hypervolume(t, e, m, res->ref_time, res->ref_energy);
  }
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  res->wall = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec - t0;
  return POM_OK;
}

/* ---- 1-D sweeps (section 11.6) ------------------------------------------------------ */
int pom_cds_feasible(const pom_cds_problem *pb, const pom_cds_figures *f) {
  double q[NQ];
  quantities(pb, f, q);
  opt_ctx tmp;
  memset(&tmp, 0, sizeof tmp);
  tmp.eps = NAN;
  return feasible_q(&tmp, q);
}

pom_status pom_cds_sweep(const pom_cds_problem *pb, int c, int n, double *xs, pom_cds_figures *figs,
                         pom_error *err) {
  const pom_cds_candidate *cd = &pb->cand[c];
  if (n < 2 || n > 200) POM_FAIL(err, POM_ERR_ARG, "sweep: %d points (2..200)", n);
  double *rows = calloc((size_t)n * POM_CDS_MAX_VARS, sizeof *rows);
  if (!rows) POM_FAIL(err, POM_ERR_NOMEM, "sweep: out of memory");
  pom_status st = POM_OK;
  for (int v = 0; v < cd->n_vars && st == POM_OK; ++v) {
    /* one variable per batch */
    for (int j = 0; j < n; ++j) {
      double *x = rows + j * POM_CDS_MAX_VARS;
      for (int w = 0; w < cd->n_vars; ++w)
        x[w] = cd->var[w].x0;
      x[v] = to_x(&cd->var[v], (double)j / (n - 1));
      xs[v * n + j] = x[v];
    }
    st = pom_cds_evaluate_many(pb, c, rows, n, pb->maneuvers.seed, pb->maneuvers.count, 0,
                               figs + v * n, err);
  }
  free(rows);
  return st;
}

/* ---- grid-slice check (section 11.6) --------------------------------------------------- */
pom_status pom_cds_grid_slice(const pom_cds_problem *pb, int c, int v1, int v2, int n,
                              pom_cds_slice *out, pom_error *err) {
  const pom_cds_candidate *cd = &pb->cand[c];
  memset(out, 0, sizeof *out);
  if (v1 < 0 || v2 < 0 || v1 >= cd->n_vars || v2 >= cd->n_vars || v1 == v2 || n < 2 || n > 200)
    POM_FAIL(err, POM_ERR_ARG, "grid slice: variables %d, %d of %d, grid %d", v1 + 1, v2 + 1,
             cd->n_vars, n);
  out->grid_best = INFINITY;
  double *xs = calloc((size_t)n * POM_CDS_MAX_VARS, sizeof *xs);
  pom_cds_figures *figs = calloc((size_t)n, sizeof *figs);
  if (!xs || !figs) {
    free(xs);
    free(figs);
    POM_FAIL(err, POM_ERR_NOMEM, "grid slice: out of memory");
  }
  pom_status st = POM_OK;
  for (int i = 0; i < n && st == POM_OK; ++i) {
    /* one row of the grid per batch */
    for (int j = 0; j < n; ++j) {
      double *x = xs + j * POM_CDS_MAX_VARS;
      for (int v = 0; v < cd->n_vars; ++v)
        x[v] = cd->var[v].x0;
      x[v1] = to_x(&cd->var[v1], (double)i / (n - 1));
      x[v2] = to_x(&cd->var[v2], (double)j / (n - 1));
    }
    st = pom_cds_evaluate_many(pb, c, xs, n, pb->maneuvers.seed, pb->maneuvers.count, 0, figs, err);
    for (int j = 0; j < n && st == POM_OK; ++j) {
      out->grid_simulations += figs[j].simulations;
      double q[NQ];
      quantities(pb, &figs[j], q);
      opt_ctx tmp;
      memset(&tmp, 0, sizeof tmp);
      tmp.eps = NAN;
      if (feasible_q(&tmp, q) && q[0] < out->grid_best) {
        out->grid_best = q[0];
        out->grid_x1 = xs[j * POM_CDS_MAX_VARS + v1];
        out->grid_x2 = xs[j * POM_CDS_MAX_VARS + v2];
        out->grid_feasible = 1;
      }
    }
  }
  free(xs);
  free(figs);
  if (st != POM_OK) return st;
  int fv[POM_CDS_MAX_VARS] = {0};
  fv[v1] = fv[v2] = 1;
  /* the optimizer from the best of the config's design and the box centre */
  pom_cds_point best;
  memset(&best, 0, sizeof best);
  for (int s = 0; s < 2; ++s) {
    double x0[POM_CDS_MAX_VARS];
    for (int v = 0; v < cd->n_vars; ++v)
      x0[v] = cd->var[v].x0;
    if (s == 1) {
      x0[v1] = to_x(&cd->var[v1], 0.5);
      x0[v2] = to_x(&cd->var[v2], 0.5);
    }
    pom_cds_point p;
    POM_TRY(pom_cds_optimize(pb, c, x0, 0, NAN, fv, pb->alg, &p, err));
    out->opt_simulations += p.simulations;
    if (!best.done || (p.feasible && (!best.feasible || p.opt.p95 < best.opt.p95))) best = p;
  }
  out->opt_best = best.feasible ? best.opt.p95 : NAN;
  out->opt_x1 = best.x[v1];
  out->opt_x2 = best.x[v2];
  return POM_OK;
}

/* ---- efficiency (section 11.8) ---------------------------------------------------------- */
void pom_cds_first_within(const pom_cds_point *p, double target, double rel_tol, pom_cds_reach *r) {
  memset(r, 0, sizeof *r);
  r->cpu = NAN;
  for (int i = 0; i < p->n_hist; ++i)
    if (p->hist_best[i] <= target * (1.0 + rel_tol)) {
      r->reached = 1;
      r->sims = p->hist_sims[i];
      r->sens_runs = p->hist_sens[i];
      r->cpu = p->hist_cpu[i];
      return;
    }
  /* not in the record: not reached, or unknown when improvements were lost */
  r->reached = p->hist_full ? -1 : 0;
  r->sims = p->simulations;
  r->sens_runs = p->sens_runs;
  r->cpu = p->cpu;
}

pom_status pom_cds_efficiency_run(const pom_cds_problem *pb, int c, int budget, double rel_tol,
                                  pom_cds_efficiency *out, pom_error *err) {
  memset(out, 0, sizeof *out);
  POM_TRY(pom_cds_optimize(pb, c, NULL, 0, NAN, NULL, pb->alg, &out->grad, err));
  out->grad_sims = out->grad.simulations;
  out->grad_best = out->grad.feasible ? out->grad.opt.p95 : NAN;
  pom_cds_problem *p2 = malloc(sizeof *p2);
  if (!p2) POM_FAIL(err, POM_ERR_NOMEM, "efficiency: out of memory");
  *p2 = *pb;
  p2->max_evals = budget;
  pom_status st = pom_cds_optimize(p2, c, NULL, 0, NAN, NULL, POM_CDS_ALG_COBYLA, &out->dfree, err);
  free(p2);
  if (st != POM_OK) return st;
  out->dfree_best = out->dfree.feasible ? out->dfree.opt.p95 : NAN;
  /* the common target: the better final objective (fmin ignores a NaN) */
  out->target = fmin(out->grad_best, out->dfree_best);
  pom_cds_first_within(&out->grad, out->target, rel_tol, &out->grad_to_target);
  pom_cds_first_within(&out->dfree, out->target, rel_tol, &out->dfree_to_target);
  pom_cds_first_within(&out->grad, out->dfree_best, rel_tol, &out->grad_to_dfree);
  pom_cds_first_within(&out->dfree, out->dfree_best, rel_tol, &out->dfree_to_dfree);
  /* a sensitivity run in plain runs: CPU per sensitivity run (inside the
   * engine, the gradient-based run) over CPU per plain run (COBYLA's whole
   * run: plain runs only, model building and static figures included; the
   * gradient-based run has few or no plain runs of its own since a point
   * is one sensitivity run, docs/optimize.md 11.8) */
  const pom_cds_point *g = &out->grad, *d = &out->dfree;
  out->sens_cost = g->sens_runs > 0 && d->simulations > 0 && d->cpu > 0
                       ? (g->cpu_sens / (double)g->sens_runs) / (d->cpu / (double)d->simulations)
                       : NAN;
  return POM_OK;
}

/* ---- the gradient at one design (the check of section 11.5) ------------------------ */
pom_status pom_cds_gradient_at(const pom_cds_problem *pb, int c, const double *x,
                               pom_cds_grad_check *out, pom_error *err) {
  opt_ctx oc;
  double u[POM_CDS_MAX_VARS];
  memset(out, 0, sizeof *out);
  opt_ctx_init(&oc, pb, c, x, NULL, 0, NAN, u, err);
  pom_status st = oc.status != POM_OK ? oc.status : point(&oc, u, 1);
  if (st != POM_OK) {
    opt_ctx_free(&oc);
    return st;
  }
  const int rows[3] = {0, 1, 3};
  for (int r = 0; r < 3; ++r) {
    out->q[r] = oc.q[rows[r]];
    for (int i = 0; i < POM_CDS_MAX_VARS; ++i)
      out->g[r][i] = i < oc.n_free ? oc.g[rows[r]][i] : 0.0;
  }
  out->n_man = (int)(oc.nm < POM_CDS_CHECK_MANEUVERS ? oc.nm : POM_CDS_CHECK_MANEUVERS);
  for (int k = 0; k < out->n_man; ++k) {
    out->man_q[k] = oc.fig.i_limit > 0 ? oc.pk[k] / oc.fig.i_limit - 1.0 : 0.0;
    out->man_src[k] = oc.pk_src[k];
    for (int i = 0; i < POM_CDS_MAX_VARS; ++i)
      out->man_g[k][i] = i < oc.n_free ? oc.gpk[k][i] : 0.0;
  }
  out->simulations = oc.simulations;
  out->sens_runs = oc.sens_runs;
  out->fallbacks = oc.sens_fallbacks;
  out->peak_rows = oc.peak_rows;
  out->peak_fallbacks = oc.peak_fallbacks;
  out->peak_held = oc.peak_held;
  snprintf(out->why, sizeof out->why, "%s", oc.sens_why);
  snprintf(out->peak_why, sizeof out->peak_why, "%s", oc.peak_why);
  opt_ctx_free(&oc);
  return POM_OK;
}
