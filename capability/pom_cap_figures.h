/* pom_cap_figures.h - the one list of candidate-level capability figures
 * (docs/capability.md, "As study responses and constraints").
 *
 * Every figure a study column, a JSON report, summary.md, the tabular
 * files, the Python result or a capability requirement reads from a
 * pom_cap_result is declared ONCE here; every consumer is generated from
 * the list (pom_cap_figure_* in cap_figures.c). Adding a figure = one line.
 *
 *   F(name, unit, slews, description, accessor)
 *   name      the figure's key (config, JSON, CSV column, HDF5 attribute);
 *   unit      SI unit as printed;
 *   slews     1 when it needs the slews (simulations), 0 when the envelope
 *             over the grid gives it;
 *   accessor  an expression of `r` (const pom_cap_result *) giving the value
 *             in SI, NaN where not computed (JSON null).
 * Included by pom_capability.h (other folders include that one). */
#ifndef POM_CAP_FIGURES_H
#define POM_CAP_FIGURES_H

/* clang-format off */
#define POM_CAP_FIGURES(F)                                                                       \
  F(acc_inscribed_worst, "rad/s^2", 0,                                                           \
    "smallest inscribed peak angular acceleration from rest over the workspace grid",            \
    ((r)->worst_acc >= 0 ? (r)->pose[(r)->worst_acc].acc_inscribed : NAN))                        \
  F(rate_inscribed_worst, "rad/s", 0,                                                            \
    "smallest inscribed steady angular rate over the workspace grid",                            \
    ((r)->worst_rate >= 0 ? (r)->pose[(r)->worst_rate].rate_inscribed : NAN))                     \
  F(bw_worst_hz, "Hz", 0,                                                                        \
    "smallest worst-direction -3 dB closed-loop bandwidth over the workspace grid",              \
    ((r)->bw_worst_hz))                                                                          \
  F(pm_worst_deg, "deg", 0,                                                                      \
    "smallest phase margin of the actuator loops over the workspace grid",                       \
    ((r)->pm_worst_deg))                                                                         \
  F(slew_10deg_worst_s, "s", 1,                                                                  \
    "longest pointing settling time of a 10 deg slew from home about x, y, z, (1,1,1)/sqrt3",    \
    (pom_cap_slew_worst_time((r), 10.0 * POM_DEG)))
/* clang-format on */

#define POM_CAP_FIG_ENUM_(name, ...) POM_CAP_FIG_##name,
typedef enum { POM_CAP_FIGURES(POM_CAP_FIG_ENUM_) POM_CAP_N_FIGURES } pom_cap_figure_id;
#undef POM_CAP_FIG_ENUM_

#endif
