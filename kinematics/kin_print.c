/* kin_print.c - the kinematics' own data as text and JSON
 * (pom_kin_print.h): the resolved mechanism (`pomlab model`), the
 * registered architectures (`--list-architectures`), a pose's limits (`ik`,
 * `fk`). */
#include "pom_kin_print.h"

#include "pom_arch.h"
#include "pom_json.h"
#include "pom_math.h"

#include <string.h>

/* ---- kinematic part: JSON ---------------------------------------------------- */
static void points_json(FILE *out, const char *key, const double p[3][3], int last) {
  fprintf(out, "    \"%s\": [", key);
  for (int i = 0; i < 3; ++i) {
    if (i) fprintf(out, ", ");
    pom_json_vec(out, p[i], 3, 1.0);
  }
  fprintf(out, "]%s\n", last ? "" : ",");
}

/* Prints the members "geometry", "limits" and "mechanism" of the top-level
 * object (no surrounding braces, no trailing comma). Generic over the
 * architecture: its type's tables name every value (pom_arch.h). */
void pom_kin_mechanism_json(FILE *out, const pom_kin_arch *a, const pom_mechanism *m) {
  const pom_kin_arch_type *t = a->type;
  const pom_act_desc *u = pom_act_kind_desc(t->actuator);
  fprintf(out, "  \"geometry\": {\n    \"mode\": \"%s\",\n",
          a->has_design ? "parameters" : "points");
  fprintf(out, "    \"scale_m\": ");
  pom_json_number(out, a->design.scale);
  fprintf(out, ", \"scale_key\": \"%s\",\n", t->scale_key);
  if (a->has_design) {
    fprintf(out, "    \"design\": {");
    for (int k = 0; k < t->n_params; ++k) {
      fprintf(out, "%s\"%s\": ", k ? ", " : "", t->params[k].key);
      pom_json_number(out, a->design.x[k] / t->params[k].to_si);
    }
    fprintf(out, "}%s\n", t->n_points > 0 ? "," : ""); /* a file's type has no points */
  }
  for (int k = 0; k < t->n_points; ++k) {
    const double(*p)[3] =
        (const double(*)[3])(const void *)((const char *)a->data + t->points[k].offset);
    points_json(out, t->points[k].key, p, k + 1 == t->n_points);
  }
  fprintf(out, "  },\n  \"limits\": {\"stroke\": ");
  pom_json_number(out, a->stroke);
  fprintf(out, ", \"stroke_unit\": \"%s\"", u->si);
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_kin_limit_desc *ld = &t->limits[kind];
    if (!ld->name) continue;
    fprintf(out, ", \"%s\": ", ld->key);
    pom_json_number(out, a->limit_bound[kind] * ld->to_display);
  }
  fprintf(out, "},\n  \"mechanism\": {\n    \"gravity_mps2\": ");
  pom_json_vec(out, m->gravity, 3, 1.0);
  fprintf(out, ",\n    \"platform\": %d,\n    \"bodies\": [\n", m->platform);
  for (int b = 0; b < m->n_bodies; ++b) {
    const pom_mech_body *body = &m->body[b];
    fprintf(out, "      {\"index\": %d, \"name\": ", b);
    pom_json_string(out, body->name);
    fprintf(out, ", \"mass_kg\": ");
    pom_json_number(out, body->mass);
    fprintf(out, ", \"cm_m\": ");
    pom_json_vec(out, body->cm, 3, 1.0);
    fprintf(out, ", \"inertia_kgm2\": ");
    pom_json_mat3(out, body->inertia, 1.0);
    fprintf(out, "}%s\n", b + 1 < m->n_bodies ? "," : "");
  }
  fprintf(out, "    ],\n    \"joints\": [\n");
  for (int j = 0; j < m->n_joints; ++j) {
    const pom_mech_joint *jt = &m->joint[j];
    fprintf(out, "      {\"index\": %d, \"name\": ", j);
    pom_json_string(out, jt->name);
    fprintf(out, ", \"type\": \"%s\", \"bodies\": [%d, %d], \"body_names\": [",
            pom_joint_type_name(jt->type), jt->body[0], jt->body[1]);
    pom_json_string(out, m->body[jt->body[0]].name);
    fprintf(out, ", ");
    pom_json_string(out, m->body[jt->body[1]].name);
    fprintf(out, "], \"point_m\": ");
    pom_json_vec(out, jt->point, 3, 1.0);
    fprintf(out, ", \"axis\": ");
    if (jt->type == POM_JOINT_SPHERICAL) {
      fprintf(out, "null");
    } else {
      pom_json_vec(out, jt->axis, 3, 1.0);
    }
    fprintf(out, ", \"axis2\": ");
    if (jt->type == POM_JOINT_UNIVERSAL) {
      pom_json_vec(out, jt->axis2, 3, 1.0);
    } else {
      fprintf(out, "null");
    }
    fprintf(out, ", \"actuated\": %s, \"actuator\": ", jt->actuator >= 0 ? "true" : "false");
    if (jt->actuator >= 0) {
      fprintf(out, "%d", jt->actuator);
    } else {
      fprintf(out, "null");
    }
    fprintf(out, "}%s\n", j + 1 < m->n_joints ? "," : "");
  }
  fprintf(out, "    ],\n    \"actuators\": [\n");
  for (int k = 0; k < m->n_actuators; ++k) {
    const pom_mech_actuator *ac = &m->actuator[k];
    fprintf(out, "      {\"index\": %d, \"joint\": %d, \"joint_name\": ", k, ac->joint);
    pom_json_string(out, m->joint[ac->joint].name);
    const pom_act_desc *au = pom_act_kind_desc(ac->kind);
    fprintf(out, ", \"kind\": \"%s\", \"moving_body\": %d, \"axis\": ", au->kind_name,
            ac->moving_body);
    pom_json_vec(out, m->joint[ac->joint].axis, 3, 1.0);
    fprintf(out, ", \"stroke\": ");
    pom_json_number(out, ac->stroke);
    fprintf(out, ", \"unit\": \"%s\", \"effort_unit\": \"%s\"", au->si, au->effort);
    fprintf(out, "}%s\n", k + 1 < m->n_actuators ? "," : "");
  }
  fprintf(out, "    ]\n  }");
}

