/* test_metrics_schema.c - the metric schema (dynamics/pom_dyn_metrics_schema.h)
 * and the actuator units through rows/ and study/: every declared metric
 * reaches the row, units resolve per actuator kind, joint-space range keys follow the
 * candidates' actuator kind and mixed kinds are refused in joint space. The
 * outputs themselves (HDF5, JSON, summary.md) are checked by
 * test_metric_outputs.sh. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"
#include "pom_run.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- schema ------------------------------------------------------------------ */
static void test_schema(void) {
  const pom_dyn_metric_info *s = pom_dyn_metric_schema();
  int nstat = 0;
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    check_true(pom_dyn_metric(j) == &s[j]);
    check_true(s[j].count == 1 || s[j].count == 3);
    check_true(s[j].description && s[j].description[0]);
    /* names unique, offsets distinct */
    for (int i = 0; i < j; ++i) {
      check_true(strcmp(s[i].name, s[j].name) != 0);
      check_true(s[i].offset != s[j].offset);
      check_true(pom_doe_row_offset(i) < pom_doe_row_offset(j)); /* list order in the row */
    }
    if (s[j].stat >= 0) {
      check_true(pom_dyn_stat_metric(s[j].stat) == &s[j]);
      check_true(s[j].reduce != POM_DYN_REDUCE_NONE && s[j].stat_name && s[j].stat_key);
      ++nstat;
    }
  }
  check_true(nstat == POM_DYN_N_STATS);
  check_true(pom_dyn_metric(-1) == NULL && pom_dyn_metric(POM_DYN_N_METRICS) == NULL);
  /* the chosen metrics of Tables 1 and 2 */
  check_true(strcmp(pom_dyn_stat_metric(POM_DYN_STAT_execution_time)->name, "execution_time") == 0);
  check_true(strcmp(pom_dyn_stat_metric(POM_DYN_STAT_energy)->name, "energy_total") == 0);
}

/* Every metric goes from pom_dyn_metrics to the row with its value. */
static void test_row_copy(void) {
  pom_dyn_metrics m;
  memset(&m, 0, sizeof m);
  const pom_dyn_metric_info *s = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j)
    for (int k = 0; k < s[j].count; ++k) {
      char *p = (char *)&m + s[j].offset;
      double v = 1.375 * (j + 1) + 0.25 * k;
      if (s[j].type == POM_DYN_TYPE_INT)
        ((int *)(void *)p)[k] = 10 * j + k;
      else if (s[j].type == POM_DYN_TYPE_LONG)
        ((long *)(void *)p)[k] = 1000L * j + k;
      else
        ((double *)(void *)p)[k] = v;
    }
  pom_doe_row row;
  pom_doe_row_from_metrics(&row, &m);
  check_true(row.done == 1);
  for (int j = 0; j < POM_DYN_N_METRICS; ++j)
    for (int k = 0; k < s[j].count; ++k)
      check_abs(pom_doe_row_value(&row, j, k), pom_dyn_metric_value(&m, &s[j], k), 0);
  check_abs(row.max_abs_q[2], m.max_abs_q[2], 0);
}

