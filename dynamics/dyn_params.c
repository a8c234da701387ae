/* dyn_params.c - defaults and config loading of the dynamics parameters
 * (keys: docs/dynamics.md section 9). */
#include "pom_dynamics.h"

#include "pom_dyn_ctrl.h"

#include <stdio.h>
#include <string.h>

/* ---- defaults ------------------------------------------------------------ */
void pom_dyn_params_defaults(pom_dyn_params *p) {
  memset(p, 0, sizeof *p);
  /* reference actuator of docs/PARAMETERS.md (a) */
  p->actuator.force_constant = 3.8;
  p->actuator.resistance = 10.0;
  p->actuator.inductance = 1.45e-4;
  p->actuator.bearing_friction = 9.8e-2;
  p->actuator.voltage_limit = 24.0;
  p->actuator.sensor_gain = 833.33;
  p->actuator.kind = POM_ACT_PRISMATIC; /* "linear"; a rotary actuator needs its own values */
  /* the PID with the 3P-S-S/S reference gains, ideal form (its descriptors'
   * defaults; docs/PARAMETERS.md controller-form note) */
  pom_dyn_ctrl_set_defaults(&p->controller, &pom_dyn_ctrl_pid);
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
  p->solver.atol_scale = 0.0; /* natural sizes: rtol alone sets the accuracy (docs 7) */
  p->solver.max_step = 0.0;
  p->solver.max_steps = 200000;
  p->solver.linear_solver = POM_LINSOL_KLU;
  p->solver.jacobian = POM_JAC_ANALYTIC;
  p->solver.max_order = 5;
  p->solver.stability_limit_detection = 1;
  p->solver.max_wall = 60.0; /* generous: a maneuver takes milliseconds (docs 14) */
  p->solver.max_balance_error = 0.05;
  p->maneuver.horizon = 0.100;
  p->maneuver.settle_band = 0.02;
  p->maneuver.output_dt = 1.0e-4;
  p->maneuver.pointing_band = 1.0e-3;
  p->maneuver.pointing_band_rel = 0.0;
}

/* ---- names --------------------------------------------------------------- */
static const char *const orient_kinds[] = {"euler", "quaternion", NULL};
static const char *const linsol_kinds[] = {"dense", "klu", NULL};
static const char *const jacobian_kinds[] = {"analytic", "finite-difference", NULL};
static const char *const joint_models[] = {"parasitic", "rigid", NULL};
static const char *const inertia_kinds[] = {"full", "lumped", NULL};
/* each table lists its enum's values in order: the loader casts the index */
#define TABLE_LEN(t) (sizeof(t) / sizeof((t)[0]) - 1)
_Static_assert(TABLE_LEN(orient_kinds) == POM_ORIENT_QUATERNION + 1,
               "orient_kinds follows pom_orient_kind");
_Static_assert(TABLE_LEN(linsol_kinds) == POM_LINSOL_KLU + 1,
               "linsol_kinds follows pom_linsol_kind");
_Static_assert(TABLE_LEN(jacobian_kinds) == POM_JAC_FINITE_DIFFERENCE + 1,
               "jacobian_kinds follows pom_jac_kind");
_Static_assert(TABLE_LEN(joint_models) == POM_JOINTS_RIGID + 1,
               "joint_models follows pom_joint_model");
_Static_assert(TABLE_LEN(inertia_kinds) == POM_INERTIA_LUMPED + 1,
               "inertia_kinds follows pom_inertia_kind");
/* "actuator.<key>" of the constant (0), bearing friction (1) or sensor gain
 * (2) of an actuator kind */
static const char *actuator_key(char *buf, size_t cap, const pom_act_desc *kind, int which) {
  const char *key[3] = {kind->constant_key, kind->friction_key, kind->gain_key};
  snprintf(buf, cap, "actuator.%s", key[which]);
  return buf;
}

/* names from the tables above, indexed by the enum's value; "?" for a value
 * outside the table (never the first name by default) */
const char *pom_dyn_pid_form_name(pom_pid_form f) {
  return pom_cfg_choice_name(pom_dyn_ctrl_pid.options[0].names, (int)f); /* ctrl_pid.c */
}
const char *pom_dyn_orient_name(pom_orient_kind k) {
  return pom_cfg_choice_name(orient_kinds, (int)k);
}
const char *pom_dyn_linsol_name(pom_linsol_kind k) {
  return pom_cfg_choice_name(linsol_kinds, (int)k);
}
const char *pom_dyn_jacobian_name(pom_jac_kind k) {
  return pom_cfg_choice_name(jacobian_kinds, (int)k);
}
const char *pom_dyn_joint_model_name(pom_joint_model k) {
  return pom_cfg_choice_name(joint_models, (int)k);
}
const char *pom_dyn_inertia_name(pom_inertia_kind k) {
  return pom_cfg_choice_name(inertia_kinds, (int)k);
}

