/* test_dyn_params.c - the one list of dynamics parameters
 * (dynamics/pom_dyn_params_schema.h): the defaults it generates are the
 * former hand-written ones bit for bit; loading and the model's check agree
 * on every range, at both ends and just outside; names parse back; every
 * parameter reaches the HDF5 provenance under a unique name. */
#define _POSIX_C_SOURCE 200809L /* mkstemp */
#include "check.h"
#include "pom_dyn_params_schema.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- 1. defaults ------------------------------------------------------------ */
/* pom_dyn_params_defaults as it was written before the list (outside the
 * controller, which its type's descriptors set). */
static void former_defaults(pom_dyn_params *p) {
  memset(p, 0, sizeof *p);
  p->actuator.force_constant = 3.8;
  p->actuator.resistance = 10.0;
  p->actuator.inductance = 1.45e-4;
  p->actuator.bearing_friction = 9.8e-2;
  p->actuator.voltage_limit = 24.0;
  p->actuator.sensor_gain = 833.33;
  p->actuator.kind = POM_ACT_PRISMATIC;
  p->joints.stiffness = 1.0e6;
  p->joints.damping = 200.0;
  p->joints.angular_stiffness = 1.0e6;
  p->joints.angular_damping = 200.0;
  p->joints.model = POM_JOINTS_PARASITIC;
  p->scene.gravity = 1;
  p->scene.bearing_friction = 1;
  p->scene.coil_inductance = 1;
  p->scene.orientation = POM_ORIENT_EULER_ZYX;
  p->scene.euler_cos_min = 1.0e-2;
  p->scene.limb_inertia = POM_INERTIA_FULL;
  p->scene.universal_joint = 1;
  p->solver.rtol = 1.0e-6;
  p->solver.atol_scale = 0.0;
  p->solver.max_step = 0.0;
  p->solver.max_steps = 200000;
  p->solver.linear_solver = POM_LINSOL_STRUCTURED; /* KLU until issue 20 */
  p->solver.jacobian = POM_JAC_ANALYTIC;
  p->solver.max_order = 5;
  p->solver.stability_limit_detection = 1;
  p->solver.max_wall = 60.0;
  p->solver.max_balance_error = 0.05;
  p->maneuver.horizon = 0.100;
  p->maneuver.settle_band = 0.02;
  p->maneuver.output_dt = 1.0e-4;
}

/* bitwise equality of one field of a and b */
#define SAME(field) check_true(memcmp(&a.field, &b.field, sizeof a.field) == 0)

static void test_defaults(void) {
  pom_dyn_params a, b;
  pom_error err;
  pom_error_clear(&err);
  pom_dyn_params_defaults(&a);
  former_defaults(&b);
  /* the fields that existed before the list (a later parameter has its own
   * default, which the list declares) */
  SAME(actuator.force_constant);
  SAME(actuator.resistance);
  SAME(actuator.inductance);
  SAME(actuator.bearing_friction);
  SAME(actuator.voltage_limit);
  SAME(actuator.sensor_gain);
  SAME(actuator.kind);
  SAME(joints.stiffness);
  SAME(joints.damping);
  SAME(joints.angular_stiffness);
  SAME(joints.angular_damping);
  SAME(joints.model);
  SAME(scene.gravity);
  SAME(scene.bearing_friction);
  SAME(scene.coil_inductance);
  SAME(scene.orientation);
  SAME(scene.euler_cos_min);
  SAME(scene.limb_inertia);
  SAME(scene.universal_joint);
  SAME(solver.rtol);
  SAME(solver.atol_scale);
  SAME(solver.max_step);
  SAME(solver.max_steps);
  SAME(solver.linear_solver);
  SAME(solver.jacobian);
  SAME(solver.max_order);
  SAME(solver.stability_limit_detection);
  SAME(solver.max_wall);
  SAME(solver.max_balance_error);
  SAME(maneuver.horizon);
  SAME(maneuver.settle_band);
  SAME(maneuver.output_dt);
  /* every declared default is the list's, and within its range */
  const pom_dyn_param_info *s = pom_dyn_param_schema();
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k)
    check_true(pom_dyn_param_value(&a, &s[k]) == s[k].def);
  check_true(pom_dyn_params_check(&a, &err) == POM_OK);
}

/* ---- 2. one range: loading and the model agree -------------------------------- */
static pom_status load_text(pom_dyn_params *p, const char *text, pom_error *err) {
  pom_cfg *cfg = NULL;
  pom_dyn_params_defaults(p);
  pom_status st = pom_cfg_load_string(&cfg, text, "<test>", err);
  if (st == POM_OK) st = pom_dyn_params_load(p, cfg, err);
  pom_cfg_destroy(cfg);
  return st;
}

/* value (config unit) of parameter pi: loaded from a file, and set by a
 * program in SI; both accept it or both refuse it. Returns 1 when accepted. */
