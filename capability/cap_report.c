/* cap_report.c - the capability report: text in device units (deg/s,
 * deg/s^2, ms), JSON in SI, the grid as CSV for the map. */
#include "pom_capability.h"

#include "pom_json.h"
#include "pom_math.h"

#include <errno.h>
#include <math.h>
#include <string.h>

#define DEG_PER_RAD (180.0 / POM_PI)

/* "x", "y", "z" or "(1,1,1)/sqrt3" for slew direction k. */
static const char *dir_name(int k) {
  static const char *const names[POM_CAP_MAX_DIRECTIONS] = {"x", "y", "z", "xyz"};
  return names[k];
}

static const char *binding_text(int b, char *buf, size_t cap) {
  if (b < 0)
    snprintf(buf, cap, "none");
  else
    snprintf(buf, cap, "%s of actuator %d", b >= 3 ? "current" : "voltage", b % 3 + 1);
  return buf;
}

static void print_pose(FILE *out, const char *label, const pom_cap_pose *p) {
  char bind[48];
  fprintf(out, "  %-10s (psi, theta, phi) = (%.3g, %.3g, %.3g) deg\n", label,
          p->euler[0] * DEG_PER_RAD, p->euler[1] * DEG_PER_RAD, p->euler[2] * DEG_PER_RAD);
  fprintf(out,
          "    acceleration  inscribed %10.0f deg/s^2   x %10.0f  y %10.0f  z %10.0f  "
          "(worst direction %.3f %.3f %.3f)\n",
          p->acc_inscribed * DEG_PER_RAD, p->acc_axis[0] * DEG_PER_RAD,
          p->acc_axis[1] * DEG_PER_RAD, p->acc_axis[2] * DEG_PER_RAD, p->acc_worst_dir[0],
          p->acc_worst_dir[1], p->acc_worst_dir[2]);
  fprintf(out,
          "    steady rate   inscribed %10.0f deg/s     x %10.0f  y %10.0f  z %10.0f  "
          "(worst direction %.3f %.3f %.3f, %s)\n",
          p->rate_inscribed * DEG_PER_RAD, p->rate_axis[0] * DEG_PER_RAD,
          p->rate_axis[1] * DEG_PER_RAD, p->rate_axis[2] * DEG_PER_RAD, p->rate_worst_dir[0],
          p->rate_worst_dir[1], p->rate_worst_dir[2], binding_text(p->rate_binding, bind, 48));
  fprintf(out,
          "    back-EMF only inscribed %10.0f deg/s     x %10.0f  y %10.0f  z %10.0f  "
          "(without the velocity-product terms)\n",
          p->rate_emf_inscribed * DEG_PER_RAD, p->rate_emf_axis[0] * DEG_PER_RAD,
          p->rate_emf_axis[1] * DEG_PER_RAD, p->rate_emf_axis[2] * DEG_PER_RAD);
}

/* "inf" or the number. */
static const char *num_text(double v, const char *fmt, char *buf, size_t cap) {
  if (isinf(v))
    snprintf(buf, cap, "%s", v > 0 ? "inf" : "-inf");
  else
    snprintf(buf, cap, fmt, v);
  return buf;
}

static void print_freq_pose(FILE *out, const char *label, const pom_cap_pose *p) {
  char pm[32], gm[32];
  fprintf(out, "  %-10s (psi, theta, phi) = (%.3g, %.3g, %.3g) deg\n", label,
          p->euler[0] * DEG_PER_RAD, p->euler[1] * DEG_PER_RAD, p->euler[2] * DEG_PER_RAD);
  if (!p->freq_ok) {
    fprintf(out, "    not evaluated\n");
    return;
  }
  fprintf(out,
          "    bandwidth (-3 dB) worst %8.2f Hz    x %8.2f  y %8.2f  z %8.2f Hz; resonant peak "
          "%.3g dB\n",
          p->bw_worst_hz, p->bw_axis_hz[0], p->bw_axis_hz[1], p->bw_axis_hz[2], p->peak_db_worst);
  fprintf(out,
          "    actuator loops    phase margin %s deg, gain margin %s dB (smallest of the three)\n",
          num_text(p->pm_deg_min, "%.1f", pm, sizeof pm),
          num_text(p->gm_db_min, "%.1f", gm, sizeof gm));
  if (isfinite(p->mode_hz))
    fprintf(out, "    lowest parasitic mode %.1f Hz (damping ratio %.3f)\n", p->mode_hz,
            p->mode_zeta);
  else
    fprintf(out, "    no parasitic mode (rigid joints)\n");
}

