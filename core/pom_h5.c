/* pom_h5.c - HDF5 helpers: quiet error stack, failures into pom_error. */
#include "pom_h5.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- errors -------------------------------------------------------------- */
void pom_h5_quiet(void) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

typedef struct {
  char text[512];   /* description of the innermost (first) stack entry */
  char system[200]; /* the system's reason of a failed read or write, "" if none */
} h5_walk_data;

static herr_t h5_walk(unsigned n, const H5E_error2_t *e, void *client) {
  h5_walk_data *w = client;
  if (!e) return 0;
  if (n == 0)
    snprintf(w->text, sizeof w->text, "%s (in %s)", e->desc ? e->desc : "?",
             e->func_name ? e->func_name : "?");
  /* the file driver's long message ("file write failed: time = ..., errno =
   * 28, error message = 'No space left on device', ...") carries the reason */
  const char *m = e->desc ? strstr(e->desc, "error message = '") : NULL;
  if (m && !w->system[0]) {
    m += strlen("error message = '");
    size_t len = strcspn(m, "'");
    snprintf(w->system, sizeof w->system, "%.*s", (int)(len < 190 ? len : 190), m);
  }
  return 0;
}

pom_status pom_h5_fail(pom_error *err, const char *src_file, int src_line, const char *what) {
  h5_walk_data w;
  snprintf(w.text, sizeof w.text, "no HDF5 error message");
  w.system[0] = '\0';
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, h5_walk, &w);
  H5Eclear2(H5E_DEFAULT);
  if (w.system[0])
    return pom_error_set(err, POM_ERR_HDF5, src_file, src_line, "%s: %s", what, w.system);
  return pom_error_set(err, POM_ERR_HDF5, src_file, src_line, "%s: %s", what, w.text);
}

/* ---- the library's lifetime ------------------------------------------------ */
/* Failed creates and closes in this process. Global because what it mirrors
 * is global: HDF5's own table of open files, shared by the whole process. */
static int file_failures;

void pom_h5_startup(void) {
  H5dont_atexit();
  pom_h5_quiet();
}

void pom_h5_shutdown(void) {
  /* H5close would visit a half-closed file and crash like the exit handler,
   * and loses a half-created one's buffers (measured with HDF5 1.10.8:
   * tests/test_dataloss.sh) */
  if (file_failures == 0) H5close();
}

int pom_h5_file_failures(void) {
  return file_failures;
}

/* ---- files and groups ---------------------------------------------------- */
pom_status pom_h5_create_file(hid_t *file, const char *path, pom_error *err) {
  pom_h5_quiet();
  *file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (*file < 0) {
    ++file_failures; /* a half-made file: HDF5 1.10.8 keeps its buffers */
    char what[600];
    snprintf(what, sizeof what, "cannot create HDF5 file '%s'", path);
    POM_H5_FAIL(err, what);
  }
  return POM_OK;
}

pom_status pom_h5_open_file(hid_t *file, const char *path, int writable, pom_error *err) {
  pom_h5_quiet();
  *file = H5Fopen(path, writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT);
  if (*file < 0) {
    ++file_failures; /* as a failed create */
    char what[600];
    snprintf(what, sizeof what, "cannot open HDF5 file '%s'", path);
    POM_H5_FAIL(err, what);
  }
  return POM_OK;
}

pom_status pom_h5_close_file(hid_t file, pom_error *err) {
  if (file < 0) return POM_OK;
  pom_h5_quiet();
  herr_t a = H5Fflush(file, H5F_SCOPE_LOCAL);
  herr_t b = H5Fclose(file);
  if (b < 0) ++file_failures; /* still in HDF5's ID table (pom_h5_startup) */
  if (a < 0 || b < 0) POM_H5_FAIL(err, "closing HDF5 file");
  return POM_OK;
}

int pom_h5_exists(hid_t loc, const char *name) {
  pom_h5_quiet();
  htri_t r = H5Lexists(loc, name, H5P_DEFAULT);
  if (r < 0) H5Eclear2(H5E_DEFAULT);
  return r > 0;
}

