/* dyn_structured_ls.c - the parasitic path's structured Newton solve
 * (solver.linear_solver = "structured", docs/dynamics.md section 7,
 * "Structured Newton solve"): a block LU of A = I - gamma J over the groups
 * of the bond graph, with dense blocks and a fixed elimination order. Per
 * body: its displacement u (3), orientation (3 or 4) and the pair (p, h')
 * (6); per actuator its coil flux and controller states; each remaining
 * state (the energy accumulators) alone. The u and orientation groups go
 * first (pivots I and I - gamma de_dot/de), then the rest by minimum degree
 * on the group graph; pivoting is partial inside each diagonal block. The
 * block structure with its fill, the order and the map from the CSC entries
 * of A to the blocks are built once per worker; setup and solve allocate
 * nothing. */
#include "dyn_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* The small-block loops ask GCC to unroll them (blocks are 3-7 wide); clang
 * reads the same pragma as a requirement and warns (an error under -Werror)
 * where it cannot fulfil it: a request, not a requirement, here. */
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

/* Groups are runs of consecutive states; group k (in elimination order)
 * starts at state g0[k] and has gs[k] states. Its factors: the diagonal
 * block (gs x gs, column-major: unit L below, U on and above the diagonal),
 * the L panel (the blocks L_Ik, I > k, stacked: one row of gs[k] values per
 * state of the I, row-major) and the U panel (the blocks U_kJ, J > k, side
 * by side: one column of gs[k] values per state of the J). */
typedef struct {
  int n;     /* states */
  int ng;    /* groups */
  int *g0;   /* [ng] first state of each group */
  int *gs;   /* [ng] its size */
  long *dg;  /* [ng] value index of its diagonal block */
  long *lp;  /* [ng] value index of its L panel */
  long *up;  /* [ng] value index of its U panel */
  int *rb;   /* [ng + 1] L panel rows: the states lrow[rb[k] .. rb[k + 1]) */
  int *lrow; /* [rb[ng]] */
  int *cb;   /* [ng + 1] U panel columns: the states ucol[cb[k] .. cb[k + 1]) */
  int *ucol; /* [cb[ng]] */
  /* per group k: the I > k of its L panel and the J > k of its U panel */
  int *lb, *lower; /* [ng + 1], [..] */
  int *ub, *upper; /* [ng + 1], [..] */
  /* block (I, J): element (i, j) at val[blk + i * rs + j * cs], blk -1 for
   * a zero block ([ng * ng] each) */
  long *blk;
  int *rs, *cs;
  long n_val;
  double *val; /* [n_val] the blocks of A, overwritten by its factors */
  long nnz;
  long *pos; /* [nnz] value index of each CSC entry of A */
  long n_zero;
  long *zero; /* [n_zero] value indices that no entry of A writes (the fill) */
  int *piv;   /* [n] row interchange of each state inside its diagonal block */
  pom_dyn_sls_stats stats;
} structured_ls;

/* ---- kernels: the group sizes 1-4 and 6 as compile-time constants --------
 * (a body's u and orientation are 3 or 4 states, its (p, h') 6, an
 * actuator's 1-2, an accumulator 1): BY_SIZE calls KERNEL(s) with s a
 * constant in the common cases, so that the loops over s unroll. */
#define BY_SIZE(s, KERNEL)                                                                         \
  do {                                                                                             \
    switch (s) {                                                                                   \
    case 1:                                                                                        \
      KERNEL(1);                                                                                   \
      break;                                                                                       \
    case 2:                                                                                        \
      KERNEL(2);                                                                                   \
      break;                                                                                       \
    case 3:                                                                                        \
      KERNEL(3);                                                                                   \
      break;                                                                                       \
    case 4:                                                                                        \
      KERNEL(4);                                                                                   \
      break;                                                                                       \
    case 6:                                                                                        \
      KERNEL(6);                                                                                   \
      break;                                                                                       \
    default:                                                                                       \
      KERNEL(s);                                                                                   \
      break;                                                                                       \
    }                                                                                              \
  } while (0)

/* LU with partial pivoting of the s x s column-major block a, row
 * interchanges in piv; 1 when a pivot column is zero. */
