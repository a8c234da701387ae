/* test_dyn_exact_jac.c - the exact path's Jacobian (docs/dynamics-exact.md
 * section 5): analytic orientation and omega columns where the architecture
 * has second-order kinematics (limb_twist_diff: the 3PSS, and whichever
 * others provide it), forward differences over them otherwise; analytic
 * coil-flux and PID-integral columns. Compared with central differences of
 * the right-hand side over random states of the 3PSS, 3SPS and 3RRR,
 * inductive and quasi-static coils, Euler angles and quaternions, with
 * saturated and unsaturated actuators; an analytic Jacobian must not
 * evaluate the right-hand side at all (d->jac_rhs_count). */
#include "check.h"
#include "dyn_internal.h"
#include "dyn_test_util.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_STATES_TESTED 12

/* Largest error of the Jacobian's entry (i, j) found so far, relative to its
 * tolerance, per column kind (0 mechanical, 1 electrical, 2 mechanical
 * analytic). */
static double worst[3];
static int analytic_models;
static int saturated_seen, linear_seen, kinks_skipped;

/* Random state: orientation within 0.08 rad of home, omega +-2 rad/s, coil
 * currents +-2 A, PID integrals that put the loop either inside its linear
 * band or in saturation. */
static void random_state(const pom_dyn_model *m, pom_rng *rng, double *y) {
  int ori, n_ori, omega;
  check_true(pom_dyn_exact_layout(m, &ori, &n_ori, &omega) == 1);
  memset(y, 0, (size_t)m->n_states * sizeof(double));
  double e[3], R[9];
  for (int k = 0; k < 3; ++k)
    e[k] = pom_rng_range(rng, -0.08, 0.08);
  if (n_ori == 4) {
    pom_euler_zyx_to_matrix(R, e);
    pom_quat_from_matrix(y + ori, R);
    for (int k = 0; k < 4; ++k) /* off the unit sphere: the state is normalized inside */
      y[ori + k] *= 1.0 + pom_rng_range(rng, -1e-3, 1e-3);
  } else {
    memcpy(y + ori, e, sizeof e);
  }
  for (int k = 0; k < 3; ++k)
    y[omega + k] = pom_rng_range(rng, -2.0, 2.0);
  for (int a = 0; a < m->n_actuators; ++a) {
    const dyn_actuator *ac = &m->act[a];
    if (ac->flux_state >= 0)
      y[ac->flux_state] = m->par.actuator.inductance * pom_rng_range(rng, -2.0, 2.0);
    y[ac->ctrl_state] = m->scale[ac->ctrl_state] * pom_rng_range(rng, -3.0, 3.0);
  }
}

/* Drives actuator a's raw voltage to u_raw at state y by its target (the
 * law is affine in the target with slope S K_P), so that both sides of the
 * saturation are exercised. */
static void set_target_for(pom_dyn_model *m, pom_dyn_data *d, const double *y, int a,
                           double u_raw) {
  d->target[a] = 0.0;
  pom_dyn_eval(m, d, y, NULL);
  double q = d->out.q[a], qd = d->out.q_dot[a];
  const pom_dyn_actuator *ap = &m->par.actuator;
  const pom_dyn_controller *cp = &m->par.controller;
  double z = y[m->act[a].ctrl_state];
  /* u_raw = S K_P (e + K_I z - K_D qd) (ideal) or S (K_P e + K_I z - K_D qd) */
  double rest =
      cp->form == POM_PID_IDEAL ? cp->kp * (cp->ki * z - cp->kd * qd) : cp->ki * z - cp->kd * qd;
  d->target[a] = q + (u_raw / ap->sensor_gain - rest) / cp->kp;
}

/* 1 for the rows whose law has a kink inside a step: the positive part of the
 * source power and the saturation indicator (a step function). */
static int kink_row(const pom_dyn_model *m, int i) {
  for (int a = 0; a < m->n_actuators; ++a) {
    int r = i - m->act[a].acc_state;
    if (r == DYN_ACC_SOURCE_POS || r == DYN_ACC_SATURATED) return 1;
  }
  return 0;
}

/* Both values on the same branch of max(x, 0) or of the indicator. */
static int same_branch(double a, double b) {
  return (a > 0) == (b > 0) && (a == 0) == (b == 0);
}

/* Central difference of the RHS along column j with step h. */
static void central_column(pom_dyn_model *m, pom_dyn_data *d, const double *y, int j, double h,
                           double *yp, double *fp, double *fm, double *col) {
  const int n = m->n_states;
  memcpy(yp, y, (size_t)n * sizeof(double));
  yp[j] = y[j] + h;
  check_true(pom_dyn_eval(m, d, yp, fp) == 0);
  yp[j] = y[j] - h;
  check_true(pom_dyn_eval(m, d, yp, fm) == 0);
  for (int i = 0; i < n; ++i)
    col[i] = (fp[i] - fm[i]) / (2.0 * h);
}

