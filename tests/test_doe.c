/* test_doe.c - the Monte-Carlo runner with a cheap analytic evaluator:
 * statistics against hand-computed values, common random numbers,
 * bit-identical results on 1 and N threads, interrupt + resume, failures
 * recorded, config validation, sweeps. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"
#include "pom_run.h"
#include "study_internal.h"
#include "pom_math.h"
#include "pom_progress.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- analytic evaluator ---------------------------------------------------------
 * Actuator i moves at constant speed v after a dead time t0: settling time
 * t0 + |q_i| / v (unsettled beyond the 100 ms horizon), energy c q_i^2.
 * Maneuvers with q_0 above fail_above fail on purpose. */
typedef struct {
  double speed;       /* m/s */
  double dead_time;   /* s */
  double energy_coef; /* J/m^2 */
  double fail_above;  /* m */
} analytic;

static int worker_count = 0; /* workers created (checked: one per thread per candidate) */

static pom_status an_worker_create(void **w, const void *ctx, pom_error *err) {
  (void)ctx, (void)err;
  int *state = malloc(sizeof *state);
  if (!state) return POM_ERR_NOMEM;
  *state = 0;
  *w = state;
  __atomic_add_fetch(&worker_count, 1, __ATOMIC_SEQ_CST);
  return POM_OK;
}

static void an_worker_destroy(void *w) {
  free(w);
}

static pom_status an_run(const void *p, void *w, const double q[3], pom_dyn_metrics *m,
                         pom_error *err) {
  const analytic *a = p;
  ++*(int *)w;
  memset(m, 0, sizeof *m);
  for (int i = 0; i < 3; ++i)
    m->target[i] = q[i];
  if (q[0] > a->fail_above) {
    m->status = POM_ERR_SOLVER;
    snprintf(m->reason, sizeof m->reason, "injected failure at q0 = %.3g mm", q[0] * 1e3);
    return pom_error_set(err, POM_ERR_SOLVER, __FILE__, __LINE__, "%s", m->reason);
  }
  double tmax = 0;
  int all = 1;
  for (int i = 0; i < 3; ++i) {
    double t = a->dead_time + fabs(q[i]) / a->speed;
    m->settled[i] = t < 0.1;
    all &= m->settled[i];
    m->settling_time[i] = m->settled[i] ? t : NAN;
    m->settling_time_final[i] = m->settling_time[i];
    m->energy[i] = a->energy_coef * q[i] * q[i];
    m->energy_positive[i] = m->energy[i];
    m->energy_total += m->energy[i];
    m->final_q[i] = q[i];
    tmax = fmax(tmax, t);
  }
  m->execution_time = all ? tmax : NAN;
  /* the platform: settles with the slowest actuator (the toy has no orientation) */
  m->horizon = 0.1;
  m->pointing_settled = all;
  m->pointing_settling_time = all ? tmax : NAN;
  m->energy_supplied = m->energy_total; /* as the metric schema defines it */
  m->steps = 1;
  return POM_OK;
}

static pom_status an_targets(const void *p, const pom_doe_maneuver *mv, double q[3],
                             pom_error *err) {
  (void)p, (void)err;
  /* a toy IK: actuator i sees the rotation vector's component i times 15 mm */
  double rv[3];
  pom_m3_rotvec(rv, mv->R);
  for (int i = 0; i < 3; ++i)
    q[i] = 0.015 * rv[i];
  return POM_OK;
}

static void an_destroy(void *p) {
  free(p);
}

static pom_status an_factory(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                             pom_error *err) {
  static const char *const scopes[] = {"analytic", NULL};
  (void)user;
  analytic *a = calloc(1, sizeof *a);
  if (!a) return POM_ERR_NOMEM;
  pom_status st = pom_cfg_real(cfg, "analytic.speed_m_per_s", 1.0, 1e-6, 1e3, &a->speed, err);
  if (st == POM_OK)
    st = pom_cfg_real_opt(cfg, "analytic.dead_time_ms", 1e-3, 0, 1e3, 0.002, &a->dead_time, err);
  if (st == POM_OK)
    st =
        pom_cfg_real_opt(cfg, "analytic.energy_J_per_mm2", 1e6, 0, 1e3, 0.01, &a->energy_coef, err);
  if (st == POM_OK)
    st = pom_cfg_real_opt(cfg, "analytic.fail_above_mm", 1e-3, -1e3, 1e3, 1.0, &a->fail_above, err);
  if (st == POM_OK) st = pom_cfg_check_unknown(cfg, scopes, NULL, err);
  if (st != POM_OK) {
    free(a);
    return st;
  }
  memset(eval, 0, sizeof *eval);
  eval->ctx = a;
  eval->ctx_destroy = an_destroy;
  eval->worker_create = an_worker_create;
  eval->worker_destroy = an_worker_destroy;
  eval->run = an_run;
  eval->targets = an_targets;
  return POM_OK;
}

/* ---- files ------------------------------------------------------------------------ */
static char tmpdir[256];

static void write_file(const char *name, const char *text) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  FILE *f = fopen(path, "w");
  if (!f) {
    printf("cannot write %s\n", path);
    exit(1);
  }
  fputs(text, f);
  fclose(f);
}

static pom_status load_study(pom_doe_study *study, const char *name, pom_error *err) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load(&cfg, path, err);
  if (st == POM_OK) st = pom_doe_study_load(study, cfg, an_factory, NULL, err);
  pom_cfg_destroy(cfg);
  return st;
}