/* ---- kinematic part: human text ------------------------------------------------ */
void pom_kin_mechanism_text(FILE *out, const pom_kin_arch *a, const pom_mechanism *m) {
  const pom_kin_arch_type *t = a->type;
  const pom_act_desc *u = pom_act_kind_desc(t->actuator);
  fprintf(out, "geometry (%s form), fixed frame at home:\n",
          a->has_design ? "design parameters" : "explicit points");
  fprintf(out, "  scale: %s = %.6g mm (%s)\n", t->scale_key, a->design.scale * 1e3,
          t->scale_meaning);
  if (a->has_design)
    for (int k = 0; k < t->n_params; ++k)
      fprintf(out, "  %-22s = %.6g\n", t->params[k].key, a->design.x[k] / t->params[k].to_si);
  for (int k = 0; k < t->n_points; ++k) {
    const double(*p)[3] =
        (const double(*)[3])(const void *)((const char *)a->data + t->points[k].offset);
    /* metre-valued point sets are printed in mm, unit axes as they are */
    int metres = strstr(t->points[k].key, "_m") != NULL;
    double f = metres ? 1e3 : 1.0;
    fprintf(out, "  %-18s%s", t->points[k].key, metres ? " (mm)" : "     ");
    for (int i = 0; i < 3; ++i)
      fprintf(out, "  (%8.3f %8.3f %8.3f)", p[i][0] * f, p[i][1] * f, p[i][2] * f);
    fprintf(out, "\n");
  }
  fprintf(out, "limits: %s +-%.6g %s", u->range_word, 0.5 * a->stroke * u->to_display, u->display);
  for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind) {
    const pom_kin_limit_desc *ld = &t->limits[kind];
    if (!ld->name) continue;
    fprintf(out, ", %s %s %.4g %s", ld->name,
            ld->lower ? ">=" : "<=", a->limit_bound[kind] * ld->to_display, ld->unit);
  }
  fprintf(out, "\n");
  fprintf(out, "gravity (m/s^2): %g %g %g\n", m->gravity[0], m->gravity[1], m->gravity[2]);
  fprintf(out, "bodies (mass in kg, CM in mm, inertia about the CM in kg m^2, fixed axes):\n");
  for (int b = 0; b < m->n_bodies; ++b) {
    const pom_mech_body *body = &m->body[b];
    const double *I = body->inertia;
    fprintf(out,
            "  %2d %-10s m = %-9.4g CM = (%8.3f %8.3f %8.3f)  I = [%.3e %.3e %.3e; %.3e %.3e "
            "%.3e; %.3e %.3e %.3e]\n",
            b, body->name, body->mass, body->cm[0] * 1e3, body->cm[1] * 1e3, body->cm[2] * 1e3,
            I[0], I[1], I[2], I[3], I[4], I[5], I[6], I[7], I[8]);
  }
  fprintf(out, "joints (point in mm):\n");
  for (int j = 0; j < m->n_joints; ++j) {
    const pom_mech_joint *jt = &m->joint[j];
    fprintf(out, "  %2d %-4s %-10s %-10s - %-10s at (%8.3f %8.3f %8.3f)", j, jt->name,
            pom_joint_type_name(jt->type), m->body[jt->body[0]].name, m->body[jt->body[1]].name,
            jt->point[0] * 1e3, jt->point[1] * 1e3, jt->point[2] * 1e3);
    if (jt->type != POM_JOINT_SPHERICAL)
      fprintf(out, "  axis (%6.3f %6.3f %6.3f)", jt->axis[0], jt->axis[1], jt->axis[2]);
    if (jt->type == POM_JOINT_UNIVERSAL)
      fprintf(out, "  axis2 (%6.3f %6.3f %6.3f)", jt->axis2[0], jt->axis2[1], jt->axis2[2]);
    if (jt->actuator >= 0) fprintf(out, "  actuator %d", jt->actuator);
    fprintf(out, "\n");
  }
  fprintf(out, "actuators:\n");
  for (int k = 0; k < m->n_actuators; ++k) {
    const pom_mech_actuator *ac = &m->actuator[k];
    const double *ax = m->joint[ac->joint].axis;
    const pom_act_desc *au = pom_act_kind_desc(ac->kind);
    fprintf(out, "  %d %s joint %s, moves %s, axis (%6.3f %6.3f %6.3f), range +-%.4g %s\n", k,
            au->kind_name, m->joint[ac->joint].name, m->body[ac->moving_body].name, ax[0], ax[1],
            ax[2], 0.5 * ac->stroke * au->to_display, au->display);
  }
}

