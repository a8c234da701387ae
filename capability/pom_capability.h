/* pom_capability.h - what a design can do in the figures pointing devices are
 * specified by (docs/capability.md): over the regular dexterous workspace,
 * the platform's peak angular acceleration from rest and steady angular rate
 * under the voltage (and current) limits, inscribed (every direction) and per
 * fixed axis, and large-angle slew times simulated with the controller, on
 * the rigid model (dynamics/pom_dyn_rigid.h) whatever joints.model says; the
 * small-signal bandwidth and margins (dynamics/pom_dyn_freq.h) on the
 * config's own joints.model.
 * Layered right after dynamics (docs/layers.txt). */
#ifndef POM_CAPABILITY_H
#define POM_CAPABILITY_H

#include "pom_cap_figures.h"
#include "pom_config.h"
#include "pom_dyn_rigid.h"
#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

#include <stdio.h>

#define POM_CAP_MAX_AMPLITUDES 16 /* slew amplitudes per direction (the edge included) */
#define POM_CAP_MAX_DIRECTIONS 4  /* slew directions: x, y, z, (1, 1, 1)/sqrt 3 */
#define POM_CAP_MAX_GRID       41 /* poses per Euler angle */

/* Options: the `capability` config group (docs/config.md). */
typedef struct {
  int grid_points;      /* poses per Euler angle over the workspace cube, odd (default 5) */
  double current_limit; /* I_max (A), 0 = the voltage limit alone (default 0) */
  int rate_directions;  /* Fibonacci-sphere points of the inscribed rate search (default 200) */
  int slew_directions;  /* 0..4 of x, y, z, (1,1,1)/sqrt 3 (default 4; 0 = no slews) */
  int bandwidth_grid;   /* poses per Euler angle of the small-signal figures, odd, a sub-grid
                           of grid_points (default 3; 1 = home alone, 0 = none); home and the
                           worst envelope poses are always evaluated when > 0 */
  int n_amplitudes;     /* amplitudes asked for */
  double amplitude[POM_CAP_MAX_AMPLITUDES]; /* rad, ascending (default 1, 3, 10, 30 deg) */
  /* progress: called after each pose and each slew with (done, total); NULL = none */
  void (*progress)(void *user, long done, long total);
  void *progress_user;
} pom_cap_opts;

void pom_cap_defaults(pom_cap_opts *o);
/* Reads the `capability` group over the defaults; POM_ERR_CONFIG naming the key. */
pom_status pom_cap_load(pom_cap_opts *o, const pom_cfg *cfg, pom_error *err);
/* The groups pom_cap_load reads ("capability"), NULL-terminated, static. */
const char *const *pom_cap_groups(void);

/* ---- the envelope at one pose (docs/capability.md sections 2, 3) ----------- */
/* Acceleration from rest: largest s with s d reachable along the unit d
 * (rad/s^2), for efforts |F_a| <= f_max, M w_dot = g + J^T F. NaN when J is
 * singular; 0 when the pose cannot be held against gravity. */
double pom_cap_acc_along(const double M[9], const double J[9], const double g[3], double f_max,
                         const double d[3]);
/* The inscribed radius (rad/s^2) of the acceleration polytope, equation (3),
 * and its worst direction (unit; may be NULL). NaN when J is singular. */
double pom_cap_acc_inscribed(const double M[9], const double J[9], const double g[3], double f_max,
                             double worst[3]);

/* What the steady-rate limit needs at one pose: J, gravity, the quadratic
 * form of the velocity terms and the actuator's constants. */
