/* pom_doe_report.c - per-candidate statistics, paired comparisons and the
 * ranking (docs/results.md, "Statistics"). */
#include "pom_doe_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The per-maneuver value of each statistic: its metric combined over the
 * actuators, kept when the maneuver counts for it (ok, or settled) and the
 * value is finite; NaN otherwise. */
void pom_doe_cell_from_row(pom_doe_cell *cell, const pom_doe_row *row) {
  cell->done = (int8_t)(row->done != 0);
  cell->ok = (int8_t)(row->done && row->status == POM_OK);
  cell->settled = (int8_t)(cell->ok && row->settled[0] && row->settled[1] && row->settled[2] &&
                           isfinite(row->execution_time));
  for (int s = 0; s < POM_DYN_N_STATS; ++s) {
    const pom_dyn_metric_info *mi = pom_dyn_stat_metric(s);
    int j = (int)(mi - pom_dyn_metric_schema());
    double v[3];
    for (int k = 0; k < mi->count; ++k)
      v[k] = pom_doe_row_value(row, j, k);
    double x = pom_dyn_combine_values(mi->combine, v, mi->count);
    int counts = mi->reduce == POM_DYN_REDUCE_SETTLED ? cell->settled : cell->ok && isfinite(x);
    cell->stat[s] = counts ? x : NAN;
  }
}

void pom_doe_report_destroy(pom_doe_report *r) {
  if (!r) return;
  free(r->cand);
  free(r->cmp);
  free(r->rank_time);
  free(r->rank_energy);
  free(r);
}

/* 1 when maneuver cell counts for the metric (time needs settling). */
static int usable(const pom_doe_cell *cell, pom_doe_metric metric) {
  return metric == POM_DOE_METRIC_TIME ? cell->settled : cell->ok;
}

/* The chosen metrics of the paired comparison and the ranking, read through
 * the schema's statistics. */
static double value_of(const pom_doe_cell *cell, pom_doe_metric metric) {
  return cell
      ->stat[metric == POM_DOE_METRIC_TIME ? POM_DYN_STAT_execution_time : POM_DYN_STAT_energy];
}

/* Ranking by the mean over the maneuvers usable for every candidate (the
 * common set), so every candidate is judged on the same maneuvers. */
typedef struct {
  int index;
  double mean;
  long bad; /* failed + unsettled: tie-break */
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

static void rank(int *order, const pom_doe_study *study, const pom_doe_report *rep,
                 const pom_doe_cell *cells, pom_doe_metric metric, rank_item *items) {
  int nc = study->n_candidates;
  long m = study->maneuvers.count;
  for (int c = 0; c < nc; ++c) {
    items[c].index = c;
    items[c].bad = rep->cand[c].n_failed + rep->cand[c].n_unsettled;
    items[c].mean = 0;
  }
  long n = 0;
  for (long k = 0; k < m; ++k) {
    int all = 1;
    for (int c = 0; c < nc && all; ++c)
      all = usable(&cells[(size_t)c * (size_t)m + (size_t)k], metric);
    if (!all) continue;
    ++n;
    for (int c = 0; c < nc; ++c)
      items[c].mean += value_of(&cells[(size_t)c * (size_t)m + (size_t)k], metric);
  }
  for (int c = 0; c < nc; ++c)
    items[c].mean = n ? items[c].mean / (double)n : NAN;
  qsort(items, (size_t)nc, sizeof *items, cmp_rank);
  for (int c = 0; c < nc; ++c)
    order[c] = items[c].index;
}

pom_status pom_doe_report_compute(pom_doe_report **out, const pom_doe_study *study,
                                  const pom_doe_cell *cells, pom_error *err) {
  pom_status st = POM_OK;
  int nc = study->n_candidates;
  size_t m = (size_t)study->maneuvers.count;
  double *a = NULL, *b = NULL, *scratch = NULL;
  rank_item *items = NULL;
  pom_doe_report *rep = calloc(1, sizeof *rep);
  if (!rep) POM_FAIL(err, POM_ERR_NOMEM, "report: out of memory");
  *out = NULL;
  rep->n_candidates = nc;
  rep->n_maneuvers = (long)m;
  rep->alpha = study->alpha;
  rep->n_comparisons = nc * (nc - 1); /* every pair, two metrics */
  rep->cand = calloc((size_t)nc, sizeof *rep->cand);
  rep->cmp = calloc(rep->n_comparisons ? (size_t)rep->n_comparisons : 1, sizeof *rep->cmp);
  rep->rank_time = calloc((size_t)nc, sizeof *rep->rank_time);
  rep->rank_energy = calloc((size_t)nc, sizeof *rep->rank_energy);
  a = malloc((m ? m : 1) * sizeof *a);
  b = malloc((m ? m : 1) * sizeof *b);
  scratch = malloc((m ? m : 1) * 3 * sizeof *scratch);
  items = malloc((size_t)nc * sizeof *items);
  if (!rep->cand || !rep->cmp || !rep->rank_time || !rep->rank_energy || !a || !b || !scratch ||
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
    }
    /* every reduced metric of the schema over the maneuvers that count */
    for (int s = 0; s < POM_DYN_N_STATS; ++s) {
      size_t n = 0;
      for (size_t k = 0; k < m; ++k)
        if (col[k].done && !isnan(col[k].stat[s])) a[n++] = col[k].stat[s];
      pom_doe_stats_compute(&cs->stat[s], a, n, a);
    }
  }

  int j = 0;
  for (int ca = 0; ca < nc; ++ca)
    for (int cb = ca + 1; cb < nc; ++cb)
      for (int metric = 0; metric < 2; ++metric) {
        size_t n = 0;
        for (size_t k = 0; k < m; ++k) {
          const pom_doe_cell *x = &cells[(size_t)ca * m + k], *y = &cells[(size_t)cb * m + k];
          if (!usable(x, (pom_doe_metric)metric) || !usable(y, (pom_doe_metric)metric)) continue;
          a[n] = value_of(x, (pom_doe_metric)metric);
          b[n] = value_of(y, (pom_doe_metric)metric);
          ++n;
        }
        pom_doe_comparison *cmp = &rep->cmp[j++];
        cmp->a = ca;
        cmp->b = cb;
        cmp->metric = (pom_doe_metric)metric;
        pom_doe_paired_compute(&cmp->test, a, b, n, study->confidence, scratch);
      }
  rank(rep->rank_time, study, rep, cells, POM_DOE_METRIC_TIME, items);
  rank(rep->rank_energy, study, rep, cells, POM_DOE_METRIC_ENERGY, items);
  *out = rep;
  goto done;
fail:
  pom_doe_report_destroy(rep);
done:
  free(a);
  free(b);
  free(scratch);
  free(items);
  return st;
}
