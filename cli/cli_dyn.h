/* cli_dyn.h - printing of the dynamics parameter groups (actuator,
 * controller, joints, scene, solver, maneuver) for `pomlab model`. */
#ifndef POM_CLI_DYN_H
#define POM_CLI_DYN_H

#include "pom_dynamics.h"

#include <stdio.h>

/* Prints ",\n  \"actuator\": {...}, ..." (JSON members, SI units) to out:
 * every group of pom_dyn_param_groups(), every parameter of the list by its
 * json key (pom_dyn_params_schema.h), the controller by its type. */
void pom_cli_dyn_params_json(FILE *out, const pom_dyn_params *p);

/* Prints the groups as human-readable lines to out: one line per group,
 * each parameter by its config key with the value in the key's unit. */
void pom_cli_dyn_params_text(FILE *out, const pom_dyn_params *p);

/* Prints the members of the `controller` group of c, from its type's
 * descriptors: "type": "pid", then each option and gain by its config key
 * (SI values), without braces. */
void pom_cli_ctrl_json_members(FILE *out, const pom_dyn_controller *c);

/* `pomlab model --list-controllers [--json]`: every registered controller
 * type with its states, options and gains (key, unit, range, default,
 * tunable, searched in log). Returns the exit status (0). */
int pom_cli_list_controllers(FILE *out, int json);

#endif
