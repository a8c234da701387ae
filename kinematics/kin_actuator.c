/* kin_actuator.c - the actuator kinds: one descriptor per kind, everything
 * that depends on it (units, config keys, joint type, wording). A new kind is
 * its enum value in pom_mechanism.h and its entry here (docs/extending.md
 * section 8). */
#include "pom_mechanism.h"

#include "pom_math.h"

#include <stddef.h>
#include <string.h>

static const pom_act_desc kinds[POM_ACT_KINDS] = {
    [POM_ACT_PRISMATIC] = {.kind = POM_ACT_PRISMATIC,
                           .name = "linear",
                           .kind_name = "prismatic",
                           .device = "linear voice coil",
                           .joint = POM_JOINT_PRISMATIC,
                           .angular = 0,
                           .coordinate = "displacement",
                           .si = "m",
                           .rate = "m/s",
                           .rate_tag = "mps",
                           .display = "mm",
                           .to_display = 1e3,
                           .display_words = "millimetres",
                           .key_suffix = "_mm",
                           .range_word = "stroke",
                           .range_max = 1000.0,
                           .maneuver_range_max = 100.0,
                           .lever_unit = "mm/rad",
                           .lever_to_display = 1e3,
                           .effort = "N",
                           .constant_symbol = "K_m",
                           .constant_unit = "N/A",
                           .friction_unit = "N s/m",
                           .gain_unit = "V/m",
                           .constant_key = "force_constant_N_per_A",
                           .friction_key = "bearing_friction_Ns_per_m",
                           .gain_key = "sensor_gain_V_per_m",
                           .legacy_keys = 1},
    [POM_ACT_REVOLUTE] = {.kind = POM_ACT_REVOLUTE,
                          .name = "rotary",
                          .kind_name = "revolute",
                          .device = "rotary voice coil",
                          .joint = POM_JOINT_REVOLUTE,
                          .angular = 1,
                          .coordinate = "angle",
                          .si = "rad",
                          .rate = "rad/s",
                          .rate_tag = "radps",
                          .display = "deg",
                          .to_display = 180.0 / POM_PI,
                          .display_words = "degrees",
                          .key_suffix = "_deg",
                          .range_word = "range",
                          .range_max = 360.0,
                          .maneuver_range_max = 180.0,
                          .lever_unit = "rad/rad",
                          .lever_to_display = 1.0,
                          .effort = "N m",
                          .constant_symbol = "K_t",
                          .constant_unit = "N m/A",
                          .friction_unit = "N m s/rad",
                          .gain_unit = "V/rad",
                          .constant_key = "torque_constant_Nm_per_A",
                          .friction_key = "bearing_friction_Nms_per_rad",
                          .gain_key = "sensor_gain_V_per_rad",
                          .legacy_keys = 0},
};

const pom_act_desc *pom_act_kind_desc(pom_actuator_kind k) {
  return (int)k >= 0 && (int)k < POM_ACT_KINDS ? &kinds[k] : NULL;
}

int pom_act_kind_parse(const char *name, pom_actuator_kind *kind) {
  if (!name) return 0;
  for (int k = 0; k < POM_ACT_KINDS; ++k)
    if (strcmp(kinds[k].name, name) == 0) {
      *kind = kinds[k].kind;
      return 1;
    }
  return 0;
}
