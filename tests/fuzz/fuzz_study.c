/* fuzz_study.c - libFuzzer target: bytes -> a study file beside copies of
 * the shipped configs -> everything `pomlab study` (and `pomlab
 * sensitivity`) does before its first maneuver: the study, montecarlo,
 * candidates, sweep, uncertain and override keys, every candidate resolved
 * and its evaluator built, the run prepared (work split, worker states; no
 * results file), the maneuver table drawn, the orientation targets mapped by
 * inverse kinematics and the first maneuver's uncertain draws made into an
 * evaluator. Nothing is simulated or written (docs/fuzzing.md). */
#include "fuzz_common.h"
#include "pom_config.h"
#include "pom_run.h"
#include "pom_explore.h"
#include "pom_pipeline.h"
#include "pom_study.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A study larger than this is loaded and checked but not prepared: the run
 * holds one cell per candidate x maneuver, so `montecarlo.maneuvers` alone
 * would let one input ask for gigabytes (issue 22 items 15-16 are about
 * saying so up front; the fuzzer is not the place to measure it). */
#define FUZZ_MAX_MANEUVERS 20000L
#define FUZZ_MAX_UNITS     200000L
/* Orientation-space maneuvers mapped to actuator targets per candidate. */
#define FUZZ_IK_MANEUVERS 16L
/* Candidate evaluators a study's load may build: a 4096-candidate sweep is
 * valid and takes seconds under the sanitizers (more with uncertain
 * parameters, each checked at both ends of its distribution), which would
 * read as a hang and slow the search; the code is the same at 256. */
#define FUZZ_MAX_BUILDS 256L
/* The loader's own limit on candidates (study/pom_doe_study.c): above it the
 * study is refused before any candidate is built, so such inputs run. */
#define FUZZ_LOADER_MAX_CANDIDATES 4096L

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *input_path;

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  input_path = pom_fuzz_setup();
  if (!input_path) abort();
  return 0;
}

/* The maneuver table and, in orientation space, each candidate's actuator
 * targets: a target found must be finite (numerical outcomes are data). */
static void check_maneuvers(const pom_doe_study *study) {
  const pom_doe_maneuvers *mv = &study->maneuvers;
  for (long k = 0; k < mv->count; ++k) {
    pom_doe_maneuver m;
    pom_doe_maneuver_draw(&m, mv, k);
    const double *v = mv->space == POM_DOE_SPACE_JOINT ? m.q : m.orient;
    for (int i = 0; i < 3; ++i)
      if (!isfinite(v[i])) {
        fprintf(stderr, "fuzz: maneuver %ld drew a non-finite value\n", k);
        abort();
      }
  }
  if (mv->space != POM_DOE_SPACE_ORIENTATION) return;
  for (int c = 0; c < study->n_candidates; ++c) {
    const pom_doe_evaluator *ev = &study->candidates[c].eval;
    for (long k = 0; k < mv->count && k < FUZZ_IK_MANEUVERS; ++k) {
      pom_doe_maneuver m;
      pom_error e;
      double q[3];
      pom_error_clear(&e);
      pom_doe_maneuver_draw(&m, mv, k);
      pom_status st = ev->targets(ev->ctx, &m, q, &e);
      pom_fuzz_check_failure(st, &e, "evaluator targets");
      if (st == POM_OK && !(isfinite(q[0]) && isfinite(q[1]) && isfinite(q[2]))) {
        fprintf(stderr, "fuzz: candidate %d maneuver %ld: targets ok but not finite\n", c, k);
        abort();
      }
    }
  }
}

/* What a worker does with maneuver 0's uncertain draws before simulating it
 * (run/pom_doe_run.c, run_unit): a drawn value that breaks a candidate is a
 * recorded failure, never a crash. */
