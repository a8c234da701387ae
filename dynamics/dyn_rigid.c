/* dyn_rigid.c - the rigid model's terms at one pose (pom_dyn_rigid.h):
 * pom_dyn_exact_terms at w and at rest, split into gravity and velocity
 * terms (docs/capability.md section 1). */
#include "pom_dyn_rigid.h"

#include "dyn_internal.h"

#include <math.h>
#include <string.h>

int pom_dyn_model_is_rigid(const pom_dyn_model *m) {
  return m && m->form == &pom_dyn_form_exact;
}

pom_status pom_dyn_rigid_terms_at(const pom_dyn_model *m, pom_dyn_data *d, const double R[9],
                                  const double w[3], pom_dyn_rigid_terms *out, pom_error *err) {
  if (!m || !d || !R || !out) POM_FAIL(err, POM_ERR_ARG, "pom_dyn_rigid_terms_at: NULL argument");
  if (!pom_dyn_model_is_rigid(m))
    POM_FAIL(err, POM_ERR_ARG,
             "the rigid terms need joints.model = \"rigid\" (the model is \"%s\")", m->form->name);
  if (m->n_actuators != 3)
    POM_FAIL(err, POM_ERR_ARG, "the rigid terms need 3 actuators (the model has %d)",
             m->n_actuators);
  static const double rest[3] = {0.0, 0.0, 0.0};
  double M0[9], f0[3], f[3];
  if (pom_dyn_exact_terms(m, d, R, rest, M0, f0, out->q, out->J) != 0)
    POM_FAIL(err, POM_ERR_UNREACHABLE, "the mechanism cannot be assembled at this rotation");
  memcpy(out->M, M0, sizeof M0);
  memcpy(out->gravity, f0, sizeof f0);
  if (w) {
    if (pom_dyn_exact_terms(m, d, R, w, M0, f, out->q, out->J) != 0)
      POM_FAIL(err, POM_ERR_UNREACHABLE, "the mechanism cannot be assembled at this rotation");
    for (int k = 0; k < 3; ++k)
      out->velocity[k] = f[k] - f0[k];
  } else {
    memset(out->velocity, 0, sizeof out->velocity);
  }
  for (int k = 0; k < 9; ++k)
    if (!isfinite(out->M[k]) || !isfinite(out->J[k]))
      POM_FAIL(err, POM_ERR_NONFINITE, "non-finite mass matrix or Jacobian");
  for (int k = 0; k < 3; ++k)
    if (!isfinite(out->gravity[k]) || !isfinite(out->velocity[k]))
      POM_FAIL(err, POM_ERR_NONFINITE, "non-finite generalized force");
  return POM_OK;
}
