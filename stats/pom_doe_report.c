/* pom_doe_report.c - per-candidate statistics, paired comparisons and the
 * ranking (docs/results.md, "Statistics"). */
#include "stats_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pom_doe_report_destroy(pom_doe_report *r) {
  if (!r) return;
  free(r->cand);
  free(r->cmp);
  free(r->rank_time);
  free(r->rank_energy);
  free(r->mean_time);
  free(r->mean_energy);
  free(r->censored_common);
  free(r->effects);
  free(r->pareto);
  free(r->ranked);
  free(r->cap_effects);
  free(r);
}

/* Ranking by the mean over the maneuvers usable for every candidate (the
 * common set), so every candidate is judged on the same maneuvers. */
typedef struct {
  int index;
  double mean;
  long bad; /* failed + censored: tie-break */
} rank_item;

static int cmp_rank(const void *a, const void *b) {
  const rank_item *x = a, *y = b;
  if (x->mean != y->mean) {
    if (isnan(x->mean)) return 1;
    if (isnan(y->mean)) return -1;
    return x->mean < y->mean ? -1 : 1;
  }
  if (x->bad != y->bad) return x->bad < y->bad ? -1 : 1;
  return x->index - y->index;
}

static void rank(int *order, double *means, long *censored, const pom_doe_study *study,
                 const pom_doe_report *rep, const pom_doe_cell *cells, pom_doe_metric metric,
                 const int *idx, rank_item *items) {
  int nc = study->n_candidates, nr = rep->n_ranked;
  long m = study->maneuvers.count;
  for (int c = 0; c < nc; ++c) {
    means[c] = NAN;
    if (censored) censored[c] = 0;
  }
  for (int i = 0; i < nr; ++i) {
    items[i].index = idx[i];
    items[i].bad = rep->cand[idx[i]].n_failed + rep->cand[idx[i]].n_censored;
    items[i].mean = 0;
  }
  long n = 0;
  for (long k = 0; k < m; ++k) {
    int all = 1;
    for (int i = 0; i < nr && all; ++i)
      all = pom_doe_cell_usable(&cells[(size_t)idx[i] * (size_t)m + (size_t)k], metric);
    if (!all) continue;
    ++n;
    for (int i = 0; i < nr; ++i) {
      const pom_doe_cell *cell = &cells[(size_t)idx[i] * (size_t)m + (size_t)k];
      items[i].mean += pom_doe_cell_value(cell, metric);
      if (censored) censored[idx[i]] += cell->censored;
    }
  }
  for (int i = 0; i < nr; ++i) {
    items[i].mean = n ? items[i].mean / (double)n : NAN;
    means[idx[i]] = items[i].mean;
  }
  qsort(items, (size_t)nr, sizeof *items, cmp_rank);
  for (int i = 0; i < nr; ++i)
    order[i] = items[i].index;
  for (int c = 0, r = nr; c < nc; ++c) /* the excluded ones last, in index order */
    if (!rep->ranked[c]) order[r++] = c;
}

/* The paired comparison of candidates x and y (differences x - y) on the
 * maneuvers both can use; a, b: m values of scratch, scratch 3 m. */
static void compare(pom_doe_comparison *out, const pom_doe_cell *cells, size_t m, int x, int y,
                    pom_doe_metric metric, double confidence, double *a, double *b,
                    double *scratch) {
  size_t n = 0;
  out->censored_a = out->censored_b = 0;
  for (size_t k = 0; k < m; ++k) {
    const pom_doe_cell *u = &cells[(size_t)x * m + k], *v = &cells[(size_t)y * m + k];
    if (!pom_doe_cell_usable(u, metric) || !pom_doe_cell_usable(v, metric)) continue;
    a[n] = pom_doe_cell_value(u, metric);
    b[n] = pom_doe_cell_value(v, metric);
    if (metric == POM_DOE_METRIC_TIME) {
      out->censored_a += u->censored;
      out->censored_b += v->censored;
    }
    ++n;
  }
  pom_doe_paired_compute(&out->test, a, b, n, confidence, scratch);
}

