/* cli_kin.c - helpers shared by the kinematics subcommands. */
#include "cli_kin.h"

#include "pom_arch.h"
#include "pom_cli.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>

int pom_cli_kin_check_unknown(const pom_cfg *cfg, const char *const *const scopes[]) {
  pom_error err;
  pom_error_clear(&err);
  if (pom_cli_check_unknown(cfg, scopes, &err) != POM_OK) {
    pom_cli_report("config", &err);
    return 2;
  }
  return 0;
}

int pom_cli_kin_load(const char *path, pom_cfg **cfg_out, pom_kin_arch *arch, pom_kin_ws_opts *ws,
                     const char *const *const check_scopes[]) {
  pom_error err;
  pom_error_clear(&err);
  *cfg_out = NULL;
  pom_cfg *cfg = pom_cli_load_config(path);
  if (!cfg) return 2;
  pom_status st = pom_kin_arch_load(arch, cfg, &err);
  if (st == POM_OK && ws) st = pom_kin_ws_load(ws, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_cfg_destroy(cfg);
    return pom_cli_exit_code(st);
  }
  if (check_scopes) {
    int rc = pom_cli_kin_check_unknown(cfg, check_scopes);
    if (rc) {
      pom_cfg_destroy(cfg);
      return rc;
    }
  }
  *cfg_out = cfg;
  return 0;
}
