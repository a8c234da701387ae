/* pom_kinematics.h - geometry, inverse/forward kinematics, Jacobian and
 * dexterity of orientation manipulators: the 3P-S-S/S, the 3S-P-S/S, the
 * 3-RRR spherical wrist and any architecture registered through pom_arch.h
 * (derivations: docs/kinematics.md, docs/kinematics-3rrr.md; adding one:
 * docs/extending.md).
 *
 * The platform turns about the fixed spherical joint O (the origin). R is the
 * platform rotation (platform frame -> fixed frame), R = I at home, where every
 * actuator is at mid-stroke. q[i] is actuator i's coordinate from mid-stroke
 * in its own unit: a displacement (m, positive = extension) for a prismatic
 * actuator, an angle (rad) for a revolute one. q_dot = J omega, omega the
 * platform angular velocity in the fixed frame (rad/s), J in m/rad or rad/rad
 * (row-major, row i = limb i).
 *
 * This header is a contract used by dynamics/, doe/ and optimize/: extend it,
 * do not rename or remove fields. */
#ifndef POM_KINEMATICS_H
#define POM_KINEMATICS_H

#include "pom_config.h"
#include "pom_mechanism.h"
#include "pom_status.h"

typedef struct pom_kin_arch_type pom_kin_arch_type; /* an architecture's op table (pom_arch.h) */

#define POM_KIN_MAX_PARAMS 12  /* design parameters of one architecture */
#define POM_KIN_ARCH_DATA  192 /* doubles of private geometry data of one architecture */

/* Design parameters of an architecture: its dimensionless parameters (ratios
 * and angles, SI: rad) in the order of its type's parameter table, plus one
 * scale (m) that turns them into metres (docs/kinematics.md section 2,
 * docs/extending.md). What the scale is depends on the type: the platform
 * radius of the 3P-S-S/S and 3S-P-S/S, the link radius of the 3-RRR. */
typedef struct {
  double scale;                 /* m */
  double x[POM_KIN_MAX_PARAMS]; /* [type->n_params] SI values (rad or ratio) */
} pom_kin_design;

/* Limit kinds of an architecture: kind 0 is the actuator range (stroke) of
 * every architecture; kinds 1..3 are the type's own (pom_arch.h). */
#define POM_KIN_LIM_KINDS 4

/* One architecture instance: its type, name, limits and its type's private
 * geometry (everything in SI: m, rad; fixed frame at home). Plain data:
 * copying it by value copies the whole geometry. Filled by
 * pom_kin_arch_load() or pom_kin_arch_from_design(). */
typedef struct {
  const pom_kin_arch_type *type; /* the architecture (never NULL once loaded) */
  char name[64];                 /* config `name` */
  double stroke; /* total actuator range in the unit of q (m or rad): |q_i| <= stroke / 2 */
  double limit_bound[POM_KIN_LIM_KINDS]; /* [1..3] bound of the type's limit kind k (SI);
                                            [0] unused (stroke) */
  double home_det_sign;           /* sign of det J at home (+1 or -1): FK rejects solutions across a
                                     singularity */
  int has_design;                 /* 1 when loaded from design parameters (mode = "parameters") */
  pom_kin_design design;          /* the design parameters when has_design (else zero) */
  double data[POM_KIN_ARCH_DATA]; /* private geometry of the type (its data_size bytes) */
  int central_joint; /* 1: the mechanism has the spherical joint O between ground and platform
                        (always for types without optional_central_joint; the 3-RRR's
                        geometry.central_joint, default 0: docs/kinematics-3rrr.md section 9) */
} pom_kin_arch;

/* Loads geometry and limits from the `architecture`, `geometry` and `limits`
 * keys of cfg (docs/config.md). */
pom_status pom_kin_arch_load(pom_kin_arch *arch, const pom_cfg *cfg, pom_error *err);

/* The top-level config names that the kinematic model of a mechanism reads
 * (pom_kin_arch_load and pom_kin_inertia_load: `name`, `architecture`,
 * `geometry`, `limits`, `inertia`), NULL-terminated, static storage. The
 * `workspace` group (pom_kin_ws_load) belongs to `pomlab workspace`, not to
 * the model, and is not listed. Callers use it to refuse settings that the
 * model never reads (docs/config.md). */
