/* cmd_view.c - `pomlab view CFG -o F.html`: the mechanism in 3-D in one
 * self-contained HTML page, at home or a pose, a simulated maneuver
 * (--trace), the workspace (--workspace), several architectures side by side
 * (--compare); pictures of it by headless Chromium (--png) and a film by
 * ffmpeg (--mp4). docs/view.md. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include "cli_kin.h"
#include "pom_job.h"
#include "cli_view.h"
#include "cli_view_shot.h"
#include "pom_arch.h"
#include "pom_cli.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_h5.h"
#include "pom_io.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void view_usage(FILE *out) {
  fprintf(out,
          "usage: pomlab view CONFIG [options] -o FILE.html\n\n"
          "One self-contained HTML page (three.js inlined, no network needed) showing the\n"
          "resolved mechanism in 3-D: every body drawn from its architecture's shapes,\n"
          "joints marked by type, actuator axes, the base frame and O; orbit, zoom, reset.\n\n"
          "  -o FILE.html          the page (optional with --png or --mp4)\n"
          "  --pose psi,theta,phi  platform orientation, ZYX Euler angles in degrees\n"
          "                        (default: home)\n"
          "  --trace FILE.h5       animate a maneuver written by `pomlab simulate ... --out\n"
          "                        FILE.h5`: time slider, play, actuator positions, voltages\n"
          "                        and pointing error plotted beside\n"
          "  --frame N             frame of the trace shown first (default 0; -1 = last)\n"
          "  --frames N            frames of the trace kept, evenly spread (2 to 400,\n"
          "                        default 400): the film's length at --fps\n"
          "  --workspace           pointing directions coloured by dexterity, the regular\n"
          "                        dexterous workspace outlined (workspace group of CONFIG)\n"
          "  --compare CFG2 ...    more configs drawn side by side at the same orientation\n"
          "  --png FILE.png        a picture of the page by headless Chromium\n"
          "  --mp4 FILE.mp4        the maneuver as a film (needs --trace, Chromium, ffmpeg)\n"
          "  --size WxH            picture or film size in pixels (default 1200x800;\n"
          "                        640x480 for --mp4)\n"
          "  --fps N               film frame rate (default 25)\n"
          "  --help                this text\n\n"
          "Chromium: $POM_CHROMIUM, else chromium in PATH (Debian package chromium);\n"
          "three.js: $POM_THREE_JS, else /usr/share/javascript/three/three.min.js (libjs-three).\n"
          "Exit status: 0 ok; 1 a pose that cannot be assembled, a trace that cannot be\n"
          "read, Chromium or ffmpeg missing or failing; 2 usage or config error.\n");
}

/* ---- one config ----------------------------------------------------------------- */
typedef struct {
  char label[128];
  pom_kin_arch arch;
  pom_kin_ws_opts ws;
  pom_mechanism mech;
} view_model;

static int load_model(const char *path, view_model *vm) {
  pom_cfg *cfg = NULL;
  int rc = pom_cli_kin_load(path, &cfg, &vm->arch, &vm->ws, NULL);
  if (rc) return rc;
  pom_error err;
  pom_error_clear(&err);
  pom_status st = pom_kin_mechanism_build(&vm->mech, &vm->arch, cfg, &err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    pom_cli_report("view: config", &err);
    return pom_cli_exit_code(st);
  }
  const char *slash = strrchr(path, '/');
  snprintf(vm->label, sizeof vm->label, "%s", slash ? slash + 1 : path);
  return 0;
}

/* ---- the trace ------------------------------------------------------------------ */
typedef struct {
  int n; /* samples in the file */
  double *t, *q, *voltage, *quat;
  double target[3];
  int has_target;
} trace_file;

static void trace_free(trace_file *tf) {
  free(tf->t);
  free(tf->q);
  free(tf->voltage);
  free(tf->quat);
  memset(tf, 0, sizeof *tf);
}

/* Rows of dataset `name` of g with `cols` columns; -1 when absent or shaped
 * otherwise. */
static long dataset_rows(hid_t g, const char *name, int cols) {
  if (!pom_h5_exists(g, name)) return -1;
  hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t s = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  int rank = s >= 0 ? H5Sget_simple_extent_ndims(s) : -1;
  if (rank >= 1 && rank <= 2) H5Sget_simple_extent_dims(s, dims, NULL);
  if (s >= 0) H5Sclose(s);
  H5Dclose(d);
  if (rank == 1 && cols == 1) return (long)dims[0];
  if (rank == 2 && (int)dims[1] == cols) return (long)dims[0];
  return -1;
}

