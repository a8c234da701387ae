/* bench_exact_maneuver.c - cost per maneuver of the exact (rigid-joint) path
 * at one setting (issue 10 goal: <= 0.5 ms per maneuver at the recommended
 * 1 % setting of `pomlab tradeoff`: rigid joints, quasi-static coil, rtol
 * 1e-4).
 *
 * usage: bench_exact_maneuver CONFIG [maneuvers] [repeats] [rtol] [quasi-static|inductive]
 * Draws `maneuvers` targets uniformly in +-3 mm per actuator (seed 2385,
 * stream k for maneuver k, as bench_dynamics_exact), builds the model and one
 * data once (as a Monte-Carlo worker does), runs the set once to warm up and
 * then `repeats` times. Prints the minimum and median processor time per
 * maneuver (the machine is shared: the minimum is the better figure), the
 * solver counts per maneuver (noise-free) and the sums of execution times and
 * energies (to check that a change of the engine leaves the results alone; a
 * maneuver that does not settle is left out of the first sum and counted). */
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_MANEUVERS 1000
#define MAX_REPEATS   101

static double cpu_seconds(void) {
  return (double)clock() / (double)CLOCKS_PER_SEC;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s CONFIG [maneuvers] [repeats] [rtol] [quasi-static|inductive]\n",
            argv[0]);
    return 2;
  }
  int n = argc > 2 ? atoi(argv[2]) : 20;
  int repeats = argc > 3 ? atoi(argv[3]) : 5;
  double rtol = argc > 4 ? atof(argv[4]) : 1e-4;
  int quasi_static = !(argc > 5 && strcmp(argv[5], "inductive") == 0);
  if (n < 1 || n > MAX_MANEUVERS || repeats < 1 || repeats > MAX_REPEATS || !(rtol > 0)) {
    fprintf(stderr, "bench_exact_maneuver: maneuvers 1..%d, repeats 1..%d, rtol > 0\n",
            MAX_MANEUVERS, MAX_REPEATS);
    return 2;
  }
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  double(*target)[3] = calloc((size_t)n, sizeof *target);
  double times[MAX_REPEATS];
  pom_dyn_params par;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  int rc = 1;
  if (!mech || !target) goto done;
  pom_dyn_params_defaults(&par);
  if (pom_cfg_load(&cfg, argv[1], &err) != POM_OK ||
      pom_kin_arch_load(&arch, cfg, &err) != POM_OK ||
      pom_kin_mechanism_build(mech, &arch, cfg, &err) != POM_OK ||
      pom_dyn_params_load(&par, cfg, &err) != POM_OK)
    goto fail;
  par.joints.model = POM_JOINTS_RIGID;
  par.solver.rtol = rtol;
  /* the tradeoff's rtol rows: atol_scale = min(config's, 1e3 rtol) */
  par.solver.atol_scale = fmin(par.solver.atol_scale, 1e3 * rtol);
  if (quasi_static) par.scene.coil_inductance = 0;
  for (int k = 0; k < n; ++k) {
    pom_rng rng;
    pom_rng_seed(&rng, 2385, (uint64_t)k);
    for (int a = 0; a < 3; ++a)
      target[k][a] = pom_rng_range(&rng, -3e-3, 3e-3);
  }
  if (pom_dyn_model_create(&m, mech, &arch, &par, &err) != POM_OK ||
      pom_dyn_data_create(&d, m, &err) != POM_OK)
    goto fail;
  double steps = 0, rhs = 0, jac = 0, setups = 0, exec_sum = 0, energy_sum = 0;
  int unsettled = 0;
  for (int r = -1; r < repeats; ++r) {
    double c0 = cpu_seconds();
    for (int k = 0; k < n; ++k) {
      pom_dyn_metrics mt;
      if (pom_dyn_simulate(m, d, target[k], &mt, NULL, &err) != POM_OK) goto fail;
      if (r < 0) {
        steps += (double)mt.steps / n;
        rhs += (double)mt.rhs_evals / n;
        jac += (double)mt.jac_evals / n;
        setups += (double)mt.linsol_setups / n;
        if (isnan(mt.execution_time))
          ++unsettled;
        else
          exec_sum += mt.execution_time;
        energy_sum += mt.energy_total;
      }
    }
    if (r >= 0) times[r] = (cpu_seconds() - c0) / n;
  }
  qsort(times, (size_t)repeats, sizeof times[0], cmp_double);
  printf("%s: rigid joints, %s coil, %s, rtol %.1e, %d states, %d maneuvers x %d runs\n", arch.name,
         quasi_static ? "quasi-static" : "inductive", pom_dyn_orient_name(par.scene.orientation),
         rtol, pom_dyn_model_n_states(m), n, repeats);
  printf("CPU per maneuver: min %.4f ms, median %.4f ms\n", times[0] * 1e3,
         times[repeats / 2] * 1e3);
  printf("per maneuver: steps %.2f, RHS %.2f, Jacobians %.2f, factorizations %.2f\n", steps, rhs,
         jac, setups);
  printf("sum of execution times %.9f s (%d unsettled left out), sum of energies %.9f J\n",
         exec_sum, unsettled, energy_sum);
  rc = 0;
  goto done;
fail:
  fprintf(stderr, "bench_exact_maneuver: %s\n", err.message);
done:
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  pom_cfg_destroy(cfg);
  free(mech);
  free(target);
  return rc;
}
