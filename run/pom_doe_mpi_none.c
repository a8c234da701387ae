/* pom_doe_mpi_none.c - the MPI layer of a build without POM_WITH_MPI: asking
 * for MPI is an error, everything else does nothing. */
#include "pom_doe_mpi.h"

pom_status pom_doe_mpi_create(pom_doe_mpi **out, pom_error *err) {
  *out = NULL;
  POM_FAIL(err, POM_ERR_MPI,
           "this pomlab was built without MPI (configure with -DPOM_WITH_MPI=ON)");
}

void pom_doe_mpi_destroy(pom_doe_mpi *mpi) {
  (void)mpi;
}
int pom_doe_mpi_rank(const pom_doe_mpi *mpi) {
  (void)mpi;
  return 0;
}
int pom_doe_mpi_size(const pom_doe_mpi *mpi) {
  (void)mpi;
  return 1;
}
int pom_doe_mpi_local_size(const pom_doe_mpi *mpi) {
  (void)mpi;
  return 1;
}

pom_status pom_doe_mpi_share_start(pom_doe_mpi *mpi, pom_status *st, pom_doe_cell *cells,
                                   long total, pom_error *err) {
  (void)mpi, (void)st, (void)cells, (void)total, (void)err;
  return POM_OK;
}

pom_status
pom_doe_mpi_exchange(pom_doe_mpi *mpi, const void *units, int n, size_t item_size,
                     int local_finished,
                     pom_status (*store)(struct pom_doe_run *, const void *, int, pom_error *),
                     struct pom_doe_run *run, int *cancel, int *finished, pom_error *err) {
  (void)mpi, (void)units, (void)n, (void)item_size, (void)store, (void)run, (void)cancel;
  *finished = local_finished;
  POM_FAIL(err, POM_ERR_MPI, "MPI exchange in a build without MPI");
}

void pom_doe_mpi_request_stop(pom_doe_mpi *mpi) {
  (void)mpi;
}

pom_status pom_doe_mpi_finish(pom_doe_mpi *mpi, pom_error *err) {
  (void)mpi, (void)err;
  return POM_OK;
}
