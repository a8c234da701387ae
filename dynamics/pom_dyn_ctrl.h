/* pom_dyn_ctrl.h - what a controller is to pomlab: one table of operations
 * and descriptors (pom_dyn_ctrl_type), in the manner of the architectures'
 * pom_kin_arch_type (kinematics/pom_arch.h). The ideal and parallel PID
 * (ctrl_pid.c) are the built-in implementation; a user's control law is one
 * more file and one registration (docs/extending.md section 8,
 * docs/dynamics.md section 4).
 *
 * Contract every implementation keeps: the law of actuator a sees only what
 * its sensors give, the setpoint, the actuator coordinate q and rate q_dot
 * (m, m/s or rad, rad/s) and the actuator's sensor gain K_S, plus its own
 * controller states z; it returns the raw drive voltage before the
 * saturation, which the engine applies (docs/dynamics.md section 4), and the
 * rates of its states. It never allocates, prints or fails: a law is a pure
 * function of its inputs. */
#ifndef POM_DYN_CTRL_H
#define POM_DYN_CTRL_H

#include "pom_dynamics.h"
#include "pom_h5.h"

#include <stddef.h>

/* Limits of what a type may declare (the sizes of pom_dyn_controller). */
#define POM_DYN_CTRL_MAX_STATES 4 /* states per actuator */

/* One gain: a numeric key of the `controller` group. The value lives in
 * pom_dyn_controller at byte offset `offset` (a double): the PID's gains
 * are its named fields, other types use the slots of gain[]
 * (POM_DYN_CTRL_GAIN_SLOT). Config unit = SI unit (the key names it). */
typedef struct {
  const char *key;     /* key under `controller` ("kp", "ki_per_s", "omega_n_rad_per_s") */
  const char *symbol;  /* in the law's text ("K_P") */
  const char *unit;    /* SI unit of the value ("V/V", "1/s", "s") */
  const char *meaning; /* one line for --list-controllers and docs */
  double lo, hi;       /* allowed range, one check for the config, flags and the model */
  double def;          /* default value */
  int tunable;         /* 1: `pomlab tune` may search it (tuning.variables name = key) */
  int log_search;      /* 1: searched in log (a positive scale gain); 0: linearly */
  size_t offset;       /* byte offset of the double inside pom_dyn_controller */
  /* the default search of `pomlab tune` when tuning.variables is absent */
  int search_default;          /* 1: tuned by default */
  double search_lo, search_hi; /* its default bounds (SI; > 0 when log_search) */
} pom_dyn_gain_desc;

/* Byte offset of slot k of pom_dyn_controller.gain (for types other than the
 * PID). */
#define POM_DYN_CTRL_GAIN_SLOT(k)                                                                  \
  (offsetof(pom_dyn_controller, gain) + (size_t)(k) * sizeof(double))

/* One named choice of the `controller` group (the PID's `form`): an int at
 * byte offset `offset` of pom_dyn_controller holds the index into names. */
typedef struct {
  const char *key;          /* key under `controller` ("form") */
  const char *meaning;      /* one line */
  const char *const *names; /* NULL-terminated; index 0 is the default */
  size_t offset;            /* byte offset of the int inside pom_dyn_controller */
} pom_dyn_ctrl_option_desc;

/* Byte offset of slot k of pom_dyn_controller.option. */
#define POM_DYN_CTRL_OPTION_SLOT(k)                                                                \
  (offsetof(pom_dyn_controller, option) + (size_t)(k) * sizeof(int))

/* What one controller state measures: its unit and hence its scale in the
 * integrator's error test (docs/dynamics.md section 7). */
typedef enum {
  POM_DYN_CTRL_STATE_Q_TIME = 0, /* an integral of q: m s or rad s (the PID integral) */
  POM_DYN_CTRL_STATE_Q = 1,      /* like q: m or rad */
  POM_DYN_CTRL_STATE_RATE = 2    /* like q_dot: m/s or rad/s */
} pom_dyn_ctrl_state_kind;

typedef struct {
  const char *name;    /* "integral" */
  const char *meaning; /* one line */
  pom_dyn_ctrl_state_kind kind;
} pom_dyn_ctrl_state_desc;

/* What the law of one actuator sees (sensors and setpoint). */
typedef struct {
  double target;      /* setpoint q_set (m or rad) */
  double q;           /* measured coordinate from mid-stroke (m or rad) */
  double q_dot;       /* measured rate (m/s or rad/s) */
  double sensor_gain; /* K_S (V/m or V/rad) */
} pom_dyn_ctrl_input;

/* What a coupled controller (law_all) sees of all actuators at once: the
 * sensors (actuator coordinates, rates, and the coil currents where the coil
 * has a state) and the setpoints. */
