/* kin_registry.c - the registry of architectures: the built-ins, then the
 * ones a program registers (docs/extending.md). Registering an
 * architecture of the library = one line in `builtin` below. */
#include "pom_kinematics.h"

#include "kin_internal.h"

#include <pthread.h>
#include <string.h>

static const pom_kin_arch_type *const builtin[] = {
    &pom_kin_arch_3pss,
    &pom_kin_arch_3sps,
    &pom_kin_arch_3rrr,
};
#define N_BUILTIN ((int)(sizeof builtin / sizeof builtin[0]))
#define MAX_USER  16

/* Types registered at run time; written only under the lock, before any
 * reader thread starts (pom_kin_arch_register's contract). */
static const pom_kin_arch_type *user[MAX_USER];
static int n_user = 0;
static pthread_mutex_t user_lock = PTHREAD_MUTEX_INITIALIZER;

int pom_kin_arch_type_count(void) {
  return N_BUILTIN + n_user;
}

const pom_kin_arch_type *pom_kin_arch_type_at(int k) {
  if (k < 0) return NULL;
  if (k < N_BUILTIN) return builtin[k];
  k -= N_BUILTIN;
  return k < n_user ? user[k] : NULL;
}

const pom_kin_arch_type *pom_kin_arch_type_find(const char *name) {
  if (!name) return NULL;
  for (int k = 0; k < pom_kin_arch_type_count(); ++k) {
    const pom_kin_arch_type *t = pom_kin_arch_type_at(k);
    if (strcmp(t->name, name) == 0) return t;
  }
  return NULL;
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
  pthread_mutex_lock(&user_lock);
  pom_status st = POM_OK;
  if (pom_kin_arch_type_find(t->name)) {
    st = POM_ERR_ARG;
  } else if (n_user >= MAX_USER) {
    st = POM_ERR_NOMEM;
  } else {
    user[n_user++] = t;
  }
  pthread_mutex_unlock(&user_lock);
  if (st == POM_ERR_ARG) POM_FAIL(err, st, "architecture %s is registered already", t->name);
  if (st != POM_OK)
    POM_FAIL(err, st, "architecture %s: the registry holds %d user types at most", t->name,
             MAX_USER);
  return POM_OK;
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