/* Reads the trace of `pomlab simulate --out FILE.h5`; warns when the file
 * names another mechanism than `name` (the config's). */
static int read_trace(const char *path, const char *name, trace_file *tf) {
  pom_error err;
  pom_error_clear(&err);
  hid_t file = -1, g = -1, m = -1;
  int rc = 1;
  memset(tf, 0, sizeof *tf);
  if (pom_h5_open_file(&file, path, 0, &err) != POM_OK) {
    pom_cli_report("view: --trace", &err);
    return 1;
  }
  if (pom_h5_open_group(&g, file, "trace", &err) != POM_OK) {
    fprintf(stderr,
            "pomlab view: --trace '%s' has no group 'trace' (write it with pomlab simulate "
            "CONFIG --target ... --out FILE.h5)\n",
            path);
    goto done;
  }
  char stored[256];
  pom_error nerr;
  pom_error_clear(&nerr);
  if (pom_h5_read_attr_string(file, "name", stored, sizeof stored, &nerr) == POM_OK &&
      strcmp(stored, name) != 0)
    fprintf(stderr,
            "pomlab view: warning: the trace '%s' was simulated for '%s', the config is '%s': "
            "the bodies follow the config's kinematics\n",
            path, stored, name);
  long n = dataset_rows(g, "t", 1);
  if (n < 1 || dataset_rows(g, "q", 3) != n || dataset_rows(g, "voltage", 3) != n ||
      dataset_rows(g, "quat", 4) != n) {
    fprintf(stderr,
            "pomlab view: --trace '%s': trace/t, q, voltage and quat must exist with the same "
            "number of rows (quat with 4 columns)\n",
            path);
    goto done;
  }
  tf->n = (int)n;
  size_t un = (size_t)n;
  tf->t = malloc(un * sizeof *tf->t);
  tf->q = malloc(3 * un * sizeof *tf->q);
  tf->voltage = malloc(3 * un * sizeof *tf->voltage);
  tf->quat = malloc(4 * un * sizeof *tf->quat);
  if (!tf->t || !tf->q || !tf->voltage || !tf->quat) {
    fprintf(stderr, "pomlab view: no memory for the trace of %ld samples\n", n);
    goto done;
  }
  if (pom_h5_read_doubles(g, "t", un, tf->t, &err) != POM_OK ||
      pom_h5_read_doubles(g, "q", 3 * un, tf->q, &err) != POM_OK ||
      pom_h5_read_doubles(g, "voltage", 3 * un, tf->voltage, &err) != POM_OK ||
      pom_h5_read_doubles(g, "quat", 4 * un, tf->quat, &err) != POM_OK) {
    pom_cli_report("view: --trace", &err);
    goto done;
  }
  /* the setpoints: the metric `target` of the file's metrics group */
  if (pom_h5_exists(file, "metrics") && pom_h5_open_group(&m, file, "metrics", &err) == POM_OK) {
    char key[96];
    pom_dyn_metric_json_key(pom_dyn_metric(POM_DYN_METRIC_target), key, sizeof key);
    if (H5Aexists(m, key) > 0) {
      hid_t a = H5Aopen(m, key, H5P_DEFAULT);
      if (a >= 0) {
        hid_t s = H5Aget_space(a);
        if (s >= 0 && H5Sget_simple_extent_npoints(s) == 3 &&
            H5Aread(a, H5T_NATIVE_DOUBLE, tf->target) >= 0)
          tf->has_target = 1;
        if (s >= 0) H5Sclose(s);
        H5Aclose(a);
      }
    }
  }
  rc = 0;
done:
  if (m >= 0) H5Gclose(m);
  if (g >= 0) H5Gclose(g);
  pom_error cerr;
  pom_error_clear(&cerr);
  pom_h5_close_file(file, &cerr);
  if (rc) trace_free(tf);
  return rc;
}

/* The page's frames: at most POM_VIEW_MAX_FRAMES samples spread evenly,
 * platform rotations from the quaternions, the pointing error against the
 * target's orientation (forward kinematics of the setpoints; the last
 * sample's when they are unknown or it fails). */
typedef struct {
  int n;
  double t[POM_VIEW_MAX_FRAMES], R[9 * POM_VIEW_MAX_FRAMES], q[3 * POM_VIEW_MAX_FRAMES];
  double u[3 * POM_VIEW_MAX_FRAMES], err[POM_VIEW_MAX_FRAMES];
} trace_frames;

