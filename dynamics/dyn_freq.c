/* dyn_freq.c - the small-signal frequency response of the closed loop about
 * the equilibrium that holds a pose (docs/capability.md, "Small-signal
 * frequency response"; pom_dyn_freq.h): the equilibrium by Newton on
 * f(y, s) = 0, A = df/dy from the formulation's Jacobian, the input and
 * output maps, T(jw) through one Hessenberg reduction of A, the figures. */
#include "pom_dyn_freq.h"

#include "dyn_internal.h"
#include "pom_json.h"
#include "pom_math.h"

#include <complex.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The controller's clock at the equilibrium (s): a reference trajectory
 * (pid_feedforward) has long reached its setpoint. */
#define FREQ_T_EQ 1e6
/* Newton: at most this many steps; converged when the scaled step is below
 * FREQ_NEWTON_TOL (units of each state's characteristic scale). */
#define FREQ_NEWTON_MAX 40
#define FREQ_NEWTON_TOL 1e-9
/* Singular values of the scaled A below this fraction of the largest are
 * the idle (uncontrollable and unobservable) modes: free link spins, whose
 * singular values are rounding, ~1e-18 of the largest on the shipped
 * scenes. A real pole bounds the smallest singular value from above, and
 * the PID's integral pole K_I = 1e-3 1/s against the parasitic springs'
 * 1e10 1/s sits at ~1e-14: the cut lies between (docs/capability.md). */
#define FREQ_SV_TRUNC 1e-16
/* An idle mode is also unseen by every output: |C v| below this fraction
 * of |C| for its unit null vector v. */
#define FREQ_IDLE_UNSEEN 1e-8
/* Voltage step of the loop-breaking injection (V): f is affine in it. */
#define FREQ_DU 1e-3
/* Frequency grid of the searches (Hz), points per decade. */
#define FREQ_F_LO    1e-3
#define FREQ_F_HI    1e6
#define FREQ_PER_DEC 40
/* Relative width of the bisections in log f. */
#define FREQ_BISECT_TOL 1e-9
/* A parasitic mode lies above this multiple of the largest axis bandwidth. */
#define FREQ_MODE_ABOVE 3.0
/* ... and is underdamped: a complex pair below this damping ratio (a real
 * double pole splits into a pair of zeta 1 - O(eps^1/2) by rounding). */
#define FREQ_MODE_ZETA 0.99

#define NIO 6 /* inputs and outputs: 3 setpoint rotations, 3 loop injections */

/* ---- the linearization ---------------------------------------------------- */
typedef struct {
  int n;         /* kept states (the accumulators left out) */
  int n_act;     /* actuators (<= 3) */
  int *idx;      /* [n] model state index of each kept state */
  double *y;     /* [n_states] equilibrium */
  double *scale; /* [n] scale of each kept state */
  double *As;    /* [n * n] scaled A = D^-1 A D, row-major */
  double *Bs;    /* [n * NIO] scaled inputs D^-1 [B_rot | b_u], row-major */
  double *Cs;    /* [NIO * n] scaled outputs [C_rot; c_u] D, row-major */
  /* system 0: the closed loop A; system 1 + k: the loop of actuator k
   * broken at its input, A_k = A - b_k c_k^T (scaled) */
  int n_sys;              /* 1 + n_act */
  double *UB[4];          /* [n * NIO] U^T Bs (Hessenberg basis of each system) */
  double *CU[4];          /* [NIO * n] Cs U */
  double *H[4];           /* [n * n] Hessenberg form of each system's matrix, row-major */
  double complex *M;      /* [n * n] jw I - H */
  double complex *X;      /* [n * NIO] solutions */
  double T0[9];           /* T(0), setpoint rotation -> platform rotation */
  double T0inv[9];        /* its inverse */
  int modes_ok;           /* eigenvalues computed */
  int n_idle;             /* dimension of the idle modes' subspace left out of lambda */
  int n_lambda;           /* eigenvalues in lambda */
  double complex *lambda; /* [n] eigenvalues of A (1/s) */
  /* each system's response on the search grid, computed once: the searches
   * (bandwidths, peaks, margins) walk the same grid several times */
  double complex *grid_Y[4]; /* [grid points][NIO][NIO] */
  unsigned char *grid_ok[4]; /* [grid points] 0 not yet, 1 computed, 2 singular */
} freq_lin;

static void lin_free(freq_lin *L) {
  free(L->idx);
  free(L->y);
  free(L->scale);
  free(L->As);
  free(L->Bs);
  free(L->Cs);
  for (int k = 0; k < 4; ++k) {
    free(L->UB[k]);
    free(L->CU[k]);
    free(L->H[k]);
  }
  free(L->M);
  free(L->X);
  free(L->lambda);
  for (int k = 0; k < 4; ++k) {
    free(L->grid_Y[k]);
    free(L->grid_ok[k]);
  }
  memset(L, 0, sizeof *L);
}

static int is_accumulator(const pom_dyn_model *m, int i) {
  if (i == m->acc_parasitic) return 1;
  for (int a = 0; a < m->n_actuators; ++a)
    if (i >= m->act[a].acc_state && i < m->act[a].acc_state + DYN_ACC_PER_ACT) return 1;
  return 0;
}

/* The formulation's Jacobian at y into d->jac (f0 = f(y); yp, fp scratch):
 * the exact path's (analytic mechanical columns where the architecture and
 * controller allow), the parasitic analytic one, else differences. */
static int full_jacobian(const pom_dyn_model *m, pom_dyn_data *d, const double *y, const double *f0,
                         double *yp, double *fp) {
  if (m->form == &pom_dyn_form_exact) return pom_dyn_exact_jacobian(d, y, f0, yp, fp);
  if (m->form->jacobian && m->par.solver.jacobian == POM_JAC_ANALYTIC && m->ctrl_analytic)
    return m->form->jacobian(m, d, y, d->jac);
  return pom_dyn_fd_jacobian(d, y, f0, yp, fp);
}

/* Orientation states of the platform: first index and count. */
static void platform_ori(const pom_dyn_model *m, int *ori, int *n_ori) {
  int omega;
  if (!pom_dyn_exact_layout(m, ori, n_ori, &omega)) {
    *ori = m->body[m->platform_slot].offset + DYN_BODY_ORI;
    *n_ori = m->par.scene.orientation == POM_ORIENT_QUATERNION ? 4 : 3;
  }
}

static void set_orientation(double *o, int n_ori, const double R[9]) {
  if (n_ori == 4)
    pom_quat_from_matrix(o, R);
  else
    (void)pom_euler_zyx_from_matrix(o, R); /* singular pitch: still a decomposition */
}

/* The rigid pose of every body at platform rotation R as the initial guess. */
static pom_status initial_guess(const pom_dyn_model *m, const double R[9], double *y,
                                pom_error *err) {
  m->form->initial(m, y, NULL);
  int ori, n_ori;
  platform_ori(m, &ori, &n_ori);
  if (m->form == &pom_dyn_form_exact) {
    set_orientation(y + ori, n_ori, R);
    return POM_OK;
  }
  pom_kin_twists tw;
  POM_TRY(pom_kin_body_twists(&m->arch, R, NULL, &tw, err));
  for (int b = 0; b < m->n_bodies; ++b) {
    const dyn_body *bd = &m->body[b];
    const int k = bd->mech_index;
    if (k < 0 || k >= tw.n_bodies) continue;
    const pom_kin_body_twist *t = &tw.body[k];
    double *yb = y + bd->offset;
    set_orientation(yb + DYN_BODY_ORI, n_ori, t->R);
    if (bd->pinned) continue;
    double d0[3], r[3], x[3];
    pom_v3_sub(d0, bd->cm_home, t->ref_home);
    pom_m3_apply(r, t->R, d0);
    pom_v3_add(x, t->ref, r);
    pom_v3_sub(yb + DYN_BODY_U, x, bd->cm_home);
  }
  return POM_OK;
}

