/* test_dyn_structured_ls.c - the structured Newton solve of the parasitic
 * path (dynamics/dyn_structured_ls.c, solver.linear_solver = "structured",
 * docs/dynamics.md section 7, "Structured Newton solve"). At random states
 * of the three shipped architectures (Euler angles and quaternions, the PID
 * and the coupled computed-torque controller, a quasi-static coil, lumped
 * limbs) the Newton matrix A = I - gamma J that CVODE would factor is solved
 * for random right-hand sides by the structured solver and by a dense LU
 * with partial pivoting written here; the structured solution must have a
 * normwise backward error at rounding level and differ from the dense one by
 * no more than the condition number allows. A whole maneuver with the
 * structured solver gives KLU's metrics to the integration tolerance. */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_linearsolver.h>
#include <sunmatrix/sunmatrix_sparse.h>

#define EPS 2.220446049250313e-16

/* fixed-seed uniform numbers in (-1, 1) */
static double urand(uint64_t *s) {
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) / 4503599627370496.0 - 1.0;
}

/* A random state: every component up to its natural size (atol / rtol with
 * atol_scale 0), orientations up to 0.2 rad, quaternions off unit length
 * (as tests/test_dyn_jacobian.c). */
static void random_state(const pom_dyn_model *m, double *y, uint64_t *seed) {
  const double rtol = m->par.solver.rtol;
  for (int i = 0; i < m->n_states; ++i)
    y[i] = (m->atol[i] / rtol) * urand(seed);
  for (int b = 0; b < m->n_bodies; ++b) {
    double *o = y + m->body[b].offset + DYN_BODY_ORI;
    if (m->par.scene.orientation == POM_ORIENT_QUATERNION) {
      o[0] = 1.07 + 0.1 * urand(seed);
      for (int k = 1; k < 4; ++k)
        o[k] = 0.1 * urand(seed);
    } else {
      for (int k = 0; k < 3; ++k)
        o[k] = 0.2 * urand(seed);
    }
  }
}

/* Targets 1 mm (or 1 mrad) off the actuators' positions: the PID's
 * voltages stay inside the limit for some actuators, not for others. */
static void set_targets(const pom_dyn_model *m, pom_dyn_data *d, const double *y, uint64_t *seed) {
  pom_dyn_eval(m, d, y, NULL);
  for (int a = 0; a < m->n_actuators; ++a)
    d->target[a] = d->out.q[a] + 1e-3 * urand(seed);
}

/* ---- the dense reference: LU with partial pivoting, column-major --------- */
static int dense_lu(double *a, int n, int *piv) {
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (fabs(a[k * n + i]) > fabs(a[k * n + p])) p = i;
    piv[k] = p;
    if (a[k * n + p] == 0.0) return 1;
    for (int j = 0; j < n; ++j) {
      double t = a[j * n + k];
      a[j * n + k] = a[j * n + p];
      a[j * n + p] = t;
    }
    for (int i = k + 1; i < n; ++i)
      a[k * n + i] /= a[k * n + k];
    for (int j = k + 1; j < n; ++j)
      for (int i = k + 1; i < n; ++i)
        a[j * n + i] -= a[k * n + i] * a[j * n + k];
  }
  return 0;
}

static void dense_solve(const double *lu, int n, const int *piv, double *x) {
  for (int k = 0; k < n; ++k) {
    double t = x[k];
    x[k] = x[piv[k]];
    x[piv[k]] = t;
  }
  for (int k = 0; k < n; ++k)
    for (int i = k + 1; i < n; ++i)
      x[i] -= lu[k * n + i] * x[k];
  for (int k = n - 1; k >= 0; --k) {
    x[k] /= lu[k * n + k];
    for (int i = 0; i < k; ++i)
      x[i] -= lu[k * n + i] * x[k];
  }
}

static double inf_norm(const double *v, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i)
    s = fmax(s, fabs(v[i]));
  return s;
}

/* Normwise backward error |b - A x|_inf / (|A|_inf |x|_inf + |b|_inf) of x
 * for the CSC matrix av over m's pattern (Rigal and Gaches: the smallest
 * relative perturbation of A and b of which x is the exact solution). */
