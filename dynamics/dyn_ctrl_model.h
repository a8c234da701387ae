/* dyn_ctrl_model.h - what the model-based controllers share (not a public
 * header): their own model of the nominal candidate (an exact model for M and
 * f, the architecture for the kinematics, the actuator for the coil's
 * inverse), per-worker scratch with the reference of the maneuver, and the
 * inverse dynamics from a desired angular acceleration to actuator efforts
 * (docs/control.md sections 2 and 3). */
#ifndef POM_DYN_CTRL_MODEL_H
#define POM_DYN_CTRL_MODEL_H

#include "pom_dyn_ctrl.h"

typedef struct {
  const pom_dyn_ctrl_engine *eng; /* the engine's services */
  pom_dyn_model *dyn;             /* exact (rigid) model of the nominal mechanism: M and f */
  pom_kin_arch arch;              /* nominal architecture: kinematics */
  pom_dyn_actuator act;           /* nominal actuator: the coil's inverse */
  int bearing;                    /* 1: the nominal scene has bearing friction */
} dyn_ctrl_model;

typedef struct {
  const pom_dyn_ctrl_engine *eng;
  pom_dyn_data *dd;   /* scratch of the controller's model */
  double target[3];   /* setpoints the reference belongs to */
  double R_set[9];    /* forward kinematics of the setpoints */
  double r_set[3];    /* its rotation vector (fixed frame, rad) */
  double R_last[9];   /* last measured rotation: the next forward kinematics' start */
  int have_ref;       /* 1 once R_set belongs to target */
  pom_kin_fk_opts fk; /* forward-kinematics options */
} dyn_ctrl_work;

/* model_create / model_destroy / work_create / work_destroy of a
 * model-based type; `who` names the type in messages. */
pom_status pom_dyn_ctrl_model_create(void **out, const pom_dyn_ctrl_engine *eng, const char *who,
                                     const pom_mechanism *mech, const pom_kin_arch *arch,
                                     const pom_dyn_params *p, pom_error *err);
void pom_dyn_ctrl_model_destroy(void *model);
pom_status pom_dyn_ctrl_work_create(void **out, const void *model, pom_error *err);
void pom_dyn_ctrl_work_destroy(void *work);

/* The reference of the maneuver: R_set = FK(setpoints), recomputed when the
 * setpoints change (a new maneuver, which starts at home). 0 when the
 * forward kinematics fails. */
int pom_dyn_ctrl_reference(const dyn_ctrl_model *cm, dyn_ctrl_work *w, const double target[3]);

/* Actuator efforts F[3] (N or N m) that give the platform the angular
 * acceleration alpha at rotation R and angular velocity w in the
 * controller's model: J^T F = M alpha - f. Also q and J there. 0 when the
 * mechanism cannot be assembled or J is singular. */
int pom_dyn_ctrl_inverse_dynamics(const dyn_ctrl_model *cm, dyn_ctrl_work *w, const double R[9],
                                  const double omega[3], const double alpha[3], double F[3],
                                  double q[3], double J[9]);

/* The voltage that drives effort F against the back-EMF and the bearing
 * friction at rate q_dot (the coil's inverse, quasi-static; V), and the
 * coil current it needs in *current (A; NULL: not wanted). */
double pom_dyn_ctrl_coil_voltage(const dyn_ctrl_model *cm, double F, double q_dot, double *current);

/* x = A^-1 b for a 3x3 A; 0 when singular. */
int pom_dyn_ctrl_solve3(double x[3], const double A[9], const double b[3]);

#endif