/* ---- the registry ---------------------------------------------------------------- */
void pom_kin_arch_list(FILE *out, int json) {
  int n = pom_kin_arch_type_count();
  if (json) fprintf(out, "{\n  \"architectures\": [\n");
  for (int k = 0; k < n; ++k) {
    const pom_kin_arch_type *t = pom_kin_arch_type_at(k);
    const pom_act_desc *u = pom_act_kind_desc(t->actuator);
    if (json) {
      fprintf(out, "    {\"name\": ");
      pom_json_string(out, t->name);
      fprintf(out, ", \"label\": ");
      pom_json_string(out, t->label);
      fprintf(out, ", \"description\": ");
      pom_json_string(out, t->description);
      fprintf(out, ", \"actuator_kind\": \"%s\", \"actuator_unit\": \"%s\", \"scale_key\": ",
              u->kind_name, u->si);
      pom_json_string(out, t->scale_key);
      fprintf(out, ", \"parameters\": [");
      for (int i = 0; i < t->n_params; ++i) {
        fprintf(out, "%s", i ? ", " : "");
        pom_json_string(out, t->params[i].key);
      }
      fprintf(out, "], \"synthesis_variables\": [");
      int first = 1;
      for (int i = 0; i < t->n_params; ++i) {
        if (!t->params[i].synth) continue;
        fprintf(out, "%s", first ? "" : ", ");
        pom_json_string(out, t->params[i].key);
        first = 0;
      }
      fprintf(out, "]}%s\n", k + 1 < n ? "," : "");
    } else {
      fprintf(out, "%-6s %-9s %s actuators (q in %s); %s\n", t->name, t->label, u->kind_name,
              u->display, t->description);
      fprintf(out, "       scale %s: %s\n", t->scale_key, t->scale_meaning);
      for (int i = 0; i < t->n_params; ++i)
        fprintf(out, "       geometry.%-22s %s%s\n", t->params[i].key, t->params[i].meaning,
                t->params[i].synth ? " [synthesis variable]" : "");
      for (int kind = 1; kind < POM_KIN_LIM_KINDS; ++kind)
        if (t->limits[kind].name)
          fprintf(out, "       limits.%-24s %s (%s)\n", t->limits[kind].key, t->limits[kind].name,
                  t->limits[kind].lower ? "a lower bound" : "an upper bound");
    }
  }
  if (json) fprintf(out, "  ]\n}\n");
}

