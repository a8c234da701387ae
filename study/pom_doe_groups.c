/* pom_doe_groups.c - the config groups the doe library reads (docs/config.md).
 * Its own file, with no dependencies, so that the light pomlab can name every
 * top-level group without linking the study machinery. */
#include "pom_study.h"

#include <stddef.h>

/* ---- lists ---------------------------------------------------------------------- */
/* What pom_doe_study_load reads from a study file (mechanism groups belong in
 * the candidates' configs or in study.override). */
static const char *const study_groups[] = {"name",       "montecarlo", "study",
                                           "candidates", "uncertain",  NULL};
/* What pom_doe_maneuvers_load reads. */
static const char *const montecarlo_groups[] = {"montecarlo", NULL};
/* What pom_doe_sens_load reads (on top of the study's groups). */
static const char *const sens_groups[] = {"sensitivity", NULL};
/* What pom_grad_create reads beyond the models' and the Monte-Carlo's. */
static const char *const grad_groups[] = {"gradient", NULL};
/* What pom_tradeoff_load reads. */
static const char *const tradeoff_groups[] = {"tradeoff", NULL};

const char *const *pom_doe_study_groups(void) {
  return study_groups;
}
const char *const *pom_doe_montecarlo_groups(void) {
  return montecarlo_groups;
}
const char *const *pom_doe_sens_groups(void) {
  return sens_groups;
}
const char *const *pom_grad_groups(void) {
  return grad_groups;
}
const char *const *pom_tradeoff_groups(void) {
  return tradeoff_groups;
}
