/* dyn_internal.h - model and data layout shared by the files of dynamics/
 * (not a public header). The model is the bond graph of docs/dynamics.md
 * flattened into arrays; the data holds one worker's CVODE objects and
 * scratch, all allocated at create time. */
#ifndef POM_DYN_INTERNAL_H
#define POM_DYN_INTERNAL_H

#include "pom_dynamics.h"
#include "pom_kinematics.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

/* states per body: displacement u (3), momentum p (3), principal angular
 * momentum h' (3), orientation (3 Euler angles or 4 quaternion components) */
#define DYN_BODY_U   0
#define DYN_BODY_P   3
#define DYN_BODY_H   6
#define DYN_BODY_ORI 9

/* energy accumulators per actuator (docs/dynamics.md section 6) */
enum {
  DYN_ACC_SOURCE = 0, /* int u i dt */
  DYN_ACC_SOURCE_POS, /* int max(u i, 0) dt */
  DYN_ACC_SATURATED,  /* int [|u_raw| >= limit] dt */
  DYN_ACC_COIL,       /* int R_c i^2 dt */
  DYN_ACC_BEARING,    /* int b q_dot^2 dt */
  DYN_ACC_PER_ACT
};

typedef struct {
  int mech_index;      /* index in the mechanism */
  int offset;          /* first state index */
  double mass;         /* kg */
  double principal[3]; /* principal moments (kg m^2) */
  double V[9];         /* principal axes at home (columns, fixed frame), det +1 */
  double cm_home[3];   /* CM at home (m); the pivot of a pinned body */
  /* scene.limb_inertia = lumped (docs/dynamics.md section 13) */
  int pinned;         /* 1: turns about the fixed point cm_home (u, p frozen at 0), principal
                         moments about that point */
  double grav_arm[3]; /* true CM minus cm_home at home, fixed frame (m); weight acts there */
} dyn_body;

#define DYN_MAX_LIN 3
#define DYN_MAX_ANG 3

typedef struct {
  pom_joint_type type;
  int slot[2];                    /* model body slot of each side, -1 for the ground */
  double rho[2][3];               /* joint point minus CM at home, fixed axes at home (m) */
  int n_lin;                      /* linear pseudo-constraints */
  int lin_rotates;                /* 1: directions fixed in side 0 (prismatic); 0: fixed frame */
  double lin_dir[DYN_MAX_LIN][3]; /* directions at home (unit) */
  int n_ang;                      /* angular pseudo-constraints g = (R0 e).(R1 h) */
  double ang_e[DYN_MAX_ANG][3];   /* vector fixed in side 0, home */
  double ang_h[DYN_MAX_ANG][3];   /* vector fixed in side 1, home, e.h = 0 */
  double axis[3];                 /* prismatic axis at home (unit) */
  int actuator;                   /* model actuator index, -1 passive */
  /* massless rod of a lumped binary link (docs/dynamics.md section 13): one linear
   * pseudo-constraint |p1 - p0| - length, no other constraint */
  int distance;  /* 1 for a rod */
  double length; /* rest length of the rod (m) */
} dyn_joint;

typedef struct {
  int joint;      /* model joint index (prismatic) */
  int flux_state; /* state index of the coil flux linkage, -1 when quasi-static */
  int int_state;  /* state index of the PID integral */
  int acc_state;  /* first of DYN_ACC_PER_ACT accumulator states */
  double stroke;  /* total stroke (m), targets within +-stroke/2; 0 = not limited */
} dyn_actuator;

/* Exact-constraint (rigid-joint) path in minimal coordinates, dyn_exact.c
 * (docs/dynamics-exact.md). Bodies use the model's body[] slots (mass,
 * principal moments, cm_home, mech_index); offsets are unused. */
typedef struct {
  pom_kin_arch arch;                      /* geometry the body poses come from */
  int platform_mech;                      /* mechanism index of the platform */
  int n_ori;                              /* orientation states: 3 (ZYX Euler) or 4 (quaternion) */
  int ori;                                /* first orientation state */
  int omega;                              /* first state of omega (platform, fixed frame, rad/s) */
  int n_jac;                              /* leading states with Jacobian columns */
  int act_limb[POM_MECH_MAX_ACTUATORS];   /* kinematic limb (q index) of each actuator */
  double inertia[POM_MECH_MAX_BODIES][9]; /* [slot] inertia about the CM, fixed axes at home */
  int spin_free[POM_MECH_MAX_BODIES];     /* [slot] 1: idle spin, axisymmetric equivalent */
  double transverse[POM_MECH_MAX_BODIES]; /* [slot] its transverse moment (kg m^2) */
} dyn_exact;

