/* main.c - pomlab as a C library: loads a mechanism config, solves the
 * inverse kinematics of one orientation and runs one maneuver, printing both
 * (SI units). The library itself never prints: every message below is this
 * program's, taken from the pom_error records the calls fill.
 * Usage: pomlab_example CONFIG [PSI THETA PHI [Q1 Q2 Q3]]: the orientation
 * in degrees (default 2, -1.5, 1) and the maneuver's actuator targets in
 * the program's display unit, mm (default 1, 2, 3). */
#include <pom_config.h>
#include <pom_dyn_metrics_schema.h>
#include <pom_dynamics.h>
#include <pom_kinematics.h>
#include <pom_math.h>
#include <pom_version.h>

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
  if (argc != 2 && argc != 5 && argc != 8) {
    fprintf(stderr, "usage: %s CONFIG [PSI THETA PHI [Q1 Q2 Q3]]\n", argv[0]);
    return 2;
  }
  double e_deg[3] = {2.0, -1.5, 1.0}, target_mm[3] = {1.0, 2.0, 3.0};
  for (int k = 0; argc >= 5 && k < 3; ++k)
    e_deg[k] = atof(argv[2 + k]);
  for (int k = 0; argc == 8 && k < 3; ++k)
    target_mm[k] = atof(argv[5 + k]);

  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = NULL;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_dyn_model *model = NULL;
  pom_dyn_data *data = NULL;
  pom_kin_arch arch;
  pom_dyn_params par;
  pom_kin_pose pose;
  pom_dyn_metrics mt;
  int rc = 1;
  if (!mech) return 1;

  /* the config, its architecture and the pose at a ZYX Euler orientation */
  pom_status st = pom_cfg_load(&cfg, argv[1], &err);
  if (st == POM_OK) st = pom_kin_arch_load(&arch, cfg, &err);
  if (st != POM_OK) goto fail;
  double e[3] = {e_deg[0] * POM_DEG, e_deg[1] * POM_DEG, e_deg[2] * POM_DEG}, R[9];
  pom_euler_zyx_to_matrix(R, e);
  st = pom_kin_pose_evaluate(&arch, R, &pose, &err);
  if (st != POM_OK && st != POM_ERR_LIMIT) goto fail;
  printf("pomlab %s, %s (%s)\n", pom_version(), arch.name, pom_kin_type_label(arch.type));
  printf("ik euler_zyx_deg %g %g %g\n", e_deg[0], e_deg[1], e_deg[2]);
  printf("ik q %.17g %.17g %.17g\n", pose.q[0], pose.q[1], pose.q[2]);
  printf("ik dexterity %.17g\n", pose.dexterity);

  /* one maneuver from rest at mid-stroke to the targets (SI inside) */
  double target[3] = {target_mm[0] / 1e3, target_mm[1] / 1e3, target_mm[2] / 1e3};
  st = pom_kin_mechanism_build(mech, &arch, cfg, &err);
  pom_dyn_params_defaults(&par);
  if (st == POM_OK) st = pom_dyn_params_load(&par, cfg, &err);
  if (st == POM_OK) st = pom_dyn_model_create(&model, mech, &arch, &par, &err);
  if (st == POM_OK) st = pom_dyn_data_create(&data, model, &err);
  if (st == POM_OK) st = pom_dyn_simulate(model, data, target, &mt, NULL, &err);
  if (st != POM_OK) goto fail;
  printf("simulate target %.17g %.17g %.17g\n", target[0], target[1], target[2]);
  printf("simulate execution_time_s %.9g\n", mt.execution_time);
  printf("simulate energy_total_J %.9g\n", mt.energy_total);
  printf("simulate steps %ld\n", mt.steps);
  rc = 0;
fail:
  if (rc) fprintf(stderr, "pomlab_example: %s: %s\n", pom_status_name(st), err.message);
  pom_dyn_data_destroy(data);
  pom_dyn_model_destroy(model);
  pom_cfg_destroy(cfg);
  free(mech);
  return rc;
}
