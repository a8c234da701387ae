/* pom_io.c - files written whole or not at all. */
#define _GNU_SOURCE /* copy_file_range (Linux, glibc 2.27) */
#include "pom_io.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
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

/* ---- sync -------------------------------------------------------------------- */
pom_status pom_io_sync(const char *path, pom_error *err) {
  int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0 || fsync(fd) != 0) {
    int e = errno;
    if (fd >= 0) close(fd);
    POM_FAIL(err, POM_ERR_IO, "cannot sync '%s' to the disk: %s", path, strerror(e));
  }
  if (close(fd) != 0) POM_FAIL(err, POM_ERR_IO, "closing '%s': %s", path, strerror(errno));
  return POM_OK;
}

pom_status pom_io_sync_folder(const char *path, pom_error *err) {
  char dir[1200];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (!slash)
    snprintf(dir, sizeof dir, ".");
  else if (slash == dir)
    dir[1] = '\0';
  else
    *slash = '\0';
  int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  /* a folder that cannot be synced (EINVAL: some file systems) has nothing
   * the kernel would write later */
  if (fd < 0 || (fsync(fd) != 0 && errno != EINVAL)) {
    int e = errno;
    if (fd >= 0) close(fd);
    POM_FAIL(err, POM_ERR_IO, "cannot sync the folder '%s' to the disk: %s", dir, strerror(e));
  }
  close(fd);
  return POM_OK;
}

/* ---- commit -------------------------------------------------------------------- */
/* Closes w, checking every write, the close and (for a temporary file) the
 * sync. Returns 0, or the errno of the failure (-1 when none is known). */
static int close_checked(pom_io_file *w) {
  /* a failed write sets the error flag (errno still says why, unless the
   * close fails too and says it again); the close flushes the rest */
  int e = errno;
  int failed = ferror(w->f) != 0;
  if (!failed && fflush(w->f) != 0) {
    failed = 1;
    e = errno;
  }
  if (!failed && w->tmp[0] && fsync(fileno(w->f)) != 0) {
    failed = 1;
    e = errno;
  }
  if (fclose(w->f) != 0) {
    failed = 1;
    e = errno;
  }
  w->f = NULL;
  return failed ? (e ? e : -1) : 0;
}

pom_status pom_io_commit_all(pom_io_file *w, int n, pom_error *err) {
  pom_status st = POM_OK;
  for (int k = 0; k < n; ++k) {
    if (!w[k].f) {
      if (st == POM_OK)
        st = pom_error_set(err, POM_ERR_ARG, __FILE__, __LINE__, "'%s' is not open", w[k].path);
      continue;
    }
    int e = close_checked(&w[k]);
    if (e != 0 && st == POM_OK)
      st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__, "writing '%s' failed: %s", w[k].path,
                         e > 0 ? strerror(e) : "write error");
  }
  /* every file is complete before the first rename */
  for (int k = 0; k < n && st == POM_OK; ++k) {
    if (!w[k].tmp[0]) continue;
    if (rename(w[k].tmp, w[k].path) != 0) {
      st = pom_error_set(err, POM_ERR_IO, __FILE__, __LINE__, "cannot rename '%s' to '%s': %s",
                         w[k].tmp, w[k].path, strerror(errno));
      break;
    }
    w[k].tmp[0] = '\0';
    st = pom_io_sync_folder(w[k].path, err);
  }
  for (int k = 0; k < n; ++k) {
    if (w[k].tmp[0]) unlink(w[k].tmp);
    w[k].tmp[0] = '\0';
  }
  return st;
}

pom_status pom_io_commit(pom_io_file *w, pom_error *err) {
  return pom_io_commit_all(w, 1, err);
}

void pom_io_abort(pom_io_file *w) {
  if (w->f) fclose(w->f);
  w->f = NULL;
  if (w->tmp[0]) unlink(w->tmp);
  w->tmp[0] = '\0';
}

