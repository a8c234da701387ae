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

/* The figures of every maneuver 0..n-1 of seed at design x by the
 * sensitivity engine (study/pom_grad.h; docs/optimize.md 11.5): the
 * pointing time t[k] (the horizon when unsettled), the energy e[k], and
 * their derivatives per design variable (config units) dt[k][v], de[k][v]
 * (an unsettled time has derivative 0). *gr is the caller's pom_grad (NULL
 * the first time: created here and reused; the caller destroys it); one
 * per thread. *ok = 0 with the reason in why when a derivative is undefined
 * (a failed maneuver, a grazing or censored crossing, a design the engine
 * refuses): the caller falls back to differences. Errors: out of memory
 * only. */
pom_status pom_cds_sens_maneuvers(const pom_cds_problem *pb, int c, const double *x, uint64_t seed,
                                  long n, pom_grad **gr, double *t, double *e,
                                  double (*dt)[POM_CDS_MAX_VARS], double (*de)[POM_CDS_MAX_VARS],
                                  int *ok, char *why, size_t why_cap, pom_error *err);

/* The figures of design x that need no simulation: kinematic margin,
 * envelope, the size law's current limit (in f; the rest untouched). */
void pom_cds_static_figures(const pom_cds_problem *pb, int c, const double *x, pom_cds_figures *f);

/* The smooth p95 q[0] (s) and mean energy q[1] (J) of design x (config
 * units, every variable free) on the optimization set, and their gradients
 * in the unit box g[0], g[1] by the problem's gradient source (pb->grad;
 * fd_step for the differences); *fallbacks = 1 when the sensitivity path
 * fell back to differences, why says why. The check of docs/optimize.md 11.5. */
pom_status pom_cds_gradient_at(const pom_cds_problem *pb, int c, const double *x, double q[2],
                               double g[2][POM_CDS_MAX_VARS], long *fallbacks, char why[160],
                               pom_error *err);

/* Why design x (figures f, optimization set) misses the requirement set, in
 * words: the workspace term that sets the kinematic margin (pose, stroke,
 * limit or dexterity floor), the current, envelope, failures, time bound. */
void pom_cds_infeasible_reason(const pom_cds_problem *pb, int c, const double *x,
                               const pom_cds_figures *f, char *why, size_t cap);

/* Axis bounds for the figure: nice numbers around the data range [lo, hi]
 * (display units) with a margin of 5 % of the range each side, a tick step
 * of 1, 2, 2.5 or 5 x 10^k giving 4..8 intervals, *a and *b multiples of
 * the step that hold the data; nonneg = 1 for a quantity that is never
 * negative (a time, an energy): *a is then >= 0. A range of zero width is
 * widened by 10 % of |lo| (or 1). *decimals: the digits after the point
 * that print every tick exactly. */
void pom_cds_axis_range(double lo, double hi, int nonneg, double *a, double *b, double *step,
                        int *decimals);

#endif
