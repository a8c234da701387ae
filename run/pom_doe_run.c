/* pom_doe_run.c - the batch runner: worker threads pull (candidate,
 * maneuver) units, the driving thread stores finished rows (docs/results.md,
 * "Execution"). Results are stored by unit index, so the order in which
 * workers finish never matters. */
#define _POSIX_C_SOURCE 200809L
#include "run_internal.h"
#include "pom_doe_mpi.h"

#include <errno.h>
#include <stddef.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define DEFAULT_QUEUE  64
#define DEFAULT_POLL_S 0.1
#define READ_BLOCK     256 /* rows read at a time when resuming */

typedef struct {
  long unit;       /* k * n_candidates + c */
  long order;      /* c * count + k: the storage order (set when storing) */
  pom_doe_row row; /* its result */
} finished_unit;

typedef struct pom_doe_worker {
  struct pom_doe_run *run;
  int index;     /* worker number */
  void **states; /* [n_candidates] evaluator worker states */
} pom_doe_worker;

struct pom_doe_run {
  const pom_doe_study *study;
  pom_doe_run_options opt;
  int n_threads;
  int rank, size;       /* MPI rank and size (0, 1 without MPI) */
  pom_doe_results *res; /* root: results file, NULL when none */
  pom_doe_cell *cells;  /* [n_candidates * count] compact results (others: done flags) */
  long total;           /* units in the study */
  long start_done;      /* units finished before this run */
  long done;            /* units finished in total (root: all ranks) */
  long new_done;        /* units finished by this run (root: all ranks) */
  long *todo;           /* [n_todo] units this rank computes */
  long n_todo;
  /* shared with the workers, under mu */
  pthread_mutex_t mu;
  pthread_cond_t not_empty, not_full;
  int sync_ready;       /* 1 once mu and the conditions exist */
  long next;            /* next index into todo */
  int cancel;           /* 1: take no new units */
  int alive;            /* workers still running */
  finished_unit *queue; /* ring buffer [queue_capacity] */
  int q_head, q_count;
  /* driving thread only */
  finished_unit *batch;    /* [queue_capacity] units popped by step() */
  finished_unit *sorted;   /* [queue_capacity] root: units in storage order */
  pom_doe_row *rows;       /* [queue_capacity] root: contiguous rows for one write */
  pom_doe_worker *workers; /* [n_threads] */
  pthread_t *threads;      /* [n_threads] */
  int n_started;
  int finished;
  pom_doe_mpi *mpi; /* NULL without MPI */
};

void pom_doe_run_options_defaults(pom_doe_run_options *o) {
  memset(o, 0, sizeof *o);
  o->queue_capacity = DEFAULT_QUEUE;
  o->poll_interval = DEFAULT_POLL_S;
}

/* Runs one unit into row: draw the maneuver, map it to targets, evaluate. A
 * failure of any kind becomes the row's status and reason. */
