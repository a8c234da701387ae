/* pom_rsm.h - full quadratic response surfaces fitted by least squares (GSL),
 * with the statistics of response-surface methodology: standard errors,
 * R^2, adjusted R^2, predicted R^2 (PRESS from the hat matrix), lack of fit
 * from replicated runs, an ANOVA table and a check on held-out points
 * (derivations: docs/optimize.md, section 2).
 *
 * Models are fitted in coded units u (the design's coordinates):
 * y = b0 + sum_i b_i u_i + sum_i b_ii u_i^2 + sum_{i<j} b_ij u_i u_j. */
#ifndef POM_RSM_H
#define POM_RSM_H

#include "pom_status.h"

#define POM_RSM_MAX_K     8                                               /* factors */
#define POM_RSM_MAX_TERMS ((POM_RSM_MAX_K + 1) * (POM_RSM_MAX_K + 2) / 2) /* 45 */

/* Rows of the ANOVA table. */
typedef enum {
  POM_RSM_ROW_MODEL = 0,       /* all terms but the intercept */
  POM_RSM_ROW_LINEAR = 1,      /* b_i, given the intercept (sequential SS) */
  POM_RSM_ROW_SQUARE = 2,      /* b_ii, given intercept and linear terms */
  POM_RSM_ROW_INTERACTION = 3, /* b_ij, given all other terms */
  POM_RSM_ROW_RESIDUAL = 4,
  POM_RSM_ROW_LACK_OF_FIT = 5, /* only when has_lack_of_fit */
  POM_RSM_ROW_PURE_ERROR = 6,  /* only when has_lack_of_fit */
  POM_RSM_ROW_TOTAL = 7,       /* corrected total */
  POM_RSM_N_ROWS = 8
} pom_rsm_row;

typedef struct {
  double ss;    /* sum of squares (response unit^2) */
  double df;    /* degrees of freedom */
  double ms;    /* mean square ss / df (NaN for the total row) */
  double f;     /* F = ms / ms_residual (ms_lof / ms_pure_error for lack of fit); NaN where none */
  double p;     /* upper-tail probability of f; NaN where none */
  double floor; /* as a denominator: mean squares at or below this count as zero (F, p NaN) */
} pom_rsm_anova_row;

/* Options of a fit. */
typedef struct {
  double replicate_tol; /* coded distance under which two runs count as replicates (default 1e-9) */
  double confidence;    /* level of the coefficient intervals (default 0.95) */
  double min_rcond;     /* smallest reciprocal condition number of X^T X accepted (default 1e-12) */
  double pure_error_rel_tol; /* pure error below this fraction of SST is zero (deterministic
                                responses; no lack-of-fit test) (default 1e-12) */
  double leverage_tol; /* runs with 1 - h_ii below this are interpolated: PRESS undefined (default
                          1e-10) */
} pom_rsm_options;

/* A fitted surface and its statistics. Term order: intercept, u_1..u_k,
 * u_1^2..u_k^2, then u_i u_j for i < j in row order (u1u2, u1u3, ..., u2u3, ...). */
typedef struct {
  int k;                             /* factors */
  int p;                             /* terms (k+1)(k+2)/2 */
  int n;                             /* runs fitted */
  double beta[POM_RSM_MAX_TERMS];    /* coefficients (response unit per coded unit^order) */
  double se[POM_RSM_MAX_TERMS];      /* standard errors of beta */
  double t[POM_RSM_MAX_TERMS];       /* beta / se */
  double p_value[POM_RSM_MAX_TERMS]; /* two-sided p of t with df_residual */
  double ci_half[POM_RSM_MAX_TERMS]; /* half-width of the `confidence` interval */
  double cov_unscaled[POM_RSM_MAX_TERMS * POM_RSM_MAX_TERMS]; /* (X^T X)^-1, [p * p] */
  double sigma;               /* residual standard deviation s (response unit) */
  double df_residual;         /* n - p */
  double r2, r2_adj, r2_pred; /* R^2, adjusted R^2, predicted R^2 = 1 - PRESS / SST */
  double press;               /* prediction error sum of squares */
  double max_leverage;        /* largest hat-matrix diagonal */
  int has_lack_of_fit;        /* 1 when replicates leave df for pure error and lack of fit */
  int n_distinct;             /* distinct design points */
  pom_rsm_anova_row anova[POM_RSM_N_ROWS];
} pom_rsm_fit;

/* Validation of a fit on points it did not see. */
typedef struct {
  int n;            /* points */
  double rmse;      /* root mean square of y - y_hat */
  double max_abs;   /* largest |y - y_hat| */
  double r2;        /* 1 - SS(y - y_hat) / SS(y - mean y); NaN for n < 2 or constant y */
  double within_pi; /* fraction of points inside the `confidence` prediction interval */
} pom_rsm_check;

void pom_rsm_defaults(pom_rsm_options *opts);

/* Number of terms of the full quadratic in k factors. */
int pom_rsm_terms(int k);

/* Values of the p model terms at coded point u[k] into row[p]. */
void pom_rsm_row_terms(int k, const double u[], double row[]);

/* Short name of term j ("1", "x2", "x1^2", "x1*x3") into buf. */
void pom_rsm_term_name(int k, int j, char *buf, unsigned cap);

/* Fits y[n] at coded points u[n * k]. Requires n > p and a full-rank model
 * (POM_ERR_ARG otherwise, naming the problem); non-finite data are
 * POM_ERR_NONFINITE. opts may be NULL (defaults). */
pom_status pom_rsm_fit_quadratic(pom_rsm_fit *fit, int k, int n, const double u[], const double y[],
                                 const pom_rsm_options *opts, pom_error *err);

/* Prediction at coded point u[k]; *se_mean (may be NULL) receives the
 * standard error of the mean prediction, s sqrt(x^T (X^T X)^-1 x). */
double pom_rsm_predict(const pom_rsm_fit *fit, const double u[], double *se_mean);

/* Why the fit has no lack-of-fit p value, for the reader: "no replicates"
 * when no two runs coincide (no pure-error degrees of freedom), "no distinct
 * runs beyond the terms" when the distinct runs leave none for lack of fit,
 * "zero pure error" when the replicates agree to round-off (a deterministic
 * experiment, docs/optimize.md 2.4). NULL when the test applies
 * (anova[POM_RSM_ROW_LACK_OF_FIT].p is finite). Static strings. */
const char *pom_rsm_lack_of_fit_note(const pom_rsm_fit *fit);

/* Compares the fit with n held-out runs (u[n * k], y[n]). */
void pom_rsm_validate(const pom_rsm_fit *fit, int n, const double u[], const double y[],
                      double confidence, pom_rsm_check *out);

#endif
