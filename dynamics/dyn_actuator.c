/* dyn_actuator.c - the voice coil and its saturated controller, the same
 * law for every formulation and for both actuator kinds (docs/dynamics.md
 * section 4): linear (q in m, force K_m i along the axis) or rotary (q in rad,
 * torque K_t i about the axis). The control law itself is the controller
 * type's (pom_dyn_ctrl.h); this file saturates its voltage and drives the
 * coil. Allocates nothing. */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <string.h>

/* ---- the controller --------------------------------------------------------- */
/* What the sensors give (q, qd), the setpoint and the controller's states:
 * the type's law, and its partials when asked. */
double pom_dyn_controller_law(const pom_dyn_model *m, const pom_dyn_data *d, int a, double q,
                              double qd, const double *y, double *zdot, pom_dyn_ctrl_partials *cp) {
  const dyn_actuator *ac = &m->act[a];
  const pom_dyn_ctrl_input in = {d->target[a], q, qd, m->par.actuator.sensor_gain};
  const double *z = ac->ctrl_state >= 0 ? y + ac->ctrl_state : NULL;
  if (cp) m->ctrl->partials(&m->par.controller, &in, z, cp);
  return m->ctrl->law(&m->par.controller, &in, z, zdot);
}

/* A coupled law over every actuator: the sensors, then the voltages and the
 * state rates (the states are contiguous per actuator, actuator-major, as
 * both formulations lay them out). */
void pom_dyn_controller_pass(const pom_dyn_model *m, pom_dyn_data *d, const double *q,
                             const double *qd, const double *y, double *ydot) {
  const int n = m->n_actuators, ns = m->ctrl->n_states;
  double current[POM_MECH_MAX_ACTUATORS];
  int inductive = n > 0 && m->act[0].flux_state >= 0;
  for (int a = 0; a < n && inductive; ++a)
    current[a] = y[m->act[a].flux_state] / m->par.actuator.inductance;
  double z[POM_MECH_MAX_ACTUATORS * POM_DYN_CTRL_MAX_STATES];
  double zdot[POM_MECH_MAX_ACTUATORS * POM_DYN_CTRL_MAX_STATES];
  for (int a = 0; a < n; ++a)
    for (int k = 0; k < ns; ++k)
      z[a * ns + k] = y[m->act[a].ctrl_state + k];
  const pom_dyn_ctrl_sensed s = {d->t, n, d->target, q, qd, inductive ? current : NULL};
  m->ctrl->law_all(&m->par.controller, m->ctrl_model, d->ctrl_work, &s, m->par.actuator.sensor_gain,
                   ns > 0 ? z : NULL, d->ctrl_u, ydot && ns > 0 ? zdot : NULL);
  if (ydot)
    for (int a = 0; a < n; ++a)
      for (int k = 0; k < ns; ++k)
        ydot[m->act[a].ctrl_state + k] = zdot[a * ns + k];
}

/* ---- the law ------------------------------------------------------------- */
/* The controller's voltage, saturation, coil (flux state or quasi-static),
 * bearing friction; outputs and (with ydot) the coil, controller-state and
 * energy-accumulator derivatives of actuator a. */
double pom_dyn_actuator_law(const pom_dyn_model *m, pom_dyn_data *d, int a, double q, double qd,
                            const double *y, double *ydot) {
  const pom_dyn_actuator *ap = &m->par.actuator;
  const dyn_actuator *ac = &m->act[a];
  dyn_outputs *o = &d->out;
  double u_raw;
  if (m->ctrl->law_all) {
    u_raw = d->ctrl_u[a]; /* the coupled law ran for every actuator (pom_dyn_controller_pass) */
  } else {
    double *zdot = (ydot && ac->ctrl_state >= 0) ? ydot + ac->ctrl_state : NULL;
    u_raw = pom_dyn_controller_law(m, d, a, q, qd, y, zdot, NULL);
  }
  u_raw += d->u_inject[a]; /* 0 but where a loop is broken (dyn_freq.c) */
  double lim = ap->voltage_limit;
  double u = u_raw > lim ? lim : (u_raw < -lim ? -lim : u_raw);
  /* a perturbed model's evaluation for the sensitivities: the nominal's
   * saturation pattern, so that the difference is the derivative of one
   * smooth piece (dyn_sens.c, docs/optimize.md 12.1) */
  if (d->sat_frozen) u = d->sat_mode[a] ? d->sat_mode[a] * lim : u_raw;
  double i;
  if (ac->flux_state >= 0)
    i = y[ac->flux_state] / ap->inductance;
  else
    i = (u - ap->force_constant * qd) / ap->resistance;
  double b = m->par.scene.bearing_friction ? ap->bearing_friction : 0.0;
  o->q[a] = q;
  o->q_dot[a] = qd;
  o->u_raw[a] = u_raw;
  o->current[a] = i;
  o->voltage[a] = u;
  if (ydot) {
    if (ac->flux_state >= 0)
      ydot[ac->flux_state] = u - ap->resistance * i - ap->force_constant * qd;
    double *acc = ydot + ac->acc_state;
    double pw = u * i;
    acc[DYN_ACC_SOURCE] = pw;
    acc[DYN_ACC_SOURCE_POS] = pw > 0 ? pw : 0.0;
    acc[DYN_ACC_SATURATED] = fabs(u_raw) >= lim ? 1.0 : 0.0;
    acc[DYN_ACC_COIL] = ap->resistance * i * i;
    acc[DYN_ACC_BEARING] = b * qd * qd;
  }
  o->effort[a] = ap->force_constant * i - b * qd;
  return o->effort[a];
}

