/* cmd_view.c - `pomlab view CFG -o F.html`: the mechanism in 3-D in one
 * self-contained HTML page, at home or a pose, a simulated maneuver
 * (--trace), the workspace (--workspace), several architectures side by side
 * (--compare); pictures of it by headless Chromium (--png) and a film by
 * ffmpeg (--mp4). The program parses and reports; the page, its scene and
 * the pictures are the library view/ (pom_view.h). docs/view.md. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include "cli_kin.h"
#include "cli_opts.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_io.h"
#include "pom_kinematics.h"
#include "pom_math.h"
#include "pom_view.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

/* The workspace's directions coloured by the capability figure f: the
 * config's dynamics and capability groups read again; the exit status. */
static int capability(const char *path, const view_model *vm, const pom_cap_pose_figure *f,
                      pom_view_workspace *w, pom_view_cap_grid *g, pom_view_capability *c) {
  pom_error err;
  pom_error_clear(&err);
  pom_cfg *cfg = pom_cli_load_config(path);
  if (!cfg) return 2;
  pom_dyn_params par;
  pom_cap_opts o;
  pom_dyn_params_defaults(&par);
  pom_status st = pom_dyn_params_load(&par, cfg, &err);
  if (st == POM_OK) st = pom_cap_load(&o, cfg, &err);
  pom_cfg_destroy(cfg);
  if (st != POM_OK) {
    pom_cli_report("view: --capability: config", &err);
    return pom_cli_exit_code(st);
  }
  st = pom_view_capability_compute(&vm->arch, &vm->mech, &par, &o, f, w, g, c, &err);
  if (st != POM_OK) {
    pom_cli_report("view: --capability", &err);
    return 1;
  }
  if (c->n_failed)
    fprintf(stderr,
            "pomlab view: warning: --capability %s: %d of %d directions failed (left pale)\n",
            f->name, c->n_failed, c->n_failed + c->n_evaluated);
  return 0;
}

/* ---- the command -------------------------------------------------------------------- */
static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* Prints the library's failure as "pomlab view: <context>: <message>";
 * returns 1. */
static int fail(const char *context, const pom_error *err) {
  fprintf(stderr, "pomlab view: %s%s%s\n", context, context[0] ? ": " : "", err->message);
  return 1;
}

