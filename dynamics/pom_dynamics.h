/* pom_dynamics.h - bond-graph multi-body simulation of a mechanism with
 * voice-coil actuators and saturated PID control, integrated with CVODE
 * (derivations: docs/dynamics.md).
 *
 * A const model (pom_dyn_model) is built once from a pom_mechanism and the
 * parameters; each worker thread owns a pom_dyn_data. One call of
 * pom_dyn_simulate runs one maneuver from rest at home to actuator setpoints.
 *
 * This header is a contract used by doe/, optimize/ and cli/: extend it, do
 * not rename or remove fields. */
#ifndef POM_DYNAMICS_H
#define POM_DYNAMICS_H

#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

typedef enum { POM_PID_IDEAL = 0, POM_PID_PARALLEL = 1 } pom_pid_form;
typedef enum { POM_ORIENT_EULER_ZYX = 0, POM_ORIENT_QUATERNION = 1 } pom_orient_kind;
/* Newton linear solver of the parasitic path: SUNDIALS' dense LU, KLU, or the block LU over
 * the bond graph's groups (docs/dynamics.md section 7, "Structured Newton solve"). */
typedef enum {
  POM_LINSOL_DENSE = 0,
  POM_LINSOL_KLU = 1,
  POM_LINSOL_STRUCTURED = 2
} pom_linsol_kind;
/* Newton Jacobian: the formulation's analytic one (finite differences where it has none) or
 * coloured finite differences (docs/dynamics.md section 7). */
typedef enum { POM_JAC_ANALYTIC = 0, POM_JAC_FINITE_DIFFERENCE = 1 } pom_jac_kind;
/* Joint model (joints.model): parasitic springs (docs/dynamics.md) or exact
 * constraints in minimal coordinates (docs/dynamics-exact.md). */
typedef enum { POM_JOINTS_PARASITIC = 0, POM_JOINTS_RIGID = 1 } pom_joint_model;
/* Limb-body inertia model (scene.limb_inertia, docs/dynamics.md section 13). */
typedef enum { POM_INERTIA_FULL = 0, POM_INERTIA_LUMPED = 1 } pom_inertia_kind;

/* Voice-coil actuator, identical for the three limbs: linear (kind
 * POM_ACT_PRISMATIC, q in m) or rotary (POM_ACT_REVOLUTE, q in rad; the law
 * of docs/dynamics.md section 4 with a torque). The kind must be the
 * mechanism's actuator kind (pom_dyn_model_create checks it). */
typedef struct {
  double force_constant;   /* linear: K_m, force per current = back-EMF per velocity (N/A =
                              V s/m); rotary: K_t, torque per current = back-EMF per angular
                              velocity (N m/A = V s/rad) */
  double resistance;       /* coil resistance R_c (ohm) */
  double inductance;       /* coil inductance L (H) */
  double bearing_friction; /* viscous bearing friction b: linear (N s/m), rotary (N m s/rad) */
  double voltage_limit;    /* saturation of the drive voltage, +- (V) */
  double sensor_gain;      /* K_S: linear (V/m), rotary (V/rad) */
  /* added by issue 9 (rotary actuators) */
  pom_actuator_kind kind; /* POM_ACT_PRISMATIC (default, "linear") or POM_ACT_REVOLUTE
                             ("rotary") */
} pom_dyn_actuator;

/* A controller type (its op table and descriptors: pom_dyn_ctrl.h). */
typedef struct pom_dyn_ctrl_type pom_dyn_ctrl_type;

#define POM_DYN_CTRL_MAX_GAINS   8 /* gain slots of a controller type other than the PID */
#define POM_DYN_CTRL_MAX_OPTIONS 4 /* option slots of a controller type other than the PID */

/* The controller of every actuator: a type (pom_dyn_ctrl.h; NULL reads as
 * the PID) and its gains. The PID keeps its gains in the named fields:
 * PID on e = q_set - q (m or rad); derivative on the measured velocity.
 * ideal:    u = sat(K_S K_P (e + K_I int e - tau_D q_dot))
 * parallel: u = sat(K_S (K_P e + K_I int e - K_D q_dot)) */
