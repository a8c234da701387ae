/* cmd_sensitivity.c - `pomlab sensitivity CFG`: Sobol indices or Morris
 * effects of every candidate of a study file over its uncertain parameters;
 * table or JSON, HDF5 file and bar plot (docs/results.md, section 11). */
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_doe_sensitivity.h"
#include "pom_pipeline.h"
#include "pom_progress.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void usage(FILE *out) {
  fprintf(out, "usage: pomlab sensitivity CONFIG [options]\n\n"
               "Global sensitivity of every candidate of a study file to the parameters of its\n"
               "`uncertain` group: Sobol first-order and total indices with bootstrap intervals\n"
               "(sensitivity.method = \"sobol\", Saltelli design, N (d + 2) runs) or Morris\n"
               "elementary effects (\"morris\", r (d + 1) runs), for one metric of each run\n"
               "(sensitivity.metric, default execution_time). Writes an HDF5 file\n"
               "(sensitivity.output, default results/<name>-sensitivity.h5) and a bar plot\n"
               "beside it (.png).\n\n"
               "  --candidate C only this candidate of the study (its name as printed, or its\n"
               "                position 1..n): e.g. the winner of a sweep\n"
               "  --threads N   worker threads (default: study.threads, else all cores)\n"
               "  --out FILE    results file (replaced only once complete; taken before the\n"
               "                first run: FILE.lock, and FILE.partial keeps every run)\n"
               "  --resume      continue FILE.partial of an interrupted run (or one whose\n"
               "                file could not be written: then nothing runs again)\n"
               "  --stop-after N stop after N more runs (to test --resume)\n"
               "  --json        JSON on stdout instead of tables\n"
               "  --no-plots    skip the figure\n"
               "  --quiet       no progress bar\n"
               "  --help        this text\n\n"
               "Config keys: docs/results.md sections 10 and 11.\n"
               "Exit status: 0 done; 1 runtime failure (e.g. the output cannot be written: the\n"
               "indices are printed all the same; or too few runs succeeded for the indices);\n"
               "2 usage or config error. Stopped by --stop-after: 0 (continue with --resume).\n");
}

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

/* A positive count for --stop-after; -1 when text is not one. */
static long parse_positive(const char *text) {
  char *end = NULL;
  errno = 0;
  long v = strtol(text, &end, 10);
  return text[0] && !*end && errno == 0 && v >= 1 ? v : -1;
}