/* ---- its derivatives ------------------------------------------------------ */
/* z enters u_raw with the controller's du/dz (the PID: S K_I, or S K_P K_I in
 * the ideal form) and passes the saturation only inside the limits; i is
 * flux / L (inductive) or (u - K_m qd) / R_c (quasi-static); the effort is
 * K_m i - b qd. Only for a controller with analytic partials and at most one
 * state (m->ctrl_analytic). */
void pom_dyn_actuator_law_partials(const pom_dyn_model *m, const pom_dyn_data *d, int a, double q,
                                   double qd, const double *y, dyn_law_partials *lp) {
  const pom_dyn_actuator *ap = &m->par.actuator;
  const dyn_actuator *ac = &m->act[a];
  pom_dyn_ctrl_partials cp;
  memset(&cp, 0, sizeof cp); /* a controller without a state leaves its z entries */
  double u_raw = pom_dyn_controller_law(m, d, a, q, qd, y, NULL, &cp);
  double g_z = cp.du_dz[0];
  lp->dzd_dz = cp.dzd_dz[0][0];
  lp->dzd_dq = cp.dzd_dq[0];
  lp->dzd_dqd = cp.dzd_dqd[0];
  double lim = ap->voltage_limit;
  int saturated = u_raw > lim || u_raw < -lim;
  double K = ap->force_constant, Rc = ap->resistance;
  double b = m->par.scene.bearing_friction ? ap->bearing_friction : 0.0;
  lp->u = u_raw > lim ? lim : (u_raw < -lim ? -lim : u_raw);
  lp->du_dz = saturated ? 0.0 : g_z;
  lp->du_dq = saturated ? 0.0 : cp.du_dq;
  lp->du_dqd = saturated ? 0.0 : cp.du_dqd;
  if (ac->flux_state >= 0) {
    lp->i = y[ac->flux_state] / ap->inductance;
    lp->di_dz = lp->di_dq = lp->di_dqd = 0.0;
    lp->di_dflux = 1.0 / ap->inductance;
  } else {
    lp->i = (lp->u - K * qd) / Rc;
    lp->di_dz = lp->du_dz / Rc;
    lp->di_dq = lp->du_dq / Rc;
    lp->di_dqd = (lp->du_dqd - K) / Rc;
    lp->di_dflux = 0.0;
  }
  lp->effort = K * lp->i - b * qd;
  lp->dF_dz = K * lp->di_dz;
  lp->dF_dflux = K * lp->di_dflux;
  lp->dF_dq = K * lp->di_dq;
  lp->dF_dqd = K * lp->di_dqd - b;
  lp->dflux_dz = lp->du_dz - Rc * lp->di_dz;
  lp->dflux_dflux = -Rc * lp->di_dflux;
  lp->dflux_dq = lp->du_dq - Rc * lp->di_dq;
  lp->dflux_dqd = lp->du_dqd - Rc * lp->di_dqd - K;
  lp->dbearing_dqd = 2.0 * b * qd;
}

/* ---- stored energy of the coils ------------------------------------------ */
double pom_dyn_add_coil_energy(const pom_dyn_model *m, const double *y, double E) {
  for (int a = 0; a < m->n_actuators; ++a)
    if (m->act[a].flux_state >= 0) {
      double lam = y[m->act[a].flux_state];
      E += 0.5 * lam * lam / m->par.actuator.inductance;
    }
  return E;
}

/* ---- the rotary coordinate ------------------------------------------------ */
void pom_dyn_perp_basis(double e1[3], double e2[3], const double n[3]) {
  double t[3] = {1.0, 0.0, 0.0};
  if (fabs(n[0]) > 0.6) pom_v3_set(t, 0.0, 1.0, 0.0);
  double c[3];
  pom_v3_cross(c, n, t);
  pom_v3_normalize(e1, c);
  pom_v3_cross(e2, n, e1);
}

double pom_dyn_revolute_angle(const double n[3], const double r0[3], const double r1[3]) {
  double c[3];
  pom_v3_cross(c, r0, r1);
  return atan2(pom_v3_dot(n, c), pom_v3_dot(r0, r1));
}
