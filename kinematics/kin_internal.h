/* kin_internal.h - constants and helpers shared by the kinematics sources
 * (not part of the public contract). */
#ifndef POM_KIN_INTERNAL_H
#define POM_KIN_INTERNAL_H

#include "pom_arch.h"
#include "pom_kinematics.h"

/* Degeneracy guard used only when a geometry or mechanism is built: a home
 * pose whose |cos(link, slider axis)|, U-joint axis length or sv_min/sv_max
 * falls below this is rejected as singular (docs/kinematics.md section 3),
 * and a limb axis closer than this (in |e_z x axis|) to vertical gets its
 * transverse body axis from e_t (section 7). It never affects an IK, FK or
 * workspace result. */
#define POM_KIN_HOME_MIN_COS 1e-6

/* The built-in architectures (arch_3pss.c, arch_3sps.c, arch_3rrr.c). */
extern const pom_kin_arch_type pom_kin_arch_3pss;
extern const pom_kin_arch_type pom_kin_arch_3sps;
extern const pom_kin_arch_type pom_kin_arch_3rrr;

/* Limits of the two architectures whose limbs are segments (3PSS: link
 * B_i -> C_i; 3SPS: limb A_i -> B_i): value[0..2] the base cone angle of limb
 * i (the segment from its home direction), [3..5] the platform cone angle
 * (the segment in the platform frame from home), [6..8] the distances of
 * the limb pairs 1-2, 2-3, 3-1 (docs/kinematics.md section 5). */
/* The limit kinds of pom_kin_segment_limits as a pom_kin_arch_type.limits
 * initializer: 1 base cone, 2 platform cone (upper bounds, default 90 deg,
 * not binding), 3 limb distance per pair (a lower bound, default 0). */
#define POM_KIN_SEGMENT_LIMIT_KINDS                                                                \
  {                                                                                                \
    [1] = {.name = "base cone",                                                                    \
           .per_pair = 0,                                                                          \
           .lower = 0,                                                                             \
           .key = "cone_base_max_deg",                                                             \
           .json = "cone_base_deg",                                                                \
           .unit = "deg",                                                                          \
           .to_display = 1.0 / POM_DEG,                                                            \
           .lo = 0.0,                                                                              \
           .hi = 180.0,                                                                            \
           .def = 0.5 * POM_PI,                                                                    \
           .cls = POM_KIN_LIMCLASS_CONE},                                                          \
    [2] = {.name = "platform cone",                                                                \
           .per_pair = 0,                                                                          \
           .lower = 0,                                                                             \
           .key = "cone_platform_max_deg",                                                         \
           .json = "cone_platform_deg",                                                            \
           .unit = "deg",                                                                          \
           .to_display = 1.0 / POM_DEG,                                                            \
           .lo = 0.0,                                                                              \
           .hi = 180.0,                                                                            \
           .def = 0.5 * POM_PI,                                                                    \
           .cls = POM_KIN_LIMCLASS_CONE},                                                          \
    [3] = {                                                                                        \
      .name = "distance",                                                                          \
      .per_pair = 1,                                                                               \
      .lower = 1,                                                                                  \
      .key = "min_limb_distance_mm",                                                               \
      .json = "limb_distance_mm",                                                                  \
      .unit = "mm",                                                                                \
      .to_display = 1e3,                                                                           \
      .lo = 0.0,                                                                                   \
      .hi = 1e4,                                                                                   \
      .def = 0.0,                                                                                  \
      .cls = POM_KIN_LIMCLASS_INTERFERENCE                                                         \
    }                                                                                              \
  }

void pom_kin_segment_limits(const double R[9], const double *from, const double *to,
                            const double *dir_home, double value[9]);

/* For a group whose keys are all optional: when the group is present but
 * holds none of `known` (NULL-terminated key names), fails with a message
 * that names the group and lists the known keys (the generic unknown-key
 * check could only name the group itself). */
pom_status pom_kin_require_known_key(const pom_cfg *cfg, const char *group,
                                     const char *const known[], pom_error *err);

/* ---- the 3-RRR's arc links (kin_arc.c; docs/kinematics-3rrr.md section 6),
 * shared by arch_3rrr.c and the limb tables (kin_limb.c) ---------------- */
/* Orthonormal frame (columns) of the pair (a, b): a, unit(b - (a.b) a), and
 * their cross product. */
void pom_kin_pair_frame(double F[9], const double a[3], const double b[3]);
/* Mass, CM and inertia about O of a thin circular arc of radius r from unit a
 * to unit b (angle acos(a . b)), linear density lam (kg/m). */
void pom_kin_arc_inertia(double *mass, double cm[3], double IO[9], const double a[3],
                         const double b[3], double r, double lam);
/* Adds a point mass m at p to (mass, first moment s = sum m x, IO). */
void pom_kin_add_point_mass(double *mass, double s[3], double IO[9], double m, const double p[3]);
/* Writes a body given its mass, first moment about O and inertia about O;
 * returns its index. */
int pom_kin_body_from_O(pom_mechanism *mech, const char *name, int limb_no, double mass,
                        const double s[3], const double IO[9]);

#endif