static void check_model(const char *label, const pom_kin_arch *arch, const pom_mechanism *mech,
                        const pom_dyn_params *p0, int inductive, pom_orient_kind orient) {
  pom_dyn_params p = *p0;
  p.joints.model = POM_JOINTS_RIGID;
  p.scene.coil_inductance = inductive;
  p.scene.orientation = orient;
  pom_error err;
  pom_dyn_model *m = NULL;
  pom_dyn_data *d = NULL;
  if (pom_dyn_model_create(&m, mech, arch, &p, &err) != POM_OK ||
      pom_dyn_data_create(&d, m, &err) != POM_OK) {
    printf("%s: %s\n", label, err.message);
    check_true(0);
    pom_dyn_data_destroy(d);
    pom_dyn_model_destroy(m);
    return;
  }
  const int n = m->n_states;
  int ori, n_ori, omega;
  check_true(pom_dyn_exact_layout(m, &ori, &n_ori, &omega) == 1);
  const int n_mech = n_ori + 3;
  double *y = calloc((size_t)n, sizeof *y), *f0 = calloc((size_t)n, sizeof *f0);
  double *yp = calloc((size_t)n, sizeof *yp), *fp = calloc((size_t)n, sizeof *fp);
  double *fm = calloc((size_t)n, sizeof *fm), *col = calloc((size_t)n, sizeof *col);
  double *jac = calloc((size_t)m->nnz, sizeof *jac);
  pom_rng rng;
  pom_rng_seed(&rng, 2385, (uint64_t)(100 * inductive + (int)orient));
  const double lim = p.actuator.voltage_limit;
  double local[3] = {0.0, 0.0, 0.0};
  double *col2 = calloc((size_t)n, sizeof *col2);
  const int analytic = pom_kin_has_twists_diff(arch);
  analytic_models += analytic;
  for (int s = 0; s < N_STATES_TESTED; ++s) {
    random_state(m, &rng, y);
    /* actuator 0 inside the linear band, the others saturated or not by turns */
    for (int a = 0; a < m->n_actuators; ++a) {
      double u_raw = a == 0 ? pom_rng_range(&rng, -0.5, 0.5) * lim
                            : ((s + a) % 2 ? 3.0 : 0.4) * lim * (a == 1 ? 1.0 : -1.0);
      set_target_for(m, d, y, a, u_raw);
    }
    check_true(pom_dyn_eval(m, d, y, f0) == 0);
    for (int a = 0; a < m->n_actuators; ++a) {
      if (fabs(d->out.voltage[a]) < lim)
        ++linear_seen;
      else
        ++saturated_seen;
    }
    const long rhs_before = d->jac_rhs_count;
    check_true(pom_dyn_exact_jacobian(d, y, f0, yp, fp) == 0);
    /* analytic: no right-hand side evaluated (forward differences: one per
     * mechanical column) */
    check_true(d->jac_rhs_count - rhs_before == (analytic ? 0 : n_mech));
    memcpy(jac, d->jac, (size_t)m->nnz * sizeof *jac);
    for (int j = 0; j < n; ++j) {
      int kind = j < n_mech ? (analytic ? 2 : 0) : 1;
      if (kind == 2) {
        /* analytic mechanical column: central differences at h and 2h,
         * h = 1e-6 of the state's size (a 5e-8 rad step moves q by ~1.5 nm
         * and u by ~15 mV: inside one branch of the loop). Their difference
         * bounds the error of the one at h: the truncation c h^2 of D(h)
         * is a third of D(2h) - D(h), and the rounding eps |f| / h of both
         * (the IK's q carries a rounding of ~eps L, which the loop's gain
         * makes ~1e-7 of these columns at this h) enters it at its own
         * size; a wrong analytic entry does not depend on h and is not in
         * it. Tolerance: 1e-6 relative plus twice that difference plus the
         * rounding of f itself. */
        double h = 1e-5 * fmax(fabs(y[j]), m->scale[j]);
        central_column(m, d, y, j, 2.0 * h, yp, fp, fm, col2);
        central_column(m, d, y, j, h, yp, fp, fm, col);
        for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
          int i = m->rowind[k];
          if (kink_row(m, i) && !(same_branch(f0[i], fp[i]) && same_branch(f0[i], fm[i]))) {
            ++kinks_skipped;
            continue;
          }
          double ref = col[i];
          double tol = 1e-6 * fabs(ref) + 2.0 * fabs(col2[i] - col[i]) +
                       100.0 * 2.220446049250313e-16 * (fabs(fp[i]) + fabs(fm[i])) / h + 1e-300;
          double e = fabs(jac[k] - ref) / tol;
          if (e > local[2]) local[2] = e;
          if (e > 1.0)
            printf("  %s state %d: J[%d][%d] = %.9g, central %.9g (tol %.2g)\n", label, s, i, j,
                   jac[k], ref, tol);
        }
        continue;
      }
      /* reference step: central differences are exact for the electrical
       * columns up to rounding (omega_dot, coil and PID rows are affine in z
       * and the flux, the accumulators quadratic: 1e-4 of the scale); for the
       * mechanical columns 1e-7 of it keeps the step inside one branch of the
       * loop (S K_P ~ 1e7 V/m: an 8e-9 rad step moves u by ~4 mV) with a
       * truncation error h^2 f''' / 6 far below the forward differences' own
       * error (below) */
      double h = (kind == 0 ? 1e-7 : 1e-4) * fmax(fabs(y[j]), m->scale[j]);
      central_column(m, d, y, j, h, yp, fp, fm, col);
      /* the Jacobian's forward step (dyn_fdjac.c) and its rounding error: each
       * f is computed with an absolute error of a few eps times the largest
       * term that cancels in it; 1e-7 |f_i| / h_fd bounds it with a margin of
       * ~50 over sqrt(eps) |f_i| / h_fd = eps |f_i| / (sqrt(eps) scale) */
      double h_fd = sqrt(2.220446049250313e-16) * fmax(fabs(y[j]), m->scale[j]);
      for (long k = m->colptr[j]; k < m->colptr[j + 1]; ++k) {
        int i = m->rowind[k];
        if (kink_row(m, i) && !(same_branch(f0[i], fp[i]) && same_branch(f0[i], fm[i]))) {
          ++kinks_skipped; /* the positive part or the indicator switched within h */
          continue;
        }
        double ref = m->dep[(size_t)i * (size_t)n + (size_t)j] ? col[i] : 0.0;
        double noise = (kind == 0 ? 1e-7 : 1e-11) * (fabs(f0[i]) + fabs(fp[i])) / h_fd;
        /* its truncation error h_fd |f''| / 2 (the accumulator rows are
         * quadratic in u, whose slope S K_P J ~ 5e5 V/rad makes f'' large),
         * f'' from the same three evaluations; bounded with a factor 2 */
        double f2 = (fp[i] + fm[i] - 2.0 * f0[i]) / (h * h);
        double trunc = kind == 0 ? h_fd * fabs(f2) : 0.0;
        double tol = 1e-6 * fabs(ref) + noise + trunc + 1e-300;
        double e = fabs(jac[k] - ref) / tol;
        if (e > local[kind]) local[kind] = e;
        if (e > 1.0)
          printf("  %s state %d: J[%d][%d] = %.9g, central %.9g (tol %.2g)\n", label, s, i, j,
                 jac[k], ref, tol);
      }
    }
  }
  printf("%s: worst error / tolerance: mechanical columns %.3g (%s), electrical columns %.3g\n",
         label, analytic ? local[2] : local[0], analytic ? "analytic" : "differenced", local[1]);
  check_true(local[0] <= 1.0 && local[1] <= 1.0 && local[2] <= 1.0);
  for (int k = 0; k < 3; ++k)
    worst[k] = fmax(worst[k], local[k]);
  free(col2);
  free(y);
  free(f0);
  free(yp);
  free(fp);
  free(fm);
  free(col);
  free(jac);
  pom_dyn_data_destroy(d);
  pom_dyn_model_destroy(m);
}

