/* pom_sensitivity.c - Sobol indices (Saltelli design, Saltelli-2010 and
 * Jansen estimators, bootstrap intervals) and Morris elementary effects
 * (docs/results.md, section 11). */
#include "pom_explore.h"
#include "pom_stats.h"
#include "pom_rng.h"
#include "pom_study.h"

#include <gsl/gsl_qrng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Generator streams of the random designs and of the bootstrap (far from
 * the maneuver and uncertain-draw streams). */
#define STREAM_SOBOL     0x5000000000000000ULL
#define STREAM_BOOTSTRAP 0x6000000000000000ULL
#define STREAM_MORRIS    0x7000000000000000ULL

/* ---- Sobol design -------------------------------------------------------------- */
void pom_sens_sobol_defaults(pom_sens_sobol_opts *o) {
  memset(o, 0, sizeof *o);
  o->dim = 1;
  o->n_base = 512;
  o->sampling = POM_SENS_QMC;
  o->seed = 1;
  o->bootstrap = 1000;
  o->confidence = 0.95;
}

long pom_sens_sobol_rows(const pom_sens_sobol_opts *o) {
  return o->n_base * (o->dim + 2);
}

static pom_status check_sobol(const pom_sens_sobol_opts *o, pom_error *err) {
  if (o->dim < 1 || o->dim > POM_SENS_MAX_DIM)
    POM_FAIL(err, POM_ERR_ARG, "sobol: %d inputs (expected 1 to %d)", o->dim, POM_SENS_MAX_DIM);
  if (o->n_base < 2) POM_FAIL(err, POM_ERR_ARG, "sobol: %ld base samples (at least 2)", o->n_base);
  if (o->bootstrap < 0 || !(o->confidence > 0 && o->confidence < 1))
    POM_FAIL(err, POM_ERR_ARG, "sobol: bootstrap %d, confidence %g", o->bootstrap, o->confidence);
  return POM_OK;
}

pom_status pom_sens_sobol_design(double *u, const pom_sens_sobol_opts *o, pom_error *err) {
  POM_TRY(check_sobol(o, err));
  int d = o->dim, w = d + 2;
  gsl_qrng *q = NULL;
  if (o->sampling == POM_SENS_QMC) {
    q = gsl_qrng_alloc(gsl_qrng_sobol, (unsigned int)(2 * d));
    if (!q) POM_FAIL(err, POM_ERR_GSL, "sobol: cannot make a %d-dimensional Sobol sequence", 2 * d);
  }
  double ab[2 * POM_SENS_MAX_DIM];
  /* the sequence starts at the corner 0 (no information): skip it */
  if (q) gsl_qrng_get(q, ab);
  for (long j = 0; j < o->n_base; ++j) {
    if (q) {
      gsl_qrng_get(q, ab);
    } else {
      pom_rng rng;
      pom_rng_seed(&rng, o->seed, STREAM_SOBOL + (uint64_t)j);
      for (int i = 0; i < 2 * d; ++i)
        ab[i] = pom_dist_u_from_bits(pom_rng_next(&rng));
    }
    double *blk = u + (size_t)j * (size_t)(w * d);
    for (int i = 0; i < d; ++i) {
      blk[i] = ab[i];         /* A */
      blk[d + i] = ab[d + i]; /* B */
    }
    for (int k = 0; k < d; ++k) /* AB_k: A with input k from B */
      for (int i = 0; i < d; ++i)
        blk[(2 + k) * d + i] = i == k ? ab[d + i] : ab[i];
  }
  gsl_qrng_free(q);
  return POM_OK;
}

