/* kin_fk.c - forward kinematics: Newton on SO(3) with the analytic Jacobian,
 * continued from home along a straight path in q when direct Newton fails
 * (docs/kinematics.md section 4). */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void pom_kin_fk_defaults(pom_kin_fk_opts *o) {
  o->residual_tol = 1e-12;
  o->max_iterations = 30;
  o->max_rotation = 0.3;
  o->initial_steps = 4;
  o->max_halvings = 16;
  o->singular_tol = 1e-10;
}

typedef enum {
  NEWTON_OK,
  NEWTON_UNREACHABLE,
  NEWTON_SINGULAR,
  NEWTON_BRANCH,
  NEWTON_MAXITER
} newton_result;

static const char *newton_text(newton_result r) {
  switch (r) {
  case NEWTON_OK:
    return "converged";
  case NEWTON_UNREACHABLE:
    return "an iterate could not be assembled";
  case NEWTON_SINGULAR:
    return "the Jacobian became singular";
  case NEWTON_BRANCH:
    return "an iterate crossed a singularity (det J changed sign): another assembly branch";
  default:
    return "the iteration limit was reached";
  }
}

/* Newton iteration R <- exp([delta]) R with J delta = q_target - q(R). R is
 * updated in place; *iters counts updates, *res gets the last residual. */
static newton_result newton(const pom_kin_arch *arch, const double target[3], double R[9],
                            const pom_kin_fk_opts *o, int *iters, double *res) {
  for (int it = 0;; ++it) {
    double q[3], J[9], r[3], sv[3];
    if (pom_kin_inverse_jacobian(arch, R, q, J, NULL) != POM_OK) return NEWTON_UNREACHABLE;
    double m = 0.0;
    for (int k = 0; k < 3; ++k) {
      r[k] = target[k] - q[k];
      m = fmax(m, fabs(r[k]));
    }
    *res = m;
    pom_kin_dexterity(J, sv, NULL, NULL);
    if (!(sv[2] > o->singular_tol * sv[0])) return NEWTON_SINGULAR;
    if (pom_m3_det(J) * arch->home_det_sign <= 0.0) return NEWTON_BRANCH;
    if (m <= o->residual_tol) return NEWTON_OK;
    if (it >= o->max_iterations) return NEWTON_MAXITER;
    double Ji[9], delta[3], Rn[9], E[9];
    if (pom_m3_inverse(Ji, J, 0.0) != POM_OK) return NEWTON_SINGULAR;
    pom_m3_apply(delta, Ji, r);
    double angle = pom_v3_norm(delta);
    if (!isfinite(angle)) return NEWTON_SINGULAR;
    if (angle > 0.0) {
      double axis[3];
      pom_v3_scale(axis, 1.0 / angle, delta);
      pom_m3_axis_angle(E, axis, fmin(angle, o->max_rotation));
      pom_m3_mul(Rn, E, R); /* omega is in the fixed frame: left multiplication */
      memcpy(R, Rn, sizeof Rn);
    }
    ++*iters;
  }
}

pom_status pom_kin_forward(const pom_kin_arch *arch, const double q[3], const double R_start[9],
                           const pom_kin_fk_opts *opts, double R[9], pom_kin_fk_info *info,
                           pom_error *err) {
  pom_kin_fk_opts o;
  if (opts) {
    o = *opts;
  } else {
    pom_kin_fk_defaults(&o);
  }
  if (!(o.residual_tol > 0.0) || o.max_iterations < 1 || !(o.max_rotation > 0.0) ||
      o.initial_steps < 1 || o.max_halvings < 0 || !(o.singular_tol >= 0.0))
    POM_FAIL(err, POM_ERR_ARG, "forward kinematics: invalid options");
  for (int k = 0; k < 3; ++k)
    if (!isfinite(q[k]))
      POM_FAIL(err, POM_ERR_NONFINITE, "forward kinematics: q[%d] is not finite", k);
  pom_kin_fk_info inf = {0, 0, INFINITY};
  double R0[9], Rc[9], q0[3];
  if (R_start) {
    memcpy(R0, R_start, sizeof R0);
  } else {
    pom_m3_identity(R0);
  }
  pom_status st = pom_kin_inverse(arch, R0, q0, err);
  if (st != POM_OK) return pom_error_prefix(err, "forward kinematics: start pose");

  /* 1. direct Newton from the start */
  memcpy(Rc, R0, sizeof Rc);
  newton_result nr = newton(arch, q, Rc, &o, &inf.iterations, &inf.residual);
  if (nr == NEWTON_OK) {
    memcpy(R, Rc, sizeof Rc);
    if (info) *info = inf;
    return POM_OK;
  }

  /* 2. continuation q(t) = q0 + t (q - q0), t: 0 -> 1 */
  double t = 0.0, dt = 1.0 / o.initial_steps;
  const double dt_min = ldexp(1.0 / o.initial_steps, -o.max_halvings);
  memcpy(Rc, R0, sizeof Rc);
  while (t < 1.0) {
    double tn = fmin(1.0, t + dt), qt[3], Rt[9];
    for (int k = 0; k < 3; ++k)
      qt[k] = q0[k] + tn * (q[k] - q0[k]);
    memcpy(Rt, Rc, sizeof Rt);
    nr = newton(arch, qt, Rt, &o, &inf.iterations, &inf.residual);
    if (nr == NEWTON_OK) {
      memcpy(Rc, Rt, sizeof Rc);
      t = tn;
      ++inf.continuation_steps;
      dt = fmin(2.0 * dt, 1.0 / o.initial_steps); /* recover after a hard stretch */
    } else {
      dt *= 0.5;
      if (dt < dt_min) {
        if (info) *info = inf;
        POM_FAIL(err, POM_ERR_NOCONVERGE,
                 "forward kinematics of q = (%.6g, %.6g, %.6g) mm: continuation stalled at "
                 "t = %.4f of the path from the start pose: %s (residual %.3g m after %d "
                 "iterations)",
                 q[0] * 1e3, q[1] * 1e3, q[2] * 1e3, t, newton_text(nr), inf.residual,
                 inf.iterations);
      }
    }
  }
  memcpy(R, Rc, sizeof Rc);
  if (info) *info = inf;
  return POM_OK;
}
