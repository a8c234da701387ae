/* cmd_capability.c - `pomlab capability CFG`: peak angular acceleration and
 * rate over the regular dexterous workspace and large-angle slews, in device
 * units (docs/capability.md). Parses, checks and calls capability/. */
#define _DEFAULT_SOURCE /* rename */
#include "cli_opts.h"
#include "pom_capability.h"
#include "pom_cli.h"
#include "pom_job.h"
#include "pom_kinematics.h"
#include "pom_progress.h"
#include "pom_version.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* The capability driver's progress callback drives a pom_progress bar. */
static void on_progress(void *user, long done, long total) {
  pom_progress *bar = user;
  bar->total = total;
  pom_progress_update(bar, done);
}

/* Writes the HDF5 file through OUT.partial and a rename, so that a failed
 * write never leaves a truncated results file; 0 or 1. */
static int write_h5(const char *out, const pom_cfg *cfg, const char *name, const pom_cap_opts *o,
                    const pom_cap_result *r) {
  char partial[4200];
  pom_error err;
  pom_error_clear(&err);
  snprintf(partial, sizeof partial, "%s.partial", out);
  pom_status st =
      pom_cap_write_h5(partial, "pomlab capability " POM_VERSION, cfg, name, o, r, &err);
  if (st == POM_OK && rename(partial, out) != 0)
    st = pom_error_set(&err, POM_ERR_IO, __FILE__, __LINE__, "renaming '%s' to '%s': %s", partial,
                       out, strerror(errno));
  if (st != POM_OK) {
    unlink(partial);
    pom_cli_report("capability: writing --out", &err);
    return 1;
  }
  return 0;
}

/* Bode data grid (Hz) and density of the plots, as `simulate --bode` */
#define BODE_F_LO       0.1
#define BODE_F_HI       1e5
#define BODE_PER_DECADE 40

/* DIR/bode_<what>.json at pose k and its figure by scripts/plot_bode.py; 0
 * or 1. */
static int write_bode(const char *dir, const char *scripts, const char *what,
                      const pom_kin_arch *arch, const pom_mechanism *mech,
                      const pom_dyn_params *par, const pom_cap_pose *p) {
  char json[4200], png[4200];
  pom_error err;
  pom_error_clear(&err);
  snprintf(json, sizeof json, "%s/bode_%s.json", dir, what);
  snprintf(png, sizeof png, "%s/bode_%s.png", dir, what);
  if (pom_cap_write_bode(json, arch, mech, par, p->q, BODE_F_LO, BODE_F_HI, BODE_PER_DECADE,
                         &err) != POM_OK) {
    pom_cli_report("capability --plots (Bode data)", &err);
    return 1;
  }
  if (!scripts) return 0;
  int rc = pom_job_run_script(scripts, "plot_bode.py", json, png, stderr);
  if (rc != 0)
    fprintf(stderr, "pomlab capability: warning: %s not drawn: plot_bode.py exited %d\n", png, rc);
  return 0;
}

/* The map: DIR/capability_map.csv and its figure by scripts/plot_capability.py;
 * the Bode plots at home and at the worst-bandwidth pose. */
static int write_plots(const char *dir, const pom_cap_result *r, const pom_kin_arch *arch,
                       const pom_mechanism *mech, const pom_dyn_params *par) {
  char csv[4200], png[4200], failed[4200], scripts[1024];
  pom_error err;
  pom_error_clear(&err);
  snprintf(csv, sizeof csv, "%s/capability_map.csv", dir);
  snprintf(png, sizeof png, "%s/capability_map.png", dir);
  if (pom_job_make_parent(csv, failed, sizeof failed) != 0) {
    fprintf(stderr, "pomlab capability: --plots: cannot create '%s': %s\n", failed,
            strerror(errno));
    return 1;
  }
  if (pom_cap_write_csv(csv, r, &err) != POM_OK) {
    pom_cli_report("capability --plots", &err);
    return 1;
  }
  const int have_scripts = pom_cli_scripts_dir(scripts, sizeof scripts) == 0;
  if (!have_scripts)
    fprintf(stderr, "pomlab capability: warning: no plotting scripts (%s): map left as %s\n",
            scripts, csv);
  int rc = have_scripts ? pom_job_run_script(scripts, "plot_capability.py", csv, png, stderr) : 0;
  if (rc != 0)
    fprintf(stderr, "pomlab capability: warning: map not drawn: plot_capability.py exited %d\n",
            rc);
  int fail = 0;
  const char *sd = have_scripts ? scripts : NULL;
  if (r->home >= 0 && r->pose[r->home].freq_ok)
    fail |= write_bode(dir, sd, "home", arch, mech, par, &r->pose[r->home]);
  if (r->worst_bw >= 0 && r->worst_bw != r->home)
    fail |= write_bode(dir, sd, "worst", arch, mech, par, &r->pose[r->worst_bw]);
  return fail;
}