/* ---- Sobol indices ---------------------------------------------------------------- */
/* Estimates from the base samples idx[n] (blocks of y). */
static void sobol_estimate(double *S1, double *ST, double *mean, double *var, const double *y,
                           const long *idx, long n, int d) {
  int w = d + 2;
  double s = 0, s2 = 0;
  for (long t = 0; t < n; ++t) {
    const double *b = y + idx[t] * w;
    s += b[0] + b[1];
  }
  double m = s / (2.0 * (double)n);
  for (long t = 0; t < n; ++t) {
    const double *b = y + idx[t] * w;
    s2 += (b[0] - m) * (b[0] - m) + (b[1] - m) * (b[1] - m);
  }
  double v = s2 / (2.0 * (double)n - 1.0);
  for (int i = 0; i < d; ++i) {
    double a1 = 0, at = 0;
    for (long t = 0; t < n; ++t) {
      const double *b = y + idx[t] * w;
      double fa = b[0] - m, fb = b[1] - m, fab = b[2 + i] - m;
      a1 += fb * (fab - fa);
      at += (fa - fab) * (fa - fab);
    }
    S1[i] = a1 / (double)n / v;
    ST[i] = at / (2.0 * (double)n) / v;
  }
  *mean = m;
  *var = v;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

pom_status pom_sens_sobol_indices(pom_sens_sobol_result *r, const double *y,
                                  const pom_sens_sobol_opts *o, pom_error *err) {
  POM_TRY(check_sobol(o, err));
  memset(r, 0, sizeof *r);
  int d = o->dim, w = d + 2;
  r->dim = d;
  r->confidence = o->confidence;
  pom_status st = POM_OK;
  long *ok = malloc((size_t)o->n_base * sizeof *ok), *pick = NULL;
  double *boot = NULL;
  if (!ok) POM_FAIL(err, POM_ERR_NOMEM, "sobol: out of memory");
  for (long j = 0; j < o->n_base; ++j) {
    int finite = 1;
    for (int k = 0; k < w; ++k)
      finite &= isfinite(y[j * w + k]);
    if (finite)
      ok[r->n_used++] = j;
    else
      ++r->n_failed;
  }
  if (r->n_used < 2)
    POM_FAIL_GOTO(err, POM_ERR_ARG, done, "sobol: %ld of %ld base samples usable (at least 2)",
                  r->n_used, o->n_base);
  sobol_estimate(r->S1, r->ST, &r->mean, &r->variance, y, ok, r->n_used, d);
  if (!(r->variance > 0))
    POM_FAIL_GOTO(err, POM_ERR_ARG, done, "sobol: the output does not vary (variance %g)",
                  r->variance);
  for (int i = 0; i < d; ++i)
    r->S1_low[i] = r->S1_high[i] = r->ST_low[i] = r->ST_high[i] = NAN;
  if (o->bootstrap > 0) {
    long n = r->n_used, nb = o->bootstrap;
    pick = malloc((size_t)n * sizeof *pick);
    boot = malloc((size_t)(nb * 2 * d) * sizeof *boot);
    if (!pick || !boot) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "sobol: out of memory");
    for (long b = 0; b < nb; ++b) {
      pom_rng rng;
      pom_rng_seed(&rng, o->seed, STREAM_BOOTSTRAP + (uint64_t)b);
      for (long t = 0; t < n; ++t)
        pick[t] = ok[(long)(pom_rng_uniform(&rng) * (double)n)];
      double S1[POM_SENS_MAX_DIM], ST[POM_SENS_MAX_DIM], m, v;
      sobol_estimate(S1, ST, &m, &v, y, pick, n, d);
      for (int i = 0; i < d; ++i) {
        boot[(2 * i) * nb + b] = S1[i];
        boot[(2 * i + 1) * nb + b] = ST[i];
      }
    }
    double lo = 0.5 * (1 - o->confidence), hi = 0.5 * (1 + o->confidence);
    for (int i = 0; i < d; ++i) {
      double *s1 = boot + (2 * i) * nb, *st_ = boot + (2 * i + 1) * nb;
      qsort(s1, (size_t)nb, sizeof *s1, cmp_double);
      qsort(st_, (size_t)nb, sizeof *st_, cmp_double);
      r->S1_low[i] = pom_doe_percentile(s1, (size_t)nb, lo);
      r->S1_high[i] = pom_doe_percentile(s1, (size_t)nb, hi);
      r->ST_low[i] = pom_doe_percentile(st_, (size_t)nb, lo);
      r->ST_high[i] = pom_doe_percentile(st_, (size_t)nb, hi);
    }
  }
done:
  free(ok);
  free(pick);
  free(boot);
  return st;
}

/* ---- Morris ------------------------------------------------------------------------- */
void pom_sens_morris_defaults(pom_sens_morris_opts *o) {
  memset(o, 0, sizeof *o);
  o->dim = 1;
  o->trajectories = 20;
  o->levels = 4;
  o->seed = 1;
}

long pom_sens_morris_rows(const pom_sens_morris_opts *o) {
  return o->trajectories * (o->dim + 1);
}

static pom_status check_morris(const pom_sens_morris_opts *o, pom_error *err) {
  if (o->dim < 1 || o->dim > POM_SENS_MAX_DIM)
    POM_FAIL(err, POM_ERR_ARG, "morris: %d inputs (expected 1 to %d)", o->dim, POM_SENS_MAX_DIM);
  if (o->trajectories < 2)
    POM_FAIL(err, POM_ERR_ARG, "morris: %ld trajectories (at least 2)", o->trajectories);
  if (o->levels < 2 || o->levels % 2)
    POM_FAIL(err, POM_ERR_ARG, "morris: %d levels (an even number >= 2)", o->levels);
  return POM_OK;
}

