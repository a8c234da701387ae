/* dyn_report.c - one maneuver's metrics as JSON or text, and its traces as
 * CSV (pom_dyn_print.h; what `pomlab simulate` prints and writes,
 * docs/dynamics.md section 10). */
#include "pom_dyn_print.h"

#include "pom_dyn_ctrl.h"
#include "pom_dyn_metrics_schema.h"
#include "pom_io.h"
#include "pom_json.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>

static void json_num(FILE *f, const char *key, double v, const char *sep) {
  if (isfinite(v))
    fprintf(f, "  \"%s\": %.9g%s\n", key, v, sep);
  else
    fprintf(f, "  \"%s\": null%s\n", key, sep);
}

/* One metric's values (SI) under key: a number or an array of three. */
static void json_metric(FILE *f, const char *key, const pom_dyn_metrics *mt,
                        const pom_dyn_metric_info *mi, const char *sep) {
  fprintf(f, "  \"%s\": %s", key, mi->count > 1 ? "[" : "");
  for (int k = 0; k < mi->count; ++k) {
    double v = pom_dyn_metric_value(mt, mi, k);
    if (k) fputs(", ", f);
    if (!isfinite(v))
      fputs("null", f);
    else if (mi->type != POM_DYN_TYPE_DOUBLE)
      fprintf(f, "%.0f", v);
    else
      fprintf(f, "%.9g", v);
  }
  fprintf(f, "%s%s\n", mi->count > 1 ? "]" : "", sep);
}

/* Marks in out[] the actuators whose |q| went beyond half the stroke (half,
 * SI; 0 = not limited) on the output grid; returns how many did. The model
 * has no end stops, so such a maneuver is not physical (docs/dynamics.md
 * section 10). */
int pom_dyn_stroke_excursions(const pom_dyn_metrics *mt, double half, int out[3]) {
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    out[a] = half > 0 && mt->max_abs_q[a] > half;
    n += out[a];
  }
  return n;
}

/* Every metric of the schema (pom_dyn_metrics_schema.h) under its key, in SI
 * units; actuator coordinates in actuator_unit (m or rad). */
void pom_dyn_report_json(FILE *f, const char *name, const pom_dyn_params *p,
                         const pom_dyn_metrics *mt, pom_actuator_kind kind, double half_stroke) {
  const pom_act_desc *u = pom_act_kind_desc(kind);
  /* the name comes from the config and the reason may quote option values:
   * both escaped */
  fputs("{\n  \"name\": ", f);
  pom_json_string(f, name);
  fprintf(f, ",\n  \"status\": \"%s\",\n  \"reason\": ", pom_status_name(mt->status));
  pom_json_string(f, mt->reason);
  fputs(",\n", f);
  fprintf(f, "  \"controller\": {");
  pom_dyn_ctrl_json_members(f, &p->controller);
  fprintf(f, "},\n");
  if (pom_dyn_ctrl_of(&p->controller) == &pom_dyn_ctrl_pid) /* the key before controller types */
    fprintf(f, "  \"controller_form\": \"%s\",\n", pom_dyn_pid_form_name(p->controller.form));
  fprintf(f,
          "  \"orientation\": \"%s\",\n"
          "  \"linear_solver\": \"%s\",\n  \"joints_model\": \"%s\",\n"
          "  \"actuator_kind\": \"%s\",\n  \"actuator_unit\": \"%s\",\n",
          pom_dyn_orient_name(p->scene.orientation), pom_dyn_linsol_name(p->solver.linear_solver),
          pom_dyn_joint_model_name(p->joints.model), u->kind_name, u->si);
  /* horizon_s comes with the metrics (the schema's `horizon`) */
  int out[3];
  pom_dyn_stroke_excursions(mt, half_stroke, out);
  json_num(f, "half_stroke", half_stroke, ",");
  fprintf(f, "  \"stroke_exceeded\": [%s, %s, %s],\n", out[0] ? "true" : "false",
          out[1] ? "true" : "false", out[2] ? "true" : "false");
  /* the keys of prismatic mechanisms before actuator units existed */
  if (u->legacy_keys) {
    json_metric(f, "target_m", mt, pom_dyn_metric(POM_DYN_METRIC_target), ",");
    json_metric(f, "final_q_m", mt, pom_dyn_metric(POM_DYN_METRIC_final_q), ",");
  }
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    char key[96];
    json_metric(f, pom_dyn_metric_json_key(&schema[j], key, sizeof key), mt, &schema[j],
                j + 1 < POM_DYN_N_METRICS ? "," : "");
  }
  fprintf(f, "}\n");
}

/* The per-actuator metrics of the schema, one row each, in display units. */
static void print_actuator_table(FILE *out, const pom_dyn_metrics *mt, pom_actuator_kind kind) {
  fprintf(out, "%-22s %-5s %12s %12s %12s\n", "metric", "unit", "actuator 1", "actuator 2",
          "actuator 3");
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    const pom_dyn_metric_info *mi = &schema[j];
    if (mi->count != 3) continue;
    double f = 1.0;
    const char *unit = pom_dyn_metric_display_unit(mi, kind, &f);
    fprintf(out, "%-22s %-5s", mi->name, unit);
    for (int k = 0; k < 3; ++k) {
      double v = pom_dyn_metric_value(mt, mi, k);
      if (mi->type != POM_DYN_TYPE_DOUBLE)
        fprintf(out, " %12.0f", v);
      else
        fprintf(out, " %12.6g", v * f);
    }
    fprintf(out, "\n");
  }
}

