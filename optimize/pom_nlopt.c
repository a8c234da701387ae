/* pom_nlopt.c - NLopt driver: global stage, then local polish
 * (docs/optimize.md, section 4). */
#include "pom_nlopt.h"

#include <nlopt.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void pom_opt_defaults(pom_opt_options *opts) {
  memset(opts, 0, sizeof *opts);
  opts->global = POM_OPT_GLOBAL_CRS2;
  opts->global_max_evals = 2000;
  opts->global_ftol_rel = 1e-8;
  opts->local = POM_OPT_LOCAL_BOBYQA;
  opts->local_max_evals = 500;
  opts->local_xtol_rel = 1e-8;
  opts->local_ftol_abs = 1e-12;
  opts->max_time = 0.0;
  opts->seed = 2385;
  opts->population = 0;
  opts->local_starts = 1;
  opts->local_start_separation = 0.1;
}

const char *pom_opt_result_name(int r) {
  switch (r) {
  case 0:
    return "not run";
  case NLOPT_SUCCESS:
    return "NLOPT_SUCCESS";
  case NLOPT_STOPVAL_REACHED:
    return "NLOPT_STOPVAL_REACHED";
  case NLOPT_FTOL_REACHED:
    return "NLOPT_FTOL_REACHED";
  case NLOPT_XTOL_REACHED:
    return "NLOPT_XTOL_REACHED";
  case NLOPT_MAXEVAL_REACHED:
    return "NLOPT_MAXEVAL_REACHED";
  case NLOPT_MAXTIME_REACHED:
    return "NLOPT_MAXTIME_REACHED";
  case NLOPT_FAILURE:
    return "NLOPT_FAILURE";
  case NLOPT_INVALID_ARGS:
    return "NLOPT_INVALID_ARGS";
  case NLOPT_OUT_OF_MEMORY:
    return "NLOPT_OUT_OF_MEMORY";
  case NLOPT_ROUNDOFF_LIMITED:
    return "NLOPT_ROUNDOFF_LIMITED";
  case NLOPT_FORCED_STOP:
    return "NLOPT_FORCED_STOP";
  }
  return "NLOPT_UNKNOWN";
}

/* State shared with the NLopt callback. */
typedef struct {
  pom_opt_objective f;
  void *ctx;
  nlopt_opt opt;     /* the running stage, for nlopt_force_stop */
  pom_status status; /* first failure of the objective */
  pom_error *err;
  long evals;
  int n;
  double best_x[POM_OPT_MAX_DIM];
  double best_f;
  int have_best;
  /* every point of the global stage with its value, when the local stage
   * starts from several of them: pts[k * (n + 1)] = x..., f */
  int record;
  double *pts;
  long n_pts, cap_pts;
} driver;

/* Appends (x, f) to dr->pts. 0 when out of memory. */
static int record_point(driver *dr, const double *x, double f) {
  size_t w = (size_t)dr->n + 1;
  if (dr->n_pts == dr->cap_pts) {
    long cap = dr->cap_pts ? 2 * dr->cap_pts : 64;
    double *p = realloc(dr->pts, sizeof(double) * w * (size_t)cap);
    if (!p) return 0;
    dr->pts = p;
    dr->cap_pts = cap;
  }
  double *row = dr->pts + w * (size_t)dr->n_pts;
  memcpy(row, x, sizeof(double) * (size_t)dr->n);
  row[dr->n] = f;
  ++dr->n_pts;
  return 1;
}

static double callback(unsigned n, const double *x, double *grad, void *data) {
  driver *dr = data;
  (void)grad;                                 /* derivative-free algorithms only */
  if (dr->status != POM_OK) return -HUGE_VAL; /* already stopping */
  double f = 0.0;
  ++dr->evals;
  pom_status st = dr->f(dr->ctx, x, &f, dr->err);
  if (st == POM_OK && !isfinite(f))
    st = pom_error_set(dr->err, POM_ERR_NONFINITE, __FILE__, __LINE__,
                       "objective is %g at evaluation %ld", f, dr->evals);
  if (st != POM_OK) {
    /* Stop NLopt; the value returned below is never used as a result. */
    dr->status = st;
    nlopt_force_stop(dr->opt);
    return -HUGE_VAL;
  }
  if (dr->record && !record_point(dr, x, f)) {
    dr->status = pom_error_set(dr->err, POM_ERR_NOMEM, __FILE__, __LINE__,
                               "optimizer: out of memory recording the global stage's points");
    nlopt_force_stop(dr->opt);
    return -HUGE_VAL;
  }
  if (!dr->have_best || f > dr->best_f) {
    dr->have_best = 1;
    dr->best_f = f;
    memcpy(dr->best_x, x, sizeof(double) * n);
  }
  return f;
}

static nlopt_algorithm global_alg(pom_opt_global g) {
  switch (g) {
  case POM_OPT_GLOBAL_DIRECT_L:
    return NLOPT_GN_DIRECT_L;
  case POM_OPT_GLOBAL_ISRES:
    return NLOPT_GN_ISRES;
  case POM_OPT_GLOBAL_ESCH:
    return NLOPT_GN_ESCH;
  default:
    return NLOPT_GN_CRS2_LM;
  }
}