/* ---- statistics -------------------------------------------------------------------- */
static void test_stats(void) {
  /* values chosen by hand; sorted: 0.75 1.25 2.385 3.5 4.125 (n = 5) */
  const double x[5] = {2.385, 4.125, 0.75, 3.5, 1.25};
  double s[5];
  pom_doe_stats st;
  pom_doe_stats_compute(&st, x, 5, s);
  double mean = (2.385 + 4.125 + 0.75 + 3.5 + 1.25) / 5;
  double ss = 0;
  for (int k = 0; k < 5; ++k)
    ss += (x[k] - mean) * (x[k] - mean);
  check_rel(st.mean, mean, 1e-15);
  check_rel(st.sigma, sqrt(ss / 4), 1e-14);
  check_abs(st.min, 0.75, 0);
  check_abs(st.max, 4.125, 0);
  check_abs(st.median, 2.385, 0);
  /* type-7 percentiles: h = 4 p; p25 -> h = 1 -> 1.25; p05 -> h = 0.2 ->
   * 0.75 + 0.2 (1.25 - 0.75) = 0.85; p95 -> h = 3.8 -> 3.5 + 0.8 (0.625) = 4.0 */
  check_abs(st.p25, 1.25, 1e-15);
  check_rel(st.p05, 0.85, 1e-14);
  check_rel(st.p95, 4.0, 1e-14);
  check_rel(st.p75, 3.5, 1e-15);
  pom_doe_stats_compute(&st, x, 0, s);
  check_true(st.n == 0 && isnan(st.mean));

  /* Wilcoxon, exact: 5 positive differences -> W+ = 15, p = 2 / 2^5 */
  double d[8] = {0.3, 1.1, 2.2, 0.7, 1.9, 0, 0, 0}, scr[16], w = 0;
  long used = 0;
  double p = pom_doe_wilcoxon(d, 5, &w, &used, scr);
  check_abs(w, 15, 0);
  check_rel(p, 2.0 / 32.0, 1e-15);
  /* signs + - + + - on ranks of |d| = 1..5: d sorted by |d|: 0.3(+) 0.7(-)
   * 1.1(+) 1.9(+) 2.2(-) -> W+ = 1 + 3 + 4 = 8 (mean 7.5): p from the exact
   * counts of subsets of {1..5} with sum <= 7 (= 16 of 32) and >= 8 (16): 1 */
  const double d2[5] = {0.3, -0.7, 1.1, 1.9, -2.2};
  p = pom_doe_wilcoxon(d2, 5, &w, &used, scr);
  check_abs(w, 8, 0);
  check_abs(p, 1.0, 1e-15);
  /* zeros are dropped: n_used counts the others */
  p = pom_doe_wilcoxon(d, 8, &w, &used, scr);
  check_true(used == 5);
  /* ties force the normal approximation: d = 1, 1, -1, 2 -> ranks of |d|:
   * 1,1,1 tie -> 2 each; 2 -> 4. W+ = 2 + 2 + 4 = 8, mean 5, var =
   * 4*5*9/24 - (27 - 3)/48 = 7.5 - 0.5 = 7; z = 3/sqrt(7) */
  const double d3[4] = {1, 1, -1, 2};
  p = pom_doe_wilcoxon(d3, 4, &w, &used, scr);
  check_abs(w, 8, 0);
  check_rel(p, erfc(3 / sqrt(7.0) / sqrt(2.0)), 1e-14);

  /* paired: a - b = constant 0.5 plus symmetric noise; t quantile for 9 df
   * at 0.975 is 2.2621571627409915 (tables) */
  double a[10], b[10], scratch[30];
  const double noise[10] = {0.1, -0.1, 0.2, -0.2, 0.05, -0.05, 0.3, -0.3, 0.0, 0.0};
  for (int k = 0; k < 10; ++k) {
    b[k] = 1.0 + 0.37 * k;
    a[k] = b[k] + 0.5 + noise[k];
  }
  pom_doe_paired pr;
  pom_doe_paired_compute(&pr, a, b, 10, 0.95, scratch);
  double var = 0;
  for (int k = 0; k < 10; ++k)
    var += noise[k] * noise[k];
  double se = sqrt(var / 9 / 10);
  check_rel(pr.mean_diff, 0.5, 1e-14);
  check_rel(pr.ci_high - pr.mean_diff, 2.2621571627409915 * se, 1e-9);
  check_rel(pr.mean_diff - pr.ci_low, 2.2621571627409915 * se, 1e-9);
  check_abs(pr.win_fraction, 0.0, 0); /* a > b everywhere */
  {
    /* ties are ties: a < b once, a == b twice, a > b once -> wins 1/4, ties
     * 2/4; the two zero differences are left out of the Wilcoxon test */
    const double ta[4] = {1, 2, 3, 4}, tb[4] = {2, 2, 1, 4};
    double tscr[12];
    pom_doe_paired tp;
    pom_doe_paired_compute(&tp, ta, tb, 4, 0.95, tscr);
    check_abs(tp.win_fraction, 0.25, 0);
    check_abs(tp.tie_fraction, 0.5, 0);
    check_true(tp.n == 4 && tp.n_nonzero == 2);
    /* identical candidates: every pair a tie, no win, p = 1 */
    pom_doe_paired_compute(&tp, ta, ta, 4, 0.95, tscr);
    check_abs(tp.win_fraction, 0.0, 0);
    check_abs(tp.tie_fraction, 1.0, 0);
    check_abs(tp.wilcoxon_p, 1.0, 0);
    check_true(tp.n_nonzero == 0);
  }
  /* 10 positive differences, two tied at 0.5 (ranks 5.5): normal
   * approximation, W+ = 55, mean 27.5, var = 10 11 21 / 24 - (8 - 2) / 48 */
  check_abs(pr.wilcoxon_w, 55, 0);
  check_rel(pr.wilcoxon_p, erfc(27.5 / sqrt(96.25 - 0.125) / sqrt(2.0)), 1e-13);
}

