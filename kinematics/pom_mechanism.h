/* pom_mechanism.h - the mechanical description of a mechanism: rigid bodies,
 * joints and actuated joints, at the home pose, in SI units and the fixed
 * frame. Architectures only *generate* this (pom_kin_mechanism_build); the
 * dynamics engine consumes it without asking which architecture it is.
 *
 * Body 0 is always the ground. Every joint connects body[0] and body[1]; the
 * joint centre and axes are given in the fixed frame at the home pose (R = I
 * for every body), so body-frame offsets follow as point - cm. */
#ifndef POM_MECHANISM_H
#define POM_MECHANISM_H

#define POM_MECH_MAX_BODIES    16
#define POM_MECH_MAX_JOINTS    24
#define POM_MECH_MAX_ACTUATORS 6
#define POM_MECH_NAME_LEN      32

typedef enum {
  POM_JOINT_SPHERICAL = 0, /* points coincide; rotation free */
  POM_JOINT_PRISMATIC = 1, /* no relative rotation; translation only along axis */
  POM_JOINT_UNIVERSAL = 2, /* spherical + no relative rotation about axis x axis2 */
  POM_JOINT_REVOLUTE = 3   /* spherical + relative rotation only about axis */
} pom_joint_type;

/* Name of a joint type ("spherical", "prismatic", "universal", "revolute"),
 * "?" for a value that is not one (kin_mechanism.c). */
const char *pom_joint_type_name(pom_joint_type t);

typedef struct {
  char name[POM_MECH_NAME_LEN]; /* e.g. "platform", "link2" */
  double mass;                  /* kg (0 for the ground) */
  double inertia[9]; /* inertia tensor about the CM, fixed-frame axes at home (kg m^2), row-major */
  double cm[3];      /* centre of mass at home, fixed frame (m) */
} pom_mech_body;

typedef struct {
  char name[POM_MECH_NAME_LEN]; /* e.g. "O", "B1", "P2" */
  pom_joint_type type;
  int body[2]; /* the two bodies (indices into body[]); body[0] is the "outer" side, e.g. ground */
  /* joint centre at home, fixed frame (m); for a prismatic joint a point on its axis */
  double point[3];
  double axis[3]; /* unit, fixed frame at home: prismatic sliding axis (positive = actuator
                     extension, direction body[0] -> body[1]); revolute hinge axis; universal:
                     axis fixed in body[0]; unused for spherical */
  /* universal: second axis, fixed in body[1], perpendicular to axis; else unused */
  double axis2[3];
  int actuator; /* index into actuator[] driving this joint (prismatic or revolute), -1 if
                   passive */
} pom_mech_joint;

/* Kind of an actuated joint: it fixes the unit of the actuator coordinate q
 * and of everything derived from it (stroke, targets, settling bands,
 * Monte-Carlo ranges, sensor gain, force/torque constant). What depends on the
 * kind is read from its descriptor (pom_act_kind_desc), never by comparing
 * kinds; a new kind is one enum value and one table entry (kin_actuator.c). */
typedef enum {
  POM_ACT_PRISMATIC = 0, /* linear voice coil on a prismatic joint: q in m, force in N */
  POM_ACT_REVOLUTE = 1   /* rotary voice coil on a revolute joint: q in rad, torque in N m */
} pom_actuator_kind;
#define POM_ACT_KINDS 2 /* number of kinds: the valid kinds are 0 .. POM_ACT_KINDS - 1 */

/* Everything that depends on the kind of an actuator: names, units, config
 * keys, the joint it drives and the wording of outputs (static storage). */
