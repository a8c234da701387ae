/* pom_dyn_rigid.h - the rigid (exact-constraint) model's terms at one pose, for
 * the analyses that need the equations of motion rather than a simulation
 * (capability/, docs/capability.md section 1): Kane's
 *   M(R) w_dot = g(R) + h(R, w) + J(R)^T F
 * with the actuator efforts F (N, or N m for rotary actuators). The same code
 * as the right-hand side of the rigid path (dyn_exact.c), not a copy. */
#ifndef POM_DYN_RIGID_H
#define POM_DYN_RIGID_H

#include "pom_dynamics.h"

/* The rigid model's terms at platform rotation R and angular velocity w. */
typedef struct {
  double M[9];        /* mass matrix (kg m^2), row-major, symmetric positive definite */
  double gravity[3];  /* generalized force of gravity g(R) (N m, fixed frame) */
  double velocity[3]; /* velocity-product terms h(R, w) (N m; centripetal, Coriolis, gyroscopic) */
  double q[3];        /* actuator coordinates (m or rad), actuator order */
  double J[9];        /* q_dot = J w, row a for actuator a (m/rad or rad/rad) */
} pom_dyn_rigid_terms;

/* 1 when m integrates the rigid (exact-constraint) formulation, 0 otherwise. */
int pom_dyn_model_is_rigid(const pom_dyn_model *m);

/* The terms of m at rotation R (from home, fixed frame) and angular velocity
 * w (rad/s, fixed frame; NULL = rest), using d's scratch. POM_ERR_ARG when m
 * is not rigid or has fewer than 3 actuators; POM_ERR_UNREACHABLE when the
 * mechanism cannot be assembled at R; POM_ERR_NONFINITE for a non-finite
 * term. */
pom_status pom_dyn_rigid_terms_at(const pom_dyn_model *m, pom_dyn_data *d, const double R[9],
                                  const double w[3], pom_dyn_rigid_terms *out, pom_error *err);

#endif