/* Friedman's test and Holm's adjustment on cases computed by hand. */
static void test_friedman_holm(void) {
  /* 4 blocks x 3 treatments, block 4 with a tie: ranks (1,2,3), (2,1,3),
   * (1,3,2), (1.5,1.5,3) -> R = (5.5, 7.5, 11), sum R^2 = 207.5;
   * 12 / (4 3 4) 207.5 - 3 4 4 = 3.875; tie term 2^3 - 2 = 6, C = 1 - 6 /
   * (4 3 8) = 0.9375; Q = 4.1333..., p = exp(-Q / 2) for 2 degrees of
   * freedom (scipy.stats.friedmanchisquare gives the same 4.133333333333334,
   * 0.12660710278908355) */
  const double x[12] = {1.2, 2.3, 3.4, 2.1, 1.7, 3.9, 0.5, 0.9, 0.7, 4.4, 4.4, 5.1};
  double scratch[12];
  pom_doe_friedman_result fr;
  pom_doe_friedman(&fr, x, 4, 3, scratch);
  check_rel(fr.statistic, 3.875 / 0.9375, 1e-14);
  check_rel(fr.p, exp(-0.5 * 3.875 / 0.9375), 1e-12);
  check_true(fr.n_blocks == 4 && fr.k == 3 && fr.df == 2);
  /* average ranks and the tie term of one block */
  double rank[3];
  check_abs(pom_doe_rank_average(rank, x + 9, 3, scratch), 6.0, 0);
  check_abs(rank[0], 1.5, 0);
  check_abs(rank[1], 1.5, 0);
  check_abs(rank[2], 3.0, 0);
  /* identical treatments: every block all ties, no statistic, p = 1 */
  const double same[6] = {2.385, 2.385, 1.25, 1.25, 0.5, 0.5};
  pom_doe_friedman(&fr, same, 3, 2, scratch);
  check_true(isnan(fr.statistic));
  check_abs(fr.p, 1.0, 0);
  /* Holm: sorted 0.005 0.01 0.03 0.04 -> 4 x 0.005 = 0.02, 3 x 0.01 = 0.03,
   * 2 x 0.03 = 0.06, max(1 x 0.04, 0.06) = 0.06; a large p is capped at 1 */
  const double p[5] = {0.01, 0.04, 0.03, 0.005, 0.6};
  double adj[5];
  size_t order[5];
  pom_doe_holm(adj, p, 4, order);
  check_rel(adj[0], 0.03, 1e-15);
  check_rel(adj[1], 0.06, 1e-15);
  check_rel(adj[2], 0.06, 1e-15);
  check_rel(adj[3], 0.02, 1e-15);
  /* five: 5 x 0.005, 4 x 0.01, 3 x 0.03, max(2 x 0.04, 0.09), 1 x 0.6 */
  pom_doe_holm(adj, p, 5, order);
  check_rel(adj[3], 0.025, 1e-15);
  check_rel(adj[1], 0.09, 1e-15);
  check_rel(adj[4], 0.6, 1e-15);
  /* 2 x 0.6 = 1.2 is capped at 1, and 0.7 inherits it */
  pom_doe_holm(adj, p + 4, 1, order);
  check_rel(adj[0], 0.6, 1e-15);
  const double big[2] = {0.7, 0.6};
  pom_doe_holm(adj, big, 2, order);
  check_abs(adj[0], 1.0, 0);
  check_abs(adj[1], 1.0, 0);
}

/* ---- maneuvers ------------------------------------------------------------------------ */
static void test_maneuvers(void) {
  pom_doe_maneuvers mv;
  pom_doe_maneuvers_defaults(&mv);
  check_true(mv.count == 1000);
  check_abs(mv.range, 3e-3, 0);
  /* the same (seed, k) gives the same targets, in any order */
  pom_doe_maneuver a, b;
  pom_doe_maneuver_draw(&a, &mv, 417);
  pom_doe_maneuver_draw(&b, &mv, 3);
  pom_doe_maneuver_draw(&b, &mv, 417);
  check_true(memcmp(a.q, b.q, sizeof a.q) == 0);
  pom_doe_maneuver_draw(&b, &mv, 418);
  check_true(a.q[0] != b.q[0]);
  /* uniform in [-3, 3] mm: mean within 4 standard errors of 0 (sigma of a
   * uniform = range / sqrt(3)); extremes inside the range */
  double sum = 0, lo = 1, hi = -1;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    pom_doe_maneuver_draw(&a, &mv, k);
    for (int i = 0; i < 3; ++i) {
      sum += a.q[i];
      lo = fmin(lo, a.q[i]);
      hi = fmax(hi, a.q[i]);
    }
  }
  check_abs(sum / (3.0 * n), 0, 4 * 3e-3 / sqrt(3.0) / sqrt(3.0 * n));
  check_true(lo >= -3e-3 && hi < 3e-3 && lo < -2.99e-3 && hi > 2.99e-3);
  /* truncated normal stays inside the range */
  mv.distribution = POM_DOE_DIST_NORMAL;
  mv.sigma = 2.5e-3;
  double amax = 0;
  for (int k = 0; k < 2000; ++k) {
    pom_doe_maneuver_draw(&a, &mv, k);
    for (int i = 0; i < 3; ++i)
      amax = fmax(amax, fabs(a.q[i]));
  }
  check_true(amax <= 3e-3 && amax > 2.9e-3);
  /* orientation space: R is a rotation with tilt (angle of R e_z from e_z) <=
   * tilt_max and the drawn tilt */
  mv.space = POM_DOE_SPACE_ORIENTATION;
  mv.tilt_max = 12.5 * POM_DEG;
  double worst_orth = 0, worst_tilt = 0;
  for (int k = 0; k < 500; ++k) {
    pom_doe_maneuver_draw(&a, &mv, k);
    double RtR[9];
    pom_m3_tmul(RtR, a.R, a.R);
    for (int j = 0; j < 9; ++j)
      worst_orth = fmax(worst_orth, fabs(RtR[j] - (j % 4 == 0)));
    double tilt = acos(fmin(1.0, a.R[8]));
    worst_tilt = fmax(worst_tilt, fabs(tilt - a.orient[1]));
    check_true(a.orient[1] <= mv.tilt_max + 1e-15);
    check_true(fabs(a.orient[2]) <= mv.torsion_max);
  }
  check_abs(worst_orth, 0, 1e-14);
  check_abs(worst_tilt, 0, 1e-7); /* acos near 1 loses half the digits */
}

/* ---- study files ---------------------------------------------------------------------- */
static const char *study_text =
    "name = \"toy\";\n"
    "montecarlo = { maneuvers = 37; seed = 4242; range_mm = 3.0; };\n"
    "study = { threads = 2; override = { analytic = { dead_time_ms = 1.5; }; }; };\n"
    "candidates = (\n"
    "  { name = \"fast\"; config = \"fast.cfg\"; },\n"
    "  { name = \"slow\"; config = \"fast.cfg\";\n"
    "    override = { analytic = { speed_m_per_s = 0.025; energy_J_per_mm2 = 0.03; }; }; }\n"
    ");\n";

