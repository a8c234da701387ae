/* pom_h5.h - small HDF5 helpers with HDF5's own error printing turned off and
 * every failure routed into a pom_status / pom_error (docs/STYLE.md 5).
 *
 * Handles are plain hid_t values owned by the caller (close them with the
 * matching H5*close or pom_h5_close_file). The HDF5 library used is the serial
 * one: call these from one thread at a time. */
#ifndef POM_H5_H
#define POM_H5_H

#include "pom_status.h"

#include <hdf5.h>
#include <stddef.h>
#include <stdint.h>

/* Turns off HDF5's automatic error printing for the default error stack.
 * Every function below calls it; calling it again is harmless. */
void pom_h5_quiet(void);

/* ---- the library's lifetime (for programs; library code never calls these) -- */
/* Call first in a program, before any other HDF5 call: keeps HDF5 from
 * registering its own exit handler (H5dont_atexit). HDF5 1.10 leaves a file
 * whose close failed (a full disk) half-closed in its ID table, where no
 * call can release it and its exit handler crashes (SIGSEGV) on it. */
void pom_h5_startup(void);
/* Call last: closes the HDF5 library (H5close) unless a file failed to be
 * created, opened or closed in this process; then HDF5's state is left for the
 * operating system to release at exit (the failure was already reported).
 * After a failed H5Fcreate, HDF5 1.10.8's H5close drops the half-made
 * file's buffers without freeing them (LeakSanitizer reports them). */
void pom_h5_shutdown(void);
/* The number of pom_h5_create_file, pom_h5_open_file and pom_h5_close_file
 * calls that failed in this process. */
int pom_h5_file_failures(void);

/* Fills err with POM_ERR_HDF5, "what: <innermost HDF5 message>", and returns
 * POM_ERR_HDF5. Use right after an HDF5 call failed. */
pom_status pom_h5_fail(pom_error *err, const char *src_file, int src_line, const char *what);

#define POM_H5_FAIL(err, what) return pom_h5_fail((err), __FILE__, __LINE__, (what))

/* ---- files and groups --------------------------------------------------- */
/* Creates (truncates) a file; *file receives the handle. */
pom_status pom_h5_create_file(hid_t *file, const char *path, pom_error *err);
/* Opens an existing file read-write (writable != 0) or read-only. */
pom_status pom_h5_open_file(hid_t *file, const char *path, int writable, pom_error *err);
/* Flushes and closes a file handle (a negative handle is ignored). On
 * failure the handle stays unusable in HDF5's ID table (HDF5 1.10 cannot
 * release it): do not use it again, and end the program through
 * pom_h5_shutdown. */
pom_status pom_h5_close_file(hid_t file, pom_error *err);
/* 1 when a link `name` exists below loc (one level, no path walking). */
int pom_h5_exists(hid_t loc, const char *name);
/* Creates a group below loc; *group receives the handle. */
pom_status pom_h5_create_group(hid_t *group, hid_t loc, const char *name, pom_error *err);
/* Opens an existing group below loc. */
pom_status pom_h5_open_group(hid_t *group, hid_t loc, const char *name, pom_error *err);

/* ---- attributes (scalars, small arrays, strings) ------------------------- */
pom_status pom_h5_attr_string(hid_t loc, const char *name, const char *value, pom_error *err);
pom_status pom_h5_attr_double(hid_t loc, const char *name, double value, pom_error *err);
pom_status pom_h5_attr_int64(hid_t loc, const char *name, int64_t value, pom_error *err);
/* n doubles as a 1-D attribute. */
pom_status pom_h5_attr_doubles(hid_t loc, const char *name, const double *values, size_t n,
                               pom_error *err);
/* Reads a string attribute into buf (cap bytes, NUL-terminated; too long is an
 * error). */
pom_status pom_h5_read_attr_string(hid_t loc, const char *name, char *buf, size_t cap,
                                   pom_error *err);
pom_status pom_h5_read_attr_double(hid_t loc, const char *name, double *value, pom_error *err);
pom_status pom_h5_read_attr_int64(hid_t loc, const char *name, int64_t *value, pom_error *err);

/* ---- datasets ------------------------------------------------------------ */
/* A scalar fixed-length string dataset holding text (e.g. a config file). */
pom_status pom_h5_write_text(hid_t loc, const char *name, const char *text, pom_error *err);
/* Reads a text dataset written by pom_h5_write_text; *text is malloc'ed and
 * owned by the caller. */
pom_status pom_h5_read_text(hid_t loc, const char *name, char **text, pom_error *err);
/* A contiguous row-major double dataset of rank 1 or 2 (dims[rank]). */
pom_status pom_h5_write_doubles(hid_t loc, const char *name, int rank, const size_t *dims,
                                const double *data, pom_error *err);
/* A 1-D int64 dataset of n values. */
pom_status pom_h5_write_int64s(hid_t loc, const char *name, size_t n, const int64_t *data,
                               pom_error *err);
/* A row-major rows x cols int64 dataset. */
pom_status pom_h5_write_int64_table(hid_t loc, const char *name, size_t rows, size_t cols,
                                    const int64_t *data, pom_error *err);
/* Reads a whole double dataset of exactly `count` elements into data. */
pom_status pom_h5_read_doubles(hid_t loc, const char *name, size_t count, double *data,
                               pom_error *err);
/* A 1-D dataset of n fixed-length strings (each up to width-1 characters;
 * strings[k] must be NUL-terminated). */
pom_status pom_h5_write_strings(hid_t loc, const char *name, size_t n, const char *const *strings,
                                size_t width, pom_error *err);

#endif
