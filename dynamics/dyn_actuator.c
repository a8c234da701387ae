/* dyn_actuator.c - the voice coil and its saturated PID controller, the same
 * law for every formulation and for both actuator kinds (docs/dynamics.md
 * section 4): linear (q in m, force K_m i along the axis) or rotary (q in rad,
 * torque K_t i about the axis). Allocates nothing. */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>

/* ---- the law ------------------------------------------------------------- */
/* PID on e = target - q with the derivative on the measured rate, saturation,
 * coil (flux state or quasi-static), bearing friction; outputs and (with
 * ydot) the coil, integral and energy-accumulator derivatives of actuator a. */
double pom_dyn_actuator_law(const pom_dyn_model *m, pom_dyn_data *d, int a, double q, double qd,
                            const double *y, double *ydot) {
  const pom_dyn_actuator *ap = &m->par.actuator;
  const pom_dyn_controller *cp = &m->par.controller;
  const dyn_actuator *ac = &m->act[a];
  dyn_outputs *o = &d->out;
  double e = d->target[a] - q;
  double z = y[ac->int_state];
  double u_raw;
  if (cp->form == POM_PID_IDEAL)
    u_raw = ap->sensor_gain * cp->kp * (e + cp->ki * z - cp->kd * qd);
  else
    u_raw = ap->sensor_gain * (cp->kp * e + cp->ki * z - cp->kd * qd);
  double lim = ap->voltage_limit;
  double u = u_raw > lim ? lim : (u_raw < -lim ? -lim : u_raw);
  double i;
  if (ac->flux_state >= 0)
    i = y[ac->flux_state] / ap->inductance;
  else
    i = (u - ap->force_constant * qd) / ap->resistance;
  double b = m->par.scene.bearing_friction ? ap->bearing_friction : 0.0;
  o->q[a] = q;
  o->q_dot[a] = qd;
  o->current[a] = i;
  o->voltage[a] = u;
  if (ydot) {
    if (ac->flux_state >= 0)
      ydot[ac->flux_state] = u - ap->resistance * i - ap->force_constant * qd;
    ydot[ac->int_state] = e;
    double *acc = ydot + ac->acc_state;
    double pw = u * i;
    acc[DYN_ACC_SOURCE] = pw;
    acc[DYN_ACC_SOURCE_POS] = pw > 0 ? pw : 0.0;
    acc[DYN_ACC_SATURATED] = fabs(u_raw) >= lim ? 1.0 : 0.0;
    acc[DYN_ACC_COIL] = ap->resistance * i * i;
    acc[DYN_ACC_BEARING] = b * qd * qd;
  }
  return ap->force_constant * i - b * qd;
}

/* ---- its derivatives ------------------------------------------------------ */
/* z enters u_raw linearly (gain S K_I, or S K_P K_I in the ideal form) and
 * passes the saturation only inside the limits; i is flux / L (inductive) or
 * (u - K_m qd) / R_c (quasi-static); the effort is K_m i - b qd. */
void pom_dyn_actuator_law_partials(const pom_dyn_model *m, const pom_dyn_data *d, int a, double q,
                                   double qd, const double *y, dyn_law_partials *lp) {
  const pom_dyn_actuator *ap = &m->par.actuator;
  const pom_dyn_controller *cp = &m->par.controller;
  const dyn_actuator *ac = &m->act[a];
  double e = d->target[a] - q, z = y[ac->int_state], u_raw, g_z;
  if (cp->form == POM_PID_IDEAL) {
    u_raw = ap->sensor_gain * cp->kp * (e + cp->ki * z - cp->kd * qd);
    g_z = ap->sensor_gain * cp->kp * cp->ki;
  } else {
    u_raw = ap->sensor_gain * (cp->kp * e + cp->ki * z - cp->kd * qd);
    g_z = ap->sensor_gain * cp->ki;
  }
  double lim = ap->voltage_limit;
  int saturated = u_raw > lim || u_raw < -lim;
  lp->u = u_raw > lim ? lim : (u_raw < -lim ? -lim : u_raw);
  lp->du_dz = saturated ? 0.0 : g_z;
  if (ac->flux_state >= 0) {
    lp->i = y[ac->flux_state] / ap->inductance;
    lp->di_dz = 0.0;
    lp->di_dflux = 1.0 / ap->inductance;
  } else {
    lp->i = (lp->u - ap->force_constant * qd) / ap->resistance;
    lp->di_dz = lp->du_dz / ap->resistance;
    lp->di_dflux = 0.0;
  }
  lp->dF_dz = ap->force_constant * lp->di_dz;
  lp->dF_dflux = ap->force_constant * lp->di_dflux;
  lp->dflux_dz = lp->du_dz - ap->resistance * lp->di_dz;
  lp->dflux_dflux = -ap->resistance * lp->di_dflux;
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
