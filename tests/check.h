/* check.h - the small assertion kit of pomlab's test programs.
 *
 * Each check prints a line only when it fails (with the values and the
 * tolerance) and counts failures; a test's main returns check_summary(). */
#ifndef POM_CHECK_H
#define POM_CHECK_H

#include <math.h>
#include <stdio.h>

static int check_failures_ = 0;
static int check_count_ = 0;

/* |got - want| <= tol_abs */
#define check_abs(got, want, tol_abs) check_abs_((got), (want), (tol_abs), #got, __FILE__, __LINE__)
/* |got - want| <= tol_rel * |want| */
#define check_rel(got, want, tol_rel) check_rel_((got), (want), (tol_rel), #got, __FILE__, __LINE__)
/* a condition */
#define check_true(cond) check_true_((cond) ? 1 : 0, #cond, __FILE__, __LINE__)

static inline int check_abs_(double got, double want, double tol, const char *what,
                             const char *file, int line) {
  ++check_count_;
  if (!(fabs(got - want) <= tol)) {
    ++check_failures_;
    printf("%s:%d: FAIL %s = %.17g, want %.17g (abs tol %.3g, diff %.3g)\n", file, line, what, got,
           want, tol, fabs(got - want));
    return 0;
  }
  return 1;
}

static inline int check_rel_(double got, double want, double tol, const char *what,
                             const char *file, int line) {
  ++check_count_;
  if (!(fabs(got - want) <= tol * fabs(want))) {
    ++check_failures_;
    printf("%s:%d: FAIL %s = %.17g, want %.17g (rel tol %.3g, rel diff %.3g)\n", file, line, what,
           got, want, tol, fabs(got - want) / fabs(want));
    return 0;
  }
  return 1;
}

static inline int check_true_(int ok, const char *what, const char *file, int line) {
  ++check_count_;
  if (!ok) {
    ++check_failures_;
    printf("%s:%d: FAIL %s\n", file, line, what);
  }
  return ok;
}

/* Prints the tally; returns the exit code for main. */
static inline int check_summary(const char *name) {
  printf("%s: %d checks, %d failed\n", name, check_count_, check_failures_);
  return check_failures_ ? 1 : 0;
}

#endif
