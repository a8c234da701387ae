/* pom_doe_effects.c - main effects of a sweep's factors and the Pareto front
 * of time against energy (docs/results.md, "Many candidates"). */
#include "stats_internal.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* More distinct values than this (a Latin hypercube) are grouped into this
 * many equal-width bins of the factor's range. */
#define MAX_PLAIN_LEVELS 12
#define BINS             8

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int pom_doe_factor_levels(const pom_doe_study *study, int f, int *level_of, double *lo,
                          double *hi) {
  int nc = study->n_candidates, n = 0;
  double *v = malloc((size_t)(nc ? nc : 1) * sizeof *v);
  if (!v) return -1;
  for (int c = 0; c < nc; ++c)
    v[c] = study->candidates[c].factor_value[f];
  qsort(v, (size_t)nc, sizeof *v, cmp_double);
  for (int c = 0; c < nc; ++c)
    if (c == 0 || v[c] != v[n - 1]) v[n++] = v[c];
  if (n <= MAX_PLAIN_LEVELS) {
    for (int l = 0; l < n; ++l)
      lo[l] = hi[l] = v[l];
    for (int c = 0; c < nc; ++c) {
      double x = study->candidates[c].factor_value[f];
      for (int l = 0; l < n; ++l)
        if (x == v[l]) level_of[c] = l;
    }
  } else {
    double a = v[0], w = (v[n - 1] - v[0]) / BINS;
    for (int l = 0; l < BINS; ++l) {
      lo[l] = a + l * w;
      hi[l] = l + 1 < BINS ? a + (l + 1) * w : v[n - 1];
    }
    for (int c = 0; c < nc; ++c) {
      int l = (int)((study->candidates[c].factor_value[f] - a) / w);
      level_of[c] = l < 0 ? 0 : (l >= BINS ? BINS - 1 : l);
    }
    n = BINS;
  }
  free(v);
  return n;
}

/* One level's effect: y_k = mean over the level's candidates that can use
 * maneuver k, then the mean of y_k over the maneuvers and its t interval
 * (maneuvers are the independent replicates; averaging inside a maneuver
 * keeps the common random numbers paired). y: m doubles of scratch. */
static void level_effect(pom_doe_effect *e, const pom_doe_cell *cells, size_t m,
                         const int *level_of, int nc, double confidence, double *y) {
  long n = 0;
  double sum = 0;
  for (size_t k = 0; k < m; ++k) {
    double s = 0;
    int cnt = 0;
    for (int c = 0; c < nc; ++c) {
      const pom_doe_cell *cell = &cells[(size_t)c * m + k];
      if (level_of[c] != e->level || !pom_doe_cell_usable(cell, e->metric)) continue;
      s += pom_doe_cell_value(cell, e->metric);
      e->n_censored += e->metric == POM_DOE_METRIC_TIME && cell->censored;
      ++cnt;
    }
    if (!cnt) continue;
    y[n] = s / cnt;
    sum += y[n++];
  }
  e->n = n;
  e->mean = n ? sum / (double)n : NAN;
  e->ci_low = e->ci_high = NAN;
  if (n >= 2) {
    double ss = 0;
    for (long k = 0; k < n; ++k)
      ss += (y[k] - e->mean) * (y[k] - e->mean);
    double half = gsl_cdf_tdist_Pinv(0.5 + 0.5 * confidence, (double)(n - 1)) *
                  sqrt(ss / (double)(n - 1) / (double)n);
    e->ci_low = e->mean - half;
    e->ci_high = e->mean + half;
  }
}

pom_status pom_doe_effects_compute(pom_doe_report *rep, const pom_doe_study *study,
                                   const pom_doe_cell *cells, pom_error *err) {
  int nc = study->n_candidates, nf = study->n_factors;
  size_t m = (size_t)study->maneuvers.count;
  pom_status st = POM_OK;
  int *level_of = malloc((size_t)(nc ? nc : 1) * sizeof *level_of);
  double *lo = malloc((size_t)(nc ? nc : 1) * sizeof *lo);
  double *hi = malloc((size_t)(nc ? nc : 1) * sizeof *hi);
  double *y = malloc((m ? m : 1) * sizeof *y);
  rep->effects = calloc((size_t)(2 * nf * (nc > BINS ? nc : BINS) + 1), sizeof *rep->effects);
  rep->pareto = calloc((size_t)(nc ? nc : 1), sizeof *rep->pareto);
  if (!level_of || !lo || !hi || !y || !rep->effects || !rep->pareto)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "effects: out of memory");
  rep->n_effects = 0;
  for (int f = 0; f < nf; ++f) {
    int nl = pom_doe_factor_levels(study, f, level_of, lo, hi);
    if (nl < 0) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "effects: out of memory");
    for (int metric = 0; metric < 2; ++metric)
      for (int l = 0; l < nl; ++l) {
        pom_doe_effect *e = &rep->effects[rep->n_effects++];
        e->factor = f;
        e->level = l;
        e->lo = lo[l];
        e->hi = hi[l];
        e->metric = (pom_doe_metric)metric;
        for (int c = 0; c < nc; ++c)
          e->n_candidates += level_of[c] == l;
        level_effect(e, cells, m, level_of, nc, study->confidence, y);
      }
  }
  /* the capability figures (study.capability): every candidate, competing or not */
  if (study->capability_n > 0) {
    rep->cap_effects = calloc((size_t)(nf * study->capability_n * (nc > BINS ? nc : BINS) + 1),
                              sizeof *rep->cap_effects);
    if (!rep->cap_effects) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "effects: out of memory");
  }
  rep->n_cap_effects = 0;
  for (int f = 0; f < nf && study->capability_n > 0; ++f) {
    int nl = pom_doe_factor_levels(study, f, level_of, lo, hi);
    if (nl < 0) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "effects: out of memory");
    for (int i = 0; i < POM_CAP_N_FIGURES; ++i) {
      if (!study->capability_want[i]) continue;
      for (int l = 0; l < nl; ++l) {
        pom_doe_cap_effect *e = &rep->cap_effects[rep->n_cap_effects++];
        e->factor = f;
        e->level = l;
        e->lo = lo[l];
        e->hi = hi[l];
        e->figure = i;
        e->min = INFINITY;
        e->max = -INFINITY;
        double sum = 0;
        for (int c = 0; c < nc; ++c) {
          if (level_of[c] != l) continue;
          ++e->n_candidates;
          const pom_doe_candidate *cand = &study->candidates[c];
          double v = cand->capability_done ? cand->capability[i] : NAN;
          if (!isfinite(v)) continue;
          ++e->n;
          sum += v;
          e->min = fmin(e->min, v);
          e->max = fmax(e->max, v);
        }
        e->mean = e->n ? sum / e->n : NAN;
        if (!e->n) e->min = e->max = NAN;
      }
    }
  }
  /* Pareto front of the common-maneuver means: c is on it when no other
   * candidate is at least as good on both and better on one */
  for (int c = 0; c < nc; ++c) {
    double t = rep->mean_time[c], e = rep->mean_energy[c];
    int dominated = !isfinite(t) || !isfinite(e);
    for (int d = 0; d < nc && !dominated; ++d) {
      double td = rep->mean_time[d], ed = rep->mean_energy[d];
      dominated = d != c && td <= t && ed <= e && (td < t || ed < e);
    }
    rep->pareto[c] = !dominated;
  }
done:
  free(level_of);
  free(lo);
  free(hi);
  free(y);
  return st;
}
