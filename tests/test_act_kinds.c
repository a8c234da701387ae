/* test_act_kinds.c - the actuator-kind descriptors (pom_mechanism.h,
 * kinematics/kin_actuator.c): every kind has every field, names parse back
 * to their kind, the fields that tell kinds apart differ, the mechanism
 * builder maps each kind's joint type back to it, and what is not a kind
 * gives NULL or is not parsed. */
#include "check.h"
#include "pom_arch.h"
#include "pom_kinematics.h"
#include "pom_math.h"

#include <string.h>

static int set(const char *s) {
  return s && s[0];
}

/* ---- every field of every kind ------------------------------------------------ */
static void test_fields(void) {
  for (int k = 0; k < POM_ACT_KINDS; ++k) {
    const pom_act_desc *d = pom_act_kind_desc((pom_actuator_kind)k);
    if (!check_true(d != NULL)) continue;
    check_true((int)d->kind == k);
    check_true(set(d->name) && set(d->kind_name) && set(d->device) && set(d->coordinate));
    check_true(set(d->si) && set(d->rate) && set(d->rate_tag) && set(d->display) &&
               set(d->display_words) && set(d->key_suffix) && set(d->range_word) &&
               set(d->lever_unit));
    check_true(set(d->effort) && set(d->constant_symbol) && set(d->constant_unit) &&
               set(d->friction_unit) && set(d->gain_unit));
    check_true(set(d->constant_key) && set(d->friction_key) && set(d->gain_key));
    check_true(d->joint == POM_JOINT_PRISMATIC || d->joint == POM_JOINT_REVOLUTE);
    check_true(d->angular == 0 || d->angular == 1);
    check_true(d->legacy_keys == 0 || d->legacy_keys == 1);
    check_true(d->to_display > 0 && d->range_max > 0 && d->maneuver_range_max > 0 &&
               d->lever_to_display > 0);
    /* the config-key suffix is the display unit's; q_dot is q per second */
    check_true(d->key_suffix[0] == '_' && strcmp(d->key_suffix + 1, d->display) == 0);
    check_true(strncmp(d->rate, d->si, strlen(d->si)) == 0 &&
               strcmp(d->rate + strlen(d->si), "/s") == 0);
    /* display factors: mm per m, deg per rad; the lever J is shown per rad
     * of platform rotation, a ratio (1) when q is an angle */
    check_rel(d->to_display, d->angular ? 1.0 / POM_DEG : 1e3, 1e-15);
    check_rel(d->lever_to_display, d->angular ? 1.0 : d->to_display, 1e-15);
    check_true(strcmp(d->si, d->angular ? "rad" : "m") == 0);
    /* the parse of the name is the kind */
    pom_actuator_kind back = (pom_actuator_kind)-1;
    check_true(pom_act_kind_parse(d->name, &back) == 1 && (int)back == k);
    printf("  kind %d: %s (%s, %s), q in %s / %s, limits.%s%s, %s in %s\n", k, d->name,
           d->kind_name, d->device, d->si, d->display, d->range_word, d->key_suffix,
           d->constant_symbol, d->constant_unit);
  }
}

/* ---- the fields that name a kind differ between kinds -------------------------- */
static void test_distinct(void) {
  for (int a = 0; a < POM_ACT_KINDS; ++a)
    for (int b = a + 1; b < POM_ACT_KINDS; ++b) {
      const pom_act_desc *x = pom_act_kind_desc((pom_actuator_kind)a);
      const pom_act_desc *y = pom_act_kind_desc((pom_actuator_kind)b);
      check_true(strcmp(x->name, y->name) != 0 && strcmp(x->kind_name, y->kind_name) != 0);
      check_true(x->joint != y->joint);
      check_true(strcmp(x->key_suffix, y->key_suffix) != 0);
      check_true(strcmp(x->constant_key, y->constant_key) != 0 &&
                 strcmp(x->friction_key, y->friction_key) != 0 &&
                 strcmp(x->gain_key, y->gain_key) != 0);
      check_true(strcmp(x->rate_tag, y->rate_tag) != 0);
    }
}

/* ---- the builder gives an actuator the kind of its joint type ------------------ */
static void test_builder(void) {
  for (int k = 0; k < POM_ACT_KINDS; ++k) {
    const pom_act_desc *d = pom_act_kind_desc((pom_actuator_kind)k);
    pom_mechanism mech;
    memset(&mech, 0, sizeof mech);
    const double point[3] = {0.0123, -0.0457, 0.0311}, axis[3] = {0.0, 0.6, 0.8};
    int j = pom_kin_build_joint(&mech, "A", 1, d->joint, 0, 1, point, axis, NULL);
    pom_kin_build_actuator(&mech, j, 1, 0.02385);
    check_true(mech.n_actuators == 1 && (int)mech.actuator[0].kind == k);
    check_true(mech.joint[j].actuator == 0);
  }
}

/* ---- what is not a kind --------------------------------------------------------- */
static void test_not_a_kind(void) {
  check_true(pom_act_kind_desc((pom_actuator_kind)POM_ACT_KINDS) == NULL);
  check_true(pom_act_kind_desc((pom_actuator_kind)-1) == NULL);
  pom_actuator_kind k = POM_ACT_REVOLUTE;
  check_true(pom_act_kind_parse("spinning", &k) == 0 && k == POM_ACT_REVOLUTE);
  check_true(pom_act_kind_parse("", &k) == 0 && pom_act_kind_parse(NULL, &k) == 0);
  /* names are matched whole and with their case */
  check_true(pom_act_kind_parse("Rotary", &k) == 0 && pom_act_kind_parse("linea", &k) == 0);
}

int main(void) {
  test_fields();
  test_distinct();
  test_builder();
  test_not_a_kind();
  return check_summary("test_act_kinds");
}