const char *const *pom_kin_model_groups(void);

/* The geometry groups alone, what pom_kin_arch_load reads with the model's
 * name (`name`, `architecture`, `geometry`, `limits`): the groups of the
 * kinematic commands and of the synthesis. NULL-terminated, static storage. */
const char *const *pom_kin_arch_groups(void);

/* The group pom_kin_ws_load reads (`workspace`), NULL-terminated, static
 * storage. */
const char *const *pom_kin_ws_groups(void);

/* Inverse kinematics in closed form on the home assembly branch: q (m) for
 * rotation R. POM_ERR_UNREACHABLE (q untouched, err says which limb) when a
 * limb cannot be assembled; POM_ERR_NONFINITE when R holds NaN or Inf. Does
 * not check limits. */
pom_status pom_kin_inverse(const pom_kin_arch *arch, const double R[9], double q[3],
                           pom_error *err);

/* Jacobian J (m/rad) with q_dot = J omega at rotation R (q from IK). */
pom_status pom_kin_jacobian(const pom_kin_arch *arch, const double R[9], double J[9],
                            pom_error *err);

/* Builds the mechanical description (bodies with mass/inertia from the
 * `inertia` keys of cfg, joints, actuators) at the home pose. */
pom_status pom_kin_mechanism_build(pom_mechanism *mech, const pom_kin_arch *arch,
                                   const pom_cfg *cfg, pom_error *err);

/* ---- additions: design parameters, limits, pose evaluation -------------- */

/* Default limits of arch->type: its default actuator range (12 mm for the
 * linear voice coils) and the default bounds of its limit kinds (not
 * binding). arch->type must be set. */
void pom_kin_limits_defaults(pom_kin_arch *arch);

/* Builds the geometry of an architecture of `type` from design parameters
 * (limits set to pom_kin_limits_defaults, name set to type->name).
 * POM_ERR_ARG with a message when the design is degenerate (e.g. a limb
 * perpendicular to its slider axis at home). */
pom_status pom_kin_arch_from_design(pom_kin_arch *arch, const pom_kin_arch_type *type,
                                    const pom_kin_design *design, pom_error *err);

/* Completes an arch whose type and private points were filled by the caller
 * (explicit-points form): checks it and computes the derived fields. */
pom_status pom_kin_arch_finish(pom_kin_arch *arch, pom_error *err);

/* The private point set `key` of arch's type (pom_arch.h points table, e.g.
 * "platform_points_m", "slider_axes", "base_axes"): 3 rows of 3 doubles, SI,
 * fixed frame at home; NULL when the type has no such set. */
const double *pom_kin_arch_points(const pom_kin_arch *arch, const char *key);

/* ---- the registry of architectures (docs/extending.md) ------------------- */

/* The architecture registered under `name` (config `architecture` value,
 * e.g. "3PSS", "3RRR"); NULL when none. */
const pom_kin_arch_type *pom_kin_arch_type_find(const char *name);

/* Number of registered architectures, and the k-th (0-based, built-ins
 * first, in registration order); NULL out of range. */
int pom_kin_arch_type_count(void);
const pom_kin_arch_type *pom_kin_arch_type_at(int k);

/* Registers an architecture defined outside the library (pom_arch.h).
 * POM_ERR_ARG when its name is taken, its table is incomplete or its private
 * data exceeds POM_KIN_ARCH_DATA doubles. Register before any thread reads
 * the registry (lookups are not locked). The table must outlive every use. */
pom_status pom_kin_arch_register(const pom_kin_arch_type *type, pom_error *err);

/* Short name ("3PSS"), label ("3P-S-S/S") and actuator kind of a type. */
const char *pom_kin_type_name(const pom_kin_arch_type *type);
const char *pom_kin_type_label(const pom_kin_arch_type *type);
pom_actuator_kind pom_kin_type_actuator(const pom_kin_arch_type *type);

/* IK and Jacobian together (cheaper than the two calls): q (m) and J (m/rad).
 * Same failures as pom_kin_inverse. */
