/* dyn_params_h5.c - the dynamics parameters as HDF5 attributes, from their
 * list (pom_dyn_params_schema.h). Its own file so that a program that never
 * writes HDF5 (the light pomlab) does not link it. */
#include "pom_dyn_params_schema.h"

#include "pom_dyn_ctrl.h"

/* ---- description ------------------------------------------------------------ */
pom_status pom_dyn_params_h5_describe(hid_t g, const pom_dyn_params *p, pom_error *err) {
  POM_TRY(pom_dyn_ctrl_h5_describe(g, &p->controller, err));
  const pom_dyn_param_info *schema = pom_dyn_param_schema();
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
    const pom_dyn_param_info *pi = &schema[k];
    char name[128];
    if (!pom_dyn_param_h5_name(pi, p->actuator.kind, name, sizeof name))
      POM_FAIL(err, POM_ERR_ARG, "actuator kind %d is not a kind", (int)p->actuator.kind);
    switch (pi->type) {
    case POM_DYN_PARAM_REAL:
    case POM_DYN_PARAM_KIND_REAL:
      POM_TRY(pom_h5_attr_double(g, name, pom_dyn_param_value(p, pi), err));
      break;
    case POM_DYN_PARAM_LONG:
    case POM_DYN_PARAM_INT:
    case POM_DYN_PARAM_BOOL:
      POM_TRY(pom_h5_attr_int64(g, name, (int64_t)pom_dyn_param_value(p, pi), err));
      break;
    case POM_DYN_PARAM_ENUM:
    case POM_DYN_PARAM_KIND:
      POM_TRY(pom_h5_attr_string(g, name, pom_dyn_param_choice(p, pi), err));
      break;
    }
  }
  return POM_OK;
}