typedef struct {
  pom_pid_form form;
  double kp; /* K_P (V/V) */
  double ki; /* ideal: integral factor (1/s); parallel: K_I (1/s) */
  double kd; /* ideal: tau_D (s); parallel: K_D (s) */
  /* added by the controller types (issue 17) */
  const pom_dyn_ctrl_type *type;        /* the law; NULL = the PID (pom_dyn_ctrl_pid) */
  double gain[POM_DYN_CTRL_MAX_GAINS];  /* other types' gains, by their descriptors (SI) */
  int option[POM_DYN_CTRL_MAX_OPTIONS]; /* other types' option indices */
} pom_dyn_controller;

/* Parasitic joint elements (pseudo-constraints). */
typedef struct {
  double stiffness;         /* k_p for linear constraints (N/m) */
  double damping;           /* R_p for linear constraints (N s/m) */
  double angular_stiffness; /* k_p for angular constraints (N m/rad) */
  double angular_damping;   /* R_p for angular constraints (N m s/rad) */
  pom_joint_model model;    /* parasitic (default) or rigid; rigid needs the architecture
                               (the arch argument of pom_dyn_model_create) and ignores the
                               four values above */
} pom_dyn_joints;

/* What the scene models. */
typedef struct {
  int gravity;          /* 1: gravity on */
  int bearing_friction; /* 1: b v on each actuator */
  int coil_inductance;  /* 1: L di/dt dynamics; 0: quasi-static current */
  pom_orient_kind orientation;
  double euler_cos_min; /* |cos pitch| of any body below which the Euler path stops with
                           POM_ERR_EULER_SINGULAR (default 1e-2, pitch beyond 89.4 deg; the
                           config key scene.euler_cos_min since the parameter list) */
  /* added by the scene options (issue 6, docs/dynamics.md section 13) */
  pom_inertia_kind limb_inertia; /* full: every body as given; lumped: binary S-S links become
                                    massless distance constraints with their mass at the two
                                    ends, bodies pivoting on the ground turn about the pivot */
  int universal_joint;           /* 1: universal joints keep their anti-spin constraint; 0: they
                                    act as spherical joints (the limb may spin) */
} pom_dyn_scene;

/* CVODE settings. */
typedef struct {
  double rtol;       /* relative tolerance */
  double atol_scale; /* 0 (default): absolute tolerance of each state = rtol * its natural size
                        (docs/dynamics.md section 7, docs/dynamics-exact.md section 5); > 0:
                        atol_scale * characteristic scale per state kind */
  double max_step;   /* s, 0 = unlimited */
  long max_steps;    /* per maneuver */
  pom_linsol_kind linear_solver;
  int max_order; /* largest BDF order, 1..5 (default 5); the rigid path may cap it at 2 */
  int stability_limit_detection; /* 1: CVODE's BDF stability limit detection (default 1; the
                                    closed loop has lightly damped fast poles, docs 7) */
  /* added for the extreme cases (issue 6, docs/dynamics.md section 14) */
  double max_wall;          /* s of wall-clock time per maneuver, 0 = unlimited (default 60) */
  double max_balance_error; /* a finished maneuver whose energy_balance_error exceeds this is
                               a failure (POM_ERR_UNSTABLE); 0 = no check (default 0.05) */
  pom_jac_kind jacobian;    /* analytic (default) or finite-difference (issue 10) */
  double min_dexterity;     /* rigid joints: a maneuver whose platform pose has 3/kappa_F(J) below
                               this stops (POM_ERR_SINGULAR), in [0, 0.99], 0 = off (default
                               1e-3; docs/dynamics-exact.md section 3) */
} pom_dyn_solver;

/* Maneuver definition. */
typedef struct {
  double horizon;     /* s (default 0.100) */
  double settle_band; /* fraction of |step| (default 0.02) */
  double output_dt;   /* s, trace sampling period (default 1e-4); the metrics do not use it */
  /* pointing band of the platform (docs/results.md section 1b): the angle
   * between the platform's and the target orientation must stay within
   * max(pointing_band, pointing_band_rel x rotation angle of the target) */
  double pointing_band;     /* rad (default 1e-3) */
  double pointing_band_rel; /* fraction of the target's rotation angle (default 0: off) */
} pom_dyn_maneuver;

