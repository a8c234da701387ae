/* cmd_model.c - pomlab model: the resolved mechanism in SI units, fixed frame
 * at the home pose. The kinematic part (geometry, limits, bodies, joints,
 * actuator axes) is printed by model_mechanism_*; the dynamics groups
 * (actuator electrics, controller gains, joints, scene) are added by the
 * dynamics module in the marked places. */
#include "cli_dyn.h"
#include "cli_kin.h"
#include "pom_cli.h"
#include "pom_math.h"

#include <stdio.h>
#include <string.h>

/* groups validated by `model` (unknown keys rejected in these) */
static const char *const model_scopes[] = {
    "name",       "architecture", "geometry", "limits", "workspace", "inertia", "actuator",
    "controller", "joints",       "scene",    "solver", "maneuver",  NULL};

static void model_usage(FILE *out) {
  fprintf(out, "usage: pomlab model CONFIG [--json]\n\n"
               "The resolved mechanism at the home pose (R = I, actuators at mid-stroke), in\n"
               "the fixed frame (text: lengths in mm, angles in deg, masses in kg, inertias in\n"
               "kg m^2; --json: SI, m and rad): geometry and limits, every body\n"
               "with mass, centre of mass and inertia tensor about the CM, every joint with\n"
               "type, bodies, location and axes, every actuator with axis and stroke. Complete\n"
               "enough for another program to rebuild the mechanism.\n\n"
               "  --json   machine-readable output on stdout\n"
               "  --help   this text\n\n"
               "Validates the config groups name, architecture, geometry, limits, workspace,\n"
               "inertia, and the dynamics groups actuator, controller, joints, scene, solver,\n"
               "maneuver (printed after the mechanism). Exit status: 0 ok; 2 usage or config\n"
               "error.\n");
}

static const char *joint_type_name(pom_joint_type t) {
  switch (t) {
  case POM_JOINT_SPHERICAL:
    return "spherical";
  case POM_JOINT_PRISMATIC:
    return "prismatic";
  case POM_JOINT_UNIVERSAL:
    return "universal";
  case POM_JOINT_REVOLUTE:
    return "revolute";
  }
  return "?";
}

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
 * object (no surrounding braces, no trailing comma). */
static void model_mechanism_json(const pom_kin_arch *a, const pom_mechanism *m) {
  printf("  \"geometry\": {\n    \"mode\": \"%s\",\n", a->has_design ? "parameters" : "points");
  if (a->has_design) {
    const pom_kin_design *d = &a->design;
    printf("    \"design\": {\"platform_radius_m\": ");
    pom_json_number(stdout, d->scale);
    printf(", \"first_azimuth_rad\": ");
    pom_json_number(stdout, d->first_azimuth);
    printf(", \"platform_height\": ");
    pom_json_number(stdout, d->platform_height);
    printf(", \"limb_length\": ");
    pom_json_number(stdout, d->limb_length);
    printf(", \"limb_lean_rad\": ");
    pom_json_number(stdout, d->limb_lean);
    printf(", \"limb_azimuth_rad\": ");
    pom_json_number(stdout, d->limb_azimuth);
    if (a->type == POM_ARCH_3PSS) {
      printf(", \"actuator_tilt_rad\": ");
      pom_json_number(stdout, d->actuator_tilt);
      printf(", \"actuator_azimuth_rad\": ");
      pom_json_number(stdout, d->actuator_azimuth);
    }
    printf("},\n");
  }
  points_json("platform_points_m", a->platform_point, 0);
  points_json("limb_directions_home", a->limb_dir_home, 0);
  if (a->type == POM_ARCH_3PSS) {
    points_json("slider_points_mid_m", a->slider_mid, 0);
    points_json("slider_axes", a->slider_axis, 0);
    printf("    \"link_lengths_m\": ");
    pom_json_vec(stdout, a->link_length, 3, 1.0);
  } else {
    points_json("base_points_m", a->base_point, 0);
    points_json("ujoint_axes", a->ujoint_axis, 0);
    printf("    \"limb_lengths_mid_m\": ");
    pom_json_vec(stdout, a->limb_length_mid, 3, 1.0);
  }
  printf("\n  },\n  \"limits\": {\"stroke_m\": ");
  pom_json_number(stdout, a->stroke);
  printf(", \"cone_base_max_rad\": ");
  pom_json_number(stdout, a->cone_base_max);
  printf(", \"cone_platform_max_rad\": ");
  pom_json_number(stdout, a->cone_platform_max);
  printf(", \"min_limb_distance_m\": ");
  pom_json_number(stdout, a->min_limb_distance);
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
    printf(", \"type\": \"%s\", \"bodies\": [%d, %d], \"body_names\": [", joint_type_name(jt->type),
           jt->body[0], jt->body[1]);
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
    printf(", \"moving_body\": %d, \"axis\": ", ac->moving_body);
    pom_json_vec(stdout, m->joint[ac->joint].axis, 3, 1.0);
    printf(", \"stroke_m\": ");
    pom_json_number(stdout, ac->stroke);
    printf("}%s\n", k + 1 < m->n_actuators ? "," : "");
  }
  printf("    ]\n  }");
}

