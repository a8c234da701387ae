/* pom_dyn_sens.h - design gradients of one maneuver's metrics by forward
 * sensitivities (CVODES) through the exact (rigid-joint) formulation
 * (derivation: docs/optimize.md, "Design gradients").
 *
 * The dynamics know nothing of configs: a parameter p_j is given as the two
 * models built by the caller at p_j + h_j and p_j - h_j (same architecture,
 * formulation, state layout and controller type as the nominal model) and
 * the setpoints each of them runs to. Every derivative the engine needs of
 * the right-hand side and of the metric functions is the central
 * directional difference along (p, y) = (1, s_j) between those two models:
 *   J s_j + df/dp_j = (f_{p+h}(y + h s_j) - f_{p-h}(y - h s_j)) / (2 h),
 * which holds for any numeric design parameter (geometry, masses and
 * inertias, coil, gains) without a derivative written per parameter; the
 * corrector's later calls at the same (t, y) add the change along the
 * correction by one plus-model evaluation (docs/optimize.md 12.5). */
#ifndef POM_DYN_SENS_H
#define POM_DYN_SENS_H

#include "pom_dynamics.h"

#define POM_DYN_SENS_MAX 16 /* parameters of one sensitivity run at most */

/* Why a derivative is undefined (docs/optimize.md, "Design gradients"). */
typedef enum {
  POM_DYN_GRAD_OK = 0,           /* defined */
  POM_DYN_GRAD_NEVER_SETTLED,    /* outside the band at the horizon: the time is censored */
  POM_DYN_GRAD_SETTLED_AT_START, /* inside the band from t = 0 on (or no band: zero step) */
  POM_DYN_GRAD_GRAZING,          /* the last crossing grazes the band (dg/dt ~ 0), a later
                                    excursion comes within the grazing margin of it, or the
                                    excursion outside it ends peaks within that margin */
  POM_DYN_GRAD_TIE,              /* execution time: two actuators' settling times tie; peak
                                    current: two candidates (coils or times) tie */
  POM_DYN_GRAD_UNKNOWN,          /* the metric itself is NaN (no target orientation, no
                                    reference trajectory, a failed maneuver) */
  POM_DYN_GRAD_NONFINITE,        /* a non-finite sensitivity (an evaluation failed) */
  POM_DYN_GRAD_PEAK_EDGE,        /* peak current at t = 0 or at the horizon (no di/dt = 0) */
  POM_DYN_GRAD_PEAK_KINK         /* peak current on a kink of i(t) (a jump of di/dt: the
                                    voltage saturation's corner without coil inductance) */
} pom_dyn_grad_why;

/* Short text of a reason ("never settled", ...), static storage. */
const char *pom_dyn_grad_why_text(pom_dyn_grad_why why);

/* d(metric)/dp_j for j < n_params (SI units of the metric per unit of p_j as
 * the caller counts it: h_j's unit); NaN where undefined. */
typedef struct {
  double d[POM_DYN_SENS_MAX];
  int defined;          /* 1: d[] are derivatives; 0: undefined, d[] NaN */
  pom_dyn_grad_why why; /* POM_DYN_GRAD_OK when defined */
} pom_dyn_dmetric;

/* The gradients of one maneuver. */
typedef struct {
  int n_params;
  pom_dyn_dmetric energy_total;           /* J per unit of p */
  pom_dyn_dmetric energy[3];              /* J */
  pom_dyn_dmetric tracking_rms_error;     /* rad */
  pom_dyn_dmetric final_pointing_error;   /* rad */
  pom_dyn_dmetric settling_time[3];       /* s */
  pom_dyn_dmetric execution_time;         /* s */
  pom_dyn_dmetric pointing_settling_time; /* s */
  /* the crossing rates dg/dt at the last band crossing of each actuator and
   * of the pointing angle (m/s, rad/s; 0 where there is none): how far from
   * grazing the derivative was taken */
  double crossing_rate[3];
  double pointing_crossing_rate;
  long sens_rhs_evals; /* right-hand sides spent on the sensitivities (both models) */
  long restarts;       /* restarts at a raw voltage entering or leaving its linear band */
  /* restarts where the nominal's saturation pattern at a step's end
   * disagreed with the one the sensitivities followed (two crossings
   * inside one step; docs/optimize.md 12.1) */
  long resyncs;
  /* the peak coil current (metrics->peak_current): its derivative by the
   * envelope theorem, sign(i) di/dp at the argmax (docs/optimize.md 12.2),
   * with the argmax's time (s) and coil (0-based) */
  pom_dyn_dmetric peak_current; /* A */
  double peak_time;
  int peak_coil;
} pom_dyn_grad;

