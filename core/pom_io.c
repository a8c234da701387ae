/* pom_io.c - text files written whole or not at all. */
#define _POSIX_C_SOURCE 200809L
#include "pom_io.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Removes PATH.tmp.<pid> files that a process of this machine left when it
 * was killed before its rename: <pid> is not this process and no longer
 * runs (kill(pid, 0) fails with ESRCH). A temporary file of a running
 * process, or one whose pid has been reused, is left alone. */
static void remove_stale_temps(const char *path) {
  char dir[1100];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  const char *base = slash ? slash + 1 : path;
  if (slash == dir)
    dir[1] = '\0';
  else if (slash)
    *slash = '\0';
  else
    snprintf(dir, sizeof dir, ".");
  char prefix[1100];
  int n_prefix = snprintf(prefix, sizeof prefix, "%s.tmp.", base);
  if (n_prefix <= 0 || (size_t)n_prefix >= sizeof prefix) return;
  DIR *d = opendir(dir);
  if (!d) return;
  for (struct dirent *e = readdir(d); e; e = readdir(d)) {
    if (strncmp(e->d_name, prefix, (size_t)n_prefix) != 0) continue;
    const char *digits = e->d_name + n_prefix;
    char *end = NULL;
    long pid = strtol(digits, &end, 10);
    if (end == digits || *end || pid <= 0 || pid == (long)getpid()) continue;
    if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue;
    char stale[2300];
    snprintf(stale, sizeof stale, "%s/%s", dir, e->d_name);
    unlink(stale);
  }
  closedir(d);
}

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
  if (!special) {
    remove_stale_temps(path);
    snprintf(w->tmp, sizeof w->tmp, "%s.tmp.%ld", path, (long)getpid());
  }
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