static double backward_error(const pom_dyn_model *m, const double *av, double anorm,
                             const double *x, const double *b, double *r) {
  const int n = m->n_states;
  memcpy(r, b, (size_t)n * sizeof *r);
  for (int j = 0; j < n; ++j)
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k)
      r[m->rowind[k]] -= av[k] * x[j];
  return inf_norm(r, n) / (anorm * inf_norm(x, n) + inf_norm(b, n));
}

/* Componentwise backward error max_i |b - A x|_i / (|A| |x| + |b|)_i
 * (Oettli and Prager: the smallest relative perturbation of each entry of
 * A and b of which x is the exact solution); s is scratch. */
static double componentwise_error(const pom_dyn_model *m, const double *av, const double *x,
                                  const double *b, double *r, double *s) {
  const int n = m->n_states;
  for (int i = 0; i < n; ++i)
    r[i] = b[i], s[i] = fabs(b[i]);
  for (int j = 0; j < n; ++j)
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
      r[m->rowind[k]] -= av[k] * x[j];
      s[m->rowind[k]] += fabs(av[k] * x[j]);
    }
  double w = 0.0;
  for (int i = 0; i < n; ++i)
    if (s[i] > 0) w = fmax(w, fabs(r[i]) / s[i]);
  return w;
}

typedef enum { V_PLAIN, V_QUASISTATIC, V_LUMPED } variant;

typedef struct {
  double backward;        /* largest normwise backward error of the structured solve */
  double component;       /* largest componentwise backward error of the structured solve */
  double dense_component; /* the same of the dense LU */
  double ratio;           /* largest |x_s - x_d| / |x_d| over its bound 2 kappa (eta_s + eta_d) */
  double difference;      /* largest |x_s - x_d|_inf / |x_d|_inf */
  double kappa;           /* largest kappa_inf(A) met */
} solve_errors;

/* Random states of one configuration, gamma from 1e-7 to 1e-3 s, random
 * right-hand sides: the structured and the dense solutions. */
