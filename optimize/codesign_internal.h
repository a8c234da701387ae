/* codesign_internal.h - helpers shared by the files of the co-design (not
 * public; docs/optimize.md section 11). */
#ifndef POM_CODESIGN_INTERNAL_H
#define POM_CODESIGN_INTERNAL_H

#include "pom_codesign.h"

/* Figures of n_designs designs (rows of POM_CDS_MAX_VARS doubles, config
 * units) on maneuvers 0..n-1 of seed, in parallel over the problem's
 * threads. A design the model refuses is infeasible (every maneuver
 * failed, kinematic margin 1), never an error. */
pom_status pom_cds_evaluate_many(const pom_cds_problem *pb, int c, const double *xs, int n_designs,
                                 uint64_t seed, long n, int parasitic, pom_cds_figures *figs,
                                 pom_error *err);

/* The regular dexterous workspace of design x by pom_kin_workspace (deg), at
 * the requirement's dexterity floor with every limit checked. */
pom_status pom_cds_rdw_deg(const pom_cds_problem *pb, int c, const double *x, double *deg,
                           pom_error *err);

#endif