int pom_cmd_capability(int argc, char **argv) {
  const char *path = NULL, *out = NULL, *plots = NULL, *grid = NULL, *current = NULL;
  const char *controller = NULL;
  int json = 0, quiet = 0;
  const pom_opt opts[] = {
      {.name = "--out",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.h5",
       .help = "write every pose's figures and the slews (SI) to FILE.h5; an existing file is "
               "never overwritten",
       .text = &out},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "machine-readable report (SI) on stdout",
       .flag = &json,
       .set = 1},
      {.name = "--plots",
       .kind = POM_OPT_TEXT,
       .arg = "DIR",
       .help = "write DIR/capability_map.csv and its figure DIR/capability_map.png, and the "
               "Bode data and plots at home and the worst-bandwidth pose (DIR/bode_home.json, "
               "bode_home.png, bode_worst.json, bode_worst.png)",
       .text = &plots},
      {.name = "--grid",
       .kind = POM_OPT_NUMBER,
       .arg = "N",
       .key = "capability.grid_points",
       .help = "poses per Euler angle over the workspace cube (odd)",
       .text = &grid},
      {.name = "--current-limit",
       .kind = POM_OPT_NUMBER,
       .arg = "A",
       .unit = "A",
       .key = "capability.current_limit_A",
       .help = "coil current limit of the envelope, 0 = the voltage limit alone",
       .text = &current},
      {.name = "--controller",
       .kind = POM_OPT_CHOICE,
       .arg = "NAME",
       .key = "controller.type",
       .help = "the controller of the slews (pomlab model --list-controllers)",
       .text = &controller},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress on stderr",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "capability",
      .usage = "CONFIG [--out FILE.h5] [--json] [--plots DIR] [options]",
      .about = "Capability in device units over the regular dexterous workspace (the workspace\n"
               "command's Euler cube, capability.grid_points poses per angle), rigid joints:\n"
               "the angular acceleration reachable from rest under the voltage (and current)\n"
               "limits and the steady angular rate the voltage sustains against back-EMF and the\n"
               "velocity-product terms, each inscribed (every direction) and per fixed axis, at\n"
               "home and at the worst pose; then slews from home about x, y, z and (1,1,1)/sqrt3\n"
               "(capability.slew_amplitudes_deg up to the workspace edge) simulated with the\n"
               "controller and the saturation: slew (pointing settling) time and peak rate;\n"
               "then the small-signal closed loop on the config's own joints.model (parasitic\n"
               "by default): -3 dB bandwidth per axis and in the worst direction, resonant\n"
               "peak, the actuator loops' phase and gain margins, the lowest parasitic mode,\n"
               "on capability.bandwidth_grid_points per angle (docs/capability.md).",
      .notes = "Text in deg/s, deg/s^2 and ms; SI in --json and --out (rad/s, rad/s^2, s).\n"
               "Reads the config groups of the model (architecture, geometry, limits,\n"
               "inertia, actuator, controller, scene, solver, maneuver), workspace and\n"
               "capability (grid_points, current_limit_A, rate_directions, slew_directions,\n"
               "slew_amplitudes_deg, bandwidth_grid_points). The envelope and the slews replace\n"
               "joints.model by \"rigid\"; the bandwidth and margins keep it.\n"
               "Exit status: 0 ok; 1 the evaluation or an output failed; 2 usage or config\n"
               "error (also an --out that exists).",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!path) {
    fprintf(stderr, "pomlab capability: missing CONFIG\n");
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  if (out && !ends_with(out, ".h5")) {
    fprintf(stderr, "pomlab capability: --out must end in .h5, got '%s'\n", out);
    return 2;
  }
  if (out && access(out, F_OK) == 0) {
    fprintf(stderr,
            "pomlab capability: --out '%s' exists: a results file is never overwritten; remove "
            "it or give another name; nothing was run\n",
            out);
    return 2;
  }

  int rc = 1;
  pom_error err;
  pom_error_clear(&err);
  pom_cap_result res;
  memset(&res, 0, sizeof res);
  pom_mechanism *mech = calloc(1, sizeof *mech);
  pom_cfg *cfg = pom_cli_load_config(path);
  if (!cfg) rc = 2;
  if (!cfg || !mech) goto done;
  rc = pom_job_check_output("capability", path, out, "the results (--out)", stderr, NULL);
  if (rc) goto done;
  pom_kin_arch arch;
  pom_kin_ws_opts ws;
  pom_dyn_params par;
  pom_cap_opts o;
  pom_status st = pom_cli_opts_apply(&spec, cfg, &err);
  if (st == POM_OK) st = pom_kin_arch_load(&arch, cfg, &err);
  if (st == POM_OK) st = pom_kin_ws_load(&ws, cfg, &err);
  if (st == POM_OK) st = pom_kin_mechanism_build(mech, &arch, cfg, &err);
  pom_dyn_params_defaults(&par);
  if (st == POM_OK) st = pom_dyn_params_load(&par, cfg, &err);
  if (st == POM_OK) st = pom_cap_load(&o, cfg, &err);
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_kin_ws_groups(),
                                       pom_dyn_param_groups(), pom_cap_groups(), NULL};
  if (st == POM_OK) st = pom_cli_check_unknown(cfg, scopes, &err);
  if (st != POM_OK) {
    pom_cli_report("capability", &err);
    rc = pom_cli_exit_code(st);
    goto done;
  }
  pom_progress bar;
  pom_progress_init(&bar, quiet ? NULL : stderr, "capability (poses and slews)", 1, 0, 0);
  o.progress = on_progress;
  o.progress_user = &bar;
  st = pom_cap_run(&arch, &ws, mech, &par, &o, &res, &err);
  pom_progress_finish(&bar, bar.total);
  if (st != POM_OK) {
    pom_cli_report("capability", &err);
    rc = pom_cli_exit_code(st);
    goto done;
  }
  if (json)
    pom_cap_print_json(stdout, arch.name, &o, &res);
  else
    pom_cap_print_text(stdout, arch.name, &o, &res);
  rc = 0;
  if (out) rc |= write_h5(out, cfg, arch.name, &o, &res);
  if (plots) rc |= write_plots(plots, &res, &arch, mech, &par);
done:
  pom_cap_result_free(&res);
  pom_cfg_destroy(cfg);
  free(mech);
  return rc;
}