/* ---- pose reports ------------------------------------------------------------ */
void pom_kin_print_limits(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p) {
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

/* ,\n  "key": [1-based limbs of the bits of mask] */
static void json_limbs(FILE *out, const char *key, unsigned mask) {
  fprintf(out, ",\n  \"%s\": [", key);
  for (int i = 0, c = 0; i < 3; ++i)
    if (mask >> i & 1u) fprintf(out, "%s%d", c++ ? ", " : "", i + 1);
  fputc(']', out);
}

void pom_kin_pose_json(FILE *out, const pom_kin_arch *arch, const pom_kin_pose *p) {
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
    if (p->singular & POM_KIN_SING_SERIAL) {
      fputs(",\n  \"singularities\": [\"serial\"]", out);
      json_limbs(out, "serial_limbs", p->serial_limbs);
    }
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
  /* the three singularities told apart (docs/kinematics-tables.md 3.1): the
   * constraint figures only for limbs that hold O through one wrench each */
  fputs(",\n  \"singularities\": [", out);
  static const char *const sing[3] = {"serial", "parallel", "constraint"};
  for (int k = 0, n = 0; k < 3; ++k)
    if (p->singular & (1 << k)) fprintf(out, "%s\"%s\"", n++ ? ", " : "", sing[k]);
  fputs("]", out);
  /* the serial measure per limb and the limbs it flags (3.2) */
  fputs(",\n  \"transmission\": ", out);
  pom_json_vec(out, p->transmission, 3, 1.0);
  json_limbs(out, "serial_limbs", p->serial_limbs);
  if (p->n_constraint) {
    fputs(",\n  \"constraint_sv\": ", out);
    pom_json_number(out, p->constraint_sv);
    fputs(",\n  \"constraint_offset_m\": ", out);
    pom_json_number(out, p->constraint_offset);
  }
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

/* ---- ik and fk ------------------------------------------------------------------ */
void pom_kin_ik_report(FILE *out, int json, const char *config, const pom_kin_arch *arch,
                       const double e_deg[3], const pom_kin_pose *p, pom_status st,
                       const char *message) {
  if (json) {
    fprintf(out, "{\n  \"config\": ");
    pom_json_string(out, config);
    fprintf(out, ",\n  \"name\": ");
    pom_json_string(out, arch->name);
    fprintf(out, ",\n  \"architecture\": \"%s\",\n  \"euler_zyx_deg\": ", pom_kin_arch_name(arch));
    pom_json_vec(out, e_deg, 3, 1.0);
    fprintf(out, ",\n  ");
    pom_kin_pose_json(out, arch, p);
    fprintf(out, ",\n  \"message\": ");
    pom_json_string(out, st == POM_OK ? "" : message);
    fprintf(out, "\n}\n");
  } else {
    fprintf(out, "%s (%s), config %s\n", arch->name, pom_kin_arch_name(arch), config);
    fprintf(out, "orientation: ZYX Euler psi = %g deg, theta = %g deg, phi = %g deg\n", e_deg[0],
            e_deg[1], e_deg[2]);
    if (!p->reachable) {
      fprintf(out, "reachable: NO - %s\n", message);
      if (p->singular & POM_KIN_SING_SERIAL)
        fprintf(out, "singularity: serial (limb %d assembles, its actuator side B_ii is 0)\n",
                p->unreachable_limb + 1);
    } else {
      fprintf(out, "reachable: yes\n");
      const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch->type));
      const double f = u->to_display;
      fprintf(out, "q (%s):  %12.6f %12.6f %12.6f\n", u->display, p->q[0] * f, p->q[1] * f,
              p->q[2] * f);
      /* a lever arm in mm/rad, or for a rotary actuator a plain ratio
       * (rad/rad): docs/conventions.md */
      const double fj = u->lever_to_display;
      const char *ju = u->lever_unit;
      fprintf(out, "J (%s), q_dot = J omega (omega in the fixed frame):\n", ju);
      for (int i = 0; i < 3; ++i)
        fprintf(out, "  [%12.6f %12.6f %12.6f]\n", p->J[3 * i] * fj, p->J[3 * i + 1] * fj,
                p->J[3 * i + 2] * fj);
      fprintf(out, "singular values (%s): %.6f %.6f %.6f\n", ju, p->sv[0] * fj, p->sv[1] * fj,
              p->sv[2] * fj);
      fprintf(out, "condition number kappa: %.6f   dexterity 1/kappa: %.6f\n", p->kappa,
              p->dexterity);
      fprintf(out, "transmission (0 at a limb's serial singularity): %.6g %.6g %.6g\n",
              p->transmission[0], p->transmission[1], p->transmission[2]);
      if (p->n_constraint)
        fprintf(out,
                "constraint forces (one per limb, no central joint): smallest singular value "
                "%.6f, largest offset from O %.3g mm\n",
                p->constraint_sv, p->constraint_offset * 1e3);
      if (p->singular) {
        char sb[80];
        fprintf(out, "singularity: %s\n",
                pom_kin_singular_text(p->singular, p->serial_limbs, sb, sizeof sb));
      }
      pom_kin_print_limits(out, arch, p);
      if (st == POM_ERR_LIMIT) fprintf(out, "limit check: FAILED - %s\n", message);
      if (st == POM_OK) fprintf(out, "limit check: ok\n");
    }
  }
}

