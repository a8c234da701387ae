/* pom_doe_sensitivity.c - Sobol indices or Morris effects of a study's
 * candidates over its uncertain parameters, run through the batch runner
 * (docs/results.md, section 11). */
#define _POSIX_C_SOURCE 200809L
#include "pom_explore.h"
#include "pom_h5.h"
#include "pom_io.h"
#include "pom_progress.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- config --------------------------------------------------------------------- */
pom_status pom_doe_sens_load(pom_doe_sens *s, const pom_cfg *cfg, const pom_doe_study *study,
                             pom_error *err) {
  static const char *const methods[] = {"sobol", "morris", NULL};
  static const char *const samplings[] = {"qmc", "random", NULL};
  const char *const *scopes = pom_doe_sens_groups();
  memset(s, 0, sizeof *s);
  int dim = study->uncertain.n;
  if (dim < 1)
    return pom_cfg_error(cfg, "uncertain", NULL, err,
                         "a sensitivity study needs an `uncertain` group: its parameters are the "
                         "inputs (docs/results.md section 10)");
  if (dim > POM_SENS_MAX_DIM)
    return pom_cfg_error(cfg, "uncertain", NULL, err, "at most %d inputs", POM_SENS_MAX_DIM);
  int method = 0, sampling = 0;
  long samples = 0, boot = 0, traj = 0, levels = 0, seed = 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "sensitivity.method", methods, 0, &method, err));
  s->method = (pom_doe_sens_method)method;
  pom_sens_sobol_defaults(&s->sobol);
  pom_sens_morris_defaults(&s->morris);
  s->sobol.dim = s->morris.dim = dim;
  POM_TRY(pom_cfg_int_opt(cfg, "sensitivity.seed", 0, 9007199254740991L,
                          (long)study->maneuvers.seed, &seed, err));
  s->sobol.seed = s->morris.seed = (uint64_t)seed;
  if (method == POM_DOE_SENS_SOBOL) {
    POM_TRY(pom_cfg_int_opt(cfg, "sensitivity.samples", 2, 1L << 20, 512, &samples, err));
    POM_TRY(pom_cfg_choice_opt(cfg, "sensitivity.sampling", samplings, 0, &sampling, err));
    POM_TRY(pom_cfg_int_opt(cfg, "sensitivity.bootstrap", 0, 100000, 1000, &boot, err));
    POM_TRY(pom_cfg_real_opt(cfg, "sensitivity.confidence", 1.0, 0.5, 0.999, 0.95,
                             &s->sobol.confidence, err));
    s->sobol.n_base = samples;
    s->sobol.sampling = (pom_sens_sampling)sampling;
    s->sobol.bootstrap = (int)boot;
  } else {
    POM_TRY(pom_cfg_int_opt(cfg, "sensitivity.trajectories", 2, 1L << 20, 20, &traj, err));
    POM_TRY(pom_cfg_int_opt(cfg, "sensitivity.levels", 2, 64, 4, &levels, err));
    if (levels % 2)
      return pom_cfg_error(cfg, "sensitivity.levels", NULL, err, "expected an even number");
    s->morris.trajectories = traj;
    s->morris.levels = (int)levels;
  }
  char metric[64];
  POM_TRY(
      pom_cfg_string_opt(cfg, "sensitivity.metric", "execution_time", metric, sizeof metric, err));
  s->stat = -1;
  char list[512] = "";
  for (int k = 0; k < POM_DYN_N_STATS; ++k) {
    const pom_dyn_metric_info *mi = pom_dyn_stat_metric(k);
    if (strcmp(metric, mi->name) == 0 || strcmp(metric, mi->stat_name) == 0) s->stat = k;
    size_t used = strlen(list);
    snprintf(list + used, sizeof list - used, "%s\"%s\"", k ? ", " : "", mi->stat_name);
  }
  if (s->stat < 0)
    return pom_cfg_error(cfg, "sensitivity.metric", NULL, err, "expected one of %s", list);
  POM_TRY(pom_cfg_int_opt(cfg, "sensitivity.maneuvers", 1, 1000, 1, &s->per_sample, err));
  char dflt[POM_DOE_PATH_LEN];
  snprintf(dflt, sizeof dflt, "results/%s-sensitivity.h5", study->name);
  POM_TRY(pom_cfg_string_opt(cfg, "sensitivity.output", dflt, s->output, sizeof s->output, err));
  return pom_cfg_check_unknown(cfg, scopes, NULL, err);
}

