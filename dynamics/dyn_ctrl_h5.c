/* dyn_ctrl_h5.c - a controller as HDF5 attributes (results provenance, the
 * traces of pomlab simulate). Its own file so that a program that never
 * writes HDF5 (the light pomlab) does not link it. */
#include "pom_dyn_ctrl.h"

#include <stdio.h>

/* ---- description ---------------------------------------------------------------- */
pom_status pom_dyn_ctrl_h5_describe(hid_t g, const pom_dyn_controller *c, pom_error *err) {
  const pom_dyn_ctrl_type *t = pom_dyn_ctrl_of(c);
  char name[96];
  POM_TRY(pom_h5_attr_string(g, "controller_type", t->name, err));
  for (int k = 0; k < t->n_options; ++k) {
    snprintf(name, sizeof name, "controller_%s", t->options[k].key);
    POM_TRY(pom_h5_attr_string(g, name, pom_dyn_ctrl_option_name(c, k), err));
  }
  for (int k = 0; k < t->n_gains; ++k) {
    snprintf(name, sizeof name, "controller_%s", t->gains[k].key);
    POM_TRY(pom_h5_attr_double(g, name, pom_dyn_ctrl_gain(c, k), err));
  }
  return POM_OK;
}