pom_status pom_h5_create_group(hid_t *group, hid_t loc, const char *name, pom_error *err) {
  pom_h5_quiet();
  *group = H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (*group < 0) {
    char what[300];
    snprintf(what, sizeof what, "cannot create group '%s'", name);
    POM_H5_FAIL(err, what);
  }
  return POM_OK;
}

pom_status pom_h5_open_group(hid_t *group, hid_t loc, const char *name, pom_error *err) {
  pom_h5_quiet();
  *group = H5Gopen2(loc, name, H5P_DEFAULT);
  if (*group < 0) {
    char what[300];
    snprintf(what, sizeof what, "cannot open group '%s'", name);
    POM_H5_FAIL(err, what);
  }
  return POM_OK;
}

/* ---- attributes ---------------------------------------------------------- */
/* Writes an attribute of type `type` and dataspace `space` (both closed here). */
static pom_status write_attr(hid_t loc, const char *name, hid_t type, hid_t space, const void *data,
                             pom_error *err) {
  pom_status st = POM_OK;
  hid_t attr = -1;
  char what[300];
  snprintf(what, sizeof what, "writing attribute '%s'", name);
  if (type < 0 || space < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, what);
    goto done;
  }
  if (H5Aexists(loc, name) > 0 && H5Adelete(loc, name) < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, what);
    goto done;
  }
  attr = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  if (attr < 0 || H5Awrite(attr, type, data) < 0) st = pom_h5_fail(err, __FILE__, __LINE__, what);
done:
  if (attr >= 0) H5Aclose(attr);
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  return st;
}

/* A fixed-length, NUL-terminated C string type of `size` bytes. */
static hid_t string_type(size_t size) {
  hid_t t = H5Tcopy(H5T_C_S1);
  if (t < 0) return t;
  if (H5Tset_size(t, size) < 0 || H5Tset_strpad(t, H5T_STR_NULLTERM) < 0 ||
      H5Tset_cset(t, H5T_CSET_UTF8) < 0) {
    H5Tclose(t);
    return -1;
  }
  return t;
}

pom_status pom_h5_attr_string(hid_t loc, const char *name, const char *value, pom_error *err) {
  pom_h5_quiet();
  return write_attr(loc, name, string_type(strlen(value) + 1), H5Screate(H5S_SCALAR), value, err);
}

pom_status pom_h5_attr_double(hid_t loc, const char *name, double value, pom_error *err) {
  pom_h5_quiet();
  return write_attr(loc, name, H5Tcopy(H5T_NATIVE_DOUBLE), H5Screate(H5S_SCALAR), &value, err);
}

pom_status pom_h5_attr_int64(hid_t loc, const char *name, int64_t value, pom_error *err) {
  pom_h5_quiet();
  return write_attr(loc, name, H5Tcopy(H5T_NATIVE_INT64), H5Screate(H5S_SCALAR), &value, err);
}

pom_status pom_h5_attr_doubles(hid_t loc, const char *name, const double *values, size_t n,
                               pom_error *err) {
  pom_h5_quiet();
  hsize_t dim = (hsize_t)n;
  return write_attr(loc, name, H5Tcopy(H5T_NATIVE_DOUBLE), H5Screate_simple(1, &dim, NULL), values,
                    err);
}

/* Opens attribute `name`, checks its class, returns it (or fails). */
static pom_status open_attr(hid_t *attr, hid_t loc, const char *name, H5T_class_t cls,
                            pom_error *err) {
  char what[300];
  snprintf(what, sizeof what, "reading attribute '%s'", name);
  *attr = H5Aopen(loc, name, H5P_DEFAULT);
  if (*attr < 0) POM_H5_FAIL(err, what);
  hid_t t = H5Aget_type(*attr);
  H5T_class_t got = t >= 0 ? H5Tget_class(t) : H5T_NO_CLASS;
  if (t >= 0) H5Tclose(t);
  if (got != cls) {
    H5Aclose(*attr);
    *attr = -1;
    POM_FAIL(err, POM_ERR_HDF5, "attribute '%s' has an unexpected type", name);
  }
  return POM_OK;
}

