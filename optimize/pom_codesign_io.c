/* pom_codesign_io.c - the co-design's results file, text report and
 * figure (docs/optimize.md section 11.7). */
#define _POSIX_C_SOURCE 200809L /* getpid */
#include "codesign_internal.h"
#include "pom_h5.h"
#include "pom_io.h"
#include "pom_math.h"
#include "pom_nlopt.h"
#include "pom_version.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* Columns of a figures row. */
#define NFIG 10
static const char *const fig_columns[NFIG] = {"p95_smooth_s",    "p95_order_statistic_s",
                                              "mean_energy_J",   "peak_current_A",
                                              "current_limit_A", "kinematic_margin",
                                              "envelope_m",      "failed",
                                              "unsettled",       "maneuvers"};

/* Columns of a front_info row: the last is pom_cds_rdw_below (1: the true
 * RDW at the point is below the required half-width; docs/optimize.md 11.6). */
#define NINFO 9

static void fig_row(const pom_cds_figures *f, double *r) {
  r[0] = f->p95;
  r[1] = f->p95_plain;
  r[2] = f->energy;
  r[3] = f->i_peak;
  r[4] = f->i_limit;
  r[5] = f->kin;
  r[6] = f->envelope;
  r[7] = f->failed;
  r[8] = f->unsettled;
  r[9] = f->n;
}

static void stem_of(char *out, size_t cap, const char *name) {
  size_t k = 0;
  int run = 0;
  for (const char *p = name; *p && k + 1 < cap; ++p) {
    int ok = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9');
    if (ok) {
      out[k++] = *p;
      run = 0;
    } else if (!run) {
      out[k++] = '_';
      run = 1;
    }
  }
  out[k] = '\0';
}

static pom_status write_candidate(hid_t file, const pom_cds_problem *pb, const pom_cds_result *res,
                                  int c, pom_error *err) {
  const pom_cds_candidate *cd = &pb->cand[c];
  const pom_cds_cand_result *cr = &res->cand[c];
  char stem[POM_DOE_NAME_LEN];
  stem_of(stem, sizeof stem, cd->name);
  char path[POM_DOE_NAME_LEN + 32];
  snprintf(path, sizeof path, "candidates/%s", stem);
  hid_t g = -1;
  POM_TRY(pom_h5_create_group(&g, file, path, err));
  pom_status st = pom_h5_attr_string(g, "name", cd->name, err);
  if (st == POM_OK) st = pom_h5_attr_string(g, "config", cd->config, err);
  if (st == POM_OK) st = pom_h5_attr_double(g, "hypervolume_sJ", cr->hypervolume, err);
  if (st == POM_OK) st = pom_h5_attr_int64(g, "simulations", cr->simulations, err);
  const char *names[POM_CDS_MAX_VARS];
  double lo[POM_CDS_MAX_VARS], hi[POM_CDS_MAX_VARS], x0[POM_CDS_MAX_VARS];
  for (int v = 0; v < cd->n_vars; ++v) {
    names[v] = cd->var[v].key;
    lo[v] = cd->var[v].lo;
    hi[v] = cd->var[v].hi;
    x0[v] = cd->var[v].x0;
  }
  size_t nv = (size_t)cd->n_vars;
  if (st == POM_OK) st = pom_h5_write_strings(g, "variables", nv, names, POM_CDS_KEY_LEN, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "lower", 1, &nv, lo, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "upper", 1, &nv, hi, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "config_design", 1, &nv, x0, err);
  double row[NFIG];
  size_t nf = NFIG;
  fig_row(&cr->nominal, row);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "config_figures", 1, &nf, row, err);
  fig_row(&cr->nominal_fresh, row);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "config_figures_fresh", 1, &nf, row, err);
  /* the front: one row per point */
  size_t K = (size_t)cr->n_points;
  double *x = calloc(K * nv + 1, sizeof *x);
  double *fo = calloc(K * NFIG + 1, sizeof *fo), *ff = calloc(K * NFIG + 1, sizeof *ff),
         *fp = calloc(K * NFIG + 1, sizeof *fp), *info = calloc(K * NINFO + 1, sizeof *info);
  if (!x || !fo || !ff || !fp || !info)
    st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "results: out of memory");
  for (size_t k = 0; k < K && st == POM_OK; ++k) {
    const pom_cds_point *p = &cr->point[k];
    memcpy(x + k * nv, p->x, nv * sizeof *x);
    fig_row(&p->opt, fo + k * NFIG);
    fig_row(&p->fresh, ff + k * NFIG);
    fig_row(&p->fresh_parasitic, fp + k * NFIG);
    double *in = info + k * NINFO;
    in[0] = p->objective;
    in[1] = p->eps;
    in[2] = p->feasible;
    in[3] = p->fallback_used;
    in[4] = p->nlopt_result;
    in[5] = (double)p->simulations;
    in[6] = (double)p->evaluations;
    in[7] = p->rdw_deg;
    in[8] = pom_cds_rdw_below(pb, p);
  }
  size_t d2[2] = {K, nv}, df[2] = {K, NFIG}, di[2] = {K, NINFO};
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_x", 2, d2, x, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_optimizer", 2, df, fo, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_fresh", 2, df, ff, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_fresh_parasitic", 2, df, fp, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_info", 2, di, info, err);
  static const char *const info_cols[NINFO] = {"objective (0 time, 1 energy)",
                                               "energy_bound_J",
                                               "feasible",
                                               "fallback_used",
                                               "nlopt_result",
                                               "simulations",
                                               "evaluations",
                                               "rdw_deg",
                                               "rdw_below_required"};
  if (st == POM_OK) st = pom_h5_write_strings(g, "front_info_columns", NINFO, info_cols, 40, err);
  free(x);
  free(fo);
  free(ff);
  free(fp);
  free(info);
  H5Gclose(g);
  return st;
}