static inline int block_lu(double *a, int s, int *piv) {
#pragma GCC unroll 8
  for (int k = 0; k < s; ++k) {
    int p = k;
    double big = fabs(a[k * s + k]);
#pragma GCC unroll 8
    for (int i = k + 1; i < s; ++i)
      if (fabs(a[k * s + i]) > big) {
        big = fabs(a[k * s + i]);
        p = i;
      }
    piv[k] = p;
    if (!(big > 0)) return 1;
    if (p != k)
#pragma GCC unroll 8
      for (int j = 0; j < s; ++j) {
        double t = a[j * s + k];
        a[j * s + k] = a[j * s + p];
        a[j * s + p] = t;
      }
    const double inv = 1.0 / a[k * s + k];
#pragma GCC unroll 8
    for (int i = k + 1; i < s; ++i)
      a[k * s + i] *= inv;
#pragma GCC unroll 8
    for (int j = k + 1; j < s; ++j) {
      const double f = a[j * s + k];
#pragma GCC unroll 8
      for (int i = k + 1; i < s; ++i)
        a[j * s + i] -= f * a[k * s + i];
    }
  }
  return 0;
}

/* x[s] <- L^-1 P x with the factors of block_lu */
static inline void block_lower(const double *lu, int s, const int *piv, double *x) {
#pragma GCC unroll 8
  for (int k = 0; k < s; ++k) {
    const int p = piv[k];
    const double t = x[k];
    x[k] = x[p];
    x[p] = t;
  }
#pragma GCC unroll 8
  for (int k = 0; k < s; ++k) {
    const double xk = x[k];
#pragma GCC unroll 8
    for (int i = k + 1; i < s; ++i)
      x[i] -= lu[k * s + i] * xk;
  }
}

/* x[s] <- U^-1 x */
static inline void block_upper(const double *lu, int s, double *x) {
#pragma GCC unroll 8
  for (int k = s - 1; k >= 0; --k) {
    const double xk = x[k] / lu[k * s + k];
    x[k] = xk;
#pragma GCC unroll 8
    for (int i = 0; i < k; ++i)
      x[i] -= lu[k * s + i] * xk;
  }
}

/* The rows of an L panel (row-major, s values each) <- rows U^-1. */
static inline void panel_rows_by_uinv(double *lp, int nrow, const double *lu, int s) {
#pragma GCC unroll 8
  for (int i = 0; i < nrow; ++i) {
    double *x = lp + (long)i * s;
#pragma GCC unroll 8
    for (int col = 0; col < s; ++col) {
      double v = x[col];
#pragma GCC unroll 8
      for (int r = 0; r < col; ++r)
        v -= x[r] * lu[col * s + r];
      x[col] = v / lu[col * s + col];
    }
  }
}

/* Schur update of block (I, J): A_IJ -= L_Ik U_kJ, with L_Ik rows of s values
 * (row-major) and U_kJ columns of s values (column-major). */
static inline void schur_block(double *a, int rs, int cs, const double *l, int si, const double *u,
                               int sj, int s) {
  for (int j = 0; j < sj; ++j) {
    const double *uj = u + (long)j * s;
    double *aj = a + (long)j * cs;
    for (int i = 0; i < si; ++i) {
      const double *li = l + (long)i * s;
      double v = 0.0;
#pragma GCC unroll 8
      for (int r = 0; r < s; ++r)
        v += li[r] * uj[r];
      aj[(long)i * rs] -= v;
    }
  }
}

/* Forward step of group k: x[lrow[i]] -= L panel row i . y (y = x_k). */
static inline void panel_forward(double *x, const double *lp, const int *rows, int nrow,
                                 const double *yk, int s) {
  double y[8];
  const double *yy = yk;
  if (s <= 8) {
#pragma GCC unroll 8
    for (int r = 0; r < s; ++r)
      y[r] = yk[r];
    yy = y;
  }
  for (int i = 0; i < nrow; ++i) {
    const double *li = lp + (long)i * s;
    double v = 0.0;
#pragma GCC unroll 8
    for (int r = 0; r < s; ++r)
      v += li[r] * yy[r];
    x[rows[i]] -= v;
  }
}