/* ---- copy ---------------------------------------------------------------------- */
pom_status pom_io_copy(const char *from, const char *to, pom_error *err) {
  char buf[1 << 16];
  int in = open(from, O_RDONLY | O_CLOEXEC);
  if (in < 0) POM_FAIL(err, POM_ERR_IO, "cannot read '%s': %s", from, strerror(errno));
  int out = open(to, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (out < 0) {
    int e = errno;
    close(in);
    POM_FAIL(err, POM_ERR_IO, "cannot create '%s': %s", to, strerror(e));
  }
  int e = 0;
  const char *failed = to;
  /* in the kernel first: a reflink (no data copied, no space taken) where the
   * file system shares blocks (btrfs, XFS), else a copy without the round
   * trip through this process; read and write where it is not supported */
  off_t copied = 0;
  for (;;) {
    ssize_t n = copy_file_range(in, NULL, out, NULL, (size_t)1 << 30, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      int ce = errno;
      if (copied == 0 && (ce == ENOSYS || ce == EXDEV || ce == EINVAL || ce == EOPNOTSUPP ||
                          ce == EBADF || ce == EPERM))
        break; /* not supported here: read and write below */
      e = ce;
      break;
    }
    if (n == 0) break;
    copied += n;
  }
  for (; !e;) {
    ssize_t n = read(in, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      e = errno;
      failed = from;
      break;
    }
    if (n == 0) break;
    for (ssize_t off = 0; off < n;) {
      ssize_t m = write(out, buf + off, (size_t)(n - off));
      if (m < 0 && errno == EINTR) continue;
      if (m <= 0) {
        e = m < 0 ? errno : ENOSPC;
        break;
      }
      off += m;
    }
    if (e) break;
  }
  if (!e && fsync(out) != 0) e = errno;
  if (close(out) != 0 && !e) e = errno;
  close(in);
  if (e) {
    unlink(to);
    POM_FAIL(err, POM_ERR_IO, "copying '%s' to '%s' failed: %s ('%s')", from, to, strerror(e),
             failed);
  }
  return POM_OK;
}

/* ---- exclusive use of an output path ----------------------------------------------- */
pom_status pom_io_lock_take(pom_io_lock *lk, const char *path, pom_error *err) {
  lk->fd = -1;
  if ((size_t)snprintf(lk->path, sizeof lk->path, "%s.lock", path) >= sizeof lk->path)
    POM_FAIL(err, POM_ERR_ARG, "output path too long for its lock file: '%s'", path);
  for (int attempt = 0; attempt < 8; ++attempt) {
    int fd = open(lk->path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      POM_FAIL(err, POM_ERR_IO, "cannot create the lock file '%s': %s", lk->path, strerror(errno));
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      int e = errno;
      char owner[32] = "";
      ssize_t n = read(fd, owner, sizeof owner - 1);
      owner[n > 0 ? n : 0] = '\0';
      owner[strcspn(owner, "\n")] = '\0';
      close(fd);
      if (e == EWOULDBLOCK)
        POM_FAIL(err, POM_ERR_IO,
                 "'%s' is being written by another pomlab run (process %s holds '%s'): wait for "
                 "it to finish or choose another output; nothing was changed",
                 path, owner[0] ? owner : "?", lk->path);
      POM_FAIL(err, POM_ERR_IO, "cannot lock '%s': %s", lk->path, strerror(e));
    }
    /* the holder before us may have removed the file after we opened it:
     * then our lock is on a file nobody else sees; take the new one */
    struct stat held, now;
    if (fstat(fd, &held) == 0 && stat(lk->path, &now) == 0 && held.st_ino == now.st_ino &&
        held.st_dev == now.st_dev) {
      char pid[32];
      int len = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
      if (ftruncate(fd, 0) != 0 || write(fd, pid, (size_t)len) != len) {
        int e = errno;
        close(fd);
        POM_FAIL(err, POM_ERR_IO, "cannot write the lock file '%s': %s", lk->path, strerror(e));
      }
      lk->fd = fd;
      return POM_OK;
    }
    close(fd);
  }
  POM_FAIL(err, POM_ERR_IO, "cannot take the lock file '%s': it keeps being replaced", lk->path);
}

void pom_io_lock_release(pom_io_lock *lk) {
  if (lk->fd < 0) return;
  unlink(lk->path); /* while still holding it (see pom_io_lock_take) */
  close(lk->fd);
  lk->fd = -1;
}
