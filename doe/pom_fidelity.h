/* pom_fidelity.h - fidelity earned per candidate (docs/tradeoff.md section 9,
 * docs/results.md section 12): the cheapest setting of the dynamics engine
 * (joint model, coil model, tolerance) whose execution time and expended
 * energy stay within an accuracy of a tight reference, chosen on one set of
 * maneuvers with a margin and validated on another (drawn from a different
 * seed), whose measured errors are recorded as the setting's bound.
 * The one rule behind `study.fidelity = "auto"` and `pomlab tradeoff`'s
 * recommendation. Library code: never prints. */
#ifndef POM_FIDELITY_H
#define POM_FIDELITY_H

#include "pom_dynamics.h"
#include "pom_kinematics.h"
#include "pom_mechanism.h"
#include "pom_status.h"

#define POM_FIDELITY_MAX_MANEUVERS 1000 /* per set */
#define POM_FIDELITY_LABEL_LEN     64

/* One rung of the ladder: rigid joints (full limb inertia, universal
 * joints), the coil model and rtol (natural absolute tolerances). */
typedef struct {
  char label[POM_FIDELITY_LABEL_LEN]; /* e.g. "rigid, quasi-static coil, rtol 1e-04" */
  int coil_inductance;                /* 1: inductive coil (L di/dt); 0: quasi-static */
  double rtol;                        /* CVODE relative tolerance */
} pom_fidelity_setting;

/* The ladder, cheapest first (docs/tradeoff.md section 9); *n gets its
 * length. Static storage. */
const pom_fidelity_setting *pom_fidelity_ladder(int *n);

/* Sets p to rung s: rigid joints, full limb inertia, universal joints on,
 * s's coil model, rtol = s->rtol with natural absolute tolerances
 * (atol_scale 0). Everything else (actuator, gains, gravity, friction,
 * horizon, linear solver) stays p's. */
void pom_fidelity_apply(pom_dyn_params *p, const pom_fidelity_setting *s);

/* The reference of the rule: p with rigid joints, full scene, inductive coil
 * at rtol `rtol` (natural absolute tolerances). */
void pom_fidelity_reference(pom_dyn_params *p, double rtol);

/* Options of the rule. */
typedef struct {
  double accuracy;       /* relative accuracy asked on execution time and energy (0.01 = 1 %) */
  double margin;         /* the selection set must meet accuracy / margin (>= 1; default 2) */
  int n_select;          /* maneuvers of the selection set (default 20) */
  int n_validate;        /* maneuvers of the validation set (default 20) */
  double reference_rtol; /* rtol of the reference (default 1e-8) */
} pom_fidelity_opts;

/* Defaults: 1 %, margin 2, 20 + 20 maneuvers, reference rtol 1e-8. */
void pom_fidelity_defaults(pom_fidelity_opts *o);

/* What the rule chose and what it measured. Errors are relative, the worst
 * over the maneuvers the reference finished. */
typedef struct {
  int rung;                                 /* index in the ladder of the choice */
  pom_fidelity_setting setting;             /* the choice */
  int met;                                  /* 1: validated within the accuracy; 0: no rung was,
                                               the choice is the ladder's last (most accurate)
                                               rung and its bound is what it measured */
  double accuracy, margin;                  /* as asked */
  double select_time, select_energy;        /* the choice's errors on the selection set */
  double bound_time, bound_energy;          /* on the validation set: the recorded bound */
  int n_select, n_validate;                 /* maneuvers compared in each set */
  int tried;                                /* rungs run on the selection set */
  int validated;                            /* rungs run on the validation set */
  double steps, reference_steps;            /* mean CVODE steps per validation maneuver */
  double wall;                              /* s spent by the rule (references included) */
  char failure[POM_FIDELITY_LABEL_LEN * 2]; /* why the last rejected rung failed a maneuver,
                                               "" if none did */
} pom_fidelity_result;

/* The rule (docs/tradeoff.md section 9): runs the reference on both sets of
 * targets (actuator coordinates, m or rad: sel[n_sel], val[n_val]), then
 * walks the ladder cheapest first: a rung is chosen when its worst error in
 * execution time and in energy on the selection set is at most
 * accuracy / margin and, on the validation set, at most accuracy. A
 * maneuver the reference does not finish is left out; one the rung does not
 * finish (where the reference did) rejects the rung; an execution time that
 * does not settle is censored at the horizon. POM_ERR_SOLVER when the
 * reference finishes none of a set's maneuvers. */
pom_status pom_fidelity_select(pom_fidelity_result *res, const pom_kin_arch *arch,
                               const pom_mechanism *mech, const pom_dyn_params *base,
                               const double (*sel)[3], int n_sel, const double (*val)[3], int n_val,
                               const pom_fidelity_opts *o, pom_error *err);

/* The worst relative errors e[0] (execution time) and e[1] (energy) of
 * setting p against reference ref on targets q[n] (rule as above); *n_used
 * gets the maneuvers the reference finished (may be NULL). */
pom_status pom_fidelity_measure(double e[2], int *n_used, const pom_kin_arch *arch,
                                const pom_mechanism *mech, const pom_dyn_params *p,
                                const pom_dyn_params *ref, const double (*q)[3], int n,
                                pom_error *err);

#endif