/* Friedman's test over the maneuvers every candidate can use (blocks), one
 * maneuver at a time so nothing grows with their number; values, rank:
 * nc doubles each, scratch 4 nc. */
static void friedman(pom_doe_friedman_result *out, long *censored, const pom_doe_cell *cells,
                     size_t m, const int *idx, int nc, pom_doe_metric metric, double *values,
                     double *rank, double *scratch) {
  double *rank_sum = scratch, *pairs = scratch + nc;
  double tie_sum = 0;
  long n = 0, n_censored = 0;
  for (int c = 0; c < nc; ++c)
    rank_sum[c] = 0;
  for (size_t k = 0; k < m; ++k) {
    int all = 1;
    for (int c = 0; c < nc && all; ++c) {
      const pom_doe_cell *cell = &cells[(size_t)idx[c] * m + k];
      all = pom_doe_cell_usable(cell, metric);
      values[c] = all ? pom_doe_cell_value(cell, metric) : NAN;
    }
    if (!all) continue;
    for (int c = 0; c < nc; ++c)
      n_censored += metric == POM_DOE_METRIC_TIME && cells[(size_t)idx[c] * m + k].censored;
    tie_sum += pom_doe_rank_average(rank, values, nc, pairs);
    for (int c = 0; c < nc; ++c)
      rank_sum[c] += rank[c];
    ++n;
  }
  pom_doe_friedman_from_ranks(out, rank_sum, nc, n, tie_sum);
  if (metric == POM_DOE_METRIC_TIME) *censored = n_censored;
}

int pom_doe_candidate_competes(const pom_doe_study *study, int c) {
  if (study->n_requirements == 0) return 1;
  const pom_doe_candidate *cand = &study->candidates[c];
  return cand->capability_done && cand->capability_met;
}