/* Per-worker scratch of the exact path. */
typedef struct {
  pom_kin_twists tw; /* body poses and twists of the last evaluation */
  double M[9];       /* mass matrix of the last evaluation (kg m^2) */
  double kinetic;    /* 1/2 omega^T M omega of the last evaluation (J) */
  double potential;  /* gravitational energy relative to home (J) */
} dyn_exact_work;

struct pom_dyn_model {
  pom_dyn_params par;
  double gravity[3]; /* m/s^2, zero when the scene has gravity off */
  int n_bodies;      /* moving bodies (the ground is not a model body) */
  int n_joints;
  int n_actuators;
  int platform_slot; /* model slot of the platform, -1 if none */
  int body_states;   /* states per body, 12 (Euler) or 13 (quaternion) */
  int n_states;
  int acc_parasitic; /* state index of the parasitic damper dissipation */
  dyn_body body[POM_MECH_MAX_BODIES];
  dyn_joint joint[POM_MECH_MAX_JOINTS];
  dyn_actuator act[POM_MECH_MAX_ACTUATORS];
  int slot_of_mech[POM_MECH_MAX_BODIES]; /* mechanism body -> slot, -1 ground */
  double *atol;                          /* [n_states] absolute tolerances */
  double *scale; /* [n_states] characteristic scale (finite-difference increments) */
  /* Jacobian structure (docs/dynamics.md section 7) */
  unsigned char *dep; /* [n_states][n_states] row i depends on column j */
  int *color;         /* [n_states] colour of each column */
  int n_colors;
  long nnz;      /* structural non-zeros (including the diagonal) */
  long *colptr;  /* [n_states + 1] CSC column starts of the pattern */
  int *rowind;   /* [nnz] CSC row indices */
  long *diag;    /* [n_states] position of the diagonal entry of each column */
  dyn_exact *ex; /* exact-constraint path (joints.model = rigid), NULL for the parasitic one */
};

/* Per-body kinematic quantities at one evaluation. */
typedef struct {
  double R[9];    /* rotation from home (fixed frame) */
  double Rp[9];   /* principal axes -> fixed frame = R V */
  double x[3];    /* CM position (m) */
  double v[3];    /* CM velocity (m/s) */
  double w[3];    /* angular velocity, fixed frame (rad/s) */
  double wp[3];   /* angular velocity, principal axes (rad/s) */
  double F[3];    /* force sum, fixed frame (N) */
  double T[3];    /* torque sum about the CM, fixed frame (N m) */
  double trig[4]; /* Euler path: cos psi, sin psi, cos theta, sin theta */
} dyn_body_eval;

/* Outputs of one evaluation that metrics and traces use. */
typedef struct {
  double q[POM_MECH_MAX_ACTUATORS];       /* actuator displacement (m) */
  double q_dot[POM_MECH_MAX_ACTUATORS];   /* m/s */
  double current[POM_MECH_MAX_ACTUATORS]; /* A */
  double voltage[POM_MECH_MAX_ACTUATORS]; /* saturated u (V) */
  double max_lin_deflection;              /* m */
  double max_ang_deflection;              /* rad */
  double spring_energy;                   /* J */
  double parasitic_power;                 /* W */
  int euler_singular;                     /* 1 when a body was too close to pitch 90 deg */
  int nonfinite;                          /* 1 when a derivative was not finite */
  int kin_fail;                           /* exact path: the rigid mechanism cannot be assembled */
} dyn_outputs;

struct pom_dyn_data {
  const pom_dyn_model *m;
  SUNContext ctx;
  void *cvode;
  N_Vector y, atol, ytmp, ftmp;
  SUNMatrix A;
  SUNLinearSolver LS;
  dyn_body_eval be[POM_MECH_MAX_BODIES];
  dyn_outputs out;
  double target[POM_MECH_MAX_ACTUATORS];
  long rhs_count;     /* all RHS evaluations (CVODE + Jacobian) */
  long jac_rhs_count; /* RHS evaluations inside the Jacobian */
  long jac_count;
  double *jac;   /* [nnz] last finite-difference Jacobian, CSC over the model's pattern */
  int jac_valid; /* 1 once jac holds a Jacobian of this maneuver */
  int last_euler_singular;
  int last_nonfinite;
  long euler_singular_count; /* RHS calls of this run that met the Euler singularity */
  long nonfinite_count;      /* RHS calls of this run with a non-finite derivative */
  char cvode_msg[256];       /* last CVODE error message (from its handler) */
  int n_samples;             /* output grid size */
  double *qs;                /* [n_samples][n_actuators] sampled positions for metrics */
  double *yfinal;            /* [n_states] state at the end of the last run */
  int have_final;
  dyn_exact_work *xw;  /* exact path scratch, NULL for the parasitic path */
  long kin_fail_count; /* exact path: RHS calls of this run at an unassemblable pose */
};