/* x = A^+ b for the n x n row-major A by its SVD, singular values below
 * FREQ_SV_TRUNC of the largest dropped (the idle modes); nb right-hand
 * sides b[n * nb] row-major, overwritten by x. Returns 0, or 1 on a GSL
 * failure. */
static int pinv_solve(const double *A, int n, double *b, int nb) {
  gsl_matrix *U = gsl_matrix_alloc((size_t)n, (size_t)n);
  gsl_matrix *V = gsl_matrix_alloc((size_t)n, (size_t)n);
  gsl_vector *S = gsl_vector_alloc((size_t)n), *w = gsl_vector_alloc((size_t)n);
  gsl_vector *t = gsl_vector_alloc((size_t)n);
  int bad = !U || !V || !S || !w || !t;
  if (!bad) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        gsl_matrix_set(U, (size_t)i, (size_t)j, A[i * n + j]);
    bad = gsl_linalg_SV_decomp(U, V, S, w) != GSL_SUCCESS;
  }
  if (!bad) {
    const double smax = gsl_vector_get(S, 0);
    for (int c = 0; c < nb; ++c) {
      for (int k = 0; k < n; ++k) { /* t = S^+ U^T b */
        double sk = gsl_vector_get(S, (size_t)k), acc = 0.0;
        for (int i = 0; i < n; ++i)
          acc += gsl_matrix_get(U, (size_t)i, (size_t)k) * b[i * nb + c];
        gsl_vector_set(t, (size_t)k, sk > FREQ_SV_TRUNC * smax ? acc / sk : 0.0);
      }
      for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int k = 0; k < n; ++k)
          acc += gsl_matrix_get(V, (size_t)i, (size_t)k) * gsl_vector_get(t, (size_t)k);
        b[i * nb + c] = acc;
      }
    }
  }
  gsl_matrix_free(U);
  gsl_matrix_free(V);
  gsl_vector_free(S);
  gsl_vector_free(w);
  gsl_vector_free(t);
  return bad;
}

/* The idle modes (docs/capability.md): a link that spins freely between two
 * spherical joints adds a Jordan chain of the eigenvalue 0, the spin angle
 * (a null vector of A: nothing depends on it) and its angular momentum
 * (A g = that null vector), which rounding splits into +-sqrt(eps |A|)
 * (~1e-4 1/s here: as small as the integral's pole). The chains span an
 * invariant subspace S = span(N, A^+ N), N the null space of the scaled A;
 * in an orthonormal basis [Q_S Q_P] A is block upper triangular and the
 * other poles are those of Q_P^T A Q_P. Returns that (m x m) matrix with
 * *n_idle = dim S, or A itself (*n_idle 0) when A has no null space or S
 * is not invariant to 1e-9 |A|; NULL when out of memory. */
static gsl_matrix *active_matrix(const double *As, const double *Cs, int n, int *m_out,
                                 int *n_idle) {
  gsl_matrix *U = gsl_matrix_alloc((size_t)n, (size_t)n),
             *V = gsl_matrix_alloc((size_t)n, (size_t)n);
  gsl_matrix *Sb = gsl_matrix_alloc((size_t)n, (size_t)(2 * n)), *Q = NULL, *out = NULL;
  gsl_vector *S = gsl_vector_alloc((size_t)n), *w = gsl_vector_alloc((size_t)n);
  gsl_vector *tq = gsl_vector_alloc((size_t)n);
  int k = 0;
  *n_idle = 0;
  if (!U || !V || !Sb || !S || !w || !tq) goto fallback;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      gsl_matrix_set(U, (size_t)i, (size_t)j, As[i * n + j]);
  if (gsl_linalg_SV_decomp(U, V, S, w) != GSL_SUCCESS) goto fallback;
  const double smax = gsl_vector_get(S, 0);
  int n0 = 0;
  for (int c = 0; c < n; ++c)
    if (!(gsl_vector_get(S, (size_t)c) > FREQ_SV_TRUNC * smax)) {
      /* null vector v and g = A^+ v: Gram-Schmidt into the basis Sb */
      double v[2][512];
      if (n > 512) goto fallback;
      for (int i = 0; i < n; ++i)
        v[0][i] = gsl_matrix_get(V, (size_t)i, (size_t)c);
      /* seen by an output (the platform, a controller): not idle */
      double cv = 0.0, cn = 0.0;
      for (int r = 0; r < NIO; ++r) {
        double acc = 0.0;
        for (int i = 0; i < n; ++i) {
          acc += Cs[r * n + i] * v[0][i];
          cn += Cs[r * n + i] * Cs[r * n + i];
        }
        cv = fmax(cv, fabs(acc));
      }
      if (cv > FREQ_IDLE_UNSEEN * sqrt(cn)) continue;
      double ur[512]; /* (U^T v)_r / s_r over the kept singular values */
      for (int r = 0; r < n; ++r) {
        double sr = gsl_vector_get(S, (size_t)r), acc = 0.0;
        if (sr > FREQ_SV_TRUNC * smax)
          for (int l = 0; l < n; ++l)
            acc += gsl_matrix_get(U, (size_t)l, (size_t)r) * v[0][l];
        ur[r] = sr > FREQ_SV_TRUNC * smax ? acc / sr : 0.0;
      }
      for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int r = 0; r < n; ++r)
          if (ur[r] != 0.0) acc += gsl_matrix_get(V, (size_t)i, (size_t)r) * ur[r];
        v[1][i] = acc;
      }
      ++n0;
      for (int t = 0; t < 2; ++t) {
        for (int pass = 0; pass < 2; ++pass) /* twice is enough (Kahan) */
          for (int b = 0; b < k; ++b) {
            double dot = 0.0;
            for (int i = 0; i < n; ++i)
              dot += gsl_matrix_get(Sb, (size_t)i, (size_t)b) * v[t][i];
            for (int i = 0; i < n; ++i)
              v[t][i] -= dot * gsl_matrix_get(Sb, (size_t)i, (size_t)b);
          }
        double nv = 0.0;
        for (int i = 0; i < n; ++i)
          nv += v[t][i] * v[t][i];
        nv = sqrt(nv);
        if (!(nv > 1e-6)) continue; /* g already in the span */
        for (int i = 0; i < n; ++i)
          gsl_matrix_set(Sb, (size_t)i, (size_t)k, v[t][i] / nv);
        ++k;
      }
    }
  if (n0 == 0 || k >= n) goto fallback;
  /* invariance: |A Q_S - Q_S Q_S^T A Q_S| <= 1e-9 |A| */
  double worst = 0.0;
  for (int b = 0; b < k; ++b) {
    double aq[512], proj[512];
    for (int i = 0; i < n; ++i) {
      double acc = 0.0;
      for (int j = 0; j < n; ++j)
        acc += As[i * n + j] * gsl_matrix_get(Sb, (size_t)j, (size_t)b);
      aq[i] = acc;
      proj[i] = 0.0;
    }
    for (int c = 0; c < k; ++c) {
      double dot = 0.0;
      for (int i = 0; i < n; ++i)
        dot += gsl_matrix_get(Sb, (size_t)i, (size_t)c) * aq[i];
      for (int i = 0; i < n; ++i)
        proj[i] += dot * gsl_matrix_get(Sb, (size_t)i, (size_t)c);
    }
    for (int i = 0; i < n; ++i)
      worst = fmax(worst, fabs(aq[i] - proj[i]));
  }
  if (!(worst <= 1e-9 * smax)) goto fallback;
  /* the complement: full Q of the QR of Q_S */
  {
    gsl_matrix_view qs = gsl_matrix_submatrix(Sb, 0, 0, (size_t)n, (size_t)k);
    gsl_matrix *QR = gsl_matrix_alloc((size_t)n, (size_t)k);
    gsl_vector *tk = gsl_vector_alloc((size_t)k);
    Q = gsl_matrix_alloc((size_t)n, (size_t)n);
    gsl_matrix *Rm = gsl_matrix_alloc((size_t)n, (size_t)k);
    int ok = QR && tk && Q && Rm && gsl_matrix_memcpy(QR, &qs.matrix) == GSL_SUCCESS &&
             gsl_linalg_QR_decomp(QR, tk) == GSL_SUCCESS &&
             gsl_linalg_QR_unpack(QR, tk, Q, Rm) == GSL_SUCCESS;
    gsl_matrix_free(QR);
    gsl_vector_free(tk);
    gsl_matrix_free(Rm);
    if (!ok) goto fallback;
  }
  {
    const int m = n - k;
    out = gsl_matrix_alloc((size_t)m, (size_t)m);
    double *aq = malloc((size_t)n * (size_t)m * sizeof *aq); /* A Q_P, n x m */
    if (!out || !aq) {
      free(aq);
      goto fallback;
    }
    for (int i = 0; i < n; ++i)
      for (int b = 0; b < m; ++b) {
        double row = 0.0;
        for (int j = 0; j < n; ++j)
          row += As[i * n + j] * gsl_matrix_get(Q, (size_t)j, (size_t)(k + b));
        aq[i * m + b] = row;
      }
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) {
        double acc = 0.0;
        for (int i = 0; i < n; ++i) {
          double qa = gsl_matrix_get(Q, (size_t)i, (size_t)(k + a));
          if (qa != 0.0) acc += qa * aq[i * m + b];
        }
        gsl_matrix_set(out, (size_t)a, (size_t)b, acc);
      }
    free(aq);
    *m_out = m;
    *n_idle = k;
  }
  goto done;
