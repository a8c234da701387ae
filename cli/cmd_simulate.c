/* cmd_simulate.c - `pomlab simulate CFG --target q1,q2,q3`: one maneuver of
 * the configured mechanism; metrics on stdout, traces to HDF5 or CSV on
 * request (docs/dynamics.md section 10). */
#include "cli_kin.h"
#include "pom_job.h"
#include "pom_version.h"
#include "pom_cli.h"
#include "pom_io.h"
#include "pom_doe.h"
#include "cli_dyn.h"
#include "pom_doe_estimate.h"
#include "pom_dyn_ctrl.h"
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

static void simulate_usage(FILE *out) {
  fprintf(out,
          "usage: pomlab simulate CONFIG --target q1,q2,q3 [options]\n\n"
          "One maneuver from rest at home (mid-stroke) to the three actuator setpoints.\n\n"
          "  --target q1,q2,q3     setpoints from mid-stroke in the display unit of the\n"
          "                        mechanism's actuators (required): MILLIMETRES for\n"
          "                        prismatic actuators, DEGREES for revolute ones\n"
          "  --json                machine-readable metrics on stdout\n"
          "  --out FILE            write traces: FILE.h5 (HDF5) or FILE.csv (SI units)\n"
          "  --controller NAME     override controller.type (pomlab model --list-controllers)\n"
          "  --form ideal|parallel override controller.form (the PID)\n"
          "  --kp X --ki X --kd X  override controller.kp (V/V), ki_per_s (1/s), kd_s (s)\n"
          "  --orientation euler|quaternion   override scene.orientation\n"
          "  --linsol dense|klu|structured  override solver.linear_solver\n"
          "  --joints parasitic|rigid   override joints.model\n"
          "  --rtol X              override solver.rtol, in [1e-13, 0.1]\n"
          "  --help                this text\n\n"
          "Text in the units of docs/conventions.md: times in ms, energies in J, lengths in\n"
          "mm, angles in deg, actuator coordinates in mm or deg (SI in --json and traces:\n"
          "m or rad, named by actuator_unit).\n"
          "Exit status: 0 ok; 1 the maneuver failed or the traces cannot be written;\n"
          "2 usage or config error (also a target outside the stroke).\n");
}

/* ---- output -------------------------------------------------------------- */
static void json_num(FILE *f, const char *key, double v, const char *sep) {
  if (isfinite(v))
    fprintf(f, "  \"%s\": %.9g%s\n", key, v, sep);
  else
    fprintf(f, "  \"%s\": null%s\n", key, sep);
}

/* One metric's values (SI) under key: a number or an array of three. */
static void json_metric(FILE *f, const char *key, const pom_dyn_metrics *mt,
                        const pom_dyn_metric_info *mi, const char *sep) {
  fprintf(f, "  \"%s\": %s", key, mi->count > 1 ? "[" : "");
  for (int k = 0; k < mi->count; ++k) {
    double v = pom_dyn_metric_value(mt, mi, k);
    if (k) fputs(", ", f);
    if (!isfinite(v))
      fputs("null", f);
    else if (mi->type != POM_DYN_TYPE_DOUBLE)
      fprintf(f, "%.0f", v);
    else
      fprintf(f, "%.9g", v);
  }
  fprintf(f, "%s%s\n", mi->count > 1 ? "]" : "", sep);
}

/* Marks in out[] the actuators whose |q| went beyond half the stroke (half,
 * SI; 0 = not limited) on the output grid; returns how many did. The model
 * has no end stops, so such a maneuver is not physical (docs/dynamics.md
 * section 10). */
static int stroke_excursions(const pom_dyn_metrics *mt, double half, int out[3]) {
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    out[a] = half > 0 && mt->max_abs_q[a] > half;
    n += out[a];
  }
  return n;
}

/* Every metric of the schema (pom_dyn_metrics_schema.h) under its key, in SI
 * units; actuator coordinates in actuator_unit (m or rad). */
