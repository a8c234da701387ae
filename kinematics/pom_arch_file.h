/* pom_arch_file.h - an architecture described by a file (libconfig, format
 * of docs/architecture-files.md): three limbs of three joints (R, P, U, S)
 * whose home points and axes are expressions (core/pom_expr.h) of named
 * design parameters, the two bodies of each limb, the limit kinds and the
 * central joint. Loading a file gives a runtime architecture type whose
 * first member is a pom_kin_arch_type: its descriptors (parameters, scale,
 * limits, inertia groups) come from the file and its from_design evaluates
 * the expressions for a design into the numeric limb table; the other
 * operations are filled by the numerics (kinematics/pom_limb.h) before the
 * type is registered.
 *
 * Lifetime: pom_arch_file_load allocates; pom_arch_file_destroy frees. A
 * registered type must outlive every use (pom_kin_arch_register). */
#ifndef POM_ARCH_FILE_H
#define POM_ARCH_FILE_H

#include "pom_arch.h"
#include "pom_expr.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

#define POM_AF_MAX_LETS 32 /* named expressions of one scope (global, or one limb table) */
#define POM_AF_NAME_LEN 32 /* names of lets, symbols, bodies, joints */
#define POM_AF_MAX_REFS 8  /* references listed */
#define POM_AF_FORMAT   1  /* the format version this loader reads (key `format`) */

/* Central constraint between ground and platform. */
typedef enum {
  POM_AF_CENTRAL_NONE = 0,    /* none: the limbs alone keep the platform on O (3-RRR) */
  POM_AF_CENTRAL_S = 1,       /* a spherical joint at O, always part of the mechanism */
  POM_AF_CENTRAL_OPTIONAL = 2 /* a modelling choice: config geometry.central_joint */
} pom_af_central;

/* How a limb body's mass properties are given. */
typedef enum {
  POM_AF_BODY_RIGID = 0, /* inertia.<group> mass_kg, moments_kgm2 and a placement */
  POM_AF_BODY_ARC = 1    /* thin circular arc about O (docs/kinematics-3rrr.md section 6) */
} pom_af_body_model;

/* Where a rigid body's centre of mass is. */
typedef enum {
  POM_AF_CM_AT = 0,      /* at `from` (no placement key) */
  POM_AF_CM_OFFSET = 1,  /* from + cm_offset unit(along) (inertia.<group>.cm_offset_mm) */
  POM_AF_CM_FRACTION = 2 /* from + cm_fraction (to - from) (inertia.<group>.cm_fraction) */
} pom_af_cm_rule;

/* What a limit kind measures (pom_arch.h limit kinds 1..3). */
typedef enum {
  POM_AF_MEASURE_CONE = 0,      /* per limb: angle of the segment joint a -> joint b from its home
                                   direction, in the fixed or the platform frame */
  POM_AF_MEASURE_DISTANCE = 1,  /* per limb pair: distance of the segments joint a -> joint b */
  POM_AF_MEASURE_AXIS_ANGLE = 2 /* per limb pair: angle between the axes of joint a */
} pom_af_measure;

/* ---- the evaluated (numeric) form, SI, fixed frame at home ---------------- */
typedef struct {
  pom_joint_type type; /* R, P, U or S */
  int actuated;        /* 1 for the limb's one actuated joint */
  double point[3];     /* joint centre at home (m); P: a point on its axis */
  double axis[3];      /* unit; R: hinge, P: slide (+ = extension), U: fixed in the body before
                          it; zero for S */
  double axis2[3];     /* U: unit, fixed in the body after it, normal to axis; else zero */
} pom_af_joint_num;

typedef struct {
  pom_af_body_model model;
  /* rigid */
  double from[3];   /* m: the CM rule's start point */
  double dir[3];    /* unit: the offset direction (OFFSET) */
  double to[3];     /* m: the fraction's end point (FRACTION) */
  double axis[3];   /* unit principal z axis */
  double x_axis[3]; /* unit principal x axis; zero = the default (pom_kin_limb_axes) */
  /* arc */
  double arc_from[3], arc_to[3]; /* unit axes through O the arc joins */
  double radius;                 /* m */
  double mass_at[3];             /* point mass position (m) */
  double mass_axis[3];           /* unit axis of its axial inertia, zero when none */
} pom_af_body_num;

typedef struct {
  double azimuth;            /* eta of the limb (rad) */
  double er[3];              /* (cos eta, sin eta, 0) */
  pom_af_joint_num joint[3]; /* base to platform */
  pom_af_body_num body[2];   /* between joints 1-2 and 2-3 */
  int branch;                /* +1, -1, or 0 = the IK root through the home configuration */
} pom_af_limb_num;

typedef struct {
  pom_af_limb_num limb[3];
} pom_af_geometry;

/* ---- the description ------------------------------------------------------- */
typedef struct {
  pom_expr e;
  int line;       /* line of its key in the file */
  char key[96];   /* its key, "limbs.joints.[0].point" */
  char text[128]; /* the expression as written (shortened), for messages */
} pom_af_expr;

typedef struct {
  char name[POM_AF_NAME_LEN];
  pom_af_expr value;
  int slot;
} pom_af_let;

typedef struct {
  char name[POM_MECH_NAME_LEN];
  pom_joint_type type;
  int actuated;
  pom_af_expr point, axis, axis2; /* axis: R, P, U; axis2: U (else not compiled) */
} pom_af_joint;

