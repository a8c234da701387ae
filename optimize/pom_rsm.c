/* pom_rsm.c - quadratic response surfaces and their statistics
 * (docs/optimize.md, section 2). */
#include "pom_rsm.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void pom_rsm_defaults(pom_rsm_options *opts) {
  opts->replicate_tol = 1e-9;
  opts->confidence = 0.95;
  opts->min_rcond = 1e-12;
  opts->leverage_tol = 1e-10;
  opts->pure_error_rel_tol = 1e-12;
}

int pom_rsm_terms(int k) {
  return (k + 1) * (k + 2) / 2;
}

void pom_rsm_row_terms(int k, const double u[], double row[]) {
  int c = 0;
  row[c++] = 1.0;
  for (int i = 0; i < k; ++i)
    row[c++] = u[i];
  for (int i = 0; i < k; ++i)
    row[c++] = u[i] * u[i];
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j)
      row[c++] = u[i] * u[j];
}

void pom_rsm_term_name(int k, int j, char *buf, unsigned cap) {
  if (j == 0) {
    snprintf(buf, cap, "1");
  } else if (j <= k) {
    snprintf(buf, cap, "x%d", j);
  } else if (j <= 2 * k) {
    snprintf(buf, cap, "x%d^2", j - k);
  } else {
    int c = 2 * k + 1;
    for (int a = 0; a < k; ++a)
      for (int b = a + 1; b < k; ++b, ++c)
        if (c == j) {
          snprintf(buf, cap, "x%d*x%d", a + 1, b + 1);
          return;
        }
    snprintf(buf, cap, "?");
  }
}

/* x^T A x for the symmetric p x p matrix A (row-major). */
static double quad_form(int p, const double *A, const double *x) {
  double s = 0.0;
  for (int a = 0; a < p; ++a) {
    double r = 0.0;
    for (int b = 0; b < p; ++b)
      r += A[a * p + b] * x[b];
    s += x[a] * r;
  }
  return s;
}

/* Residual sum of squares of the least-squares fit on the first `cols`
 * columns of X (the nested sub-models of the ANOVA). */
static pom_status sub_sse(const gsl_matrix *X, const gsl_vector *y, size_t cols, double *sse,
                          pom_error *err) {
  pom_status st = POM_OK;
  size_t n = X->size1;
  gsl_multifit_linear_workspace *w = gsl_multifit_linear_alloc(n, cols);
  gsl_vector *c = gsl_vector_alloc(cols);
  gsl_matrix *cov = gsl_matrix_alloc(cols, cols);
  if (!w || !c || !cov) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "response surface: out of memory");
  gsl_matrix_const_view sub = gsl_matrix_const_submatrix(X, 0, 0, n, cols);
  int gs = gsl_multifit_linear(&sub.matrix, y, c, cov, sse, w);
  if (gs) POM_FAIL_GOTO(err, POM_ERR_GSL, done, "sub-model fit: %s", gsl_strerror(gs));
done:
  gsl_multifit_linear_free(w);
  gsl_vector_free(c);
  gsl_matrix_free(cov);
  return st;
}

static void set_row(pom_rsm_anova_row *r, double ss, double df) {
  /* Differences of nested residual sums can come out a few ulps negative when
     a group of terms explains nothing. */
  r->ss = ss < 0.0 ? 0.0 : ss;
  r->df = df;
  r->ms = df > 0 ? r->ss / df : NAN; /* of the clamped sum: never negative */
  r->f = NAN;
  r->p = NAN;
}

static void set_f(pom_rsm_anova_row *r, const pom_rsm_anova_row *denominator) {
  if (r->df > 0 && denominator->df > 0 && denominator->ms > denominator->floor) {
    r->f = r->ms / denominator->ms;
    r->p = gsl_cdf_fdist_Q(r->f, r->df, denominator->df);
  }
}