static void print_json(const char *name, const pom_dyn_params *p, const pom_dyn_metrics *mt,
                       pom_actuator_kind kind, double half_stroke) {
  FILE *f = stdout;
  const pom_act_desc *u = pom_act_kind_desc(kind);
  /* the name comes from the config and the reason may quote option values:
   * both escaped */
  fputs("{\n  \"name\": ", f);
  pom_json_string(f, name);
  fprintf(f, ",\n  \"status\": \"%s\",\n  \"reason\": ", pom_status_name(mt->status));
  pom_json_string(f, mt->reason);
  fputs(",\n", f);
  fprintf(f, "  \"controller\": {");
  pom_cli_ctrl_json_members(f, &p->controller);
  fprintf(f, "},\n");
  if (pom_dyn_ctrl_of(&p->controller) == &pom_dyn_ctrl_pid) /* the key before controller types */
    fprintf(f, "  \"controller_form\": \"%s\",\n", pom_dyn_pid_form_name(p->controller.form));
  fprintf(f,
          "  \"orientation\": \"%s\",\n"
          "  \"linear_solver\": \"%s\",\n  \"joints_model\": \"%s\",\n"
          "  \"actuator_kind\": \"%s\",\n  \"actuator_unit\": \"%s\",\n",
          pom_dyn_orient_name(p->scene.orientation), pom_dyn_linsol_name(p->solver.linear_solver),
          pom_dyn_joint_model_name(p->joints.model), u->kind_name, u->si);
  /* horizon_s comes with the metrics (the schema's `horizon`) */
  int out[3];
  stroke_excursions(mt, half_stroke, out);
  json_num(f, "half_stroke", half_stroke, ",");
  fprintf(f, "  \"stroke_exceeded\": [%s, %s, %s],\n", out[0] ? "true" : "false",
          out[1] ? "true" : "false", out[2] ? "true" : "false");
  /* the keys of prismatic mechanisms before actuator units existed */
  if (u->legacy_keys) {
    json_metric(f, "target_m", mt, pom_dyn_metric(POM_DYN_METRIC_target), ",");
    json_metric(f, "final_q_m", mt, pom_dyn_metric(POM_DYN_METRIC_final_q), ",");
  }
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    char key[96];
    json_metric(f, pom_dyn_metric_json_key(&schema[j], key, sizeof key), mt, &schema[j],
                j + 1 < POM_DYN_N_METRICS ? "," : "");
  }
  fprintf(f, "}\n");
}

/* The per-actuator metrics of the schema, one row each, in display units. */
static void print_actuator_table(const pom_dyn_metrics *mt, pom_actuator_kind kind) {
  printf("%-22s %-5s %12s %12s %12s\n", "metric", "unit", "actuator 1", "actuator 2", "actuator 3");
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    const pom_dyn_metric_info *mi = &schema[j];
    if (mi->count != 3) continue;
    double f = 1.0;
    const char *unit = pom_dyn_metric_display_unit(mi, kind, &f);
    printf("%-22s %-5s", mi->name, unit);
    for (int k = 0; k < 3; ++k) {
      double v = pom_dyn_metric_value(mt, mi, k);
      if (mi->type != POM_DYN_TYPE_DOUBLE)
        printf(" %12.0f", v);
      else
        printf(" %12.6g", v * f);
    }
    printf("\n");
  }
}

