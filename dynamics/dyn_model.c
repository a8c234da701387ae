/* dyn_model.c - the one model constructor: validates the parameters and the
 * mechanism's sizes and actuator kinds, picks the formulation the parameters
 * name (joints.model) and lets it build its model; destroy and the model's
 * accessors (docs/dynamics.md section 15). */
#include "dyn_internal.h"
#include "pom_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The formulations by joints.model. */
static const dyn_formulation *const formulations[] = {
    [POM_JOINTS_PARASITIC] = &pom_dyn_form_parasitic,
    [POM_JOINTS_RIGID] = &pom_dyn_form_exact,
};

/* What model-based controllers may call (pom_dyn_ctrl_engine). */
static const pom_dyn_ctrl_engine ctrl_engine = {
    .model_create = pom_dyn_model_create,
    .model_destroy = pom_dyn_model_destroy,
    .data_create = pom_dyn_data_create,
    .data_destroy = pom_dyn_data_destroy,
    .exact_terms = pom_dyn_exact_terms,
};

/* ---- create / destroy ---------------------------------------------------- */
pom_status pom_dyn_model_create(pom_dyn_model **out, const pom_mechanism *mech,
                                const pom_kin_arch *arch, const pom_dyn_params *p, pom_error *err) {
  return pom_dyn_model_create_ex(out, mech, arch, p, NULL, NULL, NULL, err);
}

/* The parasitic path's drive mode is the rigid mechanism's (its joint modes
 * lie far above it, docs/dynamics.md section 7, "Order and stability"): the
 * rigid model built from the same mechanism analyses it, and its BDF order
 * cap applies to both paths. A scene the rigid path does not take (lumped
 * limbs, no universal joint) or a model that cannot be built leaves the
 * order as configured. */
static void parasitic_order_cap(pom_dyn_model *m, const pom_mechanism *mech,
                                const pom_kin_arch *arch) {
  if (!arch || !m->ctrl_analytic || m->par.scene.limb_inertia != POM_INERTIA_FULL ||
      !m->par.scene.universal_joint)
    return;
  pom_dyn_params pr = m->par;
  pr.joints.model = POM_JOINTS_RIGID;
  pom_dyn_model *rm = NULL;
  if (pom_dyn_model_create(&rm, mech, arch, &pr, NULL) != POM_OK) return;
  m->drive = rm->drive;
  if (rm->max_order < m->max_order) m->max_order = rm->max_order;
  pom_dyn_model_destroy(rm);
}