typedef struct {
  pom_dyn_actuator actuator;
  pom_dyn_controller controller;
  pom_dyn_joints joints;
  pom_dyn_scene scene;
  pom_dyn_solver solver;
  pom_dyn_maneuver maneuver;
} pom_dyn_params;

/* Defaults: the reference values of docs/PARAMETERS.md for the 3P-S-S/S. */
void pom_dyn_params_defaults(pom_dyn_params *p);

/* Reads the `actuator`, `controller`, `joints`, `scene`, `solver` and
 * `maneuver` groups (docs/config.md) over the defaults. */
pom_status pom_dyn_params_load(pom_dyn_params *p, const pom_cfg *cfg, pom_error *err);

/* Checks every parameter outside the controller against the range that
 * loading checks (pom_dyn_params_schema.h: one range per parameter), the
 * controller against its type's descriptors, and the relations between
 * parameters (the coil's inductance when scene.coil_inductance is on, the
 * trace grid within the horizon). POM_ERR_ARG naming the config key
 * otherwise. pom_dyn_model_create calls it. */
pom_status pom_dyn_params_check(const pom_dyn_params *p, pom_error *err);

/* Ends of the ranges of solver.rtol and joints.stiffness_N_per_m: what
 * integrates with the shipped defaults (max_steps 200000) on every shipped
 * architecture (docs/dynamics.md section 14, "Ranges"; measured by
 * bench/range_limits.sh): rtol 1e-13 with natural sizes runs out of steps
 * (3S-P-S/S, 3-RRR), a linear stiffness of 3e10 N/m does (3P-S-S/S). */
#define POM_DYN_RTOL_MIN      1e-12
#define POM_DYN_STIFFNESS_MAX 1e10

/* Absolute tolerances per unit of rtol under the scale rule: a model uses
 * atol_scale = min(solver.atol_scale, POM_DYN_ATOL_PER_RTOL x rtol), so that
 * an rtol asked below solver.atol_scale / 1e3 tightens the absolute
 * tolerances with it (docs/dynamics.md section 7; the shipped pair rtol
 * 1e-6, atol_scale 1e-3 sits on the line). */
#define POM_DYN_ATOL_PER_RTOL 1e3

/* The atol_scale a model built from s integrates with (docs/dynamics.md
 * section 7): 0 (natural sizes) for 0; otherwise s->atol_scale, or
 * POM_DYN_ATOL_PER_RTOL x s->rtol when that is smaller by more than rounding
 * (a pair on the line, such as the shipped 1e-6 and 1e-3, keeps its
 * atol_scale bit for bit). */
double pom_dyn_atol_scale_used(const pom_dyn_solver *s);

/* The config groups pom_dyn_params_load reads (`actuator`, `controller`,
 * `joints`, `scene`, `solver`, `maneuver`), NULL-terminated, static
 * storage: callers use it to refuse settings that the model never reads
 * (docs/config.md). */
const char *const *pom_dyn_param_groups(void);

typedef struct pom_dyn_model pom_dyn_model;
typedef struct pom_dyn_data pom_dyn_data;

/* Builds the const model of mech with parameters p (copied) in the
 * formulation p->joints.model names: the parasitic bond graph
 * (docs/dynamics.md) or the exact rigid joints in minimal coordinates
 * (docs/dynamics-exact.md). arch is the architecture mech was built from
 * (pom_kin_mechanism_from); only the rigid formulation reads it, and it fails
 * with POM_ERR_ARG when arch is NULL; it may be NULL for the parasitic one.
 * The rigid model checks that the kinematic body poses realise every joint
 * of mech (POM_ERR_ARG naming the joint otherwise). p->actuator.kind must
 * match every actuator of mech (POM_ERR_ARG otherwise). The caller owns *out
 * (pom_dyn_model_destroy). */
pom_status pom_dyn_model_create(pom_dyn_model **out, const pom_mechanism *mech,
                                const pom_kin_arch *arch, const pom_dyn_params *p, pom_error *err);
/* Frees a model; NULL is a no-op. */
void pom_dyn_model_destroy(pom_dyn_model *m);

