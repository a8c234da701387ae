/* cli_kin.c - helpers shared by the kinematics subcommands. */
#include "cli_kin.h"

#include "pom_cli.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>

const char *const pom_cli_kin_scopes[] = {"name", "architecture", "geometry", "limits", NULL};

int pom_cli_kin_check_unknown(const pom_cfg *cfg, const char *const scopes[]) {
  pom_error err;
  pom_error_clear(&err);
  if (pom_cfg_check_unknown(cfg, scopes, pom_cli_known_top, &err) != POM_OK) {
    pom_cli_report("config", &err);
    return 2;
  }
  return 0;
}

int pom_cli_kin_load(const char *path, pom_cfg **cfg_out, pom_kin_arch *arch, pom_kin_ws_opts *ws,
                     const char *const check_scopes[]) {
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

/* ---- JSON ------------------------------------------------------------------ */
void pom_json_string(FILE *out, const char *s) {
  fputc('"', out);
  for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
    if (*p == '"' || *p == '\\') {
      fprintf(out, "\\%c", *p);
    } else if (*p < 0x20) {
      fprintf(out, "\\u%04x", *p);
    } else {
      fputc(*p, out);
    }
  }
  fputc('"', out);
}

void pom_json_number(FILE *out, double v) {
  if (isfinite(v)) {
    fprintf(out, "%.17g", v);
  } else {
    fputs("null", out);
  }
}

void pom_json_vec(FILE *out, const double *v, int n, double scale) {
  fputc('[', out);
  for (int k = 0; k < n; ++k) {
    if (k) fputs(", ", out);
    pom_json_number(out, v[k] * scale);
  }
  fputc(']', out);
}

void pom_json_mat3(FILE *out, const double M[9], double scale) {
  fputc('[', out);
  for (int r = 0; r < 3; ++r) {
    if (r) fputs(", ", out);
    pom_json_vec(out, M + 3 * r, 3, scale);
  }
  fputc(']', out);
}

/* ---- pose reports ------------------------------------------------------------ */
void pom_cli_kin_print_limits(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p) {
  fprintf(out, "limits:\n");
  fprintf(out, "  stroke            +-%.4g mm        q = %9.4f %9.4f %9.4f mm\n",
          0.5 * arch->stroke * 1e3, p->q[0] * 1e3, p->q[1] * 1e3, p->q[2] * 1e3);
  fprintf(out, "  base cone         %8.4g deg      angle = %7.3f %7.3f %7.3f deg\n",
          arch->cone_base_max / POM_DEG, p->cone_base[0] / POM_DEG, p->cone_base[1] / POM_DEG,
          p->cone_base[2] / POM_DEG);
  fprintf(out, "  platform cone     %8.4g deg      angle = %7.3f %7.3f %7.3f deg\n",
          arch->cone_platform_max / POM_DEG, p->cone_platform[0] / POM_DEG,
          p->cone_platform[1] / POM_DEG, p->cone_platform[2] / POM_DEG);
  fprintf(out, "  limb distance  >= %8.4g mm       1-2, 2-3, 3-1 = %.3f %.3f %.3f mm\n",
          arch->min_limb_distance * 1e3, p->limb_distance[0] * 1e3, p->limb_distance[1] * 1e3,
          p->limb_distance[2] * 1e3);
  char buf[512];
  pom_kin_violations_text(p->violations, buf, sizeof buf);
  fprintf(out, "  violated: %s\n", buf);
}

void pom_cli_kin_pose_json(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p) {
  (void)arch;
  fprintf(out, "\"reachable\": %s,\n  \"unreachable_limb\": ", p->reachable ? "true" : "false");
  if (p->unreachable_limb >= 0) {
    fprintf(out, "%d", p->unreachable_limb + 1);
  } else {
    fputs("null", out);
  }
  if (!p->reachable) {
    /* nothing about the pose is defined beyond which limb failed */
    fputs(",\n  \"q_m\": null,\n  \"q_mm\": null,\n  \"jacobian_m_per_rad\": null,\n  "
          "\"singular_values_m_per_rad\": null,\n  \"kappa\": null,\n  \"dexterity\": null,\n  "
          "\"cone_base_deg\": null,\n  \"cone_platform_deg\": null,\n  \"limb_distance_mm\": "
          "null,\n  \"within_limits\": false,\n  \"violations\": []",
          out);
    return;
  }
  fputs(",\n  \"q_m\": ", out);
  pom_json_vec(out, p->q, 3, 1.0);
  fputs(",\n  \"q_mm\": ", out);
  pom_json_vec(out, p->q, 3, 1e3);
  fputs(",\n  \"jacobian_m_per_rad\": ", out);
  pom_json_mat3(out, p->J, 1.0);
  fputs(",\n  \"singular_values_m_per_rad\": ", out);
  pom_json_vec(out, p->sv, 3, 1.0);
  fputs(",\n  \"kappa\": ", out);
  pom_json_number(out, p->kappa);
  fputs(",\n  \"dexterity\": ", out);
  pom_json_number(out, p->dexterity);
  fputs(",\n  \"cone_base_deg\": ", out);
  pom_json_vec(out, p->cone_base, 3, 1.0 / POM_DEG);
  fputs(",\n  \"cone_platform_deg\": ", out);
  pom_json_vec(out, p->cone_platform, 3, 1.0 / POM_DEG);
  fputs(",\n  \"limb_distance_mm\": ", out);
  pom_json_vec(out, p->limb_distance, 3, 1e3);
  fprintf(out, ",\n  \"within_limits\": %s,\n  \"violations\": [",
          p->reachable && p->violations == 0 ? "true" : "false");
  int first = 1;
  for (int k = 0; k < POM_KIN_LIM_COUNT; ++k) {
    if (!(p->violations & (1u << k))) continue;
    if (!first) fputs(", ", out);
    pom_json_string(out, pom_kin_limit_name(k));
    first = 0;
  }
  fputc(']', out);
}
