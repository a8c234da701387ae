/* dyn_print.c - the dynamics parameter groups and the registered
 * controllers as JSON or text (pom_dyn_print.h), generated from the
 * parameter list (pom_dyn_params_schema.h; keys and units: docs/config.md,
 * "Dynamics parameters") and the controllers' descriptors. */
#include "pom_dyn_print.h"

#include "pom_json.h"
#include "pom_dyn_ctrl.h"
#include "pom_dyn_params_schema.h"

#include <string.h>

/* ---- the parameters, from their list ------------------------------------------ */
/* Each group in loading order; the controller is described by its type. */
void pom_dyn_params_json(FILE *out, const pom_dyn_params *p) {
  const pom_dyn_param_info *schema = pom_dyn_param_schema();
  const char *const *groups = pom_dyn_param_groups();
  for (int g = 0; groups[g]; ++g) {
    fprintf(out, ",\n  \"%s\": {", groups[g]);
    if (strcmp(groups[g], "controller") == 0) pom_dyn_ctrl_json_members(out, &p->controller);
    int n = 0;
    for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
      const pom_dyn_param_info *pi = &schema[k];
      if (strcmp(pi->group, groups[g]) != 0) continue;
      fprintf(out, "%s", n++ ? ", " : "");
      pom_json_string(out, pom_dyn_param_json_key(pi, p->actuator.kind));
      fprintf(out, ": ");
      switch (pi->type) {
      case POM_DYN_PARAM_REAL:
      case POM_DYN_PARAM_KIND_REAL:
        pom_json_number(out, pom_dyn_param_value(p, pi)); /* SI */
        break;
      case POM_DYN_PARAM_LONG:
      case POM_DYN_PARAM_INT:
        fprintf(out, "%.0f", pom_dyn_param_value(p, pi));
        break;
      case POM_DYN_PARAM_BOOL:
        fprintf(out, "%s", pom_dyn_param_value(p, pi) != 0.0 ? "true" : "false");
        break;
      case POM_DYN_PARAM_ENUM:
      case POM_DYN_PARAM_KIND:
        pom_json_string(out, pom_dyn_param_choice(p, pi));
        break;
      }
    }
    fprintf(out, "}");
  }
}

void pom_dyn_params_text(FILE *out, const pom_dyn_params *p) {
  const pom_dyn_param_info *schema = pom_dyn_param_schema();
  const char *const *groups = pom_dyn_param_groups();
  const pom_act_desc *kind = pom_act_kind_desc(p->actuator.kind);
  for (int g = 0; groups[g]; ++g) {
    if (strcmp(groups[g], "controller") == 0) {
      char law[512];
      pom_dyn_ctrl_of(&p->controller)->describe(&p->controller, law, sizeof law);
      fprintf(out, "controller (%s): %s\n", pom_dyn_ctrl_of(&p->controller)->name, law);
      continue;
    }
    if (strcmp(groups[g], "actuator") == 0 && kind)
      fprintf(out, "actuator (%s):", kind->device);
    else
      fprintf(out, "%s:", groups[g]);
    int n = 0;
    for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
      const pom_dyn_param_info *pi = &schema[k];
      char key[96], value[64];
      if (strcmp(pi->group, groups[g]) != 0) continue;
      /* the config key after the group and the value in its unit */
      const char *full = pom_dyn_param_key(pi, p->actuator.kind, key, sizeof key);
      fprintf(out, "%s %s %s", n++ ? "," : "", full ? full + strlen(pi->group) + 1 : "?",
              pom_dyn_param_format(p, pi, value, sizeof value));
    }
    fprintf(out, "\n");
  }
}

/* ---- controllers ------------------------------------------------------------ */
void pom_dyn_ctrl_json_members(FILE *out, const pom_dyn_controller *c) {
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

void pom_dyn_ctrl_list(FILE *out, int json) {
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
}
