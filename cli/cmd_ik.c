/* cmd_ik.c - pomlab ik: inverse kinematics, Jacobian, dexterity and limits of
 * one orientation. */
#include "cli_opts.h"
#include "cli_kin.h"
#include "pom_kin_print.h"
#include "pom_arch.h"
#include "pom_cli.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int pom_cmd_ik(int argc, char **argv) {
  const char *path = NULL, *angles = NULL;
  int json = 0, all = 0;
  const pom_opt opts[] = {
      {.name = "--euler-zyx",
       .kind = POM_OPT_TEXT,
       .arg = "P,T,R",
       .unit = "deg",
       .help = "orientation (required)",
       .text = &angles},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "machine-readable output on stdout",
       .flag = &json,
       .set = 1},
      {.name = "--all",
       .kind = POM_OPT_FLAG,
       .help = "every working mode (IK root per limb) instead of the home one",
       .flag = &all,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "ik",
      .usage = "CONFIG --euler-zyx PSI,THETA,PHI [--all] [--json]",
      .about = "Inverse kinematics of the platform orientation R = Rz(PSI) Ry(THETA) Rx(PHI),\n"
               "ZYX Euler angles in DEGREES (yaw, pitch, roll), on the home assembly branch.\n"
               "Prints the actuator coordinates q from mid-stroke (mm for linear actuators, deg\n"
               "for rotary ones; JSON in SI), the Jacobian J (q_dot = J omega, omega in the\n"
               "fixed frame; mm/rad or deg/rad, JSON m/rad or rad/rad), its singular values, the\n"
               "condition number kappa, the dexterity 1/kappa, reachability and every limit\n"
               "(stroke, joint cones, limb distance) with the ones that fail.\n"
               "--all: every working mode instead, one IK root per limb (2^3 = 8 for three\n"
               "limbs with two roots each): per mode the branch (+ the home root), q, det J,\n"
               "det J with unit rows (0 at a parallel singularity), kappa, the leg (serial)\n"
               "singularities and the limits (docs/kinematics-modes.md).",
      .notes = "Reads the config groups name, architecture, geometry, limits.\n"
               "Exit status: 0 reachable and within limits (--all: some working mode is);\n"
               "1 unreachable or a limit violated (the report is still printed); 2 usage or\n"
               "config error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!path || !angles) {
    fprintf(stderr, "pomlab ik: %s\n",
            !path ? "missing CONFIG" : "missing --euler-zyx PSI,THETA,PHI");
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  double e_deg[3];
  if (pom_cli_parse_list(angles, 3, e_deg) != 0 || !isfinite(e_deg[0]) || !isfinite(e_deg[1]) ||
      !isfinite(e_deg[2])) {
    fprintf(stderr,
            "pomlab ik: --euler-zyx '%s': expected three numbers PSI,THETA,PHI in degrees, all "
            "finite\n",
            angles);
    return 2;
  }
  if (fabs(e_deg[1]) >= 90.0) {
    fprintf(stderr, "pomlab ik: --euler-zyx: pitch THETA = %g deg must lie in (-90, 90)\n",
            e_deg[1]);
    return 2;
  }
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  const char *const *const scopes[] = {pom_kin_arch_groups(), NULL};
  int rc = pom_cli_kin_load(path, &cfg, &arch, NULL, scopes);
  if (rc) return rc;

  double e[3] = {e_deg[0] * POM_DEG, e_deg[1] * POM_DEG, e_deg[2] * POM_DEG}, R[9];
  pom_euler_zyx_to_matrix(R, e);
  pom_error err;
  pom_error_clear(&err);
  if (all) {
    pom_kin_mode modes[8];
    int n = 0, any = 0;
    pom_status st = pom_kin_inverse_all(&arch, R, modes, &n, &err);
    if (st != POM_OK) {
      pom_cli_report("ik", &err);
      pom_cfg_destroy(cfg);
      return 1;
    }
    pom_kin_modes_report(stdout, json, path, &arch, e_deg, NULL, 0, modes, n);
    for (int k = 0; k < n; ++k)
      any = any || modes[k].status == POM_OK;
    pom_cfg_destroy(cfg);
    return any ? 0 : 1;
  }
  pom_kin_pose p;
  pom_status st = pom_kin_pose_evaluate(&arch, R, &p, &err);

  pom_kin_ik_report(stdout, json, path, &arch, e_deg, &p, st, err.message);
  pom_cfg_destroy(cfg);
  return st == POM_OK ? 0 : 1;
}
