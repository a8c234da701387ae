/* dyn_internal.h - model and data layout shared by the files of dynamics/
 * (not a public header). The model is the bond graph of docs/dynamics.md
 * flattened into arrays; the data holds one worker's CVODE objects and
 * scratch, all allocated at create time. */
#ifndef POM_DYN_INTERNAL_H
#define POM_DYN_INTERNAL_H

#include "pom_dyn_ctrl.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>

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
  double axis[3];                 /* prismatic or revolute axis at home (unit) */
  double ref[3]; /* revolute: reference vector fixed in both sides, perpendicular to axis at
                    home; the joint angle is measured from its side-0 to its side-1 image */
  int actuator;  /* model actuator index, -1 passive */
  /* massless rod of a lumped binary link (docs/dynamics.md section 13): one linear
   * pseudo-constraint |p1 - p0| - length, no other constraint */
  int distance;  /* 1 for a rod */
  double length; /* rest length of the rod (m) */
} dyn_joint;

typedef struct {
  int joint;      /* model joint index (prismatic or revolute) */
  int flux_state; /* state index of the coil flux linkage, -1 when quasi-static */
  int ctrl_state; /* first of the controller's n_states state indices (the PID integral), -1
                     when the controller has none */
  int acc_state;  /* first of DYN_ACC_PER_ACT accumulator states */
  double stroke;  /* total stroke (m or rad), targets within +-stroke/2; 0 = not limited */
} dyn_actuator;

/* A setpoint within this fraction of its actuator's stroke of mid-stroke is
 * a zero step (no settling band): the rounding an orientation about a limb's
 * axis leaves through a generic IK (3.5e-18 m on a 12 mm stroke measured) */
#define DYN_ZERO_STEP 1e-12

typedef struct dyn_formulation dyn_formulation;

/* The closed loop's drive mode (dyn_exact_order.c, docs/dynamics.md section
 * 7, "Order and stability"): the least damped oscillating root of the
 * linearized actuator loop (reflected inertia, bearing, coil, controller) at
 * rest at home, over the actuator-space modal masses, against the A(alpha)
 * sectors of the BDF orders. */
typedef struct {
  int analysed;      /* 1: computed; 0: not (a coupled law, more than one state, no partials) */
  int oscillating;   /* 1: the loop has a complex pair; 0: every root real */
  double re, im;     /* the pair's root (1/s), im > 0 */
  double angle_deg;  /* its angle from the negative real axis, atan2(im, -re) (deg) */
  double modal_mass; /* the actuator-space modal mass it belongs to (kg or kg m^2) */
  int stable_order;  /* highest BDF order whose A(alpha) sector holds the root (0: none) */
} dyn_drive_mode;

struct pom_dyn_model {
  const dyn_formulation *form;   /* the formulation's operations (never NULL once created) */
  const pom_dyn_ctrl_type *ctrl; /* the controller's type (never NULL once created) */
  /* 1: the controller has partials and at most one state, and the analytic
   * Jacobians use them; 0: its columns go by finite differences (docs 7) */
  int ctrl_analytic;
  void *ctrl_model; /* the controller's own model (its type's model_create), owned; or NULL */
  void *form_model; /* the formulation's private model, owned (NULL if none) */
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
  /* [n_states] or NULL: 1 where the error test has the relative term
   * rtol |y_i|, 0 where it is absolute only (positions of a high-gain loop,
   * docs/dynamics-exact.md section 5); NULL = relative everywhere */
  unsigned char *relative;
  double *scale; /* [n_states] characteristic scale (finite-difference increments) */
  /* Jacobian structure (docs/dynamics.md section 7) */
  unsigned char *dep; /* [n_states][n_states] row i depends on column j */
  int *color;         /* [n_states] colour of each column, -1: never perturbed (zero column) */
  int n_colors;
  long nnz;     /* structural non-zeros (including the diagonal) */
  long *colptr; /* [n_states + 1] CSC column starts of the pattern */
  int *rowind;  /* [nnz] CSC row indices */
  long *diag;   /* [n_states] position of the diagonal entry of each column */
  /* the architecture the mechanism was built from (a copy), for the target
   * orientation FK(setpoints) of the pointing metrics; has_arch 0 when the
   * caller gave none (the pointing metrics are then NaN) */
  int has_arch;
  pom_kin_arch arch;
  /* the largest BDF order CVODE is given: solver.max_order, capped at 2 on
   * the rigid path when the drive mode lies outside BDF 3's sector
   * (dyn_exact_order.c, docs/dynamics.md section 7) */
  int max_order;
  dyn_drive_mode drive; /* analysed 0 on the parasitic path */
  /* CVODE's Newton convergence coefficient (CVodeSetNonlinConvCoef): 0 =
   * CVODE's default 0.1; below it on the rigid path when the tolerated
   * Newton error of the mechanical states would move the drive voltage by
   * more than a fraction of its limit (dyn_exact_order.c, docs/dynamics.md
   * section 7, "Newton accuracy at high gain") */
  double newton_coef;
  /* the drive voltage the absolute tolerances of the orientation, omega and
   * controller states move at rest at home (V; 0 where not analysed) */
  double newton_voltage;
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
  double q[POM_MECH_MAX_ACTUATORS];       /* actuator coordinate (m or rad) */
  double q_dot[POM_MECH_MAX_ACTUATORS];   /* m/s or rad/s */
  double current[POM_MECH_MAX_ACTUATORS]; /* A */
  double voltage[POM_MECH_MAX_ACTUATORS]; /* saturated u (V) */
  double effort[POM_MECH_MAX_ACTUATORS];  /* K_m i - b q_dot on the moving side (N or N m) */
  double platform_rate;                   /* |omega| of the platform (rad/s), 0 without one */
  double max_lin_deflection;              /* m */
  double max_ang_deflection;              /* rad */
  double spring_energy;                   /* J */
  double parasitic_power;                 /* W */
  int euler_singular;                     /* 1 when a body was too close to pitch 90 deg */
  int nonfinite;                          /* 1 when a derivative was not finite */
  int kin_fail;                           /* exact path: the rigid mechanism cannot be assembled */
  /* exact path, outputs-only evaluations (ydot NULL): 3/kappa_F(J) of the
   * kinematic Jacobian, an upper bound on the dexterity 1/kappa_2(J) within a
   * factor 3 (pom_kin_dexterity_bound); NaN where not measured (the parasitic
   * path, the RHS evaluations, an unassemblable pose) */
  double dexterity_bound;
  /* added by the design gradients (issue 29): the controller's raw voltage
   * before the saturation (V), the root functions of a sensitivity run */
  double u_raw[POM_MECH_MAX_ACTUATORS];
} dyn_outputs;