/* pom_dyn_model_create with the model a model-based controller believes in:
 * ctrl_mech, ctrl_arch and ctrl_params (the nominal candidate) build the
 * controller's own model while mech, arch and p are the plant (which an
 * `uncertain` draw may have changed). NULL for any of the three: the
 * plant's. Controllers without a model ignore them. */
pom_status pom_dyn_model_create_ex(pom_dyn_model **out, const pom_mechanism *mech,
                                   const pom_kin_arch *arch, const pom_dyn_params *p,
                                   const pom_mechanism *ctrl_mech, const pom_kin_arch *ctrl_arch,
                                   const pom_dyn_params *ctrl_params, pom_error *err);

pom_status pom_dyn_data_create(pom_dyn_data **out, const pom_dyn_model *m, pom_error *err);
void pom_dyn_data_destroy(pom_dyn_data *d);

/* rigid_limit_ratio above which the parasitic model is not at its rigid
 * limit (docs/dynamics.md section 13b: the joints' dynamic deviation from
 * their quasi-static response is of order the ratio; 1e-2 = a drive time
 * ten times the joint's 1/omega). `pomlab simulate` warns, studies count. */
#define POM_DYN_RIGID_LIMIT_WARN 1e-2
/* joint_dissipation_share above which the parasitic model is not at its
 * rigid limit (docs/dynamics.md section 13b: the joints' own motion, of
 * relative amplitude ~sqrt(share), moves the energy by at most 2.5
 * sqrt(share) in every measured case; 2e-4 separates the 3S-P-S/S k_p
 * sweep's 2.5 % gap (6.7e-4) from its 0.5 % one (7.5e-5)). */
#define POM_DYN_JOINT_SHARE_WARN 2e-4

/* Metrics of one maneuver. Times in s, energies in J. */
typedef struct {
  pom_status status;       /* POM_OK or why it failed */
  char reason[256];        /* failure reason, "" when ok */
  double target[3];        /* setpoints (m, or rad for rotary actuators) */
  double settling_time[3]; /* last time outside the band of settle_band |step| about the setpoint
                              (s); NaN if unsettled */
  int settled[3];          /* 1 when inside the band at the horizon */
  double settling_time_final[3]; /* stepinfo variant: band about the final value */
  double execution_time;         /* max of settling_time (s); NaN if any unsettled */
  double energy[3];              /* int u i dt, signed (J) */
  double energy_positive[3];     /* int max(u i, 0) dt (J) */
  double energy_total;           /* sum of energy[] (J) */
  double peak_voltage[3];        /* max |u| (V) */
  double saturation_time[3];     /* time with |u| at the limit (s) */
  double final_q[3];             /* q at the horizon (m or rad) */
  double max_abs_q[3];           /* largest |q| over the integrator's steps (m or rad) */
  double max_deflection;         /* largest parasitic deflection (m) */
  double energy_balance_error; /* |supplied - dissipated - stored change| / energy_balance_scale */
  long steps, rhs_evals, jac_evals, newton_iters, error_test_fails;
  double wall_time; /* s */
  /* added by dynamics (issue 3) */
  double max_angular_deflection; /* largest angular parasitic deflection (rad) */
  double energy_supplied;        /* sum over sources of int u i dt (J) = energy_total */
  double energy_dissipated;      /* coil + bearing + parasitic dampers (J) */
  double energy_stored_change;   /* kinetic + gravity + springs + coil, end minus start (J) */
  double energy_coil[3];         /* int R_c i^2 dt per actuator (J) */
  double energy_bearing[3];      /* int b q_dot^2 dt per actuator (J) */
  double energy_parasitic;       /* int of all parasitic damper powers (J) */
  double energy_balance_scale;   /* denominator of energy_balance_error (J), see docs/dynamics.md */
  long jac_rhs_evals;            /* RHS evaluations spent inside the Jacobian (part of rhs_evals) */
  long linsol_setups;            /* Newton matrix factorizations */
  long nonlin_conv_fails;        /* Newton convergence failures */
  double last_step;              /* last internal step size (s) */
  /* platform-level metrics (issue 18, docs/results.md section 1b) */
  double horizon; /* the maneuver's horizon (s): the value an unsettled time is censored at */
  double pointing_settling_time; /* time after which the angle between the platform's and the
                                    target orientation stays within the pointing band (s); NaN
                                    when unsettled or the target orientation is unknown */
  int pointing_settled;          /* 1 when the pointing error is inside its band at the horizon */
  double final_pointing_error;   /* that angle at the horizon (rad); NaN when unknown */
  double peak_angular_rate;      /* largest |omega| of the platform (rad/s) */
  double peak_effort[3];         /* largest |K_m i - b q_dot| of each actuator (N or N m) */
  double tracking_rms_error;     /* time-averaged RMS over the horizon of the angle between the
                                    platform and the controller's reference (rad); NaN without a
                                    trajectory */
  int stepinfo_unresolved[3];    /* 1 when the stepinfo band (settle_band times the largest
                                    deviation from the final value) is narrower than what the
                                    integration resolves of that position: settling_time_final is
                                    then NaN (docs/results.md section 1c) */
  double rigid_limit_ratio;      /* parasitic joints: 1 / (omega_low T_E)^2, omega_low the lowest
                                    joint frequency (rad/s) and T_E the duration over which the
                                    drive spends its energy (s); above POM_DYN_RIGID_LIMIT_WARN the
                                    parasitic model is not at its rigid limit (docs/dynamics.md
                                    section 13b). NaN on rigid joints and when the maneuver did
                                    not finish */
  /* parasitic joints: energy_parasitic over the drive's positive mechanical
   * work int sum max(0, effort q_dot) dt, the share of what the drive puts
   * into the mechanism that the joints' own motion dissipates; above
   * POM_DYN_JOINT_SHARE_WARN not at the rigid limit (docs/dynamics.md
   * section 13b). NaN as rigid_limit_ratio */
  double joint_dissipation_share;
  /* largest |i| over the coils and the horizon, its interior maxima located
   * on the interpolant (A; docs/optimize.md 12.2): NaN unless the data
   * watched it (pom_dyn_data_watch_peak_current; every sensitivity run).
   * Not in the metric schema: no output shows it but the gradients' */
  double peak_current;
} pom_dyn_metrics;