static pom_status write_all(hid_t file, const pom_cds_problem *pb, const pom_cds_result *res,
                            pom_error *err) {
  char when[32];
  time_t now = time(NULL);
  struct tm tmv;
  gmtime_r(&now, &tmv);
  strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &tmv);
  POM_TRY(pom_h5_attr_string(file, "format", "pomlab codesign results", err));
  POM_TRY(pom_h5_attr_int64(file, "format_version", 1, err));
  POM_TRY(pom_h5_attr_string(file, "version", POM_VERSION, err));
  POM_TRY(pom_h5_attr_string(file, "git_commit", POM_GIT_COMMIT, err));
  POM_TRY(pom_h5_attr_string(file, "created_utc", when, err));
  POM_TRY(pom_h5_attr_string(file, "codesign_name", pb->name, err));
  POM_TRY(pom_h5_attr_string(file, "codesign_source", pb->source, err));
  POM_TRY(pom_h5_attr_double(file, "required_rdw_deg", pb->ws_half_width * 180.0 / POM_PI, err));
  POM_TRY(pom_h5_attr_double(file, "reference_time_s", res->ref_time, err));
  POM_TRY(pom_h5_attr_double(file, "reference_energy_J", res->ref_energy, err));
  POM_TRY(pom_h5_attr_int64(file, "simulations", res->simulations, err));
  POM_TRY(pom_h5_attr_double(file, "wall_time_s", res->wall, err));
  POM_TRY(pom_h5_attr_int64(file, "resumed_tasks", res->resumed_tasks, err));
  POM_TRY(pom_h5_write_text(file, "config", pb->config_text, err));
  POM_TRY(pom_h5_write_strings(file, "figure_columns", NFIG, fig_columns, 32, err));
  hid_t g = -1;
  POM_TRY(pom_h5_create_group(&g, file, "candidates", err));
  H5Gclose(g);
  for (int c = 0; c < pb->n_candidates; ++c)
    POM_TRY(write_candidate(file, pb, res, c, err));
  return POM_OK;
}

pom_status pom_cds_write_h5(const pom_cds_problem *pb, const pom_cds_result *res, const char *path,
                            pom_error *err) {
  char tmp[POM_DOE_PATH_LEN + 40];
  snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
  hid_t file = -1;
  POM_TRY(pom_h5_create_file(&file, tmp, err));
  pom_status st = write_all(file, pb, res, err);
  pom_status cst = pom_h5_close_file(file, st == POM_OK ? err : NULL);
  if (st == POM_OK) st = cst;
  if (st == POM_OK) st = pom_io_sync(tmp, err);
  if (st == POM_OK && rename(tmp, path) != 0)
    st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__, "cannot rename '%s' to '%s': %s", tmp,
                       path, strerror(errno));
  if (st == POM_OK) st = pom_io_sync_folder(path, err);
  if (st != POM_OK) unlink(tmp);
  return st;
}

