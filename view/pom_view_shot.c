/* pom_view_shot.c - pictures of a `pomlab view` page: headless Chromium
 * (software WebGL) for screenshots, ffmpeg for films (docs/view.md
 * section 5). */
#define _DEFAULT_SOURCE /* posix_spawn, realpath, mkstemp */
#include "pom_view.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

/* The first of names found in PATH (or names[0] as given when it holds a
 * slash) into buf; 0 when found. */
int pom_view_find_program(const char *const *names, char *buf, size_t cap) {
  for (int k = 0; names[k]; ++k) {
    if (strchr(names[k], '/')) {
      if (access(names[k], X_OK) == 0) {
        snprintf(buf, cap, "%s", names[k]);
        return 0;
      }
      continue;
    }
    const char *path = getenv("PATH");
    if (!path) path = "/usr/bin:/bin";
    while (*path) {
      const char *colon = strchr(path, ':');
      size_t len = colon ? (size_t)(colon - path) : strlen(path);
      snprintf(buf, cap, "%.*s/%s", (int)len, path, names[k]);
      if (len && access(buf, X_OK) == 0) return 0;
      path += len + (colon ? 1 : 0);
    }
  }
  return -1;
}

int pom_view_find_chromium(char *buf, size_t cap) {
  const char *env = getenv("POM_CHROMIUM");
  const char *const own[] = {env, NULL};
  const char *const names[] = {"chromium", "chromium-browser", "google-chrome", NULL};
  if (env && env[0]) return pom_view_find_program(own, buf, cap);
  return pom_view_find_program(names, buf, cap);
}

/* Runs argv with stdout to out_path (NULL: /dev/null) and stderr to
 * err_path; returns the exit status, or -1 when it could not start. */
