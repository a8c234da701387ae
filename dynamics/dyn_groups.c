/* dyn_groups.c - the config groups the dynamics model reads (docs/config.md). */
#include "pom_dynamics.h"

#include <stddef.h>

/* What pom_dyn_params_load reads (dyn_params.c); one line per group. */
static const char *const param_groups[] = {"actuator", "controller", "joints", "scene",
                                           "solver",   "maneuver",   NULL};

const char *const *pom_dyn_param_groups(void) {
  return param_groups;
}