typedef struct {
  double J[9];           /* q_dot = J w */
  double gravity[3];     /* g(R) (N m) */
  double H[3][9];        /* h_k(R, w) = w^T H[k] w (N m s^2), H[k] symmetric */
  double K;              /* force (torque) constant = back-EMF constant */
  double Rc;             /* coil resistance (ohm) */
  double b;              /* bearing friction (N s/m or N m s/rad; 0 when off) */
  double V;              /* voltage limit (V) */
  double I_max;          /* current limit (A), 0 = none */
  int no_velocity_terms; /* 1: h ignored (the back-EMF-only limit) */
} pom_cap_rate_model;
/* Steady rate along unit d (rad/s): the smallest s > 0 at which a voltage
 * (or current) reaches its limit holding w = s d, w_dot = 0 (section 3).
 * *binding (may be NULL): 0-based actuator that binds, +3 when it is the
 * current; INFINITY when nothing binds. */
double pom_cap_rate_along(const pom_cap_rate_model *rm, const double d[3], int *binding);
/* The rate model of the rigid model m at rotation R (six evaluations of the
 * velocity terms give their quadratic form), with the current limit (A, 0 =
 * none); the terms at rest into *rest when non-NULL. Fails as
 * pom_dyn_rigid_terms_at. */
pom_status pom_cap_rate_model_at(const pom_dyn_model *m, pom_dyn_data *d, const double R[9],
                                 double current_limit, pom_cap_rate_model *rm,
                                 pom_dyn_rigid_terms *rest, pom_error *err);
/* The minimum over unit directions (n Fibonacci points, then a pattern
 * search) and its direction (may be NULL). */
double pom_cap_rate_inscribed(const pom_cap_rate_model *rm, int n, double worst[3]);

/* Every figure of one pose. */
typedef struct {
  double euler[3];           /* ZYX Euler angles (psi, theta, phi) (rad) */
  double q[3];               /* its actuator coordinates (m or rad; the home branch's IK) */
  int ok;                    /* 1 when evaluated (the rigid terms exist there) */
  double acc_inscribed;      /* rad/s^2 */
  double acc_axis[3];        /* per fixed axis, the smaller of the two senses (rad/s^2) */
  double acc_worst_dir[3];   /* unit */
  double rate_inscribed;     /* rad/s */
  double rate_axis[3];       /* rad/s */
  double rate_worst_dir[3];  /* unit */
  int rate_binding;          /* actuator binding the inscribed rate (0-based, +3: current) */
  double rate_emf_inscribed; /* the same without the velocity terms (back-EMF only) (rad/s) */
  double rate_emf_axis[3];   /* rad/s */
  /* small-signal closed loop at the pose (dynamics/pom_dyn_freq.h); NaN where not evaluated */
  double bw_axis_hz[3]; /* -3 dB bandwidth of a setpoint rotation about fixed x, y, z (Hz) */
  double bw_worst_hz;   /* the same in the worst direction (Hz) */
  double peak_db_worst; /* resonant peak (dB) */
  double pm_deg_min;    /* smallest phase margin of the actuator loops (deg) */
  double gm_db_min;     /* smallest gain margin of the actuator loops (dB; inf: none) */
  double mode_hz;       /* lowest parasitic joint mode (Hz; NaN: none, the rigid path) */
  double mode_zeta;     /* its damping ratio */
  int freq_ok;          /* 1 when the small-signal figures were evaluated there */
} pom_cap_pose;

/* ---- one pose, any rotation (pom_cap_run's evaluation, for callers that
 * sample other poses: `pomlab view --capability`) ------------------------- */
typedef struct pom_cap_ctx pom_cap_ctx;
/* The rigid model of the envelope and, when with_freq, the config's own
 * model of the small-signal figures (as pom_cap_run). */
pom_status pom_cap_ctx_create(pom_cap_ctx **out, const pom_kin_arch *arch,
                              const pom_mechanism *mech, const pom_dyn_params *p,
                              const pom_cap_opts *o, int with_freq, pom_error *err);
void pom_cap_ctx_destroy(pom_cap_ctx *c);
/* Every figure at rotation R into *pp (euler set from R; the small-signal
 * ones when the context has them, else NaN). Fails as pom_cap_rate_model_at
 * or pom_dyn_freq_figures_at (pp->ok and pp->freq_ok say how far it got). */
