/* pom_dyn_params_schema.h - the one list of dynamics parameters
 * (docs/config.md, "Dynamics parameters").
 *
 * Every field of pom_dyn_params outside the controller (the controller is
 * described by its type's descriptors, pom_dyn_ctrl.h) is declared ONCE in
 * POM_DYN_PARAMS_LIST. Generated from it: the defaults
 * (pom_dyn_params_defaults), the config loading with its range check
 * (pom_dyn_params_load), the model's check of the same ranges
 * (pom_dyn_params_check), the `pomlab model` text and JSON, the HDF5
 * provenance attributes (pom_dyn_params_h5_describe) and the parameter table
 * of docs/config.md (tests/dyn_params_table.c; test_params_doc fails when
 * the doc differs). Adding a parameter = one line here plus its field in
 * pom_dyn_params (pom_dynamics.h) and the code that uses it.
 *
 * A line is X(group, key, json, member, type, arg, to_si, unit, lo, hi, def,
 * h5, meaning):
 *   group    the config group (one of POM_DYN_PARAM_GROUPS_LIST);
 *   key      the config key under the group, unit in the name ("horizon_ms");
 *            NULL for a KIND_REAL, whose key the actuator kind's descriptor
 *            names (pom_act_desc: constant_key, friction_key, gain_key);
 *   json     its key in `pomlab model --json`, SI unit in the name
 *            ("horizon_s"); NULL for a KIND_REAL (the descriptor's key);
 *   member   the field, as a member of pom_dyn_params ("maneuver.horizon");
 *   type     REAL (double), LONG (long), INT (int), BOOL (int 0/1), ENUM (an
 *            enum whose value is the index in the names table `arg`), KIND
 *            (pom_actuator_kind, names from the kinds' descriptors) or
 *            KIND_REAL (a double whose key and unit depend on the actuator
 *            kind: `arg` 0 constant, 1 friction, 2 sensor gain);
 *   arg      the names table of an ENUM, the descriptor slot of a KIND_REAL,
 *            0 otherwise;
 *   to_si    factor from the config unit to SI (1e-3 for ms);
 *   unit     the config unit as printed ("ms", "%", "1" dimensionless, "-"
 *            for names and flags; NULL for a KIND_REAL: the descriptor's);
 *   lo, hi   the allowed range, inclusive, in the config unit (the one
 *            check: loading refuses a value outside it, the model refuses an
 *            SI value outside [lo to_si, hi to_si]); ignored for names and
 *            flags;
 *   def      the default, SI (an enum's value for ENUM and KIND);
 *   h5       the HDF5 provenance attribute (never renamed: files and scripts
 *            read it); NULL for a KIND_REAL ("actuator_" + the descriptor's key);
 *   meaning  one line, for the doc table.
 * The order of the lines is the order of loading, of the outputs and of the
 * doc table. */
#ifndef POM_DYN_PARAMS_SCHEMA_H
#define POM_DYN_PARAMS_SCHEMA_H

#include "pom_dynamics.h"
#include "pom_h5.h"
#include "pom_mechanism.h"

#include <stddef.h>

/* The config groups of the dynamics model, in loading order (controller:
 * pom_dyn_ctrl_load, the others: the list below). */
#define POM_DYN_PARAM_GROUPS_LIST(G)                                                               \
  G(actuator) G(controller) G(joints) G(scene) G(solver) G(maneuver)