static void test_study_config(void) {
  pom_error err;
  pom_doe_study study;
  pom_error_clear(&err);
  pom_status st = load_study(&study, "toy.cfg", &err);
  check_true(st == POM_OK);
  if (st != POM_OK) {
    printf("  %s\n", err.message);
    return;
  }
  check_true(study.n_candidates == 2);
  check_true(study.maneuvers.count == 37 && study.maneuvers.seed == 4242);
  check_true(strcmp(study.name, "toy") == 0);
  check_true(strcmp(study.output, "results/toy.h5") == 0);
  const analytic *fast = study.candidates[0].eval.ctx, *slow = study.candidates[1].eval.ctx;
  check_abs(fast->speed, 0.5, 0);
  check_abs(fast->dead_time, 1.5e-3, 1e-18);  /* study-wide override */
  check_abs(slow->speed, 0.025, 0);           /* candidate override */
  check_abs(slow->energy_coef, 0.03e6, 1e-9); /* J/mm^2 -> J/m^2 */
  check_true(strstr(study.candidates[1].resolved, "speed_m_per_s = 0.025") != NULL);
  pom_doe_study_clear(&study);

  /* errors stop before any work, naming the key */
  struct {
    const char *file, *text, *want;
  } bad[] = {
      {"bad1.cfg", "candidates = ( { name = \"a\"; config = \"fast.cfg\"; colour = 1; } );\n",
       "candidates.[0].colour"},
      {"bad2.cfg", "candidates = ( { name = \"a\"; config = \"missing.cfg\"; } );\n",
       "missing.cfg: cannot open"},
      {"bad3.cfg",
       "candidates = ( { name = \"a\"; config = \"fast.cfg\"; },\n"
       "               { name = \"a\"; config = \"fast.cfg\"; } );\n",
       "used twice"},
      {"bad4.cfg",
       "candidates = ( { name = \"a\"; config = \"fast.cfg\";\n"
       "  override = { analytic = { sped_m_per_s = 1.0; }; }; } );\n",
       "analytic.sped_m_per_s"},
      {"bad5.cfg",
       "montecarlo = { maneuvers = 0; };\n"
       "candidates = ( { name = \"a\"; config = \"fast.cfg\"; } );\n",
       "montecarlo.maneuvers"},
      {"bad6.cfg", "montecarlo = { maneuvers = 5; };\n", "candidates"},
      {"bad8.cfg",
       "solver = { rtol = 1.0e-6; };\n"
       "candidates = ( { name = \"a\"; config = \"fast.cfg\"; } );\n",
       "key 'solver'"},
      {"bad7.cfg",
       "candidates = ( { name = \"a\"; config = \"fast.cfg\"; } );\nstudy = { rank_by = \"x\"; "
       "};\n",
       "study.rank_by"},
  };
  for (size_t j = 0; j < sizeof bad / sizeof bad[0]; ++j) {
    write_file(bad[j].file, bad[j].text);
    pom_error_clear(&err);
    st = load_study(&study, bad[j].file, &err);
    check_true(st == POM_ERR_CONFIG || st == POM_ERR_IO);
    if (!check_true(strstr(err.message, bad[j].want) != NULL))
      printf("  %s: message '%s' lacks '%s'\n", bad[j].file, err.message, bad[j].want);
    if (st == POM_OK) pom_doe_study_clear(&study);
  }
}

static void test_sweep(void) {
  write_file(
      "sweep.cfg",
      "montecarlo = { maneuvers = 4; };\n"
      "candidates = { sweep = \"grid\";\n"
      "  base = ( { name = \"A\"; config = \"fast.cfg\"; } );\n"
      "  factors = ( { key = \"analytic.speed_m_per_s\"; min = 0.2; max = 0.6; levels = 3; },\n"
      "              { key = \"analytic.dead_time_ms\"; min = 1.0; max = 4.0; levels = 2; } );\n"
      "};\n");
  pom_error err;
  pom_doe_study study;
  pom_error_clear(&err);
  pom_status st = load_study(&study, "sweep.cfg", &err);
  if (!check_true(st == POM_OK)) {
    printf("  %s\n", err.message);
    return;
  }
  check_true(study.n_candidates == 6);
  /* last factor fastest: candidate 3 = speed level 1 (0.4), dead time level 1 (4 ms) */
  const analytic *a = study.candidates[3].eval.ctx;
  check_rel(a->speed, 0.4, 1e-15);
  check_rel(a->dead_time, 4e-3, 1e-15);
  /* six candidates: every pair compared on both metrics. Mean execution time
   * = dead time + x / speed with x the mean largest |q| (between 1.2 and 3.6
   * mm for these maneuvers), so: (0.6, 1) < (0.4, 1) < (0.6, 4) < (0.4, 4) <
   * (0.2, 1) < (0.2, 4) in (m/s, ms) */
  pom_doe_run_options o;
  pom_doe_run_options_defaults(&o);
  o.output = "";
  pom_doe_report *rep = NULL;
  check_true(pom_doe_run_all(&study, &o, &rep, &err) == POM_OK);
  if (rep) {
    /* six candidates: the best of each metric against the five others */
    check_true(!rep->all_pairs && rep->n_comparisons == 10);
    for (int j = 0; j < rep->n_comparisons; ++j) {
      const pom_doe_comparison *c = &rep->cmp[j];
      const int *order = c->metric == POM_DOE_METRIC_TIME ? rep->rank_time : rep->rank_energy;
      check_true(c->a == order[0] && c->b == order[1 + j % 5]);
      check_true(c->p_holm >= c->test.wilcoxon_p);
      /* energy does not depend on the factors: every pair a tie, p = 1 */
      if (c->metric == POM_DOE_METRIC_ENERGY) {
        check_abs(c->test.tie_fraction, 1.0, 0);
        check_abs(c->test.win_fraction, 0.0, 0);
        check_abs(c->p_holm, 1.0, 0);
      }
    }
    check_true(rep->friedman[POM_DOE_METRIC_TIME].n_blocks == 4);
    check_true(isnan(rep->friedman[POM_DOE_METRIC_ENERGY].statistic));
    check_abs(rep->friedman[POM_DOE_METRIC_ENERGY].p, 1.0, 0);
    const int want[6] = {4, 2, 5, 3, 0, 1};
    for (int r = 0; r < 6; ++r)
      check_true(rep->rank_time[r] == want[r]);
    for (int r = 1; r < 6; ++r)
      check_true(rep->cand[rep->rank_time[r - 1]].execution_time.mean <=
                 rep->cand[rep->rank_time[r]].execution_time.mean);
    /* energy does not depend on the factors: equal means, ties keep index order */
    check_rel(rep->cand[0].energy.mean, rep->cand[5].energy.mean, 1e-15);
    check_true(rep->rank_energy[0] == 0);
  }
  pom_doe_report_destroy(rep);
  pom_doe_study_clear(&study);

  write_file("lhs.cfg",
             "montecarlo = { maneuvers = 4; };\n"
             "candidates = { sweep = \"lhs\"; points = 8; seed = 11;\n"
             "  base = ( { name = \"A\"; config = \"fast.cfg\"; } );\n"
             "  factors = ( { key = \"analytic.speed_m_per_s\"; min = 0.1; max = 0.9; } );\n"
             "};\n");
  st = load_study(&study, "lhs.cfg", &err);
  if (!check_true(st == POM_OK)) {
    printf("  %s\n", err.message);
    return;
  }
  /* Latin hypercube: exactly one point per stratum of width 0.1 */
  int strata[8] = {0};
  for (int c = 0; c < study.n_candidates; ++c) {
    const analytic *x = study.candidates[c].eval.ctx;
    int s = (int)floor((x->speed - 0.1) / 0.1);
    if (s >= 0 && s < 8) ++strata[s];
  }
  for (int s = 0; s < 8; ++s)
    check_true(strata[s] == 1);
  pom_doe_study_clear(&study);
}

