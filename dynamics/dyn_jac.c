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
enum { KIND_U, KIND_P, KIND_H, KIND_ORI, KIND_FLUX, KIND_INT, KIND_ACC };

/* Entity (body slot 0..nb-1, actuator nb + a, -1 for an accumulator) and
 * kind of state i. */
static int state_entity(const pom_dyn_model *m, int i, int *kind) {
  if (i < m->n_bodies * m->body_states) {
    int r = i % m->body_states;
    *kind = r < DYN_BODY_P     ? KIND_U
            : r < DYN_BODY_H   ? KIND_P
            : r < DYN_BODY_ORI ? KIND_H
                               : KIND_ORI;
    return i / m->body_states;
  }
  for (int a = 0; a < m->n_actuators; ++a) {
    if (i == m->act[a].flux_state) {
      *kind = KIND_FLUX;
      return m->n_bodies + a;
    }
    if (i == m->act[a].int_state) {
      *kind = KIND_INT;
      return m->n_bodies + a;
    }
  }
  *kind = KIND_ACC;
  return -1;
}

/* Does the derivative of a state of kind ki on entity ei depend on a state of
 * kind kj on entity ej? (adjacent = same entity or coupled by a joint or an
 * actuator; docs/dynamics.md section 7) */
static int depends(int ki, int ei, int kj, int ej, int adjacent) {
  int same = ei == ej;
  int body_col = kj <= KIND_ORI;
  switch (ki) {
  case KIND_U: /* u_dot = p / m */
    return same && kj == KIND_P;
  case KIND_ORI: /* orientation rate from its own orientation and h' */
    return same && (kj == KIND_ORI || kj == KIND_H);
  case KIND_P:
  case KIND_H: /* efforts of joints and actuators on the EJS */
    return adjacent && (body_col || kj == KIND_FLUX || kj == KIND_INT);
  case KIND_FLUX: /* coil: u(e, z, q_dot), back-emf, its own flux */
    return adjacent && (body_col || kj == KIND_FLUX || kj == KIND_INT);
  case KIND_INT: /* z_dot = e = target - q(u, orientation) */
    return adjacent && !same && (kj == KIND_U || kj == KIND_ORI);
  default: /* accumulators: rows left out (they never feed back) */
    return 0;
  }
}

pom_status pom_dyn_structure_build(pom_dyn_model *m, pom_error *err) {
  pom_status st = POM_OK;
  int n = m->n_states;
  int ne = m->n_bodies + m->n_actuators;
  unsigned char *adj = NULL, *used = NULL;
  int *ent = NULL, *kind = NULL, *order = NULL, *rows = NULL;
  adj = calloc((size_t)(ne * ne), 1);
  m->dep = calloc((size_t)n * (size_t)n, 1);
  m->color = calloc((size_t)n, sizeof *m->color);
  used = calloc((size_t)n * (size_t)n, 1);
  ent = calloc((size_t)n, sizeof *ent);
  kind = calloc((size_t)n, sizeof *kind);
  order = calloc((size_t)n, sizeof *order);
  rows = calloc((size_t)n, sizeof *rows);
  if (!adj || !m->dep || !m->color || !used || !ent || !kind || !order || !rows)
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
  for (int i = 0; i < n; ++i)
    ent[i] = state_entity(m, i, &kind[i]);
  long nnz = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      int a = ent[i] >= 0 && ent[j] >= 0 && adj[ent[i] * ne + ent[j]];
      unsigned char dij = (unsigned char)(a ? depends(kind[i], ent[i], kind[j], ent[j], 1) : 0);
      m->dep[(size_t)i * (size_t)n + (size_t)j] = dij;
      if (dij || i == j) ++nnz;
    }
  }
  m->nnz = nnz;
  m->colptr = calloc((size_t)n + 1, sizeof *m->colptr);
  m->rowind = calloc((size_t)nnz, sizeof *m->rowind);
  m->diag = calloc((size_t)n, sizeof *m->diag);
  if (!m->colptr || !m->rowind || !m->diag)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "allocating the Jacobian pattern (%ld entries)", nnz);
  {
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
  }

  /* greedy colouring of the columns: a colour's columns touch disjoint rows.
   * Columns are visited by decreasing row count (largest first), which puts
   * the most coupled bodies (the platform and its links) first: 48 colours
   * for the shipped mechanisms against 60 in state order. */
  m->n_colors = 0;
  for (int j = 0; j < n; ++j) {
    order[j] = j;
    rows[j] = 0;
    for (int i = 0; i < n; ++i)
      rows[j] += m->dep[(size_t)i * (size_t)n + (size_t)j];
  }
  for (int a = 1; a < n; ++a) /* insertion sort, stable, by decreasing rows */
    for (int b = a; b > 0 && rows[order[b]] > rows[order[b - 1]]; --b) {
      int t = order[b];
      order[b] = order[b - 1];
      order[b - 1] = t;
    }
  for (int jj = 0; jj < n; ++jj) {
    int j = order[jj];
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
  free(ent);
  free(order);
  free(rows);
  free(kind);
  return st;
}

/* ---- finite-difference Jacobian ------------------------------------------ */
/* J (CSC values over the model's pattern, into d->jac) by one RHS evaluation
 * per colour at y, f0 = f(y); yp, fp scratch of n_states. */
static int jacobian_eval(pom_dyn_data *d, const double *yv, const double *f0, double *yp,
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

/* CVODE's linear-system callback: A = I - gamma J, J re-evaluated unless
 * CVODE says the stored one is still good (jok). Writing A directly skips
 * SUNDIALS' copy of a saved J and its scale-add-identity pass. */
int pom_dyn_cvode_linsys(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, sunbooleantype jok,
                         sunbooleantype *jcur, sunrealtype gamma, void *user_data, N_Vector tmp1,
                         N_Vector tmp2, N_Vector tmp3) {
  (void)t;
  (void)tmp3;
  pom_dyn_data *d = user_data;
  const pom_dyn_model *m = d->m;
  const int n = m->n_states;
  if (!jok || !d->jac_valid) {
    int r = jacobian_eval(d, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                          N_VGetArrayPointer(tmp1), N_VGetArrayPointer(tmp2));
    if (r != 0) return r;
    d->jac_valid = 1;
    *jcur = SUNTRUE;
  } else {
    *jcur = SUNFALSE;
  }
  if (SUNMatGetID(A) == SUNMATRIX_SPARSE) {
    sunindextype *cp = SUNSparseMatrix_IndexPointers(A);
    sunindextype *ri = SUNSparseMatrix_IndexValues(A);
    double *av = SUNSparseMatrix_Data(A);
    for (int j = 0; j <= n; ++j)
      cp[j] = (sunindextype)m->colptr[j];
    for (long k = 0; k < m->nnz; ++k) {
      ri[k] = m->rowind[k];
      av[k] = -gamma * d->jac[k];
    }
  } else {
    SUNMatZero(A);
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