/* ---- fit ---------------------------------------------------------------- */
pom_status pom_rsm_fit_quadratic(pom_rsm_fit *fit, int k, int n, const double u[], const double y[],
                                 const pom_rsm_options *opts, pom_error *err) {
  pom_status st = POM_OK;
  pom_rsm_options def;
  if (!opts) {
    pom_rsm_defaults(&def);
    opts = &def;
  }
  if (k < 1 || k > POM_RSM_MAX_K)
    POM_FAIL(err, POM_ERR_ARG, "response surface: %d factors, expected 1..%d", k, POM_RSM_MAX_K);
  int p = pom_rsm_terms(k);
  if (n <= p)
    POM_FAIL(err, POM_ERR_ARG,
             "response surface: %d runs for %d quadratic terms in %d factors; need more runs than "
             "terms",
             n, p, k);
  if (!(opts->confidence > 0.0 && opts->confidence < 1.0))
    POM_FAIL(err, POM_ERR_ARG, "response surface: confidence %g outside (0, 1)", opts->confidence);
  for (int r = 0; r < n; ++r) {
    if (!isfinite(y[r]))
      POM_FAIL(err, POM_ERR_NONFINITE, "response surface: response of run %d is %g", r, y[r]);
    for (int j = 0; j < k; ++j)
      if (!isfinite(u[r * k + j]))
        POM_FAIL(err, POM_ERR_NONFINITE, "response surface: factor %d of run %d is %g", j + 1, r,
                 u[r * k + j]);
  }
  gsl_set_error_handler_off();

  memset(fit, 0, sizeof *fit);
  fit->k = k;
  fit->p = p;
  fit->n = n;
  size_t np = (size_t)p, nn = (size_t)n;
  gsl_matrix *X = gsl_matrix_alloc(nn, np);
  gsl_vector *yv = gsl_vector_alloc(nn);
  gsl_vector *c = gsl_vector_alloc(np);
  gsl_matrix *cov = gsl_matrix_alloc(np, np);
  gsl_matrix *xtx = gsl_matrix_alloc(np, np);
  gsl_multifit_linear_workspace *w = gsl_multifit_linear_alloc(nn, np);
  if (!X || !yv || !c || !cov || !xtx || !w)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "response surface: out of memory");

  double row[POM_RSM_MAX_TERMS];
  double ymean = 0.0;
  for (int r = 0; r < n; ++r) {
    pom_rsm_row_terms(k, u + r * k, row);
    for (int j = 0; j < p; ++j)
      gsl_matrix_set(X, (size_t)r, (size_t)j, row[j]);
    gsl_vector_set(yv, (size_t)r, y[r]);
    ymean += y[r];
  }
  ymean /= n;

  /* (X^T X)^-1 by Cholesky: the design must estimate every term. */
  gsl_blas_dgemm(CblasTrans, CblasNoTrans, 1.0, X, X, 0.0, xtx);
  if (gsl_linalg_cholesky_decomp1(xtx))
    POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                  "response surface: the %d runs cannot estimate all %d quadratic terms "
                  "(X^T X is singular; use a design with at least 3 levels per factor)",
                  n, p);
  double rcond = 0.0;
  gsl_vector *work3 = gsl_vector_alloc(3 * np);
  if (!work3) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "response surface: out of memory");
  gsl_linalg_cholesky_rcond(xtx, &rcond, work3);
  gsl_vector_free(work3);
  if (rcond < opts->min_rcond)
    POM_FAIL_GOTO(err, POM_ERR_ARG, done,
                  "response surface: X^T X nearly singular (reciprocal condition %.3g)", rcond);
  gsl_linalg_cholesky_invert(xtx);
  for (int a = 0; a < p; ++a)
    for (int b = 0; b < p; ++b)
      fit->cov_unscaled[a * p + b] = gsl_matrix_get(xtx, (size_t)a, (size_t)b);

  double sse = 0.0;
  int gs = gsl_multifit_linear(X, yv, c, cov, &sse, w);
  if (gs) POM_FAIL_GOTO(err, POM_ERR_GSL, done, "response surface fit: %s", gsl_strerror(gs));
  for (int j = 0; j < p; ++j)
    fit->beta[j] = gsl_vector_get(c, (size_t)j);

  /* Residuals, leverages and PRESS (docs/optimize.md 2.2). */
  double sst = 0.0, press = 0.0, hmax = 0.0;
  int press_ok = 1;
  for (int r = 0; r < n; ++r) {
    pom_rsm_row_terms(k, u + r * k, row);
    double yhat = 0.0;
    for (int j = 0; j < p; ++j)
      yhat += row[j] * fit->beta[j];
    double h = quad_form(p, fit->cov_unscaled, row);
    double e = y[r] - yhat;
    if (h > hmax) hmax = h;
    if (1.0 - h < opts->leverage_tol)
      press_ok = 0; /* a run the model interpolates exactly: PRESS undefined */
    else
      press += (e / (1.0 - h)) * (e / (1.0 - h));
    sst += (y[r] - ymean) * (y[r] - ymean);
  }
  fit->df_residual = (double)(n - p);
  fit->sigma = sqrt(sse / fit->df_residual);
  fit->max_leverage = hmax;
  fit->press = press_ok ? press : NAN;
  if (sst > 0.0) {
    fit->r2 = 1.0 - sse / sst;
    fit->r2_adj = 1.0 - (sse / fit->df_residual) / (sst / (double)(n - 1));
    fit->r2_pred = press_ok ? 1.0 - press / sst : NAN;
  } else {
    /* Constant response: the fit is exact and R^2 is undefined. */
    fit->r2 = fit->r2_adj = fit->r2_pred = NAN;
  }

  double tq = gsl_cdf_tdist_Qinv(0.5 * (1.0 - opts->confidence), fit->df_residual);
  for (int j = 0; j < p; ++j) {
    fit->se[j] = fit->sigma * sqrt(fit->cov_unscaled[j * p + j]);
    fit->t[j] = fit->se[j] > 0 ? fit->beta[j] / fit->se[j] : NAN;
    fit->p_value[j] =
        fit->se[j] > 0 ? 2.0 * gsl_cdf_tdist_Q(fabs(fit->t[j]), fit->df_residual) : NAN;
    fit->ci_half[j] = tq * fit->se[j];
  }

  /* ANOVA with sequential sums of squares of the nested models. */
  double sse_lin = 0.0, sse_sq = 0.0;
  POM_TRY_GOTO(sub_sse(X, yv, (size_t)(1 + k), &sse_lin, err), done);
  POM_TRY_GOTO(sub_sse(X, yv, (size_t)(1 + 2 * k), &sse_sq, err), done);
  pom_rsm_anova_row *A = fit->anova;
  set_row(&A[POM_RSM_ROW_MODEL], sst - sse, (double)(p - 1));
  set_row(&A[POM_RSM_ROW_LINEAR], sst - sse_lin, (double)k);
  set_row(&A[POM_RSM_ROW_SQUARE], sse_lin - sse_sq, (double)k);
  set_row(&A[POM_RSM_ROW_INTERACTION], sse_sq - sse, (double)(k * (k - 1) / 2));
  set_row(&A[POM_RSM_ROW_RESIDUAL], sse, fit->df_residual);
  set_row(&A[POM_RSM_ROW_TOTAL], sst, (double)(n - 1));
  A[POM_RSM_ROW_TOTAL].ms = NAN;
  for (int rr = POM_RSM_ROW_MODEL; rr <= POM_RSM_ROW_INTERACTION; ++rr)
    set_f(&A[rr], &A[POM_RSM_ROW_RESIDUAL]);

  /* Lack of fit: pure error from groups of replicated runs. */
  int *group = malloc(sizeof(int) * nn);
  if (!group) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "response surface: out of memory");
  int ng = 0;
  for (int r = 0; r < n; ++r) {
    group[r] = -1;
    for (int q = 0; q < r && group[r] < 0; ++q) {
      double d2 = 0.0;
      for (int j = 0; j < k; ++j)
        d2 += (u[r * k + j] - u[q * k + j]) * (u[r * k + j] - u[q * k + j]);
      if (d2 <= opts->replicate_tol * opts->replicate_tol) group[r] = group[q];
    }
    if (group[r] < 0) group[r] = ng++;
  }
  double sspe = 0.0;
  for (int g = 0; g < ng; ++g) {
    double m = 0.0;
    int cnt = 0;
    for (int r = 0; r < n; ++r)
      if (group[r] == g) {
        m += y[r];
        ++cnt;
      }
    m /= cnt;
    for (int r = 0; r < n; ++r)
      if (group[r] == g) sspe += (y[r] - m) * (y[r] - m);
  }
  free(group);
  fit->n_distinct = ng;
  int df_pe = n - ng, df_lof = ng - p;
  /* Replicates of a deterministic computer experiment agree to round-off:
     such a pure error is zero, and the lack-of-fit F test does not apply. */
  A[POM_RSM_ROW_PURE_ERROR].floor = opts->pure_error_rel_tol * sst / (df_pe > 0 ? df_pe : 1);
  fit->has_lack_of_fit = df_pe > 0 && df_lof > 0;
  if (fit->has_lack_of_fit) {
    set_row(&A[POM_RSM_ROW_PURE_ERROR], sspe, (double)df_pe);
    set_row(&A[POM_RSM_ROW_LACK_OF_FIT], sse - sspe, (double)df_lof);
    set_f(&A[POM_RSM_ROW_LACK_OF_FIT], &A[POM_RSM_ROW_PURE_ERROR]);
  } else {
    set_row(&A[POM_RSM_ROW_PURE_ERROR], NAN, (double)df_pe);
    set_row(&A[POM_RSM_ROW_LACK_OF_FIT], NAN, (double)df_lof);
  }

