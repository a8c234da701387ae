/* cli_view.h - the page of `pomlab view`: one self-contained HTML file
 * (three.js inlined) showing mechanisms, a maneuver and a workspace
 * (docs/view.md). CLI code: it writes a file; it never prints or exits.
 * Built as its own small library (pom_view) so that a test can draw an
 * architecture registered outside the library (tests/test_arch_registry.c). */
#ifndef POM_CLI_VIEW_H
#define POM_CLI_VIEW_H

#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

#include <stdio.h>

#define POM_VIEW_MAX_MECHS  8   /* mechanisms side by side (--compare) */
#define POM_VIEW_MAX_FRAMES 400 /* frames of an animation kept in a page */

/* One mechanism on the page. */
typedef struct {
  const char *label;         /* shown with it (the config name or path) */
  const pom_kin_arch *arch;  /* its architecture instance */
  const pom_mechanism *mech; /* built from arch (pom_kin_mechanism_from) */
} pom_view_mech;

/* A maneuver of the first mechanism, sampled at n frames. */
typedef struct {
  int n;                        /* frames (1 .. POM_VIEW_MAX_FRAMES) */
  const double *t;              /* [n] time (s) */
  const double *R;              /* [n][9] platform rotation, row-major */
  const double *q;              /* [n][3] actuator coordinates (m or rad) */
  const double *voltage;        /* [n][3] coil voltages (V) */
  const double *pointing_error; /* [n] angle between the platform normal R e_z and the
                                   target's (rad) */
  double target[3];             /* actuator setpoints (m or rad) */
  const char *source;           /* the trace file, shown on the page */
} pom_view_trace;

/* Pointing directions n = R e_z of the platform on a tilt x azimuth grid
 * (torsion 0) with the dexterity there, and the regular dexterous
 * workspace's outline. */
typedef struct {
  int n_tilt, n_azimuth;   /* grid size: tilt k * tilt_step, azimuth j * 360 / (n_azimuth - 1) */
  double tilt_step;        /* rad */
  const double *dexterity; /* [n_tilt][n_azimuth] 1/kappa (0 when unreachable) */
  const int *state;        /* [n_tilt][n_azimuth] 0 usable, 1 reachable but outside a limit,
                              2 not assemblable */
  int n_outline;           /* points of the outline (0: no regular dexterous workspace) */
  const double *outline;   /* [n_outline][3] unit pointing directions around it */
  double rdw_half_width;   /* its half-width (rad), -1 when home fails */
  double dexterity_min;    /* the threshold it was found with */
} pom_view_workspace;

/* Everything on one page. */
typedef struct {
  const char *title;
  int n_mechs;                            /* 1 .. POM_VIEW_MAX_MECHS */
  pom_view_mech mech[POM_VIEW_MAX_MECHS]; /* side by side, first at the left */
  double R[9];                            /* platform rotation shown without a trace */
  double euler_deg[3];                    /* the same as ZYX Euler angles (deg), shown */
  const pom_view_trace *trace;            /* NULL: no animation */
  const pom_view_workspace *workspace;    /* NULL: no workspace */
  int frame;                              /* frame shown first (clamped to the trace) */
  const char *three_path;                 /* three.min.js to inline; NULL: pom_view_three_path() */
} pom_view_page;

/* Where three.js is looked for: $POM_THREE_JS when set, else Debian's
 * /usr/share/javascript/three/three.min.js (package libjs-three). */
const char *pom_view_three_path(void);

/* Writes the page to out. POM_ERR_IO with a message naming the file when
 * three.js cannot be read; POM_ERR_UNREACHABLE when the pose shown cannot be
 * assembled (a trace frame that cannot keeps the previous frame's bodies);
 * POM_ERR_ARG for a malformed page. */
pom_status pom_view_write(FILE *out, const pom_view_page *page, pom_error *err);

#endif
