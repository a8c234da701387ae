/* cmd_simulate.c - `pomlab simulate CFG --target q1,q2,q3`: one maneuver of
 * the configured mechanism; metrics on stdout, traces to HDF5 or CSV on
 * request (docs/dynamics.md section 10). */
#include "cli_kin.h"
#include "cli_opts.h"
#include "pom_job.h"
#include "pom_version.h"
#include "pom_cli.h"
#include "pom_io.h"
#include "pom_run.h"
#include "pom_dyn_print.h"
#include "pom_dyn_ctrl.h"
#include "pom_dyn_freq.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_dyn_params_schema.h"
#include "pom_dynamics.h"
#include "pom_h5.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* ---- cost of the traces ---------------------------------------------------- */
/* Doubles kept per trace sample: the trace (t, 6 x 3 actuator columns,
 * quaternion, deflection) and the maneuver's own q record. */
#define TRACE_DOUBLES_PER_SAMPLE 27.0
/* Bytes per sample in a CSV row (27 columns of up to 16 characters) and in
 * HDF5 (24 doubles). */
#define TRACE_CSV_BYTES 430.0
#define TRACE_H5_BYTES  192.0
/* Traces larger than this are announced before the simulation. */
#define TRACE_ANNOUNCE_BYTES 1e8

/* Refuses traces that cannot fit in memory (returns 2 after the message:
 * the size, the samples and the keys that set them), announces large ones
 * (samples, memory, file size); 0 when they may be made. */
static int check_trace_cost(const char *cfg_path, const pom_dyn_params *p, const char *out) {
  double samples = floor(p->maneuver.horizon / p->maneuver.output_dt) + 2.0;
  double memory = samples * TRACE_DOUBLES_PER_SAMPLE * sizeof(double);
  double file = samples * (ends_with(out, ".csv") ? TRACE_CSV_BYTES : TRACE_H5_BYTES);
  double limit = pom_doe_memory_limit();
  char mem[32], have[32], size[32];
  if (memory > limit) {
    fprintf(stderr,
            "pomlab simulate: config: %s: traces of %.4g samples (maneuver.horizon_ms = %.10g / "
            "maneuver.output_dt_ms = %.10g) need about %s of memory, more than this machine's %s: "
            "raise maneuver.output_dt_ms or shorten the horizon; nothing was run\n",
            cfg_path, samples, p->maneuver.horizon * 1e3, p->maneuver.output_dt * 1e3,
            pom_job_bytes_text(mem, sizeof mem, memory),
            pom_job_bytes_text(have, sizeof have, limit));
    return 2;
  }
  if (file > TRACE_ANNOUNCE_BYTES || memory > TRACE_ANNOUNCE_BYTES)
    fprintf(stderr,
            "pomlab simulate: traces of %.4g samples (maneuver.horizon_ms = %.10g / "
            "maneuver.output_dt_ms = %.10g): memory about %s, %s about %s\n",
            samples, p->maneuver.horizon * 1e3, p->maneuver.output_dt * 1e3,
            pom_job_bytes_text(mem, sizeof mem, memory), out,
            pom_job_bytes_text(size, sizeof size, file));
  return 0;
}

/* ---- --bode --------------------------------------------------------------- */
/* Bode data grid (Hz) and density of `--bode` */
#define BODE_F_LO       0.1
#define BODE_F_HI       1e5
#define BODE_PER_DECADE 40

/* The frequency response about the pose q (SI): the JSON into path, the
 * figures on stdout (text, or the same JSON with --json); the exit status. */