fallback:
  gsl_matrix_free(out);
  out = gsl_matrix_alloc((size_t)n, (size_t)n);
  if (out)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        gsl_matrix_set(out, (size_t)i, (size_t)j, As[i * n + j]);
  *m_out = n;
  *n_idle = 0;
done:
  gsl_matrix_free(U);
  gsl_matrix_free(V);
  gsl_matrix_free(Sb);
  gsl_matrix_free(Q);
  gsl_vector_free(S);
  gsl_vector_free(w);
  gsl_vector_free(tq);
  return out;
}

/* Scaled A of the kept states at y (f = f(y) already evaluated into f). */
static int scaled_jacobian(const pom_dyn_model *m, pom_dyn_data *d, freq_lin *L, const double *f,
                           double *yp, double *fp) {
  const int n = L->n;
  int r = full_jacobian(m, d, L->y, f, yp, fp);
  if (r != 0) return r;
  memset(L->As, 0, (size_t)n * (size_t)n * sizeof *L->As);
  for (int jj = 0; jj < n; ++jj) {
    int j = L->idx[jj];
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
      int i = m->rowind[k];
      /* kept row index: the kept states are in ascending order */
      int lo = 0, hi = n - 1, ii = -1;
      while (lo <= hi) {
        int mid = (lo + hi) / 2;
        if (L->idx[mid] == i) {
          ii = mid;
          break;
        }
        if (L->idx[mid] < i)
          lo = mid + 1;
        else
          hi = mid - 1;
      }
      if (ii >= 0) L->As[ii * n + jj] = d->jac[k] * L->scale[jj] / L->scale[ii];
    }
  }
  return 0;
}

/* Platform rotation (fixed frame, rad) per unit of the orientation states
 * o[n_ori]: rows of a 3 x n_ori map (docs/capability.md). */
static pom_status rotation_map(double C[3][4], const double *o, int n_ori, pom_error *err) {
  memset(C, 0, 12 * sizeof(double));
  if (n_ori == 4) {
    /* dtheta = 2 vec(dq q*) = 2 (q0 dqv - dq0 qv + qv x dqv) for unit q */
    double q[4] = {o[0], o[1], o[2], o[3]}, nq = 0.0;
    for (int k = 0; k < 4; ++k)
      nq += q[k] * q[k];
    nq = sqrt(nq);
    for (int k = 0; k < 4; ++k)
      q[k] /= nq;
    for (int i = 0; i < 3; ++i) {
      C[i][0] = -2.0 * q[1 + i] / nq;
      C[i][1 + i] = 2.0 * q[0] / nq;
    }
    /* qv x dqv = [qv]x dqv */
    C[0][2] += -2.0 * q[3] / nq, C[0][3] += 2.0 * q[2] / nq;
    C[1][1] += 2.0 * q[3] / nq, C[1][3] += -2.0 * q[1] / nq;
    C[2][1] += -2.0 * q[2] / nq, C[2][2] += 2.0 * q[1] / nq;
    return POM_OK;
  }
  double E[9], Ei[9];
  if (pom_euler_zyx_rate_matrix(E, o, 1e-9) != POM_OK || pom_m3_inverse(Ei, E, 1e-12) != POM_OK)
    POM_FAIL(err, POM_ERR_EULER_SINGULAR,
             "frequency response: the pose is at the Euler "
             "singularity (pitch 90 deg); use orientation = "
             "\"quaternion\"");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      C[i][j] = Ei[3 * i + j];
  return POM_OK;
}

/* Everything at the pose: equilibrium, A, inputs, outputs, Hessenberg form,
 * T(0) and the eigenvalues. d's target, clock and setpoint path are saved
 * and restored by the caller. */