/* The validity rule (docs/dynamics.md section 13b): 1 when a finished
 * parasitic maneuver is not at its rigid limit, i.e. when its
 * rigid_limit_ratio exceeds POM_DYN_RIGID_LIMIT_WARN (the drive outruns the
 * joints) or its joint_dissipation_share exceeds POM_DYN_JOINT_SHARE_WARN
 * (the joints move on their own); 0 otherwise, also for NaN (rigid joints,
 * failed maneuvers). */
int pom_dyn_rigid_limit_exceeded(const pom_dyn_metrics *mt);
/* The same rule on the two values (as a results row stores them): 1
 * flagged, 0 at the rigid limit, -1 not measured (both NaN: rigid joints or
 * a maneuver that did not finish). */
int pom_dyn_rigid_limit_flag(double rigid_limit_ratio, double joint_dissipation_share);

/* Optional traces of a maneuver, sampled every output_dt. Owned by caller:
 * create with pom_dyn_trace_create, free with pom_dyn_trace_destroy. */
typedef struct pom_dyn_trace pom_dyn_trace;
struct pom_dyn_trace {
  int capacity;       /* samples allocated */
  int n;              /* samples filled by the last pom_dyn_simulate */
  int n_actuators;    /* actuator columns in use (<= 3 stored) */
  double *t;          /* [capacity] time (s) */
  double *q;          /* [capacity][3] actuator coordinate from mid-stroke (m or rad) */
  double *q_dot;      /* [capacity][3] actuator rate (m/s or rad/s) */
  double *current;    /* [capacity][3] coil current (A) */
  double *voltage;    /* [capacity][3] saturated drive voltage u (V) */
  double *energy;     /* [capacity][3] cumulative source energy int u i dt (J) */
  double *euler_zyx;  /* [capacity][3] platform (psi, theta, phi) (rad) */
  double *quat;       /* [capacity][4] platform unit quaternion (w, x, y, z) */
  double *deflection; /* [capacity] largest linear parasitic deflection at t (m) */
};

/* Allocates a trace for the model's horizon and output_dt (capacity =
 * horizon / output_dt + 2). The caller owns *out. */
pom_status pom_dyn_trace_create(pom_dyn_trace **out, const pom_dyn_model *m, pom_error *err);
void pom_dyn_trace_destroy(pom_dyn_trace *tr);