typedef struct {
  pom_actuator_kind kind; /* the kind described */
  const char *name;       /* config value of actuator.kind: "linear" or "rotary" */
  const char *kind_name;  /* in outputs and the mechanism: "prismatic" or "revolute" */
  const char *device;     /* in text: "linear voice coil" or "rotary voice coil" */
  pom_joint_type joint;   /* the joint type it drives: prismatic or revolute */
  int angular;            /* 1 when q is an angle (rad), 0 when a length (m): the formulations
                             size the tolerance of the PID integral by it */
  /* the coordinate q */
  const char *coordinate;    /* "displacement" or "angle" */
  const char *si;            /* SI unit of q: "m" or "rad" (JSON, HDF5) */
  const char *rate;          /* SI unit of q_dot: "m/s" or "rad/s" */
  const char *rate_tag;      /* SI unit of q_dot in CSV column names: "mps" or "radps" */
  const char *display;       /* unit of q in text output and config keys: "mm" or "deg" */
  double to_display;         /* q_display = q_si * to_display (1e3 or 180/pi) */
  const char *display_words; /* the display unit in words: "millimetres" or "degrees" */
  const char *key_suffix;    /* suffix of config keys in the display unit: "_mm" or "_deg"
                                (montecarlo.range_mm, tuning.maneuvers_deg) */
  const char *range_word;    /* the actuator's range in words, limit names and its limits key:
                                "stroke" (limits.stroke_mm) or "range" (limits.range_deg) */
  double range_max;          /* largest value of that limits key (display unit): 1000 or 360 */
  double maneuver_range_max; /* largest Monte-Carlo joint range or sigma, montecarlo.range<suffix>
                                (display unit): 100 or 180 */
  const char *lever_unit;    /* unit of J = dq/domega in text: "mm/rad" or "rad/rad" */
  double lever_to_display;   /* J_text = J_si * lever_to_display (1e3 or 1) */
  /* the effort and the coil's constants */
  const char *effort;          /* SI unit of the effort: "N" or "N m" */
  const char *constant_symbol; /* force or torque constant: "K_m" or "K_t" */
  const char *constant_unit;   /* its unit in text: "N/A" or "N m/A" */
  const char *friction_unit;   /* bearing friction in text: "N s/m" or "N m s/rad" */
  const char *gain_unit;       /* sensor gain in text: "V/m" or "V/rad" */
  const char *constant_key;    /* key of the constant in the `actuator` group */
  const char *friction_key;    /* key of the bearing friction in the `actuator` group */
  const char *gain_key;        /* key of the sensor gain in the `actuator` group */
  int legacy_keys; /* 1: outputs also carry the keys written before actuator units existed
                      (stroke_m, target_m, final_q_m, range_m, sigma_m) */
} pom_act_desc;

/* The descriptor of kind k (static storage); NULL when k is not a kind (not
 * in 0 .. POM_ACT_KINDS - 1): callers validate kinds where they enter
 * (config loading, pom_kin_arch_register, pom_dyn_model_create). */
const pom_act_desc *pom_act_kind_desc(pom_actuator_kind k);

/* The kind whose name (pom_act_desc.name, e.g. "rotary") is `name`: 1 and
 * *kind set, or 0 and *kind untouched when no kind has that name (or name is
 * NULL). */
int pom_act_kind_parse(const char *name, pom_actuator_kind *kind);

typedef struct {
  int joint;              /* the joint it drives: prismatic (kind PRISMATIC) or revolute */
  pom_actuator_kind kind; /* fixes the unit of q (m or rad) */
  double stroke;          /* total range in the unit of q (m or rad); travel is
                             [-stroke/2, +stroke/2] about home */
  int moving_body;        /* body carrying the coil/rotor (moved by the force or torque) */
} pom_mech_actuator;

typedef struct {
  int n_bodies; /* including the ground (body 0) */
  int n_joints;
  int n_actuators;
  pom_mech_body body[POM_MECH_MAX_BODIES];            /* [n_bodies] */
  pom_mech_joint joint[POM_MECH_MAX_JOINTS];          /* [n_joints] */
  pom_mech_actuator actuator[POM_MECH_MAX_ACTUATORS]; /* [n_actuators] */
  int platform;                                       /* index of the moving platform body */
  double gravity[3]; /* gravitational acceleration, fixed frame (m/s^2) */
} pom_mechanism;

#endif
