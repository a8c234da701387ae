/* cmd_workspace.c - pomlab workspace: regular dexterous workspace, global
 * conditioning index and an optional dexterity map (CSV). */
#include "cli_opts.h"
#include "cli_kin.h"
#include "pom_kin_print.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_io.h"
#include "pom_math.h"
#include "pom_progress.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---- cost: budget, estimate, progress ------------------------------------------------ */
/* Refuses a grid of `poses` above the budget: exit status 2 with the config
 * file, the keys and their values; 0 when within it. */
static int check_budget(const pom_cfg *cfg, const pom_kin_ws_opts *o, double poses, double rate,
                        const char *step_key, double step, const char *width_key, double width) {
  if (poses <= o->max_poses) return 0;
  char value[64], how_long[48];
  snprintf(value, sizeof value, "%.10g", step / POM_DEG);
  pom_error err;
  pom_error_clear(&err);
  pom_cfg_error(cfg, step_key, value, &err,
                "over %s = %.10g deg this grid needs %.3g pose evaluations (%s here), above the "
                "budget workspace.max_poses = %.3g; coarsen the step, shrink the region or raise "
                "the budget",
                width_key, width / POM_DEG, poses,
                pom_job_duration_text(how_long, sizeof how_long, poses / rate), o->max_poses);
  pom_cli_report("workspace", &err);
  return 2;
}

/* Announces work expected to last over 10 s (stderr, unless quiet). */
static void announce(int quiet, const char *what, double poses, double rate) {
  char how_long[48];
  if (quiet || !(poses / rate > 10.0)) return;
  fprintf(stderr, "pomlab workspace: %s: up to %.3g poses, %s at %.3g poses/s\n", what, poses,
          pom_job_duration_text(how_long, sizeof how_long, poses / rate), rate);
}

/* The kinematics' progress callback drives a pom_progress bar. */
static void on_progress(void *user, long done, long bound) {
  pom_progress *bar = user;
  bar->total = bound;
  pom_progress_update(bar, done);
}