int main(void) {
  static const char *files[] = {"3pss.cfg", "3sps.cfg", "3rrr.cfg"};
  for (int f = 0; f < 3; ++f) {
    pom_kin_arch arch;
    pom_mechanism *mech = calloc(1, sizeof *mech);
    pom_dyn_params p;
    if (!mech || !load_shipped(files[f], &arch, mech, &p)) {
      check_true(0);
      free(mech);
      continue;
    }
    char label[64];
    for (int ind = 0; ind < 2; ++ind)
      for (int o = 0; o < 2; ++o) {
        snprintf(label, sizeof label, "%s %s %s", files[f], ind ? "inductive" : "quasi-static",
                 o ? "quaternion" : "euler");
        check_model(label, &arch, mech, &p, ind, o ? POM_ORIENT_QUATERNION : POM_ORIENT_EULER_ZYX);
      }
    free(mech);
  }
  printf("worst: mechanical differenced %.3g, analytic %.3g, electrical %.3g; actuator states "
         "linear %d, saturated %d; entries across a kink skipped %d\n",
         worst[0], worst[2], worst[1], linear_seen, saturated_seen, kinks_skipped);
  check_true(linear_seen > 0 && saturated_seen > 0);
  /* the 3PSS has second-order kinematics: its four models went analytically */
  check_true(analytic_models >= 4);
  return check_summary("test_dyn_exact_jac");
}
