/* pom_job.c - a study's job for every caller: the checks before the work,
 * the pipeline and the earned fidelity, the runs with progress and Ctrl-C,
 * the tables, verdict and JSON report, the tabular files, summary.md and
 * figures (docs/results.md, "What you see"). */
#define _POSIX_C_SOURCE 200809L
#include "pom_job.h"
#include "job_internal.h"
#include "pom_io.h"
#include "pom_math.h"
#include "pom_pipeline.h"
#include "pom_progress.h"
#include "pom_version.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

/* Set by job/CMakeLists.txt: the source tree's scripts folder. */
#ifndef POM_JOB_SCRIPTS_DIR
#define POM_JOB_SCRIPTS_DIR "scripts"
#endif

/* ---- Ctrl-C --------------------------------------------------------------------- */
static volatile sig_atomic_t interrupted = 0;

static void on_signal(int sig) {
  (void)sig;
  interrupted = 1;
}

/* ---- formatting helpers ----------------------------------------------------------- */
static void fmt_num(char *buf, size_t cap, double v, double scale, int prec) {
  if (isfinite(v))
    snprintf(buf, cap, "%.*f", prec, v * scale);
  else
    snprintf(buf, cap, "-");
}

static void fmt_p(char *buf, size_t cap, double p) {
  if (!isfinite(p))
    snprintf(buf, cap, "-");
  else if (p < 1e-4)
    snprintf(buf, cap, "%.1e", p);
  else
    snprintf(buf, cap, "%.4f", p);
}

/* The comparison of candidates a and b on metric, oriented as a - b. */
static int find_comparison(const pom_doe_report *rep, int a, int b, pom_doe_metric metric,
                           pom_doe_paired *out, double *p_holm) {
  for (int j = 0; j < rep->n_comparisons; ++j) {
    const pom_doe_comparison *c = &rep->cmp[j];
    if (c->metric != metric) continue;
    *p_holm = c->p_holm;
    if (c->a == a && c->b == b) {
      *out = c->test;
      return 1;
    }
    if (c->a == b && c->b == a) {
      *out = c->test;
      out->mean_diff = -c->test.mean_diff;
      out->ci_low = -c->test.ci_high;
      out->ci_high = -c->test.ci_low;
      out->win_fraction = 1.0 - c->test.win_fraction - c->test.tie_fraction;
      return 1;
    }
  }
  return 0;
}

/* The leading cells of a candidate's row: its name and one cell per sweep
 * factor; with a single candidate, none (the heading names it). */
static void lead_cells(FILE *out, const pom_doe_study *study, int c) {
  if (study->n_candidates < 2) return;
  fprintf(out, "| %s ", study->candidates[c].name);
  for (int f = 0; f < study->n_factors; ++f)
    fprintf(out, "| %.6g ", study->candidates[c].factor_value[f]);
}

/* The leading header cells matching lead_cells, and their separators. */
static void lead_head(FILE *out, const pom_doe_study *study, int separator) {
  if (study->n_candidates < 2) return;
  fprintf(out, "%s", separator ? "|---" : "| candidate ");
  for (int f = 0; f < study->n_factors; ++f)
    if (separator)
      fprintf(out, "|---:");
    else
      fprintf(out, "| %s ", study->factor_label[f]);
}

/* A statistics table's header: lead cells, then cols[] right-aligned. */
static void stats_head(FILE *out, const pom_doe_study *study, const char *cols) {
  lead_head(out, study, 0);
  fprintf(out, "| %s |\n", cols);
  lead_head(out, study, 1);
  for (const char *p = cols; *p; ++p)
    if (*p == '|') fprintf(out, "|---:");
  fprintf(out, "|---:|\n");
}

static void stats_row(FILE *out, const pom_doe_study *study, int c, const pom_doe_stats *s,
                      double scale, int prec, const pom_doe_candidate_stats *cs,
                      int with_unsettled) {
  char mx[32], mean[32], mn[32], sd[32], med[32], p95[32];
  fmt_num(mx, sizeof mx, s->max, scale, prec);
  fmt_num(mean, sizeof mean, s->mean, scale, prec);
  fmt_num(mn, sizeof mn, s->min, scale, prec);
  fmt_num(sd, sizeof sd, s->sigma, scale, prec);
  fmt_num(med, sizeof med, s->median, scale, prec);
  fmt_num(p95, sizeof p95, s->p95, scale, prec);
  lead_cells(out, study, c);
  fprintf(out, "| %s | %s | %s | %s | %s | %s | %ld |", mx, mean, mn, sd, med, p95, s->n);
  if (with_unsettled)
    fprintf(out, " %ld |", with_unsettled == 2 ? cs->n_censored : cs->n_unsettled);
  fprintf(out, " %ld |\n", cs->n_failed);
}

/* The response's name: the primary time metric (study.time_metric) or
 * energy. */
static const char *metric_label(const pom_doe_study *study, pom_doe_metric m) {
  if (m != POM_DOE_METRIC_TIME) return "expended energy";
  return study->time_metric == POM_DOE_TIME_POINTING ? "pointing time" : "execution time";
}

/* ---- actuator kinds ------------------------------------------------------------------ */
pom_actuator_kind pom_job_study_kind(const pom_doe_study *study, int *mixed) {
  pom_actuator_kind k =
      study->n_candidates > 0 ? study->candidates[0].eval.actuator_kind : POM_ACT_PRISMATIC;
  *mixed = 0;
  for (int c = 1; c < study->n_candidates; ++c)
    if (study->candidates[c].eval.actuator_kind != k) *mixed = 1;
  return k;
}

/* When the candidates mix actuator kinds, the study runs in orientation
 * space (joint space is refused) and the reader is told why. */
static void mixed_kinds_note(FILE *out, const pom_doe_study *study) {
  int mixed = 0;
  pom_job_study_kind(study, &mixed);
  if (mixed)
    fprintf(out, "The candidates mix actuator kinds (prismatic: q in mm; revolute: q in deg), so "
                 "the comparison is in orientation space: every candidate is driven to the same "
                 "platform orientations (its own actuator targets by inverse kinematics).\n\n");
}

/* With uncertain parameters every maneuver has its own draws, so the
 * statistics are robustness figures: mean, p95 and worst over maneuvers and
 * draws, and how often a candidate fails (docs/results.md section 10). */
static void robustness_table(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  const pom_unc *unc = &study->uncertain;
  if (unc->n == 0) return;
  fprintf(out, "\n### Robustness under %d uncertain parameter(s), drawn per maneuver\n\n", unc->n);
  for (int j = 0; j < unc->n; ++j) {
    const pom_dist *d = &unc->param[j].dist;
    fprintf(out, "- `%s`%s: %s, draws in [%.4g, %.4g]\n", unc->param[j].key,
            unc->param[j].relative ? " (relative: x nominal)" : "", d->ops->name, d->lo, d->hi);
  }
  fprintf(out, "\n| candidate | time mean (ms) | time p95 | time worst | energy mean (J) | "
               "energy p95 | energy worst | failed | unsettled |\n"
               "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int c = 0; c < rep->n_candidates; ++c) {
    const pom_doe_candidate_stats *cs = &rep->cand[c];
    const pom_doe_stats *t = &cs->execution_time, *e = &cs->energy;
    char v[6][32];
    fmt_num(v[0], sizeof v[0], t->mean, 1e3, 2);
    fmt_num(v[1], sizeof v[1], t->p95, 1e3, 2);
    fmt_num(v[2], sizeof v[2], t->max, 1e3, 2);
    fmt_num(v[3], sizeof v[3], e->mean, 1.0, 4);
    fmt_num(v[4], sizeof v[4], e->p95, 1.0, 4);
    fmt_num(v[5], sizeof v[5], e->max, 1.0, 4);
    double done = cs->n_done > 0 ? (double)cs->n_done : NAN;
    fprintf(out, "| %s | %s | %s | %s | %s | %s | %s | %.1f %% | %.1f %% |\n",
            study->candidates[c].name, v[0], v[1], v[2], v[3], v[4], v[5],
            100.0 * (double)cs->n_failed / done, 100.0 * (double)cs->n_unsettled / done);
  }
  fprintf(out, "\nfailed: share of maneuvers whose draws or run failed (reason per row); "
               "unsettled: share that never settled within the horizon. The draws are stored in "
               "the results file (/uncertain/draws).\n");
}

