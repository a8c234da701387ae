/* pom_doe_mpi.h - how the runner spreads units over MPI ranks (internal).
 * Rank r computes the units of maneuvers k with k % size == r; the root (rank 0) stores
 * every rank's results, so the results file is the one a single process
 * writes. Only the driving thread of each rank calls MPI (thread level
 * MPI_THREAD_FUNNELED). Built without POM_WITH_MPI, create fails with
 * POM_ERR_MPI and the other functions do nothing. */
#ifndef POM_DOE_MPI_H
#define POM_DOE_MPI_H

#include "pom_rows.h"
#include "run_internal.h"

typedef struct pom_doe_mpi pom_doe_mpi;

/* Needs MPI initialized by the program (MPI_Init_thread). */
pom_status pom_doe_mpi_create(pom_doe_mpi **out, pom_error *err);
void pom_doe_mpi_destroy(pom_doe_mpi *mpi);
int pom_doe_mpi_rank(const pom_doe_mpi *mpi);
int pom_doe_mpi_size(const pom_doe_mpi *mpi);
/* Ranks sharing this machine (to divide its cores). */
int pom_doe_mpi_local_size(const pom_doe_mpi *mpi);

/* Root's start status to all ranks (*st in/out) and, when ok, the `done`
 * flags of cells[0..total) (what a resumed file already holds). */
pom_status pom_doe_mpi_share_start(pom_doe_mpi *mpi, pom_status *st, pom_doe_cell *cells,
                                   long total, pom_error *err);

/* One exchange: non-root ranks send their n finished units (item_size bytes
 * each) and, once local_finished, a final message; the root stores its own
 * and every received unit with store and sends pending stop requests.
 * *cancel is set on a rank told to stop; *finished once every rank is done
 * (root) or this rank is done (others). */
pom_status
pom_doe_mpi_exchange(pom_doe_mpi *mpi, const void *units, int n, size_t item_size,
                     int local_finished,
                     pom_status (*store)(struct pom_doe_run *, const void *, int, pom_error *),
                     struct pom_doe_run *run, int *cancel, int *finished, pom_error *err);

/* Asks every rank to stop (root: sent at the next exchange). */
void pom_doe_mpi_request_stop(pom_doe_mpi *mpi);

/* Collective end of a run: consumes stop messages still in flight. */
pom_status pom_doe_mpi_finish(pom_doe_mpi *mpi, pom_error *err);

#endif
