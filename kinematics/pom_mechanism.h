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
  int actuator; /* index into actuator[] driving this (prismatic) joint, -1 if passive */
} pom_mech_joint;

typedef struct {
  int joint;       /* the prismatic joint it drives */
  double stroke;   /* total stroke (m); travel is [-stroke/2, +stroke/2] about home */
  int moving_body; /* body carrying the coil/piston (mass moved by the force) */
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