/* ---- units -------------------------------------------------------------------- */
static void test_units(void) {
  const pom_dyn_metric_info *target = pom_dyn_metric(POM_DYN_METRIC_target);
  const pom_dyn_metric_info *time = pom_dyn_metric(POM_DYN_METRIC_execution_time);
  double f = 0;
  check_true(strcmp(pom_dyn_metric_unit(target, POM_ACT_PRISMATIC), "m") == 0);
  check_true(strcmp(pom_dyn_metric_unit(target, POM_ACT_REVOLUTE), "rad") == 0);
  check_true(strcmp(pom_dyn_metric_display_unit(target, POM_ACT_PRISMATIC, &f), "mm") == 0);
  check_abs(f, 1e3, 0);
  check_true(strcmp(pom_dyn_metric_display_unit(target, POM_ACT_REVOLUTE, &f), "deg") == 0);
  check_rel(0.0523598775598 * f, 3.0, 1e-12); /* 3 deg */
  /* fixed units do not depend on the kind */
  check_true(strcmp(pom_dyn_metric_unit(time, POM_ACT_REVOLUTE), "s") == 0);
  check_true(strcmp(pom_dyn_metric_display_unit(time, POM_ACT_REVOLUTE, &f), "ms") == 0);
  /* one text unit per quantity in every command (docs/conventions.md): J, mm, deg */
  const pom_dyn_metric_info *energy = pom_dyn_metric(POM_DYN_METRIC_energy_total);
  check_true(strcmp(pom_dyn_metric_display_unit(energy, POM_ACT_PRISMATIC, &f), "J") == 0);
  check_abs(f, 1.0, 0);
  const pom_dyn_metric_info *defl = pom_dyn_metric(POM_DYN_METRIC_max_deflection);
  check_true(strcmp(pom_dyn_metric_display_unit(defl, POM_ACT_PRISMATIC, &f), "mm") == 0);
  check_abs(f, 1e3, 0);
  const pom_dyn_metric_info *adefl = pom_dyn_metric(POM_DYN_METRIC_max_angular_deflection);
  check_true(strcmp(pom_dyn_metric_display_unit(adefl, POM_ACT_PRISMATIC, &f), "deg") == 0);
  check_rel(0.0523598775598 * f, 3.0, 1e-12); /* 3 deg */
  char key[64];
  check_true(strcmp(pom_dyn_metric_json_key(time, key, sizeof key), "execution_time_s") == 0);
  check_true(strcmp(pom_dyn_metric_json_key(target, key, sizeof key), "target") == 0);
  check_true(strcmp(pom_dyn_metric_json_key(pom_dyn_metric(POM_DYN_METRIC_steps), key, sizeof key),
                    "steps") == 0);
  /* combining per-actuator values */
  const double v[3] = {2.385, 0.75, 1.125};
  check_abs(pom_dyn_combine_values(POM_DYN_COMBINE_SUM, v, 3), 2.385 + 0.75 + 1.125, 0);
  check_abs(pom_dyn_combine_values(POM_DYN_COMBINE_MAX, v, 3), 2.385, 0);
  const double w[3] = {2.385, NAN, 1.125};
  check_true(isnan(pom_dyn_combine_values(POM_DYN_COMBINE_MAX, w, 3)));
}

/* A revolute actuator's stroke check speaks degrees. */
static void test_revolute_stroke(void) {
  pom_dyn_metrics m;
  pom_error err;
  memset(&m, 0, sizeof m);
  pom_error_clear(&err);
  double stroke = 40.0 * POM_DEG;
  m.final_q[1] = 21.5 * POM_DEG;
  m.max_abs_q[1] = 21.5 * POM_DEG;
  check_true(pom_doe_check_final_stroke_kind(&m, stroke, POM_ACT_REVOLUTE, &err) == POM_ERR_LIMIT);
  check_true(strstr(m.reason, "21.5 deg") != NULL && strstr(m.reason, "+-20 deg") != NULL);
  memset(&m, 0, sizeof m);
  m.final_q[0] = 19.0 * POM_DEG;
  m.max_abs_q[0] = 19.5 * POM_DEG;
  check_true(pom_doe_check_final_stroke_kind(&m, stroke, POM_ACT_REVOLUTE, &err) == POM_OK);
}

/* The kind of a hand-built mechanism: shared by every actuator, else an error. */
static void test_mech_kind(void) {
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_error err;
  pom_error_clear(&err);
  pom_actuator_kind k = POM_ACT_PRISMATIC;
  check_true(pom_doe_mech_actuator_kind(mech, &k, &err) == POM_ERR_ARG); /* no actuator */
  mech->n_actuators = 3;
  for (int a = 0; a < 3; ++a)
    mech->actuator[a].kind = POM_ACT_REVOLUTE;
  check_true(pom_doe_mech_actuator_kind(mech, &k, &err) == POM_OK && k == POM_ACT_REVOLUTE);
  mech->actuator[2].kind = POM_ACT_PRISMATIC;
  check_true(pom_doe_mech_actuator_kind(mech, &k, &err) == POM_ERR_ARG);
  check_true(strstr(err.message, "actuator 3 is prismatic") != NULL);
  free(mech);
}

/* ---- range keys and mixed kinds ---------------------------------------------------- */
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