/* Runs one maneuver to `target` (m, per actuator). Numerical failure is
 * reported in metrics->status/reason and returned; the model and data stay
 * usable. trace may be NULL. */
pom_status pom_dyn_simulate(const pom_dyn_model *m, pom_dyn_data *d, const double target[3],
                            pom_dyn_metrics *metrics, pom_dyn_trace *trace, pom_error *err);

/* ---- added by dynamics (issue 3) ----------------------------------------- */

/* Initial body velocities for pom_dyn_simulate_ex (used by tests and
 * free-motion studies): body k (mechanism index, 1..n_bodies-1) starts at home
 * with CM velocity v[k] (m/s) and angular velocity omega[k] (rad/s), both in
 * the fixed frame. Entries for the ground are ignored. */
typedef struct {
  double v[POM_MECH_MAX_BODIES][3];
  double omega[POM_MECH_MAX_BODIES][3];
} pom_dyn_initial;

/* pom_dyn_simulate with an optional initial velocity field (NULL = rest, the
 * maneuver definition). */
pom_status pom_dyn_simulate_ex(const pom_dyn_model *m, pom_dyn_data *d, const double target[3],
                               const pom_dyn_initial *init, pom_dyn_metrics *metrics,
                               pom_dyn_trace *trace, pom_error *err);

/* A setpoint path (issue 28, docs/capability.md): fills target[n_actuators]
 * (m or rad) with the setpoints at time t (s) of the maneuver. A pure
 * function of t: the engine calls it at every evaluation, in any order of t. */
typedef void (*pom_dyn_setpoint_fn)(void *ctx, double t, double *target);

/* Makes the following pom_dyn_simulate runs on d follow fn(ctx, t) instead
 * of their constant target (which still sets the stroke check, the target
 * orientation and the settling bands); fn NULL restores the constant target.
 * ctx is not owned. The frequency response's time-domain check drives a
 * small sine about a pose with it. */
void pom_dyn_set_setpoint_path(pom_dyn_data *d, pom_dyn_setpoint_fn fn, void *ctx);

/* on = 1: the following runs on d locate the peak coil current
 * (metrics->peak_current: three more evaluations per step and a root search
 * at each local maximum, docs/optimize.md 12.2); 0 (the default): NaN. A
 * sensitivity run watches it whatever this says. */
void pom_dyn_data_watch_peak_current(pom_dyn_data *d, int on);

/* Parameters the model was built with (never NULL for a valid model). */
const pom_dyn_params *pom_dyn_model_params(const pom_dyn_model *m);

/* Number of ODE states of the model (bodies, coils, integrators, energy
 * accumulators), and the number of colours of its finite-difference
 * Jacobian (= RHS evaluations per Jacobian). */
int pom_dyn_model_n_states(const pom_dyn_model *m);
int pom_dyn_model_n_colors(const pom_dyn_model *m);

/* Pose of mechanism body k at the end of the last simulation of d: rotation
 * from home R (fixed frame) and CM position x (m). POM_ERR_ARG for a bad k. */
pom_status pom_dyn_body_pose(const pom_dyn_model *m, const pom_dyn_data *d, int k, double R[9],
                             double x[3], pom_error *err);

/* Stored energy (kinetic + gravitational relative to home + parasitic springs
 * + coil) at the end of the last simulation of d (J; NaN before any run).
 * Uses d's scratch. */
double pom_dyn_stored_energy(const pom_dyn_model *m, pom_dyn_data *d);

/* Short names for messages and JSON: "ideal"/"parallel", "euler"/"quaternion",
 * "dense"/"klu". */
const char *pom_dyn_pid_form_name(pom_pid_form f);
const char *pom_dyn_orient_name(pom_orient_kind k);
const char *pom_dyn_linsol_name(pom_linsol_kind k);
const char *pom_dyn_jacobian_name(pom_jac_kind k);
/* "parasitic"/"rigid" (joints.model). */
const char *pom_dyn_joint_model_name(pom_joint_model k);
/* "full"/"lumped" (scene.limb_inertia). */
const char *pom_dyn_inertia_name(pom_inertia_kind k);

#endif