/* Backward step of group k: x_k -= U panel x(ucol). */
static inline void panel_backward(double *xk, const double *up, const int *cols, int ncol,
                                  const double *x, int s) {
  double acc[8];
  double *a = s <= 8 ? acc : xk;
  if (s <= 8)
#pragma GCC unroll 8
    for (int r = 0; r < s; ++r)
      acc[r] = xk[r];
  for (int j = 0; j < ncol; ++j) {
    const double xj = x[cols[j]], *uj = up + (long)j * s;
#pragma GCC unroll 8
    for (int r = 0; r < s; ++r)
      a[r] -= uj[r] * xj;
  }
  if (s <= 8)
#pragma GCC unroll 8
    for (int r = 0; r < s; ++r)
      xk[r] = acc[r];
}

/* ---- setup and solve ------------------------------------------------------ */
static int sls_setup(SUNLinearSolver S, SUNMatrix A) {
  structured_ls *c = S->content;
  const int ng = c->ng;
  const double *av = SUNSparseMatrix_Data(A);
  double *val = c->val;
  for (long k = 0; k < c->n_zero; ++k)
    val[c->zero[k]] = 0.0;
  for (long k = 0; k < c->nnz; ++k)
    val[c->pos[k]] = av[k];
  for (int k = 0; k < ng; ++k) {
    const int sk = c->gs[k];
    double *d = val + c->dg[k], *lp = val + c->lp[k], *up = val + c->up[k];
    int *piv = c->piv + c->g0[k];
    const int nrow = c->rb[k + 1] - c->rb[k], ncol = c->cb[k + 1] - c->cb[k];
    int fail = 0;
#define FACTOR(sz)                                                                                 \
  fail = block_lu(d, sz, piv);                                                                     \
  if (!fail) {                                                                                     \
    for (int col = 0; col < ncol; ++col)                                                           \
      block_lower(d, sz, piv, up + (long)col * (sz));                                              \
    panel_rows_by_uinv(lp, nrow, d, sz);                                                           \
  }
    BY_SIZE(sk, FACTOR);
#undef FACTOR
    if (fail) return SUNLS_LUFACT_FAIL; /* recoverable: CVODE retries with a smaller step */
    /* Schur complement: A_IJ -= L_Ik U_kJ over the panels' block pairs */
    long roff = 0;
    for (int l = c->lb[k]; l < c->lb[k + 1]; ++l) {
      const int I = c->lower[l], si = c->gs[I];
      const double *lik = lp + roff * sk;
      long coff = 0;
      for (int u = c->ub[k]; u < c->ub[k + 1]; ++u) {
        const int J = c->upper[u], sj = c->gs[J];
        const size_t IJ = (size_t)I * (size_t)ng + (size_t)J;
        double *aij = val + c->blk[IJ];
        const double *ukj = up + coff * sk;
#define SCHUR(sz) schur_block(aij, c->rs[IJ], c->cs[IJ], lik, si, ukj, sj, sz)
        BY_SIZE(sk, SCHUR);
#undef SCHUR
        coff += sj;
      }
      roff += si;
    }
  }
  return SUNLS_SUCCESS;
}

static int sls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector xv, N_Vector bv, sunrealtype tol) {
  (void)A;
  (void)tol;
  const structured_ls *c = S->content;
  const int ng = c->ng;
  const double *val = c->val;
  double *x = N_VGetArrayPointer(xv);
  const double *b = N_VGetArrayPointer(bv);
  if (x != b) memcpy(x, b, (size_t)c->n * sizeof(double));
  /* L y = b: y_k = L_kk^-1 P_k x_k, then x_I -= L_Ik y_k over the L panel */
  for (int k = 0; k < ng; ++k) {
    const int sk = c->gs[k], nrow = c->rb[k + 1] - c->rb[k];
    double *xk = x + c->g0[k];
    const double *d = val + c->dg[k], *lp = val + c->lp[k];
    const int *piv = c->piv + c->g0[k], *rows = c->lrow + c->rb[k];
#define FORWARD(sz)                                                                                \
  block_lower(d, sz, piv, xk);                                                                     \
  panel_forward(x, lp, rows, nrow, xk, sz)
    BY_SIZE(sk, FORWARD);
#undef FORWARD
  }
  /* U x = y, groups in reverse: x_k -= U_k panel x, then U_kk^-1 */
  for (int k = ng - 1; k >= 0; --k) {
    const int sk = c->gs[k], ncol = c->cb[k + 1] - c->cb[k];
    double *xk = x + c->g0[k];
    const double *d = val + c->dg[k], *up = val + c->up[k];
    const int *cols = c->ucol + c->cb[k];
#define BACKWARD(sz)                                                                               \
  panel_backward(xk, up, cols, ncol, x, sz);                                                       \
  block_upper(d, sz, xk)
    BY_SIZE(sk, BACKWARD);
#undef BACKWARD
  }
  return SUNLS_SUCCESS;
}