static void print_human(const char *name, const pom_dyn_params *p, const pom_dyn_metrics *mt,
                        pom_actuator_kind kind, double half_stroke) {
  const pom_act_desc *u = pom_act_kind_desc(kind);
  double f = u->to_display;
  char law[512];
  pom_dyn_ctrl_of(&p->controller)->describe(&p->controller, law, sizeof law);
  printf("%s: maneuver to (%.4g, %.4g, %.4g) %s, horizon %.4g ms, controller %s, orientation %s, "
         "linear solver %s, %s joints\n",
         name, mt->target[0] * f, mt->target[1] * f, mt->target[2] * f, u->display,
         p->maneuver.horizon * 1e3, law, pom_dyn_orient_name(p->scene.orientation),
         pom_dyn_linsol_name(p->solver.linear_solver), pom_dyn_joint_model_name(p->joints.model));
  if (mt->status != POM_OK) printf("status: %s (%s)\n", pom_status_name(mt->status), mt->reason);
  print_actuator_table(mt, kind);
  int out[3];
  if (stroke_excursions(mt, half_stroke, out))
    for (int a = 0; a < 3; ++a)
      if (out[a])
        printf("STROKE EXCEEDED: actuator %d reached |q| = %.6g %s, beyond the stroke +-%.10g %s "
               "(the model has no end stops: not a physical motion)\n",
               a + 1, mt->max_abs_q[a] * f, u->display, half_stroke * f, u->display);
  printf("execution time: %.3f ms%s\n", mt->execution_time * 1e3,
         isnan(mt->execution_time) ? " (an actuator did not settle: settled = 0)" : "");
  printf("expended energy: %.6g J (positive part %.6g J)\n", mt->energy_total,
         mt->energy_positive[0] + mt->energy_positive[1] + mt->energy_positive[2]);
  printf("energy audit: supplied %.6g J = dissipated %.6g J (coil %.4g, bearing %.4g, parasitic "
         "%.4g) + stored change %.6g J; balance error %.2e (relative, docs/dynamics.md "
         "section 6)\n",
         mt->energy_supplied, mt->energy_dissipated,
         mt->energy_coil[0] + mt->energy_coil[1] + mt->energy_coil[2],
         mt->energy_bearing[0] + mt->energy_bearing[1] + mt->energy_bearing[2],
         mt->energy_parasitic, mt->energy_stored_change, mt->energy_balance_error);
  printf("largest parasitic deflection: %.3g mm, %.3g deg\n", mt->max_deflection * 1e3,
         mt->max_angular_deflection / POM_DEG);
  printf("solver: %ld steps, %ld RHS evaluations (%ld in %ld Jacobians), %ld Newton iterations, "
         "%ld factorizations, %ld error-test and %ld convergence failures; %.3f ms wall\n",
         mt->steps, mt->rhs_evals, mt->jac_rhs_evals, mt->jac_evals, mt->newton_iters,
         mt->linsol_setups, mt->error_test_fails, mt->nonlin_conv_fails, mt->wall_time * 1e3);
}

/* ---- traces -------------------------------------------------------------- */
static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

static pom_status write_csv(const char *path, const pom_dyn_trace *tr, const double target[3],
                            pom_actuator_kind kind, pom_error *err) {
  pom_io_file w;
  POM_TRY(pom_io_create(&w, path, err));
  FILE *f = w.f;
  /* actuator coordinates in their SI unit: m and m/s, or rad and rad/s */
  const char *q = pom_act_kind_desc(kind)->si, *qd = pom_act_kind_desc(kind)->rate_tag;
  fprintf(f,
          "t_s,q1_%s,q2_%s,q3_%s,qdot1_%s,qdot2_%s,qdot3_%s,i1_A,i2_A,i3_A,u1_V,u2_V,u3_V,"
          "E1_J,E2_J,E3_J,psi_rad,theta_rad,phi_rad,qw,qx,qy,qz,deflection_m,q1_set_%s,"
          "q2_set_%s,q3_set_%s\n",
          q, q, q, qd, qd, qd, q, q, q);
  for (int k = 0; k < tr->n; ++k) {
    fprintf(f, "%.9g", tr->t[k]);
    const double *cols[5] = {tr->q, tr->q_dot, tr->current, tr->voltage, tr->energy};
    for (int c = 0; c < 5; ++c)
      for (int a = 0; a < 3; ++a)
        fprintf(f, ",%.9g", cols[c][3 * k + a]);
    for (int a = 0; a < 3; ++a)
      fprintf(f, ",%.9g", tr->euler_zyx[3 * k + a]);
    for (int a = 0; a < 4; ++a)
      fprintf(f, ",%.9g", tr->quat[4 * k + a]);
    /* the setpoints on every row: plots draw them as the HDF5 file's are */
    fprintf(f, ",%.9g,%.9g,%.9g,%.9g\n", tr->deflection[k], target[0], target[1], target[2]);
  }
  return pom_io_commit(&w, err);
}