static solve_errors check_config(const char *file, pom_orient_kind orient, int computed_torque,
                                 variant v, uint64_t seed) {
  solve_errors e = {0};
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!check_true(load_shipped(file, &arch, &mech, &p))) return e;
  p.scene.orientation = orient;
  if (computed_torque) pom_dyn_ctrl_set_defaults(&p.controller, &pom_dyn_ctrl_computed_torque);
  if (v == V_QUASISTATIC) p.scene.coil_inductance = 0;
  if (v == V_LUMPED) p.scene.limb_inertia = POM_INERTIA_LUMPED;
  p.solver.atol_scale = 0.0; /* natural sizes: the random states' scale */
  p.solver.linear_solver = POM_LINSOL_STRUCTURED;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  N_Vector vy = NULL, vf = NULL, vx = NULL, vb = NULL, t1 = NULL, t2 = NULL, t3 = NULL;
  double *dense = NULL, *lu = NULL, *xd = NULL, *r = NULL, *inv = NULL, *sc = NULL;
  int *piv = NULL;
  if (!check_true(pom_dyn_model_create(&m, &mech, &arch, &p, &err) == POM_OK &&
                  pom_dyn_data_create(&d, m, &err) == POM_OK)) {
    printf("  %s: %s\n", file, err.message);
    goto done;
  }
  const int n = m->n_states;
  vy = N_VNew_Serial(n, d->ctx), vf = N_VNew_Serial(n, d->ctx), vx = N_VNew_Serial(n, d->ctx);
  vb = N_VNew_Serial(n, d->ctx), t1 = N_VNew_Serial(n, d->ctx), t2 = N_VNew_Serial(n, d->ctx);
  t3 = N_VNew_Serial(n, d->ctx);
  dense = calloc((size_t)n * (size_t)n, sizeof *dense);
  lu = calloc((size_t)n * (size_t)n, sizeof *lu);
  xd = calloc((size_t)n, sizeof *xd), r = calloc((size_t)n, sizeof *r);
  inv = calloc((size_t)n, sizeof *inv), piv = calloc((size_t)n, sizeof *piv);
  sc = calloc((size_t)n, sizeof *sc);
  if (!check_true(vy && vf && vx && vb && t1 && t2 && t3 && dense && lu && xd && r && inv && piv &&
                  sc))
    goto done;
  pom_dyn_sls_stats st;
  check_true(pom_dyn_structured_ls_stats(d->LS, &st) == 1);
  double *y = N_VGetArrayPointer(vy), *b = N_VGetArrayPointer(vb), *x = N_VGetArrayPointer(vx);
  const double gammas[] = {1e-7, 1e-6, 1e-5, 1e-4, 1e-3};
  for (int trial = 0; trial < 3; ++trial) {
    random_state(m, y, &seed);
    set_targets(m, d, y, &seed);
    pom_dyn_eval(m, d, y, N_VGetArrayPointer(vf));
    d->jac_valid = 0;
    for (int g = 0; g < 5; ++g) {
      sunbooleantype jcur = SUNFALSE;
      check_true(pom_dyn_cvode_linsys(0.0, vy, vf, d->A, g > 0, &jcur, gammas[g], d, t1, t2, t3) ==
                 0);
      const double *av = SUNSparseMatrix_Data(d->A);
      /* the dense copy, its infinity norm and condition number */
      memset(dense, 0, (size_t)n * (size_t)n * sizeof *dense);
      for (int j = 0; j < n; ++j)
        for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k)
          dense[(size_t)j * (size_t)n + (size_t)m->rowind[k]] = av[k];
      double anorm = 0.0;
      for (int i = 0; i < n; ++i) {
        double s = 0.0;
        for (int j = 0; j < n; ++j)
          s += fabs(dense[(size_t)j * (size_t)n + (size_t)i]);
        anorm = fmax(anorm, s);
      }
      memcpy(lu, dense, (size_t)n * (size_t)n * sizeof *lu);
      if (!check_true(dense_lu(lu, n, piv) == 0)) goto done;
      /* |A^-1|_inf: the largest row sum of the inverse, column by column */
      double rows[256] = {0};
      for (int j = 0; j < n && n <= 256; ++j) {
        memset(inv, 0, (size_t)n * sizeof *inv);
        inv[j] = 1.0;
        dense_solve(lu, n, piv, inv);
        for (int i = 0; i < n; ++i)
          rows[i] += fabs(inv[i]);
      }
      const double kappa = anorm * inf_norm(rows, n);
      e.kappa = fmax(e.kappa, kappa);
      check_true(SUNLinSolSetup(d->LS, d->A) == 0);
      for (int rhs = 0; rhs < 2; ++rhs) {
        for (int i = 0; i < n; ++i)
          b[i] = urand(&seed) * (rhs == 0 ? 1.0 : m->atol[i]); /* unit, then state-sized */
        memcpy(xd, b, (size_t)n * sizeof *xd);
        dense_solve(lu, n, piv, xd);
        check_true(SUNLinSolSolve(d->LS, d->A, vx, vb, 0.0) == 0);
        e.component = fmax(e.component, componentwise_error(m, av, x, b, r, sc));
        e.dense_component = fmax(e.dense_component, componentwise_error(m, av, xd, b, r, sc));
        const double eta_s = backward_error(m, av, anorm, x, b, r);
        const double eta_d = backward_error(m, av, anorm, xd, b, r);
        for (int i = 0; i < n; ++i)
          r[i] = x[i] - xd[i];
        const double diff = inf_norm(r, n) / inf_norm(xd, n);
        /* both solutions solve a problem perturbed by their eta: they
         * differ by at most ~kappa (eta_s + eta_d) relative (first order,
         * kappa eta << 1), doubled for the second-order terms */
        const double bound = 2.0 * kappa * (eta_s + eta_d) + 4.0 * EPS;
        e.backward = fmax(e.backward, eta_s);
        e.ratio = fmax(e.ratio, diff / bound);
        e.difference = fmax(e.difference, diff);
      }
    }
  }
  printf(
      "  %s %s %s%s: %d groups, %ld values, %.0f + %.0f flops; backward error %.2e, "
      "componentwise %.2e (dense LU %.2e), difference %.2e (%.2f of the bound), kappa up to %.1e\n",
      file, orient == POM_ORIENT_QUATERNION ? "quaternion" : "euler",
      computed_torque ? "computed-torque" : "pid",
      v == V_QUASISTATIC ? ", quasi-static coil"
      : v == V_LUMPED    ? ", lumped limbs"
                         : "",
      st.groups, st.values, st.setup_flops, st.solve_flops, e.backward, e.component,
      e.dense_component, e.difference, e.ratio, e.kappa);
  /* Backward error: a block LU with partial pivoting inside diagonal blocks
   * whose pivots are I (u), I - gamma dE/de (orientation) and blocks that
   * stay diagonally dominated by the mass terms has a growth of O(1): the
   * normwise backward error is then ~n eps = 2.5e-14 at worst, rounding
   * errors adding at random to ~sqrt(n) eps = 2e-15. Measured below 1e-16;
   * the bound 1e-14 is ~50 eps. A missing Schur update, a wrong pivot or a
   * lost fill entry gives errors of 1e-6 .. 1. */
  check_abs(e.backward, 0.0, 1e-14);
  /* Componentwise (Oettli-Prager): measured up to 3e-14, where the dense
   * LU with partial pivoting over all states reaches 1e-10 .. 2e-7 (its
   * pivots mix rows of unlike units); bound 1e-12, the KLU solve's bound in
   * tests/test_dyn_jacobian.c */
  check_abs(e.component, 0.0, 1e-12);
  /* the difference to the dense LU lies within what conditioning allows */
  check_true(e.ratio <= 1.0);