/* ---- runs ----------------------------------------------------------------------------- */
static pom_doe_row *read_all(const char *path, int nc, long m) {
  pom_doe_row *rows = calloc((size_t)(nc * m), sizeof *rows);
  pom_error err;
  for (int c = 0; c < nc; ++c)
    if (pom_doe_results_read_rows(path, c, 0, m, rows + (size_t)c * (size_t)m, &err) != POM_OK) {
      printf("  read %s: %s\n", path, err.message);
      free(rows);
      return NULL;
    }
  return rows;
}

static void test_runs(void) {
  pom_error err;
  pom_doe_study study;
  pom_error_clear(&err);
  if (!check_true(load_study(&study, "toy.cfg", &err) == POM_OK)) {
    printf("  %s\n", err.message);
    return;
  }
  /* a failure on every maneuver with q0 > 2 mm of the "slow" candidate */
  ((analytic *)study.candidates[1].eval.ctx)->fail_above = 2e-3;
  const long m = study.maneuvers.count;
  char p1[512], p2[512], p3[512];
  snprintf(p1, sizeof p1, "%s/one.h5", tmpdir);
  snprintf(p2, sizeof p2, "%s/two.h5", tmpdir);
  snprintf(p3, sizeof p3, "%s/resumed.h5", tmpdir);
  pom_doe_run_options o;
  pom_doe_report *r1 = NULL, *r2 = NULL, *r3 = NULL;

  pom_doe_run_options_defaults(&o);
  o.threads = 1;
  o.output = p1;
  worker_count = 0;
  check_true(pom_doe_run_all(&study, &o, &r1, &err) == POM_OK);
  check_true(worker_count == 2); /* one state per candidate for the single worker */

  /* prepared without a file: worker states made, nothing run until started
   * (the study fuzzer's setup check, tests/fuzz) */
  pom_doe_run *prep = NULL;
  o.output = "";
  worker_count = 0;
  check_true(pom_doe_run_prepare(&prep, &study, &o, &err) == POM_OK);
  check_true(worker_count == 2 && pom_doe_run_total(prep) == 2 * m && pom_doe_run_done(prep) == 0);
  pom_doe_run_destroy(prep); /* never started */
  prep = NULL;
  check_true(pom_doe_run_prepare(&prep, &study, &o, &err) == POM_OK);
  check_true(pom_doe_run_start(prep, &err) == POM_OK);
  check_true(pom_doe_run_start(prep, &err) == POM_ERR_ARG);
  int prep_finished = 0;
  while (!prep_finished)
    check_true(pom_doe_run_step(prep, &prep_finished, &err) == POM_OK);
  check_true(pom_doe_run_done(prep) == 2 * m);
  pom_doe_run_destroy(prep);

  o.threads = 3;
  o.queue_capacity = 2; /* workers wait on a full queue */
  o.output = p2;
  worker_count = 0;
  check_true(pom_doe_run_all(&study, &o, &r2, &err) == POM_OK);
  check_true(worker_count == 6);

  /* interrupted after 9 units, then resumed */
  pom_doe_run *run = NULL;
  o.threads = 2;
  o.output = p3;
  o.stop_after = 9;
  check_true(pom_doe_run_begin(&run, &study, &o, &err) == POM_OK);
  int finished = 0;
  while (!finished)
    check_true(pom_doe_run_step(run, &finished, &err) == POM_OK);
  long done_first = pom_doe_run_done(run);
  check_true(done_first >= 9 && done_first < 2 * m);
  pom_doe_report *partial = NULL;
  check_true(pom_doe_run_end(run, &partial, &err) == POM_OK);
  pom_doe_run_destroy(run);
  check_true(partial && partial->cand[0].n_done + partial->cand[1].n_done == done_first);
  pom_doe_report_destroy(partial);
  /* an unfinished run is in p3.partial; p3 appears only when it is done */
  char p3_partial[600];
  pom_doe_results_partial_path(p3_partial, sizeof p3_partial, p3);
  check_true(access(p3, F_OK) != 0 && access(p3_partial, F_OK) == 0);
  pom_doe_row *part = read_all(p3_partial, 2, m);
  long stored = 0;
  for (long j = 0; part && j < 2 * m; ++j)
    stored += part[j].done;
  check_true(stored == done_first); /* every finished maneuver kept */
  free(part);

  o.stop_after = 0;
  o.resume = 1;
  run = NULL;
  check_true(pom_doe_run_begin(&run, &study, &o, &err) == POM_OK);
  check_true(pom_doe_run_start_done(run) == done_first);
  finished = 0;
  while (!finished)
    check_true(pom_doe_run_step(run, &finished, &err) == POM_OK);
  check_true(pom_doe_run_done(run) == 2 * m);
  check_true(pom_doe_run_end(run, &r3, &err) == POM_OK);
  pom_doe_run_destroy(run);
  check_true(access(p3, F_OK) == 0 && access(p3_partial, F_OK) != 0);

  pom_doe_row *a = read_all(p1, 2, m), *b = read_all(p2, 2, m), *c = read_all(p3, 2, m);
  if (a && b && c) {
    check_true(memcmp(a, b, (size_t)(2 * m) * sizeof *a) == 0);
    check_true(memcmp(a, c, (size_t)(2 * m) * sizeof *a) == 0);
    /* rows against the evaluator itself */
    long failed = 0, unsettled = 0;
    double esum = 0;
    long nok = 0;
    for (long k = 0; k < m; ++k) {
      pom_doe_maneuver mv;
      pom_doe_maneuver_draw(&mv, &study.maneuvers, k);
      const pom_doe_row *f = &a[k], *s = &a[m + k];
      check_true(f->done && s->done);
      check_true(memcmp(f->target, mv.q, sizeof mv.q) == 0); /* common random numbers */
      check_true(memcmp(s->target, mv.q, sizeof mv.q) == 0);
      double tmax = 0;
      for (int i = 0; i < 3; ++i)
        tmax = fmax(tmax, 1.5e-3 + fabs(mv.q[i]) / 0.5);
      check_rel(f->execution_time, tmax, 1e-15);
      if (mv.q[0] > 2e-3) {
        ++failed;
        check_true(s->status == POM_ERR_SOLVER && strstr(s->reason, "injected") != NULL);
        check_true(isnan(s->execution_time));
      } else {
        check_true(s->status == POM_OK);
        esum += s->energy_total;
        ++nok;
        if (!(s->settled[0] && s->settled[1] && s->settled[2])) ++unsettled;
      }
    }
    check_true(failed > 0 && unsettled > 0);
    check_true(r1->cand[1].n_failed == failed);
    check_true(r1->cand[1].n_unsettled == unsettled);
    check_true(r1->cand[1].energy.n == nok);
    check_rel(r1->cand[1].energy.mean, esum / (double)nok, 1e-14);
    /* the fast candidate wins every comparison it can */
    check_true(r1->rank_time[0] == 0 && r1->rank_energy[0] == 0);
    check_true(r1->cmp[0].metric == POM_DOE_METRIC_TIME && r1->cmp[0].test.win_fraction == 1.0);
    check_true(r1->cmp[0].test.mean_diff < 0 && r1->cmp[0].test.ci_high < 0);
    /* reports identical whatever the threads or interruptions */
    check_true(memcmp(r1->cand, r2->cand, 2 * sizeof *r1->cand) == 0);
    check_true(memcmp(r1->cand, r3->cand, 2 * sizeof *r1->cand) == 0);
    check_true(memcmp(r1->cmp, r3->cmp, (size_t)r1->n_comparisons * sizeof *r1->cmp) == 0);
  }
  free(a);
  free(b);
  free(c);
  pom_doe_report_destroy(r1);
  pom_doe_report_destroy(r2);
  pom_doe_report_destroy(r3);

  /* resuming a file of another study is refused */
  study.maneuvers.seed = 4243;
  o.resume = 1;
  pom_error_clear(&err);
  check_true(pom_doe_run_all(&study, &o, NULL, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "another study") != NULL);
  study.maneuvers.seed = 4242;
  /* so is one drawn by another distribution with the same seed and range (a
   * resumed file would mix the maneuvers of two protocols) */
  study.maneuvers.distribution = POM_DOE_DIST_NORMAL;
  pom_error_clear(&err);
  check_true(pom_doe_run_all(&study, &o, NULL, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "another study") != NULL);
  study.maneuvers.distribution = POM_DOE_DIST_UNIFORM;
  /* and the same protocol resumes (nothing left to do) */
  pom_error_clear(&err);
  check_true(pom_doe_run_all(&study, &o, NULL, &err) == POM_OK);

  /* orientation space: targets from the evaluator's mapping */
  study.maneuvers.space = POM_DOE_SPACE_ORIENTATION;
  o.resume = 0;
  o.output = "";
  pom_doe_report *r4 = NULL;
  check_true(pom_doe_run_all(&study, &o, &r4, &err) == POM_OK);
  check_true(r4 && r4->cand[0].n_done == m);
  pom_doe_report_destroy(r4);
  pom_doe_study_clear(&study);
}

