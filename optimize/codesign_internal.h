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

/* The config keys design x of candidate c sets, their values (config units)
 * and d(value)/d(x_v) for every variable v (the size law's s^e and the
 * identity for a key variable): the chain rule from the sensitivity
 * engine's per-key derivatives (per config unit) to the design variables
 * (docs/optimize.md 11.5). Returns the number of keys (<= POM_CDS_MAX_VARS +
 * POM_CDS_MAX_SIZED_KEYS). */
#define POM_CDS_MAX_KEYS (POM_CDS_MAX_VARS + POM_CDS_MAX_SIZED_KEYS)
int pom_cds_design_keys(const pom_cds_candidate *cd, const double *x,
                        const char *key[POM_CDS_MAX_KEYS], double value[POM_CDS_MAX_KEYS],
                        double dvalue_dx[POM_CDS_MAX_KEYS][POM_CDS_MAX_VARS]);

/* dx_v/du_v of the unit-box map (linear or log10) at x_v. */
double pom_cds_dx_du(const pom_cds_var *v, double x);

#endif