void pom_kin_fk_report(FILE *out, int json, const char *config, const pom_kin_arch *arch,
                       const double q_disp[3], const double R[9], const pom_kin_fk_info *info,
                       const pom_kin_pose *p, pom_status lst, const char *message) {
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch->type));
  const double q[3] = {q_disp[0] / u->to_display, q_disp[1] / u->to_display,
                       q_disp[2] / u->to_display};
  double e[3], quat[4];
  pom_status est = pom_euler_zyx_from_matrix(e, R);
  pom_quat_from_matrix(quat, R);
  if (json) {
    fprintf(out, "{\n  \"config\": ");
    pom_json_string(out, config);
    fprintf(out, ",\n  \"name\": ");
    pom_json_string(out, arch->name);
    fprintf(out, ",\n  \"architecture\": \"%s\",\n  \"q_target\": ", pom_kin_arch_name(arch));
    pom_json_vec(out, q, 3, 1.0);
    fprintf(out, ",\n  \"solved\": true,\n  \"rotation\": ");
    pom_json_mat3(out, R, 1.0);
    fprintf(out, ",\n  \"euler_zyx_deg\": ");
    pom_json_vec(out, e, 3, 1.0 / POM_DEG);
    fprintf(out, ",\n  \"euler_singular\": %s,\n  \"quaternion_wxyz\": ",
            est == POM_OK ? "false" : "true");
    pom_json_vec(out, quat, 4, 1.0);
    fprintf(out, ",\n  \"iterations\": %d,\n  \"continuation_steps\": %d,\n  \"residual\": ",
            info->iterations, info->continuation_steps);
    pom_json_number(out, info->residual);
    fprintf(out, ",\n  ");
    pom_kin_pose_json(out, arch, p);
    fprintf(out, "\n}\n");
  } else {
    fprintf(out, "%s (%s), config %s\n", arch->name, pom_kin_arch_name(arch), config);
    fprintf(out, "q (%s): %g %g %g\n", u->display, q_disp[0], q_disp[1], q_disp[2]);
    fprintf(out, "rotation R (platform -> fixed frame):\n");
    for (int i = 0; i < 3; ++i)
      fprintf(out, "  [%12.9f %12.9f %12.9f]\n", R[3 * i], R[3 * i + 1], R[3 * i + 2]);
    fprintf(out, "ZYX Euler (deg): psi = %.6f, theta = %.6f, phi = %.6f%s\n", e[0] / POM_DEG,
            e[1] / POM_DEG, e[2] / POM_DEG,
            est == POM_OK ? "" : "  (gimbal lock: only psi -+ phi is defined)");
    fprintf(out, "quaternion (w, x, y, z): %.12f %.12f %.12f %.12f\n", quat[0], quat[1], quat[2],
            quat[3]);
    fprintf(out, "Newton: %d iterations, %d continuation steps%s, residual %.3e %s\n",
            info->iterations, info->continuation_steps, info->continuation_steps ? "" : " (direct)",
            info->residual * u->to_display, u->display);
    fprintf(out, "dexterity 1/kappa: %.6f (kappa %.6f)\n", p->dexterity, p->kappa);
    pom_kin_print_limits(out, arch, p);
    fprintf(out, "limit check: %s%s\n", lst == POM_OK ? "ok" : "FAILED - ",
            lst == POM_OK ? "" : message);
  }
}