/* ---- config trees: merge and write ---------------------------------------------------- */
static void test_cfgtree(void) {
  const char *base = "a = 1.0e-7; n = 42; big = 9007199254740993L; flag = true;\n"
                     "s = \"quote \\\" back \\\\ tab\\t\";\n"
                     "g = { x = 0.1; arr = [1.5, 2.25, 3.0]; lst = (1, \"two\", { k = 3; }); };\n";
  const char *over = "g = { x = 2.385; y = -4; }; a = 3; t = \"new\";\n";
  config_t t1, t2, o;
  config_init(&t1);
  config_init(&t2);
  config_init(&o);
  pom_error err;
  char *w1 = NULL, *w2 = NULL;
  check_true(pom_doe_tree_read_string(&t1, base, "<base>", NULL, &err) == POM_OK);
  check_true(pom_doe_tree_read_string(&o, over, "<over>", NULL, &err) == POM_OK);
  check_true(pom_doe_tree_merge(config_root_setting(&t1), config_root_setting(&o), "test", &err) ==
             POM_OK);
  check_true(pom_doe_tree_set_number(&t1, "g.h.z", 0.1 + 0.2, &err) == POM_OK);
  check_true(pom_doe_tree_set_number(&t1, "n", 7.5, &err) == POM_ERR_CONFIG); /* integer key */
  check_true(pom_doe_tree_write(&t1, &w1, &err) == POM_OK);
  /* written text reads back to the same tree: writing it again gives the same text */
  check_true(w1 && pom_doe_tree_read_string(&t2, w1, "<w1>", NULL, &err) == POM_OK);
  check_true(pom_doe_tree_write(&t2, &w2, &err) == POM_OK);
  check_true(w1 && w2 && strcmp(w1, w2) == 0);
  pom_cfg *cfg = NULL;
  check_true(w1 && pom_cfg_load_string(&cfg, w1, "<resolved>", &err) == POM_OK);
  if (cfg) {
    double x = 0, z = 0, a = 0, arr[3] = {0};
    long y = 0, n = 0, big = 0;
    int flag = 0;
    char str[64] = "";
    pom_cfg_real(cfg, "g.x", 1, -10, 10, &x, &err);
    pom_cfg_real(cfg, "g.h.z", 1, -10, 10, &z, &err);
    pom_cfg_real(cfg, "a", 1, -10, 10, &a, &err);
    pom_cfg_reals(cfg, "g.arr", 3, 1, -10, 10, arr, &err);
    pom_cfg_int(cfg, "g.y", -10, 10, &y, &err);
    pom_cfg_int(cfg, "n", 0, 100, &n, &err);
    pom_cfg_int(cfg, "big", 0, 9007199254740993L, &big, &err);
    pom_cfg_bool(cfg, "flag", &flag, &err);
    pom_cfg_string(cfg, "s", str, sizeof str, &err);
    check_abs(x, 2.385, 0);     /* overridden */
    check_abs(z, 0.1 + 0.2, 0); /* round-trip precision: 0.30000000000000004 */
    check_abs(a, 3, 0);         /* replaced by an integer */
    check_abs(arr[1], 2.25, 0);
    check_true(y == -4 && n == 42 && big == 9007199254740993L && flag == 1);
    check_true(strcmp(str, "quote \" back \\ tab\t") == 0);
    check_true(pom_cfg_length(cfg, "g.lst") == 3);
    pom_cfg_destroy(cfg);
  }
  free(w1);
  free(w2);
  config_destroy(&t1);
  config_destroy(&t2);
  config_destroy(&o);
}