/* ---- settling on the integrator's dense output (dyn_settle.c) ------------
 * docs/dynamics.md section 8: every band function g(t) = |e(t)| - band is
 * watched on CVODE's interpolant over each accepted step, at the step end and
 * at the step's two Gauss-Legendre nodes; a return inside the band is located
 * by the Illinois method on the interpolant. */
typedef struct {
  double ref;      /* value the error is taken from (m, rad; 0 for the pointing angle) */
  double band;     /* half-width of the band (same unit) */
  double t_settle; /* last crossing back inside found so far (s); 0 when never outside */
  int outside;     /* 1 when the last step end is outside the band */
  int active;      /* 0: no band (zero step, unknown target orientation) */
} dyn_band;

/* Columns of one row of the per-step record: step end time, step size, then
 * q at the two interior nodes and at the step end ([3][POM_MECH_MAX_ACTUATORS]). */
enum {
  DYN_REC_T = 0,
  DYN_REC_H = 1,
  DYN_REC_Q = 2,
  DYN_REC_WIDTH = 2 + 3 * POM_MECH_MAX_ACTUATORS
};

typedef struct {
  dyn_band act[POM_MECH_MAX_ACTUATORS];   /* per-actuator band about the setpoint */
  dyn_band point;                         /* pointing band about the target orientation */
  double t_prev;                          /* end of the previous step (s) */
  double q_prev[POM_MECH_MAX_ACTUATORS];  /* q there (m or rad) */
  double qd_prev[POM_MECH_MAX_ACTUATORS]; /* q_dot there (m/s or rad/s) */
  long interior_steps; /* steps whose interior nodes were evaluated on the interpolant */
  double theta_prev;   /* pointing angle there (rad) */
  double theta_end;    /* pointing angle at the last step end (rad) */
  double track_int;    /* integral of the squared tracking angle (rad^2 s) */
  int track_ok;        /* 1 while every node had a reference rotation */
  double *rec;         /* [rec_cap][DYN_REC_WIDTH] per-step record for the final-value variant */
  long rec_n;          /* rows used (row 0: t = 0) */
  long rec_cap;        /* rows allocated (grows geometrically, kept across maneuvers) */
  long evals;          /* interpolant evaluations of the last maneuver (nodes + root finding) */
  /* per actuator, after the metrics: the factor by which the tolerances fall
   * short of resolving the stepinfo crossing (> 1: unresolved; 0: resolved) */
  double stepinfo_need[POM_MECH_MAX_ACTUATORS];
} dyn_settle;

/* The rigid-limit watch (dyn_validity.c, docs/dynamics.md section 13b):
 * the drive's electrical power P = sum |u i| integrated over the accepted
 * steps (trapezoidal) into the duration T_E = (int P dt)^2 / int P^2 dt over
 * which the drive spends its energy, against the lowest joint frequency. */
typedef struct {
  int on;           /* 1 on a formulation with parasitic springs */
  double omega_low; /* lowest two-body joint frequency sqrt(k_p (1/m0 + 1/m1)) (rad/s) */
  double t_prev;    /* end of the previous step (s) */
  double p_prev;    /* P there (W) */
  double e1;        /* int P dt (J) */
  double e2;        /* int P^2 dt (W J) */
  double pm_prev;   /* drive's mechanical power sum max(0, effort q_dot) at t_prev (W) */
  double w_mech;    /* its integral, the mechanical work the drive puts in (J) */
} dyn_validity;

