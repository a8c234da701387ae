/* pom_doe_mpi.c - units over MPI ranks, rows gathered at rank 0
 * (docs/results.md, "Execution"). Point-to-point messages only, from the
 * driving thread of each rank (MPI_THREAD_FUNNELED). */
#define _POSIX_C_SOURCE 200809L
#include "pom_doe_mpi.h"

#include <mpi.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { TAG_DATA = 4711, TAG_FIN = 4712, TAG_STOP = 4713 };

/* Root's pause when its own workers are done and no message is waiting, so
 * it does not spin on a core the other ranks need (s). */
#define ROOT_IDLE_S 0.01

struct pom_doe_mpi {
  MPI_Comm comm; /* private duplicate of MPI_COMM_WORLD */
  int rank, size;
  int local_size; /* ranks on this machine */
  int stop_requested;
  /* root */
  int *fin;       /* [size] 1 once rank r said it is done */
  int *stop_sent; /* [size] 1 once rank r was told to stop */
  int n_fin;
  char *buf; /* receive buffer */
  size_t cap;
  /* other ranks */
  int fin_sent;
  int got_stop;
};

static pom_status mpi_fail(pom_error *err, int code, const char *what) {
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  if (MPI_Error_string(code, text, &len) != MPI_SUCCESS) snprintf(text, sizeof text, "?");
  return pom_error_set(err, POM_ERR_MPI, __FILE__, __LINE__, "%s: %s", what, text);
}

#define MPI_TRY(call, what)                                                                        \
  do {                                                                                             \
    int rc_ = (call);                                                                              \
    if (rc_ != MPI_SUCCESS) return mpi_fail(err, rc_, (what));                                     \
  } while (0)

