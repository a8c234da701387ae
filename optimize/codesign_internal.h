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

/* The same on maneuvers k0..k0+n-1 of seed (the same targets and draws as
 * in the whole set), plain runs, with every maneuver's sampled peak current
 * in peaks[n_designs][n] (NULL: not wanted): the per-maneuver current
 * constraints of docs/optimize.md 11.5 and their differences. */
pom_status pom_cds_evaluate_peaks(const pom_cds_problem *pb, int c, const double *xs, int n_designs,
                                  uint64_t seed, long k0, long n, pom_cds_figures *figs,
                                  double *peaks, pom_error *err);

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

/* The peak coil current of every maneuver of a sensitivity run (the
 * located maximum, docs/optimize.md 12.2) and its derivative per design
 * variable where defined (why: the reason where not). Arrays of n. */
typedef struct {
  double *value;                 /* A */
  double (*d)[POM_CDS_MAX_VARS]; /* A per config unit of x_v; 0 where undefined */
  int *defined;
  pom_dyn_grad_why *why;
} pom_cds_sens_peak;

/* The figures of every maneuver 0..n-1 of seed at design x by the
 * sensitivity engine (study/pom_grad.h; docs/optimize.md 11.5): the
 * design's figures in *fig (the same aggregation as a plain evaluation's,
 * the peak current the located maximum, >= the sampled one), the
 * pointing time t[k] (the horizon when unsettled), the energy e[k], and
 * their derivatives per design variable (config units) dt[k][v], de[k][v]
 * (an unsettled time has derivative 0), one sensitivity parameter per
 * design variable (the size variable's direction: the size law's tangent
 * over its keys); a variable with active[v] == 0 (active NULL: all are
 * active) gets a zero direction, costs nothing and has derivative 0. peak (always watched)
 * receives the peak currents and their derivatives, whose undefined ones do not unset *ok. *gr is
 * the caller's pom_grad (NULL the first time: created here and reused; the caller destroys it); one
 * per thread. *ok = 0 with the reason in why when a time or energy derivative is undefined (a
 * failed maneuver, a grazing or censored crossing, a design the engine refuses): the caller falls
 * back to differences. Errors: out of memory only. */
pom_status pom_cds_sens_maneuvers(const pom_cds_problem *pb, int c, const double *x,
                                  const int *active, uint64_t seed, long n, pom_grad **gr,
                                  double *t, double *e, double (*dt)[POM_CDS_MAX_VARS],
                                  double (*de)[POM_CDS_MAX_VARS], pom_cds_sens_peak *peak,
                                  pom_cds_figures *fig, int *ok, char *why, size_t why_cap,
                                  pom_error *err);

/* The figures of design x that need no simulation: kinematic margin,
 * envelope, the size law's current limit (in f; the rest untouched). */
void pom_cds_static_figures(const pom_cds_problem *pb, int c, const double *x, pom_cds_figures *f);

/* The check of docs/optimize.md 11.5 at one design: the smooth p95 q[0]
 * (s), the mean energy q[1] (J) and the current constraint q[2] = I_peak /
 * I_max(s) - 1 on the optimization set, their gradients g[0..2] in the unit
 * box (every variable free) by the problem's gradient source (pb->grad;
 * fd_step for the differences), the split current constraints of the first
 * n_man maneuvers man_q[k] = P_k / I_max(s) - 1 and their rows man_g[k]
 * (the sensitivity source: the located peak and its derivative; central
 * differences: the sampled peak, differenced) and where each row came from, the simulations spent
 * (of which with sensitivities) and the sensitivity path's counters (the pom_cds_point fields of
 * the same names; the current rows counted per maneuver). */
#define POM_CDS_CHECK_MANEUVERS 16
typedef struct {
  double q[3];
  double g[3][POM_CDS_MAX_VARS];
  int n_man;
  double man_q[POM_CDS_CHECK_MANEUVERS];
  double man_g[POM_CDS_CHECK_MANEUVERS][POM_CDS_MAX_VARS];
  int man_src[POM_CDS_CHECK_MANEUVERS]; /* 0 the peak's derivative, 1 differences, 2 held */
  long simulations, sens_runs;
  long fallbacks;      /* 1: the whole gradient fell back to differences (why) */
  long peak_rows;      /* maneuver rows from the peak current's derivative */
  long peak_fallbacks; /* maneuver rows by differences of that maneuver (peak_why) */
  long peak_held;      /* maneuver rows held (more than 20 % from active) */
  char why[160];
  char peak_why[160];
} pom_cds_grad_check;

pom_status pom_cds_gradient_at(const pom_cds_problem *pb, int c, const double *x,
                               pom_cds_grad_check *out, pom_error *err);

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
