/* tune_map.c - the gain-tuning criterion of one study candidate over the
 * tuner's box, and the tuner's own path through it (docs/catalog.md 10.1).
 *
 * The candidate's tuning problem is the study's: its config resolved with the
 * study's overrides (pom_doe_study_load), loaded by pom_tune_load as the
 * pipeline does. Two searched gains only (a map is two-dimensional).
 *
 * Usage:
 *   tune_map STUDY.cfg CANDIDATE grid N OUT.csv [Z0LO Z0HI Z1LO Z1HI]
 *     the criterion at N x N gains, evenly spaced over the box in the
 *     tuner's own variables (log10 of a log-searched gain), both edges
 *     included, or over the given part of it; CANDIDATE is the candidate's
 *     name or its 1-based index
 *   tune_map STUDY.cfg CANDIDATE path OUT.csv [LOCAL_STARTS]
 *     every criterion evaluation of the tuner's search (the candidate's
 *     optimizer, LOCAL_STARTS overriding tuning.optimizer.local_starts), in
 *     order, with its stage (g = global, l = local), then the result
 *   tune_map STUDY.cfg CANDIDATE prepare
 *     the study's own pipeline for the candidate (sizing, tuning with its
 *     optimizer; no files): the tuned gains and criterion, one line
 * Columns: stage, z0, z1 (search variables), the two gains (SI), criterion,
 * mean execution time (ms), largest overshoot (%), largest saturation time
 * (ms), unsettled maneuvers. */
#include "pom_arch_file.h"
#include "pom_dyn_ctrl.h"
#include "pom_pipeline.h"
#include "pom_study.h"
#include "pom_tune.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_PATH 4096

typedef struct {
  const pom_tune_problem *pb;
  long evals;
  double z[MAX_PATH][2];
  pom_tune_eval e[MAX_PATH];
} path_ctx;

