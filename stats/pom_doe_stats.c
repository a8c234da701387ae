/* pom_doe_stats.c - descriptive statistics, t interval, Wilcoxon signed-rank
 * test (docs/results.md, "Statistics"). */
#include "pom_stats.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Largest n for the exact Wilcoxon distribution: 2^n subset counts stay exact
 * in a double up to 2^53, and n (n + 1) / 2 + 1 sums fit the table below. */
#define WILCOXON_EXACT_MAX 50

/* ---- descriptive ---------------------------------------------------------- */
static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

double pom_doe_percentile(const double *sorted, size_t n, double p) {
  if (n == 0) return NAN;
  if (p <= 0) return sorted[0];
  if (p >= 1) return sorted[n - 1];
  double h = (double)(n - 1) * p;
  size_t lo = (size_t)floor(h);
  if (lo + 1 >= n) return sorted[n - 1];
  return sorted[lo] + (h - (double)lo) * (sorted[lo + 1] - sorted[lo]);
}

void pom_doe_stats_compute(pom_doe_stats *s, const double *x, size_t n, double *sorted) {
  s->n = (long)n;
  if (n == 0) {
    s->max = s->mean = s->min = s->sigma = s->median = NAN;
    s->p05 = s->p25 = s->p75 = s->p95 = NAN;
    return;
  }
  if (sorted != x) memcpy(sorted, x, n * sizeof *x);
  qsort(sorted, n, sizeof *sorted, cmp_double);
  /* two-pass mean and variance: the second pass on deviations avoids the
   * cancellation of the sum-of-squares formula */
  double sum = 0;
  for (size_t k = 0; k < n; ++k)
    sum += sorted[k];
  double mean = sum / (double)n;
  double ss = 0;
  for (size_t k = 0; k < n; ++k)
    ss += (sorted[k] - mean) * (sorted[k] - mean);
  s->mean = mean;
  s->sigma = n > 1 ? sqrt(ss / (double)(n - 1)) : NAN;
  s->min = sorted[0];
  s->max = sorted[n - 1];
  s->median = pom_doe_percentile(sorted, n, 0.50);
  s->p05 = pom_doe_percentile(sorted, n, 0.05);
  s->p25 = pom_doe_percentile(sorted, n, 0.25);
  s->p75 = pom_doe_percentile(sorted, n, 0.75);
  s->p95 = pom_doe_percentile(sorted, n, 0.95);
}

void pom_doe_stats_flatten(double out[POM_DOE_STATS_FIELDS], const pom_doe_stats *s) {
  out[0] = (double)s->n;
  out[1] = s->max;
  out[2] = s->mean;
  out[3] = s->min;
  out[4] = s->sigma;
  out[5] = s->median;
  out[6] = s->p05;
  out[7] = s->p25;
  out[8] = s->p75;
  out[9] = s->p95;
}

/* ---- Wilcoxon signed-rank --------------------------------------------------- */
static int cmp_abs(const void *a, const void *b) {
  double x = fabs(*(const double *)a), y = fabs(*(const double *)b);
  return (x > y) - (x < y);
}

/* Exact two-sided p of W+ = w for n non-zero, untied differences: counts of
 * rank subsets with each sum by dynamic programming over the ranks 1..n. */
static double wilcoxon_exact_p(double w, long n) {
  double count[WILCOXON_EXACT_MAX * (WILCOXON_EXACT_MAX + 1) / 2 + 1];
  long max_sum = n * (n + 1) / 2;
  for (long s = 0; s <= max_sum; ++s)
    count[s] = 0;
  count[0] = 1;
  for (long r = 1; r <= n; ++r)
    for (long s = r * (r + 1) / 2; s >= r; --s)
      count[s] += count[s - r];
  double total = ldexp(1.0, (int)n);
  long wi = (long)llround(w);
  double lower = 0, upper = 0;
  for (long s = 0; s <= max_sum; ++s) {
    if (s <= wi) lower += count[s];
    if (s >= wi) upper += count[s];
  }
  double p = 2.0 * fmin(lower, upper) / total;
  return p > 1.0 ? 1.0 : p;
}

double pom_doe_wilcoxon(const double *d, size_t n, double *w, long *n_used, double *scratch) {
  size_t m = 0;
  for (size_t k = 0; k < n; ++k)
    if (d[k] != 0.0) scratch[m++] = d[k];
  *n_used = (long)m;
  *w = 0;
  if (m == 0) return 1.0;
  qsort(scratch, m, sizeof *scratch, cmp_abs);
  /* average ranks over ties of |d|; tie_term = sum (t^3 - t) for the variance */
  double wplus = 0, tie_term = 0;
  int ties = 0;
  for (size_t i = 0; i < m;) {
    size_t j = i + 1;
    while (j < m && fabs(scratch[j]) == fabs(scratch[i]))
      ++j;
    double rank = 0.5 * (double)(i + 1 + j); /* mean of ranks i+1 .. j */
    double t = (double)(j - i);
    if (j - i > 1) {
      ties = 1;
      tie_term += t * t * t - t;
    }
    for (size_t k = i; k < j; ++k)
      if (scratch[k] > 0) wplus += rank;
    i = j;
  }
  *w = wplus;
  if (!ties && m <= WILCOXON_EXACT_MAX) return wilcoxon_exact_p(wplus, (long)m);
  double nm = (double)m;
  double mean = nm * (nm + 1) / 4.0;
  double var = nm * (nm + 1) * (2 * nm + 1) / 24.0 - tie_term / 48.0;
  if (var <= 0) return 1.0;
  double z = (wplus - mean) / sqrt(var);
  return erfc(fabs(z) / sqrt(2.0));
}