/* ---- the peak coil current (dyn_peak.c, docs/optimize.md 12.2) -----------
 * Watched only when asked (pom_dyn_data_watch_peak_current, and in every
 * sensitivity run): max over the coils and the maneuver of |i|, each
 * interior maximum located on the interpolant as a root of sign(i) di/dt. */
typedef enum {
  DYN_PEAK_INTERIOR = 0, /* a smooth interior maximum (di/dt = 0) */
  DYN_PEAK_START,        /* at t = 0 */
  DYN_PEAK_END,          /* at the horizon */
  DYN_PEAK_KINK          /* on a kink of i(t) (di/dt jumps: the saturation's corner) */
} dyn_peak_where;

typedef struct {
  int on;               /* 1: watched in this data's runs */
  double value;         /* largest |i| so far (A) */
  double t;             /* its time (s) */
  int coil;             /* its coil */
  dyn_peak_where where; /* what kind of point it is */
  double second;        /* the largest other candidate (another coil or time) (A) */
  int improved;         /* 1 when the step just watched raised the peak */
  double r_prev[POM_MECH_MAX_ACTUATORS]; /* sign(i) di/dt at the last step's end (A/s) */
  double t_corner; /* the last corner of a saturated voltage (s; -inf: none yet) */
  double *buf;     /* [n_states] scratch */
} dyn_peak;

struct pom_dyn_data {
  const pom_dyn_model *m;
  SUNContext ctx;
  void *cvode;
  N_Vector y, atol, ytmp, ftmp;
  SUNMatrix A;
  SUNLinearSolver LS;
  dyn_body_eval be[POM_MECH_MAX_BODIES];
  dyn_outputs out;
  /* a sensitivity run: the raw voltages of the driver's evaluation at the
   * last step's end (dyn_simulate.c), which the saturation pattern's check
   * of dyn_sens.c reads instead of evaluating the same (t, y) again */
  double u_raw_step[POM_MECH_MAX_ACTUATORS];
  /* 1 while d->out holds the band roots' last evaluation (dyn_sens.c):
   * cleared by every pom_dyn_eval on d */
  int out_from_roots;
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
  int n_samples;             /* output grid size (traces only) */
  dyn_settle settle;         /* settling on the dense output (dyn_settle.c) */
  dyn_validity validity;     /* the rigid-limit watch (dyn_validity.c) */
  double R_target[9];        /* target orientation of the maneuver, FK(setpoints) */
  int have_target_rotation;  /* 1 when R_target is known */
  double *yfinal;            /* [n_states] state at the end of the last run */
  double *ysave;             /* [n_states] yfinal kept across a stepinfo re-run */
  double tol_tighten;        /* 1, or the factor every tolerance is divided by in a stepinfo
                                re-run (docs/results.md section 1c) */
  int have_final;
  void *form_data; /* the formulation's per-worker scratch, owned (NULL if none) */
  void *ctrl_work; /* the controller's per-worker scratch (work_create), owned, or NULL */
  double t;        /* time of the evaluation under way (s): the controller's clock */
  double ctrl_u[POM_MECH_MAX_ACTUATORS]; /* a coupled controller's raw voltages of this
                                            evaluation (V), set by pom_dyn_controller_pass */
  long kin_fail_count;     /* exact path: RHS calls of this run at an unassemblable pose */
  int below_min_dexterity; /* 1 when this run stopped at out.dexterity_bound < min_dexterity */
  /* added for the frequency response (issue 28, docs/capability.md) */
  pom_dyn_setpoint_fn setpoint_fn; /* NULL: the maneuver's constant target; else the setpoints
                                      target(t) of every evaluation (pom_dyn_set_setpoint_path) */
  void *setpoint_ctx;              /* its context, not owned */
  double u_inject[POM_MECH_MAX_ACTUATORS]; /* V added to each controller's raw voltage: zero
                                              except while dyn_freq.c breaks a loop */
  /* added by the design gradients (issue 29, dyn_sens.c): the forward
   * sensitivities of the run under way, NULL on a plain run */
  struct dyn_sens *sens;
  /* a sensitivity evaluation of a perturbed model (dyn_sens.c): 1 while
   * the saturation follows sat_mode (+1 at +limit, -1 at -limit, 0 the
   * linear band: u = u_raw unclipped), the nominal run's pattern, instead
   * of its own raw voltage (docs/optimize.md 12.1) */
  int sat_frozen;
  int sat_mode[POM_MECH_MAX_ACTUATORS];
  dyn_peak peak; /* the peak coil current's watch (dyn_peak.c) */
  /* the state's Newton solver (CVODE's own, attached by us so that a
   * staggered sensitivity run can skip the state's right-hand side that
   * CVODES evaluates at the converged y for the sensitivities' right-hand
   * side, which ours does not read; docs/optimize.md 12.5) */
  SUNNonlinearSolver nls;
  int sens_lazy_f; /* 1 while a staggered sensitivity run may skip it */
  int nls_in;      /* inside the state's Newton solve */
  int nls_first;   /* no residual evaluated yet in this solve */
  int f_pending;   /* the solve converged: CVODES' next f call is the skippable one */
  N_Vector nls_f;  /* the vector the Newton's residual evaluates f into */
  double nls_t;    /* the time of that solve */
  N_Vector f_lazy; /* a vector CVODES holds as f(t, y) that was not evaluated, or NULL */
  long f_skipped;  /* evaluations skipped in this run */
};

