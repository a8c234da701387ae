/* pom_codesign_io.c - the co-design's results file, text report and
 * figure (docs/optimize.md section 11.7). */
#define _POSIX_C_SOURCE 200809L /* getpid */
#include "codesign_internal.h"
#include "pom_h5.h"
#include "pom_io.h"
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
         *fp = calloc(K * NFIG + 1, sizeof *fp), *info = calloc(K * 8 + 1, sizeof *info);
  if (!x || !fo || !ff || !fp || !info)
    st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "results: out of memory");
  for (size_t k = 0; k < K && st == POM_OK; ++k) {
    const pom_cds_point *p = &cr->point[k];
    memcpy(x + k * nv, p->x, nv * sizeof *x);
    fig_row(&p->opt, fo + k * NFIG);
    fig_row(&p->fresh, ff + k * NFIG);
    fig_row(&p->fresh_parasitic, fp + k * NFIG);
    double *in = info + k * 8;
    in[0] = p->objective;
    in[1] = p->eps;
    in[2] = p->feasible;
    in[3] = p->fallback_used;
    in[4] = p->nlopt_result;
    in[5] = (double)p->simulations;
    in[6] = (double)p->evaluations;
    in[7] = p->rdw_deg;
  }
  size_t d2[2] = {K, nv}, df[2] = {K, NFIG}, di[2] = {K, 8};
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_x", 2, d2, x, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_optimizer", 2, df, fo, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_fresh", 2, df, ff, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_fresh_parasitic", 2, df, fp, err);
  if (st == POM_OK) st = pom_h5_write_doubles(g, "front_info", 2, di, info, err);
  static const char *const info_cols[8] = {"objective (0 time, 1 energy)",
                                           "energy_bound_J",
                                           "feasible",
                                           "fallback_used",
                                           "nlopt_result",
                                           "simulations",
                                           "evaluations",
                                           "rdw_deg"};
  if (st == POM_OK) st = pom_h5_write_strings(g, "front_info_columns", 8, info_cols, 40, err);
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
static void fig_cell(FILE *out, const pom_cds_figures *f) {
  fprintf(out, "%7.2f ms %7.2f mJ", 1e3 * f->p95, 1e3 * f->energy);
}

