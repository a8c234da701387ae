/* cli_doe.c - running a study for the user: progress, Ctrl-C, tables,
 * verdict, summary.md and figures (docs/results.md, "What you see"). */
#define _POSIX_C_SOURCE 200809L
#include "cli_doe.h"
#include "pom_version.h"
#include "pom_cli.h"
#include "pom_progress.h"
#include "pom_math.h"

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
                           pom_doe_paired *out) {
  for (int j = 0; j < rep->n_comparisons; ++j) {
    const pom_doe_comparison *c = &rep->cmp[j];
    if (c->metric != metric) continue;
    if (c->a == a && c->b == b) {
      *out = c->test;
      return 1;
    }
    if (c->a == b && c->b == a) {
      *out = c->test;
      out->mean_diff = -c->test.mean_diff;
      out->ci_low = -c->test.ci_high;
      out->ci_high = -c->test.ci_low;
      out->win_fraction = 1.0 - c->test.win_fraction;
      return 1;
    }
  }
  return 0;
}

static void stats_row(FILE *out, const char *name, const pom_doe_stats *s, double scale, int prec,
                      const pom_doe_candidate_stats *cs, int with_unsettled) {
  char mx[32], mean[32], mn[32], sd[32], med[32], p95[32];
  fmt_num(mx, sizeof mx, s->max, scale, prec);
  fmt_num(mean, sizeof mean, s->mean, scale, prec);
  fmt_num(mn, sizeof mn, s->min, scale, prec);
  fmt_num(sd, sizeof sd, s->sigma, scale, prec);
  fmt_num(med, sizeof med, s->median, scale, prec);
  fmt_num(p95, sizeof p95, s->p95, scale, prec);
  fprintf(out, "| %s | %s | %s | %s | %s | %s | %s | %ld |", name, mx, mean, mn, sd, med, p95,
          s->n);
  if (with_unsettled) fprintf(out, " %ld |", cs->n_unsettled);
  fprintf(out, " %ld |\n", cs->n_failed);
}

static const char *metric_label(pom_doe_metric m) {
  return m == POM_DOE_METRIC_TIME ? "execution time" : "expended energy";
}

/* ---- actuator kinds ------------------------------------------------------------------ */
pom_actuator_kind pom_cli_doe_study_kind(const pom_doe_study *study, int *mixed) {
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
  pom_cli_doe_study_kind(study, &mixed);
  if (mixed)
    fprintf(out, "The candidates mix actuator kinds (prismatic: q in mm; revolute: q in deg), so "
                 "the comparison is in orientation space: every candidate is driven to the same "
                 "platform orientations (its own actuator targets by inverse kinematics).\n\n");
}