pom_status pom_kin_inverse_jacobian(const pom_kin_arch *arch, const double R[9], double q[3],
                                    double J[9], pom_error *err);

/* Singular values sv (descending, m/rad), condition number kappa = sv0/sv2
 * (INFINITY when sv2 = 0) and dexterity 1/kappa in [0, 1] of J. Closed form
 * (eigenvalues of J^T J from the characteristic cubic): errors ~1e-15 sv0,
 * up to ~1e-8 sv0 when two singular values (nearly) coincide; use
 * pom_m3_singular_values where full accuracy matters. Any output pointer may
 * be NULL. */
void pom_kin_dexterity(const double J[9], double sv[3], double *kappa, double *dexterity);

/* A cheap bound on the dexterity of J: 3/kappa_F(J) with the Frobenius
 * condition number kappa_F = |J|_F |J^-1|_F = |J|_F |adj J|_F / |det J|
 * (cofactors, one square root, no SVD). kappa_2 <= kappa_F <= 3 kappa_2, so
 * 1/kappa_2(J) <= the result <= 3/kappa_2(J); 1 exactly when J is a
 * multiple of an orthogonal matrix, 0 when J is singular, as
 * pom_kin_dexterity's (docs/dynamics-exact.md section 3). */
double pom_kin_dexterity_bound(const double J[9]);

/* Limit bits of pom_kin_pose.violations: bit 3 kind + member, kind 0 the
 * actuator range of limb member, kinds 1..3 the architecture's own limits
 * (pom_arch.h), each per limb or per limb pair (member 0: limbs 1-2, 1: 2-3,
 * 2: 3-1). For the 3P-S-S/S and 3S-P-S/S kind 1 is the base cone, 2 the
 * platform cone and 3 the limb distance (the names below). */
enum {
  POM_KIN_LIM_STROKE = 0,
  POM_KIN_LIM_CONE_BASE = 3,
  POM_KIN_LIM_CONE_PLATFORM = 6,
  POM_KIN_LIM_DISTANCE = 9,
  POM_KIN_LIM_COUNT = 12
};

/* Name of limit bit k of arch's type ("stroke limb 2", "platform cone limb
 * 1", "distance limbs 3-1", "elbow angle limbs 1-2") into buf; "?" when out
 * of range or unused by the type. Returns buf. */
const char *pom_kin_limit_name(const pom_kin_arch *arch, int k, char *buf, size_t cap);

/* Everything known about one pose. */
typedef struct {
  int reachable;                   /* 1 when every limb was assembled on the home branch */
  int unreachable_limb;            /* 0-based limb that failed, -1 when reachable */
  double q[3];                     /* actuator displacements from mid-stroke (m) */
  double J[9];                     /* Jacobian, q_dot = J omega (m/rad), row-major */
  double sv[3];                    /* singular values of J, descending (m/rad) */
  double kappa;                    /* condition number sv0/sv2 (INFINITY when singular) */
  double dexterity;                /* 1/kappa in [0, 1] */
  double limit[POM_KIN_LIM_COUNT]; /* value of limit bit k (SI: m or rad): [0..2] |q_i| (the
                                      actuator range), [3..11] the type's limit kinds 1..3 (3PSS,
                                      3SPS: base cone angle, platform cone angle, limb distance) */
  unsigned violations;             /* bit k set when limit k is violated (pom_kin_limit_name) */
  /* the three singularities told apart (docs/kinematics-tables.md 3.1) */
  int singular;             /* bits POM_KIN_SING_SERIAL, _PARALLEL, _CONSTRAINT; 0 none */
  int n_constraint;         /* 3 when the limbs alone hold O through one constraint wrench each
                               (3-RUU, 3-UPU: type op constraint), else 0 (a central joint or
                               spherical limbs hold O: no constraint singularity) */
  double constraint_sv;     /* smallest singular value of the limbs' unit constraint forces (1:
                               orthogonal, 0: a constraint singularity, the platform can
                               translate); 1 when n_constraint = 0 */
  double constraint_offset; /* largest distance of a constraint force's line from O (m): 0 when
                               the limbs leave the platform a pure rotation about O */
  double transmission[3];   /* per limb, its transmission index in [0, 1] (the limb op, pom_arch.h):
                               1 far from, 0 at its serial singularity; 0 when unreachable */
  unsigned serial_limbs;    /* bit i: limb i at a serial singularity (transmission[i] <=
                               POM_KIN_SERIAL_TOL, or it assembles without its row) */
} pom_kin_pose;

