/* pom_dyn_freq.h - small-signal frequency response of the closed loop
 * (mechanism + coil + controller) linearized about an equilibrium that holds
 * a pose (docs/capability.md, "Small-signal frequency response"; issue 28).
 *
 * The state equation y_dot = f(y, s) of the model (s: the actuators'
 * setpoints) is linearized about the equilibrium y* with f(y*, s*) = 0 that
 * holds the pose: A = df/dy from the formulation's analytic Jacobian,
 * B = df/ds. A setpoint rotation delta about the fixed axis e maps to the
 * setpoints by the kinematic Jacobian (delta s = J e delta), the output is
 * the platform's small rotation vector; T(jw) = C (jw I - A)^-1 B. */
#ifndef POM_DYN_FREQ_H
#define POM_DYN_FREQ_H

#include "pom_dynamics.h"

#include <stdio.h>

/* Largest number of parasitic modes reported. */
#define POM_DYN_FREQ_MAX_MODES 16

/* What pom_dyn_freq_response computes. */
enum {
  POM_DYN_FREQ_AXIS = 0, /* T_ee: setpoint rotation about fixed axis e -> platform rotation
                            about e (axis 0, 1, 2 = x, y, z), not normalized (|T_ee(0)| is 1
                            with integral action) */
  POM_DYN_FREQ_LOOP = 1, /* L_kk: loop gain of actuator `axis`, broken at its voltage input
                            (the others closed); the phase of -L's negative-feedback form:
                            the margins read 1 + L = 0 */
  POM_DYN_FREQ_WORST = 2 /* the worst real direction's gain relative to DC,
                            min over unit e of |T(jw) e| / |T(0) e| (axis ignored); the phase
                            is that of e^T T(jw) T(0)^-1 e along that direction */
};

/* Figures at one pose. Frequencies in Hz, gains in dB, angles in deg; NaN
 * where a figure does not exist (no crossover: margin +inf is reported as
 * INFINITY; bandwidth beyond the searched band: NaN). */
typedef struct {
  double bandwidth_hz[3];     /* -3 dB below DC, setpoint rotation about fixed x,y,z -> platform
                                 rotation about it (Hz) */
  double bandwidth_worst_hz;  /* smallest over all directions (worst direction) (Hz) */
  double worst_dir[3];        /* unit vector of that direction (fixed frame) */
  double peak_db[3];          /* resonant peak per axis: max |T| in dB over DC (0 if none) */
  double peak_db_worst;       /* the same for the largest singular value (dB) */
  double gain_margin_db[3];   /* per actuator loop, broken at its input (dB; INFINITY when the
                                 phase never crosses -180 deg) */
  double phase_margin_deg[3]; /* per actuator loop (deg; INFINITY when |L| never crosses 1) */
  double crossover_hz[3];     /* gain crossover |L| = 1 of each actuator loop (Hz; NaN if none) */
  int n_modes;                /* parasitic joint modes found (0 on the rigid path) */
  double mode_hz[POM_DYN_FREQ_MAX_MODES];   /* their natural frequencies |lambda|/2pi,
                                               ascending (Hz) */
  double mode_zeta[POM_DYN_FREQ_MAX_MODES]; /* their damping ratios -Re lambda / |lambda| */
  /* added by cap-freq */
  int n_actuators;        /* loops in the figures (3 on the shipped architectures) */
  double dc_gain[3];      /* |T_ee(0)| per axis (1 with integral action) */
  double slowest_pole_hz; /* |lambda| / 2 pi of the closed loop's slowest non-zero pole (Hz) */
  int stable;             /* 1 when every closed-loop pole has Re < 0 (the zero poles of the
                             energy accumulators aside) */
} pom_dyn_freq_figures;

/* The figures of the closed loop linearized about the equilibrium holding
 * the pose q_pose (joint coordinates, as pom_dyn_simulate's target: m or rad
 * per actuator). d is used as scratch (its last simulation's state is
 * unchanged). POM_ERR_ARG for a model without an architecture,
 * POM_ERR_NOCONVERGE when no equilibrium is found, POM_ERR_UNREACHABLE at an
 * unassemblable pose, POM_ERR_EULER_SINGULAR at pitch 90 deg with Euler
 * angles. */
pom_status pom_dyn_freq_figures_at(const pom_dyn_model *m, pom_dyn_data *d, const double q_pose[3],
                                   pom_dyn_freq_figures *out, pom_error *err);

/* Bode data at the pose q_pose: kind POM_DYN_FREQ_AXIS (T about fixed axis
 * `axis`), POM_DYN_FREQ_LOOP (loop gain of actuator `axis`) or
 * POM_DYN_FREQ_WORST, at nf frequencies f_hz[nf] (Hz, > 0): magnitude
 * mag_db[nf] (dB) and phase phase_deg[nf] (deg, unwrapped along f_hz from
 * its first value in (-180, 180]). Errors as pom_dyn_freq_figures_at. */
pom_status pom_dyn_freq_response(const pom_dyn_model *m, pom_dyn_data *d, const double q_pose[3],
                                 int kind, int axis, const double *f_hz, int nf, double *mag_db,
                                 double *phase_deg, pom_error *err);

/* The figures and the Bode data at q_pose as one JSON object on out (SI:
 * Hz, dB, deg; an infinite margin or a missing figure is null): the keys of
 * pom_dyn_freq_figures, then f_hz (a log grid from f_lo to f_hi Hz with
 * per_decade points a decade) and the curves axis[3], worst and loop[n]
 * ({mag_db, phase_deg}), which scripts/plot_bode.py draws. Errors as
 * pom_dyn_freq_figures_at; POM_ERR_ARG for a bad grid. */
pom_status pom_dyn_freq_json(FILE *out, const pom_dyn_model *m, pom_dyn_data *d,
                             const double q_pose[3], double f_lo, double f_hi, int per_decade,
                             pom_error *err);

#endif
