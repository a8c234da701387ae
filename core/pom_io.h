/* pom_io.h - files written whole or not at all.
 *
 * pom_io_create opens PATH.tmp.<pid> next to PATH; pom_io_commit checks every
 * write and the close, syncs the file to the disk, renames it over PATH and
 * syncs the folder, so PATH is either the old file or the complete new one,
 * never a truncated one (a full disk, a killed run, a power cut after the
 * commit). pom_io_commit_all does the same for files that belong together:
 * every one is complete before any is renamed. A PATH that exists and is not
 * a regular file (/dev/stdout, a pipe, /dev/full) is written directly, with
 * the same checks. A run killed before its rename leaves PATH.tmp.<pid>; the
 * next pom_io_create of PATH removes those whose process no longer runs. */
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

/* Commits n files together: closes and syncs all of them, and renames them
 * only when every one is complete; on a failure none is renamed (all
 * temporary files removed, err names the first failure). The renames
 * themselves need no space, so a full disk cannot separate them. */
pom_status pom_io_commit_all(pom_io_file *w, int n, pom_error *err);

/* Closes and removes the temporary file (nothing written); NULL f is allowed. */
void pom_io_abort(pom_io_file *w);

/* Forces a file's data to the disk (fsync); err names the path. */
pom_status pom_io_sync(const char *path, pom_error *err);

/* Forces the folder holding path to the disk, so that a rename or an
 * unlink in it survives a crash; err names the folder. */
pom_status pom_io_sync_folder(const char *path, pom_error *err);

/* Copies the regular file from to the new file to (created, 0644; an
 * existing one is replaced), checking every write, and syncs it. On
 * failure to is removed and err names the file and the reason. */
pom_status pom_io_copy(const char *from, const char *to, pom_error *err);

/* Exclusive use of an output path by one run: PATH.lock held with flock
 * (docs/results.md, "Writing safely"). The kernel drops the lock when the
 * process ends however it ends (kill -9 too), so a lock file left behind
 * never blocks the next run; the holder's pid is written in it for the
 * message a refused run prints. fd is -1 when none is held. */
typedef struct {
  int fd;          /* holds the lock, -1 when none */
  char path[1100]; /* PATH.lock */
} pom_io_lock;

/* Takes PATH.lock; while another run holds it: POM_ERR_IO and err names
 * PATH, the holder's pid and the lock file ("is being written by another
 * pomlab run ... nothing was changed"). Nothing else is touched. */
pom_status pom_io_lock_take(pom_io_lock *lk, const char *path, pom_error *err);

/* Removes the lock file (while still holding it) and releases it; a lock
 * not held (fd -1) is allowed. */
void pom_io_lock_release(pom_io_lock *lk);

#endif