/* Bits of pom_kin_pose.singular (docs/kinematics-tables.md 3.1, 3.2).
 * SERIAL: a limb's actuation wrench (nearly) does no work on its actuator:
 * its transmission index is <= POM_KIN_SERIAL_TOL (serial_limbs names the
 * limbs), or the limb assembles but its op refuses the row (the pose is then
 * unreachable). PARALLEL: the three actuation wrenches are dependent,
 * dexterity <= POM_KIN_SING_TOL: locked actuators leave the platform a
 * rotation. CONSTRAINT: the limbs' constraint forces are dependent,
 * constraint_sv <= POM_KIN_SING_TOL: the platform gains a translation. */
enum { POM_KIN_SING_SERIAL = 1, POM_KIN_SING_PARALLEL = 2, POM_KIN_SING_CONSTRAINT = 4 };
/* above the closed-form dexterity's worst error (~1e-8 when two singular
 * values nearly coincide, pom_kin_dexterity) */
#define POM_KIN_SING_TOL 1e-7
/* sqrt(POM_KIN_SING_TOL): the transmission index vanishes like the square
 * root of the distance from a fold (two IK roots meet) where the dexterity
 * vanishes like the distance from a parallel singularity, so both bits switch
 * on at the same distance, ~1e-7 rad (docs/kinematics-tables.md 3.2) */
#define POM_KIN_SERIAL_TOL 3.1622776601683794e-4

/* "none", or the set bits of `singular` as "serial (limbs 1, 2), parallel,
 * constraint" into buf (serial_limbs: bit i limb i, 0 unknown). Returns
 * buf. */
const char *pom_kin_singular_text(int singular, unsigned serial_limbs, char *buf, size_t cap);

/* Evaluates the pose R: IK, J, dexterity and every limit. Returns POM_OK when
 * reachable and within limits; POM_ERR_UNREACHABLE (pose->reachable = 0,
 * err names the limb); POM_ERR_NONFINITE (pose->reachable = 0,
 * unreachable_limb = -1) when R holds NaN or Inf; POM_ERR_LIMIT when
 * reachable but some limit is violated
 * (pose fully filled, err names every violation with its value and bound).
 * err may be NULL (no message formatting: use this in loops). */
pom_status pom_kin_pose_evaluate(const pom_kin_arch *arch, const double R[9], pom_kin_pose *pose,
                                 pom_error *err);

/* Writes the names of the violated limits of `violations` into buf as
 * "stroke limb 1, platform cone limb 2" ("none" when 0). */
void pom_kin_violations_text(const pom_kin_arch *arch, unsigned violations, char *buf, size_t cap);

/* ---- forward kinematics -------------------------------------------------- */

/* Options of the forward kinematics (docs/kinematics.md section 4). */
typedef struct {
  double residual_tol; /* converged when max_i |q_i(R) - q_i| <= this (m); default 1e-12 */
  int max_iterations;  /* Newton iterations per continuation step; default 30 */
  double max_rotation; /* largest rotation of one Newton update (rad); default 0.3 */
  int initial_steps;   /* continuation steps tried first when direct Newton fails; default 4 */
  int max_halvings;    /* times a failing continuation step may be halved; default 16 */
  double singular_tol; /* J treated as singular when sv2 <= singular_tol * sv0; default 1e-10 */
} pom_kin_fk_opts;

void pom_kin_fk_defaults(pom_kin_fk_opts *opts);

/* What the forward kinematics did. */
typedef struct {
  int iterations;         /* total Newton iterations, all steps */
  int continuation_steps; /* successful continuation steps; 0 when direct Newton converged */
  double residual;        /* final max_i |q_i(R) - q_i| (m) */
} pom_kin_fk_info;