static void run_unit(const pom_doe_study *study, void **states, long unit, pom_doe_row *row) {
  int nc = study->n_candidates;
  long k = unit / nc;
  int c = (int)(unit % nc);
  const pom_doe_evaluator *ev = &study->candidates[c].eval;
  void *state = states[c];
  pom_doe_maneuver mv;
  pom_dyn_metrics met;
  pom_error e;
  double q[3];
  pom_error_clear(&e);
  memset(&met, 0, sizeof met);
  pom_status st = POM_OK;
  /* uncertain parameters: this unit's draws make a model of their own
   * (docs/results.md section 10); a draw that breaks the candidate is a
   * failed maneuver */
  pom_doe_evaluator drawn;
  memset(&drawn, 0, sizeof drawn);
  void *drawn_state = NULL;
  long man = k;
  if (study->uncertain.n > 0) {
    double u[POM_UNC_MAX], x[POM_UNC_MAX];
    pom_unc_unit(&study->uncertain, k, &man, u);
    for (int j = 0; j < study->uncertain.n; ++j)
      x[j] = pom_dist_quantile(&study->uncertain.param[j].dist, u[j]);
    st = pom_doe_uncertain_evaluator(&drawn, study, c, x, &e);
    if (st == POM_OK) st = drawn.worker_create(&drawn_state, drawn.ctx, &e);
    ev = &drawn;
    state = drawn_state;
  }
  pom_doe_maneuver_draw(&mv, &study->maneuvers, man);
  if (st == POM_OK && study->maneuvers.space == POM_DOE_SPACE_ORIENTATION) {
    st = ev->targets(ev->ctx, &mv, q, &e);
  } else {
    for (int i = 0; i < 3; ++i)
      q[i] = mv.q[i];
  }
  if (st == POM_OK) {
    for (int i = 0; i < 3; ++i)
      met.target[i] = q[i];
    st = ev->run(ev->ctx, state, q, &met, &e);
  } else {
    for (int i = 0; i < 3; ++i)
      met.target[i] = study->maneuvers.space == POM_DOE_SPACE_ORIENTATION ? NAN : q[i];
  }
  if (drawn_state) drawn.worker_destroy(drawn_state);
  pom_doe_evaluator_clear(&drawn);
  if (st != POM_OK && met.status == POM_OK) met.status = st;
  if (met.status != POM_OK && !met.reason[0])
    snprintf(met.reason, sizeof met.reason, "%s",
             e.message[0] ? e.message : pom_strerror(met.status));
  pom_doe_row_from_metrics(row, &met);
  /* numerical outcomes are data: a non-finite result is a failure, not a NaN */
  if (row->status == POM_OK) {
    int bad = !isfinite(row->energy_total);
    for (int i = 0; i < 3; ++i)
      bad |= row->settled[i] && !isfinite(row->settling_time[i]);
    if (bad) {
      row->status = POM_ERR_NONFINITE;
      snprintf(row->reason, sizeof row->reason, "non-finite energy or settling time");
    }
  }
  if (row->status != POM_OK) row->execution_time = NAN;
}

/* ---- workers ----------------------------------------------------------------- */
static void *worker_main(void *arg) {
  pom_doe_worker *w = arg;
  pom_doe_run *run = w->run;
  finished_unit item;
  for (;;) {
    pthread_mutex_lock(&run->mu);
    if (run->cancel || run->next >= run->n_todo) {
      --run->alive;
      pthread_cond_broadcast(&run->not_empty);
      pthread_mutex_unlock(&run->mu);
      return NULL;
    }
    item.unit = run->todo[run->next++];
    pthread_mutex_unlock(&run->mu);

    run_unit(run->study, w->states, item.unit, &item.row);

    pthread_mutex_lock(&run->mu);
    while (run->q_count == run->opt.queue_capacity)
      pthread_cond_wait(&run->not_full, &run->mu);
    int slot = (run->q_head + run->q_count) % run->opt.queue_capacity;
    run->queue[slot] = item;
    ++run->q_count;
    pthread_cond_signal(&run->not_empty);
    pthread_mutex_unlock(&run->mu);
  }
}

