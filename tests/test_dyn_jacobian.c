/* test_dyn_jacobian.c - the parasitic path's analytic Jacobian
 * (dynamics/dyn_parasitic_deriv.c, docs/dynamics.md section 7) against
 * finite differences at random states: the coloured forward differences CVODE
 * used before (dyn_fdjac.c) and one-column central differences, for the
 * 3P-S-S/S, 3S-P-S/S and 3-RRR (rotary actuators) and the scene variants
 * that change the equations (quaternions, quasi-static coil, parallel PID,
 * lumped limbs with rods and pinned bodies), with actuators both inside the
 * controller's linear band and saturated. */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"

#include <math.h>
#include <sundials/sundials_linearsolver.h>
#include <sunmatrix/sunmatrix_sparse.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* fixed-seed uniform numbers in (-1, 1) */
static double urand(uint64_t *s) {
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) / 4503599627370496.0 - 1.0;
}

/* A random state: every component at up to its natural size (the sizes of
 * docs 7: deflections then reach ~1 mm, forces ~1e3 N), orientations up to
 * 0.2 rad, a quaternion off unit length. */
static void random_state(const pom_dyn_model *m, double *y, uint64_t *seed) {
  const double rtol = m->par.solver.rtol;
  for (int i = 0; i < m->n_states; ++i)
    y[i] = (m->atol[i] / rtol) * urand(seed); /* atol = rtol x natural size */
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

/* Targets that put actuator 0 inside the linear band (u_raw = 0.3 limit)
 * and the others in saturation (+ and -). */
static void set_targets(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  const pom_dyn_params *p = &m->par;
  memset(d->target, 0, sizeof d->target);
  pom_dyn_eval(m, d, y, NULL);
  for (int a = 0; a < m->n_actuators; ++a) {
    double q = d->out.q[a], qd = d->out.q_dot[a], z = y[m->act[a].ctrl_state];
    double S = p->actuator.sensor_gain, kp = p->controller.kp, ki = p->controller.ki,
           kd = p->controller.kd;
    if (a == 0) {
      double u = 0.3 * p->actuator.voltage_limit;
      /* e such that u_raw = u */
      d->target[a] = p->controller.form == POM_PID_IDEAL ? q + u / (S * kp) - ki * z + kd * qd
                                                         : q + (u / S - ki * z + kd * qd) / kp;
    } else {
      d->target[a] = q + (a == 1 ? 1e-3 : -1e-3);
    }
  }
}

typedef struct {
  double fd;      /* worst scaled difference to the coloured forward differences */
  double central; /* worst scaled difference to central differences */
} jac_errors;

/* Compares the analytic Jacobian at y with both finite-difference Jacobians.
 * Entries are scaled by the column's state size and the row's largest
 * scaled entry: |dJ_ij| s_j / max_k |J_ik| s_k, s_j = max(|y_j|, scale_j),
 * the maximum taken over the rows of the same body and kind. */
static jac_errors compare_at(const pom_dyn_model *m, pom_dyn_data *d, const double *y) {
  const int n = m->n_states;
  const long nnz = m->nnz;
  jac_errors e = {0.0, 0.0};
  double *ja = calloc((size_t)nnz, sizeof *ja), *jf = calloc((size_t)nnz, sizeof *jf);
  double *jc = calloc((size_t)nnz, sizeof *jc), *rowmax = calloc((size_t)n, sizeof *rowmax);
  double *fmag = calloc((size_t)n, sizeof *fmag);
  double *f0 = calloc((size_t)n, sizeof *f0), *yp = calloc((size_t)n, sizeof *yp);
  double *fp = calloc((size_t)n, sizeof *fp), *fm = calloc((size_t)n, sizeof *fm);
  if (!check_true(ja && jf && jc && rowmax && fmag && f0 && yp && fp && fm)) goto done;
  check_true(pom_dyn_parasitic_jacobian(m, d, y, ja) == 0);
  check_true(pom_dyn_eval(m, d, y, f0) == 0);
  check_true(pom_dyn_fd_jacobian(d, y, f0, yp, fp) == 0);
  memcpy(jf, d->jac, (size_t)nnz * sizeof *jf);
  /* central differences, one column at a time, h = eps^(1/3) s_j */
  memcpy(yp, y, (size_t)n * sizeof *yp);
  for (int j = 0; j < n; ++j) {
    double s = fmax(fabs(y[j]), m->scale[j]), h = 6.055e-6 * s;
    yp[j] = y[j] + h;
    pom_dyn_eval(m, d, yp, fp);
    yp[j] = y[j] - h;
    pom_dyn_eval(m, d, yp, fm);
    yp[j] = y[j];
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
      int i = m->rowind[k];
      jc[k] = m->dep[(size_t)i * (size_t)n + (size_t)j] ? (fp[i] - fm[i]) / (2.0 * h) : 0.0;
      rowmax[i] = fmax(rowmax[i], fabs(jc[k]) * s);
    }
  }
  /* a body's three rows of one kind (u, p, h', orientation) share their
   * scale: a 3-vector's components mix under rotation, and the axial h' row
   * of a slender link is a cancellation of large torques */
  const int nbs = m->n_bodies * m->body_states;
  for (int i = 0; i < n; ++i)
    fmag[i] = fabs(f0[i]);
  for (int i0 = 0; i0 < nbs; i0 += 3) {
    int len = (i0 % m->body_states) == DYN_BODY_ORI ? m->body_states - DYN_BODY_ORI : 3;
    double g = 0.0, gf = 0.0;
    for (int i = i0; i < i0 + len; ++i)
      g = fmax(g, rowmax[i]), gf = fmax(gf, fmag[i]);
    for (int i = i0; i < i0 + len; ++i)
      rowmax[i] = g, fmag[i] = gf;
    i0 += len - 3;
  }
  for (int j = 0; j < n; ++j) {
    double s = fmax(fabs(y[j]), m->scale[j]);
    for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
      int i = m->rowind[k];
      if (!(rowmax[i] > 0)) continue; /* a row that depends on nothing */
      /* forward differences round off by eps |f_i| / h: scaled by the row's
       * values too */
      e.fd = fmax(e.fd, fabs(ja[k] - jf[k]) * s / fmax(rowmax[i], fmag[i]));
      e.central = fmax(e.central, fabs(ja[k] - jc[k]) * s / rowmax[i]);
    }
  }
