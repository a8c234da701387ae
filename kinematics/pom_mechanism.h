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
 * Monte-Carlo ranges, sensor gain, force/torque constant). */
typedef enum {
  POM_ACT_PRISMATIC = 0, /* linear voice coil on a prismatic joint: q in m, force in N */
  POM_ACT_REVOLUTE = 1   /* rotary voice coil on a revolute joint: q in rad, torque in N m */
} pom_actuator_kind;

/* Units of one actuator kind, for printing and file attributes. */
typedef struct {
  const char *si;         /* SI unit of q: "m" or "rad" (JSON, HDF5) */
  const char *display;    /* unit of q in text output and config keys: "mm" or "deg" */
  double to_display;      /* q_display = q_si * to_display (1e3 or 180/pi) */
  const char *effort;     /* SI unit of the actuator effort: "N" or "N m" */
  const char *rate;       /* SI unit of q_dot: "m/s" or "rad/s" */
  const char *kind_name;  /* "prismatic" or "revolute" */
  const char *coordinate; /* "displacement" or "angle" */
} pom_act_units;

/* Units of kind k (static storage; the prismatic units for an unknown k). */
const pom_act_units *pom_act_units_of(pom_actuator_kind k);

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