static int run(char *const argv[], const char *out_path, const char *err_path) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out_path ? out_path : "/dev/null",
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err_path ? err_path : "/dev/null",
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid;
  int rc = posix_spawn(&pid, argv[0], &fa, NULL, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* The DOM dumped by Chromium: POM_OK when the page reported ready with no
 * script error, else why. */
static pom_status check_dom(const char *dom_path, const char *what, pom_error *err) {
  FILE *f = fopen(dom_path, "r");
  char buf[4096];
  size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
  if (f) fclose(f);
  buf[n] = '\0';
  const char *s = strstr(buf, "id=\"status\"");
  const char *ready = s ? strstr(s, "data-ready=\"1\"") : NULL;
  const char *errs = s ? strstr(s, "data-errors=\"") : NULL;
  if (!s || !ready)
    POM_FAIL(err, POM_ERR_IO, "%s: the page did not finish drawing in Chromium (no WebGL?)", what);
  if (errs && strncmp(errs, "data-errors=\"0\"", 15) != 0)
    POM_FAIL(err, POM_ERR_IO, "%s: the page reported script errors in Chromium", what);
  return POM_OK;
}

/* A screenshot of url (file://...) of w x h pixels into png. */
pom_status pom_view_screenshot(const char *chromium, const char *url, const char *png, int w, int h,
                               const char *tmpdir, const char *what, pom_error *err) {
  char size[64], shot[PATH_MAX + 16], dom[PATH_MAX], log[PATH_MAX];
  snprintf(size, sizeof size, "--window-size=%d,%d", w, h);
  snprintf(shot, sizeof shot, "--screenshot=%s", png);
  snprintf(dom, sizeof dom, "%s/dom.html", tmpdir);
  snprintf(log, sizeof log, "%s/chromium.log", tmpdir);
  /* software WebGL (SwiftShader through ANGLE): no GPU, no display needed
   * (docs/view.md section 5) */
  char *argv[] = {(char *)chromium,
                  "--headless",
                  "--no-sandbox",
                  "--disable-gpu",
                  "--use-angle=swiftshader",
                  "--enable-unsafe-swiftshader",
                  "--hide-scrollbars",
                  "--mute-audio",
                  "--no-first-run",
                  "--virtual-time-budget=5000",
                  size,
                  shot,
                  "--dump-dom",
                  (char *)url,
                  NULL};
  remove(png);
  int rc = run(argv, dom, log);
  struct stat st;
  if (rc != 0 || stat(png, &st) != 0 || st.st_size == 0)
    POM_FAIL(err, POM_ERR_IO, "%s: Chromium (%s) failed (exit %d); its messages: %s", what,
             chromium, rc, log);
  return check_dom(dom, what, err);
}

int pom_view_abs_path(const char *path, char *buf, size_t cap) {
  /* the file exists (written by us): realpath of it */
  char tmp[PATH_MAX];
  if (!realpath(path, tmp)) return -1;
  snprintf(buf, cap, "%s", tmp);
  return 0;
}

/* An output path made absolute through its folder (the file may not exist). */
int pom_view_abs_output(const char *path, char *buf, size_t cap) {
  char dir[PATH_MAX], real[PATH_MAX];
  const char *slash = strrchr(path, '/');
  if (slash) {
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    if (dir[0] == '\0') snprintf(dir, sizeof dir, "/");
  } else {
    snprintf(dir, sizeof dir, ".");
  }
  if (!realpath(dir, real)) return -1;
  snprintf(buf, cap, "%s/%s", real, slash ? slash + 1 : path);
  return 0;
}

/* The film: batches of frames drawn as tiles in one screenshot each
 * (#tiles=...), cut into frames and encoded by ffmpeg's untile filter. */
pom_status pom_view_mp4(const char *chromium, const char *ffmpeg, const char *html, const char *mp4,
                        int n_frames, int w, int h, int fps, const char *tmpdir, pom_error *err) {
  int cols = 4096 / w, rows = 4096 / h;
  if (cols < 1) cols = 1;
  if (rows < 1) rows = 1;
  if (cols > 8) cols = 8;
  if (rows > 8) rows = 8;
  /* no larger than the frames need: software WebGL pays for every pixel */
  if (cols > n_frames) cols = n_frames;
  if (rows > (n_frames + cols - 1) / cols) rows = (n_frames + cols - 1) / cols;
  int per = cols * rows, batches = (n_frames + per - 1) / per;
  for (int b = 0; b < batches; ++b) {
    int start = b * per, count = n_frames - start < per ? n_frames - start : per;
    char url[PATH_MAX + 128], png[PATH_MAX], what[64];
    snprintf(url, sizeof url, "file://%s#tiles=%d,%d,%d,%d,%d", html, start, count, cols, w, h);
    snprintf(png, sizeof png, "%s/batch_%03d.png", tmpdir, b);
    snprintf(what, sizeof what, "--mp4 frames %d-%d", start, start + count - 1);
    POM_TRY(pom_view_screenshot(chromium, url, png, cols * w, rows * h, tmpdir, what, err));
  }
  char pattern[PATH_MAX], filter[128], rate[32], frames[32], log[PATH_MAX], out[PATH_MAX + 8];
  snprintf(pattern, sizeof pattern, "%s/batch_%%03d.png", tmpdir);
  snprintf(filter, sizeof filter, "untile=%dx%d,setpts=N/(%d*TB),format=yuv420p", cols, rows, fps);
  snprintf(rate, sizeof rate, "%d", fps);
  snprintf(frames, sizeof frames, "%d", n_frames);
  snprintf(log, sizeof log, "%s/ffmpeg.log", tmpdir);
  snprintf(out, sizeof out, "%s", mp4);
  char *argv[] = {
      (char *)ffmpeg, "-y",      "-loglevel", "error",   "-framerate", "1",         "-i",
      pattern,        "-vf",     filter,      "-r",      rate,         "-frames:v", frames,
      "-c:v",         "libx264", "-pix_fmt",  "yuv420p", out,          NULL};
  int rc = run(argv, NULL, log);
  if (rc != 0)
    POM_FAIL(err, POM_ERR_IO, "--mp4: ffmpeg (%s) failed (exit %d); its messages: %s", ffmpeg, rc,
             log);
  return POM_OK;
}

pom_status pom_view_check_writable(const char *path, const char *what, pom_error *err) {
  char dir[PATH_MAX], probe[PATH_MAX + 32];
  const char *slash = strrchr(path, '/');
  if (slash && slash != path)
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
  else
    snprintf(dir, sizeof dir, slash ? "/" : ".");
  snprintf(probe, sizeof probe, "%s/.pomlab-probe-XXXXXX", strcmp(dir, "/") ? dir : "");
  int fd = mkstemp(probe);
  if (fd < 0)
    POM_FAIL(err, POM_ERR_IO, "%s: cannot write '%s': the folder %s is not writable (%s)", what,
             path, dir, strerror(errno));
  close(fd);
  remove(probe);
  return POM_OK;
}

/* Removes the files of the temporary folder and the folder. */
void pom_view_remove_tmpdir(const char *dir, int batches) {
  char p[PATH_MAX + 32];
  const char *names[] = {"page.html", "dom.html", "chromium.log", "ffmpeg.log", NULL};
  for (int k = 0; names[k]; ++k) {
    snprintf(p, sizeof p, "%s/%s", dir, names[k]);
    remove(p);
  }
  for (int b = 0; b < batches; ++b) {
    snprintf(p, sizeof p, "%s/batch_%03d.png", dir, b);
    remove(p);
  }
  rmdir(dir);
}