/* ---- comparisons ---------------------------------------------------------------------- */
/* Friedman's test over every candidate (three or more), then the paired
 * comparisons: every pair up to POM_DOE_ALL_PAIRS_MAX candidates, else the
 * best of each metric against each other one; Holm-adjusted p over each
 * metric's comparisons. */
static void print_comparisons(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  int nc = rep->n_ranked;
  if (nc >= 3) {
    fprintf(out, "\n### Friedman test (all %d %scandidates, maneuvers every one completed)\n\n", nc,
            nc < rep->n_candidates ? "competing " : "");
    fprintf(out, "| response | maneuvers | censored | chi-square | df | p |\n"
                 "|---|---:|---:|---:|---:|---:|\n");
    for (int m = 0; m < 2; ++m) {
      const pom_doe_friedman_result *f = &rep->friedman[m];
      char q[32], p[32];
      fmt_num(q, sizeof q, f->statistic, 1.0, 2);
      fmt_p(p, sizeof p, f->p);
      char cens[32] = "-";
      if (m == POM_DOE_METRIC_TIME) snprintf(cens, sizeof cens, "%ld", rep->friedman_censored);
      fprintf(out, "| %s | %ld | %s | %s | %.0f | %s |\n", metric_label(study, (pom_doe_metric)m),
              f->n_blocks, cens, q, f->df, p);
    }
  }
  if (rep->n_comparisons == 0) return;
  if (rep->all_pairs)
    fprintf(out, "\n### Paired comparisons (same maneuvers; difference = A - B)\n\n");
  else
    fprintf(out,
            "\n### Paired comparisons: the best candidate (A) against each other one (B)\n\n"
            "%d candidates: every pair would be %d comparisons, so each metric's best (its "
            "ranking's first) is compared with each other candidate on the same maneuvers; "
            "difference = A - B.\n\n",
            nc, nc * (nc - 1));
  fprintf(out,
          "| response | A | B | pairs | mean A - B | %.0f %% interval | Wilcoxon p | Holm p | A "
          "better | tie | B better | censored A / B |\n"
          "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
          100 * study->confidence);
  for (int j = 0; j < rep->n_comparisons; ++j) {
    const pom_doe_comparison *c = &rep->cmp[j];
    double scale = c->metric == POM_DOE_METRIC_TIME ? 1e3 : 1.0;
    int prec = c->metric == POM_DOE_METRIC_TIME ? 3 : 5;
    char md[32], lo[32], hi[32], p[32], ph[32], win[32], tie[32], lose[32];
    fmt_num(win, sizeof win, c->test.win_fraction, 100, 1);
    fmt_num(tie, sizeof tie, c->test.tie_fraction, 100, 1);
    fmt_num(lose, sizeof lose, 1.0 - c->test.win_fraction - c->test.tie_fraction, 100, 1);
    fmt_num(md, sizeof md, c->test.mean_diff, scale, prec);
    fmt_num(lo, sizeof lo, c->test.ci_low, scale, prec);
    fmt_num(hi, sizeof hi, c->test.ci_high, scale, prec);
    fmt_p(p, sizeof p, c->test.wilcoxon_p);
    fmt_p(ph, sizeof ph, c->p_holm);
    char cens[48] = "-";
    if (c->metric == POM_DOE_METRIC_TIME)
      snprintf(cens, sizeof cens, "%ld / %ld", c->censored_a, c->censored_b);
    fprintf(out,
            "| %s (%s) | %s | %s | %ld | %s | [%s, %s] | %s | %s | %s %% | %s %% | %s %% | %s |\n",
            metric_label(study, c->metric), c->metric == POM_DOE_METRIC_TIME ? "ms" : "J",
            study->candidates[c->a].name, study->candidates[c->b].name, c->test.n, md, lo, hi, p,
            ph, win, tie, lose, cens);
  }
}

/* ---- many candidates: main effects, heat map, Pareto front ------------------------------ */
/* A level's label: its value, or its range when binned. */
static void level_label(char *buf, size_t cap, double lo, double hi) {
  if (lo == hi)
    snprintf(buf, cap, "%.6g", lo);
  else
    snprintf(buf, cap, "%.4g-%.4g", lo, hi);
}

static void print_effects(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  if (rep->n_effects == 0) return;
  fprintf(out,
          "\n### Main effects (mean over each level's candidates, then over the maneuvers; "
          "%.0f %% interval)\n\n",
          100 * study->confidence);
  fprintf(out,
          "| factor | level | candidates | %s (ms) | interval | censored | expended energy (J) "
          "| interval |\n|---|---:|---:|---:|---:|---:|---:|---:|\n",
          metric_label(study, POM_DOE_METRIC_TIME));
  for (int j = 0; j < rep->n_effects; ++j) {
    const pom_doe_effect *t = &rep->effects[j];
    if (t->metric != POM_DOE_METRIC_TIME) continue;
    const pom_doe_effect *e = NULL; /* the same level's energy effect */
    for (int i = 0; i < rep->n_effects && !e; ++i)
      if (rep->effects[i].factor == t->factor && rep->effects[i].level == t->level &&
          rep->effects[i].metric == POM_DOE_METRIC_ENERGY)
        e = &rep->effects[i];
    char lv[64], tm[32], tl[32], th[32], em[32], el[32], eh[32];
    level_label(lv, sizeof lv, t->lo, t->hi);
    fmt_num(tm, sizeof tm, t->mean, 1e3, 3);
    fmt_num(tl, sizeof tl, t->ci_low, 1e3, 3);
    fmt_num(th, sizeof th, t->ci_high, 1e3, 3);
    fmt_num(em, sizeof em, e ? e->mean : NAN, 1.0, 4);
    fmt_num(el, sizeof el, e ? e->ci_low : NAN, 1.0, 4);
    fmt_num(eh, sizeof eh, e ? e->ci_high : NAN, 1.0, 4);
    fprintf(out, "| %s | %s | %d | %s | [%s, %s] | %ld | %s | [%s, %s] |\n",
            study->factor_label[t->factor], lv, t->n_candidates, tm, tl, th, t->n_censored, em, el,
            eh);
  }
}

/* The mean response of the candidates at each pair of levels of the first
 * two factors (their common-maneuver means). */
static void print_heat_map(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  int nc = study->n_candidates;
  if (study->n_factors < 2 || nc < 2) return;
  int *lv0 = malloc((size_t)nc * sizeof *lv0), *lv1 = malloc((size_t)nc * sizeof *lv1);
  double *lo0 = malloc((size_t)nc * sizeof *lo0), *hi0 = malloc((size_t)nc * sizeof *hi0);
  double *lo1 = malloc((size_t)nc * sizeof *lo1), *hi1 = malloc((size_t)nc * sizeof *hi1);
  int n0 = -1, n1 = -1;
  if (lv0 && lv1 && lo0 && hi0 && lo1 && hi1) {
    n0 = pom_doe_factor_levels(study, 0, lv0, lo0, hi0);
    n1 = pom_doe_factor_levels(study, 1, lv1, lo1, hi1);
  }
  for (int m = 0; m < 2 && n0 > 0 && n1 > 0; ++m) {
    const double *mean = m == 0 ? rep->mean_time : rep->mean_energy;
    fprintf(out, "\n### Heat map: mean %s (%s), %s (rows) x %s (columns)\n\n",
            metric_label(study, (pom_doe_metric)m), m == 0 ? "ms" : "J", study->factor_label[0],
            study->factor_label[1]);
    fprintf(out, "| %s \\ %s |", study->factor_label[0], study->factor_label[1]);
    for (int j = 0; j < n1; ++j) {
      char l[64];
      level_label(l, sizeof l, lo1[j], hi1[j]);
      fprintf(out, " %s |", l);
    }
    fprintf(out, "\n|---|");
    for (int j = 0; j < n1; ++j)
      fprintf(out, "---:|");
    fprintf(out, "\n");
    for (int i = 0; i < n0; ++i) {
      char l[64];
      level_label(l, sizeof l, lo0[i], hi0[i]);
      fprintf(out, "| %s |", l);
      for (int j = 0; j < n1; ++j) {
        double sum = 0;
        int cnt = 0;
        for (int c = 0; c < nc; ++c)
          if (lv0[c] == i && lv1[c] == j && isfinite(mean[c])) {
            sum += mean[c];
            ++cnt;
          }
        char v[32];
        fmt_num(v, sizeof v, cnt ? sum / cnt : NAN, m == 0 ? 1e3 : 1.0, m == 0 ? 3 : 4);
        fprintf(out, " %s |", v);
      }
      fprintf(out, "\n");
    }
  }
  free(lv0);
  free(lv1);
  free(lo0);
  free(hi0);
  free(lo1);
  free(hi1);
}

