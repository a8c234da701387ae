/* pom_io.h - text files written whole or not at all.
 *
 * pom_io_create opens PATH.tmp.<pid> next to PATH; pom_io_commit checks every
 * write and the close, then renames it over PATH, so PATH is either the old
 * file or the complete new one, never a truncated one (a full disk, a killed
 * run). A PATH that exists and is not a regular file (/dev/stdout, a pipe,
 * /dev/full) is written directly, with the same checks. A run killed before
 * its rename leaves PATH.tmp.<pid>; the next pom_io_create of PATH removes
 * those whose process no longer runs. */
#ifndef POM_IO_H
#define POM_IO_H

#include "pom_status.h"

#include <stdio.h>

typedef struct {
  FILE *f;         /* write here (fprintf etc.); NULL when not open */
  char path[1100]; /* the file asked for */
  char tmp[1140];  /* the file written, "" when writing PATH directly */
} pom_io_file;

/* Opens a file for writing; on failure err names the path and errno. */
pom_status pom_io_create(pom_io_file *w, const char *path, pom_error *err);

/* Closes and, when every write succeeded, renames the temporary file to
 * PATH. On failure the temporary file is removed, PATH is untouched and err
 * names the path and errno. */
pom_status pom_io_commit(pom_io_file *w, pom_error *err);

/* Closes and removes the temporary file (nothing written); NULL f is allowed. */
void pom_io_abort(pom_io_file *w);

#endif