static void sample_trace(trace_frames *fr, const trace_file *tf, const pom_kin_arch *arch,
                         int max_frames, pom_view_trace *vt, const char *source) {
  int m = tf->n < max_frames ? tf->n : max_frames;
  fr->n = m;
  double Rlast[9], Rt[9];
  double qn[4];
  memcpy(qn, tf->quat + 4 * (tf->n - 1), sizeof qn);
  pom_quat_to_matrix(Rlast, qn);
  memcpy(Rt, Rlast, sizeof Rt);
  if (tf->has_target) {
    pom_error err;
    pom_error_clear(&err);
    if (pom_kin_forward(arch, tf->target, Rlast, NULL, Rt, NULL, &err) != POM_OK) {
      fprintf(stderr,
              "pomlab view: warning: the target's orientation is unknown (%s): the "
              "pointing error is measured from the last sample\n",
              err.message);
      memcpy(Rt, Rlast, sizeof Rt);
    }
  }
  const double nt[3] = {Rt[2], Rt[5], Rt[8]};
  for (int k = 0; k < m; ++k) {
    long i = m > 1 ? lround((double)k * (tf->n - 1) / (m - 1)) : 0;
    double qq[4];
    memcpy(qq, tf->quat + 4 * i, sizeof qq);
    double nq = sqrt(qq[0] * qq[0] + qq[1] * qq[1] + qq[2] * qq[2] + qq[3] * qq[3]);
    for (int a = 0; a < 4; ++a)
      qq[a] = nq > 0.0 ? qq[a] / nq : (a == 0);
    double *R = fr->R + 9 * k;
    pom_quat_to_matrix(R, qq);
    fr->t[k] = tf->t[i];
    for (int a = 0; a < 3; ++a) {
      fr->q[3 * k + a] = tf->q[3 * i + a];
      fr->u[3 * k + a] = tf->voltage[3 * i + a];
    }
    const double n[3] = {R[2], R[5], R[8]};
    fr->err[k] = pom_kin_angle_between(n, nt);
  }
  memset(vt, 0, sizeof *vt);
  vt->n = m;
  vt->t = fr->t;
  vt->R = fr->R;
  vt->q = fr->q;
  vt->voltage = fr->u;
  vt->pointing_error = fr->err;
  for (int a = 0; a < 3; ++a)
    vt->target[a] = tf->has_target ? tf->target[a] : tf->q[3 * (tf->n - 1) + a];
  vt->source = source;
}

/* ---- the workspace ---------------------------------------------------------------- */
#define WS_TILT_STEPS 30 /* tilt 0 .. 90 deg in 3 deg steps */
#define WS_AZIMUTHS   73 /* azimuth 0 .. 360 deg in 5 deg steps, both ends */
#define WS_OUTLINE    16 /* outline points per side of the Euler square */

typedef struct {
  double dex[(WS_TILT_STEPS + 1) * WS_AZIMUTHS];
  int state[(WS_TILT_STEPS + 1) * WS_AZIMUTHS];
  double outline[3 * 4 * WS_OUTLINE];
} ws_grid;

/* Tilt-and-torsion grid: R = Rz(a) Ry(t) Rz(-a), pointing direction
 * (sin t cos a, sin t sin a, cos t); the RDW by pom_kin_workspace. */
