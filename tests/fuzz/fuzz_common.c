/* fuzz_common.c - the temporary config folder, refused inputs and the
 * failure invariant of the fuzz targets (fuzz_common.h). */
#define _XOPEN_SOURCE 700 /* mkdtemp, nftw */
#include "fuzz_common.h"

#include <dirent.h>
#include <errno.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifndef POM_SOURCE_DIR
#error "POM_SOURCE_DIR must name the source tree (tests/fuzz/CMakeLists.txt)"
#endif

static char fuzz_root[1024];  /* the temporary folder, "" until made */
static char fuzz_input[1100]; /* FOLDER/configs/fuzz.cfg */

/* ---- the temporary folder --------------------------------------------------- */
static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw) {
  (void)sb;
  (void)flag;
  (void)ftw;
  return remove(path);
}

static void remove_root(void) {
  if (fuzz_root[0]) nftw(fuzz_root, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* Copies every *.cfg file of src_dir into dst_dir. 0 on success. */
static int copy_configs(const char *src_dir, const char *dst_dir) {
  DIR *d = opendir(src_dir);
  if (!d) {
    fprintf(stderr, "fuzz: cannot list %s: %s\n", src_dir, strerror(errno));
    return -1;
  }
  int rc = 0;
  for (struct dirent *e = readdir(d); e && rc == 0; e = readdir(d)) {
    size_t n = strlen(e->d_name);
    if (n < 5 || strcmp(e->d_name + n - 4, ".cfg") != 0) continue;
    char from[2048], to[2048];
    snprintf(from, sizeof from, "%s/%s", src_dir, e->d_name);
    snprintf(to, sizeof to, "%s/%s", dst_dir, e->d_name);
    FILE *in = fopen(from, "rb"), *out = in ? fopen(to, "wb") : NULL;
    char buf[8192];
    size_t got;
    while (in && out && (got = fread(buf, 1, sizeof buf, in)) > 0)
      if (fwrite(buf, 1, got, out) != got) break;
    if (!in || !out || ferror(in) || ferror(out)) {
      fprintf(stderr, "fuzz: cannot copy %s to %s\n", from, to);
      rc = -1;
    }
    if (in) fclose(in);
    if (out && fclose(out) != 0) rc = -1;
  }
  closedir(d);
  return rc;
}

const char *pom_fuzz_setup(void) {
  if (fuzz_input[0]) return fuzz_input;
  const char *tmp = getenv("TMPDIR");
  snprintf(fuzz_root, sizeof fuzz_root, "%s/pomlab-fuzz-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
  if (!mkdtemp(fuzz_root)) {
    fprintf(stderr, "fuzz: cannot make %s: %s\n", fuzz_root, strerror(errno));
    fuzz_root[0] = '\0';
    return NULL;
  }
  atexit(remove_root);
  /* the layout of the source tree, so that the test configs find ../configs/ */
  static const char *const folders[] = {"configs", "tests"};
  for (size_t k = 0; k < sizeof folders / sizeof folders[0]; ++k) {
    char src[1100], dst[1100];
    snprintf(src, sizeof src, "%s/%s", POM_SOURCE_DIR, folders[k]);
    snprintf(dst, sizeof dst, "%s/%s", fuzz_root, folders[k]);
    if (mkdir(dst, 0700) != 0 || copy_configs(src, dst) != 0) {
      fprintf(stderr, "fuzz: cannot prepare %s\n", dst);
      return NULL;
    }
  }
  snprintf(fuzz_input, sizeof fuzz_input, "%s/configs/fuzz.cfg", fuzz_root);
  return fuzz_input;
}

/* ---- inputs ------------------------------------------------------------------- */
int pom_fuzz_refused(const uint8_t *data, size_t size) {
  /* quotes and blanks dropped, so that "/d" "ev" (libconfig joins adjacent
   * strings) is caught too */
  static const char *const special[] = {"/dev", "/proc", "/sys", "\\x", "\\X"};
  char *flat = malloc(size + 1);
  if (!flat) return 1;
  size_t n = 0;
  for (size_t k = 0; k < size; ++k) {
    char c = (char)data[k];
    if (c != '"' && c != ' ' && c != '\t' && c != '\n' && c != '\r') flat[n++] = c;
  }
  flat[n] = '\0';
  int refused = 0;
  for (size_t j = 0; j < sizeof special / sizeof special[0] && !refused; ++j)
    for (const char *p = flat; p < flat + n && !refused; p += strlen(p) + 1)
      refused = strstr(p, special[j]) != NULL; /* every NUL-separated piece */
  free(flat);
  return refused;
}

int pom_fuzz_write(const char *path, const uint8_t *data, size_t size) {
  FILE *f = fopen(path, "wb");
  if (!f && errno == ENOENT && path == fuzz_input) {
    /* the folder was removed under a long run (a cleaner of /tmp): the
     * copies are made again, in a new folder that path then names */
    fprintf(stderr, "fuzz: %s has gone; copying the configs again\n", fuzz_root);
    fuzz_input[0] = '\0';
    if (pom_fuzz_setup()) f = fopen(path, "wb");
  }
  if (!f) {
    fprintf(stderr, "fuzz: cannot write the input to %s: %s\n", path, strerror(errno));
    return -1;
  }
  int rc = size > 0 && fwrite(data, 1, size, f) != size ? -1 : 0;
  if (fclose(f) != 0) rc = -1;
  return rc;
}

/* ---- invariants ------------------------------------------------------------------ */
void pom_fuzz_check_failure(pom_status st, const pom_error *err, const char *stage) {
  if (st == POM_OK) return;
  /* POM_FUZZ_VERBOSE=1: say why an input stopped (for checking a seed) */
  const char *verbose = getenv("POM_FUZZ_VERBOSE");
  if (verbose && verbose[0] == '1') fprintf(stderr, "fuzz: %s: %s\n", stage, err->message);
  if ((int)st > 0 || strcmp(pom_status_name(st), "POM_UNKNOWN") == 0) {
    fprintf(stderr, "fuzz: %s returned %d, which is no pomlab error status\n", stage, (int)st);
    abort();
  }
  if (!err->message[0]) {
    fprintf(stderr, "fuzz: %s failed with %s and no message\n", stage, pom_status_name(st));
    abort();
  }
}

/* ---- sanitizer settings ------------------------------------------------------------ */
/* libconfig 1.5 (Debian 12) leaks the text of a string token that a syntax
 * error discards (allocated by its scanner: strbuf_append, or
 * libconfig_yylex for an empty string; fixed upstream in libconfig 1.7.3,
 * pull request 155 of hyperrealm/libconfig): not pomlab's memory to free.
 * A config tree pomlab failed to destroy still shows through its settings.
 * Every other leak fails the run. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) {
  return "leak:strbuf_append\nleak:libconfig_yylex\n";
}

/* ... and without a note after every input that hit it. */
const char *__lsan_default_options(void);
const char *__lsan_default_options(void) {
  return "print_suppressions=0";
}