static int bode(const char *path, int json, const char *name, const pom_dyn_model *model,
                pom_dyn_data *data, const double q[3], const pom_act_desc *u) {
  pom_error err;
  pom_error_clear(&err);
  pom_dyn_freq_figures F;
  pom_status st = json ? POM_OK : pom_dyn_freq_figures_at(model, data, q, &F, &err);
  FILE *fp = st == POM_OK ? fopen(path, json ? "w+" : "w") : NULL;
  if (st == POM_OK && !fp)
    st = pom_error_set(&err, POM_ERR_IO, __FILE__, __LINE__, "cannot write '%s'", path);
  if (st == POM_OK)
    st = pom_dyn_freq_json(fp, model, data, q, BODE_F_LO, BODE_F_HI, BODE_PER_DECADE, &err);
  if (st == POM_OK && json) { /* the same JSON on stdout */
    char buf[4096];
    size_t got;
    rewind(fp);
    while ((got = fread(buf, 1, sizeof buf, fp)) > 0)
      fwrite(buf, 1, got, stdout);
  }
  if (fp && fclose(fp) != 0 && st == POM_OK)
    st = pom_error_set(&err, POM_ERR_IO, __FILE__, __LINE__, "cannot write '%s'", path);
  if (st != POM_OK) {
    pom_cli_report("simulate --bode", &err);
    return pom_cli_exit_code(st);
  }
  if (json) return 0;
  const double f = u->to_display;
  printf("%s: small-signal frequency response about q = (%.6g, %.6g, %.6g) %s\n", name, q[0] * f,
         q[1] * f, q[2] * f, u->display);
  printf("  bandwidth (-3 dB, setpoint rotation about x, y, z): %.4g, %.4g, %.4g Hz\n",
         F.bandwidth_hz[0], F.bandwidth_hz[1], F.bandwidth_hz[2]);
  printf("  worst direction: %.4g Hz along (%.3f, %.3f, %.3f)\n", F.bandwidth_worst_hz,
         F.worst_dir[0], F.worst_dir[1], F.worst_dir[2]);
  printf("  resonant peak: %.3g, %.3g, %.3g dB; any direction %.3g dB\n", F.peak_db[0],
         F.peak_db[1], F.peak_db[2], F.peak_db_worst);
  for (int a = 0; a < F.n_actuators; ++a)
    printf("  loop %d (broken at its voltage input): crossover %.5g Hz, phase margin %.3g deg, "
           "gain margin %.3g dB\n",
           a + 1, F.crossover_hz[a], F.phase_margin_deg[a], F.gain_margin_db[a]);
  printf("  closed loop %s; slowest pole %.4g Hz\n", F.stable ? "stable" : "UNSTABLE",
         F.slowest_pole_hz);
  printf("  parasitic modes above the band (Hz, damping ratio):");
  for (int k = 0; k < F.n_modes; ++k)
    printf("%s %.4g (%.3f)", k ? "," : "", F.mode_hz[k], F.mode_zeta[k]);
  printf("%s\n  Bode data: %s\n", F.n_modes ? "" : " none", path);
  return 0;
}