int pom_cmd_workspace(int argc, char **argv) {
  const char *path = NULL, *map = NULL;
  int json = 0, quiet = 0;
  const pom_opt opts[] = {
      {.name = "--map",
       .kind = POM_OPT_TEXT,
       .arg = "FILE.csv",
       .help = "write the dexterity map over the cube of half-width workspace.map_half_width_deg, "
               "step workspace.map_resolution_deg: psi_deg,theta_deg,phi_deg,reachable,"
               "within_limits,dexterity, q1_mm,q2_mm,q3_mm (or _deg for rotary actuators),"
               "violations; figure: python3 scripts/plot_workspace.py FILE.csv OUT.png",
       .text = &map},
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "machine-readable output on stdout",
       .flag = &json,
       .set = 1},
      {.name = "--quiet",
       .kind = POM_OPT_FLAG,
       .help = "no progress on stderr",
       .flag = &quiet,
       .set = 1},
  };
  const pom_cli_spec spec = {
      .name = "workspace",
      .usage = "CONFIG [--json] [--map FILE.csv] [--quiet]",
      .about =
          "Regular dexterous workspace (RDW): the largest cube [-a, a]^3 of ZYX Euler\n"
          "angles (psi, theta, phi) about home whose grid poses (step workspace.resolution_deg)\n"
          "are all assemblable on the home branch, within the limits (when\n"
          "workspace.check_limits) and have dexterity 1/kappa >= workspace.dexterity_min\n"
          "(docs/kinematics.md section 6). Also the minimum dexterity inside it and the\n"
          "global conditioning index (mean 1/kappa, measure cos(theta) dpsi dtheta dphi)\n"
          "over the cube of half-width workspace.gci_half_width_deg (0 = the RDW).",
      .notes = "Cost: each grid (the RDW search, the GCI, the map) may evaluate at most\n"
               "workspace.max_poses poses (default 1e8, a minute or two on one core). The\n"
               "search stops before a shell that would pass it (the half-width is then a\n"
               "lower bound); a GCI region or map that would pass it is refused up front.\n"
               "Work expected to last over 10 s is announced with its estimate.\n\n"
               "Reads the config groups name, architecture, geometry, limits, workspace.\n"
               "Exit status: 0 ok; 1 home pose fails or the map cannot be written; 2 usage or\n"
               "config error (a grid above the budget included).",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (!path) {
    fprintf(stderr, "pomlab workspace: missing CONFIG\n");
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_kin_ws_opts o;
  const char *const *const scopes[] = {pom_kin_arch_groups(), pom_kin_ws_groups(), NULL};
  int rc = pom_cli_kin_load(path, &cfg, &arch, &o, scopes);
  if (rc) return rc;
  /* the map must not overwrite the config or a file it includes */
  rc = pom_job_check_output("workspace", path, map, "the map (--map)", stderr, NULL);
  if (rc) {
    pom_cfg_destroy(cfg);
    return rc;
  }
  /* The grids whose size is known before the search: refused above the
   * budget before any work (the GCI over the RDW is never larger than the
   * search that found it). */
  const double rate = pom_kin_pose_rate(&arch);
  if (o.gci_half_width > 0.0)
    rc = check_budget(cfg, &o, pom_kin_gci_poses(o.gci_half_width, o.resolution), rate,
                      "workspace.resolution_deg", o.resolution, "workspace.gci_half_width_deg",
                      o.gci_half_width);
  if (!rc && map)
    rc = check_budget(cfg, &o, pom_kin_grid_poses(o.map_half_width, o.map_resolution), rate,
                      "workspace.map_resolution_deg", o.map_resolution,
                      "workspace.map_half_width_deg", o.map_half_width);
  pom_cfg_destroy(cfg);
  if (rc) return rc;

  pom_error err;
  pom_error_clear(&err);
  pom_kin_ws_result r;
  pom_progress bar;
  double search_poses = fmin(pom_kin_grid_poses(o.max_half_width, o.resolution), o.max_poses);
  announce(quiet, "regular dexterous workspace search", search_poses, rate);
  pom_progress_init(&bar, quiet ? NULL : stderr, "workspace search (poses, at most)",
                    (long)search_poses, 0, 0);
  o.progress = on_progress;
  o.progress_user = &bar;
  pom_status st = pom_kin_workspace(&arch, &o, &r, &err);
  pom_progress_finish(&bar, r.poses);
  if (st != POM_OK) {
    pom_cli_report("workspace", &err);
    return pom_cli_exit_code(st);
  }
  char why[512];
  pom_kin_ws_reason_text(&arch, &r, &o, why, sizeof why);
  if (r.half_width < 0.0) {
    fprintf(stderr, "pomlab workspace: the home pose itself fails (%s)\n", why);
    return 1;
  }
  if (r.budget_reached)
    fprintf(stderr,
            "pomlab workspace: warning: the search stopped at workspace.max_poses = %g before "
            "finding the edge; the half-width +-%g deg is a lower bound\n",
            o.max_poses, r.half_width / POM_DEG);
  double gci_region = o.gci_half_width > 0.0 ? o.gci_half_width : r.half_width;
  double gci = NAN, usable = NAN, gci_poses = pom_kin_gci_poses(gci_region, o.resolution);
  announce(quiet, "global conditioning index", gci_poses, rate);
  pom_progress_init(&bar, quiet ? NULL : stderr, "workspace GCI (poses)", (long)gci_poses, 0, 0);
  st = pom_kin_gci_progress(&arch, gci_region, o.resolution, o.check_limits, on_progress, &bar,
                            &gci, &usable, &err);
  pom_progress_finish(&bar, (long)gci_poses);
  if (st != POM_OK) {
    pom_cli_report("workspace: GCI", &err);
    return 1;
  }
  if (map) {
    double map_poses = pom_kin_grid_poses(o.map_half_width, o.map_resolution);
    announce(quiet, "dexterity map", map_poses, rate);
    pom_progress_init(&bar, quiet ? NULL : stderr, "workspace map (poses)", (long)map_poses, 0, 0);
    st = pom_kin_ws_map_write(map, &arch, &o, &bar, &err);
    if (st != POM_OK) {
      pom_cli_report("workspace --map", &err);
      return 1;
    }
  }

  pom_kin_ws_report rep = {
      .config = path, .map = map, .gci = gci, .gci_half_width = gci_region, .gci_usable = usable};
  pom_kin_ws_report_print(stdout, json, &arch, &o, &r, &rep);
  return 0;
}