/* ---- the SUNLinearSolver object ------------------------------------------ */
static SUNLinearSolver_Type sls_gettype(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID sls_getid(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_CUSTOM;
}

static void sls_content_free(structured_ls *c) {
  if (!c) return;
  void *all[] = {c->g0,    c->gs, c->dg,    c->lp,  c->up, c->rb, c->lrow, c->cb,  c->ucol, c->lb,
                 c->lower, c->ub, c->upper, c->blk, c->rs, c->cs, c->val,  c->pos, c->zero, c->piv};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k)
    free(all[k]);
  free(c);
}

static int sls_free(SUNLinearSolver S) {
  if (!S) return 0;
  sls_content_free(S->content);
  S->content = NULL;
  SUNLinSolFreeEmpty(S);
  return 0;
}

/* ---- structure ------------------------------------------------------------ */
/* Group of every state (grp[n]) in the model's order: per body u, (p, h')
 * and orientation, per actuator its flux and controller states (one group
 * when they are consecutive states), then one group per remaining state;
 * forced[g] = 1 for the groups eliminated first. Returns the number of
 * groups; every group is a run of consecutive states. */
static int state_groups(const pom_dyn_model *m, int *grp, unsigned char *forced) {
  const int n = m->n_states;
  int ng = 0;
  for (int i = 0; i < n; ++i)
    grp[i] = -1;
  for (int b = 0; b < m->n_bodies; ++b) {
    const int o = m->body[b].offset;
    const int gu = ng++, gph = ng++, ge = ng++;
    forced[gu] = forced[ge] = 1;
    forced[gph] = 0;
    for (int k = 0; k < m->body_states; ++k)
      grp[o + k] = k < DYN_BODY_P ? gu : k < DYN_BODY_ORI ? gph : ge;
  }
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_actuator *ac = &m->act[a];
    int g = -1, last = -2;
    if (ac->flux_state >= 0) {
      grp[ac->flux_state] = g = ng++;
      forced[g] = 0;
      last = ac->flux_state;
    }
    for (int k = 0; ac->ctrl_state >= 0 && k < m->ctrl->n_states; ++k) {
      const int i = ac->ctrl_state + k;
      if (i != last + 1) forced[g = ng++] = 0; /* not consecutive: a group of its own */
      grp[i] = g;
      last = i;
    }
  }
  for (int i = 0; i < n; ++i)
    if (grp[i] < 0) {
      forced[ng] = 0;
      grp[i] = ng++;
    }
  return ng;
}

#define AT(M, I, J) (M)[(size_t)(I) * (size_t)ng + (size_t)(J)]

/* Builds the elimination order, the block structure with its fill and the
 * map of A's entries. */