static void print_freq(FILE *out, const pom_cap_opts *o, const pom_cap_result *r) {
  if (o->bandwidth_grid <= 0) return;
  const int nb = o->bandwidth_grid < o->grid_points ? o->bandwidth_grid : o->grid_points;
  fprintf(out,
          "\nbandwidth and margins (small-signal closed loop, %s joints; %d x %d x %d sub-grid and "
          "the worst envelope poses: %d poses evaluated%s):\n",
          r->freq_joints == POM_JOINTS_RIGID ? "rigid" : "parasitic", nb, nb, nb, r->n_freq,
          r->n_freq_failed ? ", some failed" : "");
  if (r->n_freq_failed)
    fprintf(out, "  %d pose(s) failed (first: %s): their figures are left out\n", r->n_freq_failed,
            pom_status_name(r->freq_status));
  if (r->home >= 0) print_freq_pose(out, "home", &r->pose[r->home]);
  if (r->worst_bw >= 0 && r->worst_bw != r->home)
    print_freq_pose(out, "worst bw", &r->pose[r->worst_bw]);
  if (r->worst_pm >= 0 && r->worst_pm != r->worst_bw && r->worst_pm != r->home)
    print_freq_pose(out, "worst PM", &r->pose[r->worst_pm]);
}

void pom_cap_print_text(FILE *out, const char *name, const pom_cap_opts *o,
                        const pom_cap_result *r) {
  const int angular = pom_act_kind_desc(r->kind)->angular;
  int ok = 0;
  for (int k = 0; k < r->n_poses; ++k)
    ok += r->pose[k].ok;
  fprintf(out, "capability of %s (envelope and slews on rigid joints; docs/capability.md)\n", name);
  fprintf(
      out,
      "workspace: Euler cube +-%.4g deg, %d x %d x %d poses (step %.4g deg), %d of %d evaluated\n",
      r->half_width * DEG_PER_RAD, o->grid_points, o->grid_points, o->grid_points,
      r->step * DEG_PER_RAD, ok, r->n_poses);
  fprintf(out, "effort limit from rest: %.4g %s (K min(I_max, V/R_c)%s)\n\n", r->f_max,
          angular ? "N m" : "N", o->current_limit > 0 ? "" : ", no current limit");
  fprintf(out, "envelope (acceleration from rest, steady rate at the pose):\n");
  if (r->home >= 0 && r->pose[r->home].ok) print_pose(out, "home", &r->pose[r->home]);
  if (r->worst_acc >= 0) print_pose(out, "worst acc", &r->pose[r->worst_acc]);
  if (r->worst_rate >= 0 && r->worst_rate != r->worst_acc)
    print_pose(out, "worst rate", &r->pose[r->worst_rate]);
  if (r->n_dirs > 0) {
    fprintf(out, "\nslews from rest at home (controller and saturation, rigid joints):\n");
    fprintf(out, "  %-4s %9s %11s %13s %s\n", "axis", "amp deg", "time ms", "peak deg/s", "status");
    for (int k = 0; k < r->n_dirs; ++k) {
      const pom_cap_slew *s = &r->slew[k];
      for (int j = 0; j < s->n; ++j)
        fprintf(out, "  %-4s %9.3g %11.3f %13.0f %s%s\n", dir_name(k),
                s->amplitude[j] * DEG_PER_RAD, s->slew_time[j] * 1e3, s->peak_rate[j] * DEG_PER_RAD,
                s->status[j] == POM_OK ? "ok" : pom_status_name(s->status[j]),
                j == s->n - 1 ? " (workspace edge)" : "");
      if (s->n_beyond)
        fprintf(out, "  %-4s %d amplitude(s) asked for beyond the edge %.4g deg: not run\n",
                dir_name(k), s->n_beyond, s->edge * DEG_PER_RAD);
    }
  }
  print_freq(out, o, r);
  fprintf(out, "\n(%.2f s)\n", r->wall_time);
}

