/* pom_job_sens.c - a sensitivity analysis's job (`pomlab sensitivity`,
 * docs/results.md section 11): the earned fidelity, the path and memory
 * checks, the runs with progress, the indices as a table or JSON, and the
 * bar plot. */
#define _POSIX_C_SOURCE 200809L
#include "pom_job.h"
#include "job_internal.h"
#include "pom_explore.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_progress.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Runs at or above which the time is measured and announced when long;
 * announced: over 10 s, or over 1 GB of memory or of results file (as a
 * study's, pom_job.c). */
#define ANNOUNCE_MIN_RUNS 64
#define ANNOUNCE_SECONDS  10.0
#define ANNOUNCE_BYTES    1e9

/* ---- checks ---------------------------------------------------------------------------------- */
/* The memory refusal and the announcement of pom_job_sens_check. */
static int sens_cost(const pom_doe_study *study, const char *method, long rows, long per_sample,
                     int dim, int threads, int quiet, FILE *msg) {
  pom_doe_cost cost;
  pom_doe_cost_sensitivity(&cost, study, rows, per_sample, dim);
  double limit = pom_doe_memory_limit();
  char mem[32], have[32], file[32], how_long[48];
  int sobol = strcmp(method, "sobol") == 0;
  if (cost.memory > limit) {
    fprintf(msg,
            "pomlab sensitivity: config: %s: %ld design rows (%s) x %ld maneuver(s) "
            "(sensitivity.maneuvers) x %d candidate(s) = %.4g runs need about %s of memory (%.0f "
            "bytes per run), more than this machine's %s: lower %s, sensitivity.maneuvers or the "
            "candidates (--candidate runs one); nothing was run\n",
            study->source, rows,
            sobol ? "sensitivity.samples N x (inputs + 2)"
                  : "sensitivity.trajectories r x (inputs + 1)",
            per_sample, study->n_candidates, cost.runs,
            pom_job_bytes_text(mem, sizeof mem, cost.memory), cost.per_run,
            pom_job_bytes_text(have, sizeof have, limit),
            sobol ? "sensitivity.samples" : "sensitivity.trajectories");
    return 2;
  }
  if (quiet || !msg) return 0;
  double per_run = NAN;
  pom_error err;
  pom_error_clear(&err);
  if (cost.runs >= ANNOUNCE_MIN_RUNS) pom_doe_calibrate(&per_run, study, &err);
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  int n_threads = threads > 0          ? threads
                  : study->threads > 0 ? study->threads
                                       : (int)(cores > 0 ? cores : 1);
  double seconds = per_run * cost.runs / n_threads;
  if (!(seconds > ANNOUNCE_SECONDS) && !(cost.memory > ANNOUNCE_BYTES) &&
      !(cost.file > ANNOUNCE_BYTES))
    return 0;
  fprintf(msg,
          "pomlab sensitivity: %s: %ld design rows x %ld maneuver(s) x %d candidate(s) = %.4g "
          "runs; memory about %s, results file about %s",
          study->name, rows, per_sample, study->n_candidates, cost.runs,
          pom_job_bytes_text(mem, sizeof mem, cost.memory),
          pom_job_bytes_text(file, sizeof file, cost.file));
  if (isfinite(seconds))
    fprintf(msg, "; %s on %d thread(s) (%.3g ms per run, measured on a few runs)",
            pom_job_duration_text(how_long, sizeof how_long, seconds), n_threads, per_run * 1e3);
  fprintf(msg, "\n");
  return 0;
}

int pom_job_sens_check(const char *cfg_path, const pom_doe_study *study, const pom_doe_sens *sens,
                       int out_given, int plots, int threads, int quiet, FILE *msg) {
  char png[POM_DOE_PATH_LEN + 8]; /* the figure: the output without .h5, .png */
  snprintf(png, sizeof png, "%s", sens->output);
  char *dot = strrchr(png, '.');
  if (dot && !strchr(dot, '/')) *dot = '\0';
  strcat(png, ".png");
  pom_job_paths *p = pom_job_inputs("sensitivity", cfg_path, study);
  pom_job_paths_output(p, sens->output,
                       out_given ? "the results file (--out)"
                                 : "the results file (sensitivity.output)");
  if (plots) pom_job_paths_output(p, png, "the figure");
  int rc = pom_job_paths_check(p, msg, NULL);
  pom_job_paths_destroy(p);
  if (rc) return rc;
  int sobol = sens->method == POM_DOE_SENS_SOBOL;
  long rows = sobol ? pom_sens_sobol_rows(&sens->sobol) : pom_sens_morris_rows(&sens->morris);
  return sens_cost(study, sobol ? "sobol" : "morris", rows, sens->per_sample, study->uncertain.n,
                   threads, quiet, msg);
}

int pom_job_sens_failures(const pom_doe_study *study, const pom_doe_sens_result *r,
                          const char *output, FILE *msg) {
  int usable = 0;
  for (int c = 0; c < r->n_candidates; ++c) {
    if (r->status[c] == POM_OK) {
      ++usable;
      continue;
    }
    fprintf(msg, "pomlab sensitivity: candidate '%s': no indices: %s\n", study->candidates[c].name,
            r->reason[c]);
  }
  if (usable == 0)
    fprintf(msg,
            "pomlab sensitivity: no candidate has indices, so nothing was written to %s; `pomlab "
            "study` of the same file gives each run's status and reason\n",
            output);
  return usable;
}

/* ---- the indices ---------------------------------------------------------------------------- */
static void on_progress(long done, long total, void *user) {
  pom_progress_update(user, done);
  (void)total;
}

static void json_num(FILE *out, double v) {
  if (isfinite(v))
    fprintf(out, "%.9g", v);
  else
    fprintf(out, "null");
}

static void print_text(FILE *out, const pom_doe_study *study, const pom_doe_sens *s,
                       const pom_doe_sens_result *r) {
  const pom_dyn_metric_info *mi = pom_dyn_stat_metric(s->stat);
  double to_text = 1.0; /* SI to the text unit (ms, J, mm, deg: docs/conventions.md) */
  const char *unit =
      pom_dyn_metric_display_unit(mi, study->candidates[0].eval.actuator_kind, &to_text);
  fprintf(out, "## Sensitivity of %s (%s) to %d uncertain parameter(s)\n\n", mi->stat_name, unit,
          r->dim);
  if (r->sobol)
    fprintf(out,
            "Sobol indices, %ld base samples (%s), %ld runs per candidate x %ld maneuver(s), "
            "%.0f %% bootstrap intervals (%d resamples); %.2f s wall on %d thread(s).\n",
            s->sobol.n_base, s->sobol.sampling ? "random" : "Sobol sequence", r->rows,
            s->per_sample, 100 * s->sobol.confidence, s->sobol.bootstrap, r->wall, r->threads);
  else
    fprintf(out,
            "Morris elementary effects, %ld trajectories on %d levels, %ld runs per candidate x "
            "%ld maneuver(s); effects per unit of each input's probability (u); %.2f s wall "
            "on %d thread(s).\n",
            s->morris.trajectories, s->morris.levels, r->rows, s->per_sample, r->wall, r->threads);
  for (int c = 0; c < r->n_candidates; ++c) {
    fprintf(out, "\n### %s\n\n", study->candidates[c].name);
    if (r->status[c] != POM_OK) {
      fprintf(out, "No indices: %s\n", r->reason[c]);
      continue;
    }
    if (r->sobol) {
      const pom_sens_sobol_result *o = &r->sobol[c];
      fprintf(out, "output mean %.6g %s, sd %.4g %s; %ld of %ld base samples used\n\n",
              o->mean * to_text, unit, sqrt(o->variance) * to_text, unit, o->n_used,
              o->n_used + o->n_failed);
      fprintf(out, "| parameter | S1 | interval | ST | interval |\n|---|---:|---:|---:|---:|\n");
      for (int i = 0; i < r->dim; ++i)
        fprintf(out, "| %s | %.3f | [%.3f, %.3f] | %.3f | [%.3f, %.3f] |\n",
                study->uncertain.param[i].key, o->S1[i], o->S1_low[i], o->S1_high[i], o->ST[i],
                o->ST_low[i], o->ST_high[i]);
    } else {
      const pom_sens_morris_result *o = &r->morris[c];
      fprintf(out, "| parameter | mu* (%s) | mu | sigma | effects |\n|---|---:|---:|---:|---:|\n",
              unit);
      for (int i = 0; i < r->dim; ++i)
        fprintf(out, "| %s | %.4g | %.4g | %.4g | %ld |\n", study->uncertain.param[i].key,
                o->mu_star[i] * to_text, o->mu[i] * to_text, o->sigma[i] * to_text,
                o->n_effects[i]);
    }
  }
}

static void print_json(FILE *out, const pom_doe_study *study, const pom_doe_sens *s,
                       const pom_doe_sens_result *r) {
  const pom_dyn_metric_info *mi = pom_dyn_stat_metric(s->stat);
  fprintf(out, "{\n  \"method\": \"%s\",\n  \"metric\": \"%s\",\n  \"unit\": \"%s\",\n",
          r->sobol ? "sobol" : "morris", mi->stat_name,
          pom_dyn_metric_unit(mi, study->candidates[0].eval.actuator_kind));
  fprintf(out, "  \"runs_per_candidate\": %ld,\n  \"maneuvers_per_sample\": %ld,\n", r->rows,
          s->per_sample);
  fprintf(out, "  \"inputs\": [");
  for (int i = 0; i < r->dim; ++i)
    fprintf(out, "%s\"%s\"", i ? ", " : "", study->uncertain.param[i].key);
  fprintf(out, "],\n  \"candidates\": [\n");
  for (int c = 0; c < r->n_candidates; ++c) {
    fprintf(out, "    {\"name\": \"%s\", \"ok\": %s", study->candidates[c].name,
            r->status[c] == POM_OK ? "true" : "false");
    for (int i = 0; i < r->dim && r->status[c] == POM_OK; ++i) {
      fprintf(out, "%s", i ? ",\n       " : ", \"indices\": [\n       ");
      if (r->sobol) {
        const pom_sens_sobol_result *o = &r->sobol[c];
        double v[6] = {o->S1[i], o->S1_low[i], o->S1_high[i],
                       o->ST[i], o->ST_low[i], o->ST_high[i]};
        fprintf(out, "{\"S1\": ");
        json_num(out, v[0]);
        fprintf(out, ", \"S1_ci\": [");
        json_num(out, v[1]);
        fprintf(out, ", ");
        json_num(out, v[2]);
        fprintf(out, "], \"ST\": ");
        json_num(out, v[3]);
        fprintf(out, ", \"ST_ci\": [");
        json_num(out, v[4]);
        fprintf(out, ", ");
        json_num(out, v[5]);
        fprintf(out, "]}");
      } else {
        const pom_sens_morris_result *o = &r->morris[c];
        fprintf(out, "{\"mu_star\": ");
        json_num(out, o->mu_star[i]);
        fprintf(out, ", \"mu\": ");
        json_num(out, o->mu[i]);
        fprintf(out, ", \"sigma\": ");
        json_num(out, o->sigma[i]);
        fprintf(out, "}");
      }
    }
    fprintf(out, "%s}%s\n", r->status[c] == POM_OK ? "]" : "", c + 1 < r->n_candidates ? "," : "");
  }
  fprintf(out, "  ]\n}\n");
}

/* ---- the job ------------------------------------------------------------------------------- */
int pom_job_sensitivity(pom_doe_study *study, pom_doe_sens *sens, const pom_job_sens_options *o) {
  FILE *msg = o->msg, *out = o->out;
  pom_error err;
  pom_error_clear(&err);
  /* study.fidelity = "auto": each candidate's earned setting, as in the
     study (docs/results.md section 12) */
  pom_status st = pom_doe_capability_run(study, NULL, NULL, &err);
  if (st != POM_OK) {
    pom_job_report_error(msg, "capability", &err);
    return pom_job_exit_code(st, NULL);
  }
  st = pom_doe_fidelity_run(study, NULL, NULL, &err);
  if (st != POM_OK) {
    pom_job_report_error(msg, "fidelity", &err);
    return pom_job_exit_code(st, NULL);
  }
  if (o->output) snprintf(sens->output, sizeof sens->output, "%s", o->output);
  /* outputs that would overwrite an input refused, a run too large for
     memory refused, a long one announced: before any work */
  int pre = pom_job_sens_check(o->cfg_path, study, sens, o->output != NULL, o->plots, o->threads,
                               o->quiet, msg);
  if (pre) return pre;
  pom_progress bar;
  long total = (sens->method == POM_DOE_SENS_SOBOL ? pom_sens_sobol_rows(&sens->sobol)
                                                   : pom_sens_morris_rows(&sens->morris)) *
               sens->per_sample * study->n_candidates;
  pom_progress_init(&bar, o->quiet ? NULL : msg, "sensitivity", total, 0, 0);
  pom_doe_sens_result *r = NULL;
  pom_doe_sens_run_opts ro;
  pom_doe_sens_run_opts_defaults(&ro);
  ro.threads = o->threads;
  ro.output = sens->output;
  ro.resume = o->resume;
  ro.stop_after = o->stop_after;
  ro.progress = on_progress;
  ro.user = &bar;
  /* the output is locked and its rows file made before the first run */
  st = pom_doe_sens_run(&r, study, sens, &ro, &err);
  pom_progress_finish(&bar, r ? total : 0);
  int code = 0;
  /* candidates without indices said on msg; with none, nothing on out and
   * no file of NaN (the runs stay in the .partial) */
  if (r && st == POM_OK && pom_job_sens_failures(study, r, sens->output, msg) == 0) {
    pom_doe_sens_result_destroy(r);
    return 1;
  }
  /* the indices, even when the file could not be written */
  if (r) {
    if (o->json)
      print_json(out, study, sens, r);
    else
      print_text(out, study, sens, r);
    for (int c = 0; c < r->n_candidates; ++c)
      if (r->status[c] != POM_OK) code = 1;
  }
  if (st != POM_OK) {
    pom_job_report_error(msg, "sensitivity", &err);
    /* stopped by --stop-after: exit 0, as pomlab study */
    code = st == POM_ERR_INTERRUPTED && o->stop_after > 0 ? 0 : pom_job_exit_code(st, NULL);
  } else {
    if (o->plots) {
      char png[POM_DOE_PATH_LEN + 8];
      snprintf(png, sizeof png, "%s", sens->output);
      char *dot = strrchr(png, '.');
      if (dot && !strchr(dot, '/')) *dot = '\0';
      strcat(png, ".png");
      if (pom_job_run_script(o->scripts_dir, "plot_sensitivity.py", sens->output, png, msg) != 0)
        fprintf(msg, "pomlab sensitivity: the figure was not drawn (needs /usr/bin/python3 "
                     "with h5py and matplotlib)\n");
      else if (!o->json)
        fprintf(out, "\nfigure: %s\n", png);
    }
    if (!o->json) fprintf(out, "results: %s\n", sens->output);
  }
  pom_doe_sens_result_destroy(r);
  return code;
}
