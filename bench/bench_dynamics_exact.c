/* bench_dynamics_exact.c - speed against accuracy of the exact-constraint
 * (rigid-joint) path and the parasitic path on the paper's maneuvers
 * (issue 6 goal: the exact path at least 5x faster at equal settling-time
 * accuracy, 1 %).
 *
 * usage: bench_dynamics_exact CONFIG [maneuvers] [repeats] [inductive|quasi-static]
 * Draws `maneuvers` targets uniformly in +-3 mm per actuator (seed 2385,
 * stream k for maneuver k), computes a reference with the rigid path at
 * rtol 1e-9 (atol_scale 1e-6), then for each setting (joints model, k_p,
 * rtol) the processor time of the whole maneuver set (median of `repeats`)
 * and the worst relative error in execution time and in total energy
 * against the reference. Prints a table and the cheapest setting of each
 * path whose execution-time error is <= 1 %. With "quasi-static" every
 * setting (not the reference) drops the coil inductance (scene.coil_inductance
 * = false), a model simplification whose error the table then includes. */
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_MANEUVERS 64

static double cpu_seconds(void) {
  return (double)clock() / (double)CLOCKS_PER_SEC;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

typedef struct {
  const pom_kin_arch *arch;
  const pom_mechanism *mech;
  int n;
  double target[MAX_MANEUVERS][3];
  double exec_ref[MAX_MANEUVERS], energy_ref[MAX_MANEUVERS];
} problem;

/* Runs the maneuver set with p: CPU seconds (median of repeats, NAN on a
 * failure), worst relative errors against the reference (ref NULL: stores
 * the results as the reference) and mean steps. */
static double run_set(problem *pb, const pom_dyn_params *p, int repeats, double *err_exec,
                      double *err_energy, double *steps, int store_ref) {
  pom_error err;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  double times[16], res = NAN;
  if (repeats > 16) repeats = 16;
  if (pom_dyn_model_create(&m, pb->mech, pb->arch, p, &err) != POM_OK ||
      pom_dyn_data_create(&d, m, &err) != POM_OK) {
    fprintf(stderr, "bench_dynamics_exact: %s\n", err.message);
    goto done;
  }
  *err_exec = *err_energy = 0.0;
  *steps = 0.0;
  for (int r = 0; r < repeats; ++r) {
    double c0 = cpu_seconds();
    for (int k = 0; k < pb->n; ++k) {
      pom_dyn_metrics mt;
      if (pom_dyn_simulate(m, d, pb->target[k], &mt, NULL, &err) != POM_OK ||
          isnan(mt.execution_time)) {
        if (r == 0) fprintf(stderr, "  maneuver %d: %s\n", k, mt.reason);
        *err_exec = INFINITY;
        continue;
      }
      if (r > 0) continue;
      *steps += (double)mt.steps / pb->n;
      if (store_ref) {
        pb->exec_ref[k] = mt.execution_time;
        pb->energy_ref[k] = mt.energy_total;
      } else {
        *err_exec = fmax(*err_exec, fabs(mt.execution_time - pb->exec_ref[k]) / pb->exec_ref[k]);
        *err_energy =
            fmax(*err_energy, fabs(mt.energy_total - pb->energy_ref[k]) / fabs(pb->energy_ref[k]));
      }
    }
    times[r] = cpu_seconds() - c0;
  }
  qsort(times, (size_t)repeats, sizeof times[0], cmp_double);
  res = times[repeats / 2];
done:
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return res;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s CONFIG [maneuvers] [repeats] [inductive|quasi-static]\n", argv[0]);
    return 2;
  }
  int n = argc > 2 ? atoi(argv[2]) : 10;
  int repeats = argc > 3 ? atoi(argv[3]) : 3;
  if (n < 1 || n > MAX_MANEUVERS) n = 10;
  if (repeats < 1) repeats = 1;
  int quasi_static = argc > 4 && strcmp(argv[4], "quasi-static") == 0;
  pom_error err;
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  problem *pb = calloc(1, sizeof *pb);
  pom_dyn_params base;
  int rc = 1;
  if (!mech || !pb) goto done;
  pom_dyn_params_defaults(&base);
  if (pom_cfg_load(&cfg, argv[1], &err) != POM_OK ||
      pom_kin_arch_load(&arch, cfg, &err) != POM_OK ||
      pom_kin_mechanism_build(mech, &arch, cfg, &err) != POM_OK ||
      pom_dyn_params_load(&base, cfg, &err) != POM_OK) {
    fprintf(stderr, "bench_dynamics_exact: %s\n", err.message);
    goto done;
  }
  pb->arch = &arch;
  pb->mech = mech;
  pb->n = n;
  for (int k = 0; k < n; ++k) {
    pom_rng rng;
    pom_rng_seed(&rng, 2385, (uint64_t)k);
    for (int a = 0; a < 3; ++a)
      pb->target[k][a] = pom_rng_range(&rng, -3e-3, 3e-3);
  }
  double e1, e2, st;
  pom_dyn_params p = base;
  p.joints.model = POM_JOINTS_RIGID;
  p.solver.rtol = 1e-9;
  p.solver.atol_scale = 1e-6;
  double tref = run_set(pb, &p, 1, &e1, &e2, &st, 1);
  if (isnan(tref) || isinf(e1)) goto done;
  printf("%s: %d maneuvers (+-3 mm), reference rigid rtol 1e-9: %.1f ms CPU per maneuver, %.0f "
         "steps\n",
         arch.name, n, 1e3 * tref / n, st);
  printf("| joints | k_p (N/m) | rtol | CPU per maneuver (ms) | steps | max exec. time error | max "
         "energy error |\n|---|---|---|---|---|---|---|\n");
  const double rtols[] = {1e-4, 1e-5, 1e-6, 1e-7};
  const double kps[] = {1e5, 1e6, 1e7, 1e8};
  double best[2] = {INFINITY, INFINITY};
  char best_txt[2][96] = {"none", "none"};
  for (int joints = 0; joints < 2; ++joints)
    for (int ik = 0; ik < (joints ? 4 : 1); ++ik)
      for (int ir = 0; ir < 4; ++ir) {
        p = base;
        p.joints.model = joints ? POM_JOINTS_PARASITIC : POM_JOINTS_RIGID;
        p.solver.rtol = rtols[ir];
        if (quasi_static) p.scene.coil_inductance = 0;
        if (joints) {
          /* damping scaled with sqrt(k_p): the shipped ratio at 1e6 for every k_p */
          p.joints.stiffness = p.joints.angular_stiffness = kps[ik];
          p.joints.damping = p.joints.angular_damping = base.joints.damping * sqrt(kps[ik] / 1e6);
        }
        double t = run_set(pb, &p, repeats, &e1, &e2, &st, 0);
        char kp[32];
        snprintf(kp, sizeof kp, joints ? "%.0e" : "-", kps[ik]);
        printf("| %s | %s | %.0e | %.2f | %.0f | %.2e | %.2e |\n",
               pom_dyn_joint_model_name(p.joints.model), kp, rtols[ir], 1e3 * t / n, st, e1, e2);
        fflush(stdout);
        if (e1 <= 0.01 && t < best[joints]) {
          best[joints] = t;
          snprintf(best_txt[joints], sizeof best_txt[0], "k_p %s, rtol %.0e: %.2f ms", kp,
                   rtols[ir], 1e3 * t / n);
        }
      }
  printf("cheapest with execution-time error <= 1 %% (%s coil): rigid %s; parasitic %s; ratio "
         "%.2f\n",
         quasi_static ? "quasi-static" : "inductive", best_txt[0], best_txt[1], best[1] / best[0]);
  rc = 0;
done:
  pom_cfg_destroy(cfg);
  free(mech);
  free(pb);
  return rc;
}