/* ---- formulations --------------------------------------------------------
 * One table of operations per formulation of the equations of motion
 * (docs/dynamics.md section 15): the parasitic bond graph (dyn_parasitic*.c)
 * and the exact minimal-coordinate rigid path (dyn_exact.c). The shared
 * driver (dyn_model.c, dyn_simulate.c, dyn_fdjac.c) calls only these. */
struct dyn_formulation {
  const char *name; /* "parasitic" or "rigid" (joints.model) */
  /* 1: init sets atol = rtol * natural size when solver.atol_scale is 0;
   * 0: the driver turns atol_scale 0 into min(1e-3, 1e3 rtol) first (both
   * shipped formulations have natural sizes) */
  int natural_tolerances;
  /* 1: the joints are parasitic springs and eval sets out.spring_energy
   * (the rigid-limit ratio is measured); 0: rigid joints (it is NaN) */
  int parasitic_springs;
  /* Fills bodies, actuators, the state layout (n_states, offsets), scale,
   * atol and the Jacobian pattern (dep, color, CSC) of m; m->par, gravity,
   * slot_of_mech (all -1) and platform_slot (-1) are set by the caller. arch
   * may be NULL when the formulation does not need it. */
  pom_status (*init)(pom_dyn_model *m, const pom_mechanism *mech, const pom_kin_arch *arch,
                     pom_error *err);
  void (*model_free)(pom_dyn_model *m); /* frees m->form_model */
  /* Per-worker part of the data: d->form_data, the Newton matrix d->A and
   * its linear solver d->LS (d->ctx and d->y exist). */
  pom_status (*data_init)(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err);
  void (*data_free)(pom_dyn_data *d); /* frees d->form_data */
  /* State derivative (ydot may be NULL: outputs only); 0, or 1 (recoverable)
   * for a non-finite value, the Euler singularity or an unassemblable pose.
   * Never allocates. */
  int (*eval)(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot);
  CVLsLinSysFn linsys; /* CVODE's linear-system callback A = I - gamma J */
  /* Analytic Jacobian at y into jac[nnz] over the model's CSC pattern; 0, or
   * 1 for a non-finite entry. NULL: the formulation has none, the linsys
   * uses finite differences whatever solver.jacobian says. */
  int (*jacobian)(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *jac);
  /* State at home with the body velocities of init (NULL = rest). */
  void (*initial)(const pom_dyn_model *m, double *y, const pom_dyn_initial *init);
  /* Actuator coordinates q[n_actuators] (m or rad) of a state, cheaply. */
  void (*positions)(const pom_dyn_model *m, const double *y, double *q);
  /* Stored energy of a state (J): kinetic, gravity, springs, coils. */
  double (*stored)(const pom_dyn_model *m, pom_dyn_data *d, const double *y);
  /* 1 when an Euler-angle orientation is beyond scene.euler_cos_min. */
  int (*near_singular)(const pom_dyn_model *m, const double *y);
  /* Rotation from home of the platform (identity when there is none). */
  void (*platform_rotation)(const pom_dyn_model *m, const double *y, double R[9]);
  /* Pose of mechanism body k (a moving body) in state y. */
  pom_status (*body_pose)(const pom_dyn_model *m, const double *y, int k, double R[9], double x[3],
                          pom_error *err);
  /* Records why CVODE failed at t (after the generic causes were ruled out). */
  pom_status (*solver_failure)(const pom_dyn_model *m, pom_dyn_data *d, double t, pom_error *err);
};

/* dyn_validity.c (docs/dynamics.md section 13b): begin at t = 0 and one
 * call per accepted step, each with the outputs of that state evaluated;
 * the ratio (NaN on rigid joints) at the end. */
void pom_dyn_validity_begin(const pom_dyn_model *m, pom_dyn_data *d);
void pom_dyn_validity_step(const pom_dyn_model *m, pom_dyn_data *d, double t);
double pom_dyn_validity_ratio(const pom_dyn_model *m, const pom_dyn_data *d);
/* energy_parasitic / the drive's positive mechanical work (NaN on rigid
 * joints, 0 without mechanical work) */
double pom_dyn_validity_share(const pom_dyn_model *m, const pom_dyn_data *d,
                              double energy_parasitic);

/* dyn_settle.c (docs/dynamics.md section 8). A root of g in [a, b] by the
 * Illinois method, g(a) and g(b) of opposite signs (ga = g(a), gb = g(b)),
 * to a bracket of width <= xtol (at most 200 evaluations); NaN from g ends
 * the search at the point that gave it. */