/* ---- command ------------------------------------------------------------- */
int pom_cmd_simulate(int argc, char **argv) {
  const char *cfg_path = NULL, *out_path = NULL, *target_text = NULL, *bode_path = NULL;
  const char *form = NULL, *orient = NULL, *linsol = NULL, *joints = NULL, *controller = NULL;
  const char *kp = NULL, *ki = NULL, *kd = NULL, *rtol = NULL;
  int json = 0;
  /* the options that set a config value go through the config's own checks,
   * in this order (pom_cli_opts_apply) */
  const pom_opt opts[] = {
      {.name = "--target",
       .kind = POM_OPT_TEXT,
       .arg = "q1,q2,q3",
       .unit = "mm or deg",
       .help = "setpoints from mid-stroke in the display unit of the mechanism's actuators "
               "(required): MILLIMETRES for prismatic actuators, DEGREES for revolute ones",
       .text = &target_text},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "machine-readable metrics on stdout",
       .flag = &json,
       .set = 1},
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "FILE",
       .help = "write traces: FILE.h5 (HDF5) or FILE.csv (SI units)",
       .text = &out_path},
      {.name = "--bode",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.json",
       .help = "instead of the maneuver: the small-signal frequency response of the closed loop "
               "about the pose --target (bandwidth per axis and worst, peaks, each actuator "
               "loop's margins, parasitic modes; docs/capability.md) in Hz, dB and deg, and its "
               "Bode data as JSON in FILE.json (scripts/plot_bode.py draws it)",
       .text = &bode_path},
      {.name = "--controller",
       .kind = POM_OPT_CHOICE,
       .arg = "NAME",
       .key = "controller.type",
       .help = "the controller (pomlab model --list-controllers)",
       .text = &controller},
      {.name = "--form",
       .kind = POM_OPT_CHOICE,
       .arg = "ideal|parallel",
       .key = "controller.form",
       .help = "the PID's form",
       .text = &form},
      {.name = "--joints",
       .kind = POM_OPT_CHOICE,
       .arg = "parasitic|rigid",
       .key = "joints.model",
       .help = "the joints' model",
       .text = &joints},
      {.name = "--orientation",
       .kind = POM_OPT_CHOICE,
       .arg = "euler|quaternion",
       .key = "scene.orientation",
       .help = "the platform's orientation coordinates",
       .text = &orient},
      {.name = "--linsol",
       .kind = POM_OPT_CHOICE,
       .arg = "dense|klu|structured",
       .key = "solver.linear_solver",
       .help = "the linear solver",
       .text = &linsol},
      {.name = "--kp",
       .kind = POM_OPT_NUMBER,
       .arg = "X",
       .unit = "V/V",
       .key = "controller.kp",
       .help = "proportional gain",
       .text = &kp},
      {.name = "--ki",
       .kind = POM_OPT_NUMBER,
       .arg = "X",
       .unit = "1/s",
       .key = "controller.ki_per_s",
       .help = "integral gain",
       .text = &ki},
      {.name = "--kd",
       .kind = POM_OPT_NUMBER,
       .arg = "X",
       .unit = "s",
       .key = "controller.kd_s",
       .help = "derivative gain",
       .text = &kd},
      {.name = "--rtol",
       .kind = POM_OPT_NUMBER,
       .arg = "X",
       .key = "solver.rtol",
       .help = "the solver's relative tolerance, in [1e-12, 0.1]",
       .text = &rtol},
  };
  const pom_cli_spec spec = {
      .name = "simulate",
      .usage = "CONFIG --target q1,q2,q3 [options]",
      .about = "One maneuver from rest at home (mid-stroke) to the three actuator setpoints.",
      .notes = "Text in the units of docs/conventions.md: times in ms, energies in J, lengths in\n"
               "mm, angles in deg, actuator coordinates in mm or deg (SI in --json and traces:\n"
               "m or rad, named by actuator_unit).\n"
               "Exit status: 0 ok; 1 the maneuver failed or the traces cannot be written;\n"
               "2 usage or config error (also a target outside the stroke).",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &cfg_path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  double target[3];
  if (!cfg_path || !target_text) {
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  if (pom_cli_parse_list(target_text, 3, target) != 0) {
    fprintf(stderr, "pomlab simulate: --target expects three numbers (mm or deg, the actuators' "
                    "display unit), 'q1,q2,q3'\n");
    return 2;
  }
  if (bode_path && (out_path || !ends_with(bode_path, ".json"))) {
    fprintf(stderr, "pomlab simulate: --bode expects a FILE.json and no --out, got '%s'\n",
            bode_path);
    return 2;
  }
  if (out_path && !ends_with(out_path, ".h5") && !ends_with(out_path, ".csv")) {
    fprintf(stderr, "pomlab simulate: --out must end in .h5 or .csv, got '%s'\n", out_path);
    return 2;
  }

  int rc = 1;
  pom_error err;
  pom_error_clear(&err);
  pom_dyn_model *model = NULL;
  pom_dyn_data *data = NULL;
  pom_dyn_trace *trace = NULL;
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_kin_arch arch;
  pom_dyn_params par;
  pom_dyn_metrics mt;
  pom_cfg *cfg = pom_cli_load_config(cfg_path);
  if (!cfg) rc = 2; /* a config that cannot be read is a config error */
  if (!cfg || !mech) goto done;
  /* the traces must not overwrite the config or a file it includes */
  int path_rc = bode_path ? pom_job_check_output("simulate", cfg_path, bode_path,
                                                 "the Bode data (--bode)", stderr, NULL)
                          : pom_job_check_output("simulate", cfg_path, out_path,
                                                 "the traces (--out)", stderr, NULL);
  if (path_rc) {
    rc = path_rc;
    goto done;
  }
  /* the options that set config keys, checked like the file's values */
  pom_status st = pom_cli_opts_apply(&spec, cfg, &err);
  if (st == POM_OK) st = pom_kin_arch_load(&arch, cfg, &err);
  if (st == POM_OK) st = pom_kin_mechanism_build(mech, &arch, cfg, &err);
  pom_dyn_params_defaults(&par);
  if (st == POM_OK) st = pom_dyn_params_load(&par, cfg, &err);
  /* every group simulate reads: the model's; unknown keys there are errors */
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_dyn_param_groups(), NULL};
  if (st == POM_OK) st = pom_cli_check_unknown(cfg, scopes, &err);
  pom_actuator_kind kind = POM_ACT_PRISMATIC;
  if (st == POM_OK) st = pom_doe_mech_actuator_kind(mech, &kind, &err);
  if (st != POM_OK) {
    pom_cli_report("simulate", &err);
    rc = pom_cli_exit_code(st);
    goto done;
  }
  /* display unit (mm or deg) -> SI (m or rad), once, at the edge */
  const pom_act_desc *u = pom_act_kind_desc(kind);
  for (int a = 0; a < 3; ++a)
    target[a] /= u->to_display;
  /* a target outside the stroke is a usage error, refused before any work */
  for (int a = 0; a < 3; ++a) {
    double half = 0.5 * arch.stroke;
    if (half > 0 && !(fabs(target[a]) <= half)) {
      fprintf(stderr,
              "pomlab simulate: --target q%d = %.10g %s is outside the stroke +-%.10g %s "
              "(limits.%s%s = %.10g)\n",
              a + 1, target[a] * u->to_display, u->display, half * u->to_display, u->display,
              u->range_word, u->key_suffix, arch.stroke * u->to_display);
      rc = 2;
      goto done;
    }
  }

  if (out_path && check_trace_cost(cfg_path, &par, out_path) != 0) {
    rc = 2;
    goto done;
  }
  st = pom_dyn_model_create(&model, mech, &arch, &par, &err);
  if (st == POM_OK) st = pom_dyn_data_create(&data, model, &err);
  if (st == POM_OK && out_path) st = pom_dyn_trace_create(&trace, model, &err);
  if (st != POM_OK) {
    pom_cli_report("simulate", &err);
    rc = pom_cli_exit_code(st);
    goto done;
  }
  if (bode_path) {
    rc = bode(bode_path, json, arch.name, model, data, target, u);
    goto done;
  }
  st = pom_dyn_simulate(model, data, target, &mt, trace, &err);
  if (json)
    pom_dyn_report_json(stdout, arch.name, &par, &mt, kind, 0.5 * arch.stroke);
  else
    pom_dyn_report_text(stdout, arch.name, &par, &mt, kind, 0.5 * arch.stroke);
  rc = st == POM_OK ? 0 : 1;
  if (st != POM_OK) pom_cli_report("simulate", &err);
  int beyond[3];
  if (pom_dyn_stroke_excursions(&mt, 0.5 * arch.stroke, beyond))
    fprintf(stderr,
            "pomlab simulate: warning: an actuator left its stroke +-%.10g %s (max |q| %.6g, "
            "%.6g, %.6g %s); the model has no end stops\n",
            0.5 * arch.stroke * u->to_display, u->display, mt.max_abs_q[0] * u->to_display,
            mt.max_abs_q[1] * u->to_display, mt.max_abs_q[2] * u->to_display, u->display);
  if (pom_dyn_rigid_limit_exceeded(&mt))
    fprintf(stderr,
            "pomlab simulate: warning: the parasitic model is not at its rigid limit "
            "(rigid_limit_ratio %.3g, above %g when the drive outruns the joints; "
            "joint_dissipation_share %.3g, above %g when the joints move on their own): its energy "
            "may be far from the rigid one; raise joints.stiffness_N_per_m or use joints.model = "
            "\"rigid\" (docs/dynamics.md section 13b)\n",
            mt.rigid_limit_ratio, POM_DYN_RIGID_LIMIT_WARN, mt.joint_dissipation_share,
            POM_DYN_JOINT_SHARE_WARN);
  double w_drive = 0.0, z_drive = 0.0;
  if (pom_dyn_drive_mode_light(model, &w_drive, &z_drive))
    fprintf(stderr,
            "pomlab simulate: warning: high loop gain: the drive mode (coil and controller "
            "loop) rings at %.3g rad/s with damping ratio %.3g (below 0.070): saturation "
            "switching makes the energy and settling times sensitive to the tolerance (energy "
            "errors up to ~3e4 x solver.rtol measured, docs/extremes.md); confirm with a tighter "
            "solver.rtol\n",
            w_drive, z_drive);
  if (trace && trace->n > 0) {
    pom_error werr;
    pom_error_clear(&werr);
    pom_status wst = ends_with(out_path, ".csv")
                         ? pom_dyn_trace_write_csv(out_path, trace, mt.target, kind, &werr)
                         : pom_dyn_trace_write_h5(out_path, "pomlab simulate " POM_VERSION, cfg,
                                                  arch.name, &par, trace, &mt, kind, &werr);
    if (wst != POM_OK) {
      pom_cli_report("simulate: writing traces", &werr);
      rc = 1;
    } else if (st != POM_OK) {
      /* kept for diagnosis, but never mistaken for a finished maneuver */
      fprintf(stderr,
              "pomlab simulate: '%s' holds the traces of the FAILED maneuver, up to t = %g ms\n",
              out_path, trace->t[trace->n - 1] * 1e3);
    }
  }
done:
  pom_dyn_trace_destroy(trace);
  pom_dyn_data_destroy(data);
  pom_dyn_model_destroy(model);
  pom_cfg_destroy(cfg);
  free(mech);
  return rc;
}