void pom_cds_report_text(FILE *out, const pom_cds_problem *pb, const pom_cds_result *res) {
  fprintf(out,
          "Co-design '%s': %d candidates, %ld maneuvers (seed %llu), re-evaluated on %ld "
          "(seed %llu)\n",
          pb->name, pb->n_candidates, pb->maneuvers.count, (unsigned long long)pb->maneuvers.seed,
          pb->reeval_count, (unsigned long long)pb->reeval_seed);
  fprintf(out,
          "Requirements: RDW >= %.1f deg at 1/kappa >= %.2f, current <= limit of the size "
          "law, envelope <= %.0f mm; time = smooth p%.0f of the pointing settling time "
          "(h = %.2f ms)\n\n",
          pb->ws_half_width * 180.0 / 3.14159265358979323846, pb->dexterity_min, 1e3 * pb->envelope,
          100 * pb->quantile, 1e3 * pb->bandwidth);
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
      fprintf(out, "   %-8.0f %-6s %ld%s\n", p->rdw_deg, p->feasible ? "yes" : "NO", p->simulations,
              p->fallback_used ? " (COBYLA fallback)" : "");
    }
    fprintf(out, "  time optimum:");
    for (int v = 0; v < cd->n_vars; ++v)
      fprintf(out, " %s = %.5g [%.5g]", cd->var[v].key, cr->point[0].x[v], cd->var[v].x0);
    fprintf(out, "\n  hypervolume %.4g ms mJ, %ld simulations\n\n", 1e6 * cr->hypervolume,
            cr->simulations);
  }
  fprintf(out, "Ranking at each architecture's best (fresh maneuver set, rigid joints)\n");
  int order[POM_CDS_MAX_CANDIDATES];
  for (int c = 0; c < pb->n_candidates; ++c)
    order[c] = c;
  for (int i = 1; i < pb->n_candidates; ++i)
    for (int j = i; j > 0 && res->cand[order[j - 1]].hypervolume < res->cand[order[j]].hypervolume;
         --j) {
      int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
  fprintf(out, "  %-4s %-16s %-14s %-16s %-16s %-16s\n", "rank", "candidate", "hypervolume",
          "best p95 (ms)", "config p95 (ms)", "min energy (mJ)");
  for (int i = 0; i < pb->n_candidates; ++i) {
    const pom_cds_cand_result *cr = &res->cand[order[i]];
    fprintf(out, "  %-4d %-16s %-14.4g %-16.2f %-16.2f %-16.2f\n", i + 1, pb->cand[order[i]].name,
            1e6 * cr->hypervolume, 1e3 * cr->point[0].fresh.p95, 1e3 * cr->nominal_fresh.p95,
            1e3 * cr->point[cr->n_points - 1].fresh.energy);
  }
  fprintf(out, "  (hypervolume in ms mJ against the reference %.2f ms, %.2f mJ)\n",
          1e3 * res->ref_time, 1e3 * res->ref_energy);
  /* pairwise: time optima and config designs */
  for (int a = 0; a < pb->n_candidates; ++a)
    for (int b = a + 1; b < pb->n_candidates; ++b) {
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
  fprintf(out, "Simulations: %ld; wall time %.1f s%s\n", res->simulations, res->wall,
          res->resumed_tasks ? " (this run; resumed tasks re-evaluated, not re-optimized)" : "");
}

/* ---- figure ------------------------------------------------------------------------------ */
pom_status pom_cds_write_svg(const pom_cds_problem *pb, const pom_cds_result *res, const char *path,
                             pom_error *err) {
  pom_io_file w;
  POM_TRY(pom_io_create(&w, path, err));
  const double W = 640, H = 420, L = 70, R = 20, T = 30, B = 50;
  double tmin = INFINITY, tmax = 0, emin = INFINITY, emax = 0;
  for (int c = 0; c < pb->n_candidates; ++c) {
    const pom_cds_cand_result *cr = &res->cand[c];
    for (int k = -1; k < cr->n_points; ++k) {
      const pom_cds_figures *f = k < 0 ? &cr->nominal_fresh : &cr->point[k].fresh;
      tmin = fmin(tmin, f->p95);
      tmax = fmax(tmax, f->p95);
      emin = fmin(emin, f->energy);
      emax = fmax(emax, f->energy);
    }
  }
  double dt = fmax(tmax - tmin, 1e-6) * 0.1, de = fmax(emax - emin, 1e-9) * 0.1;
  tmin = fmax(0.0, tmin - dt);
  tmax += dt;
  emin = fmax(0.0, emin - de);
  emax += de;
#define PX(t) (L + ((t)-tmin) / (tmax - tmin) * (W - L - R))
#define PY(e) (H - B - ((e)-emin) / (emax - emin) * (H - T - B))
  static const char *const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                        "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f"};
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
  for (int i = 0; i <= 4; ++i) {
    double t = tmin + (tmax - tmin) * i / 4, e = emin + (emax - emin) * i / 4;
    fprintf(f, "<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%.1f</text>\n", PX(t),
            H - B + 16, 1e3 * t);
    fprintf(f, "<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">%.2f</text>\n", L - 4, PY(e) + 4,
            1e3 * e);
  }
  fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">p%.0f pointing time (ms)</text>\n",
          (L + W - R) / 2, H - 12, 100 * pb->quantile);
  fprintf(f,
          "<text x=\"16\" y=\"%.0f\" transform=\"rotate(-90 16 %.0f)\" "
          "text-anchor=\"middle\">mean energy (mJ)</text>\n",
          (T + H - B) / 2, (T + H - B) / 2);
  for (int c = 0; c < pb->n_candidates; ++c) {
    const pom_cds_cand_result *cr = &res->cand[c];
    const char *col = colours[c % 8];
    fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", col);
    for (int k = 0; k < cr->n_points; ++k)
      fprintf(f, "%.1f,%.1f ", PX(cr->point[k].fresh.p95), PY(cr->point[k].fresh.energy));
    fprintf(f, "\"/>\n");
    for (int k = 0; k < cr->n_points; ++k)
      fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n",
              PX(cr->point[k].fresh.p95), PY(cr->point[k].fresh.energy), col);
    fprintf(f,
            "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"5\" fill=\"none\" stroke=\"%s\" "
            "stroke-width=\"2\"/>\n",
            PX(cr->nominal_fresh.p95), PY(cr->nominal_fresh.energy), col);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" fill=\"%s\">%s (HV %.3g ms mJ)</text>\n", W - R - 220,
            T + 16 + 16 * c, col, pb->cand[c].name, 1e6 * cr->hypervolume);
  }
#undef PX
#undef PY
  fprintf(f, "</svg>\n");
  return pom_io_commit(&w, err);
}
