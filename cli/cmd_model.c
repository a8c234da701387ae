/* cmd_model.c - pomlab model: the resolved mechanism in SI units, fixed frame
 * at the home pose. The kinematic part (geometry, limits, bodies, joints,
 * actuator axes) is printed by model_mechanism_*; the dynamics groups
 * (actuator electrics, controller gains, joints, scene) are added by the
 * dynamics module in the marked places. */
#include "cli_opts.h"
#include "pom_dyn_print.h"
#include "cli_kin.h"
#include "pom_arch.h"
#include "pom_cli.h"
#include "pom_math.h"

#include <stdio.h>
#include <string.h>

/* ---- kinematic part: JSON ---------------------------------------------------- */
static void points_json(const char *key, const double p[3][3], int last) {
  printf("    \"%s\": [", key);
  for (int i = 0; i < 3; ++i) {
    if (i) printf(", ");
    pom_json_vec(stdout, p[i], 3, 1.0);
  }
  printf("]%s\n", last ? "" : ",");
}

/* Prints the members "geometry", "limits" and "mechanism" of the top-level
 * object (no surrounding braces, no trailing comma). Generic over the
 * architecture: its type's tables name every value (pom_arch.h). */
static void model_mechanism_json(const pom_kin_arch *a, const pom_mechanism *m) {
  const pom_kin_arch_type *t = a->type;
  const pom_act_desc *u = pom_act_kind_desc(t->actuator);
  printf("  \"geometry\": {\n    \"mode\": \"%s\",\n", a->has_design ? "parameters" : "points");
  printf("    \"scale_m\": ");
  pom_json_number(stdout, a->design.scale);
  printf(", \"scale_key\": \"%s\",\n", t->scale_key);
  if (a->has_design) {
    printf("    \"design\": {");
    for (int k = 0; k < t->n_params; ++k) {
      printf("%s\"%s\": ", k ? ", " : "", t->params[k].key);
      pom_json_number(stdout, a->design.x[k] / t->params[k].to_si);
    }
    printf("},\n");
  }
  for (int k = 0; k < t->n_points; ++k) {
    const double(*p)[3] =
        (const double(*)[3])(const void *)((const char *)a->data + t->points[k].offset);
    points_json(t->points[k].key, p, k + 1 == t->n_points);
  }
  printf("  },\n  \"limits\": {\"stroke\": ");
  pom_json_number(stdout, a->stroke);
  printf(", \"stroke_unit\": \"%s\"", u->si);
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_kin_limit_desc *ld = &t->limits[kind];
    if (!ld->name) continue;
    printf(", \"%s\": ", ld->key);
    pom_json_number(stdout, a->limit_bound[kind] * ld->to_display);
  }
  printf("},\n  \"mechanism\": {\n    \"gravity_mps2\": ");
  pom_json_vec(stdout, m->gravity, 3, 1.0);
  printf(",\n    \"platform\": %d,\n    \"bodies\": [\n", m->platform);
  for (int b = 0; b < m->n_bodies; ++b) {
    const pom_mech_body *body = &m->body[b];
    printf("      {\"index\": %d, \"name\": ", b);
    pom_json_string(stdout, body->name);
    printf(", \"mass_kg\": ");
    pom_json_number(stdout, body->mass);
    printf(", \"cm_m\": ");
    pom_json_vec(stdout, body->cm, 3, 1.0);
    printf(", \"inertia_kgm2\": ");
    pom_json_mat3(stdout, body->inertia, 1.0);
    printf("}%s\n", b + 1 < m->n_bodies ? "," : "");
  }
  printf("    ],\n    \"joints\": [\n");
  for (int j = 0; j < m->n_joints; ++j) {
    const pom_mech_joint *jt = &m->joint[j];
    printf("      {\"index\": %d, \"name\": ", j);
    pom_json_string(stdout, jt->name);
    printf(", \"type\": \"%s\", \"bodies\": [%d, %d], \"body_names\": [",
           pom_joint_type_name(jt->type), jt->body[0], jt->body[1]);
    pom_json_string(stdout, m->body[jt->body[0]].name);
    printf(", ");
    pom_json_string(stdout, m->body[jt->body[1]].name);
    printf("], \"point_m\": ");
    pom_json_vec(stdout, jt->point, 3, 1.0);
    printf(", \"axis\": ");
    if (jt->type == POM_JOINT_SPHERICAL) {
      printf("null");
    } else {
      pom_json_vec(stdout, jt->axis, 3, 1.0);
    }
    printf(", \"axis2\": ");
    if (jt->type == POM_JOINT_UNIVERSAL) {
      pom_json_vec(stdout, jt->axis2, 3, 1.0);
    } else {
      printf("null");
    }
    printf(", \"actuator\": ");
    if (jt->actuator >= 0) {
      printf("%d", jt->actuator);
    } else {
      printf("null");
    }
    printf("}%s\n", j + 1 < m->n_joints ? "," : "");
  }
  printf("    ],\n    \"actuators\": [\n");
  for (int k = 0; k < m->n_actuators; ++k) {
    const pom_mech_actuator *ac = &m->actuator[k];
    printf("      {\"index\": %d, \"joint\": %d, \"joint_name\": ", k, ac->joint);
    pom_json_string(stdout, m->joint[ac->joint].name);
    const pom_act_desc *au = pom_act_kind_desc(ac->kind);
    printf(", \"kind\": \"%s\", \"moving_body\": %d, \"axis\": ", au->kind_name, ac->moving_body);
    pom_json_vec(stdout, m->joint[ac->joint].axis, 3, 1.0);
    printf(", \"stroke\": ");
    pom_json_number(stdout, ac->stroke);
    printf(", \"unit\": \"%s\", \"effort_unit\": \"%s\"", au->si, au->effort);
    printf("}%s\n", k + 1 < m->n_actuators ? "," : "");
  }
  printf("    ]\n  }");
}