static pom_status toy_run(const void *ctx, void *w, const double q[3], pom_dyn_metrics *m,
                          pom_error *err) {
  (void)ctx;
  (void)w;
  (void)err;
  for (int i = 0; i < 3; ++i) {
    m->target[i] = m->final_q[i] = q[i];
    m->settled[i] = 1;
    m->settling_time[i] = 0.01;
  }
  m->execution_time = 0.01;
  return POM_OK;
}

static pom_status toy_targets(const void *ctx, const pom_doe_maneuver *mv, double q[3],
                              pom_error *err) {
  (void)ctx;
  (void)err;
  for (int i = 0; i < 3; ++i)
    q[i] = mv->orient[i];
  return POM_OK;
}

/* A candidate whose config says its actuator kind: `toy = { kind = "revolute"; }`. */
static pom_status toy_factory(pom_doe_evaluator *eval, const pom_cfg *cfg, void *user,
                              pom_error *err) {
  static const char *const kinds[] = {"prismatic", "revolute", NULL};
  static const char *const scopes[] = {"toy", NULL};
  (void)user;
  memset(eval, 0, sizeof *eval);
  int kind = 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "toy.kind", kinds, 0, &kind, err));
  POM_TRY(pom_cfg_check_unknown(cfg, scopes, NULL, err));
  eval->actuator_kind = (pom_actuator_kind)kind;
  eval->run = toy_run;
  eval->targets = toy_targets;
  return POM_OK;
}

static pom_status load(pom_doe_study *study, const char *name, pom_error *err) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  pom_cfg *cfg = NULL;
  pom_status st = pom_cfg_load(&cfg, path, err);
  memset(study, 0, sizeof *study);
  if (st == POM_OK) st = pom_doe_study_load(study, cfg, toy_factory, NULL, err);
  pom_cfg_destroy(cfg);
  return st;
}