static pom_status sls_build(structured_ls *c, const pom_dyn_model *m, pom_error *err) {
  pom_status st = POM_OK;
  const int n = m->n_states;
  int *grp = calloc((size_t)n, sizeof *grp), *rank = NULL, *order = NULL, *size = NULL;
  int *first = NULL;
  unsigned char *forced = calloc((size_t)n, 1), *adj = NULL, *done = NULL, *hit = NULL;
  if (!grp || !forced) POM_FAIL_GOTO(err, POM_ERR_NOMEM, out, "structured solver: groups");
  const int ng = state_groups(m, grp, forced);
  c->n = n;
  c->ng = ng;
  c->nnz = m->nnz;
  adj = calloc((size_t)ng * (size_t)ng, 1);
  done = calloc((size_t)ng, 1);
  rank = calloc((size_t)ng, sizeof *rank);
  order = calloc((size_t)ng, sizeof *order);
  size = calloc((size_t)ng, sizeof *size);
  first = calloc((size_t)ng, sizeof *first);
  if (!adj || !done || !rank || !order || !size || !first)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, out, "structured solver: group graph");
  for (int i = n - 1; i >= 0; --i)
    ++size[grp[i]], first[grp[i]] = i;
  /* group pattern of A (unsymmetric: block (I, J) non-zero) */
  for (int j = 0; j < n; ++j)
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k)
      AT(adj, grp[m->rowind[k]], grp[j]) = 1;
  /* order: the forced groups first, in model order; then the group of least
   * degree (states of its uneliminated neighbours, by rows or columns),
   * the first in model order on a tie; fill as each group goes */
  int no = 0;
  for (int g = 0; g < ng; ++g)
    if (forced[g]) order[no++] = g;
  for (int step = 0; step < ng; ++step) {
    int k = step < no ? order[step] : -1;
    if (k < 0) {
      long best = -1;
      for (int g = 0; g < ng; ++g) {
        if (done[g]) continue;
        long deg = 0;
        for (int h = 0; h < ng; ++h)
          if (h != g && !done[h] && (AT(adj, g, h) || AT(adj, h, g))) deg += size[h];
        if (best < 0 || deg < best) best = deg, k = g;
      }
      order[step] = k;
    }
    done[k] = 1;
    for (int I = 0; I < ng; ++I) {
      if (done[I] || !AT(adj, I, k)) continue;
      for (int J = 0; J < ng; ++J)
        if (!done[J] && AT(adj, k, J)) AT(adj, I, J) = 1;
    }
  }
  for (int s = 0; s < ng; ++s)
    rank[order[s]] = s;

  /* groups in elimination order and their panels */
  c->g0 = calloc((size_t)ng, sizeof *c->g0);
  c->gs = calloc((size_t)ng, sizeof *c->gs);
  c->dg = calloc((size_t)ng, sizeof *c->dg);
  c->lp = calloc((size_t)ng, sizeof *c->lp);
  c->up = calloc((size_t)ng, sizeof *c->up);
  c->rb = calloc((size_t)ng + 1, sizeof *c->rb);
  c->cb = calloc((size_t)ng + 1, sizeof *c->cb);
  c->lb = calloc((size_t)ng + 1, sizeof *c->lb);
  c->ub = calloc((size_t)ng + 1, sizeof *c->ub);
  c->lower = calloc((size_t)ng * (size_t)ng, sizeof *c->lower);
  c->upper = calloc((size_t)ng * (size_t)ng, sizeof *c->upper);
  c->blk = malloc((size_t)ng * (size_t)ng * sizeof *c->blk);
  c->rs = calloc((size_t)ng * (size_t)ng, sizeof *c->rs);
  c->cs = calloc((size_t)ng * (size_t)ng, sizeof *c->cs);
  c->piv = calloc((size_t)n, sizeof *c->piv);
  c->pos = calloc((size_t)m->nnz + 1, sizeof *c->pos);
  if (!c->g0 || !c->gs || !c->dg || !c->lp || !c->up || !c->rb || !c->cb || !c->lb || !c->ub ||
      !c->lower || !c->upper || !c->blk || !c->rs || !c->cs || !c->piv || !c->pos)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, out, "structured solver: structure");
  for (int k = 0; k < ng; ++k)
    c->g0[k] = first[order[k]], c->gs[k] = size[order[k]];
  for (size_t k = 0; k < (size_t)ng * (size_t)ng; ++k)
    c->blk[k] = -1;
  int nl = 0, nu = 0;
  c->n_val = 0;
  for (int k = 0; k < ng; ++k) {
    const int sk = c->gs[k];
    c->lb[k] = nl;
    c->ub[k] = nu;
    int nrow = 0, ncol = 0;
    for (int I = k + 1; I < ng; ++I)
      if (AT(adj, order[I], order[k])) c->lower[nl++] = I, nrow += c->gs[I];
    for (int J = k + 1; J < ng; ++J)
      if (AT(adj, order[k], order[J])) c->upper[nu++] = J, ncol += c->gs[J];
    c->rb[k + 1] = c->rb[k] + nrow;
    c->cb[k + 1] = c->cb[k] + ncol;
    c->dg[k] = AT(c->blk, k, k) = c->n_val;
    AT(c->rs, k, k) = 1, AT(c->cs, k, k) = sk;
    c->n_val += (long)sk * sk;
    c->lp[k] = c->n_val;
    for (int l = c->lb[k]; l < nl; ++l) {
      const int I = c->lower[l];
      AT(c->blk, I, k) = c->n_val, AT(c->rs, I, k) = sk, AT(c->cs, I, k) = 1;
      c->n_val += (long)c->gs[I] * sk;
    }
    c->up[k] = c->n_val;
    for (int u = c->ub[k]; u < nu; ++u) {
      const int J = c->upper[u];
      AT(c->blk, k, J) = c->n_val, AT(c->rs, k, J) = 1, AT(c->cs, k, J) = sk;
      c->n_val += (long)sk * c->gs[J];
    }
  }
  c->lb[ng] = nl;
  c->ub[ng] = nu;
  c->lrow = calloc((size_t)c->rb[ng] + 1, sizeof *c->lrow);
  c->ucol = calloc((size_t)c->cb[ng] + 1, sizeof *c->ucol);
  c->val = calloc((size_t)c->n_val, sizeof *c->val);
  hit = calloc((size_t)c->n_val, 1);
  if (!c->lrow || !c->ucol || !c->val || !hit)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, out, "structured solver: blocks");
  for (int k = 0; k < ng; ++k) {
    int r = c->rb[k], q = c->cb[k];
    for (int l = c->lb[k]; l < c->lb[k + 1]; ++l)
      for (int s = 0; s < c->gs[c->lower[l]]; ++s)
        c->lrow[r++] = c->g0[c->lower[l]] + s;
    for (int u = c->ub[k]; u < c->ub[k + 1]; ++u)
      for (int s = 0; s < c->gs[c->upper[u]]; ++s)
        c->ucol[q++] = c->g0[c->upper[u]] + s;
  }
  /* where each CSC entry of A goes; the values it misses are zeroed at setup */
  for (int j = 0; j < n; ++j) {
    const int J = rank[grp[j]];
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
      const int i = m->rowind[k], I = rank[grp[i]];
      c->pos[k] = AT(c->blk, I, J) + (long)(i - c->g0[I]) * AT(c->rs, I, J) +
                  (long)(j - c->g0[J]) * AT(c->cs, I, J);
      hit[c->pos[k]] = 1;
    }
  }
  c->n_zero = 0;
  for (long v = 0; v < c->n_val; ++v)
    c->n_zero += !hit[v];
  c->zero = calloc((size_t)c->n_zero + 1, sizeof *c->zero);
  if (!c->zero) POM_FAIL_GOTO(err, POM_ERR_NOMEM, out, "structured solver: fill");
  c->n_zero = 0;
  for (long v = 0; v < c->n_val; ++v)
    if (!hit[v]) c->zero[c->n_zero++] = v;

  /* work of one setup and one solve (multiply-adds of the dense blocks) */
  c->stats = (pom_dyn_sls_stats){.groups = ng, .values = c->n_val};
  for (int k = 0; k < ng; ++k) {
    const double sk = c->gs[k], R = c->rb[k + 1] - c->rb[k], C = c->cb[k + 1] - c->cb[k];
    c->stats.blocks += 1 + (c->lb[k + 1] - c->lb[k]) + (c->ub[k + 1] - c->ub[k]);
    c->stats.setup_flops += 2.0 / 3.0 * sk * sk * sk + sk * sk * (R + C) + 2.0 * sk * R * C;
    c->stats.solve_flops += 2.0 * sk * sk + 2.0 * sk * (R + C);
  }
out:
  free(grp);
  free(forced);
  free(adj);
  free(done);
  free(rank);
  free(order);
  free(size);
  free(first);
  free(hit);
  return st;
}

pom_status pom_dyn_structured_ls_create(SUNLinearSolver *out, const pom_dyn_model *m,
                                        SUNContext ctx, pom_error *err) {
  *out = NULL;
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  structured_ls *c = calloc(1, sizeof *c);
  if (!S || !c) {
    free(c);
    if (S) SUNLinSolFreeEmpty(S);
    POM_FAIL(err, POM_ERR_NOMEM, "allocating the structured linear solver");
  }
  S->content = c;
  S->ops->gettype = sls_gettype;
  S->ops->getid = sls_getid;
  S->ops->setup = sls_setup;
  S->ops->solve = sls_solve;
  S->ops->free = sls_free;
  pom_status st = sls_build(c, m, err);
  if (st != POM_OK) {
    sls_free(S);
    return st;
  }
  *out = S;
  return POM_OK;
}

int pom_dyn_structured_ls_stats(SUNLinearSolver S, pom_dyn_sls_stats *stats) {
  if (!S || !S->ops || S->ops->setup != sls_setup) return 0;
  *stats = ((const structured_ls *)S->content)->stats;
  return 1;
}
