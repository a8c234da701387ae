/* bench_doe.c - the Monte-Carlo runner's own cost: wall time against the
 * number of maneuvers, speed-up from 1 to 2 threads, peak memory. The
 * evaluator burns a fixed amount of CPU per maneuver (no dynamics), so the
 * figures isolate the runner, the queue and the HDF5 writer. Each case runs
 * in a child process so its peak RSS is its own.
 *
 * usage: bench_doe [iterations_per_maneuver (default 20000)] */
#define _DEFAULT_SOURCE
#include "pom_run.h"
#include "pom_progress.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

static long iterations = 20000;

static pom_status burn_run(const void *ctx, void *w, const double q[3], pom_dyn_metrics *m,
                           pom_error *err) {
  (void)ctx, (void)w, (void)err;
  memset(m, 0, sizeof *m);
  double x = q[0] + 1.0;
  for (long k = 0; k < iterations; ++k)
    x = x * 0.999999 + 1e-3 * sin(x);
  for (int i = 0; i < 3; ++i) {
    m->target[i] = q[i];
    m->settled[i] = 1;
    m->settling_time[i] = 0.01 + fabs(q[i]);
    m->energy[i] = q[i] * q[i] + 1e-12 * x;
    m->energy_total += m->energy[i];
  }
  m->execution_time = 0.01 + fmax(fabs(q[0]), fmax(fabs(q[1]), fabs(q[2])));
  return POM_OK;
}

/* Runs one case; prints "wall_s". */
static int run_case(long maneuvers, int threads, const char *path) {
  pom_doe_study study;
  memset(&study, 0, sizeof study);
  snprintf(study.name, sizeof study.name, "bench");
  study.config_text = malloc(8);
  if (!study.config_text) return 1;
  strcpy(study.config_text, "bench");
  study.alpha = 0.05;
  study.confidence = 0.95;
  pom_doe_maneuvers_defaults(&study.maneuvers);
  study.maneuvers.count = maneuvers;
  study.n_candidates = 2;
  study.candidates = calloc(2, sizeof *study.candidates);
  if (!study.candidates) return 1;
  for (int c = 0; c < 2; ++c) {
    snprintf(study.candidates[c].name, sizeof study.candidates[c].name, "c%d", c);
    study.candidates[c].eval.run = burn_run;
  }
  pom_doe_run_options o;
  pom_doe_run_options_defaults(&o);
  o.threads = threads;
  o.output = path;
  pom_error err;
  pom_doe_report *rep = NULL;
  double t0 = pom_progress_now();
  pom_status st = pom_doe_run_all(&study, &o, &rep, &err);
  double wall = pom_progress_now() - t0;
  if (st != POM_OK) {
    fprintf(stderr, "bench_doe: %s\n", err.message);
    return 1;
  }
  printf("%.6f\n", wall);
  pom_doe_report_destroy(rep);
  pom_doe_study_clear(&study);
  return 0;
}

int main(int argc, char **argv) {
  if (argc > 1) iterations = strtol(argv[1], NULL, 10);
  const long counts[] = {250, 500, 1000, 2000, 4000};
  char path[] = "/tmp/bench_doe_XXXXXX.h5";
  int fd = mkstemps(path, 3);
  if (fd < 0) return 1;
  close(fd);
  printf("# 2 candidates x M maneuvers, %ld iterations of work per maneuver\n", iterations);
  printf("# %6s %7s %9s %12s %11s\n", "M", "threads", "wall_s", "us_per_unit", "maxrss_MB");
  for (size_t j = 0; j < sizeof counts / sizeof counts[0]; ++j)
    for (int threads = 1; threads <= 2; ++threads) {
      int pipefd[2];
      fflush(stdout); /* or the child inherits (and repeats) unflushed output */
      if (pipe(pipefd) != 0) return 1;
      pid_t pid = fork();
      if (pid == 0) {
        dup2(pipefd[1], 1);
        close(pipefd[0]);
        int r = run_case(counts[j], threads, path);
        fflush(stdout);
        _exit(r);
      }
      close(pipefd[1]);
      char buf[64] = "";
      ssize_t n = read(pipefd[0], buf, sizeof buf - 1);
      close(pipefd[0]);
      int status = 0;
      struct rusage ru;
      wait4(pid, &status, 0, &ru);
      if (n <= 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "bench_doe: case M=%ld failed\n", counts[j]);
        return 1;
      }
      buf[n] = '\0';
      double wall = strtod(buf, NULL);
      printf("  %6ld %7d %9.3f %12.1f %11.1f\n", counts[j], threads, wall,
             1e6 * wall / (2.0 * (double)counts[j]), (double)ru.ru_maxrss / 1024.0);
      fflush(stdout);
    }
  unlink(path);
  return 0;
}