static void test_range_keys(void) {
  write_file("lin.cfg", "toy = { kind = \"prismatic\"; };\n");
  write_file("rot.cfg", "toy = { kind = \"revolute\"; };\n");
  struct {
    const char *file, *text, *want; /* want NULL: loads */
    double range, sigma;            /* SI, when it loads */
  } cases[] = {
      {"deg.cfg",
       "montecarlo = { maneuvers = 5; range_deg = 2.5; sigma_deg = 1.25; };\n"
       "candidates = ( { name = \"r\"; config = \"rot.cfg\"; } );\n",
       NULL, 2.5 * POM_DEG, 1.25 * POM_DEG},
      /* sigma alone: the range defaults to 3 of the display unit */
      {"sigma_deg.cfg",
       "montecarlo = { maneuvers = 5; distribution = \"normal\"; sigma_deg = 0.75; };\n"
       "candidates = ( { name = \"r\"; config = \"rot.cfg\"; } );\n",
       NULL, 3.0 * POM_DEG, 0.75 * POM_DEG},
      {"mm.cfg",
       "montecarlo = { maneuvers = 5; range_mm = 2.5; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       NULL, 2.5e-3, 1.5e-3},
      {"mm_on_rot.cfg",
       "montecarlo = { maneuvers = 5; range_mm = 2.5; };\n"
       "candidates = ( { name = \"r\"; config = \"rot.cfg\"; } );\n",
       "mm_on_rot.cfg:1: key 'montecarlo.range_mm'", 0, 0},
      {"sigma_mm_on_rot.cfg",
       "montecarlo = { maneuvers = 5; distribution = \"normal\"; sigma_mm = 1.0; };\n"
       "candidates = ( { name = \"r\"; config = \"rot.cfg\"; } );\n",
       "montecarlo.sigma_deg", 0, 0},
      {"deg_on_lin.cfg",
       "montecarlo = { maneuvers = 5; range_deg = 2.5; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       "montecarlo.range_mm", 0, 0},
      {"default_on_rot.cfg", "candidates = ( { name = \"r\"; config = \"rot.cfg\"; } );\n",
       "montecarlo.range_deg", 0, 0},
      {"both.cfg",
       "montecarlo = { maneuvers = 5; range_mm = 2.5; sigma_deg = 1.0; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       "mixes units", 0, 0},
      {"mixed_joint.cfg",
       "montecarlo = { maneuvers = 5; range_mm = 2.5; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; },\n"
       "               { name = \"r\"; config = \"rot.cfg\"; } );\n",
       "montecarlo.space = \"orientation\"", 0, 0},
      {"mixed_counts.cfg",
       "montecarlo = { maneuvers = 5; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; },\n"
       "               { name = \"q\"; config = \"lin.cfg\"; },\n"
       "               { name = \"r\"; config = \"rot.cfg\"; } );\n",
       "(2 prismatic in m, 1 revolute in rad)", 0, 0},
      {"mixed_orient.cfg",
       "montecarlo = { maneuvers = 5; space = \"orientation\"; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; },\n"
       "               { name = \"r\"; config = \"rot.cfg\"; } );\n",
       NULL, 3e-3, 1.5e-3},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    pom_doe_study study;
    pom_error err;
    pom_error_clear(&err);
    write_file(cases[i].file, cases[i].text);
    pom_status st = load(&study, cases[i].file, &err);
    if (!cases[i].want) {
      if (!check_true(st == POM_OK)) printf("  %s: %s\n", cases[i].file, err.message);
      check_rel(study.maneuvers.range, cases[i].range, 1e-15);
      check_rel(study.maneuvers.sigma, cases[i].sigma, 1e-15);
    } else {
      check_true(st == POM_ERR_CONFIG);
      if (!check_true(strstr(err.message, cases[i].want) != NULL))
        printf("  %s: '%s' lacks '%s'\n", cases[i].file, err.message, cases[i].want);
    }
    pom_doe_study_clear(&study);
  }
  /* study.time_metric (docs/results.md section 4): auto is the pointing time
   * in orientation space, the per-actuator time in joint space */
  static const struct {
    const char *file, *text;
    int want; /* pom_doe_time_metric, -1: a config error */
  } times[] = {
      {"tm_joint.cfg",
       "montecarlo = { maneuvers = 5; range_mm = 2.5; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       POM_DOE_TIME_EXECUTION},
      {"tm_orient.cfg",
       "montecarlo = { maneuvers = 5; space = \"orientation\"; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       POM_DOE_TIME_POINTING},
      {"tm_orient_exec.cfg",
       "montecarlo = { maneuvers = 5; space = \"orientation\"; };\n"
       "study = { time_metric = \"execution_time\"; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       POM_DOE_TIME_EXECUTION},
      {"tm_joint_point.cfg",
       "montecarlo = { maneuvers = 5; range_mm = 2.5; };\n"
       "study = { time_metric = \"pointing_settling_time\"; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       POM_DOE_TIME_POINTING},
      {"tm_bad.cfg",
       "montecarlo = { maneuvers = 5; range_mm = 2.5; };\n"
       "study = { time_metric = \"pointing\"; };\n"
       "candidates = ( { name = \"p\"; config = \"lin.cfg\"; } );\n",
       -1},
  };
  for (size_t i = 0; i < sizeof times / sizeof times[0]; ++i) {
    pom_doe_study study;
    pom_error err;
    pom_error_clear(&err);
    write_file(times[i].file, times[i].text);
    pom_status st = load(&study, times[i].file, &err);
    if (times[i].want < 0) {
      check_true(st == POM_ERR_CONFIG && strstr(err.message, "study.time_metric") != NULL);
    } else {
      if (!check_true(st == POM_OK)) printf("  %s: %s\n", times[i].file, err.message);
      check_true((int)study.time_metric == times[i].want);
    }
    pom_doe_study_clear(&study);
  }
  /* pom_doe_kinds_mixed */
  const pom_actuator_kind same[2] = {POM_ACT_REVOLUTE, POM_ACT_REVOLUTE};
  const pom_actuator_kind mix[2] = {POM_ACT_PRISMATIC, POM_ACT_REVOLUTE};
  check_true(!pom_doe_kinds_mixed(same, 2) && pom_doe_kinds_mixed(mix, 2));
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/pom_test_metrics_XXXXXX");
  if (!mkdtemp(tmpdir)) {
    printf("cannot make a temporary folder\n");
    return 1;
  }
  test_schema();
  test_row_copy();
  test_units();
  test_revolute_stroke();
  test_mech_kind();
  test_range_keys();
  return check_summary("test_metrics_schema");
}