done:
  free(ja), free(jf), free(jc), free(rowmax), free(fmag), free(f0), free(yp), free(fp), free(fm);
  return e;
}

typedef enum { V_PLAIN, V_QUAT_QUASISTATIC_PARALLEL, V_LUMPED, V_SOFT, V_SWAPPED } variant;

static void check_config(const char *file, variant v, uint64_t seed) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!check_true(load_shipped(file, &arch, &mech, &p))) return;
  const char *what = "shipped scene";
  if (v == V_QUAT_QUASISTATIC_PARALLEL) {
    p.scene.orientation = POM_ORIENT_QUATERNION;
    p.scene.coil_inductance = 0;
    p.controller.form = POM_PID_PARALLEL;
    p.controller.ki = 2.385;
    what = "quaternion, quasi-static coil, parallel PID";
  } else if (v == V_LUMPED) {
    p.scene.limb_inertia = POM_INERTIA_LUMPED;
    what = "lumped limbs";
  } else if (v == V_SOFT || v == V_SWAPPED) {
    /* soft joints: the spring and damper terms no longer dwarf the
     * gyroscopic, orientation and coil terms in their rows */
    p.joints.stiffness = 10.0;
    p.joints.damping = 0.1;
    p.joints.angular_stiffness = 1e-2;
    p.joints.angular_damping = 1e-4;
    what = "soft joints";
  }
  if (v == V_SWAPPED) {
    /* every joint's sides swapped: an actuated joint's side 0 is then the
     * moving body (the ground carries no orientation columns) */
    for (int j = 0; j < mech.n_joints; ++j) {
      int b = mech.joint[j].body[0];
      mech.joint[j].body[0] = mech.joint[j].body[1];
      mech.joint[j].body[1] = b;
    }
    what = "joint sides swapped, soft joints";
  }
  p.solver.atol_scale = 0.0; /* natural sizes: the random states' scale */
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  double *y = NULL;
  if (!check_true(pom_dyn_model_create(&m, &mech, &arch, &p, &err) == POM_OK &&
                  pom_dyn_data_create(&d, m, &err) == POM_OK)) {
    printf("  %s: %s\n", file, err.message);
    goto done;
  }
  y = calloc((size_t)m->n_states, sizeof *y);
  if (!check_true(y != NULL)) goto done;
  jac_errors worst = {0.0, 0.0};
  for (int trial = 0; trial < 4; ++trial) {
    random_state(m, y, &seed);
    set_targets(m, d, y);
    jac_errors e = compare_at(m, d, y);
    worst.fd = fmax(worst.fd, e.fd);
    worst.central = fmax(worst.central, e.central);
  }
  printf("  %s, %s: analytic vs forward differences %.2e, vs central %.2e\n", file, what, worst.fd,
         worst.central);
  /* Central differences with h = eps^(1/3) s_j: truncation and rounding
   * ~eps^(2/3) = 4e-11 times |f_i| over the row's scaled entries (up to
   * ~1e3 where a row sums 1e3 N spring forces that cancel): measured up to
   * 7e-9, bound 1e-6. The forward differences CVODE used (h = sqrt(eps)
   * s_j) are less accurate: the articulation points lie ~0.3 m from the
   * origin, so their coordinates round by eps x 0.3 m = 7e-17 m against
   * increments down to 1.5e-8 x 1e-5 m: measured up to 2.6e-6 of the row's
   * scale (the larger of its scaled entries and its values), bound 1e-5.
   * Both lie far below any real slip: a wrong or missing term is of order
   * 1e-3..1 of its row. */
  check_abs(worst.fd, 0.0, 1e-5);
  check_abs(worst.central, 0.0, 1e-6);