double pom_dyn_illinois(double (*g)(double t, void *ctx), void *ctx, double a, double ga, double b,
                        double gb, double xtol);
/* Bracket width of the crossing search (s). */
#define POM_DYN_SETTLE_XTOL 1e-12
/* The settling watch: begin at t = 0 (outputs of y0 evaluated), one call
 * per accepted step (outputs of the step end evaluated; uses d->ytmp), and
 * the settling and pointing metrics at the end. step returns POM_ERR_NOMEM
 * when the record cannot grow, POM_ERR_SOLVER when CVodeGetDky refuses. */
pom_status pom_dyn_settle_data(pom_dyn_data *d, pom_error *err);
void pom_dyn_settle_begin(const pom_dyn_model *m, pom_dyn_data *d, const double *y0);
pom_status pom_dyn_settle_step(const pom_dyn_model *m, pom_dyn_data *d, double t, const double *y,
                               pom_error *err);
void pom_dyn_settle_metrics(const pom_dyn_model *m, pom_dyn_data *d, pom_dyn_metrics *mt);
/* The stated error of a stepinfo settling time at solver.rtol (s):
 * max(rtol x POM_DYN_STEPINFO_TIME_SCALE, POM_DYN_STEPINFO_TIME_FLOOR),
 * 10 us at the shipped rtol 1e-6 = the printed precision of Table 1b
 * (0.01 ms); finer times by a lower rtol, which scales it (docs/results.md
 * section 1c, docs/dynamics.md section 7). */
#define POM_DYN_STEPINFO_TIME_SCALE 10.0
#define POM_DYN_STEPINFO_TIME_FLOOR 1e-9
double pom_dyn_stepinfo_time_tol(double rtol);
/* A stepinfo crossing the tolerances do not resolve is re-integrated with
 * every tolerance divided by POM_DYN_STEPINFO_SAFETY x the factor they fall
 * short by, at most POM_DYN_STEPINFO_MAX_TIGHTEN and not below rtol
 * POM_DYN_STEPINFO_MIN_RTOL; beyond that it is flagged unresolved. */
#define POM_DYN_STEPINFO_SAFETY      4.0
#define POM_DYN_STEPINFO_MAX_TIGHTEN 1e4
#define POM_DYN_STEPINFO_MIN_RTOL    1e-12
/* What the error test resolves of each actuator position at state y: the
 * states' tolerances (atol_i + rtol |y_i|) carried through the positions op
 * (docs/results.md section 1c); work holds n_states doubles. */
void pom_dyn_position_resolution(const pom_dyn_model *m, const double *y, double *work,
                                 double res[3]);
void pom_dyn_position_resolution_tight(const pom_dyn_model *m, const double *y, double *work,
                                       double tighten, double res[3]);

/* dyn_parasitic.c: the parasitic bond-graph formulation (docs/dynamics.md). */
extern const dyn_formulation pom_dyn_form_parasitic;
/* dyn_exact.c: the exact-constraint formulation (docs/dynamics-exact.md). */
extern const dyn_formulation pom_dyn_form_exact;

/* dyn_parasitic_model.c: assembly of the parasitic model (the init op). */
pom_status pom_dyn_parasitic_init(pom_dyn_model *m, const pom_mechanism *mech,
                                  const pom_kin_arch *arch, pom_error *err);
/* dyn_parasitic_jac.c: dep/color of the parasitic model, then its CSC
 * pattern (called by pom_dyn_parasitic_init). */
pom_status pom_dyn_structure_build(pom_dyn_model *m, pom_error *err);

/* dyn_parasitic_deriv.c: the analytic Jacobian of the parasitic RHS
 * (docs/dynamics.md section 7): the scatter layout of a model (m->form_model,
 * built after its pattern), the per-worker scratch (d->form_data) and the
 * evaluation (the jacobian op). */
pom_status pom_dyn_parasitic_jac_layout(pom_dyn_model *m, pom_error *err);
void pom_dyn_parasitic_jac_layout_free(pom_dyn_model *m);
pom_status pom_dyn_parasitic_jac_data(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err);
void pom_dyn_parasitic_jac_data_free(pom_dyn_data *d);
int pom_dyn_parasitic_jacobian(const pom_dyn_model *m, pom_dyn_data *d, const double *y,
                               double *jac);

/* dyn_diagnose.c (docs/dynamics.md section 14): the highest natural
 * frequency of the underdamped parasitic joint springs (damping ratio
 * below 1; rad/s), a per-joint upper
 * bound sqrt(k sum of the sides' mobilities 1/m + |rho|^2/I_min), with the
 * joint (model index; NULL allowed), 1 when it is an angular spring, and its
 * damping ratio; 0 (joint -1) on the rigid path. */