pom_status pom_dyn_model_create_ex(pom_dyn_model **out, const pom_mechanism *mech,
                                   const pom_kin_arch *arch, const pom_dyn_params *p,
                                   const pom_mechanism *ctrl_mech, const pom_kin_arch *ctrl_arch,
                                   const pom_dyn_params *ctrl_params, pom_error *err) {
  pom_status st = POM_OK;
  pom_dyn_model *m = NULL;
  if (!out || !mech || !p) POM_FAIL(err, POM_ERR_ARG, "pom_dyn_model_create: NULL argument");
  *out = NULL;
  POM_TRY(pom_dyn_params_check(p, err)); /* the ranges loading checks (joints.model included) */
  if (mech->n_bodies < 2 || mech->n_bodies > POM_MECH_MAX_BODIES || mech->n_joints < 0 ||
      mech->n_joints > POM_MECH_MAX_JOINTS || mech->n_actuators < 0 || mech->n_actuators > 3)
    POM_FAIL(err, POM_ERR_ARG,
             "mechanism sizes: %d bodies (2..%d incl. ground), %d joints (0..%d), %d actuators "
             "(0..3)",
             mech->n_bodies, POM_MECH_MAX_BODIES, mech->n_joints, POM_MECH_MAX_JOINTS,
             mech->n_actuators);
  /* one actuator model for all limbs: its kind must be the mechanism's */
  for (int a = 0; a < mech->n_actuators; ++a) {
    const pom_act_desc *want = pom_act_kind_desc(mech->actuator[a].kind);
    if (!want)
      POM_FAIL(err, POM_ERR_ARG, "actuator %d of the mechanism has kind %d, not a known kind",
               a + 1, (int)mech->actuator[a].kind);
    if (want->kind != p->actuator.kind)
      POM_FAIL(err, POM_ERR_ARG,
               "actuator %d of the mechanism is %s (q in %s) but the actuator parameters are for "
               "a %s actuator: set actuator.kind = \"%s\"",
               a + 1, want->kind_name, want->si, pom_act_kind_desc(p->actuator.kind)->name,
               want->name);
  }
  m = calloc(1, sizeof *m);
  if (!m) POM_FAIL(err, POM_ERR_NOMEM, "allocating the dynamics model");
  m->form = formulations[p->joints.model];
  m->par = *p;
  m->ctrl = pom_dyn_ctrl_of(&p->controller);
  m->par.controller.type = m->ctrl;
  m->ctrl_analytic = m->ctrl->partials != NULL && m->ctrl->n_states <= 1 && !m->ctrl->law_all;
  if (p->scene.gravity) pom_v3_copy(m->gravity, mech->gravity);
  for (int b = 0; b < POM_MECH_MAX_BODIES; ++b)
    m->slot_of_mech[b] = -1;
  m->platform_slot = -1;
  /* atol_scale 0 = natural sizes; a formulation without them gets the
   * scale rule atol_scale = min(1e-3, 1e3 rtol) (docs/dynamics.md section 7) */
  if (m->par.solver.atol_scale == 0.0 && !m->form->natural_tolerances)
    m->par.solver.atol_scale = fmin(1e-3, 1e3 * m->par.solver.rtol);
  /* an rtol below atol_scale / 1e3 tightens the absolute tolerances with it
   * (docs/dynamics.md section 7, "Tolerances") */
  m->par.solver.atol_scale = pom_dyn_atol_scale_used(&m->par.solver);
  m->max_order = m->par.solver.max_order; /* the drive mode may cap it */
  POM_TRY_GOTO(m->form->init(m, mech, arch, err), fail);
  if (m->form != &pom_dyn_form_exact) parasitic_order_cap(m, mech, arch);
  if (arch) { /* the target orientation of a maneuver is FK(setpoints) */
    m->arch = *arch;
    m->has_arch = 1;
  }
  for (int a = 0; a < m->n_actuators; ++a) /* targets checked against it (docs 14) */
    m->act[a].stroke = mech->actuator[a].stroke;
  /* the controller's own model: the nominal candidate unless told otherwise */
  if (m->ctrl->model_create) {
    const pom_dyn_params *cp = ctrl_params ? ctrl_params : p;
    POM_TRY_GOTO(m->ctrl->model_create(&m->ctrl_model, &ctrl_engine, &m->par.controller,
                                       ctrl_mech ? ctrl_mech : mech, ctrl_arch ? ctrl_arch : arch,
                                       cp, err),
                 fail);
  }
  *out = m;
  return POM_OK;
fail:
  pom_dyn_model_destroy(m);
  return st;
}

void pom_dyn_model_destroy(pom_dyn_model *m) {
  if (!m) return;
  if (m->form) m->form->model_free(m);
  if (m->ctrl_model) m->ctrl->model_destroy(m->ctrl_model);
  free(m->atol);
  free(m->relative);
  free(m->scale);
  free(m->dep);
  free(m->color);
  free(m->colptr);
  free(m->rowind);
  free(m->diag);
  free(m);
}

const pom_dyn_params *pom_dyn_model_params(const pom_dyn_model *m) {
  return &m->par;
}
int pom_dyn_model_n_states(const pom_dyn_model *m) {
  return m->n_states;
}
int pom_dyn_model_n_colors(const pom_dyn_model *m) {
  return m->n_colors;
}