/* ---- JSON ---------------------------------------------------------------------------- */
static void json_pose(FILE *out, const pom_cap_pose *p) {
  fprintf(out, "{\"euler_zyx_rad\": ");
  pom_json_vec(out, p->euler, 3, 1.0);
  fprintf(out, ", \"ok\": %s, \"acc_inscribed_rad_per_s2\": ", p->ok ? "true" : "false");
  pom_json_number(out, p->acc_inscribed);
  fprintf(out, ", \"acc_axis_rad_per_s2\": ");
  pom_json_vec(out, p->acc_axis, 3, 1.0);
  fprintf(out, ", \"acc_worst_dir\": ");
  pom_json_vec(out, p->acc_worst_dir, 3, 1.0);
  fprintf(out, ", \"rate_inscribed_rad_per_s\": ");
  pom_json_number(out, p->rate_inscribed);
  fprintf(out, ", \"rate_axis_rad_per_s\": ");
  pom_json_vec(out, p->rate_axis, 3, 1.0);
  fprintf(out, ", \"rate_worst_dir\": ");
  pom_json_vec(out, p->rate_worst_dir, 3, 1.0);
  fprintf(out, ", \"rate_binding\": %d, \"rate_emf_inscribed_rad_per_s\": ", p->rate_binding);
  pom_json_number(out, p->rate_emf_inscribed);
  fprintf(out, ", \"rate_emf_axis_rad_per_s\": ");
  pom_json_vec(out, p->rate_emf_axis, 3, 1.0);
  fprintf(out, ", \"q\": ");
  pom_json_vec(out, p->q, 3, 1.0);
  fprintf(out, ", \"freq_ok\": %s, \"bw_axis_hz\": ", p->freq_ok ? "true" : "false");
  pom_json_vec(out, p->bw_axis_hz, 3, 1.0);
  const char *keys[] = {"bw_worst_hz", "peak_db_worst", "pm_deg_min",
                        "gm_db_min",   "mode_hz",       "mode_zeta"};
  const double vals[] = {p->bw_worst_hz, p->peak_db_worst, p->pm_deg_min,
                         p->gm_db_min,   p->mode_hz,       p->mode_zeta};
  for (int k = 0; k < 6; ++k) {
    fprintf(out, ", \"%s\": ", keys[k]);
    pom_json_number(out, vals[k]);
  }
  fprintf(out, "}");
}

