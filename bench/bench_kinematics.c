/* bench_kinematics.c - speed of the kinematics: IK + J + kappa per pose, full
 * pose evaluation with limits, FK per solve, the regular dexterous workspace
 * at 1 deg and the GCI, for both shipped configs. Prints medians of repeats.
 * Usage: bench_kinematics [SOURCE_DIR] (default: the configured source dir);
 * bench_kinematics twist [LOOPS [SOURCE_DIR]]: only the limb twists of the
 * three shipped architectures, one call of the type's limb_twist and (when
 * the type has it) limb_twist_diff per limb and pose, LOOPS passes over 1024
 * poses (default 200; a small LOOPS for callgrind). */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include "pom_arch.h"
#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define N_POSES 1024
#define REPEATS 7

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  return v[n / 2];
}

static double sink; /* keeps results alive */

static void bench_arch(const char *src, const char *rel) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", src, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_kin_arch arch;
  pom_kin_ws_opts ws;
  if (pom_cfg_load(&cfg, path, &err) != POM_OK || pom_kin_arch_load(&arch, cfg, &err) != POM_OK ||
      pom_kin_ws_load(&ws, cfg, &err) != POM_OK) {
    fprintf(stderr, "bench_kinematics: %s\n", err.message);
    pom_cfg_destroy(cfg);
    exit(1);
  }
  pom_cfg_destroy(cfg);

  static double R[N_POSES][9], q[N_POSES][3];
  pom_rng rng;
  pom_rng_seed(&rng, 2385, 7);
  for (int k = 0; k < N_POSES; ++k) {
    double e[3];
    for (int j = 0; j < 3; ++j)
      e[j] = pom_rng_range(&rng, -13.0 * POM_DEG, 13.0 * POM_DEG);
    pom_euler_zyx_to_matrix(R[k], e);
    pom_kin_inverse(&arch, R[k], q[k], NULL);
  }
  double t[REPEATS];
  const int loops = 500; /* 512000 poses per repeat */

  /* IK + J + kappa */
  for (int r = 0; r < REPEATS; ++r) {
    double t0 = now(), acc = 0.0;
    for (int l = 0; l < loops; ++l)
      for (int k = 0; k < N_POSES; ++k) {
        double qq[3], J[9], kappa;
        pom_kin_inverse_jacobian(&arch, R[k], qq, J, NULL);
        pom_kin_dexterity(J, NULL, &kappa, NULL);
        acc += kappa + qq[0];
      }
    t[r] = (now() - t0) / ((double)loops * N_POSES);
    sink += acc;
  }
  double t_ikj = median(t, REPEATS);

  /* full pose evaluation: IK, J, singular values, cones, segment distances */
  for (int r = 0; r < REPEATS; ++r) {
    double t0 = now(), acc = 0.0;
    for (int l = 0; l < loops / 5; ++l)
      for (int k = 0; k < N_POSES; ++k) {
        pom_kin_pose p;
        pom_kin_pose_evaluate(&arch, R[k], &p, NULL);
        acc += p.dexterity;
      }
    t[r] = (now() - t0) / ((double)(loops / 5) * N_POSES);
    sink += acc;
  }
  double t_pose = median(t, REPEATS);

  /* FK from home */
  int iters = 0;
  for (int r = 0; r < REPEATS; ++r) {
    double t0 = now(), acc = 0.0;
    iters = 0;
    for (int k = 0; k < N_POSES; ++k) {
      double Rf[9];
      pom_kin_fk_info info;
      pom_kin_forward(&arch, q[k], NULL, NULL, Rf, &info, NULL);
      acc += Rf[0];
      iters += info.iterations;
    }
    t[r] = (now() - t0) / N_POSES;
    sink += acc;
  }
  double t_fk = median(t, REPEATS);

  /* regular dexterous workspace at the config's resolution (1 deg) */
  pom_kin_ws_result res;
  for (int r = 0; r < REPEATS; ++r) {
    double t0 = now();
    pom_kin_workspace(&arch, &ws, &res, NULL);
    t[r] = now() - t0;
  }
  double t_ws = median(t, REPEATS);
  double gci = 0.0;
  for (int r = 0; r < REPEATS; ++r) {
    double t0 = now();
    pom_kin_gci(&arch, res.half_width, ws.resolution, ws.check_limits, &gci, NULL, NULL);
    t[r] = now() - t0;
  }
  double t_gci = median(t, REPEATS);

  printf("%s (%s)\n", rel, pom_kin_arch_name(&arch));
  printf("  IK + J + kappa, one pose:        %8.1f ns\n", t_ikj * 1e9);
  printf("  pose evaluation with limits:     %8.1f ns\n", t_pose * 1e9);
  printf("  FK from home (Newton):           %8.1f ns  (%.2f iterations on average)\n", t_fk * 1e9,
         (double)iters / N_POSES);
  printf("  RDW at %.3g deg: +-%g deg, %ld poses: %8.3f ms\n", ws.resolution / POM_DEG,
         res.half_width / POM_DEG, res.poses, t_ws * 1e3);
  printf("  GCI over the RDW at %.3g deg (%.4f):   %8.3f ms\n", ws.resolution / POM_DEG, gci,
         t_gci * 1e3);
}

