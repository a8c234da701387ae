/* cmd_model.c - pomlab model: the resolved mechanism in SI units, fixed frame
 * at the home pose. The kinematic part (geometry, limits, bodies, joints,
 * actuator axes) is printed by the kinematics (pom_kin_print.h); the
 * dynamics groups (actuator electrics, controller gains, joints, scene) by
 * the dynamics (pom_dyn_print.h). */
#include "cli_opts.h"
#include "pom_dyn_print.h"
#include "cli_kin.h"
#include "pom_kin_print.h"
#include "pom_arch.h"
#include "pom_cli.h"
#include "pom_math.h"

#include <stdio.h>
#include <string.h>

int pom_cmd_model(int argc, char **argv) {
  int list = 0;
  const char *path = NULL;
  int json = 0;
  const pom_opt opts[] = {
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "machine-readable output on stdout",
       .flag = &json,
       .set = 1},
      {.name = "--list-architectures",
       .kind = POM_OPT_FLAG,
       .help = "the registered architectures: name, actuator kind, scale, design parameters and "
               "limits (docs/extending.md)",
       .flag = &list,
       .set = 1},
      {.name = "--list-controllers",
       .kind = POM_OPT_FLAG,
       .help = "the registered controllers: states, options and gains with unit, range, default "
               "and whether tuning searches them",
       .flag = &list,
       .set = 2},
  };
  const pom_cli_spec spec = {
      .name = "model",
      .usage = "CONFIG [--json]\n"
               "       pomlab model --list-architectures [--json]\n"
               "       pomlab model --list-controllers [--json]",
      .about = "The resolved mechanism at the home pose (R = I, actuators at mid-stroke), in\n"
               "the fixed frame (text: lengths in mm, angles in deg, masses in kg, inertias in\n"
               "kg m^2; --json: SI, m and rad): geometry and limits, every body\n"
               "with mass, centre of mass and inertia tensor about the CM, every joint with\n"
               "type, bodies, location and axes, every actuator with axis and stroke. Complete\n"
               "enough for another program to rebuild the mechanism.",
      .notes = "Validates the config groups name, architecture, geometry, limits, workspace,\n"
               "inertia, and the dynamics groups actuator, controller, joints, scene, solver,\n"
               "maneuver (printed after the mechanism). Exit status: 0 ok; 2 usage or config\n"
               "error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (list == 2) {
    pom_dyn_ctrl_list(stdout, json);
    return 0;
  }
  if (list) {
    pom_kin_arch_list(stdout, json);
    return 0;
  }
  if (!path) {
    fprintf(stderr, "pomlab model: missing CONFIG\n");
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_kin_ws_opts ws;
  int rc = pom_cli_kin_load(path, &cfg, &arch, &ws, NULL);
  if (rc) return rc;
  pom_error err;
  pom_error_clear(&err);
  pom_mechanism mech;
  pom_status st = pom_kin_mechanism_build(&mech, &arch, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_cfg_destroy(cfg);
    return pom_cli_exit_code(st);
  }
  /* dynamics: the actuator/controller/joints/scene/solver/maneuver groups */
  pom_dyn_params dyn;
  pom_dyn_params_defaults(&dyn);
  st = pom_dyn_params_load(&dyn, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_cfg_destroy(cfg);
    return pom_cli_exit_code(st);
  }
  /* unknown keys in every group model reads: the model's and the workspace's */
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_kin_ws_groups(),
                                       pom_dyn_param_groups(), NULL};
  rc = pom_cli_kin_check_unknown(cfg, scopes);
  pom_cfg_destroy(cfg);
  if (rc) return rc;

  if (json) {
    printf("{\n  \"config\": ");
    pom_json_string(stdout, path);
    printf(",\n  \"name\": ");
    pom_json_string(stdout, arch.name);
    printf(",\n  \"architecture\": \"%s\",\n", pom_kin_arch_name(&arch));
    printf("  \"units\": \"SI (m, kg, kg m^2, rad, m/s^2); fixed frame at the home pose\",\n");
    pom_kin_mechanism_json(stdout, &arch, &mech);
    pom_dyn_params_json(stdout, &dyn);
    printf("\n}\n");
  } else {
    printf("%s (%s), config %s\n", arch.name, pom_kin_arch_name(&arch), path);
    pom_kin_mechanism_text(stdout, &arch, &mech);
    pom_dyn_params_text(stdout, &dyn);
  }
  return 0;
}