/* Forward kinematics: the rotation R (on the home branch) whose IK gives q
 * (m). Newton with the analytic Jacobian from R_start (NULL = home, R = I);
 * when it fails, continuation along q(t) = q_start + t (q - q_start).
 * POM_ERR_NOCONVERGE (R untouched, err says where it stalled) on failure.
 * opts and info may be NULL (defaults / not reported). */
pom_status pom_kin_forward(const pom_kin_arch *arch, const double q[3], const double R_start[9],
                           const pom_kin_fk_opts *opts, double R[9], pom_kin_fk_info *info,
                           pom_error *err);

/* ---- workspace ----------------------------------------------------------- */

/* Told every few thousand poses by the long workspace loops: `done` poses
 * evaluated so far out of at most `bound`. */
typedef void (*pom_kin_progress)(void *user, long done, long bound);

/* Regular dexterous workspace settings (`workspace` group; docs/kinematics.md
 * section 6). */
typedef struct {
  double dexterity_min;      /* threshold on 1/kappa; default 0.3 */
  double resolution;         /* grid step in each ZYX Euler angle (rad); default 1 deg */
  double max_half_width;     /* search stops at this cube half-width (rad); default 45 deg */
  int check_limits;          /* 1: stroke, cones and clearance count; default 1 */
  double gci_half_width;     /* GCI region: Euler cube half-width (rad); 0 = the RDW; default 0 */
  double map_half_width;     /* half-width of the CSV dexterity map (rad); default 20 deg */
  double map_resolution;     /* grid step of the CSV dexterity map (rad); default 2 deg */
  double max_poses;          /* budget of pose evaluations of each grid (RDW search, GCI, map);
                                default 1e8 */
  pom_kin_progress progress; /* told during the RDW search; NULL (default) = nobody; not a
                                config key */
  void *progress_user;       /* passed to progress */
} pom_kin_ws_opts;

void pom_kin_ws_defaults(pom_kin_ws_opts *opts);

/* Reads the `workspace` group (all keys optional) over the defaults. */
pom_status pom_kin_ws_load(pom_kin_ws_opts *opts, const pom_cfg *cfg, pom_error *err);

/* Result of the regular dexterous workspace search. */
typedef struct {
  double half_width;        /* largest a (rad, a multiple of the resolution) such that every grid
                               pose of the Euler cube [-a, a]^3 passes; -1 when home fails */
  int capped;               /* 1 when the search reached max_half_width without a failure */
  int budget_reached;       /* 1 when the next shell would have taken the search past max_poses:
                               half_width is then a lower bound, and fail_* are unset */
  double min_dexterity;     /* smallest 1/kappa over the accepted cube */
  double fail_euler[3];     /* first failing pose (psi, theta, phi) (rad) when !capped */
  pom_status fail_status;   /* why it failed: POM_ERR_UNREACHABLE, POM_ERR_LIMIT or POM_ERR_SINGULAR
                               (dexterity) */
  unsigned fail_violations; /* limit bits of the failing pose */
  double fail_dexterity;    /* 1/kappa of the failing pose (0 when unreachable) */
  long poses;               /* poses evaluated */
} pom_kin_ws_result;

/* Regular dexterous workspace: the largest cube centred at home in ZYX Euler
 * space whose grid poses are all assemblable, within limits (if
 * check_limits) and have dexterity >= dexterity_min. The search grows the
 * cube shell by shell and stops before a shell that would take the poses
 * evaluated past opts->max_poses (res->budget_reached). */
pom_status pom_kin_workspace(const pom_kin_arch *arch, const pom_kin_ws_opts *opts,
                             pom_kin_ws_result *res, pom_error *err);

/* Global conditioning index over the Euler cube of half-width half_width
 * (rad): the mean of 1/kappa over the usable poses (assemblable and, when
 * check_limits, within limits) with the invariant measure cos(theta) dpsi
 * dtheta dphi, midpoint rule with cells of size <= resolution. *usable_fraction
 * (may be NULL) receives the measure fraction of usable poses. POM_ERR_ARG
 * when no pose is usable. */
