/* fuzz_common.h - what both libFuzzer targets share: a private copy of the
 * shipped configs in a temporary folder (so @include and candidate configs
 * resolve), the input written there as a config file, the inputs refused
 * before any work, and the invariant every failure must keep
 * (docs/fuzzing.md). */
#ifndef POM_FUZZ_COMMON_H
#define POM_FUZZ_COMMON_H

#include "pom_status.h"

#include <stddef.h>
#include <stdint.h>

/* Makes the temporary folder once (TMPDIR, else /tmp): configs/ and tests/
 * hold copies of the source tree's configs/ and tests/ config files, removed at
 * exit. Returns the path the input is written to (FOLDER/configs/fuzz.cfg),
 * NULL when the folder cannot be made (the reason on stderr). */
const char *pom_fuzz_setup(void);

/* 1 when the input must not run: it names a special-file folder (/dev,
 * /proc, /sys, known issue 22 item 7 and not a setup bug), or uses a
 * string hex escape that could spell one. */
int pom_fuzz_refused(const uint8_t *data, size_t size);

/* Writes the input to path (the bytes as they are). 0 on success. When the
 * folder of pom_fuzz_setup's path has been removed, it is made again first
 * (path, its static buffer, then names the new one). */
int pom_fuzz_write(const char *path, const uint8_t *data, size_t size);

/* A failing status must come with a message naming what failed: aborts
 * (a finding) when st != POM_OK and err->message is empty, or when st is
 * positive (no pomlab function returns a positive status). With the
 * environment variable POM_FUZZ_VERBOSE=1 the message goes to stderr. */
void pom_fuzz_check_failure(pom_status st, const pom_error *err, const char *stage);

#endif