/* ---- the report ---------------------------------------------------------------------- */
void pom_cli_doe_print_report(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  int nc = rep->n_candidates;
  mixed_kinds_note(out, study);
  fprintf(out, "### Table 1: execution time (ms)\n\n");
  fprintf(out, "| candidate | max | mean | min | sigma | median | p95 | n | unsettled | failed |\n"
               "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int c = 0; c < nc; ++c)
    stats_row(out, study->candidates[c].name, &rep->cand[c].execution_time, 1e3, 2, &rep->cand[c],
              1);
  fprintf(out, "\n### Table 2: expended energy (J)\n\n");
  fprintf(out, "| candidate | max | mean | min | sigma | median | p95 | n | failed |\n"
               "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int c = 0; c < nc; ++c)
    stats_row(out, study->candidates[c].name, &rep->cand[c].energy, 1.0, 4, &rep->cand[c], 0);
  fprintf(out, "\nExecution time = largest settling time of the three actuators (2 %% band), over "
               "maneuvers that settled within the horizon; energy = sum over the actuators of the "
               "signed integral of u i over the horizon.\n");
  fprintf(out, "\n### Table 1b: execution time (ms), MATLAB stepinfo definition\n\n");
  fprintf(out, "| candidate | max | mean | min | sigma | median | p95 | n | failed |\n"
               "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int c = 0; c < nc; ++c)
    stats_row(out, study->candidates[c].name, &rep->cand[c].execution_time_final, 1e3, 2,
              &rep->cand[c], 0);
  fprintf(out, "\nstepinfo: each actuator's band is 2 %% of its largest deviation from its value "
               "at the horizon, about that value (the paper's MATLAB post-processing most likely "
               "used it); defined for tiny steps too.\n");

  if (rep->n_comparisons > 0) {
    fprintf(out, "\n### Paired comparisons (same maneuvers; difference = A - B)\n\n");
    fprintf(out,
            "| response | A | B | pairs | mean A - B | %.0f %% interval | Wilcoxon p | A "
            "better |\n|---|---|---|---:|---:|---:|---:|---:|\n",
            100 * study->confidence);
    for (int j = 0; j < rep->n_comparisons; ++j) {
      const pom_doe_comparison *c = &rep->cmp[j];
      double scale = c->metric == POM_DOE_METRIC_TIME ? 1e3 : 1.0;
      int prec = c->metric == POM_DOE_METRIC_TIME ? 3 : 5;
      char md[32], lo[32], hi[32], p[32];
      fmt_num(md, sizeof md, c->test.mean_diff, scale, prec);
      fmt_num(lo, sizeof lo, c->test.ci_low, scale, prec);
      fmt_num(hi, sizeof hi, c->test.ci_high, scale, prec);
      fmt_p(p, sizeof p, c->test.wilcoxon_p);
      fprintf(out, "| %s (%s) | %s | %s | %ld | %s | [%s, %s] | %s | %.1f %% |\n",
              metric_label(c->metric), c->metric == POM_DOE_METRIC_TIME ? "ms" : "J",
              study->candidates[c->a].name, study->candidates[c->b].name, c->test.n, md, lo, hi, p,
              100 * c->test.win_fraction);
    }
  }

  fprintf(out, "\n### Ranking (mean over the maneuvers every candidate completed)\n\n");
  /* the primary metric (study.rank_by) first */
  const int metrics[2] = {study->rank_by == POM_DOE_RANK_ENERGY,
                          study->rank_by != POM_DOE_RANK_ENERGY};
  for (int j = 0; j < 2; ++j) {
    int m = metrics[j];
    const int *order = m == 0 ? rep->rank_time : rep->rank_energy;
    fprintf(out, "- %s%s: ", metric_label((pom_doe_metric)m), j == 0 ? " (primary)" : "");
    for (int r = 0; r < nc; ++r)
      fprintf(out, "%s%d. %s", r ? ", " : "", r + 1, study->candidates[order[r]].name);
    fprintf(out, "\n");
  }

  fprintf(out, "\n### Verdict\n\n");
  if (nc < 2) {
    fprintf(out, "One candidate: nothing to compare.\n");
    return;
  }
  for (int j = 0; j < 2; ++j) {
    int m = metrics[j];
    const int *order = m == 0 ? rep->rank_time : rep->rank_energy;
    int a = order[0], b = order[1];
    pom_doe_paired t;
    if (!find_comparison(rep, a, b, (pom_doe_metric)m, &t) || t.n == 0) {
      fprintf(out, "- %s: no maneuver that both %s and %s completed.\n",
              metric_label((pom_doe_metric)m), study->candidates[a].name,
              study->candidates[b].name);
      continue;
    }
    double scale = m == 0 ? 1e3 : 1.0;
    const char *unit = m == 0 ? "ms" : "J";
    char p[32];
    fmt_p(p, sizeof p, t.wilcoxon_p);
    int significant = t.wilcoxon_p < study->alpha;
    fprintf(out,
            "- %s: **%s** %s %s (%s) on %.1f %% of %ld common maneuvers; mean difference %.4g %s "
            "(%.0f %% interval [%.4g, %.4g] %s), Wilcoxon p = %s: %s at alpha = %g.\n",
            metric_label((pom_doe_metric)m), study->candidates[a].name,
            m == 0 ? "is faster than" : "uses less energy than", study->candidates[b].name,
            m == 0 ? "lower execution time" : "lower expended energy", 100 * t.win_fraction, t.n,
            t.mean_diff * scale, unit, 100 * study->confidence, t.ci_low * scale, t.ci_high * scale,
            unit, p, significant ? "significant" : "NOT significant", study->alpha);
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
  pom_actuator_kind kind = pom_cli_doe_study_kind(study, &mixed);
  fprintf(out, "  \"montecarlo\": {\"space\": \"%s\", ",
          mv->space == POM_DOE_SPACE_JOINT ? "joint" : "orientation");
  if (mv->space == POM_DOE_SPACE_JOINT) {
    fprintf(out, "\"distribution\": \"%s\", \"actuator_unit\": \"%s\", \"range\": ",
            mv->distribution == POM_DOE_DIST_UNIFORM ? "uniform" : "normal",
            pom_act_units_of(kind)->si);
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

void pom_cli_doe_print_json(FILE *out, const pom_doe_study *study, const pom_doe_report *rep) {
  fprintf(out, "{\n  \"study\": ");
  json_string(out, study->name);
  fprintf(out, ",\n  \"maneuvers\": %ld,\n  \"seed\": %llu,\n", rep->n_maneuvers,
          (unsigned long long)study->maneuvers.seed);
  json_montecarlo(out, study);
  json_metrics(out);
  fprintf(out, "  \"candidates\": [\n");
  for (int c = 0; c < rep->n_candidates; ++c) {
    const pom_doe_candidate_stats *cs = &rep->cand[c];
    fprintf(out, "    {\"name\": ");
    json_string(out, study->candidates[c].name);
    const pom_act_units *u = pom_act_units_of(study->candidates[c].eval.actuator_kind);
    fprintf(out,
            ", \"actuator_kind\": \"%s\", \"actuator_unit\": \"%s\", \"done\": %ld, "
            "\"failed\": %ld, \"unsettled\": %ld",
            u->kind_name, u->si, cs->n_done, cs->n_failed, cs->n_unsettled);
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
    fprintf(out, ", \"win_fraction\": ");
    json_double(out, c->test.win_fraction);
    fprintf(out, "}%s\n", j + 1 < rep->n_comparisons ? "," : "");
  }
  fprintf(out, "  ],\n  \"ranking\": {");
  for (int m = 0; m < 2; ++m) {
    const int *order = m == 0 ? rep->rank_time : rep->rank_energy;
    fprintf(out, "%s\"%s\": [", m ? ", " : "", m == 0 ? "execution_time" : "energy");
    for (int r = 0; r < rep->n_candidates; ++r) {
      if (r) fprintf(out, ", ");
      json_string(out, study->candidates[order[r]].name);
    }
    fprintf(out, "]");
  }
  fprintf(out, "}\n}\n");
}

/* ---- summary.md and figures ------------------------------------------------------------- */
/* results/paper.h5 -> results/paper (the folder of the summary and figures);
 * a file name without extension gets "_summary" appended instead, so that the
 * folder never has the results file's own name. */
static void summary_dir(char *dir, size_t cap, const char *output) {
  snprintf(dir, cap, "%s", output);
  char *dot = strrchr(dir, '.');
  char *slash = strrchr(dir, '/');
  if (dot && (!slash || dot > slash + 1) && dot > dir)
    *dot = '\0';
  else
    snprintf(dir, cap, "%s_summary", output);
}

static int run_plot_script(const char *h5, const char *dir) {
  char dir_scripts[1024], script[1100];
  pom_cli_scripts_dir(dir_scripts, sizeof dir_scripts);
  snprintf(script, sizeof script, "%s/plot_study.py", dir_scripts);
  char *argv[] = {"/usr/bin/python3", script, (char *)h5, (char *)dir, NULL};
  pid_t pid;
  if (posix_spawn(&pid, argv[0], NULL, NULL, argv, environ) != 0) return -1;
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

static int write_summary(const pom_doe_study *study, const pom_doe_report *rep, const char *output,
                         double wall, int threads, int ranks, int plots_ok, const char *dir) {
  char path[1200];
  snprintf(path, sizeof path, "%s/summary.md", dir);
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  char when[64];
  time_t now = time(NULL);
  struct tm tmv;
  gmtime_r(&now, &tmv);
  strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", &tmv);
  fprintf(f, "# Study `%s`\n\n", study->name);
  fprintf(f, "- config: `%s`; results file: `%s`\n", study->source, output);
  fprintf(f, "- pomlab %s (commit %s), %s\n", POM_VERSION, POM_GIT_COMMIT, when);
  int mixed = 0;
  const pom_act_units *u = pom_act_units_of(pom_cli_doe_study_kind(study, &mixed));
  if (study->maneuvers.space == POM_DOE_SPACE_JOINT)
    fprintf(f,
            "- %d candidates x %ld maneuvers, seed %llu, targets %s within +-%.3g %s of "
            "mid-stroke (common to every candidate)\n",
            study->n_candidates, study->maneuvers.count, (unsigned long long)study->maneuvers.seed,
            study->maneuvers.distribution == POM_DOE_DIST_UNIFORM ? "uniform per actuator"
                                                                  : "truncated normal",
            study->maneuvers.range * u->to_display, u->display);
  else
    fprintf(f,
            "- %d candidates x %ld maneuvers, seed %llu, targets from tilt/torsion via IK (tilt "
            "up to %.3g deg, torsion up to +-%.3g deg; the orientations are common to every "
            "candidate%s)\n",
            study->n_candidates, study->maneuvers.count, (unsigned long long)study->maneuvers.seed,
            study->maneuvers.tilt_max / POM_DEG, study->maneuvers.torsion_max / POM_DEG,
            mixed ? ", which mix actuator kinds" : "");
  fprintf(f, "- this run: %.2f s wall, %d worker thread(s) x %d MPI rank(s)\n\n", wall, threads,
          ranks);
  fprintf(f, "| candidate | config | actuators | model (after the study's overrides) |\n"
             "|---|---|---|---|\n");
  for (int c = 0; c < study->n_candidates; ++c) {
    char model[160];
    model_text(&study->candidates[c], model, sizeof model);
    const pom_act_units *cu = pom_act_units_of(study->candidates[c].eval.actuator_kind);
    fprintf(f, "| %s | `%s` | %s (q in %s) | %s |\n", study->candidates[c].name,
            study->candidates[c].source, cu->kind_name, cu->display, model);
  }
  fprintf(f, "\n");
  pom_cli_doe_print_report(f, study, rep);
  write_metric_listing(f);
  if (plots_ok) {
    /* paired.png exists only with two candidates or more (scripts/plot_study.py) */
    char paired[1200];
    snprintf(paired, sizeof paired, "%s/paired.png", dir);
    fprintf(f, "\n### Figures\n\n![execution time](execution_time.png)\n\n"
               "![expended energy](energy.png)\n");
    if (access(paired, R_OK) == 0) fprintf(f, "\n![paired differences](paired.png)\n");
  }
  fclose(f);
  return 0;
}

/* ---- run ------------------------------------------------------------------------------------ */
int pom_cli_doe_execute(const pom_doe_study *study, const pom_cli_doe_opts *o) {
  pom_error err;
  pom_error_clear(&err);
  pom_doe_run *run = NULL;
  pom_doe_report *rep = NULL;
  const char *output = o->run.output ? o->run.output : study->output;
  double t0 = pom_progress_now();
  pom_status st = pom_doe_run_begin(&run, study, &o->run, &err);
  if (st != POM_OK) {
    pom_cli_report("study", &err);
    return pom_cli_exit_code(st);
  }
  int root = pom_doe_run_is_root(run);
  struct sigaction sa, old_int, old_term;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  interrupted = 0;
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);

  pom_progress bar;
  pom_progress_init(&bar, root && !o->quiet ? stderr : NULL, study->name, pom_doe_run_total(run),
                    pom_doe_run_start_done(run), 0);
  int finished = 0, cancelled = 0;
  while (!finished && st == POM_OK) {
    st = pom_doe_run_step(run, &finished, &err);
    if (interrupted && !cancelled) {
      pom_doe_run_cancel(run);
      cancelled = 1;
    }
    pom_progress_update(&bar, pom_doe_run_done(run));
  }
  pom_progress_finish(&bar, pom_doe_run_done(run));
  sigaction(SIGINT, &old_int, NULL);
  sigaction(SIGTERM, &old_term, NULL);
  if (st == POM_OK) st = pom_doe_run_end(run, &rep, &err);
  long done = pom_doe_run_done(run), total = pom_doe_run_total(run);
  int threads = pom_doe_run_threads(run), ranks = pom_doe_run_ranks(run);
  pom_doe_run_destroy(run);
  double wall = pom_progress_now() - t0;
  if (st != POM_OK) {
    pom_cli_report("study", &err);
    pom_doe_report_destroy(rep);
    return pom_cli_exit_code(st);
  }
  if (!root) return 0;
  int code = 0;
  if (done < total) {
    fprintf(stderr,
            "pomlab: study %s: stopped after %ld of %ld candidate-maneuvers; every finished one is "
            "in %s; "
            "continue with --resume\n",
            study->name, done, total, output[0] ? output : "(no file)");
    code = cancelled ? 130 : 0;
  }
  if (o->json) {
    pom_cli_doe_print_json(stdout, study, rep);
  } else {
    printf("## Study %s: %d candidates x %ld maneuvers (%.2f s wall, %d thread(s) x %d rank(s))"
           "\n\n",
           study->name, study->n_candidates, study->maneuvers.count, wall, threads, ranks);
    pom_cli_doe_print_report(stdout, study, rep);
  }
  if (output[0] && (o->summary || o->plots)) {
    char dir[1100];
    summary_dir(dir, sizeof dir, output);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
      fprintf(stderr, "pomlab: cannot create %s: %s\n", dir, strerror(errno));
    } else {
      int plots_ok = 0;
      if (o->plots) {
        int r = run_plot_script(output, dir);
        plots_ok = r == 0;
        if (!plots_ok)
          fprintf(stderr,
                  "pomlab: warning: figures not made (scripts/plot_study.py exited with %d; "
                  "needs /usr/bin/python3 with h5py and matplotlib)\n",
                  r);
      }
      if (o->summary && write_summary(study, rep, output, wall, threads, ranks, plots_ok, dir) != 0)
        fprintf(stderr, "pomlab: cannot write %s/summary.md\n", dir);
      else if (o->summary && !o->json)
        printf("\nSummary: %s/summary.md%s\n", dir, plots_ok ? " (with figures)" : "");
    }
  }
  pom_doe_report_destroy(rep);
  return code;
}