void pom_dyn_report_text(FILE *out, const char *name, const pom_dyn_params *p,
                         const pom_dyn_metrics *mt, pom_actuator_kind kind, double half_stroke) {
  const pom_act_desc *u = pom_act_kind_desc(kind);
  double f = u->to_display;
  char law[512];
  pom_dyn_ctrl_of(&p->controller)->describe(&p->controller, law, sizeof law);
  fprintf(out,
          "%s: maneuver to (%.4g, %.4g, %.4g) %s, horizon %.4g ms, controller %s, orientation %s, "
          "linear solver %s, %s joints\n",
          name, mt->target[0] * f, mt->target[1] * f, mt->target[2] * f, u->display,
          p->maneuver.horizon * 1e3, law, pom_dyn_orient_name(p->scene.orientation),
          pom_dyn_linsol_name(p->solver.linear_solver), pom_dyn_joint_model_name(p->joints.model));
  if (mt->status != POM_OK)
    fprintf(out, "status: %s (%s)\n", pom_status_name(mt->status), mt->reason);
  print_actuator_table(out, mt, kind);
  int beyond[3];
  if (pom_dyn_stroke_excursions(mt, half_stroke, beyond))
    for (int a = 0; a < 3; ++a)
      if (beyond[a])
        fprintf(out,
                "STROKE EXCEEDED: actuator %d reached |q| = %.6g %s, beyond the stroke +-%.10g %s "
                "(the model has no end stops: not a physical motion)\n",
                a + 1, mt->max_abs_q[a] * f, u->display, half_stroke * f, u->display);
  fprintf(out, "execution time: %.3f ms%s\n", mt->execution_time * 1e3,
          isnan(mt->execution_time) ? " (an actuator did not settle: settled = 0)" : "");
  fprintf(out, "expended energy: %.6g J (positive part %.6g J)\n", mt->energy_total,
          mt->energy_positive[0] + mt->energy_positive[1] + mt->energy_positive[2]);
  fprintf(out,
          "energy audit: supplied %.6g J = dissipated %.6g J (coil %.4g, bearing %.4g, parasitic "
          "%.4g) + stored change %.6g J; balance error %.2e (relative, docs/dynamics.md "
          "section 6)\n",
          mt->energy_supplied, mt->energy_dissipated,
          mt->energy_coil[0] + mt->energy_coil[1] + mt->energy_coil[2],
          mt->energy_bearing[0] + mt->energy_bearing[1] + mt->energy_bearing[2],
          mt->energy_parasitic, mt->energy_stored_change, mt->energy_balance_error);
  fprintf(out, "largest parasitic deflection: %.3g mm, %.3g deg\n", mt->max_deflection * 1e3,
          mt->max_angular_deflection / POM_DEG);
  if (!isnan(mt->rigid_limit_ratio))
    fprintf(
        out,
        "rigid limit: ratio %.3g, joint dissipation share %.3g%s (docs/dynamics.md section 13b)\n",
        mt->rigid_limit_ratio, mt->joint_dissipation_share,
        pom_dyn_rigid_limit_exceeded(mt) ? ": NOT at the rigid limit (ratio > 1e-2 or share > 2e-4)"
                                         : "");
  fprintf(out,
          "solver: %ld steps, %ld RHS evaluations (%ld in %ld Jacobians), %ld Newton iterations, "
          "%ld factorizations, %ld error-test and %ld convergence failures; %.3f ms wall\n",
          mt->steps, mt->rhs_evals, mt->jac_rhs_evals, mt->jac_evals, mt->newton_iters,
          mt->linsol_setups, mt->error_test_fails, mt->nonlin_conv_fails, mt->wall_time * 1e3);
}

pom_status pom_dyn_trace_write_csv(const char *path, const pom_dyn_trace *tr,
                                   const double target[3], pom_actuator_kind kind, pom_error *err) {
  pom_io_file w;
  POM_TRY(pom_io_create(&w, path, err));
  FILE *f = w.f;
  /* actuator coordinates in their SI unit: m and m/s, or rad and rad/s */
  const char *q = pom_act_kind_desc(kind)->si, *qd = pom_act_kind_desc(kind)->rate_tag;
  fprintf(f,
          "t_s,q1_%s,q2_%s,q3_%s,qdot1_%s,qdot2_%s,qdot3_%s,i1_A,i2_A,i3_A,u1_V,u2_V,u3_V,"
          "E1_J,E2_J,E3_J,psi_rad,theta_rad,phi_rad,qw,qx,qy,qz,deflection_m,q1_set_%s,"
          "q2_set_%s,q3_set_%s\n",
          q, q, q, qd, qd, qd, q, q, q);
  for (int k = 0; k < tr->n; ++k) {
    fprintf(f, "%.9g", tr->t[k]);
    const double *cols[5] = {tr->q, tr->q_dot, tr->current, tr->voltage, tr->energy};
    for (int c = 0; c < 5; ++c)
      for (int a = 0; a < 3; ++a)
        fprintf(f, ",%.9g", cols[c][3 * k + a]);
    for (int a = 0; a < 3; ++a)
      fprintf(f, ",%.9g", tr->euler_zyx[3 * k + a]);
    for (int a = 0; a < 4; ++a)
      fprintf(f, ",%.9g", tr->quat[4 * k + a]);
    /* the setpoints on every row: plots draw them as the HDF5 file's are */
    fprintf(f, ",%.9g,%.9g,%.9g,%.9g\n", tr->deflection[k], target[0], target[1], target[2]);
  }
  return pom_io_commit(&w, err);
}
