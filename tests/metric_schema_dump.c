/* metric_schema_dump.c - prints the metric schema as JSON for
 * test_metric_outputs.py: every name, its simulate JSON key and its
 * statistics (HDF5 table and study JSON key), straight from the table. */
#include "pom_dyn_metrics_schema.h"

#include <stdio.h>

int main(void) {
  const pom_dyn_metric_info *s = pom_dyn_metric_schema();
  printf("[\n");
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    char key[96];
    printf("  {\"name\": \"%s\", \"json_key\": \"%s\", \"count\": %d, \"actuator\": %s, "
           "\"stat_name\": %s%s%s, \"stat_key\": %s%s%s}%s\n",
           s[j].name, pom_dyn_metric_json_key(&s[j], key, sizeof key), s[j].count,
           s[j].unit == POM_DYN_UNIT_ACTUATOR ? "true" : "false", s[j].stat_name ? "\"" : "",
           s[j].stat_name ? s[j].stat_name : "null", s[j].stat_name ? "\"" : "",
           s[j].stat_key ? "\"" : "", s[j].stat_key ? s[j].stat_key : "null",
           s[j].stat_key ? "\"" : "", j + 1 < POM_DYN_N_METRICS ? "," : "");
  }
  printf("]\n");
  return 0;
}