typedef struct {
  double t;              /* time since the maneuver's start (s): a reference's clock */
  int n;                 /* actuators */
  const double *target;  /* [n] setpoints (m or rad) */
  const double *q;       /* [n] measured coordinates (m or rad) */
  const double *q_dot;   /* [n] measured rates (m/s or rad/s) */
  const double *current; /* [n] measured coil currents (A); NULL for a quasi-static coil */
} pom_dyn_ctrl_sensed;

/* Partial derivatives of the raw voltage u and of the state rates z_dot of
 * one actuator's law with respect to q, q_dot and the states z, at fixed
 * inputs otherwise (the saturation is the engine's, not the law's). */
typedef struct {
  double du_dq;                                                    /* V per m or rad */
  double du_dqd;                                                   /* V per m/s or rad/s */
  double du_dz[POM_DYN_CTRL_MAX_STATES];                           /* V per unit of z_k */
  double dzd_dq[POM_DYN_CTRL_MAX_STATES];                          /* d z_dot_k / d q */
  double dzd_dqd[POM_DYN_CTRL_MAX_STATES];                         /* d z_dot_k / d q_dot */
  double dzd_dz[POM_DYN_CTRL_MAX_STATES][POM_DYN_CTRL_MAX_STATES]; /* d z_dot_k / d z_l */
} pom_dyn_ctrl_partials;

/* What a state rate depends on besides q (flags of rate_deps): the
 * parasitic Jacobian's sparsity pattern is built from them. */
enum {
  POM_DYN_CTRL_DEP_QDOT = 1, /* z_dot reads q_dot */
  POM_DYN_CTRL_DEP_STATE = 2 /* z_dot reads z */
};

/* What the engine lends a model-based controller: building and running a
 * model of its own. Passed to model_create (a controller file calls the
 * engine only through it, so a program that links the descriptors alone,
 * such as the light pomlab, does not link the integrator). */
typedef struct {
  pom_status (*model_create)(pom_dyn_model **out, const pom_mechanism *mech,
                             const pom_kin_arch *arch, const pom_dyn_params *p, pom_error *err);
  void (*model_destroy)(pom_dyn_model *m);
  pom_status (*data_create)(pom_dyn_data **out, const pom_dyn_model *m, pom_error *err);
  void (*data_destroy)(pom_dyn_data *d);
  /* an exact model's M(R) (kg m^2), passive generalized force f(R, w)
   * (gravity and velocity terms, N m), actuator coordinates q and Jacobian J
   * at rotation R and angular velocity w (fixed frame); 0, or 1 when the
   * mechanism cannot be assembled at R (pom_dyn_exact_terms) */
  int (*exact_terms)(const pom_dyn_model *m, pom_dyn_data *d, const double R[9], const double w[3],
                     double M[9], double f[3], double q[3], double J[9]);
} pom_dyn_ctrl_engine;

struct pom_dyn_ctrl_type {
  const char *name;                      /* registry key and `controller.type` value: "pid" */
  const char *label;                     /* "PID" */
  const char *description;               /* one line */
  int n_states;                          /* states per actuator, 0..POM_DYN_CTRL_MAX_STATES */
  const pom_dyn_ctrl_state_desc *states; /* [n_states] */
  int rate_deps;                         /* POM_DYN_CTRL_DEP_* flags of the state rates */
  int n_gains;
  const pom_dyn_gain_desc *gains; /* [n_gains] */
  int n_options;
  const pom_dyn_ctrl_option_desc *options; /* [n_options] */

  /* operations */
  /* Raw (unsaturated) drive voltage (V) of one actuator from its input and
   * states z[n_states]; with zdot non-NULL also the state rates. Required. */
  double (*law)(const pom_dyn_controller *c, const pom_dyn_ctrl_input *in, const double *z,
                double *zdot);
  /* Partials of the law at the same arguments. NULL: the Newton matrix
   * treats the law by finite differences (docs/dynamics.md section 7). */
  void (*partials)(const pom_dyn_controller *c, const pom_dyn_ctrl_input *in, const double *z,
                   pom_dyn_ctrl_partials *out);
  /* The law with its gain values in one line of text, into buf (the
   * snprintf contract). Required. */
  int (*describe)(const pom_dyn_controller *c, char *buf, size_t cap);