/* "+ + -" / "+ 1 -": the branch per limb (1: the limb has one root). */
static void branch_text(char buf[8], const int b[3]) {
  for (int i = 0; i < 3; ++i) {
    buf[2 * i] = b[i] > 0 ? '+' : b[i] < 0 ? '-' : '1';
    buf[2 * i + 1] = i < 2 ? ' ' : '\0';
  }
}

void pom_kin_modes_report(FILE *out, int json, const char *config, const pom_kin_arch *arch,
                          const double e_deg[3], const double q_disp[3], int seeds,
                          const pom_kin_mode *modes, int n) {
  const pom_act_desc *u = pom_act_kind_desc(pom_kin_type_actuator(arch->type));
  const int ik = e_deg != NULL;
  int two[3];
  const int n2 = pom_kin_two_root_limbs(arch, two);
  if (json) {
    fprintf(out, "{\n  \"config\": ");
    pom_json_string(out, config);
    fprintf(out, ",\n  \"name\": ");
    pom_json_string(out, arch->name);
    fprintf(out, ",\n  \"architecture\": \"%s\",\n  \"kind\": \"%s\",\n  ", pom_kin_arch_name(arch),
            ik ? "working_modes" : "assembly_modes");
    if (ik) {
      fprintf(out, "\"euler_zyx_deg\": ");
      pom_json_vec(out, e_deg, 3, 1.0);
    } else {
      double q[3] = {q_disp[0] / u->to_display, q_disp[1] / u->to_display,
                     q_disp[2] / u->to_display};
      fprintf(out, "\"q_target\": ");
      pom_json_vec(out, q, 3, 1.0);
      fprintf(out, ",\n  \"seeds_per_working_mode\": %d", seeds);
    }
    fprintf(out, ",\n  \"working_modes\": %d,\n  \"count\": %d,\n  \"modes\": [", 1 << n2, n);
    for (int k = 0; k < n; ++k) {
      const pom_kin_mode *m = &modes[k];
      double e[3], quat[4];
      pom_status est = pom_euler_zyx_from_matrix(e, m->R);
      pom_quat_from_matrix(quat, m->R);
      fprintf(out, "%s\n  {\n  \"mode\": %d,\n  \"branch\": [%d, %d, %d],\n  \"rotation\": ",
              k ? "," : "", k + 1, m->branch[0], m->branch[1], m->branch[2]);
      pom_json_mat3(out, m->R, 1.0);
      fprintf(out, ",\n  \"euler_zyx_deg\": ");
      pom_json_vec(out, e, 3, 1.0 / POM_DEG);
      fprintf(out, ",\n  \"euler_singular\": %s,\n  \"quaternion_wxyz\": ",
              est == POM_OK ? "false" : "true");
      pom_json_vec(out, quat, 4, 1.0);
      fprintf(out, ",\n  \"det_jacobian\": ");
      pom_json_number(out, m->det);
      fprintf(out, ",\n  \"det_unit_rows\": ");
      pom_json_number(out, m->det_unit);
      fprintf(out, ",\n  \"serial_singular_limbs\": [");
      int first = 1;
      for (int i = 0; i < 3; ++i)
        if (m->serial >> i & 1u) {
          fprintf(out, "%s%d", first ? "" : ", ", i + 1);
          first = 0;
        }
      fprintf(out, "],\n  \"parallel_singular\": %s", m->parallel ? "true" : "false");
      if (!ik) {
        fprintf(out, ",\n  \"residual\": ");
        pom_json_number(out, m->residual);
      }
      fprintf(out, ",\n  ");
      pom_kin_pose_json(out, arch, &m->pose);
      fprintf(out, "\n  }");
    }
    fprintf(out, "\n  ]\n}\n");
    return;
  }
  fprintf(out, "%s (%s), config %s\n", arch->name, pom_kin_arch_name(arch), config);
  char limbs[32] = "";
  for (int i = 0, c = 0; i < 3; ++i)
    if (two[i]) {
      size_t l = strlen(limbs);
      snprintf(limbs + l, sizeof limbs - l, "%s%d", c++ ? ", " : "", i + 1);
    }
  if (ik) {
    fprintf(out, "orientation: ZYX Euler psi = %g deg, theta = %g deg, phi = %g deg\n", e_deg[0],
            e_deg[1], e_deg[2]);
    fprintf(out, "working modes: %d (two IK roots on limb%s %s; branch + is the home root)\n", n,
            n2 == 1 ? "" : "s", n2 ? limbs : "none");
  } else {
    fprintf(out, "q (%s): %g %g %g\n", u->display, q_disp[0], q_disp[1], q_disp[2]);
    if (n2)
      fprintf(out,
              "assembly modes: %d (damped Newton from %d starts on each of the %d working modes; "
              "branch + is the home root)\n",
              n, seeds, 1 << n2);
    else
      fprintf(out,
              "assembly modes: %d (damped Newton from %d starts; one IK root per limb: branch "
              "1)\n",
              n, seeds);
  }
  fprintf(out, "%-4s %-6s %10s %10s %10s  %10s %10s %10s  %11s %8s %10s %9s  %s\n", "mode",
          "branch", "psi", "theta", "phi", "q1", "q2", "q3", "det J", "det unit", "kappa",
          "1/kappa", "singular, limits");
  fprintf(out, "%-4s %-6s %10s %10s %10s  %10s %10s %10s  %11s\n", "", "", "(deg)", "(deg)",
          "(deg)", u->display, u->display, u->display, u->lever_unit);
  const double fj = u->lever_to_display;
  for (int k = 0; k < n; ++k) {
    const pom_kin_mode *m = &modes[k];
    char b[8], viol[256], sing[64] = "";
    double e[3];
    pom_euler_zyx_from_matrix(e, m->R);
    branch_text(b, m->branch);
    fprintf(out, "%-4d %-6s %10.4f %10.4f %10.4f  ", k + 1, b, e[0] / POM_DEG, e[1] / POM_DEG,
            e[2] / POM_DEG);
    if (!m->pose.reachable) {
      fprintf(out, "unreachable (limb %d)\n", m->pose.unreachable_limb + 1);
      continue;
    }
    for (int i = 0; i < 3; ++i)
      if (m->serial >> i & 1u) {
        size_t l = strlen(sing);
        snprintf(sing + l, sizeof sing - l, "serial limb %d, ", i + 1);
      }
    if (m->parallel) {
      size_t l = strlen(sing);
      snprintf(sing + l, sizeof sing - l, "parallel, ");
    }
    pom_kin_violations_text(arch, m->pose.violations, viol, sizeof viol);
    fprintf(out, "%10.4f %10.4f %10.4f  %11.4g %8.4f %10.4g %9.6f  %slimits %s\n",
            m->pose.q[0] * u->to_display, m->pose.q[1] * u->to_display,
            m->pose.q[2] * u->to_display, m->det * fj * fj * fj, m->det_unit, m->pose.kappa,
            m->pose.dexterity, sing, m->pose.violations ? viol : "ok");
  }
}