typedef struct {
  char name[POM_AF_NAME_LEN]; /* body name (limb number appended in the mechanism) */
  pom_af_body_model model;
  char group[POM_AF_NAME_LEN]; /* rigid: the inertia group */
  pom_af_cm_rule cm;           /* rigid */
  int has_x_axis;
  int value_density, value_section; /* arc: indices into the inertia values */
  int value_mass, value_axial;      /* arc point mass: value indices, -1 = none */
} pom_af_body;

typedef struct {
  pom_af_expr azimuth;
  int n_lets;
  pom_af_let let[POM_AF_MAX_LETS];
  pom_af_joint joint[3];
  /* body expressions (per body: from, dir/to, axis, x_axis; arc: from, to, radius, at, axis) */
  pom_af_expr body_from[2], body_to[2], body_axis[2], body_x[2], body_radius[2], body_at[2],
      body_mass_axis[2];
  int branch;
  int n_slots; /* doubles of variable values this table needs */
} pom_af_limb_table;

typedef struct {
  pom_af_measure measure;
  int frame_platform;   /* cone: 1 = in the platform frame */
  int joint_a, joint_b; /* 0-based joints */
} pom_af_limit;

typedef struct pom_arch_file {
  pom_kin_arch_type type; /* first member: arch->type casts back to the file's description */
  char path[512];
  char name[64], label[64], description[256], unreachable[256];
  int n_refs;
  char refs[POM_AF_MAX_REFS][256];
  char scale_key[64], scale_meaning[256], scale_symbol[POM_AF_NAME_LEN];
  pom_kin_param_desc params[POM_KIN_MAX_PARAMS];
  char param_key[POM_KIN_MAX_PARAMS][64], param_meaning[POM_KIN_MAX_PARAMS][256];
  char param_symbol[POM_KIN_MAX_PARAMS][POM_AF_NAME_LEN], param_source[POM_KIN_MAX_PARAMS][256];
  pom_kin_value_desc values[POM_KIN_MAX_INERTIA_VALUES];
  char value_key[POM_KIN_MAX_INERTIA_VALUES][64], value_meaning[POM_KIN_MAX_INERTIA_VALUES][256];
  pom_kin_inertia_body_desc inertia_bodies[2];
  char limit_name[POM_KIN_LIM_KINDS][48], limit_key[POM_KIN_LIM_KINDS][64];
  char limit_json[POM_KIN_LIM_KINDS][64];
  pom_af_limit limit[POM_KIN_LIM_KINDS]; /* [1..3] */
  pom_af_central central;
  int n_globals;
  pom_af_let global[POM_AF_MAX_LETS];
  int global_slots; /* slots used by the parameters, the scale and the globals */
  int per_limb;     /* 0: one table for the three limbs (C3 symmetry); 1: one table per limb */
  pom_af_limb_table limb[3]; /* [per_limb ? 3 : 1] */
  pom_af_body body[2];
} pom_arch_file;

/* Loads and checks an architecture file into a new description (*out,
 * owned by the caller). Every error names file, line, key and value
 * (POM_ERR_CONFIG); a design-independent check (types, names, joint kinds,
 * exactly one actuated joint of the declared kind per limb) is done here,
 * the design-dependent ones in pom_arch_file_eval. type.from_design is set;
 * the numerics' operations are not (pom_arch_file_numerics). */
pom_status pom_arch_file_load(pom_arch_file **out, const char *path, pom_error *err);

/* Frees; NULL is allowed. */
void pom_arch_file_destroy(pom_arch_file *f);

/* Evaluates the description at design d (d->scale in m, d->x SI in the
 * order of the parameters) into g. POM_ERR_ARG naming file, line, key,
 * expression and limb when a value is not finite, an axis is zero, or a
 * universal joint's axes are not normal to each other. Never allocates. */
pom_status pom_arch_file_eval(const pom_arch_file *f, const pom_kin_design *d, pom_af_geometry *g,
                              pom_error *err);

/* The description of a type built by pom_arch_file_load, NULL for any other
 * (the hand-coded built-ins). */
const pom_arch_file *pom_arch_file_of(const pom_kin_arch_type *t);

/* ---- discovery -------------------------------------------------------------- */
/* Folder of the shipped catalog: $POMLAB_CATALOG when set, else the
 * installed PREFIX/share/pomlab/catalog beside the running program
 * (PREFIX/bin), else the source tree's catalog/ (a build tree); NULL when
 * none exists. The string is static storage of the calling thread. */
const char *pom_arch_catalog_dir(void);

/* Calls fn for every "*.arch" file of folder dir, in name order (at most
 * 64); stops at the first failure and returns it. */
pom_status pom_arch_catalog_each(const char *dir,
                                 pom_status (*fn)(const char *path, void *user, pom_error *err),
                                 void *user, pom_error *err);

/* The architecture files of a process: those of the catalog folder
 * catalog_dir (NULL: none) and those named by `extra` (NULL or ""; a
 * ':'-separated list of files and folders, as $POMLAB_ARCHITECTURES),
 * loaded in that order into set (at most POM_AF_MAX_FILES; the caller
 * frees them with pom_arch_file_set_free). A name given twice is refused,
 * naming both files. */
#define POM_AF_MAX_FILES 64
typedef struct {
  int n;
  pom_arch_file *file[POM_AF_MAX_FILES];
} pom_arch_file_set;

pom_status pom_arch_file_set_load(pom_arch_file_set *set, const char *catalog_dir,
                                  const char *extra, pom_error *err);
void pom_arch_file_set_free(pom_arch_file_set *set);

#endif