done:;
  N_Vector all[] = {vy, vf, vx, vb, t1, t2, t3};
  for (int k = 0; k < 7; ++k)
    if (all[k]) N_VDestroy(all[k]);
  free(dense), free(lu), free(xd), free(r), free(inv), free(piv), free(sc);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
  return e;
}

/* A maneuver with the structured solver gives KLU's metrics to the
 * integration's accuracy (the solves differ by rounding, which moves the
 * step sequence, not the solution beyond rtol). */
static void check_maneuver(const char *file, const double target[3]) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!check_true(load_shipped(file, &arch, &mech, &p))) return;
  run_t rs, rk;
  p.solver.linear_solver = POM_LINSOL_STRUCTURED;
  pom_status ss = run_arch(&rs, &mech, &arch, &p, target, NULL);
  p.solver.linear_solver = POM_LINSOL_KLU;
  pom_status sk = run_arch(&rk, &mech, &arch, &p, target, NULL);
  if (check_true(ss == POM_OK && sk == POM_OK)) {
    printf("  %s maneuver: structured %ld steps, %ld factorizations; KLU %ld steps, %ld "
           "factorizations\n",
           file, rs.mt.steps, rs.mt.linsol_setups, rk.mt.steps, rk.mt.linsol_setups);
    check_true(rs.m->par.solver.linear_solver == POM_LINSOL_STRUCTURED);
    check_true(rs.mt.linsol_setups > 0);
    /* rtol 1e-6 (shipped): energies within 1e-4 relative, settling times
     * within 1 us, final positions within 1 nm (docs/dynamics.md section 7,
     * accuracy at the shipped settings) */
    for (int a = 0; a < 3; ++a) {
      check_rel(rs.mt.energy[a], rk.mt.energy[a], 1e-4);
      check_abs(rs.mt.settling_time[a], rk.mt.settling_time[a], 1e-6);
      check_abs(rs.mt.final_q[a], rk.mt.final_q[a], 1e-9);
    }
    check_abs(rs.mt.execution_time, rk.mt.execution_time, 1e-6);
  }
  run_free(&rs);
  run_free(&rk);
}

int main(void) {
  static const char *files[] = {"3pss.cfg", "3sps.cfg", "3rrr.cfg"};
  uint64_t seed = 20;
  solve_errors worst = {0};
  for (int f = 0; f < 3; ++f)
    for (int o = 0; o < 2; ++o)
      for (int ct = 0; ct < 2; ++ct) {
        solve_errors e = check_config(files[f], o ? POM_ORIENT_QUATERNION : POM_ORIENT_EULER_ZYX,
                                      ct, V_PLAIN, seed++);
        worst.backward = fmax(worst.backward, e.backward);
        worst.component = fmax(worst.component, e.component);
      }
  for (int f = 0; f < 2; ++f) {
    check_config(files[f], POM_ORIENT_EULER_ZYX, 0, V_QUASISTATIC, seed++);
    check_config(files[f], POM_ORIENT_QUATERNION, 0, V_LUMPED, seed++);
  }
  printf("  largest backward error %.2e, componentwise %.2e\n", worst.backward, worst.component);
  check_true(strcmp(pom_dyn_linsol_name(POM_LINSOL_STRUCTURED), "structured") == 0);
  const double t1[3] = {3e-3, -3e-3, 3e-3};
  check_maneuver("3pss.cfg", t1);
  check_maneuver("3sps.cfg", t1);
  return check_summary("test_dyn_structured_ls");
}