/* Sensitivity corrector: CVODES' staggered (default) or simultaneous. */
typedef enum { POM_DYN_SENS_STAGGERED = 0, POM_DYN_SENS_SIMULTANEOUS = 1 } pom_dyn_sens_method;

/* What the caller differentiates with respect to. */
typedef struct {
  int n;                                        /* parameters, 1..POM_DYN_SENS_MAX */
  const pom_dyn_model *plus[POM_DYN_SENS_MAX];  /* model at p_j + h_j */
  const pom_dyn_model *minus[POM_DYN_SENS_MAX]; /* model at p_j - h_j */
  double step[POM_DYN_SENS_MAX];                /* h_j > 0 (the caller's unit of p_j) */
  double target_plus[POM_DYN_SENS_MAX][3];      /* setpoints of plus[j] (m or rad): the nominal
                                                   target in joint space; IK of the perturbed
                                                   geometry for an orientation target */
  double target_minus[POM_DYN_SENS_MAX][3];     /* of minus[j] */
  double scale[POM_DYN_SENS_MAX]; /* typical |p_j| (h_j's unit): CVODES' pbar, the scale of
                                     s_j in the error test; 0 = 1e4 h_j */
  pom_dyn_sens_method method;     /* default staggered */
  int error_control;              /* 1 (default): the sensitivities enter CVODES' error test */
  int peak_current;    /* 1 (default): locate the peak coil current and its derivative (three more
                          evaluations per step, docs/optimize.md 12.2); 0: left undefined */
  double noise_margin; /* how far above the differencing's rounding the sensitivities' relative
                          tolerance stays: max(rtol, noise_margin eps scale_j / step_j)
                          (docs/optimize.md 12.1, 12.4); in [POM_DYN_SENS_MARGIN_MIN,
                          POM_DYN_SENS_MARGIN_MAX], default POM_DYN_SENS_MARGIN_DEFAULT; smaller
                          = more accurate sensitivities at more steps */
} pom_dyn_sens_spec;

/* The noise margin's default and range (docs/optimize.md 12.4: at 10 the
 * error test chases the rounding noise, 9x the steps on one maneuver; at
 * 3e2 every energy of the 100-design check meets the 1e-5, at 1e3
 * three of 2315 did not; the margin acts only below rtol = margin x
 * 7.4e-11, so the shipped rtol 1e-6 runs the same steps either way). */
#define POM_DYN_SENS_MARGIN_DEFAULT 3e2
#define POM_DYN_SENS_MARGIN_MIN     1.0
#define POM_DYN_SENS_MARGIN_MAX     1e6

/* Defaults: n 0, staggered, error control on, peak current on, noise margin
 * POM_DYN_SENS_MARGIN_DEFAULT. */
void pom_dyn_sens_spec_defaults(pom_dyn_sens_spec *s);

/* One maneuver of model m on data d to `target` (as pom_dyn_simulate; the
 * metrics are those of the same run) with the forward sensitivities of
 * spec: grad receives every derivative with its defined flag. Only the
 * exact formulation (joints.model = "rigid"): POM_ERR_ARG for a parasitic
 * model, for perturbed models of another layout or controller type, or for
 * a step that is not positive. A failed maneuver returns its status with
 * every derivative undefined (POM_DYN_GRAD_UNKNOWN). d stays usable for
 * plain runs, which it leaves unchanged bit for bit. */
pom_status pom_dyn_simulate_sens(const pom_dyn_model *m, pom_dyn_data *d, const double target[3],
                                 const pom_dyn_sens_spec *spec, pom_dyn_metrics *metrics,
                                 pom_dyn_grad *grad, pom_error *err);

/* The grazing margin: a crossing whose |dg/dt| is below
 * POM_DYN_GRAD_GRAZE x band / horizon, or after which the band function
 * comes back within POM_DYN_GRAD_GRAZE_MARGIN x band of the band edge, or
 * that ends an excursion outside the band peaking within
 * POM_DYN_GRAD_GRAZE_MARGIN x band of the edge, is reported
 * POM_DYN_GRAD_GRAZING (docs/optimize.md 12.2). */
#define POM_DYN_GRAD_GRAZE        1e-2
#define POM_DYN_GRAD_GRAZE_MARGIN 1e-3

#endif
