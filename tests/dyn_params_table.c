/* dyn_params_table.c - prints the markdown table of the dynamics parameters
 * straight from their list (pom_dyn_params_schema.h): the table between the
 * dyn-params markers of docs/config.md. test_params_doc.sh fails when the
 * doc differs; `tests/test_params_doc.sh build/tests/dyn_params_table
 * docs/config.md --update` rewrites it. */
#include "pom_dyn_params_schema.h"

#include <stdio.h>

/* the allowed values of a parameter, as the config writes them */
static void print_range(const pom_dyn_param_info *pi) {
  switch (pi->type) {
  case POM_DYN_PARAM_REAL:
  case POM_DYN_PARAM_KIND_REAL:
  case POM_DYN_PARAM_LONG:
  case POM_DYN_PARAM_INT:
    printf("[%g, %g]", pi->lo, pi->hi);
    break;
  case POM_DYN_PARAM_BOOL:
    printf("`true`, `false`");
    break;
  case POM_DYN_PARAM_ENUM:
    for (int j = 0; pi->names[j]; ++j)
      printf("%s`\"%s\"`", j ? ", " : "", pi->names[j]);
    break;
  case POM_DYN_PARAM_KIND:
    for (int k = 0; k < POM_ACT_KINDS; ++k)
      printf("%s`\"%s\"`", k ? ", " : "", pom_act_kind_desc((pom_actuator_kind)k)->name);
    break;
  }
}

/* one row; a KIND_REAL has one row per actuator kind */
static void print_row(const pom_dyn_param_info *pi, pom_actuator_kind kind) {
  char key[96], h5[128], def[64];
  pom_dyn_param_key(pi, kind, key, sizeof key);
  pom_dyn_param_h5_name(pi, kind, h5, sizeof h5);
  pom_dyn_param_format_default(pi, def, sizeof def);
  printf("| `%s` | ", key);
  if (pi->type == POM_DYN_PARAM_KIND_REAL)
    printf("%s (`kind = \"%s\"`): ", pom_act_kind_desc(kind)->device,
           pom_act_kind_desc(kind)->name);
  printf("%s | %s | ", pi->meaning, pom_dyn_param_unit(pi, kind));
  print_range(pi);
  printf(" | %s%s | `%s` | `%s` |\n", def,
         pi->type == POM_DYN_PARAM_KIND_REAL && kind != (pom_actuator_kind)0 ? " (set it)" : "",
         pom_dyn_param_json_key(pi, kind), h5);
}

int main(void) {
  const pom_dyn_param_info *schema = pom_dyn_param_schema();
  printf("| key | meaning | unit | range | default | `pomlab model --json` | HDF5 attribute |\n");
  printf("|---|---|---|---|---|---|---|\n");
  for (int k = 0; k < POM_DYN_N_PARAMS; ++k) {
    if (schema[k].type != POM_DYN_PARAM_KIND_REAL) {
      print_row(&schema[k], (pom_actuator_kind)0);
      continue;
    }
    for (int a = 0; a < POM_ACT_KINDS; ++a)
      print_row(&schema[k], (pom_actuator_kind)a);
  }
  return 0;
}