static int compute_workspace(const view_model *vm, ws_grid *g, pom_view_workspace *w) {
  memset(w, 0, sizeof *w);
  w->n_tilt = WS_TILT_STEPS + 1;
  w->n_azimuth = WS_AZIMUTHS;
  w->tilt_step = 0.5 * POM_PI / WS_TILT_STEPS;
  for (int it = 0; it < w->n_tilt; ++it)
    for (int ia = 0; ia < w->n_azimuth; ++ia) {
      double t = it * w->tilt_step, a = 2.0 * POM_PI * ia / (w->n_azimuth - 1);
      double e1[3] = {a, t, 0.0}, e2[3] = {-a, 0.0, 0.0}, R1[9], R2[9], R[9];
      pom_euler_zyx_to_matrix(R1, e1); /* Rz(a) Ry(t) */
      pom_euler_zyx_to_matrix(R2, e2); /* Rz(-a) */
      pom_m3_mul(R, R1, R2);
      pom_kin_pose pose;
      pom_kin_pose_evaluate(&vm->arch, R, &pose, NULL);
      int k = it * w->n_azimuth + ia;
      g->dex[k] = pose.reachable ? pose.dexterity : 0.0;
      g->state[k] = !pose.reachable ? 2 : (vm->ws.check_limits && pose.violations) ? 1 : 0;
    }
  w->dexterity = g->dex;
  w->state = g->state;
  w->dexterity_min = vm->ws.dexterity_min;
  pom_kin_ws_result res;
  pom_error err;
  pom_error_clear(&err);
  if (pom_kin_workspace(&vm->arch, &vm->ws, &res, &err) != POM_OK) {
    pom_cli_report("view: --workspace", &err);
    return 1;
  }
  w->rdw_half_width = res.half_width;
  w->outline = g->outline;
  if (res.half_width > 0.0) {
    /* the square |theta|, |phi| <= a at psi = 0, walked round */
    double a = res.half_width;
    const double corner[5][2] = {{-a, -a}, {a, -a}, {a, a}, {-a, a}, {-a, -a}};
    int n = 0;
    for (int side = 0; side < 4; ++side)
      for (int k = 0; k < WS_OUTLINE; ++k) {
        double f = (double)k / WS_OUTLINE;
        double e[3] = {0.0, corner[side][0] + f * (corner[side + 1][0] - corner[side][0]),
                       corner[side][1] + f * (corner[side + 1][1] - corner[side][1])};
        double R[9];
        pom_euler_zyx_to_matrix(R, e);
        g->outline[3 * n] = R[2];
        g->outline[3 * n + 1] = R[5];
        g->outline[3 * n + 2] = R[8];
        ++n;
      }
    w->n_outline = n;
  }
  return 0;
}

/* ---- the command -------------------------------------------------------------------- */
static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

