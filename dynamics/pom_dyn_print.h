/* pom_dyn_print.h - the dynamics' own data as text, JSON and files: the
 * parameter groups and the registered controllers (`pomlab model`), one
 * maneuver's metrics and traces (`pomlab simulate`, docs/dynamics.md
 * section 10). The caller chooses the stream; nothing here decides what the
 * user sees or exits. */
#ifndef POM_DYN_PRINT_H
#define POM_DYN_PRINT_H

#include "pom_dynamics.h"

#include <stdio.h>

/* ---- parameters and controllers (dyn_print.c) ---------------------------------- */
/* ",\n  \"actuator\": {...}, ..." (JSON members, SI units): every group of
 * pom_dyn_param_groups(), every parameter of the list by its json key
 * (pom_dyn_params_schema.h), the controller by its type. */
void pom_dyn_params_json(FILE *out, const pom_dyn_params *p);

/* The groups as human-readable lines: one line per group, each parameter by
 * its config key with the value in the key's unit. */
void pom_dyn_params_text(FILE *out, const pom_dyn_params *p);

/* The members of the `controller` group of c, from its type's descriptors:
 * "type": "pid", then each option and gain by its config key (SI values),
 * without braces. */
void pom_dyn_ctrl_json_members(FILE *out, const pom_dyn_controller *c);

/* Every registered controller type with its states, options and gains (key,
 * unit, range, default, tunable, searched in log): `pomlab model
 * --list-controllers [--json]`. */
void pom_dyn_ctrl_list(FILE *out, int json);

/* ---- one maneuver (dyn_report.c, dyn_trace_h5.c) -------------------------------- */
/* Marks in out[] the actuators whose |q| went beyond half the stroke (half,
 * SI; 0 = not limited) on the output grid; returns how many did. The model
 * has no end stops, so such a maneuver is not physical. */
int pom_dyn_stroke_excursions(const pom_dyn_metrics *mt, double half, int out[3]);

/* 1 when the closed loop's drive mode (the actuator loop linearized at rest
 * at home, docs/dynamics.md section 7, "Order and stability") is a lightly
 * damped pair outside BDF order 3's stability sector (damping ratio below
 * cos 86.03 deg = 0.070): the high-gain regime where saturation switching
 * makes the energy and the settling times sensitive to the tolerance
 * (docs/extremes.md); its angular frequency (rad/s) and damping ratio in
 * *omega and *zeta. 0 when it is not, or was not analysed. */
int pom_dyn_drive_mode_light(const pom_dyn_model *m, double *omega, double *zeta);

/* The maneuver of mechanism `name` run with p: every metric of the schema
 * (pom_dyn_metrics_schema.h) under its key in SI units (JSON), or the
 * human report in display units (text). */
void pom_dyn_report_json(FILE *out, const char *name, const pom_dyn_params *p,
                         const pom_dyn_metrics *mt, pom_actuator_kind kind, double half_stroke);
void pom_dyn_report_text(FILE *out, const char *name, const pom_dyn_params *p,
                         const pom_dyn_metrics *mt, pom_actuator_kind kind, double half_stroke);

/* The traces as CSV (SI units, the setpoints on every row), written to a
 * temporary file and renamed (pom_io). */
pom_status pom_dyn_trace_write_csv(const char *path, const pom_dyn_trace *tr,
                                   const double target[3], pom_actuator_kind kind, pom_error *err);

/* The traces, the metrics and every parameter as HDF5 (groups trace and
 * metrics; attributes program, git_commit, name, the config's text). */
pom_status pom_dyn_trace_write_h5(const char *path, const char *program, const pom_cfg *cfg,
                                  const char *name, const pom_dyn_params *p,
                                  const pom_dyn_trace *tr, const pom_dyn_metrics *mt,
                                  pom_actuator_kind kind, pom_error *err);

#endif
