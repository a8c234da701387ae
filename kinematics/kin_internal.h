/* kin_internal.h - constants and helpers shared by the kinematics sources
 * (not part of the public contract). */
#ifndef POM_KIN_INTERNAL_H
#define POM_KIN_INTERNAL_H

#include "pom_kinematics.h"

/* Degeneracy guard used only when a geometry or mechanism is built: a home
 * pose whose |cos(link, slider axis)|, U-joint axis length or sv_min/sv_max
 * falls below this is rejected as singular (docs/kinematics.md section 3),
 * and a limb axis closer than this (in |e_z x axis|) to vertical gets its
 * transverse body axis from e_t (section 7). It never affects an IK, FK or
 * workspace result. */
#define POM_KIN_HOME_MIN_COS 1e-6

/* Limb segment endpoints at rotation R with displacements q: 3PSS link
 * B_i(q) -> C_i(R), 3SPS limb A_i -> B_i(R). */
void pom_kin_limb_segments(const pom_kin_arch *arch, const double R[9], const double q[3],
                           double from[3][3], double to[3][3]);

/* Smallest distance between segments [p0, p1] and [q0, q1] (m). */
double pom_kin_segment_distance(const double p0[3], const double p1[3], const double q0[3],
                                const double q1[3]);

/* For a group whose keys are all optional: when the group is present but
 * holds none of `known` (NULL-terminated key names), fails with a message
 * that names the group and lists the known keys (the generic unknown-key
 * check could only name the group itself). */
pom_status pom_kin_require_known_key(const pom_cfg *cfg, const char *group,
                                     const char *const known[], pom_error *err);

#endif