pom_status pom_sens_morris_design(double *u, const pom_sens_morris_opts *o, pom_error *err) {
  POM_TRY(check_morris(o, err));
  int d = o->dim, p = o->levels, half = p / 2;
  for (long t = 0; t < o->trajectories; ++t) {
    pom_rng rng;
    pom_rng_seed(&rng, o->seed, STREAM_MORRIS + (uint64_t)t);
    int level[POM_SENS_MAX_DIM], order[POM_SENS_MAX_DIM];
    for (int i = 0; i < d; ++i) {
      level[i] = (int)(pom_rng_uniform(&rng) * p);
      order[i] = i;
    }
    for (int i = d - 1; i > 0; --i) { /* Fisher-Yates */
      int j = (int)(pom_rng_uniform(&rng) * (i + 1));
      int tmp = order[i];
      order[i] = order[j];
      order[j] = tmp;
    }
    double *blk = u + (size_t)t * (size_t)((d + 1) * d);
    for (int s = 0; s <= d; ++s) {
      if (s > 0) {
        int i = order[s - 1]; /* jump half the grid, up or down, staying on it */
        level[i] = level[i] < half ? level[i] + half : level[i] - half;
      }
      for (int i = 0; i < d; ++i)
        blk[s * d + i] = (level[i] + 0.5) / p;
    }
  }
  return POM_OK;
}

pom_status pom_sens_morris_effects(pom_sens_morris_result *r, const double *u, const double *y,
                                   const pom_sens_morris_opts *o, pom_error *err) {
  POM_TRY(check_morris(o, err));
  memset(r, 0, sizeof *r);
  int d = o->dim;
  r->dim = d;
  double s[POM_SENS_MAX_DIM] = {0}, sa[POM_SENS_MAX_DIM] = {0}, s2[POM_SENS_MAX_DIM] = {0};
  for (long t = 0; t < o->trajectories; ++t) {
    const double *ub = u + (size_t)t * (size_t)((d + 1) * d), *yb = y + t * (d + 1);
    for (int step = 1; step <= d; ++step) {
      int i = 0; /* the input that moved */
      while (i < d && ub[step * d + i] == ub[(step - 1) * d + i])
        ++i;
      if (i == d)
        POM_FAIL(err, POM_ERR_ARG, "morris: trajectory %ld step %d moves no input", t, step);
      if (!isfinite(yb[step]) || !isfinite(yb[step - 1])) continue;
      double ee = (yb[step] - yb[step - 1]) / (ub[step * d + i] - ub[(step - 1) * d + i]);
      s[i] += ee;
      sa[i] += fabs(ee);
      s2[i] += ee * ee;
      ++r->n_effects[i];
    }
  }
  long usable = 0;
  for (int i = 0; i < d; ++i)
    usable += r->n_effects[i];
  if (usable == 0)
    POM_FAIL(err, POM_ERR_ARG,
             "morris: 0 usable elementary effects (every step of the %ld trajectories touches a "
             "failed run)",
             o->trajectories);
  for (int i = 0; i < d; ++i) {
    double n = (double)r->n_effects[i];
    r->mu[i] = n > 0 ? s[i] / n : NAN;
    r->mu_star[i] = n > 0 ? sa[i] / n : NAN;
    r->sigma[i] = n > 1 ? sqrt(fmax(0.0, (s2[i] - n * r->mu[i] * r->mu[i]) / (n - 1))) : NAN;
  }
  return POM_OK;
}

/* ---- with a callback ------------------------------------------------------------------ */
pom_status pom_sens_sobol_run(pom_sens_sobol_result *r, pom_sens_fn f, void *user,
                              const pom_sens_sobol_opts *o, pom_error *err) {
  POM_TRY(check_sobol(o, err));
  long rows = pom_sens_sobol_rows(o);
  double *u = malloc((size_t)(rows * o->dim) * sizeof *u), *y = malloc((size_t)rows * sizeof *y);
  pom_status st = POM_OK;
  if (!u || !y) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "sobol: out of memory");
  POM_TRY_GOTO(pom_sens_sobol_design(u, o, err), done);
  for (long k = 0; k < rows; ++k)
    y[k] = f(u + k * o->dim, user);
  st = pom_sens_sobol_indices(r, y, o, err);
done:
  free(u);
  free(y);
  return st;
}

pom_status pom_sens_morris_run(pom_sens_morris_result *r, pom_sens_fn f, void *user,
                               const pom_sens_morris_opts *o, pom_error *err) {
  POM_TRY(check_morris(o, err));
  long rows = pom_sens_morris_rows(o);
  double *u = malloc((size_t)(rows * o->dim) * sizeof *u), *y = malloc((size_t)rows * sizeof *y);
  pom_status st = POM_OK;
  if (!u || !y) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "morris: out of memory");
  POM_TRY_GOTO(pom_sens_morris_design(u, o, err), done);
  for (long k = 0; k < rows; ++k)
    y[k] = f(u + k * o->dim, user);
  st = pom_sens_morris_effects(r, u, y, o, err);
done:
  free(u);
  free(y);
  return st;
}