pom_status pom_kin_gci(const pom_kin_arch *arch, double half_width, double resolution,
                       int check_limits, double *gci, double *usable_fraction, pom_error *err);

/* pom_kin_gci telling `progress` (NULL = nobody) every few thousand poses. */
pom_status pom_kin_gci_progress(const pom_kin_arch *arch, double half_width, double resolution,
                                int check_limits, pom_kin_progress progress, void *user,
                                double *gci, double *usable_fraction, pom_error *err);

/* Poses pom_kin_gci evaluates over that cube and resolution (n^3 cells). */
double pom_kin_gci_poses(double half_width, double resolution);

/* Poses of the search grid of the Euler cube [-a, a]^3 at step h, a = the
 * largest whole number of steps <= half_width: (2 floor(a/h) + 1)^3. The RDW
 * search evaluates at most this many; the CSV map exactly this many. */
double pom_kin_grid_poses(double half_width, double resolution);

/* ---- mechanism inputs ---------------------------------------------------- */

/* Mass properties of one body (docs/kinematics.md section 7). */
typedef struct {
  double mass;        /* kg */
  double moments[3];  /* principal moments about the CM along body axes x, y, z (kg m^2); limb
                         bodies: z = limb axis */
  double cm[3];       /* platform: CM at home, fixed frame (m) */
  double cm_offset;   /* 3PSS piston: CM from B_i along d_i; 3SPS cylinder: from A_i along the limb;
                         3SPS piston: from B_i toward A_i (m) */
  double cm_fraction; /* 3PSS link: CM at B_i + cm_fraction (C_i - B_i) */
} pom_kin_body_inertia;

#define POM_KIN_MAX_INERTIA_BODIES 4
#define POM_KIN_MAX_INERTIA_VALUES 8

/* Mass properties of a mechanism: the platform, then the type's limb body
 * groups in the order of its inertia table (pom_arch.h; 3PSS: piston, link;
 * 3SPS: cylinder, piston), plus the type's own scalar values (3-RRR: the link
 * model's density and section, the rotor inertia). */
typedef struct {
  pom_kin_body_inertia platform;
  pom_kin_body_inertia body[POM_KIN_MAX_INERTIA_BODIES]; /* [type's n_bodies] */
  double value[POM_KIN_MAX_INERTIA_VALUES];              /* [type's n_values] SI */
  double gravity[3]; /* gravitational acceleration, fixed frame (m/s^2) */
} pom_kin_inertia;

/* Reads the `inertia` group for arch->type. */
pom_status pom_kin_inertia_load(pom_kin_inertia *in, const pom_kin_arch *arch, const pom_cfg *cfg,
                                pom_error *err);

/* Builds the mechanism from an arch and mass properties (no config). */
pom_status pom_kin_mechanism_from(pom_mechanism *mech, const pom_kin_arch *arch,
                                  const pom_kin_inertia *in, pom_error *err);

/* Short name of an instance's architecture ("3PSS", "3SPS", "3RRR"). */
const char *pom_kin_arch_name(const pom_kin_arch *arch);

/* ---- rigid-body motion of every body (added for the exact dynamics) ------ */

/* Pose and velocity maps of one body of the rigid mechanism at one platform
 * rotation (docs/dynamics-exact.md section 2). A point of the body at home
 * position p (fixed frame) is now at ref + R (p - ref_home). With omega the
 * platform angular velocity (fixed frame): velocity of the reference point
 * = A omega, body angular velocity = B omega; at omega_dot != 0 the
 * accelerations are A omega_dot + a_bias and B omega_dot + alpha_bias. */
typedef struct {
  double R[9];          /* rotation from home, fixed frame */
  double ref_home[3];   /* reference point at home (m) */
  double ref[3];        /* reference point now (m) */
  double A[9];          /* reference-point velocity per platform angular velocity (m/rad) */
  double B[9];          /* body angular velocity per platform angular velocity (1) */
  double a_bias[3];     /* reference-point acceleration at omega_dot = 0 (m/s^2) */
  double alpha_bias[3]; /* angular acceleration at omega_dot = 0 (rad/s^2) */
  int spin_free;        /* 1: the spin about spin_axis is an idle freedom the platform does not
                           fix; R and B carry zero spin (a dynamics model must treat the body as
                           axisymmetric about spin_axis) */
  double spin_axis[3];  /* unit axis of the idle spin (fixed frame), zero when !spin_free */
} pom_kin_body_twist;