/* ---- paired comparison ------------------------------------------------------- */
void pom_doe_paired_compute(pom_doe_paired *out, const double *a, const double *b, size_t n,
                            double level, double *scratch) {
  double *d = scratch;
  memset(out, 0, sizeof *out);
  out->n = (long)n;
  double sum = 0, wins = 0, ties = 0;
  for (size_t k = 0; k < n; ++k) {
    d[k] = a[k] - b[k];
    sum += d[k];
    wins += a[k] < b[k];
    ties += a[k] == b[k];
  }
  if (n == 0) {
    out->mean_diff = out->ci_low = out->ci_high = NAN;
    out->wilcoxon_p = 1.0;
    out->win_fraction = out->tie_fraction = NAN;
    return;
  }
  double mean = sum / (double)n;
  out->mean_diff = mean;
  out->win_fraction = wins / (double)n;
  out->tie_fraction = ties / (double)n;
  if (n >= 2) {
    double ss = 0;
    for (size_t k = 0; k < n; ++k)
      ss += (d[k] - mean) * (d[k] - mean);
    double se = sqrt(ss / (double)(n - 1) / (double)n);
    double t = gsl_cdf_tdist_Pinv(0.5 + 0.5 * level, (double)(n - 1));
    out->ci_low = mean - t * se;
    out->ci_high = mean + t * se;
  } else {
    out->ci_low = out->ci_high = NAN;
  }
  out->wilcoxon_p = pom_doe_wilcoxon(d, n, &out->wilcoxon_w, &out->n_nonzero, d + n);
}

/* ---- Friedman ----------------------------------------------------------------------- */
/* (value, index) pairs sorted by value */
static int cmp_pair(const void *a, const void *b) {
  const double *x = a, *y = b;
  return (x[0] > y[0]) - (x[0] < y[0]);
}

double pom_doe_rank_average(double *rank, const double *x, int k, double *scratch) {
  for (int j = 0; j < k; ++j) {
    scratch[2 * j] = x[j];
    scratch[2 * j + 1] = (double)j;
  }
  qsort(scratch, (size_t)k, 2 * sizeof *scratch, cmp_pair);
  double tie_term = 0;
  for (int i = 0; i < k;) {
    int j = i + 1;
    while (j < k && scratch[2 * j] == scratch[2 * i])
      ++j;
    double r = 0.5 * (double)(i + 1 + j), t = (double)(j - i);
    tie_term += t * t * t - t;
    for (int m = i; m < j; ++m)
      rank[(int)scratch[2 * m + 1]] = r;
    i = j;
  }
  return tie_term;
}

void pom_doe_friedman_from_ranks(pom_doe_friedman_result *out, const double *rank_sum, int k,
                                 long n, double tie_sum) {
  out->n_blocks = n;
  out->k = k;
  out->df = k - 1;
  out->statistic = NAN;
  out->p = 1.0;
  if (n < 1 || k < 2) return;
  double nk = (double)n * (double)k, ss = 0;
  for (int j = 0; j < k; ++j)
    ss += rank_sum[j] * rank_sum[j];
  double c = 1.0 - tie_sum / (nk * ((double)k * (double)k - 1.0));
  if (!(c > 0)) return; /* every block all ties: no evidence of any difference */
  double q = (12.0 / (nk * (double)(k + 1)) * ss - 3.0 * (double)n * (double)(k + 1)) / c;
  out->statistic = q < 0 ? 0 : q; /* rounding of an exact 0 */
  out->p = gsl_cdf_chisq_Q(out->statistic, out->df);
}

void pom_doe_friedman(pom_doe_friedman_result *out, const double *x, long n, int k,
                      double *scratch) {
  double *rank_sum = scratch, *rank = scratch + k, *pairs = scratch + 2 * k;
  double tie_sum = 0;
  for (int j = 0; j < k; ++j)
    rank_sum[j] = 0;
  for (long b = 0; b < n; ++b) {
    tie_sum += pom_doe_rank_average(rank, x + b * k, k, pairs);
    for (int j = 0; j < k; ++j)
      rank_sum[j] += rank[j];
  }
  pom_doe_friedman_from_ranks(out, rank_sum, k, n, tie_sum);
}

/* ---- Holm --------------------------------------------------------------------------- */
void pom_doe_holm(double *adjusted, const double *p, size_t m, size_t *order) {
  for (size_t i = 0; i < m; ++i)
    order[i] = i;
  /* insertion sort by p (stable; qsort would need the p values as global
   * context); m is the number of comparisons, a few thousand at most */
  for (size_t i = 1; i < m; ++i) {
    size_t v = order[i], j = i;
    while (j > 0 && p[order[j - 1]] > p[v]) {
      order[j] = order[j - 1];
      --j;
    }
    order[j] = v;
  }
  double running = 0;
  for (size_t i = 0; i < m; ++i) {
    double a = (double)(m - i) * p[order[i]];
    if (a > 1) a = 1;
    if (a > running) running = a;
    adjusted[order[i]] = running;
  }
}