pom_status pom_doe_report_compute(pom_doe_report **out, const pom_doe_study *study,
                                  const pom_doe_cell *cells, pom_error *err) {
  pom_status st = POM_OK;
  int nc = study->n_candidates;
  size_t m = (size_t)study->maneuvers.count;
  double *a = NULL, *b = NULL, *scratch = NULL;
  size_t *order_scratch = NULL;
  rank_item *items = NULL;
  int *idx = NULL; /* the competing candidates' indices */
  pom_doe_report *rep = calloc(1, sizeof *rep);
  if (!rep) POM_FAIL(err, POM_ERR_NOMEM, "report: out of memory");
  *out = NULL;
  rep->n_candidates = nc;
  rep->n_maneuvers = (long)m;
  rep->alpha = study->alpha;
  rep->ranked = calloc((size_t)(nc ? nc : 1), sizeof *rep->ranked);
  idx = malloc((size_t)(nc ? nc : 1) * sizeof *idx);
  if (!rep->ranked || !idx) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "report: out of memory");
  for (int c = 0; c < nc; ++c)
    if ((rep->ranked[c] = pom_doe_candidate_competes(study, c))) idx[rep->n_ranked++] = c;
  int nr = rep->n_ranked;
  rep->all_pairs = nr <= POM_DOE_ALL_PAIRS_MAX;
  rep->n_comparisons = rep->all_pairs ? nr * (nr - 1) : 2 * (nr - 1); /* two metrics */
  rep->cand = calloc((size_t)nc, sizeof *rep->cand);
  rep->cmp = calloc(rep->n_comparisons ? (size_t)rep->n_comparisons : 1, sizeof *rep->cmp);
  rep->rank_time = calloc((size_t)nc, sizeof *rep->rank_time);
  rep->rank_energy = calloc((size_t)nc, sizeof *rep->rank_energy);
  rep->mean_time = calloc((size_t)nc, sizeof *rep->mean_time);
  rep->mean_energy = calloc((size_t)nc, sizeof *rep->mean_energy);
  rep->censored_common = calloc((size_t)nc, sizeof *rep->censored_common);
  /* a, b: one value per maneuver, per comparison or per candidate */
  size_t len = m > (size_t)rep->n_comparisons ? m : (size_t)rep->n_comparisons;
  len = len > (size_t)nc ? len : (size_t)nc;
  a = malloc((len ? len : 1) * sizeof *a);
  b = malloc((len ? len : 1) * sizeof *b);
  scratch = malloc((len ? len : 1) * 4 * sizeof *scratch);
  order_scratch = malloc((len ? len : 1) * sizeof *order_scratch);
  items = malloc((size_t)nc * sizeof *items);
  if (!rep->cand || !rep->cmp || !rep->rank_time || !rep->rank_energy || !rep->mean_time ||
      !rep->mean_energy || !rep->censored_common || !a || !b || !scratch || !order_scratch ||
      !items)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "report: out of memory");

  for (int c = 0; c < nc; ++c) {
    pom_doe_candidate_stats *cs = &rep->cand[c];
    const pom_doe_cell *col = cells + (size_t)c * m;
    for (size_t k = 0; k < m; ++k) {
      if (!col[k].done) continue;
      ++cs->n_done;
      if (!col[k].ok)
        ++cs->n_failed;
      else if (!col[k].settled)
        ++cs->n_unsettled;
      if (col[k].censored) ++cs->n_censored;
      if (col[k].rigid_limit >= 0) ++cs->n_validity;
      if (col[k].rigid_limit == 1) ++cs->n_rigid_limit;
    }
    /* every reduced metric of the schema over the maneuvers that count */
    for (int s = 0; s < POM_DYN_N_STATS; ++s) {
      size_t n = 0;
      for (size_t k = 0; k < m; ++k)
        if (col[k].done && !isnan(col[k].stat[s])) a[n++] = col[k].stat[s];
      pom_doe_stats_compute(&cs->stat[s], a, n, a);
    }
  }

  rank(rep->rank_time, rep->mean_time, rep->censored_common, study, rep, cells, POM_DOE_METRIC_TIME,
       idx, items);
  rank(rep->rank_energy, rep->mean_energy, NULL, study, rep, cells, POM_DOE_METRIC_ENERGY, idx,
       items);
  POM_TRY_GOTO(pom_doe_effects_compute(rep, study, cells, err), fail);
  int j = 0;
  for (int metric = 0; metric < 2; ++metric) {
    int first = j;
    const int *order = metric == 0 ? rep->rank_time : rep->rank_energy;
    for (int ca = 0; ca < nr; ++ca)
      for (int cb = ca + 1; cb < nr; ++cb) {
        int x = idx[ca], y = idx[cb];
        if (!rep->all_pairs) { /* the best against each other one */
          if (ca > 0) break;
          x = order[0];
          y = order[cb];
        }
        pom_doe_comparison *cmp = &rep->cmp[j++];
        cmp->a = x;
        cmp->b = y;
        cmp->metric = (pom_doe_metric)metric;
        compare(cmp, cells, m, x, y, (pom_doe_metric)metric, study->confidence, a, b, scratch);
      }
    /* Holm over this metric's comparisons */
    for (int i = first; i < j; ++i)
      a[i - first] = rep->cmp[i].test.wilcoxon_p;
    pom_doe_holm(b, a, (size_t)(j - first), order_scratch);
    for (int i = first; i < j; ++i)
      rep->cmp[i].p_holm = b[i - first];
    friedman(&rep->friedman[metric], &rep->friedman_censored, cells, m, idx, nr,
             (pom_doe_metric)metric, a, b, scratch);
  }
  *out = rep;
  goto done;
fail:
  pom_doe_report_destroy(rep);
done:
  free(a);
  free(b);
  free(scratch);
  free(order_scratch);
  free(items);
  free(idx);
  return st;
}
