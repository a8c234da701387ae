/* pom_limb.h - an architecture as data: three limbs, each a serial chain of
 * three joints (R, P, U or S) from the ground to the platform, described by
 * numbers (pom_limb_table, stored in pom_kin_arch.data), and the generic
 * operations of pom_kin_arch_type that work on any such table
 * (docs/kinematics-tables.md). The file side (an architecture file's
 * expressions evaluated for one design) fills the table's input fields and
 * from_design; pom_limb_type_ops supplies every other operation.
 *
 * Body order of one limb (pom_kinematics.h): body 2 + 2i between joints 0
 * and 1, body 3 + 2i between joints 1 and 2; joint 0 joins the ground to
 * body 2 + 2i, joint 2 joins body 3 + 2i to the platform.
 *
 * Kernels (a closed-form IK per joint sequence, docs/kinematics-tables.md
 * section 2); the actuated joint is fixed by the kernel:
 *   R-R-R, all three axes through O, joint 0 actuated (any 3-RRR wrist);
 *   P-S-S, joint 0 actuated;   R-S-S, joint 0 actuated;
 *   S-P-S and U-P-S, joint 1 actuated (its axis along the limb);
 *   R-U-U, joint 0 actuated, and U-P-U, joint 1 actuated: limbs with five
 *   joint freedoms and one constraint wrench each, in the layout that makes
 *   that wrench a force through O (docs/kinematics-tables.md section 2.5).
 * Any other sequence is refused by finish with a message. */
#ifndef POM_LIMB_H
#define POM_LIMB_H

#include "pom_arch.h"

#define POM_LIMB_JOINTS 3 /* joints per limb, base to platform */
#define POM_LIMB_BODIES 2 /* moving bodies per limb */
#define POM_LIMB_NAME   16

typedef enum {
  POM_LIMB_JOINT_NONE = 0,
  POM_LIMB_JOINT_R = 1, /* revolute: axis */
  POM_LIMB_JOINT_P = 2, /* prismatic: axis, + = extension */
  POM_LIMB_JOINT_U = 3, /* universal: axis fixed in the body before it, axis2 in the body after */
  POM_LIMB_JOINT_S = 4  /* spherical: point only */
} pom_limb_joint_type;

typedef enum {
  POM_LIMB_KERNEL_NONE = 0,
  POM_LIMB_KERNEL_RRR = 1, /* R-R-R, axes through O: w(theta) . v = cos(alpha2) */
  POM_LIMB_KERNEL_PSS = 2, /* P-S-S: |p2 - p1(q)| = L, quadratic in q */
  POM_LIMB_KERNEL_RSS = 3, /* R-S-S: |p2 - p1(theta)| = L, A cos + B sin + C = 0 */
  POM_LIMB_KERNEL_SPS = 4, /* S-P-S: q = |p2 - p0| - L0 (cylinder and piston spin freely) */
  POM_LIMB_KERNEL_UPS = 5, /* U-P-S: q = |p2 - p0| - L0 (the U-joint fixes the spin) */
  POM_LIMB_KERNEL_RUU = 6, /* R-U-U: w(theta) . v = cos alpha2 as R-R-R (v the platform U's
                              second axis); the link turns about O */
  POM_LIMB_KERNEL_UPU = 7  /* U-P-U: q = |p2 - p0| - L0; the middle U axes stay parallel */
} pom_limb_kernel;

/* One joint at home (R = I, q = 0), fixed frame, SI. */
typedef struct {
  int type;        /* pom_limb_joint_type */
  double point[3]; /* centre (m): R, U, S the joint centre; P any point of its line (the
                      mechanism's joint point) */
  double axis[3];  /* R, P, U: unit axis (finish normalizes; U: Gram-Schmidt against the
                      limb for U-P-S, as the 3S-P-S/S) */
  double axis2[3]; /* U: second axis, fixed in the body after it; zero = derived by finish
                      (unit(limb x axis)) */
} pom_limb_joint;

/* A direction at home from the joints of a limb: the axis of joint a when
 * b < 0, else the unit segment from joint a's point to joint b's point.
 * a < 0: none. */