int pom_cmd_sensitivity(int argc, char **argv) {
  const char *cfg_path = NULL, *out_path = NULL, *only = NULL;
  int json = 0, plots = 1, quiet = 0;
  int threads = 0, resume = 0;
  long stop_after = 0;
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k];
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(a, "--threads") == 0 && k + 1 < argc) {
      if (pom_cli_parse_threads("sensitivity", argv[++k], &threads) != 0) return 2;
    } else if (strcmp(a, "--out") == 0 && k + 1 < argc) {
      out_path = argv[++k];
    } else if (strcmp(a, "--resume") == 0) {
      resume = 1;
    } else if (strcmp(a, "--stop-after") == 0 && k + 1 < argc) {
      stop_after = parse_positive(argv[++k]);
      if (stop_after < 1) {
        fprintf(stderr, "pomlab sensitivity: --stop-after needs a positive integer, not '%s'\n",
                argv[k]);
        return 2;
      }
    } else if (strcmp(a, "--candidate") == 0 && k + 1 < argc) {
      only = argv[++k];
    } else if (strcmp(a, "--json") == 0) {
      json = 1;
    } else if (strcmp(a, "--no-plots") == 0) {
      plots = 0;
    } else if (strcmp(a, "--quiet") == 0) {
      quiet = 1;
    } else if (a[0] == '-' || cfg_path) {
      fprintf(stderr, "pomlab sensitivity: unexpected argument '%s'\n\n", a);
      usage(stderr);
      return 2;
    } else {
      cfg_path = a;
    }
  }
  if (!cfg_path) {
    usage(stderr);
    return 2;
  }
  pom_error err;
  pom_error_clear(&err);
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  pom_doe_sens sens;
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load(&cfg, cfg_path, &err);
  if (st == POM_OK) st = pom_doe_study_load(&study, cfg, pom_pipeline_evaluator_create, NULL, &err);
  if (st == POM_OK && only && pom_doe_study_select(&study, only, &err) != POM_OK) {
    pom_cli_report("sensitivity --candidate", &err);
    pom_cfg_destroy(cfg);
    pom_doe_study_clear(&study);
    return 2;
  }
  if (st == POM_OK) st = pom_doe_sens_load(&sens, cfg, &study, &err);
  int loaded = cfg != NULL;
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_doe_study_clear(&study);
    return loaded ? pom_cli_exit_code(st) : 2;
  }
  /* study.fidelity = "auto": each candidate's earned setting, as in the
     study (docs/results.md section 12) */
  if ((st = pom_doe_fidelity_run(&study, NULL, NULL, &err)) != POM_OK) {
    pom_cli_report("fidelity", &err);
    pom_doe_study_clear(&study);
    return pom_cli_exit_code(st);
  }
  if (out_path) snprintf(sens.output, sizeof sens.output, "%s", out_path);
  /* outputs that would overwrite an input refused, a run too large for
     memory refused, a long one announced: before any work */
  int pre =
      pom_job_sens_check(cfg_path, &study, &sens, out_path != NULL, plots, threads, quiet, stderr);
  if (pre) {
    pom_doe_study_clear(&study);
    return pre;
  }
  pom_progress bar;
  long total = (sens.method == POM_DOE_SENS_SOBOL ? pom_sens_sobol_rows(&sens.sobol)
                                                  : pom_sens_morris_rows(&sens.morris)) *
               sens.per_sample * study.n_candidates;
  pom_progress_init(&bar, quiet ? NULL : stderr, "sensitivity", total, 0, 0);
  pom_doe_sens_result *r = NULL;
  pom_doe_sens_run_opts ro;
  pom_doe_sens_run_opts_defaults(&ro);
  ro.threads = threads;
  ro.output = sens.output;
  ro.resume = resume;
  ro.stop_after = stop_after;
  ro.progress = on_progress;
  ro.user = &bar;
  /* the output is locked and its rows file made before the first run */
  st = pom_doe_sens_run(&r, &study, &sens, &ro, &err);
  pom_progress_finish(&bar, r ? total : 0);
  int code = 0;
  /* candidates without indices said on stderr; with none, nothing on stdout
   * and no file of NaN (the runs stay in the .partial) */
  if (r && st == POM_OK && pom_job_sens_failures(&study, r, sens.output, stderr) == 0) {
    pom_doe_sens_result_destroy(r);
    pom_doe_study_clear(&study);
    return 1;
  }
  /* the indices, even when the file could not be written */
  if (r) {
    if (json)
      print_json(stdout, &study, &sens, r);
    else
      print_text(stdout, &study, &sens, r);
    for (int c = 0; c < r->n_candidates; ++c)
      if (r->status[c] != POM_OK) code = 1;
  }
  if (st != POM_OK) {
    pom_cli_report("sensitivity", &err);
    /* stopped by --stop-after: exit 0, as pomlab study */
    code = st == POM_ERR_INTERRUPTED && stop_after > 0 ? 0 : pom_cli_exit_code(st);
  } else {
    if (plots) {
      char png[POM_DOE_PATH_LEN + 8];
      snprintf(png, sizeof png, "%s", sens.output);
      char *dot = strrchr(png, '.');
      if (dot && !strchr(dot, '/')) *dot = '\0';
      strcat(png, ".png");
      char scripts[1024];
      pom_cli_scripts_dir(scripts, sizeof scripts);
      if (pom_job_run_script(scripts, "plot_sensitivity.py", sens.output, png, stderr) != 0)
        fprintf(stderr, "pomlab sensitivity: the figure was not drawn (needs /usr/bin/python3 "
                        "with h5py and matplotlib)\n");
      else if (!json)
        printf("\nfigure: %s\n", png);
    }
    if (!json) printf("results: %s\n", sens.output);
  }
  pom_doe_sens_result_destroy(r);
  pom_doe_study_clear(&study);
  return code;
}