/* ---- kinematic part: human text ------------------------------------------------ */
static void model_mechanism_text(const pom_kin_arch *a, const pom_mechanism *m) {
  printf("geometry (%s form), fixed frame at home, mm:\n",
         a->has_design ? "design parameters" : "explicit points");
  if (a->has_design)
    printf("  platform radius %.6g mm, limb length %.6g r, lean %.6g deg, azimuth %.6g deg\n",
           a->design.scale * 1e3, a->design.limb_length, a->design.limb_lean / POM_DEG,
           a->design.limb_azimuth / POM_DEG);
  for (int i = 0; i < 3; ++i) {
    const double *P = a->platform_point[i];
    if (a->type == POM_ARCH_3PSS) {
      const double *B = a->slider_mid[i], *d = a->slider_axis[i];
      printf("  limb %d: C = (%8.3f %8.3f %8.3f)  B_mid = (%8.3f %8.3f %8.3f)  d = (%6.3f %6.3f "
             "%6.3f)  L = %.3f\n",
             i + 1, P[0] * 1e3, P[1] * 1e3, P[2] * 1e3, B[0] * 1e3, B[1] * 1e3, B[2] * 1e3, d[0],
             d[1], d[2], a->link_length[i] * 1e3);
    } else {
      const double *A = a->base_point[i], *u = a->ujoint_axis[i];
      printf("  limb %d: B = (%8.3f %8.3f %8.3f)  A = (%8.3f %8.3f %8.3f)  U axis = (%6.3f %6.3f "
             "%6.3f)  L0 = %.3f\n",
             i + 1, P[0] * 1e3, P[1] * 1e3, P[2] * 1e3, A[0] * 1e3, A[1] * 1e3, A[2] * 1e3, u[0],
             u[1], u[2], a->limb_length_mid[i] * 1e3);
    }
  }
  printf("limits: stroke %.4g mm, base cone %.4g deg, platform cone %.4g deg, limb distance >= "
         "%.4g mm\n",
         a->stroke * 1e3, a->cone_base_max / POM_DEG, a->cone_platform_max / POM_DEG,
         a->min_limb_distance * 1e3);
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
           joint_type_name(jt->type), m->body[jt->body[0]].name, m->body[jt->body[1]].name,
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
    printf("  %d joint %s, moves %s, axis (%6.3f %6.3f %6.3f), stroke %.4g mm\n", k,
           m->joint[ac->joint].name, m->body[ac->moving_body].name, ax[0], ax[1], ax[2],
           ac->stroke * 1e3);
  }
}

int pom_cmd_model(int argc, char **argv) {
  const char *path = NULL;
  int json = 0;
  for (int k = 1; k < argc; ++k) {
    if (strcmp(argv[k], "--help") == 0 || strcmp(argv[k], "-h") == 0) {
      model_usage(stdout);
      return 0;
    } else if (strcmp(argv[k], "--json") == 0) {
      json = 1;
    } else if (argv[k][0] == '-' && argv[k][1] != '\0') {
      fprintf(stderr, "pomlab model: unknown option '%s'\n", argv[k]);
      model_usage(stderr);
      return 2;
    } else if (!path) {
      path = argv[k];
    } else {
      fprintf(stderr, "pomlab model: unexpected argument '%s'\n", argv[k]);
      return 2;
    }
  }
  if (!path) {
    fprintf(stderr, "pomlab model: missing CONFIG\n");
    model_usage(stderr);
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
  rc = pom_cli_kin_check_unknown(cfg, model_scopes);
  pom_cfg_destroy(cfg);
  if (rc) return rc;

  if (json) {
    printf("{\n  \"config\": ");
    pom_json_string(stdout, path);
    printf(",\n  \"name\": ");
    pom_json_string(stdout, arch.name);
    printf(",\n  \"architecture\": \"%s\",\n", pom_kin_arch_name(arch.type));
    printf("  \"units\": \"SI (m, kg, kg m^2, rad, m/s^2); fixed frame at the home pose\",\n");
    model_mechanism_json(&arch, &mech);
    pom_cli_dyn_params_json(stdout, &dyn);
    printf("\n}\n");
  } else {
    printf("%s (%s), config %s\n", arch.name, pom_kin_arch_name(arch.type), path);
    model_mechanism_text(&arch, &mech);
    pom_cli_dyn_params_text(stdout, &dyn);
  }
  return 0;
}