typedef struct {
  int a, b;
} pom_limb_dir;

typedef enum {
  POM_LIMB_MASS_NONE = 0,  /* massless body */
  POM_LIMB_MASS_GROUP = 1, /* an inertia group: in->body[group] (mass, principal moments) */
  POM_LIMB_MASS_ARC = 2    /* the 3-RRR link model (docs/kinematics-3rrr.md section 6) */
} pom_limb_mass_model;

/* Mass-property rule of one limb body (the same for the three limbs). */
typedef struct {
  char name[POM_LIMB_NAME]; /* mechanism body name ("piston", "link", "proximal") */
  int model;                /* pom_limb_mass_model */
  /* GROUP: */
  int group;   /* index into pom_kin_inertia.body[] */
  int place;   /* 1: CM = point[cm_from] + cm_offset * dir(cm_dir);
                  2: CM = point[a] + cm_fraction * (point[b] - point[a]), cm_dir = {a, b};
                  0: CM at the body's reference point (docs/kinematics-tables.md 4) */
  int cm_from; /* place 1: joint whose home point the offset starts from */
  pom_limb_dir cm_dir;
  pom_limb_dir z_dir; /* principal z axis */
  pom_limb_dir x_dir; /* principal x axis; a < 0: unit(e_z x z), or e_z x radial when z is
                         vertical (pom_kin_limb_axes) */
  /* ARC: a thin arc of radius arc_radius (table) from joint arc_a's axis to
   * joint arc_b's axis, linear density value[v_density] * value[v_section]
   * (pom_kin_inertia.value indices), plus a point mass value[v_point_mass]
   * at arc_radius * axis of joint point_joint, plus an axisymmetric rotor
   * inertia value[v_rotor] (axial; half transverse) about the axis of joint
   * rotor_joint. Index -1: the term is absent. */
  int arc_a, arc_b;
  int v_density, v_section;
  int v_point_mass, point_joint;
  int v_rotor, rotor_joint;
} pom_limb_body;

typedef enum {
  POM_LIMB_MEASURE_NONE = 0,
  POM_LIMB_MEASURE_CONE_FIXED = 1,    /* per limb: angle of segment a -> b from its home
                                         direction, fixed frame */
  POM_LIMB_MEASURE_CONE_PLATFORM = 2, /* per limb: the same in the platform frame */
  POM_LIMB_MEASURE_DISTANCE = 3,      /* per pair: distance of the segments a -> b */
  POM_LIMB_MEASURE_AXIS_ANGLE = 4,    /* per pair: angle between the current axes of joint a */
  POM_LIMB_MEASURE_ARM_ANGLE = 5      /* per pair: angle about +z from limb i's joint-a axis to
                                         limb i+1's (azimuth difference, in [0, 2 pi)): the
                                         arms of coaxial actuators (Orbita's gamma; every
                                         actuated joint an R on the z axis) */
} pom_limb_measure_kind;

/* What limit kind k (1..3) of the type measures; segments join the joints'
 * current centres (a joint's centre moves with the body after it). The
 * type's limits[k] descriptor (name, per_pair, lower, key, ...) must agree:
 * per_pair = 1 exactly for DISTANCE, AXIS_ANGLE and ARM_ANGLE. */
typedef struct {
  int kind; /* pom_limb_measure_kind */
  int a, b; /* joints */
} pom_limb_measure;

/* One limb. Inputs above the line; finish fills the rest. */
typedef struct {
  pom_limb_joint joint[POM_LIMB_JOINTS];
  int actuated;    /* index of the actuated joint (must be the kernel's: header comment) */
  double branch;   /* +1 / -1: the IK root (docs/kinematics-tables.md 2); 0: the root through
                      the home configuration (finish sets it; a given +-1 must be that root) */
  double motor[3]; /* where the actuator sits at home (m): its distance from the z axis is the
                      footprint; moves along the axis over the stroke when joint 0 is an
                      actuated P. Zero: joint 0's point, or (R-R-R) the scale times its axis */
  /* ---- derived by finish ---- */
  int kernel;                     /* pom_limb_kernel */
  int ref_joint[POM_LIMB_BODIES]; /* joint whose centre is body b's reference point: the joint
                                     at its base, or at its tip when that is a P joint */
  double length;      /* P-S-S, R-S-S: link length |p2 - p1|; S/U-P-S: |p2 - p0| at home */
  double dir_home[3]; /* unit link (p1 -> p2) or limb (p0 -> p2) direction at home */
  double radial[3];   /* unit horizontal direction toward the platform joint (e_r) */
  double cos_distal;  /* R-R-R: cos alpha2 = w . v at home */
} pom_limb;