double pom_dyn_stiffest_joint_mode(const pom_dyn_model *m, int *joint, int *angular, double *zeta);
/* The message of a maneuver that reached solver.max_steps at t: the step
 * sizes and what holds them down: the rigid path's drive mode when the BDF
 * order in use can leave its stability sector or the steps resolve it, the
 * stiffest joint mode when the steps resolve it, the tolerance otherwise
 * (into buf[n]). */
void pom_dyn_max_steps_reason(const pom_dyn_model *m, double t, char *buf, size_t n);

/* ---- shared pieces -------------------------------------------------------- */
/* dyn_simulate.c: m->form->eval (tests and the shared Jacobian use it). */
int pom_dyn_eval(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *ydot);

/* dyn_simulate.c: m->form->stored, the stored energy of a state (J). */
double pom_dyn_stored(const pom_dyn_model *m, pom_dyn_data *d, const double *y);

/* dyn_simulate.c: the CVODE RHS callback (counts and flags, then eval). */
int pom_dyn_cvode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);
/* A linear-system callback's fy: evaluated now if the right-hand side
 * skipped it (pom_dyn_data.f_lazy). 0, or the evaluation's return. */
int pom_dyn_rhs_if_lazy(pom_dyn_data *d, sunrealtype t, N_Vector y, N_Vector fy);

/* dyn_actuator.c: coil and controller of actuator a at coordinate q (m or
 * rad) and rate qd (m/s or rad/s), shared by both formulations: sets d->out's
 * q, q_dot, current and voltage, and (ydot non-NULL) the coil flux, PID
 * integral and energy-accumulator derivatives; returns the effort on its
 * moving side, a force along the axis (N) or a torque about it (N m). */
double pom_dyn_actuator_law(const pom_dyn_model *m, pom_dyn_data *d, int a, double q, double qd,
                            const double *y, double *ydot);

/* Partial derivatives of one actuator's law (pom_dyn_actuator_law) with
 * respect to its own states, the controller state z (m s or rad s for the
 * PID integral; a controller with an analytic Jacobian has at most one) and
 * the coil flux linkage (V s; zero derivatives for a quasi-static coil), and
 * with respect to its coordinate q and rate qd (the exact path's mechanical
 * columns). The saturation is the law's: a saturated voltage has
 * du/dz = du/dq = du/dqd = 0. */
typedef struct {
  double u;                     /* saturated voltage (V) */
  double i;                     /* coil current (A) */
  double effort;                /* K i - b qd (N or N m) */
  double du_dz;                 /* V per unit of z */
  double di_dz, di_dflux;       /* A per unit of z, A per V s */
  double dF_dz, dF_dflux;       /* effort (N or N m) per unit of z, per V s */
  double dflux_dz, dflux_dflux; /* coil equation d(flux_dot)/dz, d(flux_dot)/d flux (1/s) */
  double dzd_dz;                /* the controller state's rate against z (1/s) */
  double du_dq, du_dqd;         /* V per m (rad), per m/s (rad/s) */
  double di_dq, di_dqd;         /* A per m (rad), per m/s (rad/s) */
  double dF_dq, dF_dqd;         /* effort per m (rad), per m/s (rad/s) */
  double dflux_dq, dflux_dqd;   /* coil equation against q, qd */
  double dzd_dq, dzd_dqd;       /* the controller state's rate against q, qd */
  double dbearing_dqd;          /* bearing dissipation rate b qd^2 against qd */
} dyn_law_partials;

/* dyn_actuator.c: a coupled controller (law_all) at one evaluation: every
 * actuator's measured q[n] and qd[n] (and, from y, the coil currents) give
 * d->ctrl_u and (ydot non-NULL) the controller state rates. The formulation
 * calls it before its actuator laws; pom_dyn_actuator_law then reads
 * d->ctrl_u. */
void pom_dyn_controller_pass(const pom_dyn_model *m, pom_dyn_data *d, const double *q,
                             const double *qd, const double *y, double *ydot);

/* dyn_exact.c: the controller's view of an exact model (model-based
 * control): at platform rotation R and angular velocity w (fixed frame), the
 * mass matrix M (kg m^2), the generalized force of gravity and the velocity
 * terms f (N m; M w_dot = f + J^T F with the actuator efforts F), the
 * actuator coordinates q and the Jacobian J (q_dot = J w). Uses d's scratch.
 * Returns 0, or 1 when the mechanism cannot be assembled at R. */
int pom_dyn_exact_terms(const pom_dyn_model *m, pom_dyn_data *d, const double R[9],
                        const double w[3], double M[9], double f[3], double q[3], double J[9]);

/* dyn_actuator.c: the controller's input and its raw (unsaturated) voltage
 * for actuator a at q, qd and state y (zdot, when non-NULL, receives the
 * controller state rates); the partials when cp is non-NULL (the type must
 * have them). */
double pom_dyn_controller_law(const pom_dyn_model *m, const pom_dyn_data *d, int a, double q,
                              double qd, const double *y, double *zdot, pom_dyn_ctrl_partials *cp);

/* dyn_actuator.c: the partials above for actuator a at coordinate q and rate
 * qd, state y (the same inputs as pom_dyn_actuator_law). */