/* ---- text ------------------------------------------------------------------------------ */
static const char *alg_label(pom_cds_alg a) {
  return a == POM_CDS_ALG_SLSQP ? "SLSQP" : a == POM_CDS_ALG_MMA ? "MMA" : "COBYLA";
}

static void fig_cell(FILE *out, const pom_cds_figures *f) {
  fprintf(out, "%7.2f ms %7.2f mJ", 1e3 * f->p95, 1e3 * f->energy);
}

void pom_cds_report_text(FILE *out, const pom_cds_problem *pb, const pom_cds_result *res) {
  const double req_deg = pb->ws_half_width * 180.0 / POM_PI;
  fprintf(out,
          "Co-design '%s': %d candidates, %ld maneuvers (seed %llu), re-evaluated on %ld "
          "(seed %llu)\n",
          pb->name, pb->n_candidates, pb->maneuvers.count, (unsigned long long)pb->maneuvers.seed,
          pb->reeval_count, (unsigned long long)pb->reeval_seed);
  fprintf(out,
          "Requirements: RDW >= %.1f deg at 1/kappa >= %.2f, current <= limit of the size "
          "law, envelope <= %.0f mm; time = smooth p%.0f of the pointing settling time "
          "(h = %.2f ms), <= %.1f ms at every front point\n\n",
          req_deg, pb->dexterity_min, 1e3 * pb->envelope, 100 * pb->quantile, 1e3 * pb->bandwidth,
          1e3 * pb->time_max);
  for (int c = 0; c < pb->n_candidates; ++c) {
    const pom_cds_candidate *cd = &pb->cand[c];
    const pom_cds_cand_result *cr = &res->cand[c];
    fprintf(out, "== %s (%s)\n", cd->name, cd->config);
    fprintf(out, "  config's design: optimizer set ");
    fig_cell(out, &cr->nominal);
    fprintf(out, " | fresh set ");
    fig_cell(out, &cr->nominal_fresh);
    fprintf(out, " | margin %.3f, i %.2f/%.2f A\n", cr->nominal.kin, cr->nominal.i_peak,
            cr->nominal.i_limit);
    fprintf(out, "  %-3s %-9s %-24s %-24s %-24s %-8s %-6s %s\n", "pt", "eps mJ",
            "optimizer (p95, E)", "fresh rigid", "fresh parasitic", "RDW deg", "feas", "sims");
    for (int k = 0; k < cr->n_points; ++k) {
      const pom_cds_point *p = &cr->point[k];
      char eps[32];
      if (isfinite(p->eps))
        snprintf(eps, sizeof eps, "%.2f", 1e3 * p->eps);
      else
        snprintf(eps, sizeof eps, "%s", p->objective == 0 ? "min t" : "min E");
      fprintf(out, "  %-3d %-9s ", k + 1, eps);
      fig_cell(out, &p->opt);
      fprintf(out, "   ");
      fig_cell(out, &p->fresh);
      fprintf(out, "   ");
      fig_cell(out, &p->fresh_parasitic);
      char rdw[32];
      snprintf(rdw, sizeof rdw, "%.1f%s", p->rdw_deg, pom_cds_rdw_below(pb, p) ? " *" : "");
      fprintf(out, "   %-8s %-6s %ld%s\n", rdw, p->feasible ? "yes" : "NO", p->simulations,
              p->fallback_used ? " (COBYLA fallback)" : "");
    }
    /* the flag (docs/optimize.md 11.6): g_kin checks only its grid's poses */
    int n_below = 0;
    for (int k = 0; k < cr->n_points; ++k)
      n_below += pom_cds_rdw_below(pb, &cr->point[k]);
    if (n_below) {
      fprintf(out, "  * RDW BELOW THE REQUIREMENT (%.1f deg) at point", req_deg);
      for (int k = 0, m = 0; k < cr->n_points; ++k)
        if (pom_cds_rdw_below(pb, &cr->point[k]))
          fprintf(out, "%s %d (%.1f deg)", m++ ? "," : "", k + 1, cr->point[k].rdw_deg);
      fprintf(out,
              ": the optimizer's workspace constraint checks only %d^3 poses of the required "
              "cube; the true RDW (every pose of the workspace grid) falls short "
              "(docs/optimize.md 11.6)\n",
              pb->ws_grid);
    }
    fprintf(out, "  time optimum:");
    for (int v = 0; v < cd->n_vars; ++v)
      fprintf(out, " %s = %.5g [%.5g]", cd->var[v].key, cr->point[0].x[v], cd->var[v].x0);
    fprintf(out, "\n  hypervolume %.4g ms mJ, %ld simulations\n", 1e6 * cr->hypervolume,
            cr->simulations);
    /* how each optimization stopped: a budget or a failure shows here, not
     * only in the results file's front_info */
    fprintf(out, "  optimizer stops:");
    for (int k = 0; k < cr->n_points; ++k) {
      const pom_cds_point *p = &cr->point[k];
      fprintf(out, "%s pt %d %s%s %s after %ld evaluations%s", k ? ";" : "", k + 1,
              p->fallback_used ? "" : alg_label(pb->alg),
              p->fallback_used ? "COBYLA (fallback)" : "", pom_opt_result_name(p->nlopt_result),
              p->evaluations,
              p->restarted == 2   ? " (stuck on its start; the second start, from the time "
                                    "optimum, kept)"
              : p->restarted == 1 ? " (stuck on its start; the second start, from the time "
                                    "optimum, was worse)"
                                  : "");
    }
    fprintf(out, "\n");
    if (!cr->point[0].feasible) {
      char why[600];
      pom_cds_infeasible_reason(pb, c, cr->point[0].x, &cr->point[0].opt, why, sizeof why);
      fprintf(out, "  INFEASIBLE: no design met the requirement set; at the best point kept: %s\n",
              why);
    }
    fprintf(out, "\n");
  }
  fprintf(out, "Ranking at each architecture's best (hypervolume of the re-evaluated front; p95 "
               "at the time optimum: optimizer's set / fresh rigid / fresh parasitic)\n");
  int order[POM_CDS_MAX_CANDIDATES];
  for (int c = 0; c < pb->n_candidates; ++c)
    order[c] = c;
    /* feasible before infeasible, then by hypervolume */
#define RANK_KEY(i) (res->cand[order[i]].point[0].feasible ? res->cand[order[i]].hypervolume : -1.0)
  for (int i = 1; i < pb->n_candidates; ++i)
    for (int j = i; j > 0 && RANK_KEY(j - 1) < RANK_KEY(j); --j) {
      int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
#undef RANK_KEY
  fprintf(out, "  %-4s %-24s %-11s %-24s %-12s %-12s %-12s\n", "rank", "candidate", "HV ms mJ",
          "p95 opt/fresh/para ms", "E at t-opt", "min E mJ", "config p95");
  for (int i = 0; i < pb->n_candidates; ++i) {
    const pom_cds_cand_result *cr = &res->cand[order[i]];
    const pom_cds_point *p0 = &cr->point[0];
    char p95s[64];
    snprintf(p95s, sizeof p95s, "%.2f/%.2f/%.2f", 1e3 * p0->opt.p95, 1e3 * p0->fresh.p95,
             1e3 * p0->fresh_parasitic.p95);
    char below[96] = "";
    if (pom_cds_rdw_below(pb, p0))
      snprintf(below, sizeof below, " (RDW %.1f < %.1f deg at the time optimum)", p0->rdw_deg,
               req_deg);
    if (p0->feasible)
      fprintf(out, "  %-4d %-24s %-11.4g %-24s %-12.1f %-12.1f %-12.2f%s\n", i + 1,
              pb->cand[order[i]].name, 1e6 * cr->hypervolume, p95s, 1e3 * p0->fresh.energy,
              1e3 * cr->point[cr->n_points - 1].fresh.energy, 1e3 * cr->nominal_fresh.p95, below);
    else
      fprintf(out, "  %-4s %-24s infeasible (see its section): %s at the best point kept\n", "-",
              pb->cand[order[i]].name, p95s);
  }
  fprintf(out, "  (hypervolume in ms mJ against the reference %.2f ms, %.2f mJ)\n",
          1e3 * res->ref_time, 1e3 * res->ref_energy);
  /* pairwise: time optima and config designs */
  /* every pair for a few candidates; beyond 4, each against the first ranked */
  for (int a = 0; a < pb->n_candidates; ++a)
    for (int b = a + 1; b < pb->n_candidates; ++b) {
      if (pb->n_candidates > 4 && a != order[0] && b != order[0]) continue;
      const pom_cds_cand_result *ra = &res->cand[a], *rb = &res->cand[b];
      double best = rb->point[0].fresh.p95 - ra->point[0].fresh.p95;
      double conf = rb->nominal_fresh.p95 - ra->nominal_fresh.p95;
      fprintf(out,
              "  %s vs %s: p95 time at each one's best %.2f vs %.2f ms (%s faster by %.2f ms); at "
              "the config designs %.2f vs %.2f ms (%s faster by %.2f ms)\n",
              pb->cand[a].name, pb->cand[b].name, 1e3 * ra->point[0].fresh.p95,
              1e3 * rb->point[0].fresh.p95, best >= 0 ? pb->cand[a].name : pb->cand[b].name,
              1e3 * fabs(best), 1e3 * ra->nominal_fresh.p95, 1e3 * rb->nominal_fresh.p95,
              conf >= 0 ? pb->cand[a].name : pb->cand[b].name, 1e3 * fabs(conf));
    }
  fprintf(out,
          "Simulations: %ld in the optimizations, %ld in the config designs' figures and the "
          "re-evaluations; wall time %.1f s%s\n",
          res->simulations, res->other_simulations, res->wall,
          res->resumed_tasks ? " (this run; resumed tasks re-evaluated, not re-optimized)" : "");
}

/* ---- figure ------------------------------------------------------------------------------ */
void pom_cds_axis_range(double lo, double hi, int nonneg, double *a, double *b, double *step,
                        int *decimals) {
  if (!(hi > lo)) {
    double w = lo != 0 ? 0.1 * fabs(lo) : 1.0;
    lo -= w;
    hi += w;
  }
  double margin = 0.05 * (hi - lo);
  lo -= margin;
  hi += margin;
  if (nonneg && lo < 0) lo = 0;
  /* the smallest nice step giving at most 8 intervals */
  double raw = (hi - lo) / 8.0;
  double mag = pow(10.0, floor(log10(raw)));
  static const double nice[] = {1.0, 2.0, 2.5, 5.0, 10.0};
  double s = 10.0 * mag;
  for (int i = 0; i < 5; ++i)
    if (nice[i] * mag >= raw * (1 - 1e-12)) {
      s = nice[i] * mag;
      break;
    }
  *a = floor(lo / s + 1e-9) * s;
  *b = ceil(hi / s - 1e-9) * s;
  if (nonneg && *a < 0) *a = 0;
  *step = s;
  int d = 0;
  while (d < 9) {
    double scaled = s * pow(10.0, d);
    if (fabs(scaled - round(scaled)) <= 1e-9 * scaled) break;
    ++d;
  }
  *decimals = d;
}

pom_status pom_cds_write_svg(const pom_cds_problem *pb, const pom_cds_result *res, const char *path,
                             pom_error *err) {
  pom_io_file w;
  POM_TRY(pom_io_create(&w, path, err));
  /* plot on the left, the legend in a column on the right (up to 16 names),
   * wide enough for the longest entry at about 7 px a character */
  double legend_w = 250;
  for (int c = 0; c < pb->n_candidates; ++c) {
    char entry[POM_DOE_NAME_LEN + 64];
    int len = snprintf(entry, sizeof entry, "%s (HV %.3g ms mJ)", pb->cand[c].name,
                       1e6 * res->cand[c].hypervolume);
    legend_w = fmax(legend_w, 7.0 * len + 10.0);
  }
  const double W = 640 + legend_w, H = 440, L = 70, R = 20 + legend_w, T = 30, B = 50;
  double tmin = INFINITY, tmax = -INFINITY, emin = INFINITY, emax = -INFINITY;
  for (int c = 0; c < pb->n_candidates; ++c) {
    const pom_cds_cand_result *cr = &res->cand[c];
    for (int k = -1; k < cr->n_points; ++k) {
      const pom_cds_figures *f = k < 0 ? &cr->nominal_fresh : &cr->point[k].fresh;
      if (!isfinite(f->p95) || !isfinite(f->energy)) continue;
      tmin = fmin(tmin, 1e3 * f->p95);
      tmax = fmax(tmax, 1e3 * f->p95);
      emin = fmin(emin, 1e3 * f->energy);
      emax = fmax(emax, 1e3 * f->energy);
    }
  }
  if (!(tmax >= tmin)) tmin = tmax = 0;
  if (!(emax >= emin)) emin = emax = 0;
  /* in ms and mJ; both quantities are never negative */
  double t0, t1, tstep, e0, e1, estep;
  int tdec, edec;
  pom_cds_axis_range(tmin, tmax, 1, &t0, &t1, &tstep, &tdec);
  pom_cds_axis_range(emin, emax, 1, &e0, &e1, &estep, &edec);
#define PX(t) (L + (1e3 * (t)-t0) / (t1 - t0) * (W - L - R))
#define PY(e) (H - B - (1e3 * (e)-e0) / (e1 - e0) * (H - T - B))
  static const char *const colours[] = {
      "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f",
      "#bcbd22", "#17becf", "#393b79", "#ad494a", "#637939", "#8c6d31", "#7b4173", "#3182bd"};
  FILE *f = w.f;
  fprintf(f,
          "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
          "font-family=\"sans-serif\" font-size=\"12\">\n",
          W, H);
  fprintf(f, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
  fprintf(f,
          "<text x=\"%.0f\" y=\"18\">%s: time-energy fronts at each architecture's best "
          "(fresh maneuvers; hollow = config design)</text>\n",
          L, pb->name);
  fprintf(f, "<line x1=\"%.0f\" y1=\"%.0f\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"black\"/>\n", L, H - B,
          W - R, H - B);
  fprintf(f, "<line x1=\"%.0f\" y1=\"%.0f\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"black\"/>\n", L, T, L,
          H - B);
  for (int i = 0; t0 + i * tstep <= t1 + 1e-9 * tstep; ++i) {
    double t = t0 + i * tstep, x = L + (t - t0) / (t1 - t0) * (W - L - R);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"black\"/>\n", x,
            H - B, x, H - B + 4);
    fprintf(f, "<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%.*f</text>\n", x, H - B + 16,
            tdec, t);
  }
  for (int i = 0; e0 + i * estep <= e1 + 1e-9 * estep; ++i) {
    double e = e0 + i * estep, y = H - B - (e - e0) / (e1 - e0) * (H - T - B);
    fprintf(f, "<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"black\"/>\n", L - 4,
            y, L, y);
    fprintf(f, "<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">%.*f</text>\n", L - 6, y + 4, edec,
            e);
  }
  fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">p%.0f pointing time (ms)</text>\n",
          (L + W - R) / 2, H - 12, 100 * pb->quantile);
  fprintf(f,
          "<text x=\"16\" y=\"%.0f\" transform=\"rotate(-90 16 %.0f)\" "
          "text-anchor=\"middle\">mean energy (mJ)</text>\n",
          (T + H - B) / 2, (T + H - B) / 2);
  for (int c = 0; c < pb->n_candidates; ++c) {
    const pom_cds_cand_result *cr = &res->cand[c];
    const char *col = colours[c % 16];
    fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", col);
    for (int k = 0; k < cr->n_points; ++k)
      if (isfinite(cr->point[k].fresh.p95) && isfinite(cr->point[k].fresh.energy))
        fprintf(f, "%.1f,%.1f ", PX(cr->point[k].fresh.p95), PY(cr->point[k].fresh.energy));
    fprintf(f, "\"/>\n");
    for (int k = 0; k < cr->n_points; ++k)
      if (isfinite(cr->point[k].fresh.p95) && isfinite(cr->point[k].fresh.energy))
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n",
                PX(cr->point[k].fresh.p95), PY(cr->point[k].fresh.energy), col);
    if (isfinite(cr->nominal_fresh.p95) && isfinite(cr->nominal_fresh.energy))
      fprintf(f,
              "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"none\" stroke=\"%s\" "
              "stroke-width=\"2\"/>\n",
              PX(cr->nominal_fresh.p95), PY(cr->nominal_fresh.energy), col);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" fill=\"%s\">%s (HV %.3g ms mJ)</text>\n", W - legend_w,
            T + 16 + 18 * c, col, pb->cand[c].name, 1e6 * cr->hypervolume);
  }
#undef PX
#undef PY
  fprintf(f, "</svg>\n");
  return pom_io_commit(&w, err);
}