done:
  free(y);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* The Newton matrix A = I - gamma J through the worker's KLU solver (no row
 * scaling, pivots chosen at the first factorization and kept by the
 * refactorizations, as in a run): the residual of A x = b relative to
 * |A| |x| + |b| stays at rounding level while gamma grows 1e6-fold after the
 * first factorization, at a random state of the shipped 3S-P-S/S. */
static void check_newton_solve(void) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!check_true(load_shipped("3sps.cfg", &arch, &mech, &p))) return;
  p.solver.atol_scale = 0.0;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  pom_error err;
  pom_error_clear(&err);
  N_Vector vy = NULL, vf = NULL, vx = NULL, vb = NULL, t1 = NULL, t2 = NULL, t3 = NULL;
  if (!check_true(pom_dyn_model_create(&m, &mech, &arch, &p, &err) == POM_OK &&
                  pom_dyn_data_create(&d, m, &err) == POM_OK))
    goto done;
  const int n = m->n_states;
  vy = N_VNew_Serial(n, d->ctx), vf = N_VNew_Serial(n, d->ctx), vx = N_VNew_Serial(n, d->ctx);
  vb = N_VNew_Serial(n, d->ctx), t1 = N_VNew_Serial(n, d->ctx), t2 = N_VNew_Serial(n, d->ctx);
  t3 = N_VNew_Serial(n, d->ctx);
  if (!check_true(vy && vf && vx && vb && t1 && t2 && t3)) goto done;
  uint64_t seed = 97;
  double *y = N_VGetArrayPointer(vy), *b = N_VGetArrayPointer(vb), *x = N_VGetArrayPointer(vx);
  random_state(m, y, &seed);
  set_targets(m, d, y);
  pom_dyn_eval(m, d, y, N_VGetArrayPointer(vf));
  const double gammas[] = {1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2};
  double worst = 0.0;
  for (int g = 0; g < 7; ++g) {
    sunbooleantype jcur = SUNFALSE;
    check_true(pom_dyn_cvode_linsys(0.0, vy, vf, d->A, g > 0, &jcur, gammas[g], d, t1, t2, t3) ==
               0);
    check_true(SUNLinSolSetup(d->LS, d->A) == 0);
    for (int i = 0; i < n; ++i)
      b[i] = urand(&seed);
    check_true(SUNLinSolSolve(d->LS, d->A, vx, vb, 0.0) == 0);
    /* r = b - A x over the CSC values of A, against |A| |x| + |b| */
    double *av = SUNSparseMatrix_Data(d->A), *r = N_VGetArrayPointer(t1),
           *s = N_VGetArrayPointer(t2);
    for (int i = 0; i < n; ++i)
      r[i] = b[i], s[i] = fabs(b[i]);
    for (int j = 0; j < n; ++j)
      for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
        r[m->rowind[k]] -= av[k] * x[j];
        s[m->rowind[k]] += fabs(av[k] * x[j]);
      }
    for (int i = 0; i < n; ++i)
      worst = fmax(worst, fabs(r[i]) / s[i]);
  }
  /* measured 1.8e-14 (at gamma 1e-2; 5e-16 up to 1e-4): the fixed pivots
   * stay backward stable; 1e-12 is a modest multiple of that */
  printf("  Newton solve: largest componentwise backward error %.2e\n", worst);
  check_abs(worst, 0.0, 1e-12);
