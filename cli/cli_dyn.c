/* cli_dyn.c - printing of the dynamics parameter groups for `pomlab model`
 * (keys and units: docs/dynamics.md section 9). */
#include "cli_dyn.h"

#include "cli_kin.h"
#include "pom_dyn_ctrl.h"

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
  fprintf(out, ",\n  \"controller\": {");
  pom_cli_ctrl_json_members(out, c);
  fprintf(out, "}");
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
  char law[512];
  pom_dyn_ctrl_of(c)->describe(c, law, sizeof law);
  fprintf(out, "controller (%s): %s\n", pom_dyn_ctrl_of(c)->name, law);
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

/* ---- controllers ------------------------------------------------------------ */
void pom_cli_ctrl_json_members(FILE *out, const pom_dyn_controller *c) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(c);
  fprintf(out, "\"type\": ");
  pom_json_string(out, t->name);
  for (int k = 0; k < t->n_options; ++k) {
    fprintf(out, ", ");
    pom_json_string(out, t->options[k].key);
    fprintf(out, ": ");
    pom_json_string(out, pom_dyn_ctrl_option_name(c, k));
  }
  for (int k = 0; k < t->n_gains; ++k) {
    fprintf(out, ", ");
    pom_json_string(out, t->gains[k].key);
    fprintf(out, ": ");
    pom_json_number(out, pom_dyn_ctrl_gain(c, k));
  }
}

static const char *const state_kind_names[] = {"integral of q (m s or rad s)", "like q (m or rad)",
                                               "like q_dot (m/s or rad/s)", NULL};

int pom_cli_list_controllers(FILE *out, int json) {
  int n = pom_dyn_ctrl_type_count();
  if (json) fprintf(out, "{\n  \"controllers\": [\n");
  for (int k = 0; k < n; ++k) {
    const pom_dyn_ctrl_type *t = pom_dyn_ctrl_type_at(k);
    if (json) {
      fprintf(out, "    {\"name\": ");
      pom_json_string(out, t->name);
      fprintf(out, ", \"label\": ");
      pom_json_string(out, t->label);
      fprintf(out, ", \"description\": ");
      pom_json_string(out, t->description);
      fprintf(out, ", \"analytic_partials\": %s, \"states_per_actuator\": [",
              t->partials ? "true" : "false");
      for (int i = 0; i < t->n_states; ++i) {
        fprintf(out, "%s{\"name\": ", i ? ", " : "");
        pom_json_string(out, t->states[i].name);
        fprintf(out, ", \"kind\": ");
        pom_json_string(out, pom_cfg_choice_name(state_kind_names, (int)t->states[i].kind));
        fprintf(out, "}");
      }
      fprintf(out, "],\n     \"options\": [");
      for (int i = 0; i < t->n_options; ++i) {
        const pom_dyn_ctrl_option_desc *o = &t->options[i];
        fprintf(out, "%s{\"key\": ", i ? ", " : "");
        pom_json_string(out, o->key);
        fprintf(out, ", \"choices\": [");
        for (int j = 0; o->names[j]; ++j) {
          fprintf(out, "%s", j ? ", " : "");
          pom_json_string(out, o->names[j]);
        }
        fprintf(out, "], \"default\": ");
        pom_json_string(out, o->names[0]);
        fprintf(out, "}");
      }
      fprintf(out, "],\n     \"gains\": [");
      for (int i = 0; i < t->n_gains; ++i) {
        const pom_dyn_gain_desc *g = &t->gains[i];
        fprintf(out, "%s\n       {\"key\": ", i ? "," : "");
        pom_json_string(out, g->key);
        fprintf(out, ", \"symbol\": ");
        pom_json_string(out, g->symbol);
        fprintf(out, ", \"unit\": ");
        pom_json_string(out, g->unit);
        fprintf(out, ", \"meaning\": ");
        pom_json_string(out, g->meaning);
        fprintf(out, ", \"min\": ");
        pom_json_number(out, g->lo);
        fprintf(out, ", \"max\": ");
        pom_json_number(out, g->hi);
        fprintf(out, ", \"default\": ");
        pom_json_number(out, g->def);
        fprintf(out, ", \"tunable\": %s, \"log_search\": %s}", g->tunable ? "true" : "false",
                g->log_search ? "true" : "false");
      }
      fprintf(out, "]}%s\n", k + 1 < n ? "," : "");
    } else {
      fprintf(out, "%-16s %s: %s (%d state%s per actuator, %s Jacobian)\n", t->name, t->label,
              t->description, t->n_states, t->n_states == 1 ? "" : "s",
              t->partials ? "analytic" : "finite-difference");
      for (int i = 0; i < t->n_options; ++i) {
        fprintf(out, "  controller.%-20s", t->options[i].key);
        for (int j = 0; t->options[i].names[j]; ++j)
          fprintf(out, "%s\"%s\"", j ? " | " : " ", t->options[i].names[j]);
        fprintf(out, "; %s\n", t->options[i].meaning);
      }
      for (int i = 0; i < t->n_gains; ++i) {
        const pom_dyn_gain_desc *g = &t->gains[i];
        fprintf(out, "  controller.%-20s %-6s %-6s in [%g, %g], default %g%s%s; %s\n", g->key,
                g->symbol, g->unit, g->lo, g->hi, g->def, g->tunable ? ", tunable" : "",
                g->tunable ? (g->log_search ? " (log)" : " (linear)") : "", g->meaning);
      }
    }
  }
  if (json) fprintf(out, "  ]\n}\n");
  return 0;
}
