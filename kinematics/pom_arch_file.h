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
#include "pom_limb.h"
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
  pom_joint_type type;
  int actuated;
  pom_af_expr point, axis, axis2; /* axis: R, P, U; axis2: U, optional (else not compiled) */
  int has_axis2;
} pom_af_joint;

/* One limb table: the three limbs' (C3 form) or one limb's (list form). */
typedef struct {
  pom_af_expr azimuth;
  int n_lets;
  pom_af_let let[POM_AF_MAX_LETS];
  pom_af_joint joint[3];
  int has_motor;
  pom_af_expr motor; /* where the actuator sits at home (the footprint), optional */
  double branch;     /* +1, -1, or 0 = the IK root through home */
} pom_af_limb_table;

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
  pom_kin_inertia_body_desc inertia_bodies[POM_LIMB_BODIES];
  char body_group[POM_LIMB_BODIES][POM_AF_NAME_LEN];
  char limit_name[POM_KIN_LIM_KINDS][48], limit_key[POM_KIN_LIM_KINDS][64];
  char limit_json[POM_KIN_LIM_KINDS][64];
  int limit_line[POM_KIN_LIM_KINDS]; /* line of limits.[k - 1].measure (messages) */
  pom_af_central central;
  /* the design-independent part of the numeric table: bodies, joint names,
   * limit measures, central joint (pom_arch_file_eval adds the limbs) */
  pom_limb_table table;
  int has_arc_radius;
  pom_af_expr arc_radius; /* radius of the arc bodies (m), global scope */
  int n_globals;
  pom_af_let global[POM_AF_MAX_LETS];
  int global_slots; /* slots used by the parameters, the scale and the globals */
  int per_limb;     /* 0: one table for the three limbs (C3 symmetry); 1: one table per limb */
  pom_af_limb_table limb[3]; /* [per_limb ? 3 : 1] */
} pom_arch_file;

/* Loads and checks an architecture file into a new description (*out,
 * owned by the caller). Every error names file, line, key and value
 * (POM_ERR_CONFIG); a design-independent check (types, names, joint kinds,
 * exactly one actuated joint of the declared kind per limb) is done here,
 * the design-dependent ones in pom_arch_file_eval (and the kernel's in the
 * numerics' finish). type.from_design, data_size and the descriptors are
 * set; the other operations are not: pom_limb_type_ops
 * (kinematics/pom_limb.h) fills them before pom_kin_arch_register. */
pom_status pom_arch_file_load(pom_arch_file **out, const char *path, pom_error *err);

/* Frees; NULL is allowed. */
void pom_arch_file_destroy(pom_arch_file *f);

/* Evaluates the description at design d (d->scale in m, d->x SI in the
 * order of the parameters) into the numeric table t: the design-independent
 * part (bodies, joint names, limit measures, central joint, the arc radius)
 * and every limb's input fields (joints, actuated joint, branch, motor); the
 * fields finish derives are zero. POM_ERR_ARG naming file, line, key,
 * expression and limb when a value is not finite, an axis is zero, or a
 * universal joint's axes are not normal to each other. Never allocates.
 * The type's from_design is this into arch->data. */
pom_status pom_arch_file_eval(const pom_arch_file *f, const pom_kin_design *d, pom_limb_table *t,
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

/* ---- registration (kin_arch_file_register.c: needs the numerics,
 * kinematics/pom_limb.h) ------------------------------------------------------ */
/* Fills f's operations (pom_limb_type_ops) and registers its type
 * (pom_kin_arch_register: refused when the name is taken). f must outlive
 * every use of the registry. */
pom_status pom_arch_file_register(pom_arch_file *f, pom_error *err);

/* Registers, once per process, the files of pom_arch_catalog_dir() and of
 * $POMLAB_ARCHITECTURES (a ':'-separated list of files and folders), kept
 * for the process's lifetime; later calls do nothing. Call it before any
 * config names one of them and before any thread reads the registry. The
 * first failure names its file; the files registered before it stay. */
pom_status pom_arch_files_register_all(pom_error *err);

#endif
