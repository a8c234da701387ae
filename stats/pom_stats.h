/* pom_stats.h - what a study's rows say: descriptive statistics and paired
 * comparisons (pom_doe_stats.c), the per-candidate statistics, comparisons,
 * ranking and Friedman test of the report (pom_doe_report.c) and the main
 * effects of sweep factors with the Pareto front (pom_doe_effects.c);
 * definitions: docs/results.md, "Statistics".
 *
 * Pure computation on rows (rows/pom_rows.h) and the study
 * (study/pom_study.h): nothing here reads or writes a file. The descriptive
 * functions take caller-owned arrays and explicit scratch and never
 * allocate; NaN inputs are the caller's business: filter them out first. */
#ifndef POM_STATS_H
#define POM_STATS_H

#include "pom_rows.h"
#include "pom_status.h"
#include "pom_study.h"

#include <stddef.h>

/* Summary of n values. With n == 0 every field but n is NaN; with n == 1
 * sigma is NaN (the sample standard deviation needs two values). */
typedef struct {
  long n;        /* number of values */
  double max;    /* largest value */
  double mean;   /* arithmetic mean */
  double min;    /* smallest value */
  double sigma;  /* sample standard deviation (divisor n - 1) */
  double median; /* 50th percentile */
  double p05;    /* 5th percentile (linear interpolation between order statistics, "type 7") */
  double p25;    /* 25th percentile */
  double p75;    /* 75th percentile */
  double p95;    /* 95th percentile */
} pom_doe_stats;

/* Number of doubles in the flat form of pom_doe_stats (for tables/files). */
#define POM_DOE_STATS_FIELDS 10

/* Computes the summary of x[0..n-1]; sorted receives the values sorted
 * ascending (n doubles of scratch; may be x itself to sort in place). */
void pom_doe_stats_compute(pom_doe_stats *s, const double *x, size_t n, double *sorted);

/* Flattens s into out[POM_DOE_STATS_FIELDS] in the order n, max, mean, min,
 * sigma, median, p05, p25, p75, p95. */
void pom_doe_stats_flatten(double out[POM_DOE_STATS_FIELDS], const pom_doe_stats *s);

/* Percentile p in [0, 1] of ascending sorted[0..n-1] by linear interpolation
 * between order statistics at h = (n - 1) p (NaN for n == 0). */
double pom_doe_percentile(const double *sorted, size_t n, double p);

/* Paired comparison of a and b on the same n maneuvers, d_k = a_k - b_k. */
typedef struct {
  long n;            /* pairs */
  double mean_diff;  /* mean of d */
  double ci_low;     /* lower end of the two-sided t interval for the mean of d */
  double ci_high;    /* upper end */
  double wilcoxon_w; /* Wilcoxon signed-rank statistic W+ (sum of ranks of positive d) */
  double wilcoxon_p; /* two-sided p (exact for <= 50 non-zero d without ties, else normal approx) */
  long n_nonzero;    /* pairs with d != 0 (the Wilcoxon test uses these) */
  double win_fraction; /* fraction of pairs with a < b (strictly) */
  double tie_fraction; /* fraction of pairs with a == b */
} pom_doe_paired;

/* Compares a and b (n each) with confidence `level` (e.g. 0.95) for the
 * interval. scratch must hold 3 n doubles. With n < 2 the interval is NaN;
 * with no non-zero difference p = 1. */
void pom_doe_paired_compute(pom_doe_paired *out, const double *a, const double *b, size_t n,
                            double level, double *scratch);

/* Two-sided Wilcoxon signed-rank test of the differences d[0..n-1] (zeros
 * dropped, average ranks for ties). *w gets W+, *n_used the non-zero count.
 * scratch must hold 2 n doubles. Returns the p value. */
double pom_doe_wilcoxon(const double *d, size_t n, double *w, long *n_used, double *scratch);

/* Average ranks 1..k of x[0..k-1] into rank[k] (ties get the mean of the
 * ranks they span). scratch must hold 2 k doubles. Returns the tie term
 * sum over groups of tied values of (t^3 - t). */