void pom_dyn_actuator_law_partials(const pom_dyn_model *m, const pom_dyn_data *d, int a, double q,
                                   double qd, const double *y, dyn_law_partials *lp);

/* dyn_actuator.c: E plus the coil energies 1/2 L i^2 of a state, added one
 * actuator at a time (J; nothing for a quasi-static coil). */
double pom_dyn_add_coil_energy(const pom_dyn_model *m, const double *y, double E);

/* dyn_actuator.c: two unit vectors completing the unit n to a right-handed
 * orthonormal basis; e1 is the zero of a revolute joint's angle in both
 * formulations. */
void pom_dyn_perp_basis(double e1[3], double e2[3], const double n[3]);

/* dyn_actuator.c: the rotary actuator coordinate (rad), the signed angle
 * from r0 to r1 about the unit n (both perpendicular to n), by atan2. */
double pom_dyn_revolute_angle(const double n[3], const double r0[3], const double r1[3]);

/* dyn_nvec.c: replaces the arithmetic operations of a serial N_Vector (and
 * of every clone CVODE makes of it) by optimized kernels. */
void pom_dyn_nvec_fast_ops(N_Vector v);

/* dyn_fdjac.c: the CSC pattern (colptr, rowind, diag, nnz) of m->dep plus
 * the diagonal. */
pom_status pom_dyn_pattern_build(pom_dyn_model *m, pom_error *err);

/* dyn_fdjac.c: writes the model's CSC pattern into the sparse matrix A (of
 * nnz entries) once, at data create; pom_dyn_cvode_linsys then writes the
 * values only. */
void pom_dyn_pattern_to_matrix(const pom_dyn_model *m, SUNMatrix A);

/* dyn_fdjac.c: the finite-difference Jacobian shared by both formulations:
 * one RHS evaluation per colour of m->color (columns of colour -1 are left
 * zero), CSC values over the model's pattern into d->jac; f0 = f(yv), yp, fp
 * scratch of n_states. Returns the RHS status (0 ok). */
int pom_dyn_fd_jacobian(pom_dyn_data *d, const double *yv, const double *f0, double *yp,
                        double *fp);

/* dyn_fdjac.c: the CVODE linear-system callback A = I - gamma J (dense or CSC
 * by the matrix id), J from pom_dyn_fd_jacobian unless CVODE says the stored
 * one is still good. */
int pom_dyn_cvode_linsys(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, sunbooleantype jok,
                         sunbooleantype *jcur, sunrealtype gamma, void *user_data, N_Vector tmp1,
                         N_Vector tmp2, N_Vector tmp3);

/* dyn_fdjac.c: largest scaled derivative that the structure leaves out (0 when
 * the pattern is complete), by one-column finite differences at y; f0, yp, fp
 * are caller scratch of n_states each. worst_i/j name the entry. */
double pom_dyn_structure_check(const pom_dyn_model *m, pom_dyn_data *d, const double *y, double *f0,
                               double *yp, double *fp, int *worst_i, int *worst_j);

/* dyn_structured_ls.c: the structured Newton solve (docs/dynamics.md section
 * 7): a block LU of the CSC Newton matrix over the bond graph's groups (per
 * body u, orientation, (p, h'); per actuator its flux and controller states;
 * every other state alone), u and orientation first, then minimum degree.
 * Its structure, order and scatter map are built here from m's pattern. */
typedef struct {
  int groups;         /* diagonal blocks */
  long blocks;        /* dense blocks of L + U (fill included) */
  long values;        /* their entries */
  double setup_flops; /* floating-point operations of one factorization (dense blocks) */
  double solve_flops; /* of one solve */
} pom_dyn_sls_stats;
pom_status pom_dyn_structured_ls_create(SUNLinearSolver *out, const pom_dyn_model *m,
                                        SUNContext ctx, pom_error *err);
/* The counts of a structured solver; 0 (stats untouched) for another solver. */
int pom_dyn_structured_ls_stats(SUNLinearSolver S, pom_dyn_sls_stats *stats);

/* dyn_exact_order.c (docs/dynamics.md section 7, "Order and stability"):
 * the A(alpha) angle of BDF order k = 1..5 (deg; 90 for the A-stable 1, 2). */
double pom_dyn_bdf_alpha_deg(int order);
/* Fills m->drive from the linearized loop at rest at home, M the mass
 * matrix about omega (kg m^2) and J the actuator Jacobian (rows in actuator
 * order, q_dot = J omega) there, and caps m->max_order at 2 when the drive
 * mode lies outside BDF 3's sector. Called at the end of the exact
 * formulation's init. */
void pom_dyn_order_cap(pom_dyn_model *m, const double M[9], const double J[9]);
/* The Newton convergence coefficient CVODE's default (0.1) leaves. */
#define POM_DYN_NEWTON_COEF_DEFAULT 0.1
/* Sets m->newton_voltage, the drive voltage the tolerances move at rest at
 * home, and from it m->newton_coef. J is the actuator Jacobian there (rows
 * in actuator order, m or rad per rad), atol_angle and atol_rate the largest
 * absolute tolerances of a rotation (rad; twice a quaternion component's)
 * and of an omega component (rad/s), atol_ctrl that of the controller state
 * (0 if none). Called at the end of the exact formulation's init. */