static pom_status linearize(const pom_dyn_model *m, pom_dyn_data *d, const double q_pose[3],
                            freq_lin *L, pom_error *err) {
  const int N = m->n_states;
  pom_status st = POM_OK;
  double *f = NULL, *yp = NULL, *fp = NULL, *fm = NULL, *dy = NULL;
  gsl_matrix *Hm = NULL, *Um = NULL;
  gsl_vector *tau = NULL;
  if (!m->has_arch)
    POM_FAIL(err, POM_ERR_ARG,
             "frequency response: the model was built without its "
             "architecture (pom_dyn_model_create with arch NULL)");
  if (m->platform_slot < 0) POM_FAIL(err, POM_ERR_ARG, "frequency response: no platform body");
  L->n_act = m->n_actuators < 3 ? m->n_actuators : 3;
  for (int a = 0; a < m->n_actuators; ++a)
    if (!isfinite(q_pose[a]))
      POM_FAIL(err, POM_ERR_ARG, "frequency response: pose coordinate %d is not finite", a + 1);

  /* the pose: R = FK(q), q_dot = J omega (actuator a is limb a, as the
   * simulator's target orientation) */
  double R[9], qq[3], J[9];
  POM_TRY(pom_kin_forward(&m->arch, q_pose, NULL, NULL, R, NULL, err));
  POM_TRY(pom_kin_inverse_jacobian(&m->arch, R, qq, J, err));

  int n = 0;
  L->idx = calloc((size_t)N, sizeof *L->idx);
  L->y = calloc((size_t)N, sizeof *L->y);
  f = calloc((size_t)N, sizeof *f);
  yp = calloc((size_t)N, sizeof *yp);
  fp = calloc((size_t)N, sizeof *fp);
  fm = calloc((size_t)N, sizeof *fm);
  if (!L->idx || !L->y || !f || !yp || !fp || !fm) {
    st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "allocating the linearization");
    goto done;
  }
  for (int i = 0; i < N; ++i)
    if (!is_accumulator(m, i)) L->idx[n++] = i;
  L->n = n;
  L->scale = calloc((size_t)n, sizeof *L->scale);
  L->As = calloc((size_t)n * (size_t)n, sizeof *L->As);
  L->Bs = calloc((size_t)n * NIO, sizeof *L->Bs);
  L->Cs = calloc((size_t)n * NIO, sizeof *L->Cs);
  L->n_sys = 1 + L->n_act;
  int sys_ok = 1;
  for (int k = 0; k < L->n_sys; ++k) {
    L->UB[k] = calloc((size_t)n * NIO, sizeof *L->UB[k]);
    L->CU[k] = calloc((size_t)n * NIO, sizeof *L->CU[k]);
    L->H[k] = calloc((size_t)n * (size_t)n, sizeof *L->H[k]);
    sys_ok = sys_ok && L->UB[k] && L->CU[k] && L->H[k];
  }
  L->M = calloc((size_t)n * (size_t)n, sizeof *L->M);
  L->X = calloc((size_t)n * NIO, sizeof *L->X);
  L->lambda = calloc((size_t)n, sizeof *L->lambda);
  dy = calloc((size_t)n, sizeof *dy);
  if (!sys_ok || !L->scale || !L->As || !L->Bs || !L->Cs || !L->M || !L->X || !L->lambda || !dy) {
    st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "allocating the linearization");
    goto done;
  }
  for (int k = 0; k < n; ++k)
    L->scale[k] = m->scale[L->idx[k]];

  /* ---- equilibrium: Newton on f(y) = 0, the setpoints at the pose ---- */
  st = initial_guess(m, R, L->y, err);
  if (st != POM_OK) goto done;
  double step = INFINITY;
  for (int it = 0; it < FREQ_NEWTON_MAX && step > FREQ_NEWTON_TOL; ++it) {
    if (pom_dyn_eval(m, d, L->y, f) != 0 || scaled_jacobian(m, d, L, f, yp, fp) != 0) {
      st = pom_error_set(err, d->out.kin_fail ? POM_ERR_UNREACHABLE : POM_ERR_NONFINITE, __FILE__,
                         __LINE__,
                         "frequency response: the model cannot be evaluated on the way to the "
                         "equilibrium (%s)",
                         d->out.kin_fail ? "mechanism not assemblable" : "non-finite or singular");
      goto done;
    }
    for (int k = 0; k < n; ++k)
      dy[k] = -f[L->idx[k]] / L->scale[k];
    if (pinv_solve(L->As, n, dy, 1)) {
      st = pom_error_set(err, POM_ERR_GSL, __FILE__, __LINE__, "frequency response: SVD failed");
      goto done;
    }
    step = 0.0;
    for (int k = 0; k < n; ++k) {
      L->y[L->idx[k]] += dy[k] * L->scale[k];
      step = fmax(step, fabs(dy[k]));
    }
  }
  if (!(step <= FREQ_NEWTON_TOL)) {
    st = pom_error_set(err, POM_ERR_NOCONVERGE, __FILE__, __LINE__,
                       "frequency response: no equilibrium holds the pose (Newton step %.3g "
                       "state scales after %d iterations)",
                       step, FREQ_NEWTON_MAX);
    goto done;
  }
  /* A at the equilibrium */
  if (pom_dyn_eval(m, d, L->y, f) != 0 || scaled_jacobian(m, d, L, f, yp, fp) != 0) {
    st = pom_error_set(err, POM_ERR_NONFINITE, __FILE__, __LINE__,
                       "frequency response: the model cannot be evaluated at the equilibrium");
    goto done;
  }

  /* ---- inputs: df/ds per actuator (central difference; f is affine in s
   * for the PID, docs/capability.md) and df/du (affine) ---- */
  double *Bsa = calloc((size_t)n * 3, sizeof *Bsa);
  if (!Bsa) {
    st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "allocating the linearization");
    goto done;
  }
  for (int a = 0; a < L->n_act; ++a) {
    const double s0 = d->target[a], h = 1e-6 * fmax(fabs(s0), 1e-3);
    d->target[a] = s0 + h;
    (void)pom_dyn_eval(m, d, L->y, fp);
    d->target[a] = s0 - h;
    (void)pom_dyn_eval(m, d, L->y, fm);
    d->target[a] = s0;
    for (int k = 0; k < n; ++k)
      Bsa[k * 3 + a] = (fp[L->idx[k]] - fm[L->idx[k]]) / (2.0 * h) / L->scale[k];
    d->u_inject[a] = FREQ_DU;
    (void)pom_dyn_eval(m, d, L->y, fp);
    d->u_inject[a] = -FREQ_DU;
    (void)pom_dyn_eval(m, d, L->y, fm);
    d->u_inject[a] = 0.0;
    for (int k = 0; k < n; ++k)
      L->Bs[k * NIO + 3 + a] = (fp[L->idx[k]] - fm[L->idx[k]]) / (2.0 * FREQ_DU) / L->scale[k];
  }
  /* setpoint rotation about fixed axis e: ds = J e */
  for (int k = 0; k < n; ++k)
    for (int e = 0; e < 3; ++e) {
      double acc = 0.0;
      for (int a = 0; a < L->n_act; ++a)
        acc += Bsa[k * 3 + a] * J[3 * a + e];
      L->Bs[k * NIO + e] = acc;
    }
  free(Bsa);

  /* ---- outputs: platform rotation (analytic map of the orientation
   * states), each controller's raw voltage (central differences) ---- */
  {
    int ori, n_ori;
    double Cr[3][4];
    platform_ori(m, &ori, &n_ori);
    st = rotation_map(Cr, L->y + ori, n_ori, err);
    if (st != POM_OK) goto done;
    for (int k = 0; k < n; ++k) {
      int i = L->idx[k];
      if (i >= ori && i < ori + n_ori)
        for (int r = 0; r < 3; ++r)
          L->Cs[r * n + k] = Cr[r][i - ori] * L->scale[k];
    }
    memcpy(yp, L->y, (size_t)N * sizeof *yp);
    for (int k = 0; k < n; ++k) {
      int i = L->idx[k];
      /* h ~ eps^1/3 of the state's working size (1e3 characteristic
       * scales: 0.1 rad, 10 rad/s): A_k = A - b_k c_k^T cancels the
       * controller's part of A, so c_k's rounding error (eps |q| / h) must
       * stay far below it; the truncation error is O(h^2) */
      double h = 1e-5 * fmax(fabs(L->y[i]), 1e3 * L->scale[k]), up[3], um[3];
      yp[i] = L->y[i] + h;
      (void)pom_dyn_eval(m, d, yp, fp);
      for (int a = 0; a < L->n_act; ++a)
        up[a] = d->out.voltage[a];
      yp[i] = L->y[i] - h;
      (void)pom_dyn_eval(m, d, yp, fp);
      for (int a = 0; a < L->n_act; ++a)
        um[a] = d->out.voltage[a];
      yp[i] = L->y[i];
      for (int a = 0; a < L->n_act; ++a)
        L->Cs[(3 + a) * n + k] = (up[a] - um[a]) / (2.0 * h) * L->scale[k];
    }
  }

  /* ---- T(0) = -C A^+ B_rot (idle modes neither driven nor seen) ---- */
  {
    double *X0 = calloc((size_t)n * 3, sizeof *X0);
    if (!X0) {
      st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "allocating the linearization");
      goto done;
    }
    for (int k = 0; k < n; ++k)
      for (int e = 0; e < 3; ++e)
        X0[k * 3 + e] = -L->Bs[k * NIO + e];
    if (pinv_solve(L->As, n, X0, 3)) {
      free(X0);
      st = pom_error_set(err, POM_ERR_GSL, __FILE__, __LINE__, "frequency response: SVD failed");
      goto done;
    }
    for (int r = 0; r < 3; ++r)
      for (int e = 0; e < 3; ++e) {
        double acc = 0.0;
        for (int k = 0; k < n; ++k)
          acc += L->Cs[r * n + k] * X0[k * 3 + e];
        L->T0[3 * r + e] = acc;
      }
    free(X0);
    if (pom_m3_inverse(L->T0inv, L->T0, 1e-12) != POM_OK) {
      st = pom_error_set(err, POM_ERR_SINGULAR, __FILE__, __LINE__,
                         "frequency response: the static gain T(0) is singular");
      goto done;
    }
  }

  /* ---- Hessenberg forms U H U^T of A and of each broken loop's A_k ---- */
  Hm = gsl_matrix_alloc((size_t)n, (size_t)n);
  Um = gsl_matrix_alloc((size_t)n, (size_t)n);
  tau = gsl_vector_alloc((size_t)n);
  if (!Hm || !Um || !tau) {
    st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "allocating the linearization");
    goto done;
  }
  for (int sy = 0; sy < L->n_sys; ++sy) {
    const int a = sy - 1; /* the broken loop, -1 for the closed one */
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        gsl_matrix_set(Hm, (size_t)i, (size_t)j,
                       L->As[i * n + j] -
                           (a >= 0 ? L->Bs[i * NIO + 3 + a] * L->Cs[(3 + a) * n + j] : 0.0));
    if (gsl_linalg_hessenberg_decomp(Hm, tau) != GSL_SUCCESS ||
        gsl_linalg_hessenberg_unpack(Hm, tau, Um) != GSL_SUCCESS ||
        gsl_linalg_hessenberg_set_zero(Hm) != GSL_SUCCESS) {
      st = pom_error_set(err, POM_ERR_GSL, __FILE__, __LINE__,
                         "frequency response: Hessenberg reduction failed");
      goto done;
    }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        L->H[sy][i * n + j] = gsl_matrix_get(Hm, (size_t)i, (size_t)j);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < NIO; ++c) {
        double ub = 0.0, cu = 0.0;
        for (int k = 0; k < n; ++k) {
          ub += gsl_matrix_get(Um, (size_t)k, (size_t)i) * L->Bs[k * NIO + c];
          cu += L->Cs[c * n + k] * gsl_matrix_get(Um, (size_t)k, (size_t)i);
        }
        L->UB[sy][i * NIO + c] = ub;
        L->CU[sy][c * n + i] = cu;
      }
  }
  {
    /* the poles without the idle modes (docs/capability.md) */
    int m_act = 0;
    gsl_matrix *Ae = active_matrix(L->As, L->Cs, n, &m_act, &L->n_idle);
    gsl_vector_complex *ev = Ae ? gsl_vector_complex_alloc((size_t)m_act) : NULL;
    gsl_eigen_nonsymm_workspace *ws = Ae ? gsl_eigen_nonsymm_alloc((size_t)m_act) : NULL;
    if (Ae && ev && ws) {
      gsl_eigen_nonsymm_params(0, 1, ws); /* balance: the scales span decades */
      if (gsl_eigen_nonsymm(Ae, ev, ws) == GSL_SUCCESS) {
        L->modes_ok = 1;
        L->n_lambda = m_act;
        for (int k = 0; k < m_act; ++k) {
          gsl_complex z = gsl_vector_complex_get(ev, (size_t)k);
          L->lambda[k] = GSL_REAL(z) + I * GSL_IMAG(z);
        }
      }
    }
    gsl_matrix_free(Ae);
    gsl_vector_complex_free(ev);
    gsl_eigen_nonsymm_free(ws);
  }