/* limb_twist and limb_twist_diff per limb call: poses in the +-13 deg ZYX
 * cube, omega with components in +-10 rad/s (seed fixed). */
static void bench_twist(const char *src, const char *rel, int loops) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", src, rel);
  pom_cfg *cfg = NULL;
  pom_error err;
  pom_error_clear(&err);
  pom_kin_arch arch;
  if (pom_cfg_load(&cfg, path, &err) != POM_OK || pom_kin_arch_load(&arch, cfg, &err) != POM_OK) {
    fprintf(stderr, "bench_kinematics: %s\n", err.message);
    pom_cfg_destroy(cfg);
    exit(1);
  }
  pom_cfg_destroy(cfg);
  static double R[N_POSES][9], w[N_POSES][3];
  pom_rng rng;
  pom_rng_seed(&rng, 2385, 11);
  for (int k = 0; k < N_POSES; ++k) {
    double e[3];
    for (int j = 0; j < 3; ++j) {
      e[j] = pom_rng_range(&rng, -13.0 * POM_DEG, 13.0 * POM_DEG);
      w[k][j] = pom_rng_range(&rng, -10.0, 10.0);
    }
    pom_euler_zyx_to_matrix(R[k], e);
  }
  const pom_kin_arch_type *t = arch.type;
  static pom_kin_twists tw;
  static pom_kin_twists_diff dtw;
  double tm[REPEATS], td[REPEATS];
  long failed = 0;
  for (int r = 0; r < REPEATS; ++r) {
    double t0 = now(), acc = 0.0;
    for (int l = 0; l < loops; ++l)
      for (int k = 0; k < N_POSES; ++k)
        for (int i = 0; i < 3; ++i) {
          failed += !t->limb_twist(&arch, i, R[k], w[k], &tw);
          acc += tw.q_bias[i];
        }
    tm[r] = (now() - t0) / (3.0 * loops * N_POSES);
    sink += acc;
    td[r] = 0.0;
    if (!t->limb_twist_diff) continue;
    t0 = now();
    acc = 0.0;
    for (int l = 0; l < loops; ++l)
      for (int k = 0; k < N_POSES; ++k)
        for (int i = 0; i < 3; ++i) {
          failed += !t->limb_twist_diff(&arch, i, R[k], w[k], &tw, &dtw);
          acc += dtw.d_theta[0].q_bias[i];
        }
    td[r] = (now() - t0) / (3.0 * loops * N_POSES);
    sink += acc;
  }
  printf("%s (%s): %ld calls per op, %ld failed\n", rel, pom_kin_arch_name(&arch),
         (long)REPEATS * loops * N_POSES * 3, failed);
  printf("  limb_twist, one limb:            %8.1f ns\n", median(tm, REPEATS) * 1e9);
  if (t->limb_twist_diff)
    printf("  limb_twist_diff, one limb:       %8.1f ns\n", median(td, REPEATS) * 1e9);
}

int main(int argc, char **argv) {
  if (argc > 1 && strcmp(argv[1], "twist") == 0) {
    int loops = argc > 2 ? atoi(argv[2]) : 200;
    const char *src = argc > 3 ? argv[3] : POM_SOURCE_DIR;
    printf("bench_kinematics twist: medians of %d repeats\n", REPEATS);
    bench_twist(src, "configs/3pss.cfg", loops);
    bench_twist(src, "configs/3sps.cfg", loops);
    bench_twist(src, "configs/3rrr.cfg", loops);
    if (sink == 12345.678) printf("%g\n", sink);
    return 0;
  }
  const char *src = argc > 1 ? argv[1] : POM_SOURCE_DIR;
  printf("bench_kinematics: medians of %d repeats\n", REPEATS);
  bench_arch(src, "configs/3pss.cfg");
  bench_arch(src, "configs/3sps.cfg");
  if (sink == 12345.678) printf("%g\n", sink);
  return 0;
}
