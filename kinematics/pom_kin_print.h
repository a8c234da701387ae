/* pom_kin_print.h - the kinematics' own data as text and JSON: the resolved
 * mechanism at home (`pomlab model`), the registered architectures
 * (`pomlab model --list-architectures`), the limits of an evaluated pose
 * (`pomlab ik`, `pomlab fk`). Generic over the architecture: its type's
 * tables name every value (pom_arch.h). The caller chooses the stream. */
#ifndef POM_KIN_PRINT_H
#define POM_KIN_PRINT_H

#include "pom_kinematics.h"
#include "pom_mechanism.h"

#include <stdio.h>

/* The members "geometry", "limits" and "mechanism" of a JSON object (SI; no
 * surrounding braces, no trailing comma), or the same as text (mm, deg). */
void pom_kin_mechanism_json(FILE *out, const pom_kin_arch *a, const pom_mechanism *m);
void pom_kin_mechanism_text(FILE *out, const pom_kin_arch *a, const pom_mechanism *m);

/* Every registered architecture: name, actuator kind, scale, design
 * parameters (synthesis variables marked) and limits. */
void pom_kin_arch_list(FILE *out, int json);

/* Limb-wise limit details (human form) of an evaluated pose. */
void pom_kin_print_limits(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p);

/* The limit/pose fields of p as JSON members (no braces, leading comma-free;
 * the caller adds separators). */
void pom_kin_pose_json(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p);

#endif