void pom_dyn_newton_coef(pom_dyn_model *m, const double J[9], double atol_angle, double atol_rate,
                         double atol_ctrl);
/* The roots of the real polynomial c[0] s^n + ... + c[n] (n <= 6, c[0] != 0)
 * into re[n], im[n]; returns 1 when every root's relative residual is below
 * 1e-9, 0 otherwise (Aberth-Ehrlich iteration, Newton polish). */
int pom_dyn_poly_roots(const double *c, int n, double *re, double *im);

/* ---- forward sensitivities (dyn_sens.c, docs/optimize.md) --------------
 * Hooks of the driver, called only when d->sens is set: after CVodeReInit
 * (CVODES' sensitivities on), after each step's settling watch (t0 the
 * step's start; the band times and the pointing band's time before the
 * watch, to find the crossings it located), and at the horizon. */
typedef struct {
  pom_status (*begin)(const pom_dyn_model *m, pom_dyn_data *d, pom_error *err);
  pom_status (*step)(const pom_dyn_model *m, pom_dyn_data *d, double t0, double t,
                     const double *t_settle_before, int point_before_valid, double point_before,
                     pom_error *err);
  void (*end)(const pom_dyn_model *m, pom_dyn_data *d);
  /* after a root return of a sensitivity run (a raw voltage entering its
   * linear band): the integration restarts there with the sensitivities
   * as they are, so that the band is resolved */
  pom_status (*restart)(const pom_dyn_model *m, pom_dyn_data *d, double t, pom_error *err);
  /* CVODES' sensitivities off for a plain re-run inside a sensitivity run */
  void (*off)(pom_dyn_data *d);
  /* 1 when d->out already holds the outputs at (t, y): the last evaluation
   * on d was the band roots' at that t and bit-identical y (CVODES checks
   * the roots at each step's end last), so the driver's per-step
   * evaluation would repeat it */
  int (*out_at)(const pom_dyn_model *m, const pom_dyn_data *d, double t, const double *y);
} dyn_sens_ops;
/* The driver reaches dyn_sens.c through this table, as it reaches the
 * formulations through theirs (no circle of calls between the files). */
extern const dyn_sens_ops pom_dyn_sens_ops;

/* dyn_peak.c: the peak coil current's watch, called by the driver when
 * d->peak.on: begin at t = 0 (state y0), one call per accepted step (after
 * the settling watch, on the step's interpolant [t0, t]; uses d->ytmp and
 * d->ftmp), end at the horizon (state y). A failed evaluation is reported
 * as a solver error at its time. */
typedef struct {
  pom_status (*begin)(const pom_dyn_model *m, pom_dyn_data *d, const double *y0, pom_error *err);
  pom_status (*step)(const pom_dyn_model *m, pom_dyn_data *d, double t0, double t, pom_error *err);
  pom_status (*end)(const pom_dyn_model *m, pom_dyn_data *d, double t, const double *y,
                    pom_error *err);
  /* a voltage enters or leaves its saturation at t (a root the sensitivity
   * run stops at, after the step's watch) */
  void (*corner)(const pom_dyn_model *m, pom_dyn_data *d, double t);
} dyn_peak_ops;
/* The driver reaches dyn_peak.c through this table, as dyn_sens.c's (no
 * circle of calls between the files). */
extern const dyn_peak_ops pom_dyn_peak_ops;
/* Ties: two candidates within this relative distance make the peak a kink
 * of max over them (docs/optimize.md 12.2). */
#define POM_DYN_PEAK_TIE 1e-9

/* ---- exact formulation queries (dyn_exact.c; tests and diagnostics) ------- */
/* State layout of an exact model: first orientation state, their number (3
 * or 4) and first state of omega; returns 0 (and leaves them) for a model of
 * another formulation. */
int pom_dyn_exact_layout(const pom_dyn_model *m, int *ori, int *n_ori, int *omega);
/* Mass matrix M(R) (kg m^2, 3x3 row-major) at state y; NULL for a model of
 * another formulation. Points into d's scratch (valid until the next
 * evaluation). */
const double *pom_dyn_exact_mass_matrix(const pom_dyn_model *m, pom_dyn_data *d, const double *y);
/* The exact path's Jacobian at y into d->jac (CSC over the model's pattern):
 * the orientation and omega columns analytic when the architecture has
 * second-order kinematics (pom_kin_has_twists_diff) and the controller
 * analytic partials (no RHS evaluation then), else forward differences; the
 * coil and PID columns analytic (docs/dynamics-exact.md section 5); f0 =
 * f(y), yp, fp scratch of n_states. Returns the RHS status (0 ok). */
int pom_dyn_exact_jacobian(pom_dyn_data *d, const double *y, const double *f0, double *yp,
                           double *fp);

#endif