/* ---- begin ------------------------------------------------------------------- */
static int available_cores(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

/* mkdir -p of the folder part of path. */
static pom_status make_parent(const char *path, pom_error *err) {
  char dir[POM_DOE_PATH_LEN];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (!slash || slash == dir) return POM_OK;
  *slash = '\0';
  for (char *p = dir + 1; *p; ++p) {
    if (*p != '/') continue;
    *p = '\0';
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
      POM_FAIL(err, POM_ERR_IO, "cannot create folder '%s': %s", dir, strerror(errno));
    *p = '/';
  }
  if (mkdir(dir, 0777) != 0 && errno != EEXIST)
    POM_FAIL(err, POM_ERR_IO, "cannot create folder '%s': %s", dir, strerror(errno));
  return POM_OK;
}

/* Root: opens or creates the results file and loads finished rows. */
static pom_status open_results(pom_doe_run *run, const char *path, pom_error *err) {
  const pom_doe_study *study = run->study;
  long m = study->maneuvers.count;
  POM_TRY(make_parent(path, err));
  POM_TRY(run->opt.rows_only
              ? pom_doe_results_start_rows(&run->res, path, study, run->opt.resume, err)
              : pom_doe_results_start(&run->res, path, study, run->opt.resume, err));
  if (!pom_doe_results_resumed(run->res)) return POM_OK;
  pom_doe_row *block = malloc(READ_BLOCK * sizeof *block);
  if (!block) POM_FAIL(err, POM_ERR_NOMEM, "resume: out of memory");
  pom_status st = POM_OK;
  /* every stored row is checked: a damaged file is refused, naming rows */
  char bad[640] = "", why[200];
  long n_bad = 0;
  for (int c = 0; c < study->n_candidates && st == POM_OK; ++c)
    for (long k0 = 0; k0 < m && st == POM_OK; k0 += READ_BLOCK) {
      long n = m - k0 < READ_BLOCK ? m - k0 : READ_BLOCK;
      st = pom_doe_results_read(run->res, c, k0, n, block, err);
      for (long j = 0; j < n && st == POM_OK; ++j) {
        if (pom_doe_results_check_row(study, c, k0 + j, &block[j], why, sizeof why) != 0) {
          if (n_bad++ < 3 && strlen(bad) < sizeof bad - 1)
            snprintf(bad + strlen(bad), sizeof bad - strlen(bad), "%scandidate %d maneuver %ld: %s",
                     n_bad > 1 ? "; " : "", c, k0 + j, why);
          continue;
        }
        pom_doe_cell_from_row(&run->cells[(size_t)c * (size_t)m + (size_t)(k0 + j)], &block[j],
                              study->time_metric);
      }
    }
  free(block);
  if (st == POM_OK && n_bad > 0)
    POM_FAIL(err, POM_ERR_IO,
             "'%s': %ld stored row(s) are inconsistent (%s%s): the file is damaged and is not "
             "resumed; remove it to start again",
             pom_doe_results_open_path(run->res), n_bad, bad, n_bad > 3 ? "; ..." : "");
  if (st == POM_OK) st = pom_doe_results_mark_resumed(run->res, err);
  return st;
}

pom_status pom_doe_run_prepare(pom_doe_run **out, const pom_doe_study *study,
                               const pom_doe_run_options *opt, pom_error *err) {
  pom_status st = POM_OK;
  *out = NULL;
  pom_doe_run *run = calloc(1, sizeof *run);
  if (!run) POM_FAIL(err, POM_ERR_NOMEM, "run: out of memory");
  run->study = study;
  if (opt)
    run->opt = *opt;
  else
    pom_doe_run_options_defaults(&run->opt);
  if (run->opt.queue_capacity < 1) run->opt.queue_capacity = DEFAULT_QUEUE;
  if (!(run->opt.poll_interval > 0)) run->opt.poll_interval = DEFAULT_POLL_S;
  run->size = 1;
  int nc = study->n_candidates;
  long m = study->maneuvers.count;
  if (nc < 1 || m < 1) POM_FAIL_GOTO(err, POM_ERR_ARG, fail, "run: the study is empty");
  run->total = (long)nc * m;

  if (run->opt.use_mpi) {
    POM_TRY_GOTO(pom_doe_mpi_create(&run->mpi, err), fail);
    run->rank = pom_doe_mpi_rank(run->mpi);
    run->size = pom_doe_mpi_size(run->mpi);
  }
  const char *path = run->opt.output ? run->opt.output : study->output;
  run->cells = calloc((size_t)run->total, sizeof *run->cells);
  if (!run->cells) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "run: out of memory");
  if (run->rank == 0 && path && path[0]) st = open_results(run, path, err);
  if (run->mpi) {
    /* every rank learns the root's outcome and which units are done */
    POM_TRY_GOTO(pom_doe_mpi_share_start(run->mpi, &st, run->cells, run->total, err), fail);
  }
  if (st != POM_OK) goto fail;

  run->todo = malloc((size_t)run->total * sizeof *run->todo);
  if (!run->todo) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "run: out of memory");
  for (long u = 0; u < run->total; ++u) {
    int c = (int)(u % nc);
    long k = u / nc;
    if (run->cells[(size_t)c * (size_t)m + (size_t)k].done) {
      ++run->start_done;
      continue;
    }
    /* by maneuver: every rank gets the same mix of candidates */
    if (k % run->size == run->rank) run->todo[run->n_todo++] = u;
  }
  run->done = run->start_done;

  int threads = run->opt.threads > 0 ? run->opt.threads
                                     : (study->threads > 0 ? study->threads : available_cores());
  if (run->mpi && run->opt.threads <= 0 && study->threads <= 0) {
    /* all cores shared among the ranks on this machine */
    threads = available_cores() / pom_doe_mpi_local_size(run->mpi);
  }
  if (threads < 1) threads = 1;
  if (threads > run->n_todo) threads = run->n_todo > 0 ? (int)run->n_todo : 1;
  run->n_threads = threads;

  run->queue = malloc((size_t)run->opt.queue_capacity * sizeof *run->queue);
  run->batch = malloc((size_t)run->opt.queue_capacity * sizeof *run->batch);
  run->sorted = malloc((size_t)run->opt.queue_capacity * sizeof *run->sorted);
  run->rows = malloc((size_t)run->opt.queue_capacity * sizeof *run->rows);
  run->workers = calloc((size_t)threads, sizeof *run->workers);
  run->threads = calloc((size_t)threads, sizeof *run->threads);
  if (!run->queue || !run->batch || !run->sorted || !run->rows || !run->workers || !run->threads)
    POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "run: out of memory");
  for (int t = 0; t < threads; ++t) {
    pom_doe_worker *w = &run->workers[t];
    w->run = run;
    w->index = t;
    w->states = calloc((size_t)nc, sizeof *w->states);
    if (!w->states) POM_FAIL_GOTO(err, POM_ERR_NOMEM, fail, "run: out of memory");
    for (int c = 0; c < nc; ++c) {
      const pom_doe_evaluator *ev = &study->candidates[c].eval;
      if (ev->worker_create) {
        st = ev->worker_create(&w->states[c], ev->ctx, err);
        if (st != POM_OK) {
          pom_error_prefix(err, "candidate '%s': worker state", study->candidates[c].name);
          goto fail;
        }
      }
    }
  }
  if (pthread_mutex_init(&run->mu, NULL) != 0 || pthread_cond_init(&run->not_empty, NULL) != 0 ||
      pthread_cond_init(&run->not_full, NULL) != 0)
    POM_FAIL_GOTO(err, POM_ERR_INTERNAL, fail, "run: cannot create thread synchronization");
  run->sync_ready = 1;
  *out = run;
  return POM_OK;