/* ---- run ------------------------------------------------------------------------ */
void pom_doe_sens_result_destroy(pom_doe_sens_result *r) {
  if (!r) return;
  free(r->u);
  free(r->x);
  free(r->y);
  free(r->sobol);
  free(r->morris);
  free(r->status);
  free(r->reason);
  free(r);
}

void pom_doe_sens_run_opts_defaults(pom_doe_sens_run_opts *o) {
  memset(o, 0, sizeof *o);
}

pom_status pom_doe_sens_run(pom_doe_sens_result **out, pom_doe_study *study, const pom_doe_sens *s,
                            const pom_doe_sens_run_opts *o, pom_error *err) {
  pom_status st = POM_OK;
  *out = NULL;
  int nc = study->n_candidates, d = study->uncertain.n;
  pom_doe_run *run = NULL;
  pom_doe_maneuvers saved_mv = study->maneuvers;
  pom_unc saved_unc = study->uncertain;
  const char *output = o->output ? o->output : "";
  pom_doe_sens_result *r = calloc(1, sizeof *r);
  if (!r) POM_FAIL(err, POM_ERR_NOMEM, "sensitivity: out of memory");
  double t0 = pom_progress_now();
  r->dim = d;
  r->n_candidates = nc;
  r->rows = s->method == POM_DOE_SENS_SOBOL ? pom_sens_sobol_rows(&s->sobol)
                                            : pom_sens_morris_rows(&s->morris);
  r->u = malloc((size_t)(r->rows * d) * sizeof *r->u);
  r->x = malloc((size_t)(r->rows * d) * sizeof *r->x);
  r->y = malloc((size_t)(r->rows * nc) * sizeof *r->y);
  r->status = calloc((size_t)nc, sizeof *r->status);
  r->reason = calloc((size_t)nc, sizeof *r->reason);
  if (s->method == POM_DOE_SENS_SOBOL)
    r->sobol = calloc((size_t)nc, sizeof *r->sobol);
  else
    r->morris = calloc((size_t)nc, sizeof *r->morris);
  if (!r->u || !r->x || !r->y || !r->status || !r->reason || (!r->sobol && !r->morris))
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "sensitivity: out of memory");
  if (s->method == POM_DOE_SENS_SOBOL)
    POM_TRY_GOTO(pom_sens_sobol_design(r->u, &s->sobol, err), fail);
  else
    POM_TRY_GOTO(pom_sens_morris_design(r->u, &s->morris, err), fail);
  for (long k = 0; k < r->rows * d; ++k)
    r->x[k] = pom_dist_quantile(&study->uncertain.param[k % d].dist, r->u[k]);

  /* the design replaces the random draws: unit k = design row k / per_sample
   * on maneuver k % per_sample */
  study->uncertain.design = r->u;
  study->uncertain.design_rows = r->rows;
  study->uncertain.per_row = s->per_sample;
  study->maneuvers.count = r->rows * s->per_sample;
  pom_doe_run_options opt;
  pom_doe_run_options_defaults(&opt);
  /* the output is taken (locked, its rows file made) before the first run */
  opt.output = output;
  opt.rows_only = 1;
  opt.resume = o->resume;
  opt.stop_after = o->stop_after;
  opt.threads = o->threads;
  POM_TRY_GOTO(pom_doe_run_begin(&run, study, &opt, err), fail);
  r->threads = pom_doe_run_threads(run);
  int finished = 0;
  while (!finished) {
    POM_TRY_GOTO(pom_doe_run_step(run, &finished, err), fail);
    if (o->progress) o->progress(pom_doe_run_done(run), pom_doe_run_total(run), o->user);
    if (o->cancel && *o->cancel) {
      pom_doe_run_cancel(run);
      POM_FAIL_GOTO(err, POM_ERR_INTERRUPTED, fail, "sensitivity: interrupted");
    }
  }
  POM_TRY_GOTO(pom_doe_run_end(run, NULL, err), fail);
  if (pom_doe_run_done(run) < pom_doe_run_total(run)) {
    if (output[0])
      POM_FAIL_GOTO(err, POM_ERR_INTERRUPTED, fail,
                    "stopped after %ld of %ld runs; every finished one is in "
                    "'%s.partial': continue with --resume",
                    pom_doe_run_done(run), pom_doe_run_total(run), output);
    POM_FAIL_GOTO(err, POM_ERR_INTERRUPTED, fail, "stopped after %ld of %ld runs",
                  pom_doe_run_done(run), pom_doe_run_total(run));
  }
  for (int c = 0; c < nc; ++c)
    for (long row = 0; row < r->rows; ++row) {
      double sum = 0;
      for (long m = 0; m < s->per_sample; ++m)
        sum += pom_doe_run_value(run, c, row * s->per_sample + m, s->stat);
      r->y[c * r->rows + row] = sum / (double)s->per_sample; /* NaN when any run failed */
    }
  for (int c = 0; c < nc; ++c) {
    pom_error e;
    pom_error_clear(&e);
    const double *y = r->y + c * r->rows;
    r->status[c] = s->method == POM_DOE_SENS_SOBOL
                       ? pom_sens_sobol_indices(&r->sobol[c], y, &s->sobol, &e)
                       : pom_sens_morris_effects(&r->morris[c], r->u, y, &s->morris, &e);
    snprintf(r->reason[c], sizeof r->reason[c], "%s", r->status[c] ? e.message : "");
  }
  r->wall = pom_progress_now() - t0;
  study->maneuvers = saved_mv;
  study->uncertain = saved_unc;
  /* the indices stand whatever happens to the file: the caller shows them */
  *out = r;
  int usable = 0;
  for (int c = 0; c < nc; ++c)
    usable += r->status[c] == POM_OK;
  /* no candidate with indices: no file of NaN (the caller says why) */
  if (output[0] && usable > 0) {
    st = pom_doe_sens_write(output, study, s, r, err);
    if (st == POM_OK) st = pom_doe_run_rows_done(run, err);
    if (st != POM_OK)
      pom_error_prefix(err,
                       "every run is kept in '%s.partial' (--resume writes the file without "
                       "running again)",
                       output);
  }
  pom_doe_run_destroy(run);
  return st;