/* clang-format off */
#define POM_DYN_PARAMS_LIST(X)                                                                     \
  X(actuator, "kind", "kind", actuator.kind, KIND, 0, 1.0, "-", 0, 0, POM_ACT_PRISMATIC,           \
    "actuator_kind_config",                                                                        \
    "voice coil on a prismatic joint (q in m) or a revolute one (q in rad): picks the unit keys; " \
    "must match the mechanism's actuators")                                                        \
  X(actuator, NULL, NULL, actuator.force_constant, KIND_REAL, 0, 1.0, NULL, 1e-6, 1e4, 3.8, NULL,  \
    "coil constant (K_m, K_t): force or torque per current = back-EMF per velocity")               \
  X(actuator, "resistance_ohm", "resistance_ohm", actuator.resistance, REAL, 0, 1.0, "ohm", 1e-6,  \
    1e6, 10.0, "actuator_resistance_ohm", "coil resistance R_c")                                   \
  X(actuator, "inductance_H", "inductance_H", actuator.inductance, REAL, 0, 1.0, "H", 0.0, 10.0,   \
    1.45e-4, "actuator_inductance_H",                                                              \
    "coil inductance L; > 0 when scene.coil_inductance is on")                                     \
  X(actuator, NULL, NULL, actuator.bearing_friction, KIND_REAL, 1, 1.0, NULL, 0.0, 1e6, 9.8e-2,    \
    NULL, "viscous bearing friction b")                                                            \
  X(actuator, "voltage_limit_V", "voltage_limit_V", actuator.voltage_limit, REAL, 0, 1.0, "V",     \
    1e-3, 1e5, 24.0, "actuator_voltage_limit_V", "drive saturation, +- this voltage")              \
  X(actuator, NULL, NULL, actuator.sensor_gain, KIND_REAL, 2, 1.0, NULL, 1e-6, 1e9, 833.33, NULL,  \
    "position sensor gain K_S")                                                                    \
  X(joints, "stiffness_N_per_m", "stiffness_N_per_m", joints.stiffness, REAL, 0, 1.0, "N/m", 1.0,  \
    POM_DYN_STIFFNESS_MAX, 1.0e6, "joints_stiffness_N_per_m", "k_p of the linear pseudo-constraints")               \
  X(joints, "damping_Ns_per_m", "damping_Ns_per_m", joints.damping, REAL, 0, 1.0, "N s/m", 0.0,    \
    1e9, 200.0, "joints_damping_Ns_per_m", "R_p of the linear pseudo-constraints")                 \
  X(joints, "angular_stiffness_Nm_per_rad", "angular_stiffness_Nm_per_rad",                        \
    joints.angular_stiffness, REAL, 0, 1.0, "N m/rad", 1e-3, 1e12, 1.0e6,                          \
    "joints_angular_stiffness_Nm_per_rad", "k_p of the angular pseudo-constraints")                \
  X(joints, "angular_damping_Nms_per_rad", "angular_damping_Nms_per_rad", joints.angular_damping,  \
    REAL, 0, 1.0, "N m s/rad", 0.0, 1e9, 200.0, "joints_angular_damping_Nms_per_rad",              \
    "R_p of the angular pseudo-constraints")                                                       \
  X(joints, "model", "model", joints.model, ENUM, pom_dyn_joint_model_names, 1.0, "-", 0, 0,       \
    POM_JOINTS_PARASITIC, "joints_model",                                                          \
    "parasitic springs (docs/dynamics.md) or exact rigid constraints (docs/dynamics-exact.md; "    \
    "ignores the four values above)")                                                              \
  X(scene, "gravity", "gravity", scene.gravity, BOOL, 0, 1.0, "-", 0, 0, 1, "scene_gravity",       \
    "gravity on the bodies")                                                                       \
  X(scene, "bearing_friction", "bearing_friction", scene.bearing_friction, BOOL, 0, 1.0, "-", 0,   \
    0, 1, "scene_bearing_friction", "b q_dot on each actuator")                                    \
  X(scene, "coil_inductance", "coil_inductance", scene.coil_inductance, BOOL, 0, 1.0, "-", 0, 0,   \
    1, "scene_coil_inductance", "L di/dt dynamics (false: quasi-static current)")                  \
  X(scene, "orientation", "orientation", scene.orientation, ENUM, pom_dyn_orient_names, 1.0, "-",  \
    0, 0, POM_ORIENT_EULER_ZYX, "orientation",                                                     \
    "platform and body orientation states: ZYX Euler angles (as the paper) or quaternions")        \
  X(scene, "limb_inertia", "limb_inertia", scene.limb_inertia, ENUM, pom_dyn_inertia_names, 1.0,   \
    "-", 0, 0, POM_INERTIA_FULL, "scene_limb_inertia",                                             \
    "limb bodies as given or lumped (docs/dynamics.md section 13)")                                \
  X(scene, "universal_joint", "universal_joint", scene.universal_joint, BOOL, 0, 1.0, "-", 0, 0,   \
    1, "scene_universal_joint", "universal joints keep their anti-spin constraint (false: spherical)") \
  X(scene, "euler_cos_min", "euler_cos_min", scene.euler_cos_min, REAL, 0, 1.0, "1", 1e-6, 0.5,    \
    1.0e-2, "scene_euler_cos_min",                                                                 \
    "the Euler path stops (POM_ERR_EULER_SINGULAR) when a body's cos pitch falls below it")        \
  X(solver, "rtol", "rtol", solver.rtol, REAL, 0, 1.0, "1", POM_DYN_RTOL_MIN, 1e-1, 1.0e-6, "solver_rtol",    \
    "CVODE relative tolerance")                                                                    \
  X(solver, "atol_scale", "atol_scale", solver.atol_scale, REAL, 0, 1.0, "1", 0.0, 1.0, 0.0,       \
    "solver_atol_scale",                                                                           \
    "0: absolute tolerance rtol x natural size per state; > 0: atol_scale x scale per state kind " \
    "(docs/dynamics.md section 7; the shipped configs set 1e-3)")                                  \
  X(solver, "max_step_ms", "max_step_s", solver.max_step, REAL, 0, 1e-3, "ms", 0.0, 1e6, 0.0,      \
    "solver_max_step_s", "largest step, 0 = unlimited")                                            \
  X(solver, "max_steps", "max_steps", solver.max_steps, LONG, 0, 1.0, "1", 1, 1000000000L, 200000, \
    "solver_max_steps", "steps per maneuver")                                                      \
  X(solver, "linear_solver", "linear_solver", solver.linear_solver, ENUM, pom_dyn_linsol_names,    \
    1.0, "-", 0, 0, POM_LINSOL_STRUCTURED, "solver_linear_solver",                                        \
    "Newton linear solver of the parasitic path: SUNDIALS dense LU, KLU, or the block LU over the "\
    "bond graph's groups (docs/dynamics.md section 7)")                                            \
  X(solver, "jacobian", "jacobian", solver.jacobian, ENUM, pom_dyn_jacobian_names, 1.0, "-", 0, 0, \
    POM_JAC_ANALYTIC, "solver_jacobian",                                                           \
    "Newton Jacobian: analytic, or finite differences (parasitic path: coloured, docs/dynamics.md " \
    "section 7; exact path: its orientation and omega columns, docs/dynamics-exact.md section 5)")                                                                \
  X(solver, "max_order", "max_order", solver.max_order, INT, 0, 1.0, "1", 1, 5, 5,                 \
    "solver_max_order", "largest BDF order (rigid path: 2 at most when its drive mode needs it)") \
  X(solver, "stability_limit_detection", "stability_limit_detection",                              \
    solver.stability_limit_detection, BOOL, 0, 1.0, "-", 0, 0, 1,                                  \
    "solver_stability_limit_detection", "CVODE's BDF stability limit detection")                   \
  X(solver, "max_wall_s", "max_wall_s", solver.max_wall, REAL, 0, 1.0, "s", 0.0, 1e6, 60.0,        \
    "solver_max_wall_s", "wall-clock budget per maneuver, 0 = none (docs/dynamics.md section 14)") \
  X(solver, "max_balance_error", "max_balance_error", solver.max_balance_error, REAL, 0, 1.0, "1", \
    0.0, 1e3, 0.05, "solver_max_balance_error",                                                    \
    "a maneuver whose energy audit is off by more fails (POM_ERR_UNSTABLE); 0 = no check")         \
  X(solver, "min_dexterity", "min_dexterity", solver.min_dexterity, REAL, 0, 1.0, "1", 0.0, 0.99,  \
    1.0e-3, "solver_min_dexterity",                                                                \
    "rigid joints: stop at a near-singular pose, 3/kappa_F(J) below it (POM_ERR_SINGULAR; "       \
    "docs/dynamics-exact.md section 3); 0 = off")                                                  \
  X(maneuver, "horizon_ms", "horizon_s", maneuver.horizon, REAL, 0, 1e-3, "ms", 1e-3, 1e7, 0.100,  \
    "maneuver_horizon_s", "simulated time (and energy horizon)")                                   \
  X(maneuver, "settle_band_percent", "settle_band", maneuver.settle_band, REAL, 0, 1e-2, "%",      \
    1e-6, 100.0, 0.02, "maneuver_settle_band", "settling band, percent of the step")               \
  X(maneuver, "output_dt_ms", "output_dt_s", maneuver.output_dt, REAL, 0, 1e-3, "ms", 1e-6, 1e6,   \
    1.0e-4, "maneuver_output_dt_s",                                                                \
    "trace grid (not the metrics); at most the horizon and 1e7 samples over it")                          \
  X(maneuver, "pointing_band_mrad", "pointing_band_rad", maneuver.pointing_band, REAL, 0, 1e-3,    \
    "mrad", 1e-6, 1e3, 1.0e-3, "maneuver_pointing_band_rad",                                       \
    "pointing settling band, absolute (docs/results.md section 1b)")                               \
  X(maneuver, "pointing_band_percent", "pointing_band_rel", maneuver.pointing_band_rel, REAL, 0,   \
    1e-2, "%", 0.0, 100.0, 0.0, "maneuver_pointing_band_rel",                                      \
    "pointing settling band, percent of the rotation (the larger band applies; 0 = off)")