done:
  if (!m || !d) printf("  %s\n", err.message);
  N_Vector all[] = {vy, vf, vx, vb, t1, t2, t3};
  for (int k = 0; k < 7; ++k)
    if (all[k]) N_VDestroy(all[k]);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

/* A maneuver with the analytic Jacobian gives the finite-difference run's
 * results to the integration's accuracy. */
static void check_maneuver(void) {
  pom_kin_arch arch;
  pom_mechanism mech;
  pom_dyn_params p;
  if (!check_true(load_shipped("3pss.cfg", &arch, &mech, &p))) return;
  const double target[3] = {3e-3, -3e-3, 3e-3};
  run_t ra, rf;
  p.solver.jacobian = POM_JAC_ANALYTIC;
  pom_status sa = run(&ra, &mech, &p, target, NULL);
  p.solver.jacobian = POM_JAC_FINITE_DIFFERENCE;
  pom_status sf = run(&rf, &mech, &p, target, NULL);
  if (check_true(sa == POM_OK && sf == POM_OK)) {
    printf("  3pss maneuver: analytic %ld steps, %ld RHS; finite differences %ld steps, %ld RHS\n",
           ra.mt.steps, ra.mt.rhs_evals, rf.mt.steps, rf.mt.rhs_evals);
    /* no RHS spent on Jacobians */
    check_true(ra.mt.jac_rhs_evals == 0 && rf.mt.jac_rhs_evals > 0);
    /* the two runs differ by the integration error (rtol 1e-6): energies
     * within 1e-4 relative, settling times within 1 us */
    for (int a = 0; a < 3; ++a) {
      check_rel(ra.mt.energy[a], rf.mt.energy[a], 1e-4);
      check_abs(ra.mt.settling_time[a], rf.mt.settling_time[a], 1e-6);
    }
  }
  run_free(&ra);
  run_free(&rf);
}

int main(void) {
  static const struct {
    const char *file;
    variant v;
  } cases[] = {
      {"3pss.cfg", V_PLAIN},
      {"3sps.cfg", V_PLAIN},
      {"3rrr.cfg", V_PLAIN},
      {"3pss.cfg", V_QUAT_QUASISTATIC_PARALLEL},
      {"3sps.cfg", V_QUAT_QUASISTATIC_PARALLEL},
      {"3rrr.cfg", V_QUAT_QUASISTATIC_PARALLEL},
      {"3pss.cfg", V_LUMPED},
      {"3sps.cfg", V_LUMPED},
      {"3pss.cfg", V_SOFT},
      {"3sps.cfg", V_SOFT},
      {"3rrr.cfg", V_SOFT},
      {"3pss.cfg", V_SWAPPED},
      {"3rrr.cfg", V_SWAPPED},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k)
    check_config(cases[k].file, cases[k].v, 11 + k);
  check_newton_solve();
  check_maneuver();
  return check_summary("test_dyn_jacobian");
}
