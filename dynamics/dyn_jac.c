/* dyn_jac.c - sparsity structure of the model's Jacobian and its
 * finite-difference evaluation with column colouring (Curtis-Powell-Reid):
 * a joint couples only its two bodies, so columns whose rows do not overlap
 * are perturbed together (docs/dynamics.md section 7). Fills a dense or a
 * CSC sparse SUNMatrix. */
#include "dyn_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* ---- structure ----------------------------------------------------------- */
/* Entity of a state: body slot (0..nb-1), actuator nb + a, or -1 for an
 * energy accumulator (rows left out of the Jacobian, see docs). */
static int state_entity(const pom_dyn_model *m, int i) {
  if (i < m->n_bodies * m->body_states) return i / m->body_states;
  for (int a = 0; a < m->n_actuators; ++a)
    if (i == m->act[a].flux_state || i == m->act[a].int_state) return m->n_bodies + a;
  return -1;
}

pom_status pom_dyn_structure_build(pom_dyn_model *m, pom_error *err) {
  pom_status st = POM_OK;
  int n = m->n_states;
  int ne = m->n_bodies + m->n_actuators;
  unsigned char *adj = NULL, *used = NULL;
  adj = calloc((size_t)(ne * ne), 1);
  m->dep = calloc((size_t)n * (size_t)n, 1);
  m->color = calloc((size_t)n, sizeof *m->color);
  used = calloc((size_t)n * (size_t)n, 1);
  if (!adj || !m->dep || !m->color || !used)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "allocating the Jacobian structure (%d states)", n);

  /* entity adjacency: a joint couples its two bodies; an actuator couples
   * with the bodies of its joint */
  for (int e = 0; e < ne; ++e)
    adj[e * ne + e] = 1;
  for (int j = 0; j < m->n_joints; ++j) {
    const dyn_joint *jt = &m->joint[j];
    int s0 = jt->slot[0], s1 = jt->slot[1];
    if (s0 >= 0 && s1 >= 0) adj[s0 * ne + s1] = adj[s1 * ne + s0] = 1;
    if (jt->actuator >= 0) {
      int ea = m->n_bodies + jt->actuator;
      for (int s = 0; s < 2; ++s)
        if (jt->slot[s] >= 0) adj[jt->slot[s] * ne + ea] = adj[ea * ne + jt->slot[s]] = 1;
    }
  }
  long nnz = 0;
  for (int i = 0; i < n; ++i) {
    int ei = state_entity(m, i);
    for (int j = 0; j < n; ++j) {
      int ej = state_entity(m, j);
      unsigned char dij = (ei >= 0 && ej >= 0 && adj[ei * ne + ej]) ? 1 : 0;
      m->dep[(size_t)i * (size_t)n + (size_t)j] = dij;
      if (dij || i == j) ++nnz;
    }
  }
  m->nnz = nnz;

  /* greedy colouring of the columns: a colour's columns touch disjoint rows */
  m->n_colors = 0;
  for (int j = 0; j < n; ++j) {
    int c = 0;
    for (;; ++c) {
      if (c == m->n_colors) {
        ++m->n_colors;
        break;
      }
      int clash = 0;
      for (int i = 0; i < n && !clash; ++i)
        if (m->dep[(size_t)i * (size_t)n + (size_t)j] && used[(size_t)c * (size_t)n + (size_t)i])
          clash = 1;
      if (!clash) break;
    }
    m->color[j] = c;
    for (int i = 0; i < n; ++i)
      if (m->dep[(size_t)i * (size_t)n + (size_t)j]) used[(size_t)c * (size_t)n + (size_t)i] = 1;
  }
done:
  free(adj);
  free(used);
  return st;
}

/* ---- finite-difference Jacobian ------------------------------------------ */
int pom_dyn_cvode_jac(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *user_data,
                      N_Vector tmp1, N_Vector tmp2, N_Vector tmp3) {
  (void)t;
  (void)tmp3;
  pom_dyn_data *d = user_data;
  const pom_dyn_model *m = d->m;
  const int n = m->n_states;
  const double *yv = N_VGetArrayPointer(y);
  const double *f0 = N_VGetArrayPointer(fy);
  double *yp = N_VGetArrayPointer(tmp1);
  double *fp = N_VGetArrayPointer(tmp2);
  const double srur = sqrt(2.220446049250313e-16); /* sqrt of the unit roundoff */
  const int sparse = SUNMatGetID(J) == SUNMATRIX_SPARSE;
  ++d->jac_count;

  SUNMatZero(J);
  if (sparse) {
    /* CSC pattern: rebuilt every call because SUNMatZero clears it */
    sunindextype *cp = SUNSparseMatrix_IndexPointers(J);
    sunindextype *ri = SUNSparseMatrix_IndexValues(J);
    sunindextype k = 0;
    for (int j = 0; j < n; ++j) {
      cp[j] = k;
      for (int i = 0; i < n; ++i)
        if (m->dep[(size_t)i * (size_t)n + (size_t)j] || i == j) ri[k++] = i;
    }
    cp[n] = k;
  }
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
      if (sparse) {
        sunindextype *cp = SUNSparseMatrix_IndexPointers(J);
        sunindextype *ri = SUNSparseMatrix_IndexValues(J);
        double *dv = SUNSparseMatrix_Data(J);
        for (sunindextype k = cp[j]; k < cp[j + 1]; ++k) {
          int i = (int)ri[k];
          dv[k] = m->dep[(size_t)i * (size_t)n + (size_t)j] ? (fp[i] - f0[i]) / h : 0.0;
        }
      } else {
        double *col = SUNDenseMatrix_Column(J, j);
        for (int i = 0; i < n; ++i)
          if (m->dep[(size_t)i * (size_t)n + (size_t)j]) col[i] = (fp[i] - f0[i]) / h;
      }
      yp[j] = yv[j];
    }
  }
  return 0;
}