/* ---- kinematic part: human text ------------------------------------------------ */
static void model_mechanism_text(const pom_kin_arch *a, const pom_mechanism *m) {
  const pom_kin_arch_type *t = a->type;
  const pom_act_desc *u = pom_act_kind_desc(t->actuator);
  printf("geometry (%s form), fixed frame at home:\n",
         a->has_design ? "design parameters" : "explicit points");
  printf("  scale: %s = %.6g mm (%s)\n", t->scale_key, a->design.scale * 1e3, t->scale_meaning);
  if (a->has_design)
    for (int k = 0; k < t->n_params; ++k)
      printf("  %-22s = %.6g\n", t->params[k].key, a->design.x[k] / t->params[k].to_si);
  for (int k = 0; k < t->n_points; ++k) {
    const double(*p)[3] =
        (const double(*)[3])(const void *)((const char *)a->data + t->points[k].offset);
    /* metre-valued point sets are printed in mm, unit axes as they are */
    int metres = strstr(t->points[k].key, "_m") != NULL;
    double f = metres ? 1e3 : 1.0;
    printf("  %-18s%s", t->points[k].key, metres ? " (mm)" : "     ");
    for (int i = 0; i < 3; ++i)
      printf("  (%8.3f %8.3f %8.3f)", p[i][0] * f, p[i][1] * f, p[i][2] * f);
    printf("\n");
  }
  printf("limits: %s +-%.6g %s", u->range_word, 0.5 * a->stroke * u->to_display, u->display);
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_kin_limit_desc *ld = &t->limits[kind];
    if (!ld->name) continue;
    printf(", %s %s %.4g %s", ld->name,
           ld->lower ? ">=" : "<=", a->limit_bound[kind] * ld->to_display, ld->unit);
  }
  printf("\n");
  printf("gravity (m/s^2): %g %g %g\n", m->gravity[0], m->gravity[1], m->gravity[2]);
  printf("bodies (mass in kg, CM in mm, inertia about the CM in kg m^2, fixed axes):\n");
  for (int b = 0; b < m->n_bodies; ++b) {
    const pom_mech_body *body = &m->body[b];
    const double *I = body->inertia;
    printf("  %2d %-10s m = %-9.4g CM = (%8.3f %8.3f %8.3f)  I = [%.3e %.3e %.3e; %.3e %.3e "
           "%.3e; %.3e %.3e %.3e]\n",
           b, body->name, body->mass, body->cm[0] * 1e3, body->cm[1] * 1e3, body->cm[2] * 1e3, I[0],
           I[1], I[2], I[3], I[4], I[5], I[6], I[7], I[8]);
  }
  printf("joints (point in mm):\n");
  for (int j = 0; j < m->n_joints; ++j) {
    const pom_mech_joint *jt = &m->joint[j];
    printf("  %2d %-4s %-10s %-10s - %-10s at (%8.3f %8.3f %8.3f)", j, jt->name,
           pom_joint_type_name(jt->type), m->body[jt->body[0]].name, m->body[jt->body[1]].name,
           jt->point[0] * 1e3, jt->point[1] * 1e3, jt->point[2] * 1e3);
    if (jt->type != POM_JOINT_SPHERICAL)
      printf("  axis (%6.3f %6.3f %6.3f)", jt->axis[0], jt->axis[1], jt->axis[2]);
    if (jt->type == POM_JOINT_UNIVERSAL)
      printf("  axis2 (%6.3f %6.3f %6.3f)", jt->axis2[0], jt->axis2[1], jt->axis2[2]);
    if (jt->actuator >= 0) printf("  actuator %d", jt->actuator);
    printf("\n");
  }
  printf("actuators:\n");
  for (int k = 0; k < m->n_actuators; ++k) {
    const pom_mech_actuator *ac = &m->actuator[k];
    const double *ax = m->joint[ac->joint].axis;
    const pom_act_desc *au = pom_act_kind_desc(ac->kind);
    printf("  %d %s joint %s, moves %s, axis (%6.3f %6.3f %6.3f), range +-%.4g %s\n", k,
           au->kind_name, m->joint[ac->joint].name, m->body[ac->moving_body].name, ax[0], ax[1],
           ax[2], 0.5 * ac->stroke * au->to_display, au->display);
  }
}

