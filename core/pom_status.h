/* pom_status.h - status codes, messages and the error record of pomlab.
 *
 * One list defines every status code and its message (docs/STYLE.md 5). Library
 * functions return a pom_status and, when given a non-NULL pom_error, fill it
 * with a specific message and the source location of the failure. Library
 * code never prints and never ends the process. */
#ifndef POM_STATUS_H
#define POM_STATUS_H

#include <stddef.h>

/* X(name, value, message) */
#define POM_STATUS_LIST(X)                                                                         \
  X(POM_OK, 0, "success")                                                                          \
  X(POM_ERR_NOMEM, -1, "out of memory")                                                            \
  X(POM_ERR_IO, -2, "file input/output failed")                                                    \
  X(POM_ERR_CONFIG, -3, "invalid configuration")                                                   \
  X(POM_ERR_ARG, -4, "invalid argument")                                                           \
  X(POM_ERR_UNREACHABLE, -5, "pose cannot be assembled")                                           \
  X(POM_ERR_LIMIT, -6, "joint, stroke or interference limit violated")                             \
  X(POM_ERR_SINGULAR, -7, "singular Jacobian")                                                     \
  X(POM_ERR_NOCONVERGE, -8, "iteration did not converge")                                          \
  X(POM_ERR_SOLVER, -9, "ODE/DAE solver failure")                                                  \
  X(POM_ERR_NONFINITE, -10, "non-finite value (NaN or Inf)")                                       \
  X(POM_ERR_HDF5, -11, "HDF5 library failure")                                                     \
  X(POM_ERR_GSL, -12, "GSL library failure")                                                       \
  X(POM_ERR_NLOPT, -13, "NLopt optimizer failure")                                                 \
  X(POM_ERR_EULER_SINGULAR, -14, "ZYX Euler angles near their singularity (pitch = +-90 deg)")     \
  X(POM_ERR_INTERRUPTED, -15, "interrupted")                                                       \
  X(POM_ERR_MPI, -16, "MPI failure")                                                               \
  X(POM_ERR_UNSTABLE, -17, "simulation went unstable")                                             \
  X(POM_ERR_INTERNAL, -18, "internal error")

#define POM_STATUS_ENUM_ITEM(name, value, msg) name = value,
/* Status of every pomlab call: POM_OK (0) or a negative error code. */
typedef enum { POM_STATUS_LIST(POM_STATUS_ENUM_ITEM) POM_STATUS_MIN_ = -1000 } pom_status;
#undef POM_STATUS_ENUM_ITEM

/* Static message for a status code; never NULL. */
const char *pom_strerror(pom_status status);

/* Short symbolic name of a status ("POM_ERR_CONFIG"); never NULL. */
const char *pom_status_name(pom_status status);

/* Error record filled by a failing call: the code, a specific message (what,
 * where, which value, what was expected) and the source location. */
typedef struct {
  pom_status status;    /* the code, POM_OK when nothing failed */
  char message[1024];   /* specific message, NUL-terminated */
  const char *src_file; /* source file of the failure (static string) */
  int src_line;         /* source line of the failure */
} pom_error;

/* Clears an error record (err may be NULL). */
void pom_error_clear(pom_error *err);

/* Records status, printf-style message and location in err (which may be
 * NULL) and returns status. */
pom_status pom_error_set(pom_error *err, pom_status status, const char *src_file, int src_line,
                         const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Prefixes err->message with a printf-style context ("loading X: ...") and
 * returns err->status. err may be NULL. */
pom_status pom_error_prefix(pom_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Fails: records the error and returns its status from the calling function. */
#define POM_FAIL(err, code, ...)                                                                   \
  return pom_error_set((err), (code), __FILE__, __LINE__, __VA_ARGS__)

/* Fails inside a function with a `pom_status st` and a cleanup label. */
#define POM_FAIL_GOTO(err, code, label, ...)                                                       \
  do {                                                                                             \
    st = pom_error_set((err), (code), __FILE__, __LINE__, __VA_ARGS__);                            \
    goto label;                                                                                    \
  } while (0)

/* Propagates a failing status from a call to a cleanup label. */
#define POM_TRY_GOTO(expr, label)                                                                  \
  do {                                                                                             \
    st = (expr);                                                                                   \
    if (st != POM_OK) goto label;                                                                  \
  } while (0)

/* Propagates a failing status by returning it. */
#define POM_TRY(expr)                                                                              \
  do {                                                                                             \
    pom_status pom_try_st_ = (expr);                                                               \
    if (pom_try_st_ != POM_OK) return pom_try_st_;                                                 \
  } while (0)

#endif
