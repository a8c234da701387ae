/* cli_kin.c - helpers shared by the kinematics subcommands. */
#include "cli_kin.h"

#include "pom_arch.h"
#include "pom_cli.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>

int pom_cli_kin_check_unknown(const pom_cfg *cfg, const char *const *const scopes[]) {
  pom_error err;
  pom_error_clear(&err);
  if (pom_cli_check_unknown(cfg, scopes, &err) != POM_OK) {
    pom_cli_report("config", &err);
    return 2;
  }
  return 0;
}

int pom_cli_kin_load(const char *path, pom_cfg **cfg_out, pom_kin_arch *arch, pom_kin_ws_opts *ws,
                     const char *const *const check_scopes[]) {
  pom_error err;
  pom_error_clear(&err);
  *cfg_out = NULL;
  pom_cfg *cfg = pom_cli_load_config(path);
  if (!cfg) return 2;
  pom_status st = pom_kin_arch_load(arch, cfg, &err);
  if (st == POM_OK && ws) st = pom_kin_ws_load(ws, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_cfg_destroy(cfg);
    return pom_cli_exit_code(st);
  }
  if (check_scopes) {
    int rc = pom_cli_kin_check_unknown(cfg, check_scopes);
    if (rc) {
      pom_cfg_destroy(cfg);
      return rc;
    }
  }
  *cfg_out = cfg;
  return 0;
}

/* ---- pose reports ------------------------------------------------------------ */
void pom_cli_kin_print_limits(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p) {
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch->type));
  fprintf(out, "limits:\n");
  fprintf(out, "  %-17s +-%-8.4g %-4s q = %9.4f %9.4f %9.4f %s\n",
          u->kind_name[0] == 'r' ? "actuator range" : "stroke", 0.5 * arch->stroke * u->to_display,
          u->display, p->q[0] * u->to_display, p->q[1] * u->to_display, p->q[2] * u->to_display,
          u->display);
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_kin_limit_desc *ld = &arch->type->limits[kind];
    if (!ld->name) continue;
    const double *v = p->limit + 3 * kind, f = ld->to_display;
    fprintf(out, "  %-14s %s %8.4g %-4s %s = %.3f %.3f %.3f %s\n", ld->name,
            ld->lower ? ">=" : "<=", arch->limit_bound[kind] * f, ld->unit,
            ld->per_pair ? "1-2, 2-3, 3-1" : "limbs 1, 2, 3", v[0] * f, v[1] * f, v[2] * f,
            ld->unit);
  }
  char buf[512];
  pom_kin_violations_text(arch, p->violations, buf, sizeof buf);
  fprintf(out, "  violated: %s\n", buf);
}

void pom_cli_kin_pose_json(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p) {
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch->type));
  fprintf(
      out,
      "\"actuator_kind\": \"%s\",\n  \"actuator_unit\": \"%s\",\n  \"display_unit\": \"%s\",\n  ",
      u->kind_name, u->si, u->display);
  fprintf(out, "\"reachable\": %s,\n  \"unreachable_limb\": ", p->reachable ? "true" : "false");
  if (p->unreachable_limb >= 0) {
    fprintf(out, "%d", p->unreachable_limb + 1);
  } else {
    fputs("null", out);
  }
  if (!p->reachable) {
    /* nothing about the pose is defined beyond which limb failed */
    fputs(",\n  \"q\": null,\n  \"q_display\": null,\n  \"jacobian\": null,\n  "
          "\"singular_values\": null,\n  \"kappa\": null,\n  \"dexterity\": null",
          out);
    for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind)
      if (arch->type->limits[kind].name)
        fprintf(out, ",\n  \"%s\": null", arch->type->limits[kind].json);
    fputs(",\n  \"within_limits\": false,\n  \"violations\": []", out);
    return;
  }
  fputs(",\n  \"q\": ", out);
  pom_json_vec(out, p->q, 3, 1.0);
  fputs(",\n  \"q_display\": ", out);
  pom_json_vec(out, p->q, 3, u->to_display);
  fputs(",\n  \"jacobian\": ", out);
  pom_json_mat3(out, p->J, 1.0);
  fputs(",\n  \"singular_values\": ", out);
  pom_json_vec(out, p->sv, 3, 1.0);
  fputs(",\n  \"kappa\": ", out);
  pom_json_number(out, p->kappa);
  fputs(",\n  \"dexterity\": ", out);
  pom_json_number(out, p->dexterity);
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_kin_limit_desc *ld = &arch->type->limits[kind];
    if (!ld->name) continue;
    fprintf(out, ",\n  \"%s\": ", ld->json);
    pom_json_vec(out, p->limit + 3 * kind, 3, ld->to_display);
  }
  fprintf(out, ",\n  \"within_limits\": %s,\n  \"violations\": [",
          p->reachable && p->violations == 0 ? "true" : "false");
  int first = 1;
  char name[64];
  for (int k = 0; k < POM_KIN_LIM_COUNT; ++k) {
    if (!(p->violations & (1u << k))) continue;
    if (!first) fputs(", ", out);
    pom_json_string(out, pom_kin_limit_name(arch, k, name, sizeof name));
    first = 0;
  }
  fputc(']', out);
}
