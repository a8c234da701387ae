/* pom_view.h - the library behind `pomlab view` (docs/view.md): one
 * self-contained HTML page (three.js inlined) showing mechanisms, a maneuver
 * and a workspace; the scene it draws (a maneuver's trace read and sampled
 * into platform rotations and a pointing error, the dexterity of pointing
 * directions and the regular dexterous workspace's outline); and pictures of
 * the page (headless Chromium screenshots, ffmpeg films). It never prints or
 * exits: failures come back as a pom_status with a message. The program
 * (cli/cmd_view.c) parses the options and calls it; a test draws an
 * architecture registered outside the library (tests/test_arch_registry.c).
 * The page's script and style are view/viewer.js and view/viewer.css,
 * embedded at build time (view/embed.cmake). */
#ifndef POM_VIEW_H
#define POM_VIEW_H

#include "pom_capability.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

#include <stddef.h>

#include <stdio.h>

#define POM_VIEW_MAX_MECHS  16  /* mechanisms side by side (--compare) */
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

/* The pointing directions coloured by a capability figure of the pose
 * (pom_capability.h, pom_cap_pose_figure) instead of the dexterity: values
 * on the workspace grid sampled every stride_tilt-th tilt and
 * stride_azimuth-th azimuth (the page colours each direction by the nearest
 * sample), NaN where not evaluated (not usable, or the evaluation failed). */
typedef struct {
  const char *name, *unit, *description;
  const char *joints; /* the small-signal figures' model, "rigid" or "parasitic"; NULL for
                         the envelope's (rigid joints) */
  int stride_tilt, stride_azimuth; /* of the workspace grid */
  int n_tilt, n_azimuth;           /* the samples */
  const double *value;             /* [n_tilt][n_azimuth] display units */
  double lo, hi;                   /* range of the finite values (NaN: none) */
  int n_evaluated, n_failed;       /* samples evaluated, and failed */
} pom_view_capability;

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
  const pom_view_capability *capability; /* NULL: coloured by dexterity */
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

/* ---- the scene: a maneuver's trace ------------------------------------------------ */
/* A trace written by `pomlab simulate ... --out FILE.h5` (trace/t, q, voltage,
 * quat; the metric `target` of its metrics group when present). */
typedef struct {
  int n; /* samples in the file */
  double *t, *q, *voltage, *quat;
  double target[3];
  int has_target;
  char name[256]; /* the file's attribute `name` (the mechanism), "" when absent */
} pom_view_trace_file;

/* Reads path into tf (freed by pom_view_trace_file_free, also after a
 * failure). POM_ERR_IO / POM_ERR_NOMEM with a message naming the file. */
pom_status pom_view_trace_file_read(pom_view_trace_file *tf, const char *path, pom_error *err);
void pom_view_trace_file_free(pom_view_trace_file *tf);

/* The page's frames of a trace: at most POM_VIEW_MAX_FRAMES samples spread
 * evenly, platform rotations from the quaternions, the pointing error against
 * the target's orientation (forward kinematics of the setpoints through arch;
 * the last sample's when they are unknown or that fails, and then `warning`
 * says why). */
typedef struct {
  int n;
  double t[POM_VIEW_MAX_FRAMES], R[9 * POM_VIEW_MAX_FRAMES], q[3 * POM_VIEW_MAX_FRAMES];
  double u[3 * POM_VIEW_MAX_FRAMES], err[POM_VIEW_MAX_FRAMES];
  char warning[1100]; /* "" or why the target's orientation is unknown */
} pom_view_frames;

/* Samples tf (n >= 1) at min(tf->n, max_frames) frames into fr and points vt
 * at them; source is the file shown on the page. */
void pom_view_trace_sample(pom_view_frames *fr, const pom_view_trace_file *tf,
                           const pom_kin_arch *arch, int max_frames, pom_view_trace *vt,
                           const char *source);

/* ---- the scene: the workspace ----------------------------------------------------- */
#define POM_VIEW_WS_TILT_STEPS 30 /* tilt 0 .. 90 deg in 3 deg steps */
#define POM_VIEW_WS_AZIMUTHS   73 /* azimuth 0 .. 360 deg in 5 deg steps, both ends */
#define POM_VIEW_WS_OUTLINE    16 /* outline points per side of the Euler square */