/* The candidates no other beats on both mean time and mean energy, fastest
 * first. */
static void print_pareto(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  int nc = rep->n_candidates, n = 0;
  if (nc < 3) return;
  for (int c = 0; c < nc; ++c)
    n += rep->pareto[c];
  fprintf(out, "\n### Pareto front: %s against energy (%d of %d candidates)\n\n",
          metric_label(study, POM_DOE_METRIC_TIME), n, nc);
  if (n == 0) {
    fprintf(out, "No maneuver that every candidate completed: no front.\n");
    return;
  }
  fprintf(out, "Means over the maneuvers every candidate completed; no other candidate is as "
               "fast and as frugal with one of them strictly better; a time that did not settle "
               "counts censored at the horizon (censored: how many).\n\n");
  lead_head(out, study, 0);
  fprintf(out, "| %s (ms) | censored | expended energy (J) |\n",
          metric_label(study, POM_DOE_METRIC_TIME));
  lead_head(out, study, 1);
  fprintf(out, "|---:|---:|---:|\n");
  for (int r = 0; r < nc; ++r) {
    int c = rep->rank_time[r];
    if (!rep->pareto[c]) continue;
    lead_cells(out, study, c);
    fprintf(out, "| %.3f | %ld | %.4f |\n", rep->mean_time[c] * 1e3, rep->censored_common[c],
            rep->mean_energy[c]);
  }
}

/* The maneuvers that did not fail but whose stepinfo time is NaN: a band
 * below what the integration resolves (docs/results.md section 1c), left out
 * of Table 1b's n. Printed only when there are some. */
static void print_unresolved(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  long total = 0;
  for (int c = 0; c < rep->n_candidates; ++c) {
    const pom_doe_candidate_stats *cs = &rep->cand[c];
    total += cs->n_done - cs->n_failed - cs->execution_time_final.n;
  }
  if (total <= 0) return;
  fprintf(out, "\nunresolved (not in n):");
  for (int c = 0, first = 1; c < rep->n_candidates; ++c) {
    const pom_doe_candidate_stats *cs = &rep->cand[c];
    long u = cs->n_done - cs->n_failed - cs->execution_time_final.n;
    if (u <= 0) continue;
    fprintf(out, "%s %s %ld", first ? "" : ",", study->candidates[c].name, u);
    first = 0;
  }
  fprintf(out, " maneuver(s) with an actuator whose stepinfo band lies below what the "
               "integration resolves of its position; their stepinfo time is not a result "
               "(docs/results.md section 1c).\n");
}

/* The parasitic model's validity rule (docs/dynamics.md section 13b): per
 * candidate, the maneuvers flagged not at the rigid limit ("n/a" on rigid
 * joints); nothing when no candidate has parasitic joints. */
static void print_rigid_limit(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  long checked = 0, flagged = 0;
  int na = 0;
  for (int c = 0; c < rep->n_candidates; ++c) {
    checked += rep->cand[c].n_validity;
    flagged += rep->cand[c].n_rigid_limit;
    na |= rep->cand[c].n_validity == 0;
  }
  if (checked <= 0) return;
  fprintf(out, "\nparasitic model not at its rigid limit (docs/dynamics.md section 13b):");
  for (int c = 0; c < rep->n_candidates; ++c) {
    const pom_doe_candidate_stats *cs = &rep->cand[c];
    fprintf(out, "%s %s ", c ? "," : "", study->candidates[c].name);
    if (cs->n_validity > 0)
      fprintf(out, "%ld of %ld", cs->n_rigid_limit, cs->n_validity);
    else
      fprintf(out, "n/a");
  }
  fprintf(out, " maneuver(s) flagged%s.\n", na ? " (n/a: rigid joints or none finished)" : "");
  if (flagged > 0)
    fprintf(out, "Note: a flagged maneuver's parasitic result may be far from the rigid model's "
                 "(rigid_limit_ratio > 1e-2: the drive outruns the joints; "
                 "joint_dissipation_share > 2e-4: the joints move on their own); compare with "
                 "joints.model = \"rigid\" or study.fidelity = \"auto\".\n");
}

