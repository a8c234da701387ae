/* cap_h5.c - the capability result as HDF5 (SI): the config, the grid's
 * figures per pose (/poses) and the slews (/slews/<axis>). Its own file so
 * that a program printing reports alone does not link HDF5's writers. */
#include "pom_capability.h"

#include "pom_h5.h"
#include "pom_version.h"

#include <stdlib.h>

/* Pose columns of /poses/figures, in this order (SI). */
static const char *const pose_columns =
    "psi, theta, phi (rad); ok; acc_inscribed, acc_x, acc_y, acc_z (rad/s^2); rate_inscribed, "
    "rate_x, rate_y, rate_z (rad/s); rate_emf_inscribed (rad/s); q1, q2, q3 (m or rad); "
    "freq_ok; bw_worst, bw_x, bw_y, bw_z (Hz); peak_db_worst (dB); pm_deg_min (deg); gm_db_min "
    "(dB, inf: no phase crossover); mode (Hz); mode_zeta (1) (NaN: not evaluated)";
#define POSE_COLS 26

pom_status pom_cap_write_h5(const char *path, const char *program, const pom_cfg *cfg,
                            const char *name, const pom_cap_opts *o, const pom_cap_result *r,
                            pom_error *err) {
  pom_status st = POM_OK;
  hid_t file = -1, g = -1, gs = -1;
  double *tab = calloc((size_t)r->n_poses * POSE_COLS, sizeof *tab);
  if (!tab) POM_FAIL(err, POM_ERR_NOMEM, "allocating the pose table");
  POM_TRY_GOTO(pom_h5_create_file(&file, path, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "program", program, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "git_commit", POM_GIT_COMMIT, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "name", name, err), done);
  POM_TRY_GOTO(pom_h5_write_text(file, "config", pom_cfg_text(cfg), err), done);
  POM_TRY_GOTO(pom_h5_attr_double(file, "half_width_rad", r->half_width, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(file, "step_rad", r->step, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(file, "effort_limit", r->f_max, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(file, "current_limit_A", o->current_limit, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(file, "home", r->home, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(file, "worst_acc", r->worst_acc, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(file, "worst_rate", r->worst_rate, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(file, "worst_bw", r->worst_bw, err), done);
  POM_TRY_GOTO(pom_h5_attr_int64(file, "worst_pm", r->worst_pm, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(file, "bw_worst_hz", r->bw_worst_hz, err), done);
  POM_TRY_GOTO(pom_h5_attr_double(file, "pm_worst_deg", r->pm_worst_deg, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "bandwidth_joints",
                                  r->freq_joints == POM_JOINTS_RIGID ? "rigid" : "parasitic", err),
               done);
  for (int k = 0; k < r->n_poses; ++k) {
    const pom_cap_pose *p = &r->pose[k];
    double *row = tab + (size_t)k * POSE_COLS;
    const double v[POSE_COLS] = {p->euler[0],
                                 p->euler[1],
                                 p->euler[2],
                                 p->ok,
                                 p->acc_inscribed,
                                 p->acc_axis[0],
                                 p->acc_axis[1],
                                 p->acc_axis[2],
                                 p->rate_inscribed,
                                 p->rate_axis[0],
                                 p->rate_axis[1],
                                 p->rate_axis[2],
                                 p->rate_emf_inscribed,
                                 p->q[0],
                                 p->q[1],
                                 p->q[2],
                                 p->freq_ok,
                                 p->bw_worst_hz,
                                 p->bw_axis_hz[0],
                                 p->bw_axis_hz[1],
                                 p->bw_axis_hz[2],
                                 p->peak_db_worst,
                                 p->pm_deg_min,
                                 p->gm_db_min,
                                 p->mode_hz,
                                 p->mode_zeta};
    for (int j = 0; j < POSE_COLS; ++j)
      row[j] = v[j];
  }
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "poses", err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "columns", pose_columns, err), done);
  size_t dims[2] = {(size_t)r->n_poses, POSE_COLS};
  POM_TRY_GOTO(pom_h5_write_doubles(g, "figures", 2, dims, tab, err), done);
  H5Gclose(g);
  g = -1;
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "slews", err), done);
  static const char *const names[POM_CAP_MAX_DIRECTIONS] = {"x", "y", "z", "xyz"};
  for (int k = 0; k < r->n_dirs; ++k) {
    const pom_cap_slew *s = &r->slew[k];
    size_t n[1] = {(size_t)s->n};
    POM_TRY_GOTO(pom_h5_create_group(&gs, g, names[k], err), done);
    POM_TRY_GOTO(pom_h5_attr_doubles(gs, "dir", s->dir, 3, err), done);
    POM_TRY_GOTO(pom_h5_attr_double(gs, "edge_rad", s->edge, err), done);
    POM_TRY_GOTO(pom_h5_write_doubles(gs, "amplitude_rad", 1, n, s->amplitude, err), done);
    POM_TRY_GOTO(pom_h5_write_doubles(gs, "slew_time_s", 1, n, s->slew_time, err), done);
    POM_TRY_GOTO(pom_h5_write_doubles(gs, "peak_rate_rad_per_s", 1, n, s->peak_rate, err), done);
    H5Gclose(gs);
    gs = -1;
  }
done:
  if (gs >= 0) H5Gclose(gs);
  if (g >= 0) H5Gclose(g);
  free(tab);
  pom_error close_err;
  pom_error_clear(&close_err);
  pom_status cst = file >= 0 ? pom_h5_close_file(file, &close_err) : POM_OK;
  if (st == POM_OK && cst != POM_OK) {
    if (err) *err = close_err;
    st = cst;
  }
  return st;
}