done:
  gsl_matrix_free(Hm);
  gsl_matrix_free(Um);
  gsl_vector_free(tau);
  free(f);
  free(yp);
  free(fp);
  free(fm);
  free(dy);
  return st;
}

/* ---- T(jw) ---------------------------------------------------------------- */
/* Y[NIO][NIO] = C (jw I - A)^-1 B at f_hz by the Hessenberg form: rows 0-2
 * platform rotation, 3-5 controller voltages; columns 0-2 setpoint rotations
 * (system 0, the closed loop, computes these alone), 3-5 voltage injections
 * (system 1 + k, the loop of actuator k broken, computes column 3 + k alone;
 * the others are NaN). Returns 0, or 1 when jw I - A is singular. */
static int response_solve(freq_lin *L, int sy, double f_hz, double complex Y[NIO][NIO]) {
  const int n = L->n;
  const double *H = L->H[sy], *UB = L->UB[sy], *CU = L->CU[sy];
  const double complex s = I * 2.0 * POM_PI * f_hz;
  double complex *M = L->M, *X = L->X;
  /* the columns a caller reads: the setpoint rotations of the closed loop,
   * the own injection of a broken loop (the others are left NaN) */
  const int c0 = sy == 0 ? 0 : 3 + (sy - 1), c1 = sy == 0 ? 3 : c0 + 1;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j)
      M[i * n + j] = (j >= i - 1) ? -H[i * n + j] : 0.0;
    M[i * n + i] += s;
    for (int c = c0; c < c1; ++c)
      X[i * NIO + c] = UB[i * NIO + c];
  }
  /* Gaussian elimination of the upper Hessenberg matrix, pivoting between
   * neighbouring rows: O(n^2) */
  for (int j = 0; j < n - 1; ++j) {
    if (cabs(M[(j + 1) * n + j]) > cabs(M[j * n + j])) {
      for (int k = j; k < n; ++k) {
        double complex t = M[j * n + k];
        M[j * n + k] = M[(j + 1) * n + k];
        M[(j + 1) * n + k] = t;
      }
      for (int c = c0; c < c1; ++c) {
        double complex t = X[j * NIO + c];
        X[j * NIO + c] = X[(j + 1) * NIO + c];
        X[(j + 1) * NIO + c] = t;
      }
    }
    if (M[j * n + j] == 0.0) return 1;
    double complex l = M[(j + 1) * n + j] / M[j * n + j];
    for (int k = j + 1; k < n; ++k)
      M[(j + 1) * n + k] -= l * M[j * n + k];
    for (int c = c0; c < c1; ++c)
      X[(j + 1) * NIO + c] -= l * X[j * NIO + c];
  }
  for (int i = n - 1; i >= 0; --i) {
    if (M[i * n + i] == 0.0) return 1;
    for (int c = c0; c < c1; ++c) {
      double complex acc = X[i * NIO + c];
      for (int k = i + 1; k < n; ++k)
        acc -= M[i * n + k] * X[k * NIO + c];
      X[i * NIO + c] = acc / M[i * n + i];
    }
  }
  for (int r = 0; r < NIO; ++r)
    for (int c = 0; c < NIO; ++c) {
      double complex acc = c >= c0 && c < c1 ? 0.0 : NAN;
      if (c >= c0 && c < c1)
        for (int k = 0; k < n; ++k)
          acc += CU[r * n + k] * X[k * NIO + c];
      Y[r][c] = acc;
    }
  return 0;
}

static int grid_size(void);
static double grid_f(int i);

