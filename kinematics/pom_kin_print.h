/* pom_kin_print.h - the kinematics' own data as text and JSON: the resolved
 * mechanism at home (`pomlab model`), the registered architectures
 * (`pomlab model --list-architectures`), the limits of an evaluated pose
 * (`pomlab ik`, `pomlab fk`). Generic over the architecture: its type's
 * tables name every value (pom_arch.h). The caller chooses the stream. */
#ifndef POM_KIN_PRINT_H
#define POM_KIN_PRINT_H

#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_progress.h"

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

/* `pomlab ik`: the pose p evaluated at ZYX Euler angles e_deg (deg), st and
 * message its evaluation's status, as JSON (SI) or text (display units). */
void pom_kin_ik_report(FILE *out, int json, const char *config, const pom_kin_arch *arch,
                       const double e_deg[3], const pom_kin_pose *p, pom_status st,
                       const char *message);

/* `pomlab fk`: the orientation R solved from the actuator coordinates q_disp
 * (display units) with info, the pose p there and its limit status lst
 * (message), as JSON (SI) or text. */
void pom_kin_fk_report(FILE *out, int json, const char *config, const pom_kin_arch *arch,
                       const double q_disp[3], const double R[9], const pom_kin_fk_info *info,
                       const pom_kin_pose *p, pom_status lst, const char *message);

/* `pomlab ik --all` (e_deg non-NULL: the working modes at ZYX Euler angles
 * e_deg) and `pomlab fk --all` (q_disp non-NULL: the assembly modes at the
 * actuator coordinates q_disp, display units, found from `seeds` starts per
 * working mode): modes[0..n) (pom_kin_inverse_all, pom_kin_forward_all) as
 * JSON (SI) or a text table (display units). */
void pom_kin_modes_report(FILE *out, int json, const char *config, const pom_kin_arch *arch,
                          const double e_deg[3], const double q_disp[3], int seeds,
                          const pom_kin_mode *modes, int n);

/* ---- the workspace (kin_ws_print.c) ---------------------------------------------- */
/* Why the regular dexterous workspace ends where it does: the search cap or
 * budget, "not assemblable", the limit violated, or the dexterity there. */
const char *pom_kin_ws_reason_text(const pom_kin_arch *arch, const pom_kin_ws_result *r,
                                   const pom_kin_ws_opts *o, char *buf, size_t cap);

/* Poses per second of this machine on this architecture, from a 8^3 grid of
 * poses within 4 deg of home (a few milliseconds). */
double pom_kin_pose_rate(const pom_kin_arch *arch);

/* The dexterity map over the cube of half-width o->map_half_width, step
 * o->map_resolution, as CSV (psi_deg, theta_deg, phi_deg, reachable,
 * within_limits, dexterity, q1..q3 in the display unit, violations); bar
 * counts the poses. */
pom_status pom_kin_ws_map_write(const char *file, const pom_kin_arch *arch,
                                const pom_kin_ws_opts *o, pom_progress *bar, pom_error *err);

/* What `pomlab workspace` reports besides the search's result. */
typedef struct {
  const char *config;    /* the config's path, shown */
  const char *map;       /* the map written, or NULL */
  double gci;            /* global conditioning index */
  double gci_half_width; /* over this cube (rad) */
  double gci_usable;     /* the fraction of its poses that are usable */
} pom_kin_ws_report;

/* The workspace report as JSON (SI angles in deg as keyed) or text. */
void pom_kin_ws_report_print(FILE *out, int json, const pom_kin_arch *arch,
                             const pom_kin_ws_opts *o, const pom_kin_ws_result *r,
                             const pom_kin_ws_report *rep);

#endif