static nlopt_algorithm local_alg(pom_opt_local l) {
  switch (l) {
  case POM_OPT_LOCAL_NELDERMEAD:
    return NLOPT_LN_NELDERMEAD;
  case POM_OPT_LOCAL_SBPLX:
    return NLOPT_LN_SBPLX;
  case POM_OPT_LOCAL_COBYLA:
    return NLOPT_LN_COBYLA;
  default:
    return NLOPT_LN_BOBYQA;
  }
}

/* Runs one stage from x (in/out). Returns the nlopt_result. */
static int run_stage(nlopt_algorithm alg, int n, const double lo[], const double hi[], double x[],
                     long max_evals, double ftol_rel, double ftol_abs, double xtol_rel,
                     const pom_opt_options *o, driver *dr, char *msg, size_t cap) {
  nlopt_opt opt = nlopt_create(alg, (unsigned)n);
  if (!opt) {
    snprintf(msg, cap, "nlopt_create failed (out of memory)");
    return NLOPT_OUT_OF_MEMORY;
  }
  dr->opt = opt;
  nlopt_set_lower_bounds(opt, lo);
  nlopt_set_upper_bounds(opt, hi);
  nlopt_set_max_objective(opt, callback, dr);
  nlopt_set_maxeval(opt, (int)max_evals);
  if (ftol_rel > 0) nlopt_set_ftol_rel(opt, ftol_rel);
  if (ftol_abs > 0) nlopt_set_ftol_abs(opt, ftol_abs);
  if (xtol_rel > 0) nlopt_set_xtol_rel(opt, xtol_rel);
  if (o->max_time > 0) nlopt_set_maxtime(opt, o->max_time);
  if (o->population > 0) nlopt_set_population(opt, (unsigned)o->population);
  double f = 0.0;
  nlopt_result r = nlopt_optimize(opt, x, &f);
  const char *m = nlopt_get_errmsg(opt);
  snprintf(msg, cap, "%s", m ? m : "");
  nlopt_destroy(opt);
  dr->opt = NULL;
  return (int)r;
}

/* Order of the recorded points: larger f first, then earlier. */
typedef struct {
  double f;
  long k;
} ranked;

static int ranked_cmp(const void *a, const void *b) {
  const ranked *p = a, *q = b;
  if (p->f != q->f) return p->f > q->f ? -1 : 1;
  return (p->k > q->k) - (p->k < q->k);
}

/* The starts of the local stage (docs/optimize.md, section 4): the global
 * stage's best point (starts[0], the single start's), then, best first, each
 * recorded point at least `sep` of the box width away, in some variable, from
 * every start taken, up to k_max. Returns the number of starts, 0 when out of
 * memory. */
static int pick_starts(const driver *dr, int n, const double lo[], const double hi[], int k_max,
                       double sep, double starts[][POM_OPT_MAX_DIM]) {
  size_t w = (size_t)n + 1;
  memcpy(starts[0], dr->best_x, sizeof(double) * (size_t)n);
  int m = 1;
  if (k_max <= 1 || dr->n_pts == 0) return m;
  ranked *r = malloc(sizeof *r * (size_t)dr->n_pts);
  if (!r) return 0;
  for (long k = 0; k < dr->n_pts; ++k) {
    r[k].f = dr->pts[w * (size_t)k + (size_t)n];
    r[k].k = k;
  }
  qsort(r, (size_t)dr->n_pts, sizeof *r, ranked_cmp);
  for (long j = 0; j < dr->n_pts && m < k_max; ++j) {
    const double *x = dr->pts + w * (size_t)r[j].k;
    int apart = 1;
    for (int s = 0; s < m && apart; ++s) {
      double d = 0.0;
      for (int i = 0; i < n; ++i)
        d = fmax(d, fabs(x[i] - starts[s][i]) / (hi[i] - lo[i]));
      apart = d >= sep;
    }
    if (apart) memcpy(starts[m++], x, sizeof(double) * (size_t)n);
  }
  free(r);
  return m;
}