  /* ---- coupled and model-based controllers (all optional) ---------------- */
  /* The controller's own model, built once per dynamics model from the
   * mechanism, architecture and parameters the controller believes in (the
   * nominal ones, whatever the plant draws: pom_dyn_model_create_ex);
   * *out is owned by the engine (model_destroy). NULL: no model. */
  pom_status (*model_create)(void **out, const pom_dyn_ctrl_engine *engine,
                             const pom_dyn_controller *c, const pom_mechanism *mech,
                             const pom_kin_arch *arch, const pom_dyn_params *p, pom_error *err);
  void (*model_destroy)(void *model);
  /* Per-worker scratch of the law (never shared between threads). */
  pom_status (*work_create)(void **out, const void *model, pom_error *err);
  void (*work_destroy)(void *work);
  /* A coupled law: the raw voltages u_raw[n] of every actuator at once and
   * the state rates zdot[n * n_states] (actuator-major; NULL: not wanted)
   * from the sensors, the states z[n * n_states] (NULL when n_states is 0),
   * its model and scratch. When set, `law` is not called and the Newton
   * matrix goes by finite differences. A non-finite voltage makes the step
   * fail recoverably (the integrator retries smaller). */
  void (*law_all)(const pom_dyn_controller *c, const void *model, void *work,
                  const pom_dyn_ctrl_sensed *s, double sensor_gain, const double *z, double *u_raw,
                  double *zdot);
  /* The platform rotation R (from home) that the controller's reference
   * trajectory asks for at time t of the maneuver to the setpoints
   * target[3], for the RMS tracking error (docs/results.md section 1b).
   * Returns 1 with R set, or 0 when the type follows no trajectory (a step
   * to the setpoint) or the reference is undefined. NULL: never a
   * trajectory; the metric is then NaN. */
  int (*reference_rotation)(const pom_dyn_controller *c, const void *model, void *work, double t,
                            const double target[3], double R[9]);
};

/* ---- registry (dyn_ctrl_registry.c) ---------------------------------------- */
/* Number of registered controller types (built-ins first), the k-th (NULL
 * out of range), and the one named `name` (NULL when none). */
int pom_dyn_ctrl_type_count(void);
const pom_dyn_ctrl_type *pom_dyn_ctrl_type_at(int k);
const pom_dyn_ctrl_type *pom_dyn_ctrl_type_find(const char *name);
/* Registers a user type (static storage, never freed) before any thread
 * reads the registry. POM_ERR_ARG for a name taken already or an
 * incomplete table. */
pom_status pom_dyn_ctrl_register(const pom_dyn_ctrl_type *t, pom_error *err);

/* The built-in PID (ctrl_pid.c), the default controller. */
extern const pom_dyn_ctrl_type pom_dyn_ctrl_pid;
/* Computed torque in orientation space (ctrl_computed_torque.c,
 * docs/control.md). */
extern const pom_dyn_ctrl_type pom_dyn_ctrl_computed_torque;
/* The PID on a reference trajectory with inverse-dynamics feedforward
 * (ctrl_pid_feedforward.c, docs/control.md section 3). */
extern const pom_dyn_ctrl_type pom_dyn_ctrl_pid_feedforward;

/* ---- helpers every caller uses --------------------------------------------- */
/* The type of c (the PID when c->type is NULL). */
const pom_dyn_ctrl_type *pom_dyn_ctrl_of(const pom_dyn_controller *c);
/* Value of gain k of c's type (SI), and a pointer to it for writing. */
double pom_dyn_ctrl_gain(const pom_dyn_controller *c, int k);
double *pom_dyn_ctrl_gain_ptr(pom_dyn_controller *c, int k);
/* Index of option k of c's type, and its name. */
int pom_dyn_ctrl_option(const pom_dyn_controller *c, int k);
const char *pom_dyn_ctrl_option_name(const pom_dyn_controller *c, int k);
/* Index of the gain or option of c's type whose key is `key` ("kp"), -1
 * when none. */
int pom_dyn_ctrl_gain_index(const pom_dyn_ctrl_type *t, const char *key);
int pom_dyn_ctrl_option_index(const pom_dyn_ctrl_type *t, const char *key);
/* Sets c to type t with every gain and option at its default. */
void pom_dyn_ctrl_set_defaults(pom_dyn_controller *c, const pom_dyn_ctrl_type *t);
/* Checks every gain of c against its descriptor's range and every option
 * index (POM_ERR_ARG naming controller.<key>, the value and the range). */
pom_status pom_dyn_ctrl_check(const pom_dyn_controller *c, pom_error *err);
/* Writes c as HDF5 attributes of g: controller_type, then
 * controller_<key> for each option (a string) and each gain (a double, SI). */
pom_status pom_dyn_ctrl_h5_describe(hid_t g, const pom_dyn_controller *c, pom_error *err);
/* Reads `controller.type` (a registered name; a change of type starts from
 * that type's defaults), then the type's options and gains with their ranges,
 * over *c. */
pom_status pom_dyn_ctrl_load(pom_dyn_controller *c, const pom_cfg *cfg, pom_error *err);

#endif