/* ---- the report ---------------------------------------------------------------------- */
void pom_job_print_report(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  int nc = rep->n_candidates;
  mixed_kinds_note(out, study);
  static const char cols[] = "max | mean | min | sigma | median | p95 | n | failed";
  static const char cols_unsettled[] =
      "max | mean | min | sigma | median | p95 | n | unsettled | failed";
  fprintf(out, "### Table 1: execution time (ms)\n\n");
  stats_head(out, study, cols_unsettled);
  for (int c = 0; c < nc; ++c)
    stats_row(out, study, c, &rep->cand[c].execution_time, 1e3, 2, &rep->cand[c], 1);
  fprintf(out, "\n### Table 2: expended energy (J)\n\n");
  stats_head(out, study, cols);
  for (int c = 0; c < nc; ++c)
    stats_row(out, study, c, &rep->cand[c].energy, 1.0, 4, &rep->cand[c], 0);
  fprintf(out,
          "\nExecution time = largest settling time of the three actuators (2 %% band), over "
          "maneuvers that settled within the horizon; energy = sum over the actuators of the "
          "signed integral of u i over the horizon. %s\n",
          study->time_metric == POM_DOE_TIME_POINTING
              ? "unsettled: some actuator outside its band at the horizon; the comparisons use "
                "the pointing time (Table 1p)."
              : "unsettled: maneuvers whose time is right-censored at the horizon; the "
                "comparisons and the ranking count them there (docs/results.md section 4).");
  if (study->time_metric == POM_DOE_TIME_POINTING) {
    static const char cols_censored[] =
        "max | mean | min | sigma | median | p95 | n | censored | failed";
    fprintf(out, "\n### Table 1p: pointing settling time (ms), the primary time metric\n\n");
    stats_head(out, study, cols_censored);
    for (int c = 0; c < nc; ++c)
      stats_row(out, study, c, &rep->cand[c].pointing_time, 1e3, 2, &rep->cand[c], 2);
    fprintf(out, "\nPointing settling time = last time the angle between the platform and the "
                 "target orientation was outside the pointing band (maneuver.pointing_band_mrad); "
                 "statistics over the maneuvers that settled, censored: those that did not within "
                 "the horizon, which the comparisons and the ranking count there "
                 "(docs/results.md section 4).\n");
  }
  fprintf(out, "\n### Table 1b: execution time (ms), MATLAB stepinfo definition\n\n");
  stats_head(out, study, cols);
  for (int c = 0; c < nc; ++c)
    stats_row(out, study, c, &rep->cand[c].execution_time_final, 1e3, 2, &rep->cand[c], 0);
  fprintf(out, "\nstepinfo: each actuator's band is 2 %% of its largest deviation from its value "
               "at the horizon, about that value (the paper's MATLAB post-processing most likely "
               "used it); defined for tiny steps too, as far as the integration resolves them.\n");
  print_unresolved(out, study, rep);
  print_rigid_limit(out, study, rep);
  robustness_table(out, study, rep);

  if (nc < 2) { /* one candidate: nothing to compare or rank */
    pom_job_capability_exclusions(out, study, rep);
    return;
  }
  print_effects(out, study, rep);
  pom_job_capability_effects(out, study, rep);
  print_heat_map(out, study, rep);
  print_pareto(out, study, rep);
  print_comparisons(out, study, rep);

  int nr = rep->n_ranked;
  fprintf(out, "\n### Ranking (mean over the maneuvers every %scandidate completed)\n\n",
          nr < nc ? "competing " : "");
  pom_job_capability_exclusions(out, study, rep);
  if (nr == 0) return; /* nothing ranked: the exclusions say why */
  /* the primary metric (study.rank_by) first */
  const int metrics[2] = {study->rank_by == POM_DOE_RANK_ENERGY,
                          study->rank_by != POM_DOE_RANK_ENERGY};
  for (int j = 0; j < 2; ++j) {
    int m = metrics[j];
    const int *order = m == 0 ? rep->rank_time : rep->rank_energy;
    const double *mean = m == 0 ? rep->mean_time : rep->mean_energy;
    fprintf(out, "- %s%s: ", metric_label(study, (pom_doe_metric)m), j == 0 ? " (primary)" : "");
    /* equal means share a place */
    int place = 1;
    for (int r = 0; r < nr; ++r) {
      if (r && !(mean[order[r]] == mean[order[r - 1]])) place = r + 1;
      int tied = (r && mean[order[r]] == mean[order[r - 1]]) ||
                 (r + 1 < nr && mean[order[r]] == mean[order[r + 1]]);
      fprintf(out, "%s%d.%s %s", r ? ", " : "", place, tied ? "=" : "",
              study->candidates[order[r]].name);
    }
    if (m == POM_DOE_METRIC_TIME) {
      fprintf(out, " (restricted mean: a time that did not settle counts at the horizon; "
                   "censored among the common maneuvers:");
      for (int r = 0; r < nr; ++r)
        fprintf(out, "%s %s %ld", r ? "," : "", study->candidates[order[r]].name,
                rep->censored_common[order[r]]);
      fprintf(out, ")");
    }
    fprintf(out, "\n");
  }
  if (nr < 2) return; /* one competing candidate: no verdict */

  fprintf(out, "\n### Verdict\n\n");
  for (int j = 0; j < 2; ++j) {
    int m = metrics[j];
    const int *order = m == 0 ? rep->rank_time : rep->rank_energy;
    int a = order[0], b = order[1];
    pom_doe_paired t;
    double p_holm = NAN;
    if (!find_comparison(rep, a, b, (pom_doe_metric)m, &t, &p_holm) || t.n == 0) {
      fprintf(out, "- %s: no maneuver that both %s and %s completed.\n",
              metric_label(study, (pom_doe_metric)m), study->candidates[a].name,
              study->candidates[b].name);
      continue;
    }
    if (t.n_nonzero == 0) { /* every difference is zero: a tie, not a win */
      fprintf(out,
              "- %s: %s and %s **tie**: the same %s on every one of the %ld common "
              "maneuvers.\n",
              metric_label(study, (pom_doe_metric)m), study->candidates[a].name,
              study->candidates[b].name, metric_label(study, (pom_doe_metric)m), t.n);
      continue;
    }
    double scale = m == 0 ? 1e3 : 1.0;
    const char *unit = m == 0 ? "ms" : "J";
    int several = rep->n_comparisons > 2; /* more than one comparison per metric */
    double p_used = several ? p_holm : t.wilcoxon_p;
    char p[32], ties[64] = "";
    fmt_p(p, sizeof p, p_used);
    if (t.tie_fraction > 0) snprintf(ties, sizeof ties, " (tie on %.1f %%)", 100 * t.tie_fraction);
    int significant = p_used < study->alpha;
    double loss_fraction = 1.0 - t.win_fraction - t.tie_fraction;
    if (loss_fraction > t.win_fraction) {
      /* the mean ranks a first, but b is lower on most maneuvers: the signed-rank
       * test then speaks for b; say that the two disagree rather than crown a */
      fprintf(out,
              "- %s: mixed: **%s** has the lower mean (difference %.4g %s, %.0f %% interval "
              "[%.4g, %.4g] %s) but %s is %s on %.1f %% of %ld common maneuvers%s (Wilcoxon "
              "p%s = %s, %s at alpha = %g): neither is better on both counts.\n",
              metric_label(study, (pom_doe_metric)m), study->candidates[a].name,
              t.mean_diff * scale, unit, 100 * study->confidence, t.ci_low * scale,
              t.ci_high * scale, unit, study->candidates[b].name, m == 0 ? "faster" : "more frugal",
              100 * loss_fraction, t.n, ties, several ? " (Holm-adjusted)" : "", p,
              significant ? "significant" : "not significant", study->alpha);
      continue;
    }
    fprintf(out,
            "- %s: **%s** %s %s (%s) on %.1f %% of %ld common maneuvers%s; mean difference %.4g "
            "%s (%.0f %% interval [%.4g, %.4g] %s), Wilcoxon p%s = %s: %s at alpha = %g.\n",
            metric_label(study, (pom_doe_metric)m), study->candidates[a].name,
            m == 0 ? "is faster than" : "uses less energy than", study->candidates[b].name,
            m == 0 ? (study->time_metric == POM_DOE_TIME_POINTING ? "lower pointing time"
                                                                  : "lower execution time")
                   : "lower expended energy",
            100 * t.win_fraction, t.n, ties, t.mean_diff * scale, unit, 100 * study->confidence,
            t.ci_low * scale, t.ci_high * scale, unit, several ? " (Holm-adjusted)" : "", p,
            significant ? "significant" : "NOT significant", study->alpha);
  }
}

/* ---- JSON -------------------------------------------------------------------------------- */
static void json_double(FILE *out, double v) {
  if (isfinite(v))
    fprintf(out, "%.10g", v);
  else
    fprintf(out, "null");
}

static void json_string(FILE *out, const char *s) {
  fputc('"', out);
  for (; *s; ++s) {
    if (*s == '"' || *s == '\\')
      fprintf(out, "\\%c", *s);
    else if ((unsigned char)*s < 0x20)
      fprintf(out, "\\u%04x", (unsigned char)*s);
    else
      fputc(*s, out);
  }
  fputc('"', out);
}

static void json_stats(FILE *out, const char *key, const pom_doe_stats *s) {
  double f[POM_DOE_STATS_FIELDS];
  static const char *const names[POM_DOE_STATS_FIELDS] = {"n",      "max", "mean", "min", "sigma",
                                                          "median", "p05", "p25",  "p75", "p95"};
  pom_doe_stats_flatten(f, s);
  fprintf(out, "\"%s\": {", key);
  for (int j = 0; j < POM_DOE_STATS_FIELDS; ++j) {
    fprintf(out, "%s\"%s\": ", j ? ", " : "", names[j]);
    json_double(out, f[j]);
  }
  fprintf(out, "}");
}

/* The maneuver protocol; joint-space ranges in the actuators' SI unit. */
static void json_montecarlo(FILE *out, const pom_doe_study *study) {
  const pom_doe_maneuvers *mv = &study->maneuvers;
  int mixed = 0;
  pom_actuator_kind kind = pom_job_study_kind(study, &mixed);
  fprintf(out, "  \"montecarlo\": {\"space\": \"%s\", ",
          pom_cfg_choice_name(pom_doe_space_names, (int)mv->space));
  if (mv->space == POM_DOE_SPACE_JOINT) {
    fprintf(out, "\"distribution\": \"%s\", \"actuator_unit\": \"%s\", \"range\": ",
            pom_cfg_choice_name(pom_doe_dist_names, (int)mv->distribution),
            pom_act_kind_desc(kind)->si);
    json_double(out, mv->range);
    fprintf(out, ", \"sigma\": ");
    json_double(out, mv->sigma);
  } else {
    fprintf(out, "\"mixed_actuator_kinds\": %s, \"tilt_max_rad\": ", mixed ? "true" : "false");
    json_double(out, mv->tilt_max);
    fprintf(out, ", \"torsion_max_rad\": ");
    json_double(out, mv->torsion_max);
  }
  fprintf(out, "},\n");
}

/* The metric schema: every metric stored per maneuver in the results file. */
/* The uncertain parameters (their draws are in the results file). */
static void json_uncertain(FILE *out, const pom_doe_study *study) {
  const pom_unc *unc = &study->uncertain;
  fprintf(out, "  \"uncertain\": [");
  for (int j = 0; j < unc->n; ++j) {
    const pom_dist *d = &unc->param[j].dist;
    fprintf(out, "%s\n    {\"key\": ", j ? "," : "");
    json_string(out, unc->param[j].key);
    fprintf(out, ", \"dist\": \"%s\", \"relative\": %s, \"parameters\": [", d->ops->name,
            unc->param[j].relative ? "true" : "false");
    for (int i = 0; i < 4; ++i) {
      fprintf(out, "%s", i ? ", " : "");
      json_double(out, d->p[i]);
    }
    fprintf(out, "], \"lo\": ");
    json_double(out, d->lo);
    fprintf(out, ", \"hi\": ");
    json_double(out, d->hi);
    fprintf(out, "}");
  }
  fprintf(out, "%s],\n", unc->n ? "\n  " : "");
}