fail:
  pom_doe_run_destroy(run);
  return st;
}

pom_status pom_doe_run_start(pom_doe_run *run, pom_error *err) {
  if (run->n_started > 0 || run->alive > 0)
    POM_FAIL(err, POM_ERR_ARG, "run: the workers have already started");
  run->alive = run->n_threads;
  for (int t = 0; t < run->n_threads; ++t) {
    if (pthread_create(&run->threads[t], NULL, worker_main, &run->workers[t]) != 0) {
      pthread_mutex_lock(&run->mu);
      run->alive -= run->n_threads - t;
      run->cancel = 1;
      pthread_mutex_unlock(&run->mu);
      POM_FAIL(err, POM_ERR_INTERNAL, "run: cannot start worker thread %d", t);
    }
    ++run->n_started;
  }
  return POM_OK;
}

pom_status pom_doe_run_begin(pom_doe_run **out, const pom_doe_study *study,
                             const pom_doe_run_options *opt, pom_error *err) {
  POM_TRY(pom_doe_run_prepare(out, study, opt, err));
  pom_status st = pom_doe_run_start(*out, err);
  if (st != POM_OK) {
    pom_doe_run_destroy(*out);
    *out = NULL;
  }
  return st;
}

/* ---- step --------------------------------------------------------------------- */
static int cmp_order(const void *a, const void *b) {
  long x = ((const finished_unit *)a)->order, y = ((const finished_unit *)b)->order;
  return (x > y) - (x < y);
}

/* Root: stores finished units (file rows + compact cells). Units are sorted
 * into storage order so that runs of neighbouring maneuvers of a candidate
 * go to the file in one write. */