#define POM_KIN_TWIST_MAX_BODIES 8

/* Every body of the mechanism of pom_kin_mechanism_from, by the same body
 * index (0 ground, 1 platform, then per limb i the type's limb bodies: 3PSS
 * piston 2+2i, link 3+2i; 3SPS cylinder 2+2i, piston 3+2i; 3RRR proximal
 * 2+2i, distal 3+2i). */
typedef struct {
  int n_bodies;     /* bodies filled, including the ground */
  double q[3];      /* actuator displacements (m), as pom_kin_inverse */
  double J[9];      /* q_dot = J omega (m/rad), as pom_kin_jacobian */
  double q_bias[3]; /* q_ddot at omega_dot = 0 (m/s^2) */
  pom_kin_body_twist body[POM_KIN_TWIST_MAX_BODIES];
} pom_kin_twists;

/* First derivatives of a limb's twists (second-order kinematics, for the
 * exact path's analytic Jacobian; docs/dynamics-exact.md section 5). With
 * R(theta) = exp([theta]x) R, a rotation increment theta (rad, fixed frame)
 * applied to the platform, d_theta[k] holds d/d theta_k at theta = 0 of the
 * fields of pom_kin_twists that limb i fills (q[i], row i of J, q_bias[i] and
 * its two bodies' A, B, a_bias, alpha_bias); d_omega[k] holds d/d omega_k of
 * the same fields at fixed R (only the biases, quadratic in omega, are
 * non-zero). Poses need no entry: d ref / d theta = A e_k and
 * d R_body / d theta_k = [B e_k]x R_body. Fields a limb does not fill are
 * left as they were (the caller zeroes the struct). */
typedef struct {
  pom_kin_twists d_theta[3]; /* per platform rotation increment about fixed axis k */
  pom_kin_twists d_omega[3]; /* per platform angular velocity component k */
} pom_kin_twists_diff;

/* Poses, twist maps and velocity-product accelerations of every body at
 * platform rotation R and angular velocity omega (rad/s, fixed frame; NULL =
 * 0: then the biases are zero). The 3PSS link spin about B_i C_i is set to
 * zero (it is not determined by R). Same failures as pom_kin_inverse, plus
 * POM_ERR_UNREACHABLE for a 3SPS limb along its U-joint axis. err may be
 * NULL (no message formatting: use this in integrator loops). */
pom_status pom_kin_body_twists(const pom_kin_arch *arch, const double R[9], const double omega[3],
                               pom_kin_twists *out, pom_error *err);

/* Whether arch's type provides second-order kinematics (limb_twist_diff):
 * 1 or 0. Without it pom_kin_body_twists_diff returns POM_ERR_ARG. */
int pom_kin_has_twists_diff(const pom_kin_arch *arch);

/* pom_kin_body_twists (same *out, same failures) and the first derivatives
 * of every field it fills (pom_kin_twists_diff) for all bodies: the limbs by
 * the type's limb_twist_diff, the platform's own entries zero (A = 0, B = I
 * and no bias at every R and omega: docs/dynamics-exact.md section 2.1).
 * omega NULL = 0. The derivative structs' pose fields (R, ref, ref_home,
 * spin) are not written: poses follow from A and B. A type without
 * limb_twist_diff: POM_ERR_ARG with *out and *dout untouched (the "not provided" status; test first
 * with pom_kin_has_twists_diff). err may be NULL (no message formatting). */
pom_status pom_kin_body_twists_diff(const pom_kin_arch *arch, const double R[9],
                                    const double omega[3], pom_kin_twists *out,
                                    pom_kin_twists_diff *dout, pom_error *err);

/* ---- all solutions: working modes and assembly modes -------------------- */
/* (docs/kinematics-modes.md) A working mode is one IK root per limb (the
 * branch combination); an assembly mode is one platform orientation R whose
 * IK on some working mode gives the actuator coordinates q (one FK root). */

