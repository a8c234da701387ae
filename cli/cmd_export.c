/* cmd_export.c - `pomlab export CONFIG --mjcf F.xml`: the resolved mechanism
 * as a MuJoCo MJCF model (kinematics/pom_mjcf.h, docs/export.md). The
 * program parses and reports; the model is written whole or not at all
 * (pom_io.h). */
#include "cli_kin.h"
#include "cli_opts.h"
#include "pom_cli.h"
#include "pom_dyn_print.h"
#include "pom_io.h"
#include "pom_kin_print.h"
#include "pom_mjcf.h"

#include <stdio.h>
#include <string.h>

static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

int pom_cmd_export(int argc, char **argv) {
  const char *path = NULL, *mjcf = NULL;
  const pom_opt opts[] = {
      {.name = "--mjcf",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.xml",
       .help = "the mechanism as a MuJoCo MJCF model: bodies, joints, loop-closing connect "
               "constraints, motors with the coil's constant (docs/export.md)",
       .text = &mjcf},
  };
  const pom_cli_spec spec = {
      .name = "export",
      .usage = "CONFIG --mjcf FILE.xml",
      .about = "The resolved mechanism (pomlab model) written for another program: MuJoCo's\n"
               "MJCF, in SI units, at the home pose (qpos = 0), so that a design can be\n"
               "cross-checked in a simulator one already has.",
      .notes = "Reads the groups pomlab model reads (the actuator group for the coil).\n"
               "Exit status: 0 ok; 1 the file cannot be written (nothing is left behind)\n"
               "or the mechanism cannot be written as MJCF; 2 usage or config error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!path || !mjcf) {
    fprintf(stderr, "pomlab export: %s\n\n", !path ? "missing CONFIG" : "missing --mjcf FILE.xml");
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  if (!ends_with(mjcf, ".xml")) {
    fprintf(stderr, "pomlab export: --mjcf must end in .xml, got '%s'\n", mjcf);
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
  pom_dyn_params dyn;
  pom_dyn_params_defaults(&dyn);
  pom_status st = pom_kin_mechanism_build(&mech, &arch, cfg, &err);
  if (st == POM_OK) st = pom_dyn_params_load(&dyn, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_cfg_destroy(cfg);
    return pom_cli_exit_code(st);
  }
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_kin_ws_groups(),
                                       pom_dyn_param_groups(), NULL};
  rc = pom_cli_kin_check_unknown(cfg, scopes);
  pom_cfg_destroy(cfg);
  if (rc) return rc;
  const pom_mjcf_coil coil = {.constant = dyn.actuator.force_constant,
                              .resistance = dyn.actuator.resistance,
                              .voltage_limit = dyn.actuator.voltage_limit};
  pom_io_file wf;
  st = pom_io_create(&wf, mjcf, &err);
  if (st == POM_OK) {
    st = pom_mjcf_write(wf.f, arch.name[0] ? arch.name : pom_kin_arch_name(&arch), &arch, &mech,
                        &coil, &err);
    if (st == POM_OK)
      st = pom_io_commit(&wf, &err);
    else
      pom_io_abort(&wf);
  }
  if (st != POM_OK) {
    char context[1200];
    snprintf(context, sizeof context, "export: %s", mjcf);
    pom_cli_report(context, &err);
    return 1;
  }
  printf("pomlab export: %s (%s) written to %s\n", path, pom_kin_arch_name(&arch), mjcf);
  return 0;
}