fail:
  pom_doe_run_destroy(run);
  study->maneuvers = saved_mv;
  study->uncertain = saved_unc;
  pom_doe_sens_result_destroy(r);
  return st;
}

/* ---- results file ---------------------------------------------------------------- */
static pom_status write_file(const char *path, const pom_doe_study *study, const pom_doe_sens *s,
                             const pom_doe_sens_result *r, pom_error *err) {
  pom_status st = POM_OK;
  hid_t f = -1, g = -1;
  const pom_unc *unc = &study->uncertain;
  const pom_dyn_metric_info *mi = pom_dyn_stat_metric(s->stat);
  const char *keys[POM_UNC_MAX], *dists[POM_UNC_MAX];
  for (int j = 0; j < unc->n; ++j) {
    keys[j] = unc->param[j].key;
    dists[j] = unc->param[j].dist.ops->name;
  }
  POM_TRY(pom_h5_create_file(&f, path, err));
  POM_TRY_GOTO(pom_h5_attr_string(f, "format", "pomlab sensitivity results", err), done);
  POM_TRY_GOTO(pom_h5_attr_string(f, "study_name", study->name, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(f, "study_source", study->source, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(f, "method", s->method ? "morris" : "sobol", err), done);
  POM_TRY_GOTO(pom_h5_attr_string(f, "metric", mi->stat_name, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(f, "metric_unit",
                                  pom_dyn_metric_unit(mi, study->candidates[0].eval.actuator_kind),
                                  err),
               done);
  POM_TRY_GOTO(pom_h5_attr_int64(f, "maneuvers_per_sample", s->per_sample, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(f, "maneuver_seed", (int64_t)study->maneuvers.seed, err), done);
  if (s->method == POM_DOE_SENS_SOBOL) {
    POM_TRY_GOTO(pom_h5_attr_int64(f, "base_samples", s->sobol.n_base, err), done);
    POM_TRY_GOTO(pom_h5_attr_string(f, "sampling", s->sobol.sampling ? "random" : "qmc", err),
                 done);
    POM_TRY_GOTO(pom_h5_attr_int64(f, "bootstrap", s->sobol.bootstrap, err), done);
    POM_TRY_GOTO(pom_h5_attr_double(f, "confidence", s->sobol.confidence, err), done);
    POM_TRY_GOTO(pom_h5_attr_int64(f, "seed", (int64_t)s->sobol.seed, err), done);
  } else {
    POM_TRY_GOTO(pom_h5_attr_int64(f, "trajectories", s->morris.trajectories, err), done);
    POM_TRY_GOTO(pom_h5_attr_int64(f, "levels", s->morris.levels, err), done);
    POM_TRY_GOTO(pom_h5_attr_int64(f, "seed", (int64_t)s->morris.seed, err), done);
  }
  POM_TRY_GOTO(pom_h5_write_text(f, "study_config", study->config_text, err), done);
  POM_TRY_GOTO(pom_h5_write_strings(f, "inputs", (size_t)unc->n, keys, POM_UNC_KEY_LEN, err), done);
  POM_TRY_GOTO(pom_h5_write_strings(f, "distributions", (size_t)unc->n, dists, 24, err), done);
  const char *names[4096];
  int nc = r->n_candidates < 4096 ? r->n_candidates : 4096;
  for (int c = 0; c < nc; ++c)
    names[c] = study->candidates[c].name;
  POM_TRY_GOTO(pom_h5_write_strings(f, "candidates", (size_t)nc, names, POM_DOE_NAME_LEN, err),
               done);
  size_t dims[2] = {(size_t)r->rows, (size_t)r->dim};
  POM_TRY_GOTO(pom_h5_write_doubles(f, "design", 2, dims, r->u, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(f, "values", 2, dims, r->x, err), done);
  dims[0] = (size_t)nc;
  dims[1] = (size_t)r->rows;
  POM_TRY_GOTO(pom_h5_write_doubles(f, "outputs", 2, dims, r->y, err), done);
  /* indices [candidate][input] */
  size_t n = (size_t)(nc * r->dim);
  double *buf = malloc(n * 6 * sizeof *buf);
  if (!buf) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "sensitivity: out of memory");
  for (int c = 0; c < nc; ++c)
    for (int i = 0; i < r->dim; ++i) {
      size_t at = (size_t)(c * r->dim + i);
      if (r->sobol) {
        const pom_sens_sobol_result *o = &r->sobol[c];
        int ok = r->status[c] == POM_OK;
        double v[6] = {o->S1[i], o->S1_low[i], o->S1_high[i],
                       o->ST[i], o->ST_low[i], o->ST_high[i]};
        for (int q = 0; q < 6; ++q)
          buf[(size_t)q * n + at] = ok ? v[q] : NAN;
      } else {
        const pom_sens_morris_result *o = &r->morris[c];
        double v[4] = {o->mu_star[i], o->mu[i], o->sigma[i], (double)o->n_effects[i]};
        for (int q = 0; q < 4; ++q)
          buf[(size_t)q * n + at] = v[q];
      }
    }
  static const char *const sobol_sets[] = {"S1", "S1_low", "S1_high", "ST", "ST_low", "ST_high"};
  static const char *const morris_sets[] = {"mu_star", "mu", "sigma", "n_effects"};
  dims[1] = (size_t)r->dim;
  pom_status wst = pom_h5_create_group(&g, f, r->sobol ? "sobol" : "morris", err);
  for (int q = 0; q < (r->sobol ? 6 : 4) && wst == POM_OK; ++q)
    wst = pom_h5_write_doubles(g, r->sobol ? sobol_sets[q] : morris_sets[q], 2, dims,
                               buf + (size_t)q * n, err);
  free(buf);
  POM_TRY_GOTO(wst, done);
done:
  if (g >= 0) H5Gclose(g);
  if (f >= 0) {
    pom_status cst = pom_h5_close_file(f, st == POM_OK ? err : NULL);
    if (st == POM_OK) st = cst;
  }
  return st;
}

pom_status pom_doe_sens_write(const char *path, const pom_doe_study *study, const pom_doe_sens *s,
                              const pom_doe_sens_result *r, pom_error *err) {
  char tmp[POM_DOE_PATH_LEN + 32];
  snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
  pom_status st = write_file(tmp, study, s, r, err);
  if (st == POM_OK) st = pom_io_sync(tmp, err);
  if (st == POM_OK && rename(tmp, path) != 0)
    st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__, "cannot rename '%s' to '%s': %s", tmp,
                       path, strerror(errno));
  if (st == POM_OK) st = pom_io_sync_folder(path, err);
  if (st != POM_OK) {
    remove(tmp);
    pom_error_prefix(err, "writing sensitivity file '%s'", path);
  }
  return st;
}
