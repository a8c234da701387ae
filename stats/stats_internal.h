/* stats_internal.h - helpers shared by the files of stats/ (not public). */
#ifndef POM_STATS_INTERNAL_H
#define POM_STATS_INTERNAL_H

#include "pom_stats.h"

/* ---- effects (pom_doe_effects.c) ---- */
/* Main effects of the sweep factors and the Pareto front into rep (after
 * the ranking's common-maneuver means are set). */
pom_status pom_doe_effects_compute(pom_doe_report *rep, const pom_doe_study *study,
                                   const pom_doe_cell *cells, pom_error *err);

#endif