pom_status pom_cap_pose_eval(pom_cap_ctx *c, const double R[9], pom_cap_pose *pp, pom_error *err);

/* A figure of one pose by name, for colouring maps: name, display unit and
 * the factor from SI to it, whether it needs the small-signal model, and
 * what it is. */
typedef struct {
  const char *name;
  const char *unit;
  double to_display;
  int freq;
  const char *description;
} pom_cap_pose_figure;
/* The table (n entries, static). */
const pom_cap_pose_figure *pom_cap_pose_figures(int *n);
/* By name; NULL when unknown. */
const pom_cap_pose_figure *pom_cap_pose_figure_find(const char *name);
/* Its value at pp in display units (NaN when not evaluated there). */
double pom_cap_pose_figure_value(const pom_cap_pose_figure *f, const pom_cap_pose *pp);

/* The slews about one direction. */
typedef struct {
  double dir[3];                             /* unit axis (fixed frame) */
  double edge;                               /* workspace edge along it (rad) */
  int n;                                     /* amplitudes run (within the edge, the edge last) */
  double amplitude[POM_CAP_MAX_AMPLITUDES];  /* rad */
  double slew_time[POM_CAP_MAX_AMPLITUDES];  /* pointing settling time (s); NaN: unsettled */
  double peak_rate[POM_CAP_MAX_AMPLITUDES];  /* largest |w| (rad/s) */
  pom_status status[POM_CAP_MAX_AMPLITUDES]; /* the maneuver's status */
  int n_beyond;                              /* amplitudes asked for beyond the edge */
} pom_cap_slew;

/* The whole result. */
typedef struct {
  double half_width; /* the workspace cube's half-width (rad) */
  double step;       /* grid step (rad), 0 for a single pose */
  int n_poses;
  pom_cap_pose *pose;     /* [n_poses], psi-major; owned (pom_cap_result_free) */
  int home;               /* index of home */
  int worst_acc;          /* pose of the smallest inscribed acceleration */
  int worst_rate;         /* pose of the smallest inscribed rate */
  int worst_bw;           /* pose of the smallest worst-direction bandwidth (-1: not evaluated) */
  double bw_worst_hz;     /* smallest worst-direction bandwidth over the poses (Hz; NaN: none) */
  double pm_worst_deg;    /* smallest phase margin over the poses (deg; NaN: none) */
  int worst_pm;           /* its pose (-1: not evaluated) */
  int n_freq;             /* poses where the small-signal figures were evaluated */
  int n_freq_failed;      /* poses where they were asked for and failed (NaN kept) */
  pom_status freq_status; /* the first failure's status (POM_OK: none) */
  pom_joint_model freq_joints; /* the small-signal model's joints (the config's joints.model) */
  double f_max;                /* effort limit from rest K min(I_max, V/R_c) (N or N m) */
  pom_actuator_kind kind;
  int n_dirs;
  pom_cap_slew slew[POM_CAP_MAX_DIRECTIONS];
  double wall_time; /* s */
} pom_cap_result;

/* Everything: the workspace (pom_kin_workspace with ws), the envelope over
 * its grid, the small-signal figures (dynamics/pom_dyn_freq.h) on the
 * bandwidth sub-grid, the slews. mech and arch as pom_dyn_model_create; p is
 * the config's parameters: the envelope and the slews replace joints.model
 * by "rigid", the small-signal figures keep it (the parasitic joints' modes
 * belong to the loop's response). */
pom_status pom_cap_run(const pom_kin_arch *arch, const pom_kin_ws_opts *ws,
                       const pom_mechanism *mech, const pom_dyn_params *p, const pom_cap_opts *o,
                       pom_cap_result *res, pom_error *err);
void pom_cap_result_free(pom_cap_result *res);

/* The small-signal Bode data at the pose q_pose (actuator coordinates, as
 * pom_cap_pose.q) as pom_dyn_freq_json writes it (scripts/plot_bode.py draws
 * it), f_lo .. f_hi Hz at per_decade points, on the model of p with its own
 * joints.model, into path. */