int pom_cmd_view(int argc, char **argv) {
  const char *cfg_path = NULL, *out = NULL, *pose_text = NULL, *trace_path = NULL;
  const char *png = NULL, *mp4 = NULL, *size_text = NULL, *cap_figure = NULL;
  const char *compare[POM_VIEW_MAX_MECHS];
  int n_compare = 0, workspace = 0, frame = 0, fps = 25, max_frames = POM_VIEW_MAX_FRAMES;
  const pom_opt opts[] = {
      {.name = "-o",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.html",
       .help = "the page (optional with --png or --mp4)",
       .text = &out},
      {.name = "--pose",
       .kind = POM_OPT_TEXT,
       .arg = "psi,theta,phi",
       .unit = "deg",
       .help = "platform orientation, ZYX Euler angles (default: home)",
       .text = &pose_text},
      {.name = "--trace",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.h5",
       .help = "animate a maneuver written by `pomlab simulate ... --out FILE.h5`: time slider, "
               "play, actuator positions, voltages and pointing error plotted beside",
       .text = &trace_path},
      {.name = "--frame",
       .kind = POM_OPT_INT,
       .arg = "N",
       .help = "frame of the trace shown first (default 0; -1 = last)",
       .ival = &frame,
       .lo = -1,
       .hi = 1000000},
      {.name = "--frames",
       .kind = POM_OPT_INT,
       .arg = "N",
       .help = "frames of the trace kept, evenly spread (default 400): the film's length at --fps",
       .ival = &max_frames,
       .lo = 2,
       .hi = POM_VIEW_MAX_FRAMES},
      {.name = "--workspace",
       .kind = POM_OPT_FLAG,
       .help = "pointing directions coloured by dexterity, the regular dexterous workspace "
               "outlined (workspace group of CONFIG)",
       .flag = &workspace,
       .set = 1},
      {.name = "--capability",
       .kind = POM_OPT_TEXT,
       .arg = "FIGURE",
       .help = "with the workspace: pointing directions coloured by a capability figure of the "
               "pose instead of the dexterity: acc_inscribed, rate_inscribed, rate_emf_inscribed "
               "(rigid joints, every direction), bw_worst, pm_min, mode (the config's "
               "joints.model, every 6 deg of tilt and 15 deg of azimuth; seconds) "
               "(docs/capability.md)",
       .text = &cap_figure},
      {.name = "--compare",
       .kind = POM_OPT_LIST,
       .arg = "CFG2 ...",
       .help = "more configs drawn side by side at the same orientation",
       .list = compare,
       .count = &n_compare,
       .hi = POM_VIEW_MAX_MECHS - 1},
      {.name = "--png",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.png",
       .help = "a picture of the page by headless Chromium",
       .text = &png},
      {.name = "--mp4",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.mp4",
       .help = "the maneuver as a film (needs --trace, Chromium, ffmpeg)",
       .text = &mp4},
      {.name = "--size",
       .kind = POM_OPT_TEXT,
       .arg = "WxH",
       .unit = "pixels",
       .help = "picture or film size (default 1200x800; 640x480 for --mp4)",
       .text = &size_text},
      {.name = "--fps",
       .kind = POM_OPT_INT,
       .arg = "N",
       .help = "film frame rate (default 25)",
       .ival = &fps,
       .lo = 1,
       .hi = 240},
  };
  const pom_cli_spec spec = {
      .name = "view",
      .usage = "CONFIG [options] -o FILE.html",
      .about = "One self-contained HTML page (three.js inlined, no network needed) showing the\n"
               "resolved mechanism in 3-D: every body drawn from its architecture's shapes,\n"
               "joints marked by type, actuator axes, the base frame and O; orbit, zoom, reset.",
      .notes =
          "Chromium: $POM_CHROMIUM, else chromium in PATH (Debian package chromium);\n"
          "three.js: $POM_THREE_JS, else /usr/share/javascript/three/three.min.js (libjs-three).\n"
          "Exit status: 0 ok; 1 a pose that cannot be assembled, a trace that cannot be\n"
          "read, Chromium or ffmpeg missing or failing, an output folder that cannot be\n"
          "written; 2 usage or config error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &cfg_path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!cfg_path || (!out && !png && !mp4)) {
    fprintf(stderr, "pomlab view: %s\n\n", !cfg_path ? "missing CONFIG" : "missing -o FILE.html");
    pom_cli_opts_usage(&spec, stderr);
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
  const pom_cap_pose_figure *cap_fig = NULL;
  if (cap_figure) {
    cap_fig = pom_cap_pose_figure_find(cap_figure);
    if (!cap_fig) {
      int nf;
      const pom_cap_pose_figure *t = pom_cap_pose_figures(&nf);
      fprintf(stderr, "pomlab view: --capability: unknown figure '%s'; one of:", cap_figure);
      for (int k = 0; k < nf; ++k)
        fprintf(stderr, "%s %s", k ? "," : "", t[k].name);
      fprintf(stderr, "\n");
      return 2;
    }
    workspace = 1;
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
      int prc2 =
          pom_job_check_output("view", cfg_path, outputs[k], "the page or picture", stderr, NULL);
      if (prc2) return prc2;
    }
  /* what the pictures need, before any work: Chromium, ffmpeg, and folders
   * they can write to (Chromium's own failure there names no file) */
  pom_error err;
  pom_error_clear(&err);
  char chromium[PATH_MAX], ffmpeg[PATH_MAX], png_abs[PATH_MAX], mp4_abs[PATH_MAX];
  const char *shots[2] = {png, mp4}, *shot_opt[2] = {"--png", "--mp4"};
  char *shot_abs[2] = {png_abs, mp4_abs};
  for (int k = 0; k < 2; ++k) {
    if (!shots[k]) continue;
    if (pom_view_abs_output(shots[k], shot_abs[k], PATH_MAX) != 0) {
      fprintf(stderr, "pomlab view: cannot resolve the folder of '%s': %s\n", shots[k],
              strerror(errno));
      return 1;
    }
    if (pom_view_check_writable(shot_abs[k], shot_opt[k], &err) != POM_OK) return fail("", &err);
  }
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

  int rc = 0, keep_tmp = 0;
  view_model *models = calloc((size_t)(1 + n_compare), sizeof *models);
  pom_view_trace_file tf;
  memset(&tf, 0, sizeof tf);
  pom_view_frames *frames = NULL;
  pom_view_ws_grid *grid = NULL;
  pom_view_cap_grid cap_grid;
  pom_view_capability vcap;
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
    if (pom_view_trace_file_read(&tf, trace_path, &err) != POM_OK) {
      rc = fail("--trace", &err);
      goto done;
    }
    if (tf.name[0] && strcmp(tf.name, models[0].arch.name) != 0)
      fprintf(stderr,
              "pomlab view: warning: the trace '%s' was simulated for '%s', the config is '%s': "
              "the bodies follow the config's kinematics\n",
              trace_path, tf.name, models[0].arch.name);
    pom_view_trace_sample(frames, &tf, &models[0].arch, max_frames, &vtrace, trace_path);
    if (frames->warning[0]) fprintf(stderr, "pomlab view: warning: %s\n", frames->warning);
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
    if (pom_view_workspace_compute(&models[0].arch, &models[0].ws, grid, &vws, &err) != POM_OK) {
      pom_cli_report("view: --workspace", &err);
      rc = 1;
      goto done;
    }
    page.workspace = &vws;
    if (cap_fig) {
      rc = capability(cfg_path, &models[0], cap_fig, &vws, &cap_grid, &vcap);
      if (rc) goto done;
    }
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
  char html_abs[PATH_MAX], url[PATH_MAX + 64];
  if ((png || mp4) && pom_view_abs_path(page_path, html_abs, sizeof html_abs) != 0) {
    fprintf(stderr, "pomlab view: cannot resolve '%s': %s\n", page_path, strerror(errno));
    rc = 1;
    goto done;
  }
  if (png) {
    snprintf(url, sizeof url, "file://%s#frame=%d", html_abs, page.frame);
    st = pom_view_screenshot(chromium, url, png_abs, w, h, tmpdir, "--png", &err);
  }
  if (mp4 && st == POM_OK)
    st = pom_view_mp4(chromium, ffmpeg, html_abs, mp4_abs, vtrace.n, w, h, fps, tmpdir, &err);
  if (st != POM_OK) {
    /* the log named in the message stays for the user to read */
    keep_tmp = 1;
    rc = fail("", &err);
    fprintf(stderr, "pomlab view: the scratch folder %s is kept for diagnosis\n", tmpdir);
  }
done:
  if (tmpdir[0] && !keep_tmp) pom_view_remove_tmpdir(tmpdir, POM_VIEW_MAX_FRAMES);
  pom_view_trace_file_free(&tf);
  free(frames);
  free(grid);
  free(models);
  return rc;
}