pom_status pom_opt_maximize(int n, const double lo[], const double hi[], const double x0[],
                            pom_opt_objective f, void *ctx, const pom_opt_options *opts,
                            pom_opt_result *res, pom_error *err) {
  pom_opt_options def;
  if (!opts) {
    pom_opt_defaults(&def);
    opts = &def;
  }
  memset(res, 0, sizeof *res);
  res->n = n;
  res->f = NAN;
  if (n < 1 || n > POM_OPT_MAX_DIM)
    POM_FAIL(err, POM_ERR_ARG, "optimizer: %d variables, expected 1..%d", n, POM_OPT_MAX_DIM);
  for (int i = 0; i < n; ++i)
    if (!(lo[i] < hi[i]) || !isfinite(lo[i]) || !isfinite(hi[i]))
      POM_FAIL(err, POM_ERR_ARG, "optimizer: variable %d has bounds [%g, %g]", i, lo[i], hi[i]);
  if (opts->global == POM_OPT_GLOBAL_NONE && opts->local == POM_OPT_LOCAL_NONE)
    POM_FAIL(err, POM_ERR_ARG, "optimizer: neither a global nor a local stage selected");
  if (opts->global_max_evals < 1 || opts->local_max_evals < 1)
    POM_FAIL(err, POM_ERR_ARG, "optimizer: evaluation budgets %ld, %ld must be positive",
             opts->global_max_evals, opts->local_max_evals);
  if (opts->local_starts < 1 || opts->local_starts > POM_OPT_MAX_STARTS)
    POM_FAIL(err, POM_ERR_ARG, "optimizer: %d local starts, expected 1..%d", opts->local_starts,
             POM_OPT_MAX_STARTS);
  if (!(opts->local_start_separation > 0.0 && opts->local_start_separation <= 1.0))
    POM_FAIL(err, POM_ERR_ARG, "optimizer: local start separation %g, expected (0, 1]",
             opts->local_start_separation);

  driver dr;
  memset(&dr, 0, sizeof dr);
  dr.f = f;
  dr.ctx = ctx;
  dr.err = err;
  dr.n = n;
  dr.record = opts->local_starts > 1 && opts->global != POM_OPT_GLOBAL_NONE &&
              opts->local != POM_OPT_LOCAL_NONE;
  res->local_best_run = -1;
  double x[POM_OPT_MAX_DIM];
  double starts[POM_OPT_MAX_STARTS][POM_OPT_MAX_DIM];
  int n_starts = 1;
  for (int i = 0; i < n; ++i)
    x[i] = x0 ? fmin(hi[i], fmax(lo[i], x0[i])) : 0.5 * (lo[i] + hi[i]);

  struct timespec t0, t1;
  timespec_get(&t0, TIME_UTC);
  char msg[256] = "";
  pom_status st = POM_OK;

  if (opts->global != POM_OPT_GLOBAL_NONE) {
    /* NLopt keeps its generator per thread; seeding it here makes the
     * stochastic global stages repeatable. */
    nlopt_srand(opts->seed);
    res->result_global = run_stage(global_alg(opts->global), n, lo, hi, x, opts->global_max_evals,
                                   opts->global_ftol_rel, 0.0, 0.0, opts, &dr, msg, sizeof msg);
    res->evals_global = dr.evals;
    if (dr.status != POM_OK) {
      st = dr.status;
      pom_error_prefix(err, "global stage (%s) stopped", pom_opt_result_name(res->result_global));
      goto out;
    }
    if (res->result_global < 0 && res->result_global != NLOPT_ROUNDOFF_LIMITED) {
      st = pom_error_set(err, POM_ERR_NLOPT, __FILE__, __LINE__, "global stage: %s%s%s",
                         pom_opt_result_name(res->result_global), msg[0] ? ": " : "", msg);
      goto out;
    }
    if (dr.have_best) memcpy(x, dr.best_x, sizeof(double) * (size_t)n);
    if (dr.record && dr.have_best) {
      n_starts =
          pick_starts(&dr, n, lo, hi, opts->local_starts, opts->local_start_separation, starts);
      if (n_starts == 0) {
        st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__,
                           "optimizer: out of memory choosing the local starts");
        goto out;
      }
    }
    dr.record = 0;
  }
  if (n_starts == 1) memcpy(starts[0], x, sizeof(double) * (size_t)n);
  if (opts->local != POM_OPT_LOCAL_NONE) {
    long before = dr.evals;
    for (int s = 0; s < n_starts; ++s) {
      double best_before = dr.have_best ? dr.best_f : -HUGE_VAL;
      memcpy(x, starts[s], sizeof(double) * (size_t)n);
      int r = run_stage(local_alg(opts->local), n, lo, hi, x, opts->local_max_evals, 0.0,
                        opts->local_ftol_abs, opts->local_xtol_rel, opts, &dr, msg, sizeof msg);
      res->local_runs = s + 1;
      res->evals_local = dr.evals - before;
      if (s == 0 || dr.status != POM_OK || (dr.have_best && dr.best_f > best_before))
        res->result_local = r;
      if (dr.status != POM_OK) {
        st = dr.status;
        pom_error_prefix(err, "local stage (%s) stopped", pom_opt_result_name(r));
        goto out;
      }
      /* Round-off-limited ends keep the best point found; it is recorded in
       * result_local for the caller to see. */
      if (r < 0 && r != NLOPT_ROUNDOFF_LIMITED) {
        st = pom_error_set(err, POM_ERR_NLOPT, __FILE__, __LINE__, "local stage: %s%s%s",
                           pom_opt_result_name(r), msg[0] ? ": " : "", msg);
        goto out;
      }
      if (dr.have_best && dr.best_f > best_before) res->local_best_run = s;
    }
  }
out:
  free(dr.pts);
  timespec_get(&t1, TIME_UTC);
  res->wall_time = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
  if (dr.have_best) {
    memcpy(res->x, dr.best_x, sizeof(double) * (size_t)n);
    res->f = dr.best_f;
  }
  if (st == POM_OK && !dr.have_best)
    st = pom_error_set(err, POM_ERR_NLOPT, __FILE__, __LINE__,
                       "optimizer: no objective evaluation succeeded");
  return st;
}
