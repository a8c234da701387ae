/* cli_dyn.c - printing of the dynamics parameter groups for `pomlab model`
 * (keys and units: docs/dynamics.md section 9). */
#include "cli_dyn.h"

#include "cli_kin.h"

const char *const pom_cli_dyn_groups[] = {"actuator", "controller", "joints", "scene",
                                          "solver",   "maneuver",   NULL};

static void member(FILE *out, const char *key, double v, int last) {
  fprintf(out, "\"%s\": ", key);
  pom_json_number(out, v);
  fprintf(out, "%s", last ? "}" : ", ");
}

void pom_cli_dyn_params_json(FILE *out, const pom_dyn_params *p) {
  const pom_dyn_actuator *a = &p->actuator;
  const pom_dyn_controller *c = &p->controller;
  const pom_dyn_joints *j = &p->joints;
  const pom_dyn_scene *s = &p->scene;
  const pom_dyn_solver *v = &p->solver;
  const pom_dyn_maneuver *m = &p->maneuver;
  const pom_act_desc *kind = pom_act_kind_desc(a->kind);
  fprintf(out, ",\n  \"actuator\": {\"kind\": \"%s\", ", kind->name);
  member(out, kind->constant_key, a->force_constant, 0);
  member(out, "resistance_ohm", a->resistance, 0);
  member(out, "inductance_H", a->inductance, 0);
  member(out, kind->friction_key, a->bearing_friction, 0);
  member(out, "voltage_limit_V", a->voltage_limit, 0);
  member(out, kind->gain_key, a->sensor_gain, 1);
  fprintf(out, ",\n  \"controller\": {\"form\": \"%s\", ", pom_dyn_pid_form_name(c->form));
  member(out, "kp", c->kp, 0);
  member(out, "ki_per_s", c->ki, 0);
  member(out, "kd_s", c->kd, 1);
  fprintf(out, ",\n  \"joints\": {\"model\": \"%s\", ", pom_dyn_joint_model_name(j->model));
  member(out, "stiffness_N_per_m", j->stiffness, 0);
  member(out, "damping_Ns_per_m", j->damping, 0);
  member(out, "angular_stiffness_Nm_per_rad", j->angular_stiffness, 0);
  member(out, "angular_damping_Nms_per_rad", j->angular_damping, 1);
  fprintf(out,
          ",\n  \"scene\": {\"gravity\": %s, \"bearing_friction\": %s, \"coil_inductance\": %s, "
          "\"orientation\": \"%s\", \"limb_inertia\": \"%s\", \"universal_joint\": %s, ",
          s->gravity ? "true" : "false", s->bearing_friction ? "true" : "false",
          s->coil_inductance ? "true" : "false", pom_dyn_orient_name(s->orientation),
          pom_dyn_inertia_name(s->limb_inertia), s->universal_joint ? "true" : "false");
  member(out, "euler_cos_min", s->euler_cos_min, 1);
  fprintf(out,
          ",\n  \"solver\": {\"linear_solver\": \"%s\", \"max_steps\": %ld, \"max_order\": %d, "
          "\"stability_limit_detection\": %s, ",
          pom_dyn_linsol_name(v->linear_solver), v->max_steps, v->max_order,
          v->stability_limit_detection ? "true" : "false");
  member(out, "rtol", v->rtol, 0);
  member(out, "atol_scale", v->atol_scale, 0);
  member(out, "max_step_s", v->max_step, 0);
  member(out, "max_wall_s", v->max_wall, 1);
  fprintf(out, ",\n  \"maneuver\": {");
  member(out, "horizon_s", m->horizon, 0);
  member(out, "settle_band", m->settle_band, 0);
  member(out, "output_dt_s", m->output_dt, 1);
}

void pom_cli_dyn_params_text(FILE *out, const pom_dyn_params *p) {
  const pom_dyn_actuator *a = &p->actuator;
  const pom_dyn_controller *c = &p->controller;
  const pom_dyn_joints *j = &p->joints;
  const pom_dyn_scene *s = &p->scene;
  const pom_dyn_solver *v = &p->solver;
  const pom_dyn_maneuver *m = &p->maneuver;
  const pom_act_desc *kind = pom_act_kind_desc(a->kind);
  fprintf(out,
          "actuator (%s): %s %g %s, R_c %g ohm, L %g H, bearing %g %s, limit +-%g V, K_S %g %s\n",
          kind->device, kind->constant_symbol, a->force_constant, kind->constant_unit,
          a->resistance, a->inductance, a->bearing_friction, kind->friction_unit, a->voltage_limit,
          a->sensor_gain, kind->gain_unit);
  if (c->form == POM_PID_IDEAL)
    fprintf(out,
            "controller: ideal PID u = sat(K_S K_P (e + K_I int e - tau_D q_dot)), K_P %g, K_I "
            "%g 1/s, tau_D %g s\n",
            c->kp, c->ki, c->kd);
  else
    fprintf(out,
            "controller: parallel PID u = sat(K_S (K_P e + K_I int e - K_D q_dot)), K_P %g, K_I "
            "%g 1/s, K_D %g s\n",
            c->kp, c->ki, c->kd);
  fprintf(out, "joints: %s; k_p %g N/m, R_p %g N s/m; angular k_p %g N m/rad, R_p %g N m s/rad\n",
          pom_dyn_joint_model_name(j->model), j->stiffness, j->damping, j->angular_stiffness,
          j->angular_damping);
  fprintf(out,
          "scene: gravity %s, bearing friction %s, coil inductance %s, orientation %s, limb "
          "inertia %s, universal joint constraint %s\n",
          s->gravity ? "on" : "off", s->bearing_friction ? "on" : "off",
          s->coil_inductance ? "on" : "off", pom_dyn_orient_name(s->orientation),
          pom_dyn_inertia_name(s->limb_inertia), s->universal_joint ? "on" : "off");
  fprintf(out,
          "solver: CVODE BDF, rtol %g, atol_scale %g, max step %g ms%s, max %ld steps, %s, "
          "order <= %d%s, wall limit %g s%s\n",
          v->rtol, v->atol_scale, v->max_step * 1e3, v->max_step > 0 ? "" : " (none)", v->max_steps,
          pom_dyn_linsol_name(v->linear_solver), v->max_order,
          v->stability_limit_detection ? ", stability limit detection" : "", v->max_wall,
          v->max_wall > 0 ? " per maneuver" : " (none)");
  fprintf(out, "maneuver: horizon %g ms, settling band %g %% of |step|, output every %g ms\n",
          m->horizon * 1e3, m->settle_band * 100.0, m->output_dt * 1e3);
}