/* ---- progress bar ------------------------------------------------------------------- */
static void test_progress(void) {
  char line[256];
  /* 50 of 200 done, 10 of them before this run, 8 s elapsed: rate (50 - 10) / 8
   * = 5/s, ETA 150 / 5 = 30 s; 25 % of a 20-wide bar = 5 marks */
  pom_progress_format(line, sizeof line, "paper", 50, 200, 10, 8.0, 20);
  check_true(strstr(line, "[#####...............]") != NULL);
  check_true(strstr(line, "50/200") != NULL && strstr(line, " 25%") != NULL);
  check_true(strstr(line, "5.0/s") != NULL && strstr(line, "ETA 0:30") != NULL);
  check_true(strstr(line, "0:08 elapsed") != NULL);
  /* nothing done in this run yet: rate and ETA unknown */
  pom_progress_format(line, sizeof line, "x", 10, 200, 10, 1.0, 10);
  check_true(strstr(line, "-/s") != NULL && strstr(line, "ETA --:--") != NULL);
  /* not a terminal: nothing drawn */
  FILE *f = tmpfile();
  pom_progress bar;
  pom_progress_init(&bar, f, "x", 10, 0, 0);
  pom_progress_update(&bar, 5);
  pom_progress_finish(&bar, 10);
  check_true(ftell(f) == 0);
  pom_progress_init(&bar, f, "x", 10, 0, 1); /* forced */
  pom_progress_finish(&bar, 10);
  check_true(ftell(f) > 0);
  fclose(f);
}

/* ---- the final-stroke rule of the dynamics evaluators ----------------------------------- */
static void test_final_stroke(void) {
  pom_dyn_metrics m;
  pom_error err;
  memset(&m, 0, sizeof m);
  pom_error_clear(&err);
  /* stroke 12 mm: +-6 mm allowed, the bound itself included */
  m.final_q[0] = 6e-3;
  m.final_q[1] = -6e-3;
  check_true(pom_doe_check_final_stroke(&m, 12e-3, &err) == POM_OK && m.status == POM_OK);
  m.final_q[2] = -6.5e-3;
  check_true(pom_doe_check_final_stroke(&m, 12e-3, &err) == POM_ERR_LIMIT);
  check_true(m.status == POM_ERR_LIMIT && strstr(m.reason, "actuator 3 ended outside") != NULL);
  /* an excursion past the stroke that came back inside is caught too */
  memset(&m, 0, sizeof m);
  m.final_q[0] = 2e-3;
  m.max_abs_q[0] = 6.2e-3;
  check_true(pom_doe_check_final_stroke(&m, 12e-3, &err) == POM_ERR_LIMIT);
  check_true(m.status == POM_ERR_LIMIT && strstr(m.reason, "actuator 1 left its stroke") != NULL);
  /* NaN is outside too */
  memset(&m, 0, sizeof m);
  m.final_q[1] = NAN;
  check_true(pom_doe_check_final_stroke(&m, 12e-3, &err) == POM_ERR_LIMIT);
  /* an earlier failure is kept as it is */
  memset(&m, 0, sizeof m);
  m.status = POM_ERR_SOLVER;
  snprintf(m.reason, sizeof m.reason, "solver");
  m.final_q[0] = 1.0;
  check_true(pom_doe_check_final_stroke(&m, 12e-3, &err) == POM_OK);
  check_true(m.status == POM_ERR_SOLVER && strcmp(m.reason, "solver") == 0);
}

/* ---- censoring (docs/results.md section 4) ---------------------------------------------
 * Synthetic rows: B settles every maneuver at t_k; A takes the same time on
 * the easiest 90 % and does not settle on B's hardest 10 % (right-censored
 * at the 0.1 s horizon); C is B plus 1 ms everywhere, with more energy; A
 * and B spend the same energy. With both primary time metrics: A never
 * ranks above B (B first, A's restricted mean strictly above B's), every
 * maneuver is compared (the censored ones included) and the censored
 * counts are reported; B is the only Pareto candidate; A's main-effect
 * level counts its 20 censored values. With A 1 % faster on the rest, B
 * still ranks first (it would not if the censored maneuvers were
 * dropped). */
