/* cli_dyn.h - printing of the dynamics parameter groups (actuator,
 * controller, joints, scene, solver, maneuver) for `pomlab model`. */
#ifndef POM_CLI_DYN_H
#define POM_CLI_DYN_H

#include "pom_dynamics.h"

#include <stdio.h>

/* The config groups the dynamics parameters come from (NULL-terminated). */
extern const char *const pom_cli_dyn_groups[];

/* Prints ",\n  \"actuator\": {...}, ..." (JSON members, SI units) to out. */
void pom_cli_dyn_params_json(FILE *out, const pom_dyn_params *p);

/* Prints the groups as human-readable lines to out. */
void pom_cli_dyn_params_text(FILE *out, const pom_dyn_params *p);

#endif