/* The storage of a pom_view_workspace. */
typedef struct {
  double dex[(POM_VIEW_WS_TILT_STEPS + 1) * POM_VIEW_WS_AZIMUTHS];
  int state[(POM_VIEW_WS_TILT_STEPS + 1) * POM_VIEW_WS_AZIMUTHS];
  double outline[3 * 4 * POM_VIEW_WS_OUTLINE];
} pom_view_ws_grid;

/* Pointing directions on a tilt-and-torsion grid, R = Rz(a) Ry(t) Rz(-a)
 * (direction (sin t cos a, sin t sin a, cos t)), coloured by dexterity and
 * state (ws->check_limits), and the regular dexterous workspace of
 * pom_kin_workspace(arch, ws) outlined; w points into g. */
pom_status pom_view_workspace_compute(const pom_kin_arch *arch, const pom_kin_ws_opts *ws,
                                      pom_view_ws_grid *g, pom_view_workspace *w, pom_error *err);

/* The storage of a pom_view_capability. */
typedef struct {
  double value[(POM_VIEW_WS_TILT_STEPS + 1) * POM_VIEW_WS_AZIMUTHS];
} pom_view_cap_grid;

/* The figure `f` at the usable directions of w (state 0) sampled with the
 * strides (1, 1 for the envelope; 2, 3 = 6 and 15 deg for the small-signal
 * figures, ~70 ms a pose), on the models of p (pom_cap_ctx_create); c points
 * into g and w->capability at c. Fails as pom_cap_ctx_create. */
pom_status pom_view_capability_compute(const pom_kin_arch *arch, const pom_mechanism *mech,
                                       const pom_dyn_params *p, const pom_cap_opts *o,
                                       const pom_cap_pose_figure *f, pom_view_workspace *w,
                                       pom_view_cap_grid *g, pom_view_capability *c,
                                       pom_error *err);

/* ---- pictures: headless Chromium and ffmpeg (docs/view.md section 5) -------------- */
/* The first of names (NULL-terminated) found in PATH, or names[k] itself
 * when it holds a slash, into buf; 0 when found, -1 otherwise. */
int pom_view_find_program(const char *const *names, char *buf, size_t cap);

/* $POM_CHROMIUM when set, else chromium, chromium-browser or google-chrome
 * in PATH; 0 when found. */
int pom_view_find_chromium(char *buf, size_t cap);

/* Opens url (file://...) in headless Chromium with software WebGL, w x h
 * pixels, and writes its screenshot to png (an absolute path); scratch files
 * (dom.html, chromium.log) go to tmpdir. POM_OK when the page finished
 * drawing without a script error; else POM_ERR_IO with a message naming
 * `what` (and the log, which the caller must keep). */
pom_status pom_view_screenshot(const char *chromium, const char *url, const char *png, int w, int h,
                               const char *tmpdir, const char *what, pom_error *err);

/* The film of the n_frames frames of the page html (absolute path) into mp4
 * (absolute path): w x h frames at fps, drawn by Chromium in tiled batches
 * (#tiles=...) and cut and encoded by ffmpeg (untile, libx264). POM_ERR_IO
 * with a message (and a log in tmpdir) on failure. */
pom_status pom_view_mp4(const char *chromium, const char *ffmpeg, const char *html, const char *mp4,
                        int n_frames, int w, int h, int fps, const char *tmpdir, pom_error *err);

/* path made absolute (realpath: it must exist), and an output path made
 * absolute through its folder (the file need not exist); 0 ok, -1 with
 * errno set. */
int pom_view_abs_path(const char *path, char *buf, size_t cap);
int pom_view_abs_output(const char *path, char *buf, size_t cap);

/* POM_OK when a file can be created in the folder of `path` (an absolute
 * output path): a probe file is made there and removed. Else POM_ERR_IO
 * naming `what`, the folder and the reason (a read-only folder, one that
 * does not exist). */
pom_status pom_view_check_writable(const char *path, const char *what, pom_error *err);

/* Removes the scratch files of pom_view_screenshot and pom_view_mp4 (at most
 * `batches` film batches) and the folder dir. */
void pom_view_remove_tmpdir(const char *dir, int batches);

#endif
