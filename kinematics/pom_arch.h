/* pom_arch.h - what an architecture is to pomlab: one table of operations
 * and descriptors (pom_kin_arch_type), in the manner of GSL's
 * gsl_odeiv2_step_type, with its private geometry in pom_kin_arch.data.
 * The 3P-S-S/S (arch_3pss.c), the 3S-P-S/S (arch_3sps.c) and the 3-RRR
 * spherical wrist (arch_3rrr.c) are three implementations; a user's
 * architecture is one more file and one registration (docs/extending.md).
 *
 * Conventions every implementation keeps (pom_kinematics.h): three limbs;
 * the platform turns about the fixed point O; R = I at home with every
 * actuator at mid-range; q_i in the unit of the type's actuator kind (m or
 * rad); q_dot = J omega with omega in the fixed frame; the mechanism's body
 * order 0 ground, 1 platform, then two bodies per limb (2 + 2i, 3 + 2i) in
 * the order the type's limb_twist fills them. */
#ifndef POM_ARCH_H
#define POM_ARCH_H

#include "pom_config.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_shape.h"
#include "pom_status.h"

#include <stddef.h>

/* One design parameter: a key of the `geometry` group in parameters mode. */
typedef struct {
  const char *key;     /* config key under `geometry`, unit in the name ("limb_lean_deg") */
  const char *meaning; /* one line for --list-architectures and docs */
  double to_si;        /* SI value = config value * to_si (POM_DEG for degrees, else 1) */
  double lo, hi;       /* allowed range, config unit */
  int optional;        /* 1: may be omitted, then `def` */
  double def;          /* default, config unit */
  int synth;           /* 1: the synthesis may vary it (synthesis.variables name = key) */
  int integer;         /* 1: a choice that takes whole values only (the 3-RRR's elbow = +1 or
                          -1): a fraction is refused, not rounded */
} pom_kin_param_desc;

/* One set of three points or axes of the private geometry: a key of the
 * `geometry` group in points mode, and what the JSON/HDF5 outputs name. */
typedef struct {
  const char *key;     /* "platform_points_m", "slider_axes", ... (SI, fixed frame at home) */
  const char *meaning; /* one line */
  size_t offset;       /* byte offset of a double[3][3] inside the type's private data */
  int optional;        /* 1: may be omitted (finish then derives it; it reads as zero) */
} pom_kin_points_desc;

/* How the synthesis counts a limit kind among its violation responses. */
typedef enum {
  POM_KIN_LIMCLASS_NONE = 0,        /* unused kind */
  POM_KIN_LIMCLASS_CONE = 1,        /* a joint's angular range (response "cone") */
  POM_KIN_LIMCLASS_INTERFERENCE = 2 /* bodies too close (response "interference") */
} pom_kin_limit_class;

/* One limit kind of the type (kinds 1..3; kind 0, the actuator range, is
 * common to every type). */
typedef struct {
  const char *name;  /* "base cone", "limb distance": bit name is "<name> limb i" or, per pair,
                        "<name> limbs i-j"; NULL = kind unused */
  int per_pair;      /* 0: one value per limb; 1: per limb pair (1-2, 2-3, 3-1) */
  int lower;         /* 0: violated when value > bound; 1: when value < bound (a clearance) */
  const char *key;   /* config key under `limits` ("cone_base_max_deg") */
  const char *json;  /* JSON key of the values in `pomlab ik --json` ("cone_base_deg") */
  const char *unit;  /* display unit ("deg", "mm") */
  double to_display; /* display = SI * to_display */
  double lo, hi;     /* allowed config range (display unit) */
  double def;        /* default bound (SI), not binding */
  pom_kin_limit_class cls;
} pom_kin_limit_desc;

/* One limb body group of the `inertia` config group (after the platform). */
typedef struct {
  const char *group; /* "piston": keys inertia.<group>.mass_kg, moments_kgm2 and `place` */
  int place;         /* 0: no placement key; 1: cm_offset_mm; 2: cm_fraction */
} pom_kin_inertia_body_desc;

/* One scalar of the `inertia` group the type reads itself (its link model). */
typedef struct {
  const char *key; /* key under `inertia`, unit in the name */
  const char *meaning;
  double to_si;
  double lo, hi; /* config unit */
  int optional;
  double def; /* config unit */
} pom_kin_value_desc;

