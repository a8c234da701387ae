/* kin_workspace.c - regular dexterous workspace (largest Euler cube about
 * home) and global conditioning index (docs/kinematics.md section 6). */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pom_kin_ws_defaults(pom_kin_ws_opts *o) {
  o->dexterity_min = 0.3;
  o->resolution = 1.0 * POM_DEG;
  o->max_half_width = 45.0 * POM_DEG;
  o->check_limits = 1;
  o->gci_half_width = 0.0;
  o->map_half_width = 20.0 * POM_DEG;
  o->map_resolution = 2.0 * POM_DEG;
  o->max_poses = 1e8;
  o->progress = NULL;
  o->progress_user = NULL;
}

static const char *const ws_groups[] = {"workspace", NULL}; /* what pom_kin_ws_load reads */

const char *const *pom_kin_ws_groups(void) {
  return ws_groups;
}

pom_status pom_kin_ws_load(pom_kin_ws_opts *o, const pom_cfg *cfg, pom_error *err) {
  static const char *const keys[] = {
      "dexterity_min",      "resolution_deg",     "max_half_width_deg",
      "check_limits",       "gci_half_width_deg", "map_half_width_deg",
      "map_resolution_deg", "max_poses",          NULL};
  pom_kin_ws_defaults(o);
  POM_TRY(pom_kin_require_known_key(cfg, "workspace", keys, err));
  POM_TRY(pom_cfg_real_opt(cfg, "workspace.dexterity_min", 1.0, 0.0, 1.0, o->dexterity_min,
                           &o->dexterity_min, err));
  POM_TRY(pom_cfg_real_opt(cfg, "workspace.resolution_deg", POM_DEG, 0.01, 10.0, o->resolution,
                           &o->resolution, err));
  /* the Euler cube must stay clear of the pitch singularity at 90 deg */
  POM_TRY(pom_cfg_real_opt(cfg, "workspace.max_half_width_deg", POM_DEG, 0.0, 85.0,
                           o->max_half_width, &o->max_half_width, err));
  POM_TRY(pom_cfg_bool_opt(cfg, "workspace.check_limits", o->check_limits, &o->check_limits, err));
  POM_TRY(pom_cfg_real_opt(cfg, "workspace.gci_half_width_deg", POM_DEG, 0.0, 85.0,
                           o->gci_half_width, &o->gci_half_width, err));
  POM_TRY(pom_cfg_real_opt(cfg, "workspace.map_half_width_deg", POM_DEG, 0.0, 85.0,
                           o->map_half_width, &o->map_half_width, err));
  POM_TRY(pom_cfg_real_opt(cfg, "workspace.map_resolution_deg", POM_DEG, 0.01, 10.0,
                           o->map_resolution, &o->map_resolution, err));
  POM_TRY(pom_cfg_real_opt(cfg, "workspace.max_poses", 1.0, 1e3, 1e13, o->max_poses, &o->max_poses,
                           err));
  return POM_OK;
}

/* Evaluates one pose against the workspace criteria; 1 when it passes. */
static int pose_passes(const pom_kin_arch *arch, const pom_kin_ws_opts *o, const double e[3],
                       pom_kin_pose *p, pom_status *why) {
  double R[9];
  pom_euler_zyx_to_matrix(R, e);
  pom_status st = pom_kin_pose_evaluate(arch, R, p, NULL);
  if (!p->reachable || (st == POM_ERR_LIMIT && o->check_limits)) {
    *why = st;
    return 0;
  }
  if (!(p->dexterity >= o->dexterity_min)) {
    *why = POM_ERR_SINGULAR;
    return 0;
  }
  return 1;
}

static pom_status check_opts(const pom_kin_ws_opts *o, pom_error *err) {
  if (!(o->resolution > 0.0) || !(o->max_half_width >= 0.0) ||
      !(o->max_half_width < 0.5 * POM_PI) || !(o->dexterity_min >= 0.0) || !(o->max_poses >= 1.0))
    POM_FAIL(err, POM_ERR_ARG,
             "workspace options: need resolution > 0, 0 <= max_half_width < 90 deg, "
             "dexterity_min >= 0, max_poses >= 1");
  return POM_OK;
}

/* Steps of size h in half_width; + 1e-9: a bound that is a whole number of
 * steps (45 deg / 1 deg) must not lose its last step to rounding */
static long whole_steps(double half_width, double h) {
  return (long)floor(half_width / h + 1e-9);
}

double pom_kin_grid_poses(double half_width, double resolution) {
  double side = 2.0 * (double)whole_steps(half_width, resolution) + 1.0;
  return side * side * side;
}

/* Cells per side of the GCI's midpoint rule: size 2a/n <= resolution, n >= 1. */
static long gci_cells(double half_width, double resolution) {
  long n = (long)ceil(2.0 * half_width / resolution);
  return n < 1 ? 1 : n;
}