double pom_doe_rank_average(double *rank, const double *x, int k, double *scratch);

/* Friedman test of k treatments on n blocks. */
typedef struct {
  long n_blocks;    /* blocks (maneuvers every candidate completed) */
  int k;            /* treatments (candidates) */
  double statistic; /* chi-square statistic, tie-corrected; NaN when undefined */
  double df;        /* degrees of freedom k - 1 */
  double p;         /* upper tail of chi-square(k - 1); 1 when every block is all ties */
} pom_doe_friedman_result;

/* Friedman's statistic from the rank sums rank_sum[k] of n blocks (ranks
 * within each block by pom_doe_rank_average) and the tie term summed over
 * the blocks: Q = (12 / (n k (k + 1)) sum R_j^2 - 3 n (k + 1)) / C with
 * C = 1 - tie_sum / (n k (k^2 - 1)) (as scipy.stats.friedmanchisquare);
 * p from the chi-square distribution with k - 1 degrees of freedom. With
 * n < 1 or k < 2 the statistic is NaN and p = 1. */
void pom_doe_friedman_from_ranks(pom_doe_friedman_result *out, const double *rank_sum, int k,
                                 long n, double tie_sum);

/* The Friedman test of x[b * k + j] (n blocks of k values, block-major).
 * scratch must hold 4 k doubles. */
void pom_doe_friedman(pom_doe_friedman_result *out, const double *x, long n, int k,
                      double *scratch);

/* Holm's step-down adjustment of m p values: sorted ascending p_(1..m),
 * adjusted p_(i) = max over j <= i of min(1, (m - j + 1) p_(j)), written
 * back in the order of p. order must hold m size_t of scratch. */
void pom_doe_holm(double *adjusted, const double *p, size_t m, size_t *order);

/* ---- report -------------------------------------------------------------------- */
#define POM_DOE_STAT_IGNORE_(...)
#define POM_DOE_STAT_FIELD_(name, type, n, unit, descr, over, combine, stat, key)                  \
  pom_doe_stats stat;
/* Statistics of one candidate: one pom_doe_stats per reduced metric of
 * POM_DYN_METRICS_LIST, by name (execution_time, energy, energy_positive,
 * execution_time_final, ...) or as stat[pom_dyn_stat_id]. */
typedef struct {
  long n_done;        /* maneuvers finished */
  long n_failed;      /* status != ok */
  long n_unsettled;   /* ok but some actuator never settled */
  long n_censored;    /* ok but the primary time metric did not settle within the horizon: its
                         value is censored at the horizon (docs/results.md section 4) */
  long n_validity;    /* ok maneuvers whose parasitic model's validity was measured (0 on rigid
                         joints) */
  long n_rigid_limit; /* of those, flagged not at the rigid limit (docs/dynamics.md 13b) */
  union {
    pom_doe_stats stat[POM_DYN_N_STATS];
    struct {
      POM_DYN_METRICS_LIST(POM_DOE_STAT_IGNORE_, POM_DOE_STAT_FIELD_)
    };
  };
} pom_doe_candidate_stats;

typedef struct {
  int a, b;              /* candidate indices; differences are a - b (a < b when every pair is
                            compared, a = the metric's best candidate otherwise) */
  pom_doe_metric metric; /* which response */
  pom_doe_paired test;   /* on maneuvers where both are ok; an unsettled time counts censored at
                            its horizon */
  long censored_a;       /* time: pairs in which a's value is censored (0 for energy) */
  long censored_b;       /* time: pairs in which b's value is censored */
  double p_holm;         /* Wilcoxon p adjusted by Holm over the comparisons of this metric */
} pom_doe_comparison;

/* The main effect of one level of a sweep factor on one response: per
 * maneuver, the mean over the level's candidates that can use it; then the
 * mean over the maneuvers and its t interval (study.confidence). */
typedef struct {
  int factor;            /* index into study->factor_key */
  int level;             /* 0-based, ascending factor values */
  double lo, hi;         /* factor values of the level (equal unless binned) */
  int n_candidates;      /* candidates at this level */
  pom_doe_metric metric; /* response */
  long n;                /* maneuvers averaged */
  long n_censored;       /* time: censored values among those averaged */
  double mean;           /* SI (s or J) */
  double ci_low, ci_high;
} pom_doe_effect;

