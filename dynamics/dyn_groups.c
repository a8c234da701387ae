/* dyn_groups.c - the config groups the dynamics model reads (docs/config.md),
 * from the list of pom_dyn_params_schema.h. */
#include "pom_dyn_params_schema.h"

#include <stddef.h>

/* What pom_dyn_params_load reads, in its order. */
#define GROUP_NAME(g) #g,
static const char *const param_groups[] = {POM_DYN_PARAM_GROUPS_LIST(GROUP_NAME) NULL};
#undef GROUP_NAME

const char *const *pom_dyn_param_groups(void) {
  return param_groups;
}
