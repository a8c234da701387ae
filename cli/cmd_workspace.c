/* cmd_workspace.c - pomlab workspace: regular dexterous workspace, global
 * conditioning index and an optional dexterity map (CSV). */
#include "cli_kin.h"
#include "pom_job.h"
#include "pom_cli.h"
#include "pom_io.h"
#include "pom_math.h"
#include "pom_progress.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static void ws_usage(FILE *out) {
  fprintf(out,
          "usage: pomlab workspace CONFIG [--json] [--map FILE.csv] [--quiet]\n\n"
          "Regular dexterous workspace (RDW): the largest cube [-a, a]^3 of ZYX Euler\n"
          "angles (psi, theta, phi) about home whose grid poses (step workspace.resolution_deg)\n"
          "are all assemblable on the home branch, within the limits (when\n"
          "workspace.check_limits) and have dexterity 1/kappa >= workspace.dexterity_min\n"
          "(docs/kinematics.md section 6). Also the minimum dexterity inside it and the\n"
          "global conditioning index (mean 1/kappa, measure cos(theta) dpsi dtheta dphi)\n"
          "over the cube of half-width workspace.gci_half_width_deg (0 = the RDW).\n\n"
          "  --map FILE.csv  write the dexterity map over the cube of half-width\n"
          "                  workspace.map_half_width_deg, step workspace.map_resolution_deg:\n"
          "                  psi_deg,theta_deg,phi_deg,reachable,within_limits,dexterity,\n"
          "                  q1_mm,q2_mm,q3_mm (or _deg for rotary actuators),violations;\n"
          "                  figure: python3 scripts/plot_workspace.py FILE.csv OUT.png\n"
          "  --json          machine-readable output on stdout\n"
          "  --quiet         no progress on stderr\n\n"
          "Cost: each grid (the RDW search, the GCI, the map) may evaluate at most\n"
          "workspace.max_poses poses (default 1e8, a minute or two on one core). The\n"
          "search stops before a shell that would pass it (the half-width is then a\n"
          "lower bound); a GCI region or map that would pass it is refused up front.\n"
          "Work expected to last over 10 s is announced with its estimate.\n"
          "  --help          this text\n\n"
          "Reads the config groups name, architecture, geometry, limits, workspace.\n"
          "Exit status: 0 ok; 1 home pose fails or the map cannot be written; 2 usage or\n"
          "config error (a grid above the budget included).\n");
}

static const char *reason_text(const pom_kin_arch *arch, const pom_kin_ws_result *r,
                               const pom_kin_ws_opts *o, char *buf, size_t cap) {
  if (r->budget_reached) {
    snprintf(buf, cap, "none: the search stopped at workspace.max_poses = %g", o->max_poses);
  } else if (r->capped) {
    snprintf(buf, cap, "none: the search stopped at max_half_width_deg = %g",
             o->max_half_width / POM_DEG);
  } else if (r->fail_status == POM_ERR_UNREACHABLE) {
    snprintf(buf, cap, "not assemblable");
  } else if (r->fail_status == POM_ERR_LIMIT) {
    char v[400];
    pom_kin_violations_text(arch, r->fail_violations, v, sizeof v);
    snprintf(buf, cap, "limit: %s", v);
  } else {
    snprintf(buf, cap, "dexterity %.4f < %.4g", r->fail_dexterity, o->dexterity_min);
  }
  return buf;
}

/* ---- cost: budget, estimate, progress ------------------------------------------------ */
/* Poses per second of this machine on this architecture, from a 8^3 grid of
 * poses within 4 deg of home (a few milliseconds). */
static double measured_rate(const pom_kin_arch *arch) {
  double t0 = pom_progress_now();
  pom_kin_pose p;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int l = 0; l < 8; ++l) {
        double e[3] = {(i - 3.5) * POM_DEG, (j - 3.5) * POM_DEG, (l - 3.5) * POM_DEG}, R[9];
        pom_euler_zyx_to_matrix(R, e);
        pom_kin_pose_evaluate(arch, R, &p, NULL);
      }
  double dt = pom_progress_now() - t0;
  return dt > 0.0 ? 512.0 / dt : NAN;
}

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

static int write_map(const char *file, const pom_kin_arch *arch, const pom_kin_ws_opts *o,
                     pom_progress *bar) {
  pom_io_file w;
  pom_error err;
  pom_error_clear(&err);
  if (pom_io_create(&w, file, &err) != POM_OK) {
    pom_cli_report("workspace --map", &err);
    return 1;
  }
  FILE *fp = w.f;
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch->type));
  fprintf(fp,
          "psi_deg,theta_deg,phi_deg,reachable,within_limits,dexterity,q1_%s,q2_%s,q3_%s,"
          "violations\n",
          u->display, u->display, u->display);
  const double h = o->map_resolution;
  const int n = (int)floor(o->map_half_width / h + 1e-9); /* + 1e-9: whole steps survive rounding */
  long done = 0;
  for (int i = -n; i <= n; ++i) {
    pom_progress_update(bar, done);
    for (int j = -n; j <= n; ++j)
      for (int l = -n; l <= n; ++l, ++done) {
        double e[3] = {i * h, j * h, l * h}, R[9];
        pom_euler_zyx_to_matrix(R, e);
        pom_kin_pose p;
        pom_kin_pose_evaluate(arch, R, &p, NULL);
        char v[400];
        pom_kin_violations_text(arch, p.violations, v, sizeof v);
        for (char *c = v; *c; ++c)
          if (*c == ',') *c = ';';
        fprintf(fp, "%.6g,%.6g,%.6g,%d,%d,%.6f,%.6f,%.6f,%.6f,%s\n", e[0] / POM_DEG, e[1] / POM_DEG,
                e[2] / POM_DEG, p.reachable, p.reachable && !p.violations, p.dexterity,
                p.q[0] * u->to_display, p.q[1] * u->to_display, p.q[2] * u->to_display,
                p.reachable ? v : "unreachable");
      }
  }
  pom_progress_finish(bar, done);
  if (pom_io_commit(&w, &err) != POM_OK) {
    pom_cli_report("workspace --map", &err);
    return 1;
  }
  return 0;
}

