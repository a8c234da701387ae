/* cli_kin.h - helpers shared by the kinematics subcommands (model, ik, fk,
 * workspace): argument scanning, loading an architecture with unknown-key
 * checks, and small JSON writers. */
#ifndef POM_CLI_KIN_H
#define POM_CLI_KIN_H

#include "pom_config.h"
#include "pom_json.h" /* the JSON writers, once in core */
#include "pom_kinematics.h"

#include <stdio.h>

/* Loads the config at path and its architecture; reports errors on stderr.
 * When ws is not NULL the `workspace` group is read too. When check_scopes is
 * not NULL, unknown keys in those groups are rejected (and unknown top-level
 * names always). Returns the exit code (0 ok, 2 config error); on success
 * *cfg_out is owned by the caller. */
int pom_cli_kin_load(const char *path, pom_cfg **cfg_out, pom_kin_arch *arch, pom_kin_ws_opts *ws,
                     const char *const *const check_scopes[]);

/* Rejects unknown keys in the groups of scopes (the libraries' lists,
 * pom_cli_check_unknown) and unknown top-level names; returns 0 or prints
 * the error and returns 2. */
int pom_cli_kin_check_unknown(const pom_cfg *cfg, const char *const *const scopes[]);

#endif
