/* pom_io.c - text files written whole or not at all. */
#define _POSIX_C_SOURCE 200809L
#include "pom_io.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

pom_status pom_io_create(pom_io_file *w, const char *path, pom_error *err) {
  memset(w, 0, sizeof *w);
  if (strlen(path) >= sizeof w->path)
    POM_FAIL(err, POM_ERR_ARG, "output path longer than %zu characters: '%s'", sizeof w->path - 1,
             path);
  snprintf(w->path, sizeof w->path, "%s", path);
  struct stat sb;
  int special = stat(path, &sb) == 0 && !S_ISREG(sb.st_mode);
  if (special && S_ISDIR(sb.st_mode))
    POM_FAIL(err, POM_ERR_IO, "cannot write '%s': it is a directory", path);
  if (!special) snprintf(w->tmp, sizeof w->tmp, "%s.tmp.%ld", path, (long)getpid());
  const char *open_path = special ? path : w->tmp;
  w->f = fopen(open_path, "w");
  if (!w->f) {
    int e = errno;
    w->tmp[0] = '\0';
    POM_FAIL(err, POM_ERR_IO, "cannot write '%s': %s", path, strerror(e));
  }
  return POM_OK;
}

pom_status pom_io_commit(pom_io_file *w, pom_error *err) {
  if (!w->f) POM_FAIL(err, POM_ERR_ARG, "'%s' is not open", w->path);
  /* a failed write sets the error flag (errno still says why, unless the
   * close fails too and says it again); the close flushes the rest */
  int e = errno;
  int failed = ferror(w->f) != 0;
  if (fclose(w->f) != 0) {
    failed = 1;
    e = errno;
  }
  w->f = NULL;
  if (!failed && w->tmp[0] && rename(w->tmp, w->path) != 0) {
    failed = 1;
    e = errno;
  }
  if (failed) {
    if (w->tmp[0]) unlink(w->tmp);
    w->tmp[0] = '\0';
    POM_FAIL(err, POM_ERR_IO, "writing '%s' failed: %s", w->path, e ? strerror(e) : "write error");
  }
  w->tmp[0] = '\0';
  return POM_OK;
}

void pom_io_abort(pom_io_file *w) {
  if (w->f) fclose(w->f);
  w->f = NULL;
  if (w->tmp[0]) unlink(w->tmp);
  w->tmp[0] = '\0';
}