static pom_status store_units(pom_doe_run *run, const void *units, int n, pom_error *err) {
  const finished_unit *u = units;
  int nc = run->study->n_candidates, cap = run->opt.queue_capacity;
  long m = run->study->maneuvers.count;
  for (int j0 = 0; j0 < n; j0 += cap) {
    int cnt = n - j0 < cap ? n - j0 : cap;
    memcpy(run->sorted, u + j0, (size_t)cnt * sizeof *u);
    for (int i = 0; i < cnt; ++i)
      run->sorted[i].order = (run->sorted[i].unit % nc) * m + run->sorted[i].unit / nc;
    qsort(run->sorted, (size_t)cnt, sizeof *run->sorted, cmp_order);
    for (int i = 0; i < cnt;) {
      int c = (int)(run->sorted[i].unit % nc);
      long k0 = run->sorted[i].unit / nc;
      int j = i;
      while (j < cnt && run->sorted[j].unit % nc == c && run->sorted[j].unit / nc == k0 + (j - i))
        ++j;
      for (int r = i; r < j; ++r) {
        run->rows[r - i] = run->sorted[r].row;
        pom_doe_cell_from_row(&run->cells[(size_t)c * (size_t)m + (size_t)(k0 + r - i)],
                              &run->sorted[r].row, run->study->time_metric);
      }
      if (run->res) POM_TRY(pom_doe_results_write_rows(run->res, c, k0, j - i, run->rows, err));
      run->done += j - i;
      run->new_done += j - i;
      i = j;
    }
  }
  return POM_OK;
}

pom_status pom_doe_run_step(pom_doe_run *run, int *finished, pom_error *err) {
  *finished = 0;
  if (run->finished) {
    *finished = 1;
    return POM_OK;
  }
  struct timespec until;
  clock_gettime(CLOCK_REALTIME, &until);
  double t = (double)until.tv_nsec * 1e-9 + run->opt.poll_interval;
  until.tv_sec += (time_t)t;
  until.tv_nsec = (long)((t - floor(t)) * 1e9);

  pthread_mutex_lock(&run->mu);
  while (run->q_count == 0 && run->alive > 0)
    if (pthread_cond_timedwait(&run->not_empty, &run->mu, &until) == ETIMEDOUT) break;
  int n = 0;
  while (run->q_count > 0) {
    run->batch[n++] = run->queue[run->q_head];
    run->q_head = (run->q_head + 1) % run->opt.queue_capacity;
    --run->q_count;
  }
  pthread_cond_broadcast(&run->not_full);
  int local_finished = run->alive == 0 && run->q_count == 0;
  pthread_mutex_unlock(&run->mu);

  int cancel_now = 0;
  if (run->mpi) {
    /* non-root ranks ship their units to the root; the root stores every
     * rank's units and says when to stop */
    POM_TRY(pom_doe_mpi_exchange(run->mpi, run->batch, n, sizeof(finished_unit), local_finished,
                                 run->rank == 0 ? store_units : NULL, run, &cancel_now, finished,
                                 err));
    if (run->rank != 0) run->new_done += n;
  } else {
    POM_TRY(store_units(run, run->batch, n, err));
    *finished = local_finished;
  }
  if (run->rank == 0 && n > 0 && run->res) POM_TRY(pom_doe_results_flush(run->res, err));
  if (run->rank == 0 && run->opt.stop_after > 0 && run->new_done >= run->opt.stop_after)
    cancel_now = 1;
  if (cancel_now) pom_doe_run_cancel(run);
  if (*finished) run->finished = 1;
  return POM_OK;
}

void pom_doe_run_cancel(pom_doe_run *run) {
  if (!run || !run->sync_ready) return;
  pthread_mutex_lock(&run->mu);
  run->cancel = 1;
  pthread_mutex_unlock(&run->mu);
  if (run->mpi) pom_doe_mpi_request_stop(run->mpi);
}

