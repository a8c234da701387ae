/* kin_ws_print.c - the regular dexterous workspace's report as text and
 * JSON, the dexterity map as CSV, and this machine's pose rate
 * (pom_kin_print.h; what `pomlab workspace` prints and writes,
 * docs/kinematics.md section 6). */
#include "pom_kin_print.h"

#include "pom_arch.h"
#include "pom_io.h"
#include "pom_json.h"
#include "pom_math.h"

#include <math.h>

const char *pom_kin_ws_reason_text(const pom_kin_arch *arch, const pom_kin_ws_result *r,
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

/* Poses per second of this machine on this architecture, from a 8^3 grid of
 * poses within 4 deg of home (a few milliseconds). */
double pom_kin_pose_rate(const pom_kin_arch *arch) {
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

pom_status pom_kin_ws_map_write(const char *file, const pom_kin_arch *arch,
                                const pom_kin_ws_opts *o, pom_progress *bar, pom_error *err) {
  pom_io_file w;
  POM_TRY(pom_io_create(&w, file, err));
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
  return pom_io_commit(&w, err);
}

void pom_kin_ws_report_print(FILE *out, int json, const pom_kin_arch *arch,
                             const pom_kin_ws_opts *o, const pom_kin_ws_result *r,
                             const pom_kin_ws_report *rep) {
  char why[512];
  pom_kin_ws_reason_text(arch, r, o, why, sizeof why);
  if (json) {
    fprintf(out, "{\n  \"config\": ");
    pom_json_string(out, rep->config);
    fprintf(out, ",\n  \"name\": ");
    pom_json_string(out, arch->name);
    fprintf(out, ",\n  \"architecture\": \"%s\",\n  \"shape\": \"euler_zyx_cube\",\n",
            pom_kin_arch_name(arch));
    fprintf(out, "  \"dexterity_min\": ");
    pom_json_number(out, o->dexterity_min);
    fprintf(out, ",\n  \"resolution_deg\": ");
    pom_json_number(out, o->resolution / POM_DEG);
    fprintf(out, ",\n  \"check_limits\": %s,\n  \"half_width_deg\": ",
            o->check_limits ? "true" : "false");
    pom_json_number(out, r->half_width / POM_DEG);
    fprintf(out, ",\n  \"capped\": %s,\n  \"budget_reached\": %s,\n  \"max_poses\": ",
            r->capped ? "true" : "false", r->budget_reached ? "true" : "false");
    pom_json_number(out, o->max_poses);
    fprintf(out, ",\n  \"min_dexterity\": ");
    pom_json_number(out, r->min_dexterity);
    fprintf(out, ",\n  \"first_failure\": ");
    if (r->capped || r->budget_reached) {
      fprintf(out, "null");
    } else {
      fprintf(out, "{\"euler_zyx_deg\": ");
      pom_json_vec(out, r->fail_euler, 3, 1.0 / POM_DEG);
      fprintf(out, ", \"reason\": ");
      pom_json_string(out, why);
      fprintf(out, "}");
    }
    fprintf(out, ",\n  \"gci\": ");
    pom_json_number(out, rep->gci);
    fprintf(out, ",\n  \"gci_half_width_deg\": ");
    pom_json_number(out, rep->gci_half_width / POM_DEG);
    fprintf(out, ",\n  \"gci_usable_fraction\": ");
    pom_json_number(out, rep->gci_usable);
    fprintf(out, ",\n  \"poses_evaluated\": %ld,\n  \"map\": ", r->poses);
    if (rep->map) {
      pom_json_string(out, rep->map);
    } else {
      fprintf(out, "null");
    }
    fprintf(out, "\n}\n");
  } else {
    fprintf(out, "%s (%s), config %s\n", arch->name, pom_kin_arch_name(arch), rep->config);
    fprintf(out,
            "regular dexterous workspace (ZYX Euler cube about home, step %g deg,\n"
            "  1/kappa >= %g, limits %s):\n",
            o->resolution / POM_DEG, o->dexterity_min, o->check_limits ? "checked" : "ignored");
    fprintf(out, "  half-width:        %s+-%g deg%s\n", r->budget_reached ? "at least " : "",
            r->half_width / POM_DEG,
            r->capped           ? " (search cap reached)"
            : r->budget_reached ? " (search stopped at workspace.max_poses)"
                                : "");
    fprintf(out, "  min dexterity:     %.4f\n", r->min_dexterity);
    if (!r->capped && !r->budget_reached)
      fprintf(out, "  first failure:     psi = %g, theta = %g, phi = %g deg: %s\n",
              r->fail_euler[0] / POM_DEG, r->fail_euler[1] / POM_DEG, r->fail_euler[2] / POM_DEG,
              why);
    fprintf(out, "  poses evaluated:   %ld\n", r->poses);
    fprintf(out, "global conditioning index over +-%g deg: %.4f (usable fraction %.4f)\n",
            rep->gci_half_width / POM_DEG, rep->gci, rep->gci_usable);
    if (rep->map) fprintf(out, "dexterity map written to %s\n", rep->map);
  }
}