static pom_status write_h5(const char *path, const pom_cfg *cfg, const char *name,
                           const pom_dyn_params *p, const pom_dyn_trace *tr,
                           const pom_dyn_metrics *mt, pom_actuator_kind kind, pom_error *err) {
  pom_status st = POM_OK;
  hid_t file = -1, g = -1;
  size_t n = (size_t)tr->n;
  size_t d1[1] = {n}, d3[2] = {n, 3}, d4[2] = {n, 4};
  POM_TRY(pom_h5_create_file(&file, path, err));
  POM_TRY_GOTO(pom_h5_attr_string(file, "program", "pomlab simulate " POM_VERSION, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "git_commit", POM_GIT_COMMIT, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "name", name, err), done);
  POM_TRY_GOTO(pom_h5_write_text(file, "config", pom_cfg_text(cfg), err), done);
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "trace", err), done);
  char units[256];
  snprintf(units, sizeof units,
           "t s; q %s; q_dot %s; current A; voltage V; energy J (cumulative int u i dt); "
           "euler_zyx rad (psi, theta, phi); quat (w, x, y, z); deflection m",
           pom_act_kind_desc(kind)->si, pom_act_kind_desc(kind)->rate);
  POM_TRY_GOTO(pom_h5_attr_string(g, "units", units, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "actuator_unit", pom_act_kind_desc(kind)->si, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "t", 1, d1, tr->t, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "q", 2, d3, tr->q, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "q_dot", 2, d3, tr->q_dot, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "current", 2, d3, tr->current, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "voltage", 2, d3, tr->voltage, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "energy", 2, d3, tr->energy, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "euler_zyx", 2, d3, tr->euler_zyx, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "quat", 2, d4, tr->quat, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "deflection", 1, d1, tr->deflection, err), done);
  H5Gclose(g);
  g = -1;
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "metrics", err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "status", pom_status_name(mt->status), err), done);
  /* every parameter of the run (controller_*, orientation, solver_*, ...) */
  POM_TRY_GOTO(pom_dyn_params_h5_describe(g, p, err), done);
  if (mt->status != POM_OK) POM_TRY_GOTO(pom_h5_attr_string(g, "reason", mt->reason, err), done);
  /* every metric of the list, named by its JSON key (docs/results.md section
   * 9): float64 in SI (counts and flags exactly), [3] per actuator */
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    char key[96];
    double v[3];
    pom_dyn_metric_json_key(&schema[j], key, sizeof key);
    for (int k = 0; k < schema[j].count; ++k)
      v[k] = pom_dyn_metric_value(mt, &schema[j], k);
    st = schema[j].count == 1 ? pom_h5_attr_double(g, key, v[0], err)
                              : pom_h5_attr_doubles(g, key, v, (size_t)schema[j].count, err);
    if (st != POM_OK) goto done;
  }
  if (pom_act_kind_desc(kind)->legacy_keys) /* the names before actuator units existed */
    POM_TRY_GOTO(pom_h5_attr_doubles(g, "target_m", mt->target, 3, err), done);
done:
  if (g >= 0) H5Gclose(g);
  pom_error close_err;
  pom_error_clear(&close_err);
  pom_status cst = pom_h5_close_file(file, &close_err);
  if (st == POM_OK && cst != POM_OK) {
    if (err) *err = close_err;
    st = cst;
  }
  return st;
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

/* ---- command ------------------------------------------------------------- */
/* Options that set a config value, checked by the config's own ranges. */
typedef struct {
  const char *option; /* "--kp" */
  const char *key;    /* "controller.kp" */
  const char *text;   /* the value given, NULL when absent */
} simulate_setting;

static int setting_index(const simulate_setting *s, int n, const char *option) {
  for (int k = 0; k < n; ++k)
    if (strcmp(s[k].option, option) == 0) return k;
  return -1;
}

