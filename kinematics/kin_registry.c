/* kin_registry.c - the registry of architectures: the built-ins, then the
 * ones a program registers (docs/extending.md). Registering an
 * architecture of the library = one line in `builtin` below. */
#include "pom_kinematics.h"

#include "kin_internal.h"
#include "pom_registry.h"

#include <stddef.h>
#include <string.h>

static const pom_kin_arch_type *const builtin[] = {
    &pom_kin_arch_3pss,
    &pom_kin_arch_3sps,
    &pom_kin_arch_3rrr,
};
static pom_registry registry = POM_REGISTRY_INIT(builtin, offsetof(pom_kin_arch_type, name));

int pom_kin_arch_type_count(void) {
  return pom_registry_count(&registry);
}

const pom_kin_arch_type *pom_kin_arch_type_at(int k) {
  return pom_registry_at(&registry, k);
}

const pom_kin_arch_type *pom_kin_arch_type_find(const char *name) {
  return pom_registry_find(&registry, name);
}

pom_status pom_kin_arch_register(const pom_kin_arch_type *t, pom_error *err) {
  if (!t || !t->name || !t->name[0]) POM_FAIL(err, POM_ERR_ARG, "architecture without a name");
  if (!t->from_design || !t->finish || !t->limb || !t->limb_twist || !t->limit_values ||
      !t->footprint || !t->mechanism)
    POM_FAIL(err, POM_ERR_ARG, "architecture %s: its operations table is incomplete", t->name);
  if (!pom_act_kind_desc(t->actuator))
    POM_FAIL(err, POM_ERR_ARG, "architecture %s: actuator kind %d is not a known kind", t->name,
             (int)t->actuator);
  if (t->data_size > sizeof(((pom_kin_arch *)0)->data))
    POM_FAIL(err, POM_ERR_ARG,
             "architecture %s: private data of %zu bytes exceeds the %zu of pom_kin_arch.data",
             t->name, t->data_size, sizeof(((pom_kin_arch *)0)->data));
  if (t->n_params < 0 || t->n_params > POM_KIN_MAX_PARAMS ||
      t->n_inertia_bodies > POM_KIN_MAX_INERTIA_BODIES ||
      t->n_inertia_values > POM_KIN_MAX_INERTIA_VALUES)
    POM_FAIL(err, POM_ERR_ARG, "architecture %s: too many parameters or inertia groups", t->name);
  return pom_registry_add(&registry, t, "architecture", err);
}

const char *pom_kin_type_name(const pom_kin_arch_type *t) {
  return t ? t->name : "?";
}
const char *pom_kin_type_label(const pom_kin_arch_type *t) {
  return t ? t->label : "?";
}
pom_actuator_kind pom_kin_type_actuator(const pom_kin_arch_type *t) {
  return t ? t->actuator : POM_ACT_PRISMATIC;
}
const char *pom_kin_arch_name(const pom_kin_arch *arch) {
  return arch ? pom_kin_type_name(arch->type) : "?";
}
