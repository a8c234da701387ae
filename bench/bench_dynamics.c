/* bench_dynamics.c - time one 100 ms maneuver of a shipped configuration
 * (issue 3 goal: under 5 ms on one core at k_p = 1e6 N/m, rtol = 1e-6).
 *
 * usage: bench_dynamics CONFIG [q1,q2,q3 mm] [repeats] [dense|klu|structured] [euler|quaternion]
 *                       [parasitic|rigid] [analytic|finite-difference]
 * Prints the median and minimum wall time of `repeats` runs of the same
 * maneuver (model and data built once, as a Monte-Carlo worker does) and the
 * solver statistics of the last run. */
#include "pom_dynamics.h"
#include "pom_kinematics.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_seconds(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Processor time of this process (s): robust on a machine shared with other
 * jobs, where wall time includes waiting for a core. */
static double cpu_seconds(void) {
  return (double)clock() / (double)CLOCKS_PER_SEC;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr,
            "usage: %s CONFIG [q1,q2,q3 mm] [repeats] [dense|klu|structured] [euler|quaternion] "
            "[parasitic|rigid] [analytic|finite-difference]\n",
            argv[0]);
    return 2;
  }
  double target[3] = {3e-3, -3e-3, 3e-3};
  if (argc > 2 && sscanf(argv[2], "%lf,%lf,%lf", &target[0], &target[1], &target[2]) == 3)
    for (int a = 0; a < 3; ++a)
      target[a] *= 1e-3;
  int repeats = argc > 3 ? atoi(argv[3]) : 20;
  if (repeats < 1) repeats = 1;

  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_params par;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_dyn_metrics mt;
  double *times = calloc((size_t)repeats, sizeof *times);
  double *cpu = calloc((size_t)repeats, sizeof *cpu);
  int rc = 1;
  if (!mech || !times || !cpu) goto done;
  if (pom_cfg_load(&cfg, argv[1], &err) != POM_OK ||
      pom_kin_arch_load(&arch, cfg, &err) != POM_OK ||
      pom_kin_mechanism_build(mech, &arch, cfg, &err) != POM_OK)
    goto fail;
  pom_dyn_params_defaults(&par);
  if (pom_dyn_params_load(&par, cfg, &err) != POM_OK) goto fail;
  if (argc > 4)
    par.solver.linear_solver = strcmp(argv[4], "klu") == 0          ? POM_LINSOL_KLU
                               : strcmp(argv[4], "structured") == 0 ? POM_LINSOL_STRUCTURED
                                                                    : POM_LINSOL_DENSE;
  if (argc > 5)
    par.scene.orientation =
        strcmp(argv[5], "quaternion") == 0 ? POM_ORIENT_QUATERNION : POM_ORIENT_EULER_ZYX;
  if (argc > 6)
    par.joints.model = strcmp(argv[6], "rigid") == 0 ? POM_JOINTS_RIGID : POM_JOINTS_PARASITIC;
  if (argc > 7)
    par.solver.jacobian =
        strcmp(argv[7], "finite-difference") == 0 ? POM_JAC_FINITE_DIFFERENCE : POM_JAC_ANALYTIC;
  if (pom_dyn_model_create(&m, mech, &arch, &par, &err) != POM_OK ||
      pom_dyn_data_create(&d, m, &err) != POM_OK)
    goto fail;
  /* one warm-up run (first-touch of pages, KLU symbolic analysis) */
  if (pom_dyn_simulate(m, d, target, &mt, NULL, &err) != POM_OK) goto fail;
  for (int r = 0; r < repeats; ++r) {
    double t0 = now_seconds(), c0 = cpu_seconds();
    if (pom_dyn_simulate(m, d, target, &mt, NULL, &err) != POM_OK) goto fail;
    times[r] = now_seconds() - t0;
    cpu[r] = cpu_seconds() - c0;
  }
  qsort(times, (size_t)repeats, sizeof *times, cmp_double);
  qsort(cpu, (size_t)repeats, sizeof *cpu, cmp_double);
  printf("%s: %s joints, %s, %s, %s Jacobian, %d states, %d colours, k_p %.3g N/m, rtol %.1e\n",
         arch.name, pom_dyn_joint_model_name(par.joints.model),
         pom_dyn_linsol_name(par.solver.linear_solver), pom_dyn_orient_name(par.scene.orientation),
         pom_dyn_jacobian_name(par.solver.jacobian), pom_dyn_model_n_states(m),
         pom_dyn_model_n_colors(m), par.joints.stiffness, par.solver.rtol);
  printf("maneuver (%.3g, %.3g, %.3g) mm over %.0f ms: wall median %.3f ms, min %.3f ms; CPU "
         "median %.3f ms, min %.3f ms (%d runs)\n",
         target[0] * 1e3, target[1] * 1e3, target[2] * 1e3, par.maneuver.horizon * 1e3,
         times[repeats / 2] * 1e3, times[0] * 1e3, cpu[repeats / 2] * 1e3, cpu[0] * 1e3, repeats);
  printf("steps %ld, RHS %ld (Jacobian %ld), Jacobians %ld, factorizations %ld, Newton %ld, "
         "error-test fails %ld, convergence fails %ld; execution time %.3f ms, energy %.4f J\n",
         mt.steps, mt.rhs_evals, mt.jac_rhs_evals, mt.jac_evals, mt.linsol_setups, mt.newton_iters,
         mt.error_test_fails, mt.nonlin_conv_fails, mt.execution_time * 1e3, mt.energy_total);
  rc = 0;
  goto done;
fail:
  fprintf(stderr, "bench_dynamics: %s\n", err.message);
done:
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  pom_cfg_destroy(cfg);
  free(mech);
  free(times);
  free(cpu);
  return rc;
}