long pom_doe_run_done(const pom_doe_run *run) {
  return run->done;
}
long pom_doe_run_start_done(const pom_doe_run *run) {
  return run->start_done;
}
long pom_doe_run_total(const pom_doe_run *run) {
  return run->total;
}
int pom_doe_run_is_root(const pom_doe_run *run) {
  return run->rank == 0;
}
int pom_doe_run_threads(const pom_doe_run *run) {
  return run->n_threads;
}
int pom_doe_run_ranks(const pom_doe_run *run) {
  return run->size;
}

/* ---- end ------------------------------------------------------------------------ */
static void join_workers(pom_doe_run *run) {
  if (!run->sync_ready) return;
  pthread_mutex_lock(&run->mu);
  run->cancel = 1;
  /* make room so no worker blocks on a full queue */
  run->q_count = 0;
  pthread_cond_broadcast(&run->not_full);
  pthread_mutex_unlock(&run->mu);
  for (int t = 0; t < run->n_started; ++t)
    pthread_join(run->threads[t], NULL);
  run->n_started = 0;
}

pom_status pom_doe_run_end(pom_doe_run *run, pom_doe_report **report, pom_error *err) {
  int finished = run->finished;
  if (report) *report = NULL;
  while (!finished)
    POM_TRY(pom_doe_run_step(run, &finished, err));
  join_workers(run);
  if (run->mpi) POM_TRY(pom_doe_mpi_finish(run->mpi, err));
  if (run->rank != 0) return POM_OK;
  pom_doe_report *rep = NULL;
  POM_TRY(pom_doe_report_compute(&rep, run->study, run->cells, err));
  pom_status st = POM_OK;
  if (run->res && run->opt.rows_only) {
    /* the caller makes its own file; the rows and the lock stay */
    st = pom_doe_results_close_rows(run->res, err);
  } else if (run->res) {
    /* a finished study replaces the results file in one rename, and only
     * when its report was written whole */
    st = pom_doe_results_end(run->res, run->study, rep, run->done == run->total, err);
    run->res = NULL;
  }
  if (st != POM_OK || !report)
    pom_doe_report_destroy(rep);
  else
    *report = rep;
  return st;
}

pom_status pom_doe_run_rows_done(pom_doe_run *run, pom_error *err) {
  if (!run->res || !run->opt.rows_only) return POM_OK;
  return pom_doe_results_drop_rows(run->res, err);
}

double pom_doe_run_value(const pom_doe_run *run, int c, long k, int stat) {
  const pom_doe_cell *cell =
      &run->cells[(size_t)c * (size_t)run->study->maneuvers.count + (size_t)k];
  return cell->done ? cell->stat[stat] : NAN;
}

void pom_doe_run_destroy(pom_doe_run *run) {
  if (!run) return;
  join_workers(run);
  if (run->workers) {
    for (int t = 0; t < run->n_threads; ++t) {
      pom_doe_worker *w = &run->workers[t];
      if (!w->states) continue;
      for (int c = 0; c < run->study->n_candidates; ++c) {
        const pom_doe_evaluator *ev = &run->study->candidates[c].eval;
        if (w->states[c] && ev->worker_destroy) ev->worker_destroy(w->states[c]);
      }
      free(w->states);
    }
  }
  if (run->sync_ready) {
    pthread_mutex_destroy(&run->mu);
    pthread_cond_destroy(&run->not_empty);
    pthread_cond_destroy(&run->not_full);
  }
  pom_doe_results_close(run->res, NULL);
  pom_doe_mpi_destroy(run->mpi);
  free(run->workers);
  free(run->threads);
  free(run->queue);
  free(run->batch);
  free(run->sorted);
  free(run->rows);
  free(run->todo);
  free(run->cells);
  free(run);
}

pom_status pom_doe_run_all(const pom_doe_study *study, const pom_doe_run_options *opt,
                           pom_doe_report **report, pom_error *err) {
  pom_doe_run *run = NULL;
  POM_TRY(pom_doe_run_begin(&run, study, opt, err));
  int finished = 0;
  pom_status st = POM_OK;
  while (!finished && st == POM_OK)
    st = pom_doe_run_step(run, &finished, err);
  if (st == POM_OK) st = pom_doe_run_end(run, report, err);
  pom_doe_run_destroy(run);
  return st;
}
