/* pom_status.c - messages of the status list and the error record. */
#include "pom_status.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

const char *pom_strerror(pom_status status) {
  switch (status) {
#define POM_STATUS_CASE(name, value, msg)                                                          \
  case name:                                                                                       \
    return msg;
    POM_STATUS_LIST(POM_STATUS_CASE)
#undef POM_STATUS_CASE
  default:
    return "unknown status";
  }
}

const char *pom_status_name(pom_status status) {
  switch (status) {
#define POM_STATUS_CASE(name, value, msg)                                                          \
  case name:                                                                                       \
    return #name;
    POM_STATUS_LIST(POM_STATUS_CASE)
#undef POM_STATUS_CASE
  default:
    return "POM_UNKNOWN";
  }
}

void pom_error_clear(pom_error *err) {
  if (!err) return;
  err->status = POM_OK;
  err->message[0] = '\0';
  err->src_file = NULL;
  err->src_line = 0;
}

pom_status pom_error_set(pom_error *err, pom_status status, const char *src_file, int src_line,
                         const char *fmt, ...) {
  if (!err) return status;
  err->status = status;
  err->src_file = src_file;
  err->src_line = src_line;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err->message, sizeof err->message, fmt, ap);
  va_end(ap);
  return status;
}

pom_status pom_error_prefix(pom_error *err, const char *fmt, ...) {
  if (!err) return POM_ERR_INTERNAL;
  char head[512];
  char old[sizeof err->message];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(head, sizeof head, fmt, ap);
  va_end(ap);
  memcpy(old, err->message, sizeof old);
  /* head + ": " + old, truncated to the buffer */
  size_t cap = sizeof err->message, n = 0;
  for (const char *p = head; *p && n + 1 < cap; ++p)
    err->message[n++] = *p;
  for (const char *p = ": "; *p && n + 1 < cap; ++p)
    err->message[n++] = *p;
  for (const char *p = old; *p && n + 1 < cap; ++p)
    err->message[n++] = *p;
  err->message[n] = '\0';
  return err->status;
}