struct pom_kin_arch_type {
  const char *name;           /* registry key and config `architecture` value: "3PSS" */
  const char *label;          /* "3P-S-S/S" */
  const char *description;    /* one line */
  pom_actuator_kind actuator; /* kind of its three actuators: fixes the unit of q */
  size_t data_size;           /* bytes of private geometry (<= sizeof pom_kin_arch.data) */

  /* design parameters: scale and the dimensionless parameters */
  const char *scale_key;     /* "platform_radius_mm" (config unit mm) */
  const char *scale_meaning; /* what the scale is */
  int scale_sets_kinematics; /* 1: q scales with the scale (linear actuators: the synthesis
                                scales the optimum to the stroke); 0: angles alone fix the
                                kinematics (the scale sets sizes and inertias only) */
  int n_params;
  const pom_kin_param_desc *params; /* [n_params] */
  int n_points;
  const pom_kin_points_desc *points; /* [n_points] the private point sets (points mode, outputs) */
  pom_kin_limit_desc limits[POM_KIN_LIM_KINDS]; /* [1..3] the type's limit kinds; [0] unused */
  double default_stroke;                        /* default actuator range (m or rad) */
  int n_inertia_bodies;
  const pom_kin_inertia_body_desc *inertia_bodies; /* [n_inertia_bodies] */
  int n_inertia_values;
  const pom_kin_value_desc *inertia_values; /* [n_inertia_values] */
  const char *unreachable; /* why a limb cannot be assembled, for messages ("the link cannot
                              reach the slider axis (no real IK root)") */
  /* 0: the spherical joint O between ground and platform is part of the
   * mechanism (3P-S-S/S, 3S-P-S/S: it holds the platform against
   * translation); 1: it is a choice, geometry.central_joint (default false:
   * the 3-RRR's legs hold O already and the wrist as built has none). */
  int optional_central_joint;

  /* operations (all required) */
  /* Private geometry from design parameters d (d->x SI in the order of params). */
  pom_status (*from_design)(pom_kin_arch *arch, const pom_kin_design *d, pom_error *err);
  /* Checks the private geometry and computes its derived fields (home
   * branches, unit axes, defaults of optional point sets). */
  pom_status (*finish)(pom_kin_arch *arch, pom_error *err);
  /* Limb i on the home branch at rotation R: q_i and (row non-NULL) the
   * Jacobian row (q_dot_i = row . omega). With row, transmission (when
   * non-NULL) receives the limb's transmission index in [0, 1]: the unit
   * actuation wrench's power on the actuated joint's unit twist, |B_ii| of
   * A omega = B q_dot normalised (P-S-S |l^ . a|, R-S-S |l^ . t^| with t^ the
   * crank point's unit velocity, R-R-R |n^ . u| with n^ = unit(w x v),
   * S-P-S 1; 0 at a serial singularity; docs/kinematics-tables.md 3.2).
   * Returns 0 when the limb cannot be assembled (or is at a leg singularity
   * when row is asked); never allocates, never formats. */
  int (*limb)(const pom_kin_arch *arch, int i, const double R[9], double *q, double row[3],
              double *transmission);
  /* Limb i's two bodies (out->body[2 + 2i], [3 + 2i]), q_i, J row and
   * q_bias at rotation R and platform angular velocity w (fixed frame).
   * Returns 0 like limb. */
  int (*limb_twist)(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                    pom_kin_twists *out);
  /* Values of limit kinds 1..3 at a reachable pose (R, q): value[3 (k - 1) +
   * member] in SI, for the kinds the type uses. */
  void (*limit_values)(const pom_kin_arch *arch, const double R[9], const double q[3],
                       double value[9]);
  /* Radius of the ground-side joints about the z axis over the actuator
   * range (m): the synthesis response "footprint" (divided by the scale). */
  double (*footprint)(const pom_kin_arch *arch);
  /* Bodies, joints and actuators at home (pom_kin_build_* helpers) from the
   * mass properties `in` (loaded by the inertia tables). */
  pom_status (*mechanism)(pom_mechanism *mech, const pom_kin_arch *arch, const pom_kin_inertia *in,
                          pom_error *err);

