/* pom_doe_row.c - the row layout: where each metric of the schema sits in a
 * pom_doe_row, its value as a double, and the row of evaluator metrics. */
#include "pom_rows.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define ROW_OFFSET(name, ...) offsetof(pom_doe_row, name),
static const size_t row_offsets[POM_DYN_N_METRICS] = {POM_DYN_METRICS_LIST(ROW_OFFSET, ROW_OFFSET)};
#undef ROW_OFFSET

size_t pom_doe_row_offset(int j) {
  return row_offsets[j];
}

double pom_doe_row_value(const pom_doe_row *row, int j, int k) {
  const pom_dyn_metric_info *mi = pom_dyn_metric(j);
  const char *base = (const char *)row + row_offsets[j];
  switch (mi->type) {
  case POM_DYN_TYPE_INT:
    return (double)((const int32_t *)(const void *)base)[k];
  case POM_DYN_TYPE_LONG:
    return (double)((const int64_t *)(const void *)base)[k];
  default:
    return ((const double *)(const void *)base)[k];
  }
}

/* Every metric of the schema, copied field by field from its offset in
 * pom_dyn_metrics to its offset in the row. */
void pom_doe_row_from_metrics(pom_doe_row *row, const pom_dyn_metrics *m) {
  memset(row, 0, sizeof *row);
  row->done = 1;
  row->status = (int32_t)m->status;
  snprintf(row->reason, sizeof row->reason, "%s", m->reason);
  const pom_dyn_metric_info *schema = pom_dyn_metric_schema();
  for (int j = 0; j < POM_DYN_N_METRICS; ++j) {
    const pom_dyn_metric_info *mi = &schema[j];
    const char *src = (const char *)m + mi->offset;
    char *dst = (char *)row + row_offsets[j];
    for (int k = 0; k < mi->count; ++k) {
      switch (mi->type) {
      case POM_DYN_TYPE_INT:
        ((int32_t *)(void *)dst)[k] = (int32_t)((const int *)(const void *)src)[k];
        break;
      case POM_DYN_TYPE_LONG:
        ((int64_t *)(void *)dst)[k] = (int64_t)((const long *)(const void *)src)[k];
        break;
      default:
        ((double *)(void *)dst)[k] = ((const double *)(const void *)src)[k];
      }
    }
  }
}