/* response_solve, memoized on the search grid (grid_f(i) exactly). */
static int response_sys(freq_lin *L, int sy, double f_hz, double complex Y[NIO][NIO]) {
  const int ng = grid_size();
  long i = lround(log10(f_hz / FREQ_F_LO) * FREQ_PER_DEC);
  if (i < 0 || i >= ng || grid_f((int)i) != f_hz) return response_solve(L, sy, f_hz, Y);
  if (!L->grid_Y[sy]) {
    L->grid_Y[sy] = malloc((size_t)ng * NIO * NIO * sizeof *L->grid_Y[sy]);
    L->grid_ok[sy] = calloc((size_t)ng, 1);
    if (!L->grid_Y[sy] || !L->grid_ok[sy]) { /* no memory: no cache */
      free(L->grid_Y[sy]);
      free(L->grid_ok[sy]);
      L->grid_Y[sy] = NULL;
      L->grid_ok[sy] = NULL;
      return response_solve(L, sy, f_hz, Y);
    }
  }
  double complex *c = L->grid_Y[sy] + (size_t)i * NIO * NIO;
  if (!L->grid_ok[sy][i]) {
    int r = response_solve(L, sy, f_hz, Y);
    L->grid_ok[sy][i] = r == 0 ? 1 : 2;
    if (r == 0) memcpy(c, Y, NIO * NIO * sizeof *c);
  }
  if (L->grid_ok[sy][i] == 2) return 1;
  memcpy(Y, c, NIO * NIO * sizeof *c);
  return 0;
}

/* The closed loop's Y. */
static int response_at(freq_lin *L, double f_hz, double complex Y[NIO][NIO]) {
  return response_sys(L, 0, f_hz, Y);
}

/* Loop gain of actuator a with its loop broken at its voltage input, the
 * others closed: L = -c_a^T (jw I - A_a)^-1 b_a with A_a = A - b_a c_a^T
 * (docs/capability.md); NAN when jw I - A_a is singular. */
static double complex loop_gain(freq_lin *L, int a, double f_hz) {
  double complex Y[NIO][NIO];
  if (response_sys(L, 1 + a, f_hz, Y) != 0) return NAN;
  return -Y[3 + a][3 + a];
}

/* Relative gain of real direction extremes at one frequency: with
 * M = T(jw) T(0)^-1, min and max over real unit e' of |M e'| are the square
 * roots of the extreme eigenvalues of Re(M^H M); emin the minimizing e'. */
static void real_dir_gains(const freq_lin *L, double complex Y[NIO][NIO], double *gmin,
                           double *gmax, double emin[3]) {
  double complex Mx[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      double complex acc = 0.0;
      for (int k = 0; k < 3; ++k)
        acc += Y[r][k] * L->T0inv[3 * k + c];
      Mx[r][c] = acc;
    }
  double S[9], w[3], V[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double complex acc = 0.0;
      for (int k = 0; k < 3; ++k)
        acc += conj(Mx[k][i]) * Mx[k][j];
      S[3 * i + j] = creal(acc);
    }
  pom_m3_sym_eig(w, V, S); /* descending */
  *gmax = sqrt(fmax(w[0], 0.0));
  *gmin = sqrt(fmax(w[2], 0.0));
  if (emin)
    for (int i = 0; i < 3; ++i)
      emin[i] = V[3 * i + 2];
}

/* What a search follows at frequency f: the relative axis gain, the worst
 * direction's, or the loop gain's modulus / imaginary part. */
enum { Q_AXIS, Q_WORST, Q_LOOP_MAG, Q_LOOP_IM };

static double quantity(freq_lin *L, int q, int k, double f) {
  double complex Y[NIO][NIO];
  if (q == Q_LOOP_MAG) return cabs(loop_gain(L, k, f));
  if (q == Q_LOOP_IM) return cimag(loop_gain(L, k, f));
  if (response_at(L, f, Y) != 0) return NAN;
  switch (q) {
  case Q_AXIS:
    return cabs(Y[k][k]) / fabs(L->T0[4 * k]);
  case Q_WORST: {
    double gmin, gmax;
    real_dir_gains(L, Y, &gmin, &gmax, NULL);
    return gmin;
  }
  default:
    return NAN;
  }
}

/* The crossing of quantity - level between f_a (sign sa) and f_b, by
 * bisection in log f. */
static double bisect(freq_lin *L, int q, int k, double level, double fa, double fb) {
  double ga = quantity(L, q, k, fa) - level;
  while (fb / fa - 1.0 > FREQ_BISECT_TOL) {
    double fm = sqrt(fa * fb), gm = quantity(L, q, k, fm) - level;
    if ((gm > 0) == (ga > 0))
      fa = fm, ga = gm;
    else
      fb = fm;
  }
  return sqrt(fa * fb);
}

static int grid_size(void) {
  return (int)lround(log10(FREQ_F_HI / FREQ_F_LO) * FREQ_PER_DEC) + 1;
}
static double grid_f(int i) {
  return FREQ_F_LO * pow(10.0, (double)i / FREQ_PER_DEC);
}

/* Largest value of quantity q over the grid, refined by golden section in
 * log f about the best grid point; returns the value. */
static double peak(freq_lin *L, int q, int k) {
  const int ng = grid_size();
  int best = 0;
  double gb = -INFINITY;
  for (int i = 0; i < ng; ++i) {
    double g = quantity(L, q, k, grid_f(i));
    if (g > gb) gb = g, best = i;
  }
  if (best == 0 || best == ng - 1) return gb;
  double a = log(grid_f(best - 1)), b = log(grid_f(best + 1));
  const double r = 0.5 * (sqrt(5.0) - 1.0);
  double c = b - r * (b - a), dd = a + r * (b - a);
  double gc = quantity(L, q, k, exp(c)), gd = quantity(L, q, k, exp(dd));
  for (int it = 0; it < 60; ++it) {
    if (gc > gd) {
      b = dd, dd = c, gd = gc;
      c = b - r * (b - a);
      gc = quantity(L, q, k, exp(c));
    } else {
      a = c, c = dd, gc = gd;
      dd = a + r * (b - a);
      gd = quantity(L, q, k, exp(dd));
    }
  }
  return fmax(gb, fmax(gc, gd));
}

/* First frequency where quantity q falls below level (NaN: not in the grid). */
static double first_below(freq_lin *L, int q, int k, double level) {
  const int ng = grid_size();
  double fprev = grid_f(0);
  if (!(quantity(L, q, k, fprev) > level)) return NAN;
  for (int i = 1; i < ng; ++i) {
    double f = grid_f(i), g = quantity(L, q, k, f);
    if (g <= level) return bisect(L, q, k, level, fprev, f);
    fprev = f;
  }
  return NAN;
}

/* Gain and phase margins of actuator a's loop (docs/capability.md): the
 * gain crossover is the first downward crossing of |L| = 1; the phase
 * margin 180 deg + arg L there, arg in (-360, 0]; the gain margin
 * -20 log10 |L| at the first crossing of the negative real axis above it. */
static void margins(freq_lin *L, int a, double *gm_db, double *pm_deg, double *fc_hz) {
  const int ng = grid_size();
  *gm_db = *pm_deg = INFINITY;
  *fc_hz = NAN;
  double fprev = grid_f(0), mprev = quantity(L, Q_LOOP_MAG, a, fprev);
  int i0 = 1;
  for (int i = 1; i < ng; ++i) {
    double f = grid_f(i), mg = quantity(L, Q_LOOP_MAG, a, f);
    if (mprev > 1.0 && mg <= 1.0) {
      *fc_hz = bisect(L, Q_LOOP_MAG, a, 1.0, fprev, f);
      double psi = carg(loop_gain(L, a, *fc_hz)) * 180.0 / POM_PI;
      *pm_deg = psi <= 0.0 ? 180.0 + psi : psi - 180.0;
      i0 = i;
      break;
    }
    fprev = f, mprev = mg;
  }
  fprev = grid_f(i0 - 1);
  double imprev = quantity(L, Q_LOOP_IM, a, fprev);
  for (int i = i0; i < ng; ++i) {
    double f = grid_f(i), im = quantity(L, Q_LOOP_IM, a, f);
    if ((im > 0) != (imprev > 0)) {
      double fx = bisect(L, Q_LOOP_IM, a, 0.0, fprev, f);
      double complex l = loop_gain(L, a, fx);
      if (creal(l) < 0 && (isnan(*fc_hz) || fx >= *fc_hz)) {
        *gm_db = -20.0 * log10(cabs(l));
        break;
      }
    }
    fprev = f, imprev = im;
  }
}