static void censor_row(pom_doe_row *row, double t, int settles, double energy) {
  pom_dyn_metrics m;
  memset(&m, 0, sizeof m);
  m.horizon = 0.1;
  for (int a = 0; a < 3; ++a) {
    m.settled[a] = settles;
    m.settling_time[a] = settles ? t : NAN;
    m.settling_time_final[a] = t;
    m.energy[a] = energy / 3.0;
    m.energy_positive[a] = m.energy[a];
  }
  m.execution_time = settles ? t : NAN;
  m.pointing_settled = settles;
  m.pointing_settling_time = settles ? t : NAN;
  m.energy_total = m.energy[0] + m.energy[1] + m.energy[2];
  m.energy_supplied = m.energy_total;
  pom_doe_row_from_metrics(row, &m);
}

static void censoring_case(pom_doe_time_metric tm, double a_speedup) {
  enum { M = 200, NC = 3 };
  static pom_doe_cell cells[NC * M];
  pom_doe_candidate cand[NC];
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  memset(cand, 0, sizeof cand);
  study.n_candidates = NC;
  study.candidates = cand;
  study.maneuvers.count = M;
  study.alpha = 0.05;
  study.confidence = 0.95;
  study.time_metric = tm;
  study.n_factors = 1;
  snprintf(study.factor_key[0], sizeof study.factor_key[0], "controller.kp");
  snprintf(study.factor_label[0], sizeof study.factor_label[0], "kp");
  for (int c = 0; c < NC; ++c) {
    snprintf(cand[c].name, sizeof cand[c].name, "%c", 'A' + c);
    cand[c].n_factors = 1;
    cand[c].factor_value[0] = 1.0 + c;
  }
  for (int k = 0; k < M; ++k) {
    /* B's times in a scrambled order; its hardest 10 % are those with
     * (37 k) mod M >= 180 */
    int r = (37 * k) % M;
    double t = 0.0101 + 4.7e-5 * r;
    int hard = r >= M - M / 10;
    pom_doe_row row;
    censor_row(&row, t * (hard ? 1.0 : 1.0 - a_speedup), !hard, 0.23);
    pom_doe_cell_from_row(&cells[0 * M + k], &row, tm);
    censor_row(&row, t, 1, 0.23);
    pom_doe_cell_from_row(&cells[1 * M + k], &row, tm);
    censor_row(&row, t + 1e-3, 1, 0.31);
    pom_doe_cell_from_row(&cells[2 * M + k], &row, tm);
  }
  pom_doe_report *rep = NULL;
  pom_error err;
  pom_error_clear(&err);
  check_true(pom_doe_report_compute(&rep, &study, cells, &err) == POM_OK);
  if (!rep) return;
  printf("  censoring (%s, A %.0f %% faster on the rest): restricted means A %.4f B %.4f C %.4f "
         "ms, ranking %s %s %s\n",
         tm == POM_DOE_TIME_POINTING ? "pointing" : "execution", 100 * a_speedup,
         rep->mean_time[0] * 1e3, rep->mean_time[1] * 1e3, rep->mean_time[2] * 1e3,
         cand[rep->rank_time[0]].name, cand[rep->rank_time[1]].name, cand[rep->rank_time[2]].name);
  check_true(rep->rank_time[0] == 1);
  check_true(rep->mean_time[0] > rep->mean_time[1]);
  check_true(rep->cand[0].n_censored == M / 10 && rep->cand[1].n_censored == 0);
  check_true(rep->censored_common[0] == M / 10 && rep->censored_common[1] == 0);
  /* every maneuver in the comparisons and the Friedman test */
  for (int j = 0; j < rep->n_comparisons; ++j) {
    const pom_doe_comparison *c = &rep->cmp[j];
    if (c->metric != POM_DOE_METRIC_TIME) continue;
    check_true(c->test.n == M);
    if (c->a == 0 && c->b == 1) {
      check_true(c->censored_a == M / 10 && c->censored_b == 0);
      /* B is better exactly on the censored maneuvers */
      check_abs(1.0 - c->test.win_fraction - c->test.tie_fraction, 0.1, 1e-12);
      if (a_speedup == 0.0) {
        check_abs(c->test.tie_fraction, 0.9, 1e-12);
        check_true(c->test.wilcoxon_p < 1e-5); /* 20 positive differences: 2 / 2^20 */
      }
    }
  }
  check_true(rep->friedman[POM_DOE_METRIC_TIME].n_blocks == M);
  check_true(rep->friedman_censored == M / 10);
  check_true(rep->friedman[POM_DOE_METRIC_TIME].p < 1e-10);
  /* Pareto: B dominates A (as fast or faster on the restricted mean, same
   * energy) and C */
  check_true(rep->pareto[1] == 1 && rep->pareto[0] == 0 && rep->pareto[2] == 0);
  for (int j = 0; j < rep->n_effects; ++j) {
    const pom_doe_effect *e = &rep->effects[j];
    if (e->metric != POM_DOE_METRIC_TIME) continue;
    check_true(e->n == M);
    check_true(e->n_censored == (e->level == 0 ? M / 10 : 0));
    if (e->level == 0) check_abs(e->mean, rep->mean_time[0], 1e-15);
  }
  pom_doe_report_destroy(rep);
}

static void test_censoring(void) {
  censoring_case(POM_DOE_TIME_EXECUTION, 0.0);
  censoring_case(POM_DOE_TIME_POINTING, 0.0);
  censoring_case(POM_DOE_TIME_EXECUTION, 0.01);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/pom_test_doe_XXXXXX");
  if (!mkdtemp(tmpdir)) {
    printf("cannot make a temporary folder\n");
    return 1;
  }
  write_file("fast.cfg", "analytic = { speed_m_per_s = 0.5; energy_J_per_mm2 = 0.01; };\n");
  write_file("toy.cfg", study_text);
  test_stats();
  test_progress();
  test_cfgtree();
  test_maneuvers();
  test_study_config();
  test_sweep();
  test_friedman_holm();
  test_runs();
  test_final_stroke();
  test_censoring();
  return check_summary("test_doe");
}
