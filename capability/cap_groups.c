/* cap_groups.c - the config group of capability/ (pom_cap_groups), its own
 * file so that a program checking config names alone links nothing else. */
#include "pom_capability.h"

static const char *const cap_groups[] = {"capability", NULL};

const char *const *pom_cap_groups(void) {
  return cap_groups;
}