/* ---- public ---------------------------------------------------------------- */
typedef struct {
  double target[POM_MECH_MAX_ACTUATORS];
  double t;
  pom_dyn_setpoint_fn fn;
  void *ctx;
} saved_data;

static void save_data(pom_dyn_data *d, saved_data *s, const double q_pose[3], int n_act) {
  memcpy(s->target, d->target, sizeof s->target);
  s->t = d->t, s->fn = d->setpoint_fn, s->ctx = d->setpoint_ctx;
  d->setpoint_fn = NULL;
  d->t = FREQ_T_EQ;
  for (int a = 0; a < n_act; ++a)
    d->target[a] = q_pose[a];
  memset(d->u_inject, 0, sizeof d->u_inject);
}

static void restore_data(pom_dyn_data *d, const saved_data *s) {
  memcpy(d->target, s->target, sizeof s->target);
  d->t = s->t, d->setpoint_fn = s->fn, d->setpoint_ctx = s->ctx;
  memset(d->u_inject, 0, sizeof d->u_inject);
  d->jac_valid = 0;
}

static pom_status check_args(const pom_dyn_model *m, const pom_dyn_data *d, const double *q,
                             const void *out, pom_error *err) {
  if (!m || !d || !q || !out || d->m != m)
    POM_FAIL(err, POM_ERR_ARG, "frequency response: NULL argument or data of another model");
  return POM_OK;
}

/* The linearization at q_pose, d's target, clock and setpoint path kept. */
static pom_status lin_at(const pom_dyn_model *m, pom_dyn_data *d, const double q_pose[3],
                         freq_lin *L, pom_error *err) {
  gsl_error_handler_t *old = gsl_set_error_handler_off();
  saved_data sv;
  save_data(d, &sv, q_pose, m->n_actuators);
  pom_status st = linearize(m, d, q_pose, L, err);
  restore_data(d, &sv);
  gsl_set_error_handler(old);
  if (st != POM_OK) lin_free(L);
  return st;
}

static void figures_of(const pom_dyn_model *m, freq_lin *L, pom_dyn_freq_figures *out) {
  memset(out, 0, sizeof *out);
  const double lvl = 1.0 / sqrt(2.0);
  out->n_actuators = L->n_act;
  double bw_max = 0.0;
  for (int e = 0; e < 3; ++e) {
    out->dc_gain[e] = fabs(L->T0[4 * e]);
    out->bandwidth_hz[e] = first_below(L, Q_AXIS, e, lvl);
    double pk = peak(L, Q_AXIS, e);
    out->peak_db[e] = pk > 1.0 ? 20.0 * log10(pk) : 0.0;
    if (isfinite(out->bandwidth_hz[e])) bw_max = fmax(bw_max, out->bandwidth_hz[e]);
  }
  out->bandwidth_worst_hz = first_below(L, Q_WORST, 0, lvl);
  {
    double complex Y[NIO][NIO];
    double gmin, gmax, e1[3] = {NAN, NAN, NAN}, e0[3];
    if (isfinite(out->bandwidth_worst_hz) && response_at(L, out->bandwidth_worst_hz, Y) == 0) {
      real_dir_gains(L, Y, &gmin, &gmax, e1);
      pom_m3_apply(e0, L->T0inv, e1); /* e' = T(0) e */
      double nn = pom_v3_norm(e0);
      for (int i = 0; i < 3; ++i)
        out->worst_dir[i] = e0[i] / nn;
    } else {
      out->worst_dir[0] = out->worst_dir[1] = out->worst_dir[2] = NAN;
    }
    /* the largest real-direction gain's peak */
    const int ng = grid_size();
    double pk = 0.0;
    for (int i = 0; i < ng; ++i)
      if (response_at(L, grid_f(i), Y) == 0) {
        real_dir_gains(L, Y, &gmin, &gmax, NULL);
        pk = fmax(pk, gmax);
      }
    out->peak_db_worst = pk > 1.0 ? 20.0 * log10(pk) : 0.0;
  }
  for (int a = 0; a < 3; ++a) {
    out->gain_margin_db[a] = out->phase_margin_deg[a] = out->crossover_hz[a] = NAN;
    if (a < L->n_act)
      margins(L, a, &out->gain_margin_db[a], &out->phase_margin_deg[a], &out->crossover_hz[a]);
  }
  /* poles: stability, the slowest, the parasitic modes */
  out->stable = 0;
  out->slowest_pole_hz = NAN;
  if (L->modes_ok) {
    int stable = 1;
    double slow = INFINITY;
    for (int k = 0; k < L->n_lambda; ++k) {
      if (!(creal(L->lambda[k]) < 0)) stable = 0;
      slow = fmin(slow, cabs(L->lambda[k]));
    }
    out->stable = stable;
    out->slowest_pole_hz = isfinite(slow) ? slow / (2.0 * POM_PI) : NAN;
    if (m->form != &pom_dyn_form_exact) {
      double fl = FREQ_MODE_ABOVE * bw_max;
      for (;;) { /* ascending selection of the oscillatory poles above the band */
        double best = INFINITY;
        int kb = -1;
        for (int k = 0; k < L->n_lambda; ++k) {
          double fk = cabs(L->lambda[k]) / (2.0 * POM_PI);
          double zeta = -creal(L->lambda[k]) / cabs(L->lambda[k]);
          if (cimag(L->lambda[k]) > 0 && zeta < FREQ_MODE_ZETA && fk > fl && fk < best)
            best = fk, kb = k;
        }
        if (kb < 0 || out->n_modes >= POM_DYN_FREQ_MAX_MODES) break;
        out->mode_hz[out->n_modes] = best;
        out->mode_zeta[out->n_modes] = -creal(L->lambda[kb]) / cabs(L->lambda[kb]);
        ++out->n_modes;
        fl = best * (1.0 + 1e-12);
      }
    }
  }
}

/* One Bode curve (pom_dyn_freq_response's kinds). */
static void curve_of(freq_lin *L, int kind, int axis, const double *f_hz, int nf, double *mag_db,
                     double *phase_deg) {
  double prev = NAN;
  for (int i = 0; i < nf; ++i) {
    double complex Y[NIO][NIO], v;
    if (response_at(L, f_hz[i], Y) != 0) {
      mag_db[i] = phase_deg[i] = NAN;
      continue;
    }
    if (kind == POM_DYN_FREQ_AXIS) {
      v = Y[axis][axis];
    } else if (kind == POM_DYN_FREQ_LOOP) {
      v = loop_gain(L, axis, f_hz[i]);
    } else {
      double gmin, gmax, e[3];
      real_dir_gains(L, Y, &gmin, &gmax, e);
      /* phase of the worst direction's response projected on itself */
      double complex acc = 0.0;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          double complex mrc = 0.0;
          for (int k = 0; k < 3; ++k)
            mrc += Y[r][k] * L->T0inv[3 * k + c];
          acc += e[r] * mrc * e[c];
        }
      v = cabs(acc) > 0 ? gmin * acc / cabs(acc) : gmin;
    }
    mag_db[i] = 20.0 * log10(cabs(v));
    double ph = carg(v) * 180.0 / POM_PI;
    if (isfinite(prev)) /* unwrap along f */
      ph += 360.0 * round((prev - ph) / 360.0);
    phase_deg[i] = prev = ph;
  }
}

