/* pom_kinematics.h - geometry, inverse/forward kinematics, Jacobian and
 * dexterity of the 3P-S-S/S and 3S-P-S/S orientation manipulators
 * (derivations: docs/kinematics.md).
 *
 * The platform turns about the fixed spherical joint O (the origin). R is the
 * platform rotation (platform frame -> fixed frame), R = I at home, where every
 * actuator is at mid-stroke. q[i] is actuator i's displacement from mid-stroke
 * (m), positive = extension. q_dot = J omega, omega the platform angular
 * velocity in the fixed frame (rad/s), J in m/rad (row-major, row i = limb i).
 *
 * This header is a contract used by dynamics/, doe/ and optimize/: extend it,
 * do not rename or remove fields. */
#ifndef POM_KINEMATICS_H
#define POM_KINEMATICS_H

#include "pom_config.h"
#include "pom_mechanism.h"
#include "pom_status.h"

typedef enum {
  POM_ARCH_3PSS = 0, /* 3P-S-S/S: fixed prismatic actuators, S-S links */
  POM_ARCH_3SPS = 1  /* 3S-P-S/S (3-UPS/S): extensible limbs, U joint at the ground */
} pom_arch_type;

/* Geometry and limits of one architecture instance (everything in metres,
 * radians, fixed frame at home). Filled by pom_kin_arch_load(). */
typedef struct {
  pom_arch_type type;
  char name[64];            /* config `name` */
  /* 3P-S-S/S */
  double slider_mid[3][3];  /* B_i at mid-stroke (m) */
  double slider_axis[3][3]; /* unit actuator axis d_i (positive = extension) */
  double link_length[3];    /* |B_i C_i| (m) */
  /* 3S-P-S/S */
  double base_point[3][3];  /* A_i, U-joint centre on the ground (m) */
  double limb_length_mid[3]; /* |B_i - A_i| at mid-stroke (m) */
  double ujoint_axis[3][3]; /* U-joint axis fixed in the ground, unit */
  /* both */
  double platform_point[3][3]; /* C_i (3PSS) or B_i (3SPS) in the platform frame = fixed at home (m) */
  /* limits */
  double stroke;               /* total actuator stroke (m): |q_i| <= stroke / 2 */
  double cone_base_max;        /* largest angle of a limb at its ground/slider joint from its home direction (rad) */
  double cone_platform_max;    /* largest angle of a limb at its platform joint, platform frame, from home (rad) */
  double min_limb_distance;    /* smallest allowed distance between limb segments (m) */
} pom_kin_arch;

/* Loads geometry and limits from the `architecture`, `geometry` and `limits`
 * keys of cfg (docs/config.md). */
pom_status pom_kin_arch_load(pom_kin_arch *arch, const pom_cfg *cfg, pom_error *err);

/* Inverse kinematics in closed form on the home assembly branch: q (m) for
 * rotation R. POM_ERR_UNREACHABLE (q untouched, err says which limb) when a
 * limb cannot be assembled. Does not check limits. */
pom_status pom_kin_inverse(const pom_kin_arch *arch, const double R[9], double q[3],
                           pom_error *err);

/* Jacobian J (m/rad) with q_dot = J omega at rotation R (q from IK). */
pom_status pom_kin_jacobian(const pom_kin_arch *arch, const double R[9], double J[9],
                            pom_error *err);

/* Builds the mechanical description (bodies with mass/inertia from the
 * `inertia` keys of cfg, joints, actuators) at the home pose. */
pom_status pom_kin_mechanism_build(pom_mechanism *mech, const pom_kin_arch *arch,
                                   const pom_cfg *cfg, pom_error *err);

#endif
