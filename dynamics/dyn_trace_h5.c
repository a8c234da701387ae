/* dyn_trace_h5.c - one maneuver's traces, metrics and parameters as an
 * HDF5 file (pom_dyn_print.h; `pomlab simulate --out FILE.h5`, read back by
 * `pomlab view --trace`). Its own file so that a program printing reports
 * alone does not link HDF5's writers. */
#include "pom_dyn_print.h"

#include "pom_dyn_metrics_schema.h"
#include "pom_dyn_params_schema.h"
#include "pom_h5.h"
#include "pom_version.h"

pom_status pom_dyn_trace_write_h5(const char *path, const char *program, const pom_cfg *cfg,
                                  const char *name, const pom_dyn_params *p,
                                  const pom_dyn_trace *tr, const pom_dyn_metrics *mt,
                                  pom_actuator_kind kind, pom_error *err) {
  pom_status st = POM_OK;
  hid_t file = -1, g = -1;
  size_t n = (size_t)tr->n;
  size_t d1[1] = {n}, d3[2] = {n, 3}, d4[2] = {n, 4};
  POM_TRY(pom_h5_create_file(&file, path, err));
  POM_TRY_GOTO(pom_h5_attr_string(file, "program", program, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "git_commit", POM_GIT_COMMIT, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(file, "name", name, err), done);
  POM_TRY_GOTO(pom_h5_write_text(file, "config", pom_cfg_text(cfg), err), done);
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "trace", err), done);
  char units[256];
  snprintf(units, sizeof units,
           "t s; q %s; q_dot %s; current A; voltage V; energy J (cumulative int u i dt); "
           "euler_zyx rad (psi, theta, phi); quat (w, x, y, z); deflection m",
           pom_act_kind_desc(kind)->si, pom_act_kind_desc(kind)->rate);
  POM_TRY_GOTO(pom_h5_attr_string(g, "units", units, err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "actuator_unit", pom_act_kind_desc(kind)->si, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "t", 1, d1, tr->t, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "q", 2, d3, tr->q, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "q_dot", 2, d3, tr->q_dot, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "current", 2, d3, tr->current, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "voltage", 2, d3, tr->voltage, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "energy", 2, d3, tr->energy, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "euler_zyx", 2, d3, tr->euler_zyx, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "quat", 2, d4, tr->quat, err), done);
  POM_TRY_GOTO(pom_h5_write_doubles(g, "deflection", 1, d1, tr->deflection, err), done);
  H5Gclose(g);
  g = -1;
  POM_TRY_GOTO(pom_h5_create_group(&g, file, "metrics", err), done);
  POM_TRY_GOTO(pom_h5_attr_string(g, "status", pom_status_name(mt->status), err), done);
  /* every parameter of the run (controller_*, orientation, solver_*, ...) */
  POM_TRY_GOTO(pom_dyn_params_h5_describe(g, p, err), done);
  if (mt->status != POM_OK) POM_TRY_GOTO(pom_h5_attr_string(g, "reason", mt->reason, err), done);
  /* every metric of the list, named by its JSON key (docs/results.md section
   * 9): float64 in SI (counts and flags exactly), [3] per actuator */
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    char key[96];
    double v[3];
    pom_dyn_metric_json_key(&schema[j], key, sizeof key);
    for (int k = 0; k < schema[j].count; ++k)
      v[k] = pom_dyn_metric_value(mt, &schema[j], k);
    st = schema[j].count == 1 ? pom_h5_attr_double(g, key, v[0], err)
                              : pom_h5_attr_doubles(g, key, v, (size_t)schema[j].count, err);
    if (st != POM_OK) goto done;
  }
  if (pom_act_kind_desc(kind)->legacy_keys) /* the names before actuator units existed */
    POM_TRY_GOTO(pom_h5_attr_doubles(g, "target_m", mt->target, 3, err), done);
done:
  if (g >= 0) H5Gclose(g);
  pom_error close_err;
  pom_error_clear(&close_err);
  pom_status cst = pom_h5_close_file(file, &close_err);
  if (st == POM_OK && cst != POM_OK) {
    if (err) *err = close_err;
    st = cst;
  }
  return st;
}
