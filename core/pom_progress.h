/* pom_progress.h - a one-line progress bar with rate and ETA.
 *
 * Library code never prints on its own: the caller (cli/) owns the FILE* and
 * drives the bar with pom_progress_update(). The bar draws only when the
 * stream is a terminal (or when forced), at most every `min_interval` seconds,
 * so redirected output stays clean. No global state. */
#ifndef POM_PROGRESS_H
#define POM_PROGRESS_H

#include <stddef.h>
#include <stdio.h>

typedef struct {
  FILE *out;           /* where to draw (not owned); NULL = never draw */
  int enabled;         /* 1 when drawing (out is a TTY, or forced) */
  char label[48];      /* text before the bar */
  long total;          /* units of work in this run */
  long start_done;     /* units already done when the run began (resume): not in the rate */
  double t_start;      /* monotonic time at init (s) */
  double t_last;       /* monotonic time of the last draw (s) */
  double min_interval; /* smallest time between draws (s), default 0.1 */
  int width;           /* bar width in characters, default 30 */
  int drawn;           /* 1 once something was drawn (finish then ends the line) */
} pom_progress;

/* Prepares a bar for `total` units of which `start_done` are already done.
 * Draws only if out is a terminal; force = 1 draws regardless (tests). */
void pom_progress_init(pom_progress *p, FILE *out, const char *label, long total, long start_done,
                       int force);

/* Redraws (rate-limited) with `done` units finished in total. */
void pom_progress_update(pom_progress *p, long done);

/* Draws the final state and ends the line (nothing when never drawn). */
void pom_progress_finish(pom_progress *p, long done);

/* Formats one bar line into buf: "label [#####.....]  done/total  pct%  rate/s
 * ETA mm:ss". elapsed is the time since the start (s); the rate counts only
 * units finished in this run (done - start_done). Returns buf. */
char *pom_progress_format(char *buf, size_t cap, const char *label, long done, long total,
                          long start_done, double elapsed, int width);

/* Monotonic clock (s). */
double pom_progress_now(void);

#endif
