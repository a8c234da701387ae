/* cmd_fk.c - pomlab fk: forward kinematics of three actuator displacements. */
#include "cli_opts.h"
#include "cli_kin.h"
#include "pom_kin_print.h"
#include "pom_arch.h"
#include "pom_cli.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int pom_cmd_fk(int argc, char **argv) {
  const char *path = NULL, *qtext = NULL;
  int json = 0, all = 0, seeds = 0;
  const pom_opt opts[] = {
      {.name = "--q",
       .kind = POM_OPT_TEXT,
       .arg = "Q1,Q2,Q3",
       .unit = "mm for linear actuators, deg for rotary ones",
       .help = "actuator coordinates from mid-stroke (required)",
       .text = &qtext},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "machine-readable output on stdout",
       .flag = &json,
       .set = 1},
      {.name = "--all",
       .kind = POM_OPT_FLAG,
       .help = "every assembly mode (FK root) instead of the one reached from home",
       .flag = &all,
       .set = 1},
      {.name = "--seeds",
       .kind = POM_OPT_INT,
       .arg = "N",
       .help = "with --all: Newton starts per working mode (default 128)",
       .ival = &seeds,
       .lo = 1,
       .hi = 100000},
  };
  const pom_cli_spec spec = {
      .name = "fk",
      .usage = "CONFIG --q Q1,Q2,Q3 [--all [--seeds N]] [--json]",
      .about = "Forward kinematics: the platform orientation on the home assembly branch for\n"
               "actuator displacements Q1,Q2,Q3 in MILLIMETRES from mid-stroke (positive =\n"
               "extension). Newton with the analytic Jacobian from home, continued along\n"
               "q(t) = t q when direct Newton fails. Prints the rotation matrix, the ZYX Euler\n"
               "angles (degrees) and the unit quaternion (w, x, y, z), the iterations, the\n"
               "residual max|q(R) - q| (m or rad), the dexterity and the limits at that pose.\n"
               "--all: every assembly mode instead: damped Newton from N quasi-uniform starts\n"
               "on each working mode, equal roots merged; per mode the orientation, the\n"
               "working mode it lies on (branch per limb, + the home root), det J, det J with\n"
               "unit rows, kappa, singular flags and limits (docs/kinematics-modes.md).",
      .notes = "Reads the config groups name, architecture, geometry, limits.\n"
               "Exit status: 0 solved and within limits (--all: some mode is); 1 no solution,\n"
               "or a limit violated at the solution (the report is still printed); 2 usage or\n"
               "config error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!path || !qtext) {
    fprintf(stderr, "pomlab fk: %s\n", !path ? "missing CONFIG" : "missing --q Q1,Q2,Q3");
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  double q_disp[3];
  if (pom_cli_parse_list(qtext, 3, q_disp) != 0 || !isfinite(q_disp[0]) || !isfinite(q_disp[1]) ||
      !isfinite(q_disp[2])) {
    fprintf(stderr,
            "pomlab fk: --q '%s': expected three numbers Q1,Q2,Q3 (mm, or deg for rotary "
            "actuators), all finite\n",
            qtext);
    return 2;
  }
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  const char *const *const scopes[] = {pom_kin_arch_groups(), NULL};
  int rc = pom_cli_kin_load(path, &cfg, &arch, NULL, scopes);
  if (rc) return rc;

  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch.type));
  double q[3] = {q_disp[0] / u->to_display, q_disp[1] / u->to_display, q_disp[2] / u->to_display};
  double R[9];
  pom_kin_fk_info info = {0, 0, 0.0};
  pom_error err;
  pom_error_clear(&err);
  if (seeds && !all) {
    fprintf(stderr, "pomlab fk: --seeds %d: only with --all\n", seeds);
    pom_cfg_destroy(cfg);
    return 2;
  }
  if (all) {
    static pom_kin_mode modes[POM_KIN_MAX_MODES];
    pom_kin_fk_all_opts fo;
    pom_kin_fk_all_defaults(&fo);
    if (seeds) fo.seeds = seeds;
    int n = 0, any = 0;
    pom_status st = pom_kin_forward_all(&arch, q, &fo, modes, POM_KIN_MAX_MODES, &n, &err);
    if (st != POM_OK) {
      pom_cli_report("fk", &err);
      pom_cfg_destroy(cfg);
      return 1;
    }
    pom_kin_modes_report(stdout, json, path, &arch, NULL, q_disp, fo.seeds, modes, n);
    for (int k = 0; k < n; ++k)
      any = any || modes[k].status == POM_OK;
    pom_cfg_destroy(cfg);
    return any ? 0 : 1;
  }
  pom_status st = pom_kin_forward(&arch, q, NULL, NULL, R, &info, &err);
  if (st != POM_OK) {
    if (json) {
      printf("{\n  \"config\": ");
      pom_json_string(stdout, path);
      printf(",\n  \"actuator_unit\": \"%s\",\n  \"q_target\": ", u->si);
      pom_json_vec(stdout, q, 3, 1.0);
      printf(",\n  \"solved\": false,\n  \"iterations\": %d,\n  \"message\": ", info.iterations);
      pom_json_string(stdout, err.message);
      printf("\n}\n");
    }
    pom_cli_report("fk", &err);
    pom_cfg_destroy(cfg);
    return 1;
  }
  pom_kin_pose p;
  pom_error lerr;
  pom_error_clear(&lerr);
  pom_status lst = pom_kin_pose_evaluate(&arch, R, &p, &lerr);

  pom_kin_fk_report(stdout, json, path, &arch, q_disp, R, &info, &p, lst, lerr.message);
  pom_cfg_destroy(cfg);
  return lst == POM_OK ? 0 : 1;
}
