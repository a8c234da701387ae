/* pom_progress.h - a one-line progress bar with rate and ETA.
 *
 * Library code never prints on its own: the caller (cli/) owns the FILE* and
 * drives the bar with pom_progress_update(). On a terminal (or when forced)
 * the bar redraws in place at most every `min_interval` seconds. Any other
 * stream (a log file, a pipe) gets whole lines instead, so that a log shows
 * long work: nothing during the first `log_delay` seconds (a short run stays
 * silent), then one line each time the work crosses a multiple of 10 % and at
 * least one every `log_interval` seconds, and a last line at the finish when
 * anything was written. No global state. */
#ifndef POM_PROGRESS_H
#define POM_PROGRESS_H

#include <stddef.h>
#include <stdio.h>

typedef struct {
  FILE *out;           /* where to draw (not owned); NULL = never draw */
  int enabled;         /* 1 when anything may be written (out != NULL) */
  int log_lines;       /* 1: whole lines for a log (out is not a TTY and not forced) */
  char label[48];      /* text before the bar */
  long total;          /* units of work in this run */
  long start_done;     /* units already done when the run began (resume): not in the rate */
  double t_start;      /* monotonic time at init (s) */
  double t_last;       /* monotonic time of the last draw (s) */
  double min_interval; /* smallest time between draws (s), default 0.1 */
  int width;           /* bar width in characters, default 30 */
  double log_delay;    /* log lines: silence after the start (s), default 2 */
  double log_interval; /* log lines: largest gap between lines (s), default 20 */
  int log_decile;      /* log lines: the 10 % step of the last line (-1 before the first) */
  int drawn;           /* 1 once something was drawn (finish then ends the line) */
} pom_progress;

/* Prepares a bar for `total` units of which `start_done` are already done.
 * out = NULL: silent. A terminal, or force = 1: a bar redrawn in place;
 * anything else: log lines (see above). */
void pom_progress_init(pom_progress *p, FILE *out, const char *label, long total, long start_done,
                       int force);

/* Redraws (rate-limited) with `done` units finished in total. */
void pom_progress_update(pom_progress *p, long done);

/* Draws the final state and ends the line (nothing when never drawn). */
void pom_progress_finish(pom_progress *p, long done);

/* pom_progress_update at a given time `now` (s, same clock as
 * pom_progress_now): what update does, with the clock made explicit for
 * tests. Returns 1 when it wrote something. */
int pom_progress_update_at(pom_progress *p, long done, double now);

/* Formats one bar line into buf: "label [#####.....]  done/total  pct%  rate/s
 * ETA mm:ss". elapsed is the time since the start (s); the rate counts only
 * units finished in this run (done - start_done). width = 0 leaves the bar
 * out ("label: done/total ..."), as log lines do. Returns buf. */
char *pom_progress_format(char *buf, size_t cap, const char *label, long done, long total,
                          long start_done, double elapsed, int width);

/* Monotonic clock (s). */
double pom_progress_now(void);

#endif
