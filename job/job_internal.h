/* job_internal.h - what the job's files share and nobody else calls. */
#ifndef POM_JOB_INTERNAL_H
#define POM_JOB_INTERNAL_H

#include "pom_status.h"

#include <stdio.h>

/* Records a printf-style message in err (may be NULL) with status st and
 * prints "pomlab COMMAND: message" and a newline on msg (NULL: nothing
 * printed; an empty command prints "pomlab: message"). Returns st. */
pom_status pom_job_say(FILE *msg, pom_error *err, pom_status st, const char *command,
                       const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Prints "pomlab: CONTEXT: message" for a failed status on msg, as the
 * program reports a library failure (nothing when msg is NULL). */
void pom_job_report_error(FILE *msg, const char *context, const pom_error *err);

#endif