int pom_cmd_simulate(int argc, char **argv) {
  const char *cfg_path = NULL, *out_path = NULL, *target_text = NULL;
  const char *form = NULL, *orient = NULL, *linsol = NULL, *joints = NULL, *controller = NULL;
  simulate_setting settings[] = {{"--kp", "controller.kp", NULL},
                                 {"--ki", "controller.ki_per_s", NULL},
                                 {"--kd", "controller.kd_s", NULL},
                                 {"--rtol", "solver.rtol", NULL}};
  const int n_settings = (int)(sizeof settings / sizeof settings[0]);
  int json = 0;
  for (int k = 1; k < argc; ++k) {
    const char *a = argv[k];
    int has_val = k + 1 < argc;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      simulate_usage(stdout);
      return 0;
    } else if (strcmp(a, "--json") == 0) {
      json = 1;
    } else if (strcmp(a, "--target") == 0 && has_val) {
      target_text = argv[++k];
    } else if (strcmp(a, "--out") == 0 && has_val) {
      out_path = argv[++k];
    } else if (strcmp(a, "--form") == 0 && has_val) {
      form = argv[++k];
    } else if (strcmp(a, "--controller") == 0 && has_val) {
      controller = argv[++k];
    } else if (strcmp(a, "--orientation") == 0 && has_val) {
      orient = argv[++k];
    } else if (strcmp(a, "--linsol") == 0 && has_val) {
      linsol = argv[++k];
    } else if (strcmp(a, "--joints") == 0 && has_val) {
      joints = argv[++k];
    } else if (a[0] == '-' && has_val && setting_index(settings, n_settings, a) >= 0) {
      settings[setting_index(settings, n_settings, a)].text = argv[++k];
    } else if (a[0] != '-' && !cfg_path) {
      cfg_path = a;
    } else {
      fprintf(stderr, "pomlab simulate: unknown or incomplete option '%s'\n\n", a);
      simulate_usage(stderr);
      return 2;
    }
  }
  double target[3];
  if (!cfg_path || !target_text) {
    simulate_usage(stderr);
    return 2;
  }
  if (pom_cli_parse_list(target_text, 3, target) != 0) {
    fprintf(stderr, "pomlab simulate: --target expects three numbers (mm or deg, the actuators' "
                    "display unit), 'q1,q2,q3'\n");
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
  int path_rc =
      pom_job_check_output("simulate", cfg_path, out_path, "the traces (--out)", stderr, NULL);
  if (path_rc) {
    rc = path_rc;
    goto done;
  }
  pom_status st = POM_OK;
  /* the controller's type and form through the config, checked like the file's values */
  if (controller) st = pom_cfg_set_string(cfg, "controller.type", controller, "--controller", &err);
  if (form && st == POM_OK) st = pom_cfg_set_string(cfg, "controller.form", form, "--form", &err);
  /* the choices likewise: the loader's tables name them, one parser */
  if (joints && st == POM_OK)
    st = pom_cfg_set_string(cfg, "joints.model", joints, "--joints", &err);
  if (orient && st == POM_OK)
    st = pom_cfg_set_string(cfg, "scene.orientation", orient, "--orientation", &err);
  if (linsol && st == POM_OK)
    st = pom_cfg_set_string(cfg, "solver.linear_solver", linsol, "--linsol", &err);
  for (int j = 0; j < n_settings && st == POM_OK; ++j)
    if (settings[j].text)
      st = pom_cfg_set_number(cfg, settings[j].key, settings[j].text, settings[j].option, &err);
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
  st = pom_dyn_simulate(model, data, target, &mt, trace, &err);
  if (json)
    print_json(arch.name, &par, &mt, kind, 0.5 * arch.stroke);
  else
    print_human(arch.name, &par, &mt, kind, 0.5 * arch.stroke);
  rc = st == POM_OK ? 0 : 1;
  if (st != POM_OK) pom_cli_report("simulate", &err);
  int beyond[3];
  if (stroke_excursions(&mt, 0.5 * arch.stroke, beyond))
    fprintf(stderr,
            "pomlab simulate: warning: an actuator left its stroke +-%.10g %s (max |q| %.6g, "
            "%.6g, %.6g %s); the model has no end stops\n",
            0.5 * arch.stroke * u->to_display, u->display, mt.max_abs_q[0] * u->to_display,
            mt.max_abs_q[1] * u->to_display, mt.max_abs_q[2] * u->to_display, u->display);
  if (trace && trace->n > 0) {
    pom_error werr;
    pom_error_clear(&werr);
    pom_status wst = ends_with(out_path, ".csv")
                         ? write_csv(out_path, trace, mt.target, kind, &werr)
                         : write_h5(out_path, cfg, arch.name, &par, trace, &mt, kind, &werr);
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