pom_status pom_h5_read_attr_string(hid_t loc, const char *name, char *buf, size_t cap,
                                   pom_error *err) {
  pom_h5_quiet();
  hid_t attr = -1, ftype = -1, mtype = -1;
  pom_status st = POM_OK;
  POM_TRY(open_attr(&attr, loc, name, H5T_STRING, err));
  ftype = H5Aget_type(attr);
  size_t size = ftype >= 0 ? H5Tget_size(ftype) : 0;
  if (size == 0 || H5Tis_variable_str(ftype) > 0)
    POM_FAIL_GOTO(err, POM_ERR_HDF5, done, "attribute '%s': not a fixed-length string", name);
  if (size + 1 > cap)
    POM_FAIL_GOTO(err, POM_ERR_HDF5, done, "attribute '%s': string longer than %zu bytes", name,
                  cap - 1);
  mtype = string_type(size + 1);
  memset(buf, 0, size + 1);
  if (mtype < 0 || H5Aread(attr, mtype, buf) < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, "reading string attribute");
    goto done;
  }
  buf[size] = '\0';
done:
  if (mtype >= 0) H5Tclose(mtype);
  if (ftype >= 0) H5Tclose(ftype);
  H5Aclose(attr);
  return st;
}

pom_status pom_h5_read_attr_double(hid_t loc, const char *name, double *value, pom_error *err) {
  pom_h5_quiet();
  hid_t attr = -1;
  POM_TRY(open_attr(&attr, loc, name, H5T_FLOAT, err));
  herr_t r = H5Aread(attr, H5T_NATIVE_DOUBLE, value);
  H5Aclose(attr);
  if (r < 0) POM_H5_FAIL(err, "reading a real attribute");
  return POM_OK;
}

pom_status pom_h5_read_attr_int64(hid_t loc, const char *name, int64_t *value, pom_error *err) {
  pom_h5_quiet();
  hid_t attr = -1;
  POM_TRY(open_attr(&attr, loc, name, H5T_INTEGER, err));
  herr_t r = H5Aread(attr, H5T_NATIVE_INT64, value);
  H5Aclose(attr);
  if (r < 0) POM_H5_FAIL(err, "reading an integer attribute");
  return POM_OK;
}

/* ---- datasets ------------------------------------------------------------ */
static pom_status write_dataset(hid_t loc, const char *name, hid_t type, hid_t space,
                                const void *data, pom_error *err) {
  pom_status st = POM_OK;
  hid_t ds = -1;
  char what[300];
  snprintf(what, sizeof what, "writing dataset '%s'", name);
  if (type < 0 || space < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, what);
    goto done;
  }
  ds = H5Dcreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds < 0 || H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    st = pom_h5_fail(err, __FILE__, __LINE__, what);
done:
  if (ds >= 0) H5Dclose(ds);
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  return st;
}

pom_status pom_h5_write_text(hid_t loc, const char *name, const char *text, pom_error *err) {
  pom_h5_quiet();
  return write_dataset(loc, name, string_type(strlen(text) + 1), H5Screate(H5S_SCALAR), text, err);
}