/* ---- the registry ---------------------------------------------------------------- */
static int list_architectures(int json) {
  int n = pom_kin_arch_type_count();
  if (json) printf("{\n  \"architectures\": [\n");
  for (int k = 0; k < n; ++k) {
    const pom_kin_arch_type *t = pom_kin_arch_type_at(k);
    const pom_act_desc *u = pom_act_kind_desc(t->actuator);
    if (json) {
      printf("    {\"name\": ");
      pom_json_string(stdout, t->name);
      printf(", \"label\": ");
      pom_json_string(stdout, t->label);
      printf(", \"description\": ");
      pom_json_string(stdout, t->description);
      printf(", \"actuator_kind\": \"%s\", \"actuator_unit\": \"%s\", \"scale_key\": ",
             u->kind_name, u->si);
      pom_json_string(stdout, t->scale_key);
      printf(", \"parameters\": [");
      for (int i = 0; i < t->n_params; ++i) {
        printf("%s", i ? ", " : "");
        pom_json_string(stdout, t->params[i].key);
      }
      printf("], \"synthesis_variables\": [");
      int first = 1;
      for (int i = 0; i < t->n_params; ++i) {
        if (!t->params[i].synth) continue;
        printf("%s", first ? "" : ", ");
        pom_json_string(stdout, t->params[i].key);
        first = 0;
      }
      printf("]}%s\n", k + 1 < n ? "," : "");
    } else {
      printf("%-6s %-9s %s actuators (q in %s); %s\n", t->name, t->label, u->kind_name, u->display,
             t->description);
      printf("       scale %s: %s\n", t->scale_key, t->scale_meaning);
      for (int i = 0; i < t->n_params; ++i)
        printf("       geometry.%-22s %s%s\n", t->params[i].key, t->params[i].meaning,
               t->params[i].synth ? " [synthesis variable]" : "");
      for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind)
        if (t->limits[kind].name)
          printf("       limits.%-24s %s (%s)\n", t->limits[kind].key, t->limits[kind].name,
                 t->limits[kind].lower ? "a lower bound" : "an upper bound");
    }
  }
  if (json) printf("  ]\n}\n");
  return 0;
}