/* clang-format on */

/* The names of the enums of the list, in enum order (NULL-terminated;
 * pom_cfg_choice parses them, pom_cfg_choice_name names a value). */
extern const char *const pom_dyn_joint_model_names[];
extern const char *const pom_dyn_orient_names[];
extern const char *const pom_dyn_inertia_names[];
extern const char *const pom_dyn_linsol_names[];
extern const char *const pom_dyn_jacobian_names[];

/* Kinds of parameter values (the `type` column). */
typedef enum {
  POM_DYN_PARAM_REAL = 0,
  POM_DYN_PARAM_LONG,
  POM_DYN_PARAM_INT,
  POM_DYN_PARAM_BOOL,
  POM_DYN_PARAM_ENUM,
  POM_DYN_PARAM_KIND,
  POM_DYN_PARAM_KIND_REAL
} pom_dyn_param_type;

/* The number of lines of the list. */
#define POM_DYN_PARAM_ONE_(...) +1
enum { POM_DYN_N_PARAMS = 0 POM_DYN_PARAMS_LIST(POM_DYN_PARAM_ONE_) };

/* One parameter as declared (the columns above). */
typedef struct {
  const char *group;        /* config group */
  const char *key;          /* config key under group; NULL for KIND_REAL */
  const char *json;         /* `pomlab model --json` key; NULL for KIND_REAL */
  size_t offset;            /* offsetof(pom_dyn_params, member) */
  pom_dyn_param_type type;  /* value kind */
  const char *const *names; /* ENUM: the names table; NULL otherwise */
  int slot;                 /* KIND_REAL: 0 constant, 1 friction, 2 sensor gain */
  double to_si;             /* config unit -> SI */
  const char *unit;         /* config unit; NULL for KIND_REAL */
  double lo, hi;            /* range in the config unit (REAL, LONG, INT) */
  double def;               /* default (SI; enum value for ENUM and KIND) */
  const char *h5;           /* HDF5 attribute; NULL for KIND_REAL */
  const char *meaning;      /* one line */
} pom_dyn_param_info;