int pom_cmd_workspace(int argc, char **argv) {
  const char *path = NULL, *map = NULL;
  int json = 0, quiet = 0;
  for (int k = 1; k < argc; ++k) {
    if (strcmp(argv[k], "--help") == 0 || strcmp(argv[k], "-h") == 0) {
      ws_usage(stdout);
      return 0;
    } else if (strcmp(argv[k], "--json") == 0) {
      json = 1;
    } else if (strcmp(argv[k], "--quiet") == 0) {
      quiet = 1;
    } else if (strcmp(argv[k], "--map") == 0 && k + 1 < argc) {
      map = argv[++k];
    } else if (strncmp(argv[k], "--map=", 6) == 0) {
      map = argv[k] + 6;
    } else if (argv[k][0] == '-' && argv[k][1] != '\0') {
      fprintf(stderr, "pomlab workspace: unknown or incomplete option '%s'\n", argv[k]);
      ws_usage(stderr);
      return 2;
    } else if (!path) {
      path = argv[k];
    } else {
      fprintf(stderr, "pomlab workspace: unexpected argument '%s'\n", argv[k]);
      return 2;
    }
  }
  if (!path) {
    fprintf(stderr, "pomlab workspace: missing CONFIG\n");
    ws_usage(stderr);
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
  const double rate = measured_rate(&arch);
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
  reason_text(&arch, &r, &o, why, sizeof why);
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
    if (write_map(map, &arch, &o, &bar) != 0) return 1;
  }

  if (json) {
    printf("{\n  \"config\": ");
    pom_json_string(stdout, path);
    printf(",\n  \"name\": ");
    pom_json_string(stdout, arch.name);
    printf(",\n  \"architecture\": \"%s\",\n  \"shape\": \"euler_zyx_cube\",\n",
           pom_kin_arch_name(&arch));
    printf("  \"dexterity_min\": ");
    pom_json_number(stdout, o.dexterity_min);
    printf(",\n  \"resolution_deg\": ");
    pom_json_number(stdout, o.resolution / POM_DEG);
    printf(",\n  \"check_limits\": %s,\n  \"half_width_deg\": ", o.check_limits ? "true" : "false");
    pom_json_number(stdout, r.half_width / POM_DEG);
    printf(",\n  \"capped\": %s,\n  \"budget_reached\": %s,\n  \"max_poses\": ",
           r.capped ? "true" : "false", r.budget_reached ? "true" : "false");
    pom_json_number(stdout, o.max_poses);
    printf(",\n  \"min_dexterity\": ");
    pom_json_number(stdout, r.min_dexterity);
    printf(",\n  \"first_failure\": ");
    if (r.capped || r.budget_reached) {
      printf("null");
    } else {
      printf("{\"euler_zyx_deg\": ");
      pom_json_vec(stdout, r.fail_euler, 3, 1.0 / POM_DEG);
      printf(", \"reason\": ");
      pom_json_string(stdout, why);
      printf("}");
    }
    printf(",\n  \"gci\": ");
    pom_json_number(stdout, gci);
    printf(",\n  \"gci_half_width_deg\": ");
    pom_json_number(stdout, gci_region / POM_DEG);
    printf(",\n  \"gci_usable_fraction\": ");
    pom_json_number(stdout, usable);
    printf(",\n  \"poses_evaluated\": %ld,\n  \"map\": ", r.poses);
    if (map) {
      pom_json_string(stdout, map);
    } else {
      printf("null");
    }
    printf("\n}\n");
  } else {
    printf("%s (%s), config %s\n", arch.name, pom_kin_arch_name(&arch), path);
    printf("regular dexterous workspace (ZYX Euler cube about home, step %g deg,\n"
           "  1/kappa >= %g, limits %s):\n",
           o.resolution / POM_DEG, o.dexterity_min, o.check_limits ? "checked" : "ignored");
    printf("  half-width:        %s+-%g deg%s\n", r.budget_reached ? "at least " : "",
           r.half_width / POM_DEG,
           r.capped           ? " (search cap reached)"
           : r.budget_reached ? " (search stopped at workspace.max_poses)"
                              : "");
    printf("  min dexterity:     %.4f\n", r.min_dexterity);
    if (!r.capped && !r.budget_reached)
      printf("  first failure:     psi = %g, theta = %g, phi = %g deg: %s\n",
             r.fail_euler[0] / POM_DEG, r.fail_euler[1] / POM_DEG, r.fail_euler[2] / POM_DEG, why);
    printf("  poses evaluated:   %ld\n", r.poses);
    printf("global conditioning index over +-%g deg: %.4f (usable fraction %.4f)\n",
           gci_region / POM_DEG, gci, usable);
    if (map) printf("dexterity map written to %s\n", map);
  }
  return 0;
}