static void json_metrics(FILE *out) {
  fprintf(out, "  \"metrics\": [\n");
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    const pom_dyn_metric_info *mi = &schema[j];
    fprintf(out, "    {\"name\": \"%s\", \"unit\": \"%s\", \"per_actuator\": %s, ", mi->name,
            mi->unit == POM_DYN_UNIT_ACTUATOR ? "actuator_unit"
                                              : pom_dyn_metric_unit(mi, POM_ACT_PRISMATIC),
            mi->count == 3 ? "true" : "false");
    fprintf(out, "\"reduced\": %s, \"description\": ", mi->stat_key ? "true" : "false");
    json_string(out, mi->description);
    if (mi->stat_key) fprintf(out, ", \"statistics\": \"%s\"", mi->stat_key);
    fprintf(out, "}%s\n", j + 1 < POM_DYN_N_METRICS ? "," : "");
  }
  fprintf(out, "  ],\n");
}

void pom_job_print_json(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  fprintf(out, "{\n  \"study\": ");
  json_string(out, study->name);
  fprintf(out, ",\n  \"maneuvers\": %ld,\n  \"seed\": %llu,\n", rep->n_maneuvers,
          (unsigned long long)study->maneuvers.seed);
  json_montecarlo(out, study);
  json_uncertain(out, study);
  json_metrics(out);
  /* the primary time metric: the comparisons, Friedman and ranking of
   * "execution_time" use it, unsettled times censored at the horizon */
  fprintf(out, "  \"time_metric\": \"%s\",\n",
          study->time_metric == POM_DOE_TIME_POINTING ? "pointing_settling_time"
                                                      : "execution_time");
  /* the sweep factors (dotted config keys), one value per candidate below */
  fprintf(out, "  \"factors\": [");
  for (int f = 0; f < study->n_factors; ++f) {
    fprintf(out, "%s", f ? ", " : "");
    json_string(out, study->factor_key[f]);
  }
  fprintf(out, "],\n");
  fprintf(out, "  \"candidates\": [\n");
  for (int c = 0; c < rep->n_candidates; ++c) {
    const pom_doe_candidate_stats *cs = &rep->cand[c];
    fprintf(out, "    {\"name\": ");
    json_string(out, study->candidates[c].name);
    const pom_act_desc *u = pom_act_kind_desc(study->candidates[c].eval.actuator_kind);
    fprintf(out,
            ", \"actuator_kind\": \"%s\", \"actuator_unit\": \"%s\", \"done\": %ld, "
            "\"failed\": %ld, \"unsettled\": %ld, \"censored\": %ld",
            u->kind_name, u->si, cs->n_done, cs->n_failed, cs->n_unsettled, cs->n_censored);
    fprintf(out, ", \"factors\": {");
    for (int f = 0; f < study->candidates[c].n_factors; ++f) {
      fprintf(out, "%s", f ? ", " : "");
      json_string(out, study->candidates[c].factor_key[f]);
      fprintf(out, ": ");
      json_double(out, study->candidates[c].factor_value[f]);
    }
    fprintf(out, "}");
    /* the validity rule's count: null where not measured (rigid joints) */
    if (cs->n_validity > 0)
      fprintf(out, ", \"rigid_limit_flagged\": %ld, \"rigid_limit_checked\": %ld",
              cs->n_rigid_limit, cs->n_validity);
    else
      fprintf(out, ", \"rigid_limit_flagged\": null, \"rigid_limit_checked\": 0");
    pom_job_fidelity_json(out, &study->candidates[c]);
    pom_job_capability_json(out, study, &study->candidates[c]);
    /* the statistics of every reduced metric of the schema */
    for (int s = 0; s < POM_DYN_N_STATS; ++s) {
      fprintf(out, ",\n     ");
      json_stats(out, pom_dyn_stat_metric(s)->stat_key, &cs->stat[s]);
    }
    fprintf(out, "}%s\n", c + 1 < rep->n_candidates ? "," : "");
  }
  fprintf(out, "  ],\n  \"comparisons\": [\n");
  for (int j = 0; j < rep->n_comparisons; ++j) {
    const pom_doe_comparison *c = &rep->cmp[j];
    fprintf(out,
            "    {\"a\": %d, \"b\": %d, \"metric\": \"%s\", \"pairs\": %ld, \"mean_diff\": ", c->a,
            c->b, c->metric == POM_DOE_METRIC_TIME ? "execution_time_s" : "energy_J", c->test.n);
    json_double(out, c->test.mean_diff);
    fprintf(out, ", \"ci\": [");
    json_double(out, c->test.ci_low);
    fprintf(out, ", ");
    json_double(out, c->test.ci_high);
    fprintf(out, "], \"wilcoxon_p\": ");
    json_double(out, c->test.wilcoxon_p);
    fprintf(out, ", \"holm_p\": ");
    json_double(out, c->p_holm);
    fprintf(out, ", \"win_fraction\": ");
    json_double(out, c->test.win_fraction);
    fprintf(out, ", \"tie_fraction\": ");
    json_double(out, c->test.tie_fraction);
    fprintf(out, ", \"censored_a\": %ld, \"censored_b\": %ld}%s\n", c->censored_a, c->censored_b,
            j + 1 < rep->n_comparisons ? "," : "");
  }
  fprintf(out, "  ],\n  \"comparison_pairs\": \"%s\",\n  \"friedman\": {",
          rep->all_pairs ? "all" : "best_against_each");
  for (int m = 0; m < 2; ++m) {
    const pom_doe_friedman_result *f = &rep->friedman[m];
    fprintf(out, "%s\"%s\": {\"maneuvers\": %ld, \"chi_square\": ", m ? ", " : "",
            m == 0 ? "execution_time" : "energy", f->n_blocks);
    json_double(out, f->statistic);
    fprintf(out, ", \"df\": %.0f, \"p\": ", f->df);
    json_double(out, f->p);
    if (m == 0) fprintf(out, ", \"censored\": %ld", rep->friedman_censored);
    fprintf(out, "}");
  }
  fprintf(out, "},\n  \"ranking\": {");
  for (int m = 0; m < 2; ++m) {
    const int *order = m == 0 ? rep->rank_time : rep->rank_energy;
    fprintf(out, "%s\"%s\": [", m ? ", " : "", m == 0 ? "execution_time" : "energy");
    for (int r = 0; r < rep->n_ranked; ++r) {
      if (r) fprintf(out, ", ");
      json_string(out, study->candidates[order[r]].name);
    }
    fprintf(out, "]");
  }
  fprintf(out, "}");
  pom_job_capability_excluded_json(out, study, rep);
  fprintf(out, "\n}\n");
}

/* ---- summary.md and figures ------------------------------------------------------------- */
/* results/paper.h5 -> results/paper (the folder of the summary and figures);
 * a file name without extension gets "_summary" appended instead, so that the
 * folder never has the results file's own name. */
void pom_job_summary_dir(char *dir, size_t cap, const char *output) {
  snprintf(dir, cap, "%s", output);
  char *dot = strrchr(dir, '.');
  char *slash = strrchr(dir, '/');
  if (dot && (!slash || dot > slash + 1) && dot > dir)
    *dot = '\0';
  else
    snprintf(dir, cap, "%s_summary", output);
}

