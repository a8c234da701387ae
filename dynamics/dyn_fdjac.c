/* dyn_fdjac.c - the finite-difference Jacobian both formulations use: the
 * CSC pattern of a model's dependency matrix, one RHS evaluation per column
 * colour (the parasitic path colours its sparse columns, the exact path gives
 * each mechanical and electrical column its own colour and leaves the
 * accumulator columns out), CVODE's linear-system callback writing
 * I - gamma J into a dense or CSC matrix, and the structural check
 * (docs/dynamics.md section 7). */
#include "dyn_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* ---- pattern ------------------------------------------------------------- */
pom_status pom_dyn_pattern_build(pom_dyn_model *m, pom_error *err) {
  const int n = m->n_states;
  long nnz = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (m->dep[(size_t)i * (size_t)n + (size_t)j] || i == j) ++nnz;
  m->nnz = nnz;
  m->colptr = calloc((size_t)n + 1, sizeof *m->colptr);
  m->rowind = calloc((size_t)nnz, sizeof *m->rowind);
  m->diag = calloc((size_t)n, sizeof *m->diag);
  if (!m->colptr || !m->rowind || !m->diag)
    POM_FAIL(err, POM_ERR_NOMEM, "allocating the Jacobian pattern (%ld entries)", nnz);
  long k = 0;
  for (int j = 0; j < n; ++j) {
    m->colptr[j] = k;
    for (int i = 0; i < n; ++i)
      if (m->dep[(size_t)i * (size_t)n + (size_t)j] || i == j) {
        if (i == j) m->diag[j] = k;
        m->rowind[k++] = i;
      }
  }
  m->colptr[n] = k;
  return POM_OK;
}

void pom_dyn_pattern_to_matrix(const pom_dyn_model *m, SUNMatrix A) {
  sunindextype *cp = SUNSparseMatrix_IndexPointers(A);
  sunindextype *ri = SUNSparseMatrix_IndexValues(A);
  for (int j = 0; j <= m->n_states; ++j)
    cp[j] = (sunindextype)m->colptr[j];
  for (long k = 0; k < m->nnz; ++k)
    ri[k] = m->rowind[k];
}

/* ---- finite-difference Jacobian ------------------------------------------ */
/* Columns of colour -1 are never perturbed: their entries (the diagonal
 * only, for the exact path's accumulators) keep the zero of data create. */
int pom_dyn_fd_jacobian(pom_dyn_data *d, const double *yv, const double *f0, double *yp,
                        double *fp) {
  const pom_dyn_model *m = d->m;
  const int n = m->n_states;
  const double srur = sqrt(2.220446049250313e-16); /* sqrt of the unit roundoff */
  ++d->jac_count;
  memcpy(yp, yv, (size_t)n * sizeof(double));
  for (int c = 0; c < m->n_colors; ++c) {
    for (int j = 0; j < n; ++j)
      if (m->color[j] == c) {
        double h = srur * fmax(fabs(yv[j]), m->scale[j]);
        volatile double yh = yv[j] + h; /* make h exactly representable */
        yp[j] = yh;
      }
    ++d->rhs_count;
    ++d->jac_rhs_count;
    int r = pom_dyn_eval(m, d, yp, fp);
    if (r != 0) return r;
    for (int j = 0; j < n; ++j) {
      if (m->color[j] != c) continue;
      double h = yp[j] - yv[j];
      for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
        int i = m->rowind[k];
        d->jac[k] = m->dep[(size_t)i * (size_t)n + (size_t)j] ? (fp[i] - f0[i]) / h : 0.0;
      }
      yp[j] = yv[j];
    }
  }
  return 0;
}

/* CVODE's linear-system callback: A = I - gamma J, J (the formulation's
 * analytic one or finite differences, by solver.jacobian) re-evaluated unless
 * CVODE says the stored one is still good (jok). Writing A directly skips
 * SUNDIALS' copy of a saved J and its scale-add-identity pass. */
int pom_dyn_cvode_linsys(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, sunbooleantype jok,
                         sunbooleantype *jcur, sunrealtype gamma, void *user_data, N_Vector tmp1,
                         N_Vector tmp2, N_Vector tmp3) {
  (void)tmp3;
  pom_dyn_data *d = user_data;
  const pom_dyn_model *m = d->m;
  const int n = m->n_states;
  d->t = t; /* the differenced evaluations at the Jacobian's time */
  if (!jok || !d->jac_valid) {
    int r = (m->form->jacobian && m->par.solver.jacobian == POM_JAC_ANALYTIC && m->ctrl_analytic)
                ? m->form->jacobian(m, d, N_VGetArrayPointer(y), d->jac)
                : pom_dyn_fd_jacobian(d, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                                      N_VGetArrayPointer(tmp1), N_VGetArrayPointer(tmp2));
    if (r != 0) return r;
    d->jac_valid = 1;
    *jcur = SUNTRUE;
  } else {
    *jcur = SUNFALSE;
  }
  if (SUNMatGetID(A) == SUNMATRIX_SPARSE) {
    /* the pattern is in A since data create (pom_dyn_pattern_to_matrix) */
    double *av = SUNSparseMatrix_Data(A);
    for (long k = 0; k < m->nnz; ++k)
      av[k] = -gamma * d->jac[k];
  } else {
    /* zeroed here: SUNMatZero of the distribution's unoptimized build cost
     * the exact path 7 % of its maneuver (bench/README.md, issue 9) */
    memset(SUNDenseMatrix_Data(A), 0, (size_t)n * (size_t)n * sizeof(double));
    for (int j = 0; j < n; ++j) {
      double *col = SUNDenseMatrix_Column(A, j);
      for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k)
        col[m->rowind[k]] = -gamma * d->jac[k];
    }
  }
  /* the identity: every diagonal entry is in the pattern */
  if (SUNMatGetID(A) == SUNMATRIX_SPARSE) {
    double *av = SUNSparseMatrix_Data(A);
    for (int j = 0; j < n; ++j)
      av[m->diag[j]] += 1.0;
  } else {
    for (int j = 0; j < n; ++j)
      SUNDenseMatrix_Column(A, j)[j] += 1.0;
  }
  return 0;
}

/* ---- structural check ---------------------------------------------------- */
double pom_dyn_structure_check(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *f0,
                               double *yp, double *fp, int *worst_i, int *worst_j) {
  const int n = m->n_states;
  const double srur = sqrt(2.220446049250313e-16);
  double worst = 0.0;
  *worst_i = *worst_j = -1;
  pom_dyn_eval(m, d, y, f0);
  memcpy(yp, y, (size_t)n * sizeof(double));
  for (int j = 0; j < n; ++j) {
    double h = srur * fmax(fabs(y[j]), m->scale[j]);
    yp[j] = y[j] + h;
    pom_dyn_eval(m, d, yp, fp);
    yp[j] = y[j];
    for (int i = 0; i < n; ++i) {
      if (m->dep[(size_t)i * (size_t)n + (size_t)j]) continue;
      int acc = 0;
      for (int a = 0; a < m->n_actuators; ++a)
        if (i >= m->act[a].acc_state && i < m->act[a].acc_state + DYN_ACC_PER_ACT) acc = 1;
      if (acc || i == m->acc_parasitic || i == j) continue;
      /* a derivative outside the pattern, relative to the row's scale / column's scale */
      double jij = fabs(fp[i] - f0[i]) / h * m->scale[j] / fmax(fabs(f0[i]), m->scale[i]);
      if (jij > worst) {
        worst = jij;
        *worst_i = i;
        *worst_j = j;
      }
    }
  }
  return worst;
}