int pom_cmd_model(int argc, char **argv) {
  int list = 0;
  const char *path = NULL;
  int json = 0;
  const pom_opt opts[] = {
      {.name = "--json",
       .kind = POM_OPT_FLAG,
       .help = "machine-readable output on stdout",
       .flag = &json,
       .set = 1},
      {.name = "--list-architectures",
       .kind = POM_OPT_FLAG,
       .help = "the registered architectures: name, actuator kind, scale, design parameters and "
               "limits (docs/extending.md)",
       .flag = &list,
       .set = 1},
      {.name = "--list-controllers",
       .kind = POM_OPT_FLAG,
       .help = "the registered controllers: states, options and gains with unit, range, default "
               "and whether tuning searches them",
       .flag = &list,
       .set = 2},
  };
  const pom_cli_spec spec = {
      .name = "model",
      .usage = "CONFIG [--json]\n"
               "       pomlab model --list-architectures [--json]\n"
               "       pomlab model --list-controllers [--json]",
      .about = "The resolved mechanism at the home pose (R = I, actuators at mid-stroke), in\n"
               "the fixed frame (text: lengths in mm, angles in deg, masses in kg, inertias in\n"
               "kg m^2; --json: SI, m and rad): geometry and limits, every body\n"
               "with mass, centre of mass and inertia tensor about the CM, every joint with\n"
               "type, bodies, location and axes, every actuator with axis and stroke. Complete\n"
               "enough for another program to rebuild the mechanism.",
      .notes = "Validates the config groups name, architecture, geometry, limits, workspace,\n"
               "inertia, and the dynamics groups actuator, controller, joints, scene, solver,\n"
               "maneuver (printed after the mechanism). Exit status: 0 ok; 2 usage or config\n"
               "error.",
      .opts = opts,
      .n_opts = POM_CLI_N(opts),
      .args = &path,
      .max_args = 1};
  int prc = pom_cli_opts_parse(&spec, argc, argv, 0);
  if (prc >= 0) return prc;
  if (list == 2) {
    pom_dyn_ctrl_list(stdout, json);
    return 0;
  }
  if (list) return list_architectures(json);
  if (!path) {
    fprintf(stderr, "pomlab model: missing CONFIG\n");
    pom_cli_opts_usage(&spec, stderr);
    return 2;
  }
  pom_cfg *cfg = NULL;
  pom_kin_arch arch;
  pom_kin_ws_opts ws;
  int rc = pom_cli_kin_load(path, &cfg, &arch, &ws, NULL);
  if (rc) return rc;
  pom_error err;
  pom_error_clear(&err);
  pom_mechanism mech;
  pom_status st = pom_kin_mechanism_build(&mech, &arch, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_cfg_destroy(cfg);
    return pom_cli_exit_code(st);
  }
  /* dynamics: the actuator/controller/joints/scene/solver/maneuver groups */
  pom_dyn_params dyn;
  pom_dyn_params_defaults(&dyn);
  st = pom_dyn_params_load(&dyn, cfg, &err);
  if (st != POM_OK) {
    pom_cli_report("config", &err);
    pom_cfg_destroy(cfg);
    return pom_cli_exit_code(st);
  }
  /* unknown keys in every group model reads: the model's and the workspace's */
  const char *const *const scopes[] = {pom_kin_model_groups(), pom_kin_ws_groups(),
                                       pom_dyn_param_groups(), NULL};
  rc = pom_cli_kin_check_unknown(cfg, scopes);
  pom_cfg_destroy(cfg);
  if (rc) return rc;

  if (json) {
    printf("{\n  \"config\": ");
    pom_json_string(stdout, path);
    printf(",\n  \"name\": ");
    pom_json_string(stdout, arch.name);
    printf(",\n  \"architecture\": \"%s\",\n", pom_kin_arch_name(&arch));
    printf("  \"units\": \"SI (m, kg, kg m^2, rad, m/s^2); fixed frame at the home pose\",\n");
    model_mechanism_json(&arch, &mech);
    pom_dyn_params_json(stdout, &dyn);
    printf("\n}\n");
  } else {
    printf("%s (%s), config %s\n", arch.name, pom_kin_arch_name(&arch), path);
    model_mechanism_text(&arch, &mech);
    pom_dyn_params_text(stdout, &dyn);
  }
  return 0;
}