/* The numeric table of a catalog architecture: pom_kin_arch.data. */
typedef struct {
  pom_limb limb[3];
  pom_limb_body body[POM_LIMB_BODIES];
  char joint_name[POM_LIMB_JOINTS][8];         /* mechanism joint names ("P", "B", "C") */
  pom_limb_measure measure[POM_KIN_LIM_KINDS]; /* [1..3] the type's limit kinds; [0] unused */
  double arc_radius; /* ARC bodies: radius of the arcs (m), usually the design scale */
  int central;       /* spherical joint O ground-platform: 1 required (the limbs do not hold O:
                        P-S-S, R-S-S, S/U-P-S), 0 none, -1 optional (geometry.central_joint;
                        the type then sets optional_central_joint = 1) */
} pom_limb_table;

/* The table inside an instance. */
#define POM_LIMB_TABLE(arch_)  POM_KIN_DATA(pom_limb_table, arch_)
#define POM_LIMB_CTABLE(arch_) POM_KIN_CDATA(pom_limb_table, arch_)

/* Fills the operations of a catalog type: finish, limb, limb_twist,
 * limb_twist_diff, limit_values, footprint, mechanism, flip_branch (shapes = NULL: the
 * derived shapes) and data_size = sizeof(pom_limb_table). Leaves every
 * descriptor and from_design to the caller. */
void pom_limb_type_ops(pom_kin_arch_type *type);

/* The generic operations (the pom_kin_arch_type contract of pom_arch.h) on
 * arch->data as a pom_limb_table. */
pom_status pom_limb_finish(pom_kin_arch *arch, pom_error *err);
int pom_limb_ik(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
                double *transmission);
int pom_limb_twist(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                   pom_kin_twists *out);
int pom_limb_twist_diff(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                        pom_kin_twists *out, pom_kin_twists_diff *dout);
void pom_limb_limit_values(const pom_kin_arch *arch, const double R[9], const double q[3],
                           double value[9]);
double pom_limb_footprint(const pom_kin_arch *arch);
/* The other IK root of limb i (R-R-R, P-S-S, R-S-S: branch -> -branch;
 * S-P-S and U-P-S have one root: returns 0). */
int pom_limb_flip_branch(pom_kin_arch *arch, int i);
pom_status pom_limb_mechanism(pom_mechanism *mech, const pom_kin_arch *arch,
                              const pom_kin_inertia *in, pom_error *err);

/* The limbs' constraint wrenches at rotation R, for tables whose platform
 * is held at O by the limbs alone through one wrench per limb (R-U-U,
 * U-P-U: five joint freedoms): each limb's wrench reciprocal to its five
 * joint twists, computed from the joint screws at the pose (not from the
 * layout), written as a unit force force[3 i ..] and its moment about O
 * divided by the force's magnitude, moment[3 i ..] (m: the force line's
 * offset from O). Returns 3; 0 when the table has a central joint or its
 * limbs hold O each (R-R-R), or a limb cannot be assembled (force and
 * moment then untouched). docs/kinematics-tables.md section 3.1. */
int pom_limb_constraint(const pom_kin_arch *arch, const double R[9], double force[9],
                        double moment[9]);

/* The kernel of a joint sequence (types of joints 0..2) with `actuated`,
 * POM_LIMB_KERNEL_NONE when no kernel covers it; its name ("R-S-S"). */
pom_limb_kernel pom_limb_kernel_of(const int type[POM_LIMB_JOINTS], int actuated);
const char *pom_limb_kernel_name(pom_limb_kernel k);

#endif