pom_status pom_doe_mpi_create(pom_doe_mpi **out, pom_error *err) {
  int init = 0;
  *out = NULL;
  MPI_Initialized(&init);
  if (!init) POM_FAIL(err, POM_ERR_MPI, "MPI is not initialized (the program must call MPI_Init)");
  pom_doe_mpi *mpi = calloc(1, sizeof *mpi);
  if (!mpi) POM_FAIL(err, POM_ERR_NOMEM, "MPI: out of memory");
  mpi->comm = MPI_COMM_NULL;
  *out = mpi;
  MPI_TRY(MPI_Comm_dup(MPI_COMM_WORLD, &mpi->comm), "MPI_Comm_dup");
  /* errors come back as codes, never abort the job from inside the library */
  MPI_TRY(MPI_Comm_set_errhandler(mpi->comm, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
  MPI_TRY(MPI_Comm_rank(mpi->comm, &mpi->rank), "MPI_Comm_rank");
  MPI_TRY(MPI_Comm_size(mpi->comm, &mpi->size), "MPI_Comm_size");
  MPI_Comm local;
  MPI_TRY(MPI_Comm_split_type(mpi->comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local),
          "MPI_Comm_split_type");
  MPI_Comm_size(local, &mpi->local_size);
  MPI_Comm_free(&local);
  mpi->fin = calloc((size_t)mpi->size, sizeof *mpi->fin);
  mpi->stop_sent = calloc((size_t)mpi->size, sizeof *mpi->stop_sent);
  if (!mpi->fin || !mpi->stop_sent) POM_FAIL(err, POM_ERR_NOMEM, "MPI: out of memory");
  return POM_OK;
}

void pom_doe_mpi_destroy(pom_doe_mpi *mpi) {
  if (!mpi) return;
  if (mpi->comm != MPI_COMM_NULL) MPI_Comm_free(&mpi->comm);
  free(mpi->fin);
  free(mpi->stop_sent);
  free(mpi->buf);
  free(mpi);
}

int pom_doe_mpi_rank(const pom_doe_mpi *mpi) {
  return mpi->rank;
}
int pom_doe_mpi_size(const pom_doe_mpi *mpi) {
  return mpi->size;
}
int pom_doe_mpi_local_size(const pom_doe_mpi *mpi) {
  return mpi->local_size > 0 ? mpi->local_size : 1;
}

pom_status pom_doe_mpi_share_start(pom_doe_mpi *mpi, pom_status *st, pom_doe_cell *cells,
                                   long total, pom_error *err) {
  int s = (int)*st;
  MPI_TRY(MPI_Bcast(&s, 1, MPI_INT, 0, mpi->comm), "sharing the start status");
  if (s != POM_OK) {
    if (mpi->rank != 0)
      pom_error_set(err, (pom_status)s, __FILE__, __LINE__, "rank 0 could not start the study");
    *st = (pom_status)s;
    return POM_OK;
  }
  signed char *done = malloc((size_t)total);
  if (!done) POM_FAIL(err, POM_ERR_NOMEM, "MPI: out of memory");
  if (mpi->rank == 0)
    for (long u = 0; u < total; ++u)
      done[u] = (signed char)cells[u].done;
  int rc = MPI_SUCCESS;
  /* in pieces: MPI counts are int */
  for (long off = 0; off < total && rc == MPI_SUCCESS; off += 1L << 30) {
    long n = total - off < (1L << 30) ? total - off : (1L << 30);
    rc = MPI_Bcast(done + off, (int)n, MPI_SIGNED_CHAR, 0, mpi->comm);
  }
  if (rc == MPI_SUCCESS && mpi->rank != 0)
    for (long u = 0; u < total; ++u)
      cells[u].done = (int8_t)done[u];
  free(done);
  if (rc != MPI_SUCCESS) return mpi_fail(err, rc, "sharing the finished maneuvers");
  return POM_OK;
}

static pom_status root_receive(pom_doe_mpi *mpi, size_t item_size,
                               pom_status (*store)(struct pom_doe_run *, const void *, int,
                                                   pom_error *),
                               struct pom_doe_run *run, int *received, pom_error *err) {
  for (;;) {
    int flag = 0;
    MPI_Status status;
    MPI_TRY(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, mpi->comm, &flag, &status), "MPI_Iprobe");
    if (!flag) return POM_OK;
    *received = 1;
    int src = status.MPI_SOURCE;
    if (status.MPI_TAG == TAG_FIN) {
      MPI_TRY(MPI_Recv(NULL, 0, MPI_BYTE, src, TAG_FIN, mpi->comm, MPI_STATUS_IGNORE),
              "receiving a final message");
      if (!mpi->fin[src]) ++mpi->n_fin;
      mpi->fin[src] = 1;
      continue;
    }
    if (status.MPI_TAG != TAG_DATA)
      POM_FAIL(err, POM_ERR_MPI, "unexpected MPI message tag %d from rank %d", status.MPI_TAG, src);
    int bytes = 0;
    MPI_TRY(MPI_Get_count(&status, MPI_BYTE, &bytes), "MPI_Get_count");
    if ((size_t)bytes > mpi->cap) {
      char *b = realloc(mpi->buf, (size_t)bytes);
      if (!b) POM_FAIL(err, POM_ERR_NOMEM, "MPI: out of memory");
      mpi->buf = b;
      mpi->cap = (size_t)bytes;
    }
    MPI_TRY(MPI_Recv(mpi->buf, bytes, MPI_BYTE, src, TAG_DATA, mpi->comm, MPI_STATUS_IGNORE),
            "receiving results");
    if ((size_t)bytes % item_size != 0)
      POM_FAIL(err, POM_ERR_MPI, "rank %d sent %d bytes, not a whole number of rows", src, bytes);
    POM_TRY(store(run, mpi->buf, (int)((size_t)bytes / item_size), err));
  }
}

pom_status
pom_doe_mpi_exchange(pom_doe_mpi *mpi, const void *units, int n, size_t item_size,
                     int local_finished,
                     pom_status (*store)(struct pom_doe_run *, const void *, int, pom_error *),
                     struct pom_doe_run *run, int *cancel, int *finished, pom_error *err) {
  *cancel = 0;
  if (mpi->rank != 0) {
    if (n > 0)
      MPI_TRY(MPI_Send(units, (int)((size_t)n * item_size), MPI_BYTE, 0, TAG_DATA, mpi->comm),
              "sending results to rank 0");
    int flag = 0;
    MPI_TRY(MPI_Iprobe(0, TAG_STOP, mpi->comm, &flag, MPI_STATUS_IGNORE), "MPI_Iprobe");
    if (flag) {
      MPI_TRY(MPI_Recv(NULL, 0, MPI_BYTE, 0, TAG_STOP, mpi->comm, MPI_STATUS_IGNORE),
              "receiving a stop request");
      mpi->got_stop = 1;
      *cancel = 1;
    }
    if (local_finished && !mpi->fin_sent) {
      MPI_TRY(MPI_Send(NULL, 0, MPI_BYTE, 0, TAG_FIN, mpi->comm), "sending the final message");
      mpi->fin_sent = 1;
    }
    *finished = local_finished;
    return POM_OK;
  }
  POM_TRY(store(run, units, n, err));
  int received = 0;
  POM_TRY(root_receive(mpi, item_size, store, run, &received, err));
  if (mpi->stop_requested)
    for (int r = 1; r < mpi->size; ++r)
      if (!mpi->fin[r] && !mpi->stop_sent[r]) {
        MPI_TRY(MPI_Send(NULL, 0, MPI_BYTE, r, TAG_STOP, mpi->comm), "sending a stop request");
        mpi->stop_sent[r] = 1;
      }
  *finished = local_finished && mpi->n_fin == mpi->size - 1;
  if (local_finished && !*finished && !received && n == 0) {
    struct timespec ts = {0, (long)(ROOT_IDLE_S * 1e9)};
    nanosleep(&ts, NULL);
  }
  return POM_OK;
}

void pom_doe_mpi_request_stop(pom_doe_mpi *mpi) {
  if (mpi) mpi->stop_requested = 1;
}

pom_status pom_doe_mpi_finish(pom_doe_mpi *mpi, pom_error *err) {
  /* a stop request may cross a rank's final message: the root says whom it
   * asked, and those ranks take the message before the barrier */
  MPI_TRY(MPI_Bcast(mpi->stop_sent, mpi->size, MPI_INT, 0, mpi->comm), "sharing stop requests");
  if (mpi->rank != 0 && mpi->stop_sent[mpi->rank] && !mpi->got_stop) {
    MPI_TRY(MPI_Recv(NULL, 0, MPI_BYTE, 0, TAG_STOP, mpi->comm, MPI_STATUS_IGNORE),
            "receiving a stop request");
    mpi->got_stop = 1;
  }
  MPI_TRY(MPI_Barrier(mpi->comm), "MPI_Barrier");
  return POM_OK;
}
