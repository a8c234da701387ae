/* bench_optimize.c - two-architecture kinematic synthesis: surrogate route
 * (design + fits + optimum + confirmation) against direct NLopt on the true
 * kinematics, with the shipped configs/synth_3pss.cfg and synth_3sps.cfg.
 * Usage: bench_optimize [repeats]   (medians over repeats, default 3) */
#include "pom_synth.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define MAXREP 15

static double now_s(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int main(int argc, char **argv) {
  int reps = argc > 1 ? atoi(argv[1]) : 3;
  if (reps < 1 || reps > MAXREP) reps = 3;
  const char *files[2] = {POM_SOURCE_DIR "/configs/synth_3pss.cfg",
                          POM_SOURCE_DIR "/configs/synth_3sps.cfg"};
  static pom_syn_problem pb[2];
  pom_error err;
  pom_error_clear(&err);
  for (int a = 0; a < 2; ++a) {
    pom_cfg *cfg = NULL;
    if (pom_cfg_load(&cfg, files[a], &err) != POM_OK || pom_syn_load(&pb[a], cfg, &err) != POM_OK) {
      fprintf(stderr, "bench_optimize: %s\n", err.message);
      pom_cfg_destroy(cfg);
      return 1;
    }
    pom_cfg_destroy(cfg);
  }
  double both[MAXREP];
  printf("| figure | 3PSS | 3SPS |\n|---|---|---|\n");
  double t_design[2][MAXREP], t_sur[2][MAXREP], t_dir[2][MAXREP], t_scale[2][MAXREP];
  long true_sur[2] = {0, 0}, surf_evals[2] = {0, 0}, true_dir[2] = {0, 0}, scale_evals[2] = {0, 0};
  double d_conf[2] = {0, 0}, d_dir[2] = {0, 0}, d_pred[2] = {0, 0};
  for (int r = 0; r < reps; ++r) {
    double t0 = now_s();
    for (int a = 0; a < 2; ++a) {
      pom_syn_run *run = NULL;
      double s0 = now_s();
      if (pom_syn_begin(&run, &pb[a], &err) != POM_OK || pom_syn_finish(run, &err) != POM_OK) {
        fprintf(stderr, "bench_optimize: %s\n", err.message);
        pom_syn_destroy(run);
        return 1;
      }
      double total = now_s() - s0;
      t_design[a][r] = run->design_time;
      t_sur[a][r] = run->surrogate_time;
      t_dir[a][r] = run->direct.wall_time;
      t_scale[a][r] = total - run->surrogate_time - run->direct.wall_time;
      true_sur[a] = run->true_evals;
      surf_evals[a] = run->surrogate.evals_global + run->surrogate.evals_local;
      true_dir[a] = run->direct.evals_global + run->direct.evals_local;
      scale_evals[a] = run->scale_evals;
      d_pred[a] = run->d_predicted;
      d_conf[a] = run->d_confirmed;
      d_dir[a] = run->d_direct;
      pom_syn_destroy(run);
    }
    both[r] = now_s() - t0;
  }
  double m[2][4];
  for (int a = 0; a < 2; ++a) {
    m[a][0] = median(t_design[a], reps);
    m[a][1] = median(t_sur[a], reps);
    m[a][2] = median(t_dir[a], reps);
    m[a][3] = median(t_scale[a], reps);
  }
  printf(
      "| surrogate route: 2 designs + held-out + fits + optima + confirmations | %.2f s (%ld true "
      "evaluations, %ld surface evaluations) | %.2f s (%ld, %ld) |\n",
      m[0][1], true_sur[0], surf_evals[0], m[1][1], true_sur[1], surf_evals[1]);
  printf("| of which the first design's runs | %.2f s | %.2f s |\n", m[0][0], m[1][0]);
  printf("| direct NLopt on the true kinematics | %.2f s (%ld true evaluations) | %.2f s (%ld) |\n",
         m[0][2], true_dir[0], m[1][2], true_dir[1]);
  printf(
      "| scaling to the stroke (bisection) + scaled responses | %.2f s (%ld workspaces) | %.2f s "
      "(%ld) |\n",
      m[0][3], scale_evals[0], m[1][3], scale_evals[1]);
  printf("| desirability: surfaces / confirmed / direct | %.4f / %.4f / %.4f | %.4f / %.4f / %.4f "
         "|\n",
         d_pred[0], d_conf[0], d_dir[0], d_pred[1], d_conf[1], d_dir[1]);
  printf("\ntwo-architecture synthesis, everything (surrogate + direct + scaling): median %.2f s "
         "over %d repeats\n",
         median(both, reps), reps);
  return 0;
}