pom_status pom_cap_write_bode(const char *path, const pom_kin_arch *arch, const pom_mechanism *mech,
                              const pom_dyn_params *p, const double q_pose[3], double f_lo,
                              double f_hi, int per_decade, pom_error *err);

/* ---- outputs (cap_report.c) ---------------------------------------------------- */
/* Text in device units (deg/s, deg/s^2, ms); JSON in SI. */
void pom_cap_print_text(FILE *out, const char *name, const pom_cap_opts *o,
                        const pom_cap_result *r);
void pom_cap_print_json(FILE *out, const char *name, const pom_cap_opts *o,
                        const pom_cap_result *r);
/* The grid as CSV (deg, deg/s, deg/s^2) for scripts/plot_capability.py. */
pom_status pom_cap_write_csv(const char *path, const pom_cap_result *r, pom_error *err);
/* HDF5 (SI): /poses, /slews, attributes; program and config text recorded. */
pom_status pom_cap_write_h5(const char *path, const char *program, const pom_cfg *cfg,
                            const char *name, const pom_cap_opts *o, const pom_cap_result *r,
                            pom_error *err);

/* ---- candidate figures (pom_cap_figures.h; cap_figures.c) ------------------------------- */
/* Figure i's key, SI unit, description; 1 when it needs the slews. */
const char *pom_cap_figure_name(int i);
const char *pom_cap_figure_unit(int i);
const char *pom_cap_figure_description(int i);
int pom_cap_figure_needs_slews(int i);
/* The index of the figure called name, -1 when there is none. */
int pom_cap_figure_index(const char *name);
/* "a, b, c": every figure's name, for messages (cap bytes). */
void pom_cap_figure_list(char *buf, size_t cap);
/* Figure i of r in SI; NaN where not computed. */
double pom_cap_figure_value(const pom_cap_result *r, int i);
/* The longest slew time over the directions at amplitude a (rad, matched to
 * 1e-9 rad); NaN when no direction ran it or one did not settle. */
double pom_cap_slew_worst_time(const pom_cap_result *r, double a);
/* The options a run needs for the figures want[POM_CAP_N_FIGURES] (1 =
 * asked): o as loaded, with grid_points replaced when grid > 0 and the slews
 * cut to what the asked figures read (none, or 10 deg about every
 * direction). */
void pom_cap_opts_for_figures(pom_cap_opts *o, const int *want, int grid);

/* A requirement on a figure: "bw_worst_hz >= 100" (figure, >= or <=, value
 * in the figure's SI unit). */
typedef struct {
  int figure;   /* pom_cap_figure_id */
  int at_most;  /* 0: value >= bound; 1: value <= bound */
  double bound; /* SI */
} pom_cap_requirement;
/* Parses text into *q; POM_ERR_ARG with a message naming the text and the
 * figures when it is not "NAME >= NUMBER" or "NAME <= NUMBER". */
pom_status pom_cap_requirement_parse(pom_cap_requirement *q, const char *text, pom_error *err);
/* 1 when value meets q, 0 when not (a NaN value, not computed, never does). */
int pom_cap_requirement_met(const pom_cap_requirement *q, double value);
/* "bw_worst_hz >= 100" (%.6g) into buf. */
void pom_cap_requirement_text(char *buf, size_t cap, const pom_cap_requirement *q);
/* The one syntax of a list of requirements, for every group that has one
 * (study.capability_require, synthesis.capability_require): key = ["FIGURE
 * >= NUMBER", ...] into q[max], *n of them (0 when key is absent);
 * POM_ERR_CONFIG naming the file, the key ("KEY.[j]") and the text. */
pom_status pom_cap_requirements_load(const pom_cfg *cfg, const char *key, pom_cap_requirement *q,
                                     int max, int *n, pom_error *err);

#endif