done:
  gsl_matrix_free(X);
  gsl_vector_free(yv);
  gsl_vector_free(c);
  gsl_matrix_free(cov);
  gsl_matrix_free(xtx);
  gsl_multifit_linear_free(w);
  return st;
}

const char *pom_rsm_lack_of_fit_note(const pom_rsm_fit *fit) {
  if (fit->has_lack_of_fit && isfinite(fit->anova[POM_RSM_ROW_LACK_OF_FIT].p)) return NULL;
  if (fit->n - fit->n_distinct <= 0) return "no replicates";
  if (fit->n_distinct - fit->p <= 0) return "no distinct runs beyond the terms";
  return "zero pure error";
}

/* ---- prediction and validation ------------------------------------------ */
double pom_rsm_predict(const pom_rsm_fit *fit, const double u[], double *se_mean) {
  double row[POM_RSM_MAX_TERMS];
  pom_rsm_row_terms(fit->k, u, row);
  double y = 0.0;
  for (int j = 0; j < fit->p; ++j)
    y += row[j] * fit->beta[j];
  if (se_mean) *se_mean = fit->sigma * sqrt(quad_form(fit->p, fit->cov_unscaled, row));
  return y;
}

void pom_rsm_validate(const pom_rsm_fit *fit, int n, const double u[], const double y[],
                      double confidence, pom_rsm_check *out) {
  memset(out, 0, sizeof *out);
  out->n = n;
  if (n < 1) {
    out->rmse = out->max_abs = out->r2 = out->within_pi = NAN;
    return;
  }
  double tq = gsl_cdf_tdist_Qinv(0.5 * (1.0 - confidence), fit->df_residual);
  double ss = 0.0, mean = 0.0, sst = 0.0;
  int inside = 0;
  for (int r = 0; r < n; ++r)
    mean += y[r];
  mean /= n;
  for (int r = 0; r < n; ++r) {
    double se = 0.0;
    double e = y[r] - pom_rsm_predict(fit, u + r * fit->k, &se);
    /* Prediction interval of a new observation: s^2 + se_mean^2. */
    double half = tq * sqrt(fit->sigma * fit->sigma + se * se);
    if (fabs(e) <= half) ++inside;
    ss += e * e;
    if (fabs(e) > out->max_abs) out->max_abs = fabs(e);
    sst += (y[r] - mean) * (y[r] - mean);
  }
  out->rmse = sqrt(ss / n);
  out->r2 = (n >= 2 && sst > 0.0) ? 1.0 - ss / sst : NAN;
  out->within_pi = (double)inside / n;
}
