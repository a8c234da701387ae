/* pom_mjcf.h - a mechanism (pom_mechanism.h) written as a MuJoCo MJCF model
 * (docs/export.md): its bodies with mass, centre of mass and inertia, its
 * joints as hinges, slides and balls (a universal joint as two hinges), the
 * limbs as a kinematic tree from the ground, equality constraints (connect)
 * closing the loops the tree leaves open, and the actuated joints as motors
 * with the coil's force or torque constant in their user data. SI units,
 * radians; every body frame parallel to the fixed frame at home, at its
 * centre of mass, so MuJoCo's qpos0 (all zero) is pomlab's home pose. */
#ifndef POM_MJCF_H
#define POM_MJCF_H

#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

#include <stdio.h>

/* The coil behind every motor (the config's actuator group): MuJoCo's
 * motor takes the force or torque itself as its control, ctrl = K i. */
typedef struct {
  double constant;      /* force constant K_m (N/A) or torque constant K_t (N m/A) */
  double resistance;    /* coil resistance (ohm) */
  double voltage_limit; /* amplifier's voltage limit (V): ctrlrange = +- K V / R */
} pom_mjcf_coil;

/* The spanning tree MJCF needs (docs/export.md section 2): the joints taken
 * slides and actuated joints first, then universal joints, hinges, balls
 * (each kind in index order), every joint that joins two parts kept, so
 * the loops close at balls where they can; the parents breadth first from
 * the ground. parent_joint[b] is the
 * joint that attaches body b to its parent (-1 for the ground), closes[j] is
 * 1 for a joint left out of the tree: a loop closure, written as equality
 * constraints. */
typedef struct {
  int parent[POM_MECH_MAX_BODIES];
  int parent_joint[POM_MECH_MAX_BODIES];
  int closes[POM_MECH_MAX_JOINTS];
  int n_closures;
} pom_mjcf_tree;

/* The tree of mech. POM_ERR_ARG when a body is not connected to the ground,
 * or a loop would close at a prismatic or an actuated joint (neither can be
 * an equality constraint of this export: the message names the joint). */
pom_status pom_mjcf_tree_build(const pom_mechanism *mech, pom_mjcf_tree *tree, pom_error *err);

/* Writes the MJCF model of arch's mechanism mech (pom_kin_mechanism_build)
 * to f: model name `name`, drawing geoms from pom_kin_body_shapes (no
 * contact), the coil in the motors' user data. Every write is checked:
 * POM_ERR_IO when one fails (the caller discards the file, pom_io_abort),
 * POM_ERR_ARG as pom_mjcf_tree_build or for duplicate body or joint names. */
pom_status pom_mjcf_write(FILE *f, const char *name, const pom_kin_arch *arch,
                          const pom_mechanism *mech, const pom_mjcf_coil *coil, pom_error *err);

#endif
