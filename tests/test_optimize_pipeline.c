/* test_optimize_pipeline.c - the study pipeline evaluator: without the
 * switches it runs exactly the dynamics evaluator's mechanism; with
 * synthesis.run_in_study it runs the scaled optimum of the synthesis. */
#include "check.h"
#include "pom_math.h"
#include "pom_pipeline.h"
#include "pom_synth.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* configs/synth_3pss.cfg with its include made relative to the source tree
 * (the tests run there), optionally switched into the study pipeline. */
static pom_cfg *synth_config(int in_study) {
  FILE *f = fopen(POM_SOURCE_DIR "/configs/synth_3pss.cfg", "r");
  if (!f) return NULL;
  static char text[16384];
  size_t n = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[n] = '\0';
  static char out[17000];
  const char *inc = strstr(text, "@include \"3pss.cfg\"");
  const char *syn = strstr(text, "synthesis = {");
  const char *dir = strstr(text, "enabled = true");
  if (!inc || !syn || !dir) return NULL;
  /* include path, the switch, and no direct optimization (time) */
  snprintf(out, sizeof out,
           "%.*s@include \"%s/configs/3pss.cfg\"%.*ssynthesis = {%s%.*senabled = false%s",
           (int)(inc - text), text, POM_SOURCE_DIR, (int)(syn - inc - 19), inc + 19,
           in_study ? " run_in_study = true;" : "", (int)(dir - syn - 13), syn + 13, dir + 14);
  pom_cfg *cfg = NULL;
  pom_error err;
  if (pom_cfg_load_string(&cfg, out, "<pipeline test>", &err) != POM_OK) {
    printf("config: %s\n", err.message);
    return NULL;
  }
  return cfg;
}

static double run_one(const pom_doe_evaluator *ev, const double q[3], pom_dyn_metrics *mt) {
  void *w = NULL;
  pom_error err;
  check_true(ev->worker_create(&w, ev->ctx, &err) == POM_OK);
  check_true(ev->run(ev->ctx, w, q, mt, &err) == POM_OK);
  ev->worker_destroy(w);
  return mt->execution_time;
}

int main(void) {
  pom_error err;
  pom_error_clear(&err);
  const double q[3] = {2.385e-3, -1.17e-3, 0.643e-3};
  pom_dyn_metrics a, b;

  /* 1. No switch: the same maneuver as the plain dynamics evaluator, to the bit. */
  pom_cfg *cfg = synth_config(0);
  check_true(cfg != NULL);
  if (!cfg) return check_summary("test_optimize_pipeline");
  pom_cfg *plain = NULL;
  check_true(pom_cfg_load(&plain, POM_SOURCE_DIR "/configs/3pss.cfg", &err) == POM_OK);
  pom_doe_evaluator e1, e2;
  check_true(pom_pipeline_evaluator_create(&e1, cfg, NULL, &err) == POM_OK);
  check_true(pom_doe_dyn_evaluator_create(&e2, plain, NULL, &err) == POM_OK);
  double t1 = run_one(&e1, q, &a), t2 = run_one(&e2, q, &b);
  check_true(t1 == t2 && a.energy_total == b.energy_total && a.steps == b.steps);
  pom_doe_evaluator_clear(&e1);
  pom_doe_evaluator_clear(&e2);
  pom_cfg_destroy(cfg);
  pom_cfg_destroy(plain);

  /* 2. With the switch: the evaluator runs the scaled synthesis optimum. */
  cfg = synth_config(1);
  check_true(cfg != NULL);
  if (!cfg) return check_summary("test_optimize_pipeline");
  char prefix[128];
  unsigned long tag = (unsigned long)time(NULL) ^ (unsigned long)(uintptr_t)&tag;
  snprintf(prefix, sizeof prefix, "/tmp/pomlab_test_pipe_%lx_", tag);
  pom_pipeline_options po;
  memset(&po, 0, sizeof po);
  po.output_prefix = prefix;
  pom_status st = pom_pipeline_evaluator_create(&e1, cfg, NULL, &err);
  check_true(st == POM_OK);
  if (st != POM_OK) printf("pipeline: %s\n", err.message);
  if (st == POM_OK) {
    /* loading runs nothing: a worker before the synthesis is refused */
    void *w = NULL;
    check_true(e1.worker_create(&w, e1.ctx, &err) == POM_ERR_ARG);
    check_true(strstr(err.message, "has not run") != NULL);
    const pom_pipeline_record *rec = pom_pipeline_record_of(&e1);
    check_true(rec && !rec->synthesized && !rec->tuned);
    /* the file stem is the candidate's, whole (longer than the old 24-character cut) */
    st = pom_pipeline_prepare(&e1, "3P_S_S_S_with_a_long_candidate_name", &po, &err);
    check_true(st == POM_OK);
    if (st != POM_OK) printf("pipeline: %s\n", err.message);
    check_true(rec->synthesized && !rec->tuned);
    check_true(strcmp(rec->stem, "3P_S_S_S_with_a_long_candidate_name") == 0);
  }
  /* the same synthesis by hand */
  static pom_syn_problem pb;
  pom_syn_run *run = NULL;
  check_true(pom_syn_load(&pb, cfg, &err) == POM_OK);
  check_true(pom_syn_begin(&run, &pb, &err) == POM_OK);
  check_true(pom_syn_finish(run, &err) == POM_OK);
  if (st == POM_OK) {
    /* a geometry different from the config's: its IK differs at a common pose */
    pom_doe_maneuver mv;
    memset(&mv, 0, sizeof mv);
    const double e[3] = {0.05, -0.03, 0.02};
    pom_euler_zyx_to_matrix(mv.R, e);
    double qp[3], qs[3];
    check_true(e1.targets(e1.ctx, &mv, qp, &err) == POM_OK);
    check_true(pom_kin_inverse(&run->scaled, mv.R, qs, &err) == POM_OK);
    for (int i = 0; i < 3; ++i)
      check_abs(qp[i], qs[i], 1e-15);
    run_one(&e1, q, &a);
    check_true(a.status == POM_OK);
    pom_doe_evaluator_clear(&e1);
  }
  char path[256];
  snprintf(path, sizeof path, "%s%s.geometry.cfg", prefix, "3P_S_S_S_with_a_long_candidate_name");
  FILE *f = fopen(path, "r");
  check_true(f != NULL);
  if (f) fclose(f);
  remove(path);
  snprintf(path, sizeof path, "%s%s.h5", prefix, "3P_S_S_S_with_a_long_candidate_name");
  f = fopen(path, "r");
  check_true(f != NULL);
  if (f) fclose(f);
  remove(path);

  /* file stems: punctuation runs become one '_', nothing is cut */
  char stem[80];
  pom_pipeline_stem(stem, sizeof stem, "3S-P-S/S");
  check_true(strcmp(stem, "3S_P_S_S") == 0);
  pom_pipeline_stem(stem, sizeof stem, " 3PSS reference (isotropic at home, sigma = 15 mm)");
  check_true(strcmp(stem, "3PSS_reference_isotropic_at_home_sigma_15_mm") == 0);
  pom_syn_destroy(run);
  pom_cfg_destroy(cfg);
  return check_summary("test_optimize_pipeline");
}