pom_status pom_h5_read_text(hid_t loc, const char *name, char **text, pom_error *err) {
  pom_h5_quiet();
  pom_status st = POM_OK;
  hid_t ds = -1, ftype = -1, mtype = -1;
  *text = NULL;
  char what[300];
  snprintf(what, sizeof what, "reading text dataset '%s'", name);
  ds = H5Dopen2(loc, name, H5P_DEFAULT);
  if (ds < 0) POM_H5_FAIL(err, what);
  ftype = H5Dget_type(ds);
  if (ftype < 0 || H5Tget_class(ftype) != H5T_STRING || H5Tis_variable_str(ftype) > 0)
    POM_FAIL_GOTO(err, POM_ERR_HDF5, done, "dataset '%s' is not a fixed-length string", name);
  size_t size = H5Tget_size(ftype);
  *text = calloc(size + 1, 1);
  if (!*text) POM_FAIL_GOTO(err, POM_ERR_NOMEM, done, "%s: out of memory", what);
  mtype = string_type(size + 1);
  if (mtype < 0 || H5Dread(ds, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, *text) < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, what);
    goto done;
  }
done:
  if (st != POM_OK) {
    free(*text);
    *text = NULL;
  }
  if (mtype >= 0) H5Tclose(mtype);
  if (ftype >= 0) H5Tclose(ftype);
  H5Dclose(ds);
  return st;
}

pom_status pom_h5_write_doubles(hid_t loc, const char *name, int rank, const size_t *dims,
                                const double *data, pom_error *err) {
  pom_h5_quiet();
  if (rank < 1 || rank > 2)
    POM_FAIL(err, POM_ERR_ARG, "dataset '%s': rank %d not 1 or 2", name, rank);
  hsize_t d[2] = {(hsize_t)dims[0], rank == 2 ? (hsize_t)dims[1] : 1};
  return write_dataset(loc, name, H5Tcopy(H5T_NATIVE_DOUBLE), H5Screate_simple(rank, d, NULL), data,
                       err);
}

pom_status pom_h5_write_int64s(hid_t loc, const char *name, size_t n, const int64_t *data,
                               pom_error *err) {
  pom_h5_quiet();
  hsize_t d = (hsize_t)n;
  return write_dataset(loc, name, H5Tcopy(H5T_NATIVE_INT64), H5Screate_simple(1, &d, NULL), data,
                       err);
}

pom_status pom_h5_write_int64_table(hid_t loc, const char *name, size_t rows, size_t cols,
                                    const int64_t *data, pom_error *err) {
  pom_h5_quiet();
  hsize_t d[2] = {(hsize_t)rows, (hsize_t)cols};
  return write_dataset(loc, name, H5Tcopy(H5T_NATIVE_INT64), H5Screate_simple(2, d, NULL), data,
                       err);
}

pom_status pom_h5_read_doubles(hid_t loc, const char *name, size_t count, double *data,
                               pom_error *err) {
  pom_h5_quiet();
  pom_status st = POM_OK;
  char what[300];
  snprintf(what, sizeof what, "reading dataset '%s'", name);
  hid_t ds = H5Dopen2(loc, name, H5P_DEFAULT);
  if (ds < 0) POM_H5_FAIL(err, what);
  hid_t space = H5Dget_space(ds);
  hssize_t n = space >= 0 ? H5Sget_simple_extent_npoints(space) : -1;
  if (n < 0 || (size_t)n != count) {
    st = pom_error_set(err, POM_ERR_HDF5, __FILE__, __LINE__,
                       "dataset '%s' has %lld elements, expected %zu", name, (long long)n, count);
  } else if (H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    st = pom_h5_fail(err, __FILE__, __LINE__, what);
  }
  if (space >= 0) H5Sclose(space);
  H5Dclose(ds);
  return st;
}

pom_status pom_h5_write_strings(hid_t loc, const char *name, size_t n, const char *const *strings,
                                size_t width, pom_error *err) {
  pom_h5_quiet();
  char *buf = calloc(n ? n : 1, width);
  if (!buf) POM_FAIL(err, POM_ERR_NOMEM, "dataset '%s': out of memory", name);
  for (size_t k = 0; k < n; ++k)
    snprintf(buf + k * width, width, "%s", strings[k]);
  hsize_t d = (hsize_t)n;
  pom_status st =
      write_dataset(loc, name, string_type(width), H5Screate_simple(1, &d, NULL), buf, err);
  free(buf);
  return st;
}
