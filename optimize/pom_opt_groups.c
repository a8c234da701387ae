/* pom_opt_groups.c - the config groups the optimize library reads
 * (docs/config.md, docs/optimize.md). Its own file, with no dependencies, so
 * that the light pomlab can name every top-level group without linking the
 * optimizers. */
#include "pom_synth.h"
#include "pom_tune.h"

#include <stddef.h>

/* ---- lists ---------------------------------------------------------------------- */
static const char *const synth_groups[] = {"synthesis", NULL}; /* pom_syn_load */
static const char *const tune_groups[] = {"tuning", NULL};     /* pom_tune_load */

const char *const *pom_syn_groups(void) {
  return synth_groups;
}
const char *const *pom_tune_groups(void) {
  return tune_groups;
}