pom_status pom_dyn_freq_figures_at(const pom_dyn_model *m, pom_dyn_data *d, const double q_pose[3],
                                   pom_dyn_freq_figures *out, pom_error *err) {
  POM_TRY(check_args(m, d, q_pose, out, err));
  freq_lin L = {0};
  memset(out, 0, sizeof *out);
  POM_TRY(lin_at(m, d, q_pose, &L, err));
  figures_of(m, &L, out);
  lin_free(&L);
  return POM_OK;
}

pom_status pom_dyn_freq_response(const pom_dyn_model *m, pom_dyn_data *d, const double q_pose[3],
                                 int kind, int axis, const double *f_hz, int nf, double *mag_db,
                                 double *phase_deg, pom_error *err) {
  POM_TRY(check_args(m, d, q_pose, f_hz, err));
  if (!mag_db || !phase_deg || nf < 0)
    POM_FAIL(err, POM_ERR_ARG, "frequency response: NULL output or nf %d < 0", nf);
  if (kind < POM_DYN_FREQ_AXIS || kind > POM_DYN_FREQ_WORST || axis < 0 || axis > 2)
    POM_FAIL(err, POM_ERR_ARG, "frequency response: kind %d or axis %d out of range", kind, axis);
  for (int i = 0; i < nf; ++i)
    if (!(f_hz[i] > 0) || !isfinite(f_hz[i]))
      POM_FAIL(err, POM_ERR_ARG, "frequency response: f_hz[%d] = %g must be > 0", i, f_hz[i]);
  freq_lin L = {0};
  POM_TRY(lin_at(m, d, q_pose, &L, err));
  if (kind == POM_DYN_FREQ_LOOP && axis >= L.n_act) {
    int na = L.n_act;
    lin_free(&L);
    POM_FAIL(err, POM_ERR_ARG, "frequency response: actuator %d of %d", axis + 1, na);
  }
  curve_of(&L, kind, axis, f_hz, nf, mag_db, phase_deg);
  lin_free(&L);
  return POM_OK;
}

/* ---- JSON ------------------------------------------------------------------ */
static void json_curve(FILE *out, const double *mag, const double *ph, int nf) {
  fputs("{\"mag_db\": ", out);
  pom_json_vec(out, mag, nf, 1.0);
  fputs(", \"phase_deg\": ", out);
  pom_json_vec(out, ph, nf, 1.0);
  fputs("}", out);
}

pom_status pom_dyn_freq_json(FILE *out, const pom_dyn_model *m, pom_dyn_data *d,
                             const double q_pose[3], double f_lo, double f_hi, int per_decade,
                             pom_error *err) {
  if (!out || !(f_lo > 0) || !(f_hi > f_lo) || per_decade < 1 || per_decade > 1000)
    POM_FAIL(err, POM_ERR_ARG, "frequency response JSON: grid %g..%g Hz, %d per decade", f_lo, f_hi,
             per_decade);
  if (!m || !d || !q_pose || d->m != m)
    POM_FAIL(err, POM_ERR_ARG, "frequency response: NULL argument or data of another model");
  pom_dyn_freq_figures F;
  freq_lin L = {0};
  POM_TRY(lin_at(m, d, q_pose, &L, err));
  figures_of(m, &L, &F);
  const int nf = (int)floor(log10(f_hi / f_lo) * per_decade + 1e-9) + 1;
  double *f = calloc((size_t)nf, sizeof *f), *mag = calloc((size_t)nf * 8, sizeof *mag);
  double *ph = calloc((size_t)nf * 8, sizeof *ph);
  pom_status st = POM_OK;
  if (!f || !mag || !ph) {
    st = pom_error_set(err, POM_ERR_NOMEM, __FILE__, __LINE__, "allocating the Bode data");
    goto done;
  }
  for (int i = 0; i < nf; ++i)
    f[i] = f_lo * pow(10.0, (double)i / per_decade);
  /* curves: axes 0-2, worst 3, loops 4.. */
  for (int c = 0; c < 4 + F.n_actuators && st == POM_OK; ++c) {
    int kind = c < 3 ? POM_DYN_FREQ_AXIS : c == 3 ? POM_DYN_FREQ_WORST : POM_DYN_FREQ_LOOP;
    int axis = c < 3 ? c : c == 3 ? 0 : c - 4;
    curve_of(&L, kind, axis, f, nf, mag + (size_t)c * (size_t)nf, ph + (size_t)c * (size_t)nf);
  }
  if (st != POM_OK) goto done;
  const int na = F.n_actuators;
  fputs("{\n  \"pose_q\": ", out);
  pom_json_vec(out, q_pose, m->n_actuators, 1.0);
  fputs(",\n  \"bandwidth_hz\": ", out);
  pom_json_vec(out, F.bandwidth_hz, 3, 1.0);
  fputs(",\n  \"bandwidth_worst_hz\": ", out);
  pom_json_number(out, F.bandwidth_worst_hz);
  fputs(",\n  \"worst_dir\": ", out);
  pom_json_vec(out, F.worst_dir, 3, 1.0);
  fputs(",\n  \"peak_db\": ", out);
  pom_json_vec(out, F.peak_db, 3, 1.0);
  fputs(",\n  \"peak_db_worst\": ", out);
  pom_json_number(out, F.peak_db_worst);
  fputs(",\n  \"dc_gain\": ", out);
  pom_json_vec(out, F.dc_gain, 3, 1.0);
  /* an infinite margin (no crossing) is null, as every non-finite number */
  fputs(",\n  \"gain_margin_db\": ", out);
  pom_json_vec(out, F.gain_margin_db, na, 1.0);
  fputs(",\n  \"phase_margin_deg\": ", out);
  pom_json_vec(out, F.phase_margin_deg, na, 1.0);
  fputs(",\n  \"crossover_hz\": ", out);
  pom_json_vec(out, F.crossover_hz, na, 1.0);
  fputs(",\n  \"slowest_pole_hz\": ", out);
  pom_json_number(out, F.slowest_pole_hz);
  fprintf(out, ",\n  \"stable\": %s,\n  \"mode_hz\": ", F.stable ? "true" : "false");
  pom_json_vec(out, F.mode_hz, F.n_modes, 1.0);
  fputs(",\n  \"mode_zeta\": ", out);
  pom_json_vec(out, F.mode_zeta, F.n_modes, 1.0);
  fputs(",\n  \"f_hz\": ", out);
  pom_json_vec(out, f, nf, 1.0);
  fputs(",\n  \"axis\": [", out);
  for (int c = 0; c < 3; ++c) {
    fputs(c ? ",\n    " : "\n    ", out);
    json_curve(out, mag + (size_t)c * (size_t)nf, ph + (size_t)c * (size_t)nf, nf);
  }
  fputs("],\n  \"worst\": ", out);
  json_curve(out, mag + 3 * (size_t)nf, ph + 3 * (size_t)nf, nf);
  fputs(",\n  \"loop\": [", out);
  for (int a = 0; a < na; ++a) {
    fputs(a ? ",\n    " : "\n    ", out);
    json_curve(out, mag + (size_t)(4 + a) * (size_t)nf, ph + (size_t)(4 + a) * (size_t)nf, nf);
  }
  fputs("]\n}\n", out);
done:
  lin_free(&L);
  free(f);
  free(mag);
  free(ph);
  return st;
}