#define POM_KIN_MAX_MODES 64 /* assembly modes kept by pom_kin_forward_all (more: refused) */

/* One mode: a pose and what is known there. */
typedef struct {
  double R[9];       /* platform rotation */
  int branch[3];     /* per limb: +1 the home IK root, -1 the other, 0 the limb has one root */
  pom_status status; /* pom_kin_pose_evaluate on this working mode: POM_OK, POM_ERR_LIMIT,
                       POM_ERR_UNREACHABLE (then pose.q and the rest are not set) */
  pom_kin_pose pose; /* q, J, singular values, kappa, dexterity, limits, violations */
  double det;        /* det J (unit of q per rad, cubed); 0 when unreachable */
  double det_unit;   /* det of J with each row scaled to unit length, in [-1, 1]: 0 at a
                        platform (parallel) singularity, +-1 when the rows are orthonormal */
  unsigned serial;   /* bit i: limb i at a leg (serial) singularity: pose.serial_limbs (its
                        transmission index <= POM_KIN_SERIAL_TOL; 0 where two IK roots meet) */
  int parallel;      /* 1: platform (parallel) singularity, |det_unit| <= singular_tol */
  double residual;   /* FK: max_i |q_i(R) - q_i| (m or rad); IK: 0 */
} pom_kin_mode;

/* Options of pom_kin_forward_all. */
typedef struct {
  int seeds;           /* start rotations per working mode (quasi-uniform over SO(3)); 128 */
  double residual_tol; /* converged when max_i |q_i(R) - q_i| <= this (m or rad); 1e-12 */
  int max_iterations;  /* damped Newton iterations per start; 60 */
  double max_rotation; /* largest rotation of one Newton update (rad); 0.3 */
  double same_tol;     /* two roots closer than this rotation angle (rad) are one; 1e-7 */
  double singular_tol; /* |det_unit| at or below this: parallel singularity; 1e-9 */
} pom_kin_fk_all_opts;

void pom_kin_fk_all_defaults(pom_kin_fk_all_opts *opts);

/* Working modes: how many limbs of arch have two IK roots (n2; the arch has
 * 2^n2 working modes), and arch with the given branch per limb (+1 home
 * root, -1 the other; a limb with one root takes only +1) in *out.
 * POM_ERR_ARG when a branch is not +-1 or -1 on a one-root limb. */
int pom_kin_two_root_limbs(const pom_kin_arch *arch, int two_roots[3]);
pom_status pom_kin_arch_with_branches(pom_kin_arch *out, const pom_kin_arch *arch,
                                      const int branch[3], pom_error *err);

/* Every working mode at rotation R: modes[k] for k < *n (*n = 2^n2 <= 8), in
 * binary order of the branches (limb 1 slowest; +1 before -1), each with its
 * status (reachable or not), q, J, conditioning, limits and singular flags.
 * POM_ERR_NONFINITE when R holds NaN or Inf; else POM_OK (unreachable modes
 * are listed with their status). */
pom_status pom_kin_inverse_all(const pom_kin_arch *arch, const double R[9], pom_kin_mode modes[8],
                               int *n, pom_error *err);

/* Every assembly mode at actuator coordinates q: damped Newton on SO(3) on
 * every working mode from opts->seeds quasi-uniform starts, converged roots
 * merged when closer than same_tol; sorted by rotation angle from home.
 * modes[k] for k < *n. POM_ERR_ARG when cap < POM_KIN_MAX_MODES or the options are invalid,
 * POM_ERR_NONFINITE when q holds NaN or Inf; POM_ERR_NOCONVERGE when more
 * than POM_KIN_MAX_MODES distinct roots appear (a self-motion: a continuum of
 * solutions). *n = 0 (POM_OK) when no orientation gives q. opts NULL =
 * defaults. */
pom_status pom_kin_forward_all(const pom_kin_arch *arch, const double q[3],
                               const pom_kin_fk_all_opts *opts, pom_kin_mode *modes, int cap,
                               int *n, pom_error *err);

#endif