static int agree(const pom_dyn_param_info *pi, double value, const char *kind_line) {
  char key[96], text[512];
  pom_dyn_params p, q;
  pom_error err;
  pom_error_clear(&err);
  pom_actuator_kind kind = POM_ACT_PRISMATIC;
  if (kind_line[0]) kind = POM_ACT_REVOLUTE;
  pom_dyn_param_key(pi, kind, key, sizeof key);
  const char *dot = strchr(key, '.');
  if (pi->type == POM_DYN_PARAM_REAL || pi->type == POM_DYN_PARAM_KIND_REAL)
    snprintf(text, sizeof text, "actuator = { %s }; %.*s = { %s = %.17e; };", kind_line,
             (int)(dot - key), key, dot + 1, value);
  else
    snprintf(text, sizeof text, "actuator = { %s }; %.*s = { %s = %ldL; };", kind_line,
             (int)(dot - key), key, dot + 1, (long)value);
  if (strncmp(key, "actuator.", 9) == 0) /* one actuator group */
    snprintf(text, sizeof text, "actuator = { %s %s = %.17e; };", kind_line, dot + 1, value);
  pom_status loaded = load_text(&p, text, &err);
  /* the message names the key (or, for a broken relation, the other key) */
  if (loaded != POM_OK && !strstr(err.message, key) && !strstr(err.message, "maneuver.output_dt")) {
    printf("  load of %s did not name the key: %s\n", text, err.message);
    check_true(0);
  }
  /* the same value set by a program, in SI */
  pom_dyn_params_defaults(&q);
  q.actuator.kind = kind;
  char *f = (char *)&q + pi->offset;
  if (pi->type == POM_DYN_PARAM_REAL || pi->type == POM_DYN_PARAM_KIND_REAL) {
    double v = value * pi->to_si;
    memcpy(f, &v, sizeof v);
  } else if (pi->type == POM_DYN_PARAM_LONG) {
    long v = (long)value;
    memcpy(f, &v, sizeof v);
  } else {
    int v = (int)value;
    memcpy(f, &v, sizeof v);
  }
  pom_status checked = pom_dyn_params_check(&q, &err);
  if ((loaded == POM_OK) != (checked == POM_OK)) {
    printf("  %s = %.17g: load %s, check %s\n", key, value, pom_status_name(loaded),
           pom_status_name(checked));
    check_true(0);
  }
  if (loaded == POM_OK) check_true(memcmp(&p, &q, sizeof p) == 0 || kind != POM_ACT_PRISMATIC);
  return loaded == POM_OK;
}

static void test_ranges(void) {
  const pom_dyn_param_info *s = pom_dyn_param_schema();
  int n_numeric = 0;
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
    const pom_dyn_param_info *pi = &s[k];
    if (pi->type == POM_DYN_PARAM_BOOL || pi->type == POM_DYN_PARAM_ENUM ||
        pi->type == POM_DYN_PARAM_KIND)
      continue;
    ++n_numeric;
    const char *kinds[2] = {"", "kind = \"rotary\";"};
    for (int a = 0; a < (pi->type == POM_DYN_PARAM_KIND_REAL ? 2 : 1); ++a) {
      int integer = pi->type == POM_DYN_PARAM_LONG || pi->type == POM_DYN_PARAM_INT;
      double below = integer ? pi->lo - 1 : pi->lo - fmax(fabs(pi->lo) * 1e-9, 1e-300);
      double above = integer ? pi->hi + 1 : pi->hi + fabs(pi->hi) * 1e-9;
      check_true(!agree(pi, below, kinds[a]));
      check_true(!agree(pi, above, kinds[a]));
      agree(pi, pi->lo, kinds[a]); /* may break a relation (a 1 us horizon): both refuse */
      check_true(agree(pi, pi->hi, kinds[a]) || strstr(pi->key ? pi->key : "", "ms"));
      check_true(agree(pi, pi->def / pi->to_si, kinds[a]));
    }
  }
  check_true(n_numeric >= 20);
  /* relations: the coil's inductance, the trace grid */
  pom_dyn_params p;
  pom_error err;
  pom_error_clear(&err);
  check_true(load_text(&p, "actuator = { inductance_H = 0.0; };", &err) == POM_ERR_CONFIG &&
             strstr(err.message, "actuator.inductance_H") != NULL);
  check_true(load_text(&p,
                       "actuator = { inductance_H = 0.0; }; scene = { coil_inductance = "
                       "false; };",
                       &err) == POM_OK);
  check_true(pom_dyn_params_check(&p, &err) == POM_OK);
  p.scene.coil_inductance = 1;
  check_true(pom_dyn_params_check(&p, &err) == POM_ERR_ARG &&
             strstr(err.message, "actuator.inductance_H") != NULL);
  check_true(load_text(&p, "maneuver = { horizon_ms = 1.0; output_dt_ms = 2.0; };", &err) ==
             POM_ERR_CONFIG);
  pom_dyn_params_defaults(&p);
  p.maneuver.output_dt = 2.0 * p.maneuver.horizon;
  check_true(pom_dyn_params_check(&p, &err) == POM_ERR_ARG &&
             strstr(err.message, "maneuver.output_dt_ms") != NULL);
  /* NaN and enum values outside their tables */
  pom_dyn_params_defaults(&p);
  p.solver.rtol = NAN;
  check_true(pom_dyn_params_check(&p, &err) == POM_ERR_ARG &&
             strstr(err.message, "solver.rtol") != NULL);
  pom_dyn_params_defaults(&p);
  p.joints.model = (pom_joint_model)7;
  check_true(pom_dyn_params_check(&p, &err) == POM_ERR_ARG &&
             strstr(err.message, "joints.model") != NULL);
  pom_dyn_params_defaults(&p);
  p.scene.gravity = 2;
  check_true(pom_dyn_params_check(&p, &err) == POM_ERR_ARG);
  pom_dyn_params_defaults(&p);
  p.actuator.kind = (pom_actuator_kind)5;
  check_true(pom_dyn_params_check(&p, &err) == POM_ERR_ARG &&
             strstr(err.message, "neither") != NULL);
}