int pom_cmd_view(int argc, char **argv) {
  const char *cfg_path = NULL, *out = NULL, *pose_text = NULL, *trace_path = NULL;
  const char *png = NULL, *mp4 = NULL, *size_text = NULL;
  const char *compare[POM_VIEW_MAX_MECHS];
  int n_compare = 0, workspace = 0, frame = 0, fps = 25, max_frames = POM_VIEW_MAX_FRAMES;
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k];
    int has = k + 1 < argc;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      view_usage(stdout);
      return 0;
    } else if (strcmp(a, "-o") == 0 && has) {
      out = argv[++k];
    } else if (strcmp(a, "--pose") == 0 && has) {
      pose_text = argv[++k];
    } else if (strcmp(a, "--trace") == 0 && has) {
      trace_path = argv[++k];
    } else if (strcmp(a, "--frame") == 0 && has) {
      char *end;
      long v = strtol(argv[++k], &end, 10);
      if (*end || v < -1 || v > 1000000) {
        fprintf(stderr, "pomlab view: --frame expects a whole number >= -1, got '%s'\n", argv[k]);
        return 2;
      }
      frame = (int)v;
    } else if (strcmp(a, "--frames") == 0 && has) {
      char *end;
      long v = strtol(argv[++k], &end, 10);
      if (*end || v < 2 || v > POM_VIEW_MAX_FRAMES) {
        fprintf(stderr, "pomlab view: --frames expects a whole number in [2, %d], got '%s'\n",
                POM_VIEW_MAX_FRAMES, argv[k]);
        return 2;
      }
      max_frames = (int)v;
    } else if (strcmp(a, "--workspace") == 0) {
      workspace = 1;
    } else if (strcmp(a, "--compare") == 0 && has) {
      while (k + 1 < argc && argv[k + 1][0] != '-') {
        if (n_compare + 1 >= POM_VIEW_MAX_MECHS) {
          fprintf(stderr, "pomlab view: --compare takes at most %d configs\n",
                  POM_VIEW_MAX_MECHS - 1);
          return 2;
        }
        compare[n_compare++] = argv[++k];
      }
    } else if (strcmp(a, "--png") == 0 && has) {
      png = argv[++k];
    } else if (strcmp(a, "--mp4") == 0 && has) {
      mp4 = argv[++k];
    } else if (strcmp(a, "--size") == 0 && has) {
      size_text = argv[++k];
    } else if (strcmp(a, "--fps") == 0 && has) {
      char *end;
      long v = strtol(argv[++k], &end, 10);
      if (*end || v < 1 || v > 240) {
        fprintf(stderr, "pomlab view: --fps expects a whole number in [1, 240], got '%s'\n",
                argv[k]);
        return 2;
      }
      fps = (int)v;
    } else if (a[0] != '-' && !cfg_path) {
      cfg_path = a;
    } else {
      fprintf(stderr, "pomlab view: unknown or incomplete option '%s'\n\n", a);
      view_usage(stderr);
      return 2;
    }
  }
  if (!cfg_path || (!out && !png && !mp4)) {
    fprintf(stderr, "pomlab view: %s\n\n", !cfg_path ? "missing CONFIG" : "missing -o FILE.html");
    view_usage(stderr);
    return 2;
  }
  if (out && !ends_with(out, ".html")) {
    fprintf(stderr, "pomlab view: -o must end in .html, got '%s'\n", out);
    return 2;
  }
  if (png && !ends_with(png, ".png")) {
    fprintf(stderr, "pomlab view: --png must end in .png, got '%s'\n", png);
    return 2;
  }
  if (mp4 && !ends_with(mp4, ".mp4")) {
    fprintf(stderr, "pomlab view: --mp4 must end in .mp4, got '%s'\n", mp4);
    return 2;
  }
  if (mp4 && !trace_path) {
    fprintf(stderr, "pomlab view: --mp4 films a maneuver: give it --trace FILE.h5\n");
    return 2;
  }
  if (trace_path && pose_text) {
    fprintf(stderr, "pomlab view: --pose and --trace exclude each other (the trace sets the "
                    "pose)\n");
    return 2;
  }
  int w = mp4 && !png ? 640 : 1200, h = mp4 && !png ? 480 : 800;
  if (size_text) {
    char x;
    if (sscanf(size_text, "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 64 || h < 64 || w > 4096 ||
        h > 4096 || (mp4 && (w % 2 || h % 2))) {
      fprintf(stderr,
              "pomlab view: --size expects WxH in pixels, 64 to 4096 (even for --mp4), "
              "got '%s'\n",
              size_text);
      return 2;
    }
  }
  double euler[3] = {0.0, 0.0, 0.0};
  if (pose_text && pom_cli_parse_list(pose_text, 3, euler) != 0) {
    fprintf(stderr, "pomlab view: --pose expects three angles in degrees, 'psi,theta,phi'\n");
    return 2;
  }
  const char *outputs[3] = {out, png, mp4};
  for (int k = 0; k < 3; ++k)
    if (outputs[k]) {
      int prc =
          pom_job_check_output("view", cfg_path, outputs[k], "the page or picture", stderr, NULL);
      if (prc) return prc;
    }
  /* what the pictures need, before any work */
  char chromium[PATH_MAX], ffmpeg[PATH_MAX];
  if ((png || mp4) && pom_view_find_chromium(chromium, sizeof chromium) != 0) {
    fprintf(stderr,
            "pomlab view: --png and --mp4 need Chromium to draw the page: '%s' was not "
            "found (install Debian's chromium, or set POM_CHROMIUM to the browser)%s\n",
            getenv("POM_CHROMIUM") && getenv("POM_CHROMIUM")[0] ? getenv("POM_CHROMIUM")
                                                                : "chromium",
            out ? "; nothing written" : "");
    return 1;
  }
  const char *const ff[] = {"ffmpeg", NULL};
  if (mp4 && pom_view_find_program(ff, ffmpeg, sizeof ffmpeg) != 0) {
    fprintf(stderr, "pomlab view: --mp4 needs ffmpeg to encode the film: 'ffmpeg' was not found "
                    "in PATH (install Debian's ffmpeg); nothing written\n");
    return 1;
  }

  int rc = 0;
  view_model *models = calloc((size_t)(1 + n_compare), sizeof *models);
  trace_file tf;
  memset(&tf, 0, sizeof tf);
  trace_frames *frames = NULL;
  ws_grid *grid = NULL;
  pom_view_trace vtrace;
  pom_view_workspace vws;
  pom_view_page page;
  memset(&page, 0, sizeof page);
  memset(&vtrace, 0, sizeof vtrace);
  char tmpdir[PATH_MAX] = "";
  if (!models) {
    fprintf(stderr, "pomlab view: out of memory\n");
    return 1;
  }
  for (int k = 0; k <= n_compare && rc == 0; ++k)
    rc = load_model(k ? compare[k - 1] : cfg_path, &models[k]);
  if (rc) goto done;
  page.title = models[0].arch.name[0] ? models[0].arch.name : models[0].label;
  page.n_mechs = 1 + n_compare;
  for (int k = 0; k < page.n_mechs; ++k) {
    page.mech[k].label = models[k].label;
    page.mech[k].arch = &models[k].arch;
    page.mech[k].mech = &models[k].mech;
  }
  memcpy(page.euler_deg, euler, sizeof euler);
  for (int a = 0; a < 3; ++a)
    euler[a] *= POM_DEG;
  pom_euler_zyx_to_matrix(page.R, euler);
  if (trace_path) {
    frames = calloc(1, sizeof *frames);
    if (!frames) {
      rc = 1;
      goto done;
    }
    rc = read_trace(trace_path, models[0].arch.name, &tf);
    if (rc) goto done;
    sample_trace(frames, &tf, &models[0].arch, max_frames, &vtrace, trace_path);
    page.trace = &vtrace;
    page.frame = frame < 0 || frame >= vtrace.n ? vtrace.n - 1 : frame;
    if (frame >= vtrace.n)
      fprintf(stderr, "pomlab view: warning: --frame %d beyond the %d frames: showing the last\n",
              frame, vtrace.n);
    /* the other mechanisms at the first frame's orientation */
    memcpy(page.R, vtrace.R, sizeof page.R);
  }
  if (workspace) {
    grid = calloc(1, sizeof *grid);
    if (!grid) {
      rc = 1;
      goto done;
    }
    rc = compute_workspace(&models[0], grid, &vws);
    if (rc) goto done;
    page.workspace = &vws;
  }

  /* the page: -o, or a temporary one for the pictures */
  const char *tmp_base = getenv("TMPDIR");
  snprintf(tmpdir, sizeof tmpdir, "%s/pomlab-view-XXXXXX",
           tmp_base && tmp_base[0] ? tmp_base : "/tmp");
  if ((png || mp4) && !mkdtemp(tmpdir)) {
    fprintf(stderr, "pomlab view: cannot create a temporary folder %s: %s\n", tmpdir,
            strerror(errno));
    tmpdir[0] = '\0';
    rc = 1;
    goto done;
  }
  if (!(png || mp4)) tmpdir[0] = '\0';
  char page_path[PATH_MAX + 16];
  if (out)
    snprintf(page_path, sizeof page_path, "%s", out);
  else
    snprintf(page_path, sizeof page_path, "%s/page.html", tmpdir);
  pom_error err;
  pom_error_clear(&err);
  pom_io_file wf;
  pom_status st = pom_io_create(&wf, page_path, &err);
  if (st == POM_OK) {
    st = pom_view_write(wf.f, &page, &err);
    if (st == POM_OK)
      st = pom_io_commit(&wf, &err);
    else
      pom_io_abort(&wf);
  }
  if (st != POM_OK) {
    pom_cli_report("view", &err);
    rc = st == POM_ERR_UNREACHABLE ? 1 : pom_cli_exit_code(st);
    goto done;
  }
  char html_abs[PATH_MAX], url[PATH_MAX + 64], target[PATH_MAX];
  if ((png || mp4) && pom_view_abs_path(page_path, html_abs, sizeof html_abs) != 0) {
    fprintf(stderr, "pomlab view: cannot resolve '%s': %s\n", page_path, strerror(errno));
    rc = 1;
    goto done;
  }
  if (png) {
    snprintf(url, sizeof url, "file://%s#frame=%d", html_abs, page.frame);
    if (pom_view_abs_output(png, target, sizeof target) != 0) {
      fprintf(stderr, "pomlab view: cannot resolve the folder of '%s': %s\n", png, strerror(errno));
      rc = 1;
      goto done;
    }
    rc = pom_view_screenshot(chromium, url, target, w, h, tmpdir, "--png");
    if (rc) goto done;
  }
  if (mp4) {
    if (pom_view_abs_output(mp4, target, sizeof target) != 0) {
      fprintf(stderr, "pomlab view: cannot resolve the folder of '%s': %s\n", mp4, strerror(errno));
      rc = 1;
      goto done;
    }
    rc = pom_view_mp4(chromium, ffmpeg, html_abs, target, vtrace.n, w, h, fps, tmpdir);
  }
done:
  if (tmpdir[0]) pom_view_remove_tmpdir(tmpdir, POM_VIEW_MAX_FRAMES);
  trace_free(&tf);
  free(frames);
  free(grid);
  free(models);
  return rc;
}