double pom_kin_gci_poses(double half_width, double resolution) {
  double n = (double)gci_cells(half_width, resolution);
  return n * n * n;
}

/* Every this many poses the long loops tell their progress callback. */
#define PROGRESS_EVERY 4096

pom_status pom_kin_workspace(const pom_kin_arch *arch, const pom_kin_ws_opts *o,
                             pom_kin_ws_result *res, pom_error *err) {
  POM_TRY(check_opts(o, err));
  memset(res, 0, sizeof *res);
  res->min_dexterity = 1.0;
  res->fail_status = POM_OK;
  const double h = o->resolution;
  const int kmax = (int)whole_steps(o->max_half_width, h);
  const long bound = (long)fmin(pom_kin_grid_poses(o->max_half_width, h), o->max_poses);
  pom_kin_pose p;
  /* Grow the cube shell by shell: shell k = grid points with
   * max(|i|, |j|, |l|) = k; the cube of half-width k h passes when every
   * shell up to k passes. The cube up to shell k holds (2k + 1)^3 poses. */
  for (int k = 0; k <= kmax; ++k) {
    double side = 2.0 * k + 1.0;
    if (side * side * side > o->max_poses) {
      res->budget_reached = 1;
      return POM_OK;
    }
    double shell_min = 1.0;
    for (int i = -k; i <= k; ++i)
      for (int j = -k; j <= k; ++j)
        for (int l = -k; l <= k; ++l) {
          if (abs(i) != k && abs(j) != k && abs(l) != k) continue;
          double e[3] = {i * h, j * h, l * h};
          pom_status why = POM_OK;
          if (++res->poses % PROGRESS_EVERY == 0 && o->progress)
            o->progress(o->progress_user, res->poses, bound);
          if (!pose_passes(arch, o, e, &p, &why)) {
            res->half_width = (k - 1) * h;
            if (k == 0) res->half_width = -1.0;
            memcpy(res->fail_euler, e, sizeof e);
            res->fail_status = why;
            res->fail_violations = p.violations;
            res->fail_dexterity = p.reachable ? p.dexterity : 0.0;
            if (k == 0) res->min_dexterity = 0.0;
            return POM_OK;
          }
          shell_min = fmin(shell_min, p.dexterity);
        }
    res->min_dexterity = fmin(res->min_dexterity, shell_min);
    res->half_width = k * h;
  }
  res->capped = 1;
  return POM_OK;
}

pom_status pom_kin_gci(const pom_kin_arch *arch, double half_width, double resolution,
                       int check_limits, double *gci, double *usable_fraction, pom_error *err) {
  return pom_kin_gci_progress(arch, half_width, resolution, check_limits, NULL, NULL, gci,
                              usable_fraction, err);
}

pom_status pom_kin_gci_progress(const pom_kin_arch *arch, double half_width, double resolution,
                                int check_limits, pom_kin_progress progress, void *user,
                                double *gci, double *usable_fraction, pom_error *err) {
  if (!(resolution > 0.0) || !(half_width >= 0.0) || !(half_width < 0.5 * POM_PI))
    POM_FAIL(err, POM_ERR_ARG, "GCI: need resolution > 0 and 0 <= half_width < 90 deg");
  /* midpoint rule on n^3 cells of size 2a/n <= resolution (n >= 1) */
  const long n = gci_cells(half_width, resolution);
  const double w = 2.0 * half_width / (double)n;
  const long bound = (long)pom_kin_gci_poses(half_width, resolution);
  long done = 0;
  double sum = 0.0, usable = 0.0, total = 0.0;
  pom_kin_pose p;
  for (long j = 0; j < n; ++j) {
    double theta = -half_width + ((double)j + 0.5) * w, weight = cos(theta);
    for (long i = 0; i < n; ++i)
      for (long l = 0; l < n; ++l) {
        if (++done % PROGRESS_EVERY == 0 && progress) progress(user, done, bound);
        double e[3] = {-half_width + ((double)i + 0.5) * w, theta,
                       -half_width + ((double)l + 0.5) * w},
               R[9];
        pom_euler_zyx_to_matrix(R, e);
        pom_status st = pom_kin_pose_evaluate(arch, R, &p, NULL);
        total += weight;
        if (!p.reachable || (st == POM_ERR_LIMIT && check_limits)) continue;
        usable += weight;
        sum += weight * p.dexterity;
      }
  }
  if (!(usable > 0.0))
    POM_FAIL(err, POM_ERR_ARG, "GCI: no usable pose in the Euler cube of half-width %.4g deg",
             half_width / POM_DEG);
  *gci = sum / usable;
  if (usable_fraction) *usable_fraction = usable / total;
  return POM_OK;
}