static double now_s(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The controller at search point z: pom_tune.c's search_to_controller. */
static void to_controller(const pom_tune_problem *pb, const double z[], pom_dyn_controller *c) {
  *c = pb->params.controller;
  for (int i = 0; i < pb->n_vars; ++i)
    *pom_dyn_ctrl_gain_ptr(c, (int)pb->var[i]) = pb->log_scale[i] ? pow(10.0, z[i]) : z[i];
}

static int write_row(FILE *out, const char *stage, const pom_tune_problem *pb, const double z[],
                     const pom_tune_eval *e) {
  pom_dyn_controller c;
  to_controller(pb, z, &c);
  return fprintf(out, "%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%d\n", stage, z[0], z[1],
                 pom_dyn_ctrl_gain(&c, (int)pb->var[0]), pom_dyn_ctrl_gain(&c, (int)pb->var[1]),
                 e->criterion * 1e3, e->mean_execution * 1e3, e->max_overshoot * 100.0,
                 e->max_saturation * 1e3, e->unsettled) > 0;
}

static pom_status path_objective(void *vctx, const double z[], double *f, pom_error *err) {
  path_ctx *c = vctx;
  pom_dyn_controller ctl;
  pom_tune_eval e;
  to_controller(c->pb, z, &ctl);
  POM_TRY(pom_tune_evaluate(c->pb, &ctl, &e, err));
  if (c->evals == MAX_PATH)
    POM_FAIL(err, POM_ERR_ARG, "tune_map: more than %d evaluations", MAX_PATH);
  c->z[c->evals][0] = z[0];
  c->z[c->evals][1] = z[1];
  c->e[c->evals++] = e;
  *f = -e.criterion;
  return POM_OK;
}

static int fail(const pom_error *err) {
  fprintf(stderr, "tune_map: %s\n", err->message);
  return 1;
}

int main(int argc, char **argv) {
  int prepare = argc == 4 && strcmp(argv[3], "prepare") == 0;
  if (!prepare && (argc < 5 || (strcmp(argv[3], "grid") != 0 && strcmp(argv[3], "path") != 0))) {
    fprintf(stderr, "usage: tune_map STUDY.cfg CANDIDATE grid N OUT.csv [Z0LO Z0HI Z1LO Z1HI]\n"
                    "       tune_map STUDY.cfg CANDIDATE path OUT.csv [LOCAL_STARTS]\n"
                    "       tune_map STUDY.cfg CANDIDATE prepare\n");
    return 2;
  }
  int grid = strcmp(argv[3], "grid") == 0;
  if (grid && argc != 6 && argc != 10) {
    fprintf(stderr, "tune_map: grid takes N, OUT.csv and optionally a part of the box\n");
    return 2;
  }
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *scfg = NULL, *ccfg = NULL;
  static pom_doe_study study;
  static pom_tune_problem pb;
  /* the catalog's architecture files, as pomlab registers them */
  if (pom_arch_files_register_all(&err) != POM_OK || pom_cfg_load(&scfg, argv[1], &err) != POM_OK ||
      pom_doe_study_load(&study, scfg, pom_pipeline_evaluator_create, NULL, &err) != POM_OK)
    return fail(&err);
  int c = -1;
  for (int k = 0; k < study.n_candidates; ++k)
    if (strcmp(study.candidates[k].name, argv[2]) == 0) c = k;
  if (c < 0) c = atoi(argv[2]) - 1;
  if (c < 0 || c >= study.n_candidates) {
    fprintf(stderr, "tune_map: no candidate '%s' in %s\n", argv[2], argv[1]);
    return 2;
  }
  if (prepare) {
    pom_pipeline_options po;
    memset(&po, 0, sizeof po);
    po.no_files = 1;
    double t0 = now_s();
    if (pom_pipeline_prepare(&study.candidates[c].eval, "tune_map", &po, &err) != POM_OK)
      return fail(&err);
    const pom_pipeline_record *r = pom_pipeline_record_of(&study.candidates[c].eval);
    if (!r || !r->tuned) {
      fprintf(stderr, "tune_map: candidate '%s' is not tuned in the study\n",
              study.candidates[c].name);
      return 2;
    }
    printf("%s | kp %.6g | kd_s %.6g | criterion %.6g ms (config gains %.6g) | mean execution "
           "%.6g ms | %ld evaluations | tuning %.1f s, sizing %.1f s, %.1f s in all\n",
           study.candidates[c].name, r->tuned_gains.kp, r->tuned_gains.kd,
           r->tuned_eval.criterion * 1e3, r->config_eval.criterion * 1e3,
           r->tuned_eval.mean_execution * 1e3, r->tuning_evaluations, r->tuning_time,
           r->sizing_time, now_s() - t0);
    pom_doe_study_clear(&study);
    pom_cfg_destroy(scfg);
    return 0;
  }
  if (pom_cfg_load_string(&ccfg, study.candidates[c].resolved, study.candidates[c].name, &err) !=
          POM_OK ||
      pom_tune_load(&pb, ccfg, &err) != POM_OK)
    return fail(&err);
  if (pb.n_vars != 2) {
    fprintf(stderr, "tune_map: %d searched gains, a map needs 2\n", pb.n_vars);
    return 2;
  }
  double lo[2], hi[2];
  for (int i = 0; i < 2; ++i) {
    lo[i] = pb.log_scale[i] ? log10(pb.lo[i]) : pb.lo[i];
    hi[i] = pb.log_scale[i] ? log10(pb.hi[i]) : pb.hi[i];
  }
  const char *path = argv[grid ? 5 : 4];
  FILE *out = fopen(path, "w");
  if (!out) {
    fprintf(stderr, "tune_map: cannot open %s\n", path);
    return 1;
  }
  int ok = fprintf(out,
                   "stage,z0,z1,%s,%s,criterion_ms,mean_execution_ms,max_overshoot_percent,"
                   "max_saturation_ms,unsettled\n",
                   pom_tune_var_name(pb.var[0]), pom_tune_var_name(pb.var[1])) > 0;
  double t0 = now_s();
  if (grid) {
    int n = atoi(argv[4]);
    if (argc == 10) {
      double g0 = atof(argv[6]), g1 = atof(argv[7]), h0 = atof(argv[8]), h1 = atof(argv[9]);
      if (!(g0 >= lo[0] && g0 < g1 && g1 <= hi[0] && h0 >= lo[1] && h0 < h1 && h1 <= hi[1])) {
        fprintf(stderr, "tune_map: the part [%g, %g] x [%g, %g] is not inside the box\n", g0, g1,
                h0, h1);
        return 2;
      }
      lo[0] = g0, hi[0] = g1, lo[1] = h0, hi[1] = h1;
    }
    if (n < 2 || n > 201) {
      fprintf(stderr, "tune_map: N = %s, expected 2..201\n", argv[4]);
      return 2;
    }
    for (int a = 0; a < n && ok; ++a)
      for (int b = 0; b < n && ok; ++b) {
        double z[2] = {lo[0] + (hi[0] - lo[0]) * a / (n - 1),
                       lo[1] + (hi[1] - lo[1]) * b / (n - 1)};
        pom_dyn_controller ctl;
        pom_tune_eval e;
        to_controller(&pb, z, &ctl);
        if (pom_tune_evaluate(&pb, &ctl, &e, &err) != POM_OK) return fail(&err);
        ok = write_row(out, "m", &pb, z, &e);
      }
    fprintf(stderr, "tune_map: %d x %d criterion evaluations, %.1f s\n", n, n, now_s() - t0);
  } else {
    if (argc > 5) pb.opt.local_starts = atoi(argv[5]);
    static path_ctx pc;
    pc.pb = &pb;
    double z0[2];
    for (int i = 0; i < 2; ++i) {
      double g = pom_dyn_ctrl_gain(&pb.params.controller, (int)pb.var[i]);
      z0[i] = pb.log_scale[i] ? (g > 0.0 ? log10(g) : lo[i]) : g;
    }
    pom_opt_result r;
    if (pom_opt_maximize(2, lo, hi, z0, path_objective, &pc, &pb.opt, &r, &err) != POM_OK)
      return fail(&err);
    for (long k = 0; k < pc.evals && ok; ++k)
      ok = write_row(out, k < r.evals_global ? "g" : "l", &pb, pc.z[k], &pc.e[k]);
    pom_tune_eval e;
    pom_dyn_controller ctl;
    to_controller(&pb, r.x, &ctl);
    if (pom_tune_evaluate(&pb, &ctl, &e, &err) != POM_OK) return fail(&err);
    ok = ok && write_row(out, "best", &pb, r.x, &e);
    fprintf(stderr,
            "tune_map: %ld global + %ld local evaluations (%d local runs, best from run %d), "
            "criterion %.6g ms at %s %.6g, %s %.6g, %.1f s\n",
            r.evals_global, r.evals_local, r.local_runs, r.local_best_run, e.criterion * 1e3,
            pom_tune_var_name(pb.var[0]), pom_dyn_ctrl_gain(&ctl, (int)pb.var[0]),
            pom_tune_var_name(pb.var[1]), pom_dyn_ctrl_gain(&ctl, (int)pb.var[1]), now_s() - t0);
  }
  if (fclose(out) != 0 || !ok) {
    fprintf(stderr, "tune_map: cannot write %s\n", path);
    return 1;
  }
  pom_cfg_destroy(ccfg);
  pom_doe_study_clear(&study);
  pom_cfg_destroy(scfg);
  return 0;
}