  /* optional (NULL: the exact path differences the orientation and omega
   * columns of its Jacobian). Limb i as limb_twist (fills *out alike, same
   * return) and the first derivatives of its fields with respect to a
   * platform rotation increment and to omega (pom_kin_twists_diff). */
  int (*limb_twist_diff)(const pom_kin_arch *arch, int i, const double R[9], const double w[3],
                         pom_kin_twists *out, pom_kin_twists_diff *dout);
  /* optional (NULL: every body drawn from its joint points, pom_shape.h) */
  /* What the bodies of `mech` (built by `mechanism`) look like at home:
   * writes up to cap shapes (fixed frame, SI) and returns how many (-1 when
   * cap is too small). Bodies it gives no shape get the derived one
   * (pom_kin_body_shapes; docs/view.md section 3). */
  int (*shapes)(const pom_kin_arch *arch, const pom_mechanism *mech, pom_kin_shape *shape, int cap);
  /* optional (NULL: every limb has one IK root, a single working mode) */
  /* Switches limb i of arch (a copy of an instance) to its other IK root
   * (working mode; docs/kinematics-modes.md section 1) and returns 1; returns
   * 0 and leaves arch untouched when limb i has a single root. Flipping
   * twice restores the home root. */
  int (*flip_branch)(pom_kin_arch *arch, int i);
  /* optional (NULL: a central joint or the limbs each hold the platform at
   * O, no constraint singularity). The limbs' constraint wrenches at R when
   * the limbs alone hold O through one wrench each (3-RUU, 3-UPU): unit
   * force of limb i in force[3 i ..], its moment about O over the force's
   * magnitude in moment[3 i ..] (m). Returns 3, or 0 when not applicable
   * at this instance or a limb cannot be assembled (pom_limb_constraint). */
  int (*constraint)(const pom_kin_arch *arch, const double R[9], double force[9], double moment[9]);
};

/* Private geometry of arch as the implementation's struct (data_size bytes,
 * aligned for doubles). */
#define POM_KIN_DATA(type_, arch_)  ((type_ *)(void *)(arch_)->data)
#define POM_KIN_CDATA(type_, arch_) ((const type_ *)(const void *)(arch_)->data)

/* ---- helpers for implementations ---------------------------------------- */

/* Limb frame at azimuth phi: e_r = (cos phi, sin phi, 0), e_t = (-sin phi,
 * cos phi, 0); direction(lean, azimuth) = sin(lean) (cos(azimuth) e_r +
 * sin(azimuth) e_t) + cos(lean) e_z (docs/kinematics.md section 2). */
void pom_kin_local_direction(double out[3], const double er[3], const double et[3], double lean,
                             double azimuth);

/* Mechanism builders: the body (name + limb number when limb > 0) with mass
 * properties b rotated to principal axes Q (columns, fixed frame) at cm
 * (b NULL: massless, e.g. the ground); the joint; the actuator on joint
 * (kind from the joint type: prismatic or revolute). Return the new index. */
int pom_kin_build_body(pom_mechanism *m, const char *name, int limb, const pom_kin_body_inertia *b,
                       const double Q[9], const double cm[3]);
int pom_kin_build_joint(pom_mechanism *m, const char *name, int limb, pom_joint_type type, int b0,
                        int b1, const double point[3], const double axis[3], const double axis2[3]);
void pom_kin_build_actuator(pom_mechanism *m, int joint, int moving_body, double stroke);
/* Ground and platform (mass properties in->platform), the first two bodies
 * of every mechanism, and when central_joint the spherical joint O at the
 * origin between them (then the first joint). */
void pom_kin_build_base(pom_mechanism *m, const pom_kin_inertia *in, int central_joint);
/* Principal axes of a limb body: z = unit limb axis a; x = x_given or
 * unit(e_z x a), or e_z x er when a is vertical; y = z x x. */
void pom_kin_limb_axes(double Q[9], const double a[3], const double er[3], const double *x_given);
/* inertia = Q diag(moments) Q^T, exactly symmetric. */
void pom_kin_rotate_inertia(double I[9], const double Q[9], const double moments[3]);

/* Twist helpers: a body at rest with R = I; the rotation taking unit a to
 * unit b by the smallest angle (a . b > -1); out = u v^T. */
void pom_kin_twist_rest(pom_kin_body_twist *b);
void pom_kin_min_rotation(double R[9], const double a[3], const double b[3]);
void pom_kin_outer(double out[9], const double u[3], const double v[3]);

/* Smallest distance between segments [p0, p1] and [q0, q1] (m). */
double pom_kin_segment_distance(const double p0[3], const double p1[3], const double q0[3],
                                const double q1[3]);
/* Angle between two vectors (rad, in [0, pi]), by atan2 (accurate near 0). */
double pom_kin_angle_between(const double a[3], const double b[3]);

#endif