void pom_cap_print_json(FILE *out, const char *name, const pom_cap_opts *o,
                        const pom_cap_result *r) {
  fprintf(out, "{\"name\": ");
  pom_json_string(out, name);
  fprintf(out, ", \"half_width_rad\": ");
  pom_json_number(out, r->half_width);
  fprintf(out, ", \"grid_points\": %d, \"step_rad\": ", o->grid_points);
  pom_json_number(out, r->step);
  fprintf(out, ", \"effort_limit\": ");
  pom_json_number(out, r->f_max);
  fprintf(out, ", \"effort_unit\": \"%s\", \"current_limit_A\": ",
          pom_act_kind_desc(r->kind)->angular ? "N m" : "N");
  pom_json_number(out, o->current_limit);
  fprintf(out, ", \"home\": ");
  if (r->home >= 0)
    json_pose(out, &r->pose[r->home]);
  else
    fprintf(out, "null");
  fprintf(out, ", \"worst_acc\": ");
  if (r->worst_acc >= 0)
    json_pose(out, &r->pose[r->worst_acc]);
  else
    fprintf(out, "null");
  fprintf(out, ", \"worst_rate\": ");
  if (r->worst_rate >= 0)
    json_pose(out, &r->pose[r->worst_rate]);
  else
    fprintf(out, "null");
  fprintf(out,
          ", \"bandwidth_joints\": \"%s\", \"bandwidth_grid_points\": %d, "
          "\"bandwidth_poses\": %d, \"bandwidth_failed\": %d, \"worst_bw\": ",
          r->freq_joints == POM_JOINTS_RIGID ? "rigid" : "parasitic", o->bandwidth_grid, r->n_freq,
          r->n_freq_failed);
  if (r->worst_bw >= 0)
    json_pose(out, &r->pose[r->worst_bw]);
  else
    fprintf(out, "null");
  fprintf(out, ", \"worst_pm\": ");
  if (r->worst_pm >= 0)
    json_pose(out, &r->pose[r->worst_pm]);
  else
    fprintf(out, "null");
  fprintf(out, ", \"bw_worst_hz\": ");
  pom_json_number(out, r->bw_worst_hz);
  fprintf(out, ", \"pm_worst_deg\": ");
  pom_json_number(out, r->pm_worst_deg);
  fprintf(out, ", \"slews\": [");
  for (int k = 0; k < r->n_dirs; ++k) {
    const pom_cap_slew *s = &r->slew[k];
    fprintf(out, "%s{\"axis\": \"%s\", \"dir\": ", k ? ", " : "", dir_name(k));
    pom_json_vec(out, s->dir, 3, 1.0);
    fprintf(out, ", \"edge_rad\": ");
    pom_json_number(out, s->edge);
    fprintf(out, ", \"amplitude_rad\": ");
    pom_json_vec(out, s->amplitude, s->n, 1.0);
    fprintf(out, ", \"slew_time_s\": ");
    pom_json_vec(out, s->slew_time, s->n, 1.0);
    fprintf(out, ", \"peak_rate_rad_per_s\": ");
    pom_json_vec(out, s->peak_rate, s->n, 1.0);
    fprintf(out, ", \"status\": [");
    for (int j = 0; j < s->n; ++j)
      fprintf(out, "%s\"%s\"", j ? ", " : "", pom_status_name(s->status[j]));
    fprintf(out, "], \"beyond_edge\": %d}", s->n_beyond);
  }
  fprintf(out, "], \"wall_time_s\": ");
  pom_json_number(out, r->wall_time);
  fprintf(out, "}\n");
}

/* ---- CSV of the grid ------------------------------------------------------------------ */
pom_status pom_cap_write_csv(const char *path, const pom_cap_result *r, pom_error *err) {
  FILE *f = fopen(path, "w");
  if (!f) POM_FAIL(err, POM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
  fprintf(f, "psi_deg,theta_deg,phi_deg,ok,acc_inscribed_deg_s2,acc_x_deg_s2,acc_y_deg_s2,"
             "acc_z_deg_s2,rate_inscribed_deg_s,rate_x_deg_s,rate_y_deg_s,rate_z_deg_s,"
             "bw_worst_hz,bw_x_hz,bw_y_hz,bw_z_hz,pm_deg_min\n");
  for (int k = 0; k < r->n_poses; ++k) {
    const pom_cap_pose *p = &r->pose[k];
    fprintf(f, "%.10g,%.10g,%.10g,%d", p->euler[0] * DEG_PER_RAD, p->euler[1] * DEG_PER_RAD,
            p->euler[2] * DEG_PER_RAD, p->ok);
    const double v[8] = {p->acc_inscribed,  p->acc_axis[0],  p->acc_axis[1],  p->acc_axis[2],
                         p->rate_inscribed, p->rate_axis[0], p->rate_axis[1], p->rate_axis[2]};
    for (int j = 0; j < 8; ++j)
      fprintf(f, p->ok ? ",%.10g" : ",nan", v[j] * DEG_PER_RAD);
    const double b[5] = {p->bw_worst_hz, p->bw_axis_hz[0], p->bw_axis_hz[1], p->bw_axis_hz[2],
                         p->pm_deg_min};
    for (int j = 0; j < 5; ++j)
      fprintf(f, p->freq_ok && isfinite(b[j]) ? ",%.10g" : ",nan", b[j]);
    fprintf(f, "\n");
  }
  if (ferror(f) | fclose(f)) POM_FAIL(err, POM_ERR_IO, "writing '%s' failed", path);
  return POM_OK;
}