/* dyn_rhs.c: evaluates the state derivative (ydot may be NULL to compute the
 * outputs only). Returns 0, or 1 (recoverable) for a non-finite value or the
 * Euler singularity; never allocates. */
int pom_dyn_eval(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot);

/* dyn_rhs.c: coil and controller of actuator a at displacement q (m) and
 * rate qd (m/s), shared by both formulations: sets d->out's q, q_dot,
 * current and voltage, and (ydot non-NULL) the coil flux, PID integral and
 * energy-accumulator derivatives; returns the force along the actuator axis
 * on its moving side (N). */
double pom_dyn_actuator_law(const pom_dyn_model *m, pom_dyn_data *d, int a, double q, double qd,
                            const double *y, double *ydot);

/* dyn_rhs.c: actuator displacements q[n_actuators] (m) of a state, without
 * the full pass (for the output grid of the metrics). */
void pom_dyn_actuator_positions(const pom_dyn_model *m, const double *y, double *q);

/* dyn_rhs.c: stored energy of a state (J). */
double pom_dyn_stored(const pom_dyn_model *m, pom_dyn_data *d, const double *y);

/* dyn_rhs.c: the CVODE RHS callback. */
int pom_dyn_cvode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);

/* dyn_nvec.c: replaces the arithmetic operations of a serial N_Vector (and
 * of every clone CVODE makes of it) by optimized kernels. */
void pom_dyn_nvec_fast_ops(N_Vector v);

/* dyn_jac.c: builds dep/color/nnz of the model (called by model create). */
pom_status pom_dyn_structure_build(pom_dyn_model *m, pom_error *err);

/* dyn_jac.c: the CVODE linear-system callback A = I - gamma J (dense or CSC
 * by the matrix id), with the coloured finite-difference Jacobian. */
int pom_dyn_cvode_linsys(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, sunbooleantype jok,
                         sunbooleantype *jcur, sunrealtype gamma, void *user_data, N_Vector tmp1,
                         N_Vector tmp2, N_Vector tmp3);

/* dyn_jac.c: largest scaled derivative that the structure leaves out (0 when
 * the pattern is complete), by one-column finite differences at y; f0, yp, fp
 * are caller scratch of n_states each. worst_i/j name the entry. */
double pom_dyn_structure_check(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *f0,
                               double *yp, double *fp, int *worst_i, int *worst_j);

/* dyn_exact.c: the exact-constraint path (docs/dynamics-exact.md). */
pom_status pom_dyn_exact_model_init(pom_dyn_model *m, const pom_mechanism *mech,
                                    const pom_kin_arch *arch, pom_error *err);
int pom_dyn_exact_eval(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot);
int pom_dyn_exact_linsys(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, sunbooleantype jok,
                         sunbooleantype *jcur, sunrealtype gamma, void *user_data, N_Vector tmp1,
                         N_Vector tmp2, N_Vector tmp3);
/* The block-triangular direct solver of the exact path's Newton systems (the
 * matrix is a SUNDenseMatrix filled by pom_dyn_exact_linsys). */
SUNLinearSolver pom_dyn_exact_linear_solver(const pom_dyn_model *m, SUNContext ctx);
/* Dexterity 1/kappa(J) of the kinematic Jacobian at the platform pose of
 * state y (NaN when the pose cannot be assembled): failure diagnostics. */
double pom_dyn_exact_dexterity(const pom_dyn_model *m, const double *y);
void pom_dyn_exact_initial(const pom_dyn_model *m, double *y, const pom_dyn_initial *init);
int pom_dyn_exact_near_singular(const pom_dyn_model *m, const double *y);
void pom_dyn_exact_positions(const pom_dyn_model *m, const double *y, double *q);
double pom_dyn_exact_stored(const pom_dyn_model *m, pom_dyn_data *d, const double *y);
void pom_dyn_exact_platform_rotation(const pom_dyn_model *m, const double *y, double R[9]);
pom_status pom_dyn_exact_body_pose(const pom_dyn_model *m, const double *y, int k, double R[9],
                                   double x[3], pom_error *err);
/* Mass matrix M(R) (kg m^2, 3x3 row-major) at state y; NULL for a parasitic
 * model. Points into d's scratch (valid until the next evaluation). */
const double *pom_dyn_exact_mass_matrix(const pom_dyn_model *m, pom_dyn_data *d, const double *y);

#endif