int pom_job_run_script(const char *scripts_dir, const char *name, const char *a1, const char *a2,
                       FILE *msg) {
  char script[1100];
  snprintf(script, sizeof script, "%s/%s", scripts_dir ? scripts_dir : POM_JOB_SCRIPTS_DIR, name);
  char *argv[] = {"/usr/bin/python3", script, (char *)a1, (char *)a2, NULL};
  pid_t pid;
  int e = posix_spawn(&pid, argv[0], NULL, NULL, argv, environ);
  if (e != 0) {
    if (msg)
      fprintf(msg, "pomlab: warning: figures not made: cannot run %s: %s\n", argv[0], strerror(e));
    return -1;
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* The model fidelity of a candidate as resolved (joints, coil), so that a
 * summary tells apart studies that differ only by their overrides. */
static void model_text(const pom_doe_candidate *cand, char *buf, size_t cap) {
  snprintf(buf, cap, "-");
  if (!cand->resolved) return;
  pom_cfg *cfg = NULL;
  pom_error e;
  pom_error_clear(&e);
  pom_dyn_params par;
  pom_dyn_params_defaults(&par);
  if (pom_cfg_load_string(&cfg, cand->resolved, cand->name, &e) == POM_OK &&
      pom_dyn_params_load(&par, cfg, &e) == POM_OK) {
    if (par.joints.model == POM_JOINTS_PARASITIC)
      snprintf(buf, cap, "parasitic joints (k_p %g N/m), %s coil", par.joints.stiffness,
               par.scene.coil_inductance ? "inductive" : "quasi-static");
    else
      snprintf(buf, cap, "%s joints, %s coil", pom_dyn_joint_model_name(par.joints.model),
               par.scene.coil_inductance ? "inductive" : "quasi-static");
  }
  pom_cfg_destroy(cfg);
}

/* The metrics stored per maneuver (the schema), for the reader of the
 * results file. */
static void write_metric_listing(FILE *f) {
  fprintf(f, "\n### Metrics per maneuver (`/candidates/<c>/maneuvers`)\n\n"
             "| metric | unit (SI) | shape | statistics | description |\n"
             "|---|---|---|---|---|\n");
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    const pom_dyn_metric_info *mi = &schema[j];
    char stat[160] = "-";
    if (mi->stat_name)
      snprintf(stat, sizeof stat, "`%s` (%s%s%s)", mi->stat_name,
               mi->combine == POM_DYN_COMBINE_NONE ? "" : pom_dyn_combine_name(mi->combine),
               mi->combine == POM_DYN_COMBINE_NONE ? "" : " over actuators, ",
               mi->reduce == POM_DYN_REDUCE_SETTLED ? "settled maneuvers" : "ok maneuvers");
    fprintf(f, "| `%s` | %s | %s | %s | %s |\n", mi->name,
            mi->unit == POM_DYN_UNIT_ACTUATOR ? "actuator (m or rad)"
                                              : pom_dyn_metric_unit(mi, POM_ACT_PRISMATIC),
            mi->count == 3 ? "per actuator" : "scalar", stat, mi->description);
  }
}

static pom_status write_summary(const pom_doe_study *study, const pom_doe_report *rep,
                                const char *output, double wall, int threads, int ranks,
                                int plots_ok, const char *dir, const pom_job_options *o,
                                pom_error *err) {
  char path[1200];
  snprintf(path, sizeof path, "%s/summary.md", dir);
  pom_io_file w;
  POM_TRY(pom_io_create(&w, path, err));
  FILE *f = w.f;
  char when[64];
  time_t now = time(NULL);
  struct tm tmv;
  gmtime_r(&now, &tmv);
  strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", &tmv);
  fprintf(f, "# Study `%s`\n\n", study->name);
  fprintf(f, "- config: `%s`; results file: `%s`\n", study->source, output);
  fprintf(f, "- pomlab %s (commit %s), %s\n", POM_VERSION, POM_GIT_COMMIT, when);
  int mixed = 0;
  const pom_act_desc *u = pom_act_kind_desc(pom_job_study_kind(study, &mixed));
  if (study->maneuvers.space == POM_DOE_SPACE_JOINT)
    fprintf(f,
            "- %d candidate%s x %ld maneuvers, seed %llu, targets %s within +-%.3g %s of "
            "mid-stroke (common to every candidate)\n",
            study->n_candidates, study->n_candidates == 1 ? "" : "s", study->maneuvers.count,
            (unsigned long long)study->maneuvers.seed,
            study->maneuvers.distribution == POM_DOE_DIST_UNIFORM ? "uniform per actuator"
                                                                  : "truncated normal",
            study->maneuvers.range * u->to_display, u->display);
  else
    fprintf(f,
            "- %d candidate%s x %ld maneuvers, seed %llu, targets from tilt/torsion via IK (tilt "
            "up to %.3g deg, torsion up to +-%.3g deg; the orientations are common to every "
            "candidate%s)\n",
            study->n_candidates, study->n_candidates == 1 ? "" : "s", study->maneuvers.count,
            (unsigned long long)study->maneuvers.seed, study->maneuvers.tilt_max / POM_DEG,
            study->maneuvers.torsion_max / POM_DEG, mixed ? ", which mix actuator kinds" : "");
  fprintf(f, "- this run: %.2f s wall, %d worker thread(s) x %d MPI rank(s)\n\n", wall, threads,
          ranks);
  fprintf(f, "| candidate | config | actuators | model (after the study's overrides) |\n"
             "|---|---|---|---|\n");
  for (int c = 0; c < study->n_candidates; ++c) {
    char model[160];
    model_text(&study->candidates[c], model, sizeof model);
    const pom_act_desc *cu = pom_act_kind_desc(study->candidates[c].eval.actuator_kind);
    fprintf(f, "| %s | `%s` | %s (q in %s) | %s |\n", study->candidates[c].name,
            study->candidates[c].source, cu->kind_name, cu->display, model);
  }
  fprintf(f, "\n");
  if (o->pipeline) pom_job_pipeline_report(f, study);
  pom_job_print_report(f, study, rep);
  pom_job_fidelity_report(f, study, rep);
  pom_job_capability_report(f, study);
  write_metric_listing(f);
  if (plots_ok) {
    /* the figures scripts/plot_study.py made for this study (it removes the
     * ones the study does not call for) */
    static const char *const figures[][2] = {{"execution time", "execution_time.png"},
                                             {"expended energy", "energy.png"},
                                             {"paired differences", "paired.png"},
                                             {"main effects", "main_effects.png"},
                                             {"heat map", "heatmap.png"},
                                             {"Pareto front", "pareto.png"}};
    fprintf(f, "\n### Figures\n");
    for (size_t j = 0; j < sizeof figures / sizeof figures[0]; ++j) {
      char fig[1300];
      struct stat sb;
      snprintf(fig, sizeof fig, "%s/%s", dir, figures[j][1]);
      if (stat(fig, &sb) == 0) fprintf(f, "\n![%s](%s)\n", figures[j][0], figures[j][1]);
    }
  }
  return pom_io_commit(&w, err);
}

/* ---- options ----------------------------------------------------------------------------------
 */
void pom_job_options_defaults(pom_job_options *o) {
  memset(o, 0, sizeof *o);
  pom_doe_run_options_defaults(&o->run);
  o->command = "study";
  o->summary = 1;
  o->plots = 1;
}

/* Messages of this process: only rank 0 prints. */
static FILE *job_msg(const pom_job_options *o) {
  return o->rank == 0 ? o->msg : NULL;
}

static const char *job_output(const pom_doe_study *study, const pom_job_options *o) {
  return o->run.output ? o->run.output : study->output;
}

static const char *job_tabular(const pom_doe_study *study, const pom_job_options *o) {
  return o->tabular ? o->tabular : study->tabular;
}

/* A status for an exit code of the path checks (2: a refused path, 1: a
 * folder that cannot be made or written, or no memory). */
static pom_status path_status(int rc, pom_error *err) {
  if (rc == 0) return POM_OK;
  if (err && err->status != POM_OK) return err->status;
  return rc == 2 ? POM_ERR_CONFIG : POM_ERR_IO;
}

/* ---- paths ---------------------------------------------------------------------------------- */
pom_job_paths *pom_job_inputs(const char *command, const char *cfg_path,
                              const pom_doe_study *study) {
  pom_job_paths *p = pom_job_paths_create(command);
  if (!p) return NULL;
  pom_job_paths_config(p, cfg_path, "the config");
  for (int c = 0; c < study->n_candidates; ++c) {
    char what[POM_DOE_NAME_LEN + 32];
    snprintf(what, sizeof what, "the config of candidate '%s'", study->candidates[c].name);
    pom_job_paths_config(p, study->candidates[c].source, what);
  }
  return p;
}

/* No output may overwrite an input or another output; then the tabular
 * file's name and folder. */
static pom_status check_paths(const pom_doe_study *study, const pom_job_options *o,
                              pom_error *err) {
  FILE *msg = job_msg(o);
  const char *command = o->command ? o->command : "study";
  const char *cfg_path = o->cfg_path ? o->cfg_path : study->source;
  const char *output = job_output(study, o), *tabular = job_tabular(study, o);
  const char *out_key = o->output_key ? o->output_key : "--out";
  const char *tab_origin =
      o->tabular ? (o->tabular_key ? o->tabular_key : "--tabular") : "study.tabular";
  if (tabular[0] && !output[0])
    return pom_job_say(msg, err, POM_ERR_ARG, "",
                       "tabular results '%s' need a results file (%s FILE.h5): the maneuver "
                       "rows are read back from it",
                       tabular, out_key);
  pom_job_paths *p = pom_job_inputs(command, cfg_path, study);
  char partial[POM_DOE_PATH_LEN + 16], summary[1200], cand[POM_DOE_PATH_LEN + 32], what[64];
  snprintf(what, sizeof what, "the results file (%s)", o->run.output ? out_key : "study.output");
  pom_job_paths_output(p, output, what);
  if (output[0]) {
    pom_doe_results_partial_path(partial, sizeof partial, output);
    pom_job_paths_output(p, partial, "the unfinished results file");
    /* and the results' lock (pom_doe_results takes OUTPUT.lock, truncating
     * it: a config of that name would be lost) */
    char lock[POM_DOE_PATH_LEN + 8];
    snprintf(lock, sizeof lock, "%s.lock", output);
    pom_job_paths_output(p, lock, "the lock file");
    if (o->summary) {
      pom_job_summary_dir(summary, sizeof summary - 12, output);
      strcat(summary, "/summary.md");
      pom_job_paths_output(p, summary, "the summary");
    }
  }
  if (tabular[0]) {
    snprintf(what, sizeof what, "the tabular file (%s)", tab_origin);
    pom_job_paths_output(p, tabular, what);
    pom_doe_tabular_candidates_path(cand, sizeof cand, tabular);
    snprintf(what, sizeof what, "the candidates table (%s)", tab_origin);
    pom_job_paths_output(p, cand, what);
  }
  int rc = pom_job_paths_check(p, msg, err);
  pom_job_paths_destroy(p);
  /* then the tabular file's name and folder (made now, as --out's is) */
  if (!rc) rc = pom_job_tabular_check(command, tab_origin, tabular, msg, err);
  return path_status(rc, err);
}

/* ---- cost ----------------------------------------------------------------------------------- */
/* Runs at or above which the time is measured and announced when long. */
#define ANNOUNCE_MIN_RUNS 64
/* Announced: over 10 s, or over 1 GB of memory or of results file. */
#define ANNOUNCE_SECONDS 10.0
#define ANNOUNCE_BYTES   1e9

static pom_status check_memory(const pom_doe_study *study, const pom_job_options *o,
                               pom_error *err) {
  const char *command = o->command ? o->command : "study";
  pom_doe_cost cost;
  pom_doe_cost_study(&cost, study, job_output(study, o)[0] != '\0');
  double limit = pom_doe_memory_limit();
  if (!(cost.memory > limit)) return POM_OK;
  char need[32], have[32];
  return pom_job_say(job_msg(o), err, POM_ERR_CONFIG, command,
                     "config: %s: %d candidate(s) x %ld maneuvers = %.4g runs need about %s of "
                     "memory (%.0f bytes per run), more than this machine's %s: lower "
                     "montecarlo.maneuvers%s or the number of candidates (the `candidates` "
                     "list, the levels of its sweep factors); nothing was run",
                     study->source, study->n_candidates, study->maneuvers.count, cost.runs,
                     pom_job_bytes_text(need, sizeof need, cost.memory), cost.per_run,
                     pom_job_bytes_text(have, sizeof have, limit),
                     strcmp(command, "montecarlo") == 0 ? " (--n)" : "");
}

pom_status pom_job_check(const pom_doe_study *study, const pom_job_options *o, pom_error *err) {
  POM_TRY(check_paths(study, o, err));
  /* and a study too large for memory is refused with the keys that size it */
  return check_memory(study, o, err);
}

void pom_job_announce(const pom_doe_study *study, const pom_job_options *o) {
  FILE *msg = job_msg(o);
  if (o->quiet || !msg) return;
  const char *command = o->command ? o->command : "study";
  pom_doe_cost cost;
  pom_doe_cost_study(&cost, study, job_output(study, o)[0] != '\0');
  double per_run = NAN;
  pom_error err;
  pom_error_clear(&err);
  if (cost.runs >= ANNOUNCE_MIN_RUNS) pom_doe_calibrate(&per_run, study, &err);
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  int threads = o->run.threads > 0   ? o->run.threads
                : study->threads > 0 ? study->threads
                                     : (int)(cores > 0 ? cores : 1);
  double seconds = per_run * cost.runs / threads;
  if (!(seconds > ANNOUNCE_SECONDS) && !(cost.memory > ANNOUNCE_BYTES) &&
      !(cost.file > ANNOUNCE_BYTES))
    return;
  char mem[32], file[32], how_long[48];
  fprintf(msg, "pomlab %s: %s: %d candidate(s) x %ld maneuvers = %.4g runs; memory about %s",
          command, study->name, study->n_candidates, study->maneuvers.count, cost.runs,
          pom_job_bytes_text(mem, sizeof mem, cost.memory));
  if (cost.file > 0)
    fprintf(msg, ", results file about %s", pom_job_bytes_text(file, sizeof file, cost.file));
  if (isfinite(seconds))
    fprintf(msg, "; %s on %d thread(s) (%.3g ms per run, measured on a few runs)",
            pom_job_duration_text(how_long, sizeof how_long, seconds), threads, per_run * 1e3);
  fprintf(msg, "\n");
}

/* ---- the pipeline and the earned fidelity ------------------------------------------------ */
static void fidelity_progress(void *user, const pom_doe_candidate *cand, int done, int total) {
  FILE *msg = user;
  const pom_fidelity_result *f = &cand->fidelity;
  fprintf(msg,
          "fidelity [%d/%d] %s: %s (%s; selected %.2e / %.2e, validated bound %.2e / %.2e in "
          "time / energy; %.1f s)\n",
          done, total, cand->name, f->setting.label, f->met ? "within the accuracy" : "NOT within",
          f->select_time, f->select_energy, f->bound_time, f->bound_energy, f->wall);
}

static void capability_progress(void *user, const pom_doe_candidate *cand, int done, int total) {
  fprintf(user, "capability [%d/%d] %s\n", done, total, cand->name);
}

pom_status pom_job_prepare(pom_doe_study *study, const pom_job_options *o, pom_error *err) {
  FILE *msg = job_msg(o);
  /* the pipeline's files go with the summary: results/x.h5 -> results/x/ */
  const char *output = job_output(study, o);
  char prefix[1200] = "results/pipeline_";
  if (output[0]) {
    pom_job_summary_dir(prefix, sizeof prefix - 1, output);
    strcat(prefix, "/");
  }
  pom_job_phases bars;
  pom_job_phases_init(&bars, !o->quiet ? msg : NULL);
  pom_pipeline_options po;
  memset(&po, 0, sizeof po);
  po.output_prefix = prefix;
  po.no_files = o->rank != 0;
  po.progress = pom_job_phases_report;
  po.progress_user = &bars;
  pom_status st = pom_pipeline_run(study, &po, err);
  pom_job_phases_end(&bars);
  if (st != POM_OK) {
    pom_job_report_error(msg, "pipeline", err);
    return st;
  }
  /* study.capability: each candidate's figures, on the geometry and gains
     the pipeline made, before the fidelity changes its model's settings */
  if (study->capability_n > 0) {
    st = pom_doe_capability_run(study, !o->quiet && msg ? capability_progress : NULL, msg, err);
    if (st != POM_OK) {
      pom_job_report_error(msg, "capability", err);
      return st;
    }
  }
  /* study.fidelity = "auto": each candidate's setting, after its tuning
     (docs/results.md section 12) */
  if (study->fidelity_auto) {
    st = pom_doe_fidelity_run(study, !o->quiet && msg ? fidelity_progress : NULL, msg, err);
    if (st != POM_OK) {
      pom_job_report_error(msg, "fidelity", err);
      return st;
    }
  }
  return POM_OK;
}

/* ---- the job ----------------------------------------------------------------------------- */
pom_status pom_job_run(pom_doe_study *study, const pom_job_options *o, pom_job_result *res,
                       pom_error *err) {
  pom_job_options opts = *o;
  if (!(opts.t_start > 0)) opts.t_start = pom_progress_now();
  /* no output may overwrite an input or another output: refused before any
     work, the pipeline's included (docs/results.md, "Output paths") */
  POM_TRY(pom_job_check(study, &opts, err));
  /* candidates whose config asks for it are synthesized and tuned first
     (synthesis/tuning.run_in_study, docs/optimize.md 10) */
  if (opts.pipeline) POM_TRY(pom_job_prepare(study, &opts, err));
  /* runs, memory, file size and time, said before a long run starts */
  pom_job_announce(study, &opts);
  return pom_job_execute(study, &opts, res, err);
}

int pom_job_exit_code(pom_status st, const pom_job_result *res) {
  if (res && res->interrupted) return 130;
  if (st == POM_OK) return 0;
  if (st == POM_ERR_CONFIG || st == POM_ERR_ARG) return 2;
  return 1;
}

/* ---- run ------------------------------------------------------------------------------------ */
/* Keeps the first failure: the later steps still run. */
static void keep_first(pom_status *first, pom_error *err, pom_status st, const pom_error *e) {
  if (st == POM_OK || *first != POM_OK) return;
  *first = st;
  if (err) *err = *e;
}

pom_status pom_job_execute(const pom_doe_study *study, const pom_job_options *o,
                           pom_job_result *res, pom_error *err) {
  pom_job_result local;
  if (!res) res = &local;
  memset(res, 0, sizeof *res);
  FILE *msg = job_msg(o), *out = o->rank == 0 ? o->out : NULL;
  pom_error e;
  pom_error_clear(&e);
  pom_doe_run *run = NULL;
  pom_doe_report *rep = NULL;
  const char *output = job_output(study, o), *tabular = job_tabular(study, o);
  if (tabular[0] && !output[0])
    return pom_job_say(msg, err, POM_ERR_ARG, "",
                       "tabular results '%s' need a results file (%s FILE.h5): the maneuver "
                       "rows are read back from it",
                       tabular, o->output_key ? o->output_key : "--out");
  double t0 = o->t_start > 0 ? o->t_start : pom_progress_now();
  pom_status st = pom_doe_run_begin(&run, study, &o->run, &e);
  if (st != POM_OK) {
    pom_job_report_error(msg, "study", &e);
    if (err) *err = e;
    return st;
  }
  int root = pom_doe_run_is_root(run);
  struct sigaction sa, old_int, old_term;
  if (o->signals) {
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    interrupted = 0;
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
  }

  pom_progress bar;
  pom_progress_init(&bar, root && !o->quiet ? msg : NULL, study->name, pom_doe_run_total(run),
                    pom_doe_run_start_done(run), 0);
  int finished = 0, cancelled = 0;
  while (!finished && st == POM_OK) {
    st = pom_doe_run_step(run, &finished, &e);
    if (((o->signals && interrupted) || (o->cancel && *o->cancel)) && !cancelled) {
      pom_doe_run_cancel(run);
      cancelled = 1;
    }
    pom_progress_update(&bar, pom_doe_run_done(run));
  }
  pom_progress_finish(&bar, pom_doe_run_done(run));
  if (o->signals) {
    sigaction(SIGINT, &old_int, NULL);
    sigaction(SIGTERM, &old_term, NULL);
  }
  if (st == POM_OK) st = pom_doe_run_end(run, &rep, &e);
  long done = pom_doe_run_done(run), total = pom_doe_run_total(run);
  int threads = pom_doe_run_threads(run), ranks = pom_doe_run_ranks(run);
  pom_doe_run_destroy(run);
  double wall = pom_progress_now() - t0;
  res->done = done;
  res->total = total;
  res->threads = threads;
  res->ranks = ranks;
  res->wall = wall;
  if (st != POM_OK) {
    pom_job_report_error(msg, "study", &e);
    if (err) *err = e;
    pom_doe_report_destroy(rep);
    return st;
  }
  if (!root) {
    pom_doe_report_destroy(rep);
    return POM_OK;
  }
  pom_status first = POM_OK;
  /* an unfinished study stays in OUTPUT.partial (docs/results.md) */
  char partial[POM_DOE_PATH_LEN + 16];
  pom_doe_results_partial_path(partial, sizeof partial, output);
  const char *h5 = done < total ? partial : output;
  if (output[0]) snprintf(res->results, sizeof res->results, "%s", h5);
  if (done < total) {
    if (msg)
      fprintf(msg,
              "pomlab: study %s: stopped after %ld of %ld candidate-maneuvers; every finished one "
              "is in %s; continue with --resume\n",
              study->name, done, total, output[0] ? h5 : "(no file)");
    res->interrupted = cancelled;
  }
  if (msg && study->n_requirements > 0 && rep->n_ranked == 0)
    fprintf(msg, "pomlab: warning: no candidate meets study.capability_require: nothing is "
                 "ranked (the report lists each one's failed requirement)\n");
  if (out && o->json) {
    pom_job_print_json(out, study, rep);
  } else if (out) {
    if (study->n_candidates == 1)
      fprintf(out, "## Study %s: %s, %ld maneuvers (%.2f s wall, %d thread(s) x %d rank(s))\n\n",
              study->name, study->candidates[0].name, study->maneuvers.count, wall, threads, ranks);
    else
      fprintf(out,
              "## Study %s: %d candidates x %ld maneuvers (%.2f s wall, %d thread(s) x %d "
              "rank(s))\n\n",
              study->name, study->n_candidates, study->maneuvers.count, wall, threads, ranks);
    if (o->pipeline) pom_job_pipeline_report(out, study);
    pom_job_print_report(out, study, rep);
    pom_job_fidelity_report(out, study, rep);
    pom_job_capability_report(out, study);
  }
  if (tabular[0]) {
    char cand[POM_DOE_PATH_LEN + 32];
    pom_doe_tabular_candidates_path(cand, sizeof cand, tabular);
    pom_error_clear(&e);
    st = pom_doe_tabular_write(study, rep, output, tabular, &e);
    if (st != POM_OK) {
      pom_job_report_error(msg, "tabular", &e);
      keep_first(&first, err, st, &e);
    } else if (out && !o->json) {
      fprintf(out, "\nTabular: %s (candidate x maneuver), %s (candidate)\n", tabular, cand);
    }
  }
  if (output[0] && (o->summary || o->plots)) {
    char dir[1100];
    pom_job_summary_dir(dir, sizeof dir, output);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
      pom_error_clear(&e);
      pom_job_say(msg, &e, POM_ERR_IO, "", "cannot create %s: %s", dir, strerror(errno));
      keep_first(&first, err, POM_ERR_IO, &e);
    } else {
      int plots_ok = 0;
      if (o->plots) {
        int r = pom_job_run_script(o->scripts_dir, "plot_study.py", h5, dir, msg);
        plots_ok = r == 0;
        /* the script's own message (a missing module, a full disk) is above */
        if (!plots_ok && r >= 0 && msg)
          fprintf(msg,
                  "pomlab: warning: figures not made: scripts/plot_study.py exited with %d (its "
                  "message is above)\n",
                  r);
      }
      pom_error_clear(&e);
      if (o->summary) {
        st = write_summary(study, rep, h5, wall, threads, ranks, plots_ok, dir, o, &e);
        if (st != POM_OK) {
          pom_job_report_error(msg, "summary", &e);
          keep_first(&first, err, st, &e);
        } else {
          snprintf(res->summary, sizeof res->summary, "%s/summary.md", dir);
          if (out && !o->json)
            fprintf(out, "\nSummary: %s/summary.md%s\n", dir, plots_ok ? " (with figures)" : "");
        }
      }
    }
  }
  pom_doe_report_destroy(rep);
  return first;
}
