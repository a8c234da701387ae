/* pom_progress.c - terminal progress bar driven by the caller. */
#define _POSIX_C_SOURCE 200809L
#include "pom_progress.h"

#include <math.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

double pom_progress_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void pom_progress_init(pom_progress *p, FILE *out, const char *label, long total, long start_done,
                       int force) {
  memset(p, 0, sizeof *p);
  p->out = out;
  p->enabled = out != NULL;
  p->log_lines = out && !force && !isatty(fileno(out));
  snprintf(p->label, sizeof p->label, "%s", label ? label : "");
  p->total = total;
  p->start_done = start_done;
  p->t_start = pom_progress_now();
  p->t_last = -1e300;
  p->min_interval = 0.1;
  p->width = 30;
  p->log_delay = 2.0;
  p->log_interval = 20.0;
  p->log_decile = -1;
}

/* Time as m:ss (or h:mm:ss); "--:--" when unknown. */
static void format_time(char *buf, size_t cap, double s) {
  if (!isfinite(s) || s < 0 || s > 360000.0) {
    snprintf(buf, cap, "--:--");
    return;
  }
  long t = (long)(s + 0.5);
  if (t >= 3600)
    snprintf(buf, cap, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else
    snprintf(buf, cap, "%ld:%02ld", t / 60, t % 60);
}

char *pom_progress_format(char *buf, size_t cap, const char *label, long done, long total,
                          long start_done, double elapsed, int width) {
  char bar[128];
  if (width < 0) width = 0;
  if (width > (int)sizeof bar - 1) width = (int)sizeof bar - 1;
  double frac = total > 0 ? (double)done / (double)total : 1.0;
  if (frac < 0) frac = 0;
  if (frac > 1) frac = 1;
  int filled = (int)(frac * width);
  for (int k = 0; k < width; ++k)
    bar[k] = k < filled ? '#' : '.';
  bar[width] = '\0';
  long run_done = done - start_done;
  double rate = elapsed > 0 && run_done > 0 ? (double)run_done / elapsed : NAN;
  double eta = isfinite(rate) && rate > 0 ? (double)(total - done) / rate : NAN;
  char eta_text[32], el_text[32];
  format_time(eta_text, sizeof eta_text, eta);
  format_time(el_text, sizeof el_text, elapsed);
  char head[192], rate_text[48];
  if (width > 0)
    snprintf(head, sizeof head, "%s [%s]", label, bar);
  else
    snprintf(head, sizeof head, "%s:", label);
  if (isfinite(rate))
    snprintf(rate_text, sizeof rate_text, "%.1f/s", rate);
  else
    snprintf(rate_text, sizeof rate_text, "-/s");
  snprintf(buf, cap, "%s %ld/%ld %3.0f%%  %s  %s elapsed  ETA %s", head, done, total, 100.0 * frac,
           rate_text, el_text, eta_text);
  return buf;
}

static void draw(pom_progress *p, long done, double now) {
  char line[512];
  pom_progress_format(line, sizeof line, p->label, done, p->total, p->start_done, now - p->t_start,
                      p->log_lines ? 0 : p->width);
  if (p->log_lines)
    fprintf(p->out, "%s\n", line);
  else /* \r returns to the line start; \033[K clears what a longer line left */
    fprintf(p->out, "\r%s\033[K", line);
  fflush(p->out);
  p->t_last = now;
  p->drawn = 1;
}

/* The 10 % step that `done` has reached (0..10). */
static int decile(const pom_progress *p, long done) {
  if (p->total <= 0) return 10;
  double frac = (double)done / (double)p->total;
  int d = (int)floor(10.0 * frac + 1e-9); /* + 1e-9: 30 of 100 is the 3rd step despite rounding */
  return d < 0 ? 0 : d > 10 ? 10 : d;
}

int pom_progress_update_at(pom_progress *p, long done, double now) {
  if (!p->enabled) return 0;
  if (!p->log_lines) {
    if (now - p->t_last < p->min_interval) return 0;
    draw(p, done, now);
    return 1;
  }
  if (now - p->t_start < p->log_delay) return 0;
  int d = decile(p, done);
  if (d <= p->log_decile && now - p->t_last < p->log_interval) return 0;
  draw(p, done, now);
  p->log_decile = d;
  return 1;
}

void pom_progress_update(pom_progress *p, long done) {
  pom_progress_update_at(p, done, pom_progress_now());
}

void pom_progress_finish(pom_progress *p, long done) {
  if (!p->enabled) return;
  if (p->log_lines) {
    /* a short run that wrote nothing stays silent */
    if (p->drawn && p->log_decile < 10) draw(p, done, pom_progress_now());
    return;
  }
  draw(p, done, pom_progress_now());
  fputc('\n', p->out);
  fflush(p->out);
}