static void check_draws(const pom_doe_study *study) {
  const pom_unc *unc = &study->uncertain;
  if (unc->n <= 0) return;
  double u[POM_UNC_MAX], x[POM_UNC_MAX];
  long man = 0;
  pom_unc_unit(unc, 0, &man, u);
  for (int j = 0; j < unc->n; ++j) {
    x[j] = pom_dist_quantile(&unc->param[j].dist, u[j]);
    if (!isfinite(x[j])) {
      fprintf(stderr, "fuzz: uncertain.[%d] drew a non-finite value at u = %.17g\n", j, u[j]);
      abort();
    }
  }
  for (int c = 0; c < study->n_candidates; ++c) {
    pom_doe_evaluator drawn;
    pom_error e;
    void *state = NULL;
    pom_error_clear(&e);
    pom_status st = pom_doe_uncertain_evaluator(&drawn, study, c, x, &e);
    pom_fuzz_check_failure(st, &e, "pom_doe_uncertain_evaluator");
    if (st == POM_OK) {
      st = drawn.worker_create(&state, drawn.ctx, &e);
      pom_fuzz_check_failure(st, &e, "drawn worker_create");
      if (state) drawn.worker_destroy(state);
    }
    pom_doe_evaluator_clear(&drawn);
  }
}

/* Evaluators the study's load would build: candidates x (1 + 2 per
 * uncertain parameter); 0 when the numbers that set it are invalid or above
 * the loader's limit, which the loader refuses before building any. */
static long planned_builds(const pom_cfg *cfg) {
  pom_error e;
  long n = 0;
  if (pom_cfg_has(cfg, "candidates.sweep")) {
    long bases = pom_cfg_length(cfg, "candidates.base");
    if (pom_cfg_has(cfg, "candidates.points")) {
      if (pom_cfg_int(cfg, "candidates.points", 2, FUZZ_LOADER_MAX_CANDIDATES, &n, &e) != POM_OK)
        return 0;
    } else {
      n = 1;
      int nf = pom_cfg_length(cfg, "candidates.factors");
      for (int f = 0; f < nf && f < POM_DOE_MAX_FACTORS; ++f) {
        char k[64];
        long levels = 0;
        snprintf(k, sizeof k, "candidates.factors.[%d].levels", f);
        if (pom_cfg_int(cfg, k, 2, 64, &levels, &e) != POM_OK) return 0;
        n *= levels;
        if (n * bases > FUZZ_LOADER_MAX_CANDIDATES) return 0;
      }
    }
    n *= bases;
  } else {
    n = pom_cfg_length(cfg, "candidates");
  }
  if (n > FUZZ_LOADER_MAX_CANDIDATES) return 0;
  return n * (1 + 2L * pom_cfg_length(cfg, "uncertain"));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (pom_fuzz_refused(data, size)) return -1; /* not added to the corpus */
  if (pom_fuzz_write(input_path, data, size) != 0) abort();
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  pom_status st = pom_cfg_load(&cfg, input_path, &err);
  pom_fuzz_check_failure(st, &err, "pom_cfg_load");
  if (st != POM_OK) return 0;
  if (planned_builds(cfg) > FUZZ_MAX_BUILDS) {
    pom_cfg_destroy(cfg);
    return -1; /* not added to the corpus */
  }
  /* as cli/cmd_study.c: candidates through the pipeline's factory */
  st = pom_doe_study_load(&study, cfg, pom_pipeline_evaluator_create, NULL, &err);
  pom_fuzz_check_failure(st, &err, "pom_doe_study_load");
  if (st == POM_OK && pom_cfg_has(cfg, "sensitivity")) {
    pom_doe_sens sens;
    st = pom_doe_sens_load(&sens, cfg, &study, &err);
    pom_fuzz_check_failure(st, &err, "pom_doe_sens_load");
  }
  pom_cfg_destroy(cfg);
  long m = study.maneuvers.count;
  if (st == POM_OK && m <= FUZZ_MAX_MANEUVERS && (long)study.n_candidates * m <= FUZZ_MAX_UNITS) {
    /* the run as `pomlab study` begins it, without a file and before the
     * workers start (candidates that ask for synthesis or tuning are
     * refused here: the pipeline would simulate) */
    pom_doe_run_options opt;
    pom_doe_run_options_defaults(&opt);
    opt.output = "";
    opt.threads = 1;
    pom_doe_run *run = NULL;
    st = pom_doe_run_prepare(&run, &study, &opt, &err);
    pom_fuzz_check_failure(st, &err, "pom_doe_run_prepare");
    if (st == POM_OK && pom_doe_run_total(run) != (long)study.n_candidates * m) {
      fprintf(stderr, "fuzz: the run counts %ld units for %d x %ld\n", pom_doe_run_total(run),
              study.n_candidates, m);
      abort();
    }
    pom_doe_run_destroy(run);
    if (st == POM_OK) {
      check_maneuvers(&study);
      check_draws(&study);
    }
  }
  pom_doe_study_clear(&study);
  return 0;
}