/* The main effect of one level of a sweep factor on a capability figure
 * (study.capability; capability/pom_cap_figures.h): one value per candidate,
 * deterministic, so the mean over the level's candidates where the figure
 * was computed and their range (no interval: nothing is sampled). */
typedef struct {
  int factor;       /* index into study->factor_key */
  int level;        /* 0-based, ascending factor values */
  double lo, hi;    /* factor values of the level (equal unless binned) */
  int n_candidates; /* candidates at this level */
  int figure;       /* pom_cap_figure_id */
  int n;            /* of those, with the figure computed (finite) */
  double mean;      /* SI (the figure's unit); NaN when n = 0 */
  double min, max;  /* over those n candidates */
} pom_doe_cap_effect;

/* Up to this many candidates every pair is compared; beyond, the best of
 * each metric against each other one (docs/results.md, section 4). */
#define POM_DOE_ALL_PAIRS_MAX 4

typedef struct {
  int n_candidates;
  long n_maneuvers;
  pom_doe_candidate_stats *cand; /* [n_candidates] */
  /* Which candidates compete (docs/results.md section 4, "Requirements"): with
   * study.capability_require, only those meeting every requirement; the
   * others are excluded from the comparisons, the Friedman test, the ranking,
   * the verdict, the Pareto front and the heat map (their statistics and the
   * main effects keep them). Without requirements, every candidate. */
  int *ranked;   /* [n_candidates] 1: competes; 0: excluded by a requirement */
  int n_ranked;  /* candidates that compete (0: none meets the requirements, nothing ranked) */
  int all_pairs; /* 1: every pair compared; 0: the best against each other */
  int n_comparisons;
  pom_doe_comparison *cmp;             /* [n_comparisons]: both metrics */
  pom_doe_friedman_result friedman[2]; /* per pom_doe_metric, over the common maneuvers */
  long friedman_censored;              /* censored time values among the Friedman blocks */
  int *rank_time;        /* [n_candidates] candidate indices, best (lowest mean) first: the
                            n_ranked competing ones, then the excluded ones in index order */
  int *rank_energy;      /* [n_candidates] */
  double *mean_time;     /* [n_candidates] mean primary time over the common maneuvers (those
                            every competing candidate completed), unsettled ones censored at
                            the horizon: the restricted mean (s); NaN when excluded */
  long *censored_common; /* [n_candidates] censored times among the common maneuvers */
  double *mean_energy;   /* [n_candidates] mean expended energy over the common maneuvers (J) */
  double alpha;          /* level used for "significant" */
  int n_effects;
  pom_doe_effect *effects; /* [n_effects] main effects: factor-major, then metric, then level */
  int *pareto;             /* [n_candidates] 1 on the Pareto front of (mean_time, mean_energy) */
  int n_cap_effects;
  pom_doe_cap_effect *cap_effects; /* [n_cap_effects] the asked capability figures' main effects:
                                      factor-major, then figure, then level; every candidate */
} pom_doe_report;

/* The levels of sweep factor f: its distinct values (ascending) when there
 * are at most 12, else 8 equal-width bins of its range (a Latin hypercube).
 * level_of[c] gets each candidate's level, lo/hi[l] (n_candidates doubles
 * each) the level's value range. Returns the number of levels, -1 when out
 * of memory. */
int pom_doe_factor_levels(const pom_doe_study *study, int f, int *level_of, double *lo, double *hi);

void pom_doe_report_destroy(pom_doe_report *r);

/* 1 when candidate c of study competes in the ranking: no
 * study.capability_require, or its figures computed and every requirement
 * met (a figure not computed meets none). */
int pom_doe_candidate_competes(const pom_doe_study *study, int c);

/* Report from cells[c * count + k] (c candidates, count maneuvers each). */
pom_status pom_doe_report_compute(pom_doe_report **out, const pom_doe_study *study,
                                  const pom_doe_cell *cells, pom_error *err);

#endif