/* The table of every parameter, [POM_DYN_N_PARAMS] in list order (static). */
const pom_dyn_param_info *pom_dyn_param_schema(void);

/* "group.key" of a parameter for actuator kind `kind` (a KIND_REAL's key is
 * the kind's; NULL when kind is not a kind). Writes into buf (cap bytes) and
 * returns it. */
const char *pom_dyn_param_key(const pom_dyn_param_info *pi, pom_actuator_kind kind, char *buf,
                              size_t cap);

/* The `pomlab model --json` key (static storage), the config unit (static;
 * a KIND_REAL's from the kind's descriptor) and the HDF5 attribute name
 * (written into buf) of a parameter for actuator kind `kind`. NULL when kind
 * is not a kind and the answer depends on it. */
const char *pom_dyn_param_json_key(const pom_dyn_param_info *pi, pom_actuator_kind kind);
const char *pom_dyn_param_unit(const pom_dyn_param_info *pi, pom_actuator_kind kind);
const char *pom_dyn_param_h5_name(const pom_dyn_param_info *pi, pom_actuator_kind kind, char *buf,
                                  size_t cap);

/* The value of a parameter in p as a double, SI (an enum's value, a flag's
 * 0/1, an integer exactly). */
double pom_dyn_param_value(const pom_dyn_params *p, const pom_dyn_param_info *pi);

/* The name of an ENUM or KIND parameter's value in p ("?" for a value
 * outside its table); NULL for other types. Static storage. */
const char *pom_dyn_param_choice(const pom_dyn_params *p, const pom_dyn_param_info *pi);

/* The value written as the config would write it, in the config unit
 * ("100", "klu", "true"), into buf (cap bytes); returns buf. */
const char *pom_dyn_param_format(const pom_dyn_params *p, const pom_dyn_param_info *pi, char *buf,
                                 size_t cap);

/* The default written as the config would write it (the value of
 * pom_dyn_params_defaults), into buf; returns buf. */
const char *pom_dyn_param_format_default(const pom_dyn_param_info *pi, char *buf, size_t cap);

/* Writes every parameter of p as an attribute of the HDF5 object g (results
 * provenance, the traces of pomlab simulate): the controller by its type
 * (pom_dyn_ctrl_h5_describe: controller_type, controller_<key>), then every
 * line of the list under its h5 name: reals as float64 in SI, integers and
 * flags as int64, names as strings. An attribute of that name is replaced. */
pom_status pom_dyn_params_h5_describe(hid_t g, const pom_dyn_params *p, pom_error *err);

#endif