/* ---- loading ------------------------------------------------------------- */
pom_status pom_dyn_params_load(pom_dyn_params *p, const pom_cfg *cfg, pom_error *err) {
  pom_dyn_actuator *a = &p->actuator;
  pom_dyn_controller *c = &p->controller;
  pom_dyn_joints *j = &p->joints;
  pom_dyn_scene *s = &p->scene;
  pom_dyn_solver *v = &p->solver;
  pom_dyn_maneuver *m = &p->maneuver;
  int idx = 0;
  long lval = 0;

  /* actuator.kind chooses the units of the constant, friction and gain keys;
   * the other kinds' keys are refused by name (docs/config.md) */
  const char *kind_names[POM_ACT_KINDS + 1];
  for (int k = 0; k < POM_ACT_KINDS; ++k)
    kind_names[k] = pom_act_kind_desc((pom_actuator_kind)k)->name;
  kind_names[POM_ACT_KINDS] = NULL;
  idx = pom_act_kind_desc(a->kind) ? (int)a->kind : 0;
  POM_TRY(pom_cfg_choice_opt(cfg, "actuator.kind", kind_names, idx, &idx, err));
  a->kind = (pom_actuator_kind)idx;
  const pom_act_desc *kind = pom_act_kind_desc(a->kind);
  char keys[3][64], other[64];
  for (int k = 0; k < 3; ++k)
    actuator_key(keys[k], sizeof keys[k], kind, k);
  for (int o = 0; o < POM_ACT_KINDS; ++o)
    for (int k = 0; k < 3 && o != idx; ++k)
      if (pom_cfg_has(
              cfg, actuator_key(other, sizeof other, pom_act_kind_desc((pom_actuator_kind)o), k)))
        return pom_cfg_error(cfg, other, NULL, err,
                             "is a key of a %s actuator but actuator.kind = \"%s\": use %s",
                             kind_names[o], kind->name, keys[k]);
  POM_TRY(
      pom_cfg_real_opt(cfg, keys[0], 1.0, 1e-6, 1e4, a->force_constant, &a->force_constant, err));
  POM_TRY(pom_cfg_real_opt(cfg, "actuator.resistance_ohm", 1.0, 1e-6, 1e6, a->resistance,
                           &a->resistance, err));
  POM_TRY(pom_cfg_real_opt(cfg, "actuator.inductance_H", 1.0, 1e-12, 10.0, a->inductance,
                           &a->inductance, err));
  POM_TRY(pom_cfg_real_opt(cfg, keys[1], 1.0, 0.0, 1e6, a->bearing_friction, &a->bearing_friction,
                           err));
  POM_TRY(pom_cfg_real_opt(cfg, "actuator.voltage_limit_V", 1.0, 1e-3, 1e5, a->voltage_limit,
                           &a->voltage_limit, err));
  POM_TRY(pom_cfg_real_opt(cfg, keys[2], 1.0, 1e-6, 1e9, a->sensor_gain, &a->sensor_gain, err));

  POM_TRY(pom_dyn_ctrl_load(c, cfg, err)); /* the type, then its options and gains */

  POM_TRY(pom_cfg_real_opt(cfg, "joints.stiffness_N_per_m", 1.0, 1.0, 1e12, j->stiffness,
                           &j->stiffness, err));
  POM_TRY(pom_cfg_real_opt(cfg, "joints.damping_Ns_per_m", 1.0, 0.0, 1e9, j->damping, &j->damping,
                           err));
  POM_TRY(pom_cfg_real_opt(cfg, "joints.angular_stiffness_Nm_per_rad", 1.0, 1e-3, 1e12,
                           j->angular_stiffness, &j->angular_stiffness, err));
  POM_TRY(pom_cfg_real_opt(cfg, "joints.angular_damping_Nms_per_rad", 1.0, 0.0, 1e9,
                           j->angular_damping, &j->angular_damping, err));
  idx = (int)j->model;
  POM_TRY(pom_cfg_choice_opt(cfg, "joints.model", joint_models, idx, &idx, err));
  j->model = (pom_joint_model)idx; /* the enum values are the table indices */

  POM_TRY(pom_cfg_bool_opt(cfg, "scene.gravity", s->gravity, &s->gravity, err));
  POM_TRY(pom_cfg_bool_opt(cfg, "scene.bearing_friction", s->bearing_friction, &s->bearing_friction,
                           err));
  POM_TRY(
      pom_cfg_bool_opt(cfg, "scene.coil_inductance", s->coil_inductance, &s->coil_inductance, err));
  idx = (int)s->orientation;
  POM_TRY(pom_cfg_choice_opt(cfg, "scene.orientation", orient_kinds, idx, &idx, err));
  s->orientation = (pom_orient_kind)idx; /* the enum values are the table indices */
  idx = (int)s->limb_inertia;
  POM_TRY(pom_cfg_choice_opt(cfg, "scene.limb_inertia", inertia_kinds, idx, &idx, err));
  s->limb_inertia = (pom_inertia_kind)idx; /* the enum values are the table indices */
  POM_TRY(
      pom_cfg_bool_opt(cfg, "scene.universal_joint", s->universal_joint, &s->universal_joint, err));

  POM_TRY(pom_cfg_real_opt(cfg, "solver.rtol", 1.0, 1e-13, 1e-1, v->rtol, &v->rtol, err));
  /* 0 = natural sizes (docs/dynamics.md section 7) */
  POM_TRY(pom_cfg_real_opt(cfg, "solver.atol_scale", 1.0, 0.0, 1.0, v->atol_scale, &v->atol_scale,
                           err));
  POM_TRY(
      pom_cfg_real_opt(cfg, "solver.max_step_ms", 1e-3, 0.0, 1e6, v->max_step, &v->max_step, err));
  POM_TRY(pom_cfg_int_opt(cfg, "solver.max_steps", 1, 1000000000L, v->max_steps, &lval, err));
  v->max_steps = lval;
  idx = (int)v->linear_solver;
  POM_TRY(pom_cfg_choice_opt(cfg, "solver.linear_solver", linsol_kinds, idx, &idx, err));
  v->linear_solver = (pom_linsol_kind)idx; /* the enum values are the table indices */
  idx = (int)v->jacobian;
  POM_TRY(pom_cfg_choice_opt(cfg, "solver.jacobian", jacobian_kinds, idx, &idx, err));
  v->jacobian = (pom_jac_kind)idx; /* the enum values are the table indices */
  POM_TRY(pom_cfg_int_opt(cfg, "solver.max_order", 1, 5, v->max_order, &lval, err));
  v->max_order = (int)lval;
  POM_TRY(pom_cfg_bool_opt(cfg, "solver.stability_limit_detection", v->stability_limit_detection,
                           &v->stability_limit_detection, err));
  POM_TRY(
      pom_cfg_real_opt(cfg, "solver.max_wall_s", 1.0, 0.0, 1e6, v->max_wall, &v->max_wall, err));
  POM_TRY(pom_cfg_real_opt(cfg, "solver.max_balance_error", 1.0, 0.0, 1e3, v->max_balance_error,
                           &v->max_balance_error, err));

  POM_TRY(
      pom_cfg_real_opt(cfg, "maneuver.horizon_ms", 1e-3, 1e-3, 1e7, m->horizon, &m->horizon, err));
  POM_TRY(pom_cfg_real_opt(cfg, "maneuver.settle_band_percent", 1e-2, 1e-6, 100.0, m->settle_band,
                           &m->settle_band, err));
  POM_TRY(pom_cfg_real_opt(cfg, "maneuver.output_dt_ms", 1e-3, 1e-6, 1e6, m->output_dt,
                           &m->output_dt, err));
  POM_TRY(pom_cfg_real_opt(cfg, "maneuver.pointing_band_mrad", 1e-3, 1e-6, 1e3, m->pointing_band,
                           &m->pointing_band, err));
  POM_TRY(pom_cfg_real_opt(cfg, "maneuver.pointing_band_percent", 1e-2, 0.0, 100.0,
                           m->pointing_band_rel, &m->pointing_band_rel, err));
  if (m->output_dt > m->horizon)
    return pom_cfg_error(cfg, "maneuver.output_dt_ms", NULL, err,
                         "must not exceed maneuver.horizon_ms (%g ms)", m->horizon * 1e3);
  if (m->horizon / m->output_dt > 1e7)
    return pom_cfg_error(cfg, "maneuver.output_dt_ms", NULL, err,
                         "more than 1e7 trace samples over the horizon; raise output_dt_ms");
  return POM_OK;
}