/* ---- 3. names ------------------------------------------------------------------ */
static void test_names(void) {
  const pom_dyn_param_info *s = pom_dyn_param_schema();
  const char *const *groups = pom_dyn_param_groups();
  pom_dyn_params p;
  pom_error err;
  pom_error_clear(&err);
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
    int listed = 0;
    for (int g = 0; groups[g]; ++g)
      listed |= strcmp(groups[g], s[k].group) == 0;
    check_true(listed);
    check_true(s[k].meaning && s[k].meaning[0]);
    for (int a = 0; a < POM_ACT_KINDS; ++a)
      for (int j = 0; j < POM_DYN_N_PARAMS; ++j) /* unique keys and attributes */
        for (int b = 0; b < POM_ACT_KINDS && j != k; ++b) {
          char ka[96], kb[96], ha[128], hb[128];
          pom_dyn_param_key(&s[k], (pom_actuator_kind)a, ka, sizeof ka);
          pom_dyn_param_key(&s[j], (pom_actuator_kind)b, kb, sizeof kb);
          check_true(strcmp(ka, kb) != 0);
          pom_dyn_param_h5_name(&s[k], (pom_actuator_kind)a, ha, sizeof ha);
          pom_dyn_param_h5_name(&s[j], (pom_actuator_kind)b, hb, sizeof hb);
          check_true(strcmp(ha, hb) != 0);
        }
    if (s[k].type != POM_DYN_PARAM_ENUM) continue;
    /* every name parses to its index and is written back */
    for (int i = 0; s[k].names[i]; ++i) {
      char text[256];
      snprintf(text, sizeof text, "%s = { %s = \"%s\"; };", s[k].group, s[k].key, s[k].names[i]);
      check_true(load_text(&p, text, &err) == POM_OK);
      check_true(pom_dyn_param_value(&p, &s[k]) == (double)i);
      check_true(strcmp(pom_dyn_param_choice(&p, &s[k]), s[k].names[i]) == 0);
      check_true(pom_cfg_choice_name(s[k].names, i) == s[k].names[i]);
    }
    char text[256];
    snprintf(text, sizeof text, "%s = { %s = \"no-such-name\"; };", s[k].group, s[k].key);
    check_true(load_text(&p, text, &err) == POM_ERR_CONFIG);
  }
  check_true(strcmp(pom_cfg_choice_name(pom_dyn_orient_names, 2), "?") == 0);
  check_true(strcmp(pom_cfg_choice_name(pom_dyn_orient_names, -1), "?") == 0);
}

/* ---- 4. HDF5 provenance --------------------------------------------------------- */
static void test_h5(void) {
  char path[] = "/tmp/test_dyn_params_XXXXXX";
  int fd = mkstemp(path);
  check_true(fd >= 0);
  if (fd < 0) return;
  close(fd);
  const pom_dyn_param_info *s = pom_dyn_param_schema();
  pom_error err;
  pom_error_clear(&err);
  for (int a = 0; a < POM_ACT_KINDS; ++a) {
    pom_dyn_params p;
    pom_dyn_params_defaults(&p);
    p.actuator.kind = (pom_actuator_kind)a;
    p.maneuver.horizon = 0.0423;
    hid_t file = -1;
    check_true(pom_h5_create_file(&file, path, &err) == POM_OK);
    check_true(pom_dyn_params_h5_describe(file, &p, &err) == POM_OK);
    check_true(H5Aexists(file, "controller_type") > 0);
    for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
      char name[128];
      pom_dyn_param_h5_name(&s[k], p.actuator.kind, name, sizeof name);
      check_true(H5Aexists(file, name) > 0);
    }
    double h = 0.0;
    hid_t at = H5Aopen(file, "maneuver_horizon_s", H5P_DEFAULT);
    check_true(at >= 0 && H5Aread(at, H5T_NATIVE_DOUBLE, &h) >= 0);
    if (at >= 0) H5Aclose(at);
    check_true(h == 0.0423);
    check_true(pom_h5_close_file(file, &err) == POM_OK);
  }
  unlink(path);
}

int main(void) {
  test_defaults();
  test_ranges();
  test_names();
  test_h5();
  return check_summary("test_dyn_params");
}
