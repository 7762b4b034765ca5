/* The sweep under MPI (mpirun -np N voussoir sweep ...): rank 0 hands the cases out one at a time
 * to the ranks that ask for work and takes their rows as they come; the other ranks run the
 * cases in their own process. A case's row depends only on the case, so the summary is the one
 * a single process writes. In the MPI plugin (libvoussoir-mpi, mpi_plugin.h), built only when
 * CMake finds MPI. */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include <mpi.h>
#include <string.h>
#include <time.h>

#include "sweep_mpi.h"

enum { TAG_ROW = 11, TAG_WORK = 12 };

int vs_sweep_mpi_begin(int *size) {
  int rank = 0;
  MPI_Init(NULL, NULL);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, size);
  return rank;
}

void vs_sweep_mpi_end(void) { MPI_Finalize(); }

/* Receive the next row. Open MPI busy-polls in a blocking receive, which would take a core from
 * the workers on a machine with as many ranks as cores: test, and yield for 1 ms between tests
 * (a case takes far longer). */
static void wait_row(vs_sweep_row *r, MPI_Status *st) {
  MPI_Request req;
  MPI_Irecv(r, (int)sizeof *r, MPI_BYTE, MPI_ANY_SOURCE, TAG_ROW, MPI_COMM_WORLD, &req);
  const struct timespec pause = {0, 1000000};
  for (int done = 0;;) {
    MPI_Test(&req, &done, st);
    if (done) return;
    nanosleep(&pause, NULL);
  }
}

/* Every message from a worker is a row (run 0: "ready"); the reply is its next run, or 0: stop. */
void vs_sweep_mpi_serve(const vs_sweep_server *s, int size) {
  int stopped = 0, more = 1;
  while (stopped < size - 1) {
    vs_sweep_row r;
    MPI_Status st;
    wait_row(&r, &st);
    if (r.run > 0) s->take(s->user, &r);
    int work = more ? s->next(s->user) : 0;
    if (work <= 0) {
      more = 0;
      work = 0;
      stopped++;
    }
    MPI_Send(&work, 1, MPI_INT, st.MPI_SOURCE, TAG_WORK, MPI_COMM_WORLD);
  }
}

void vs_sweep_mpi_work(const void *job, vs_sweep_case_fn run_case,
                       const volatile sig_atomic_t *stop, int *h5_clean) {
  vs_sweep_row r;
  memset(&r, 0, sizeof r);
  for (;;) {
    MPI_Send(&r, (int)sizeof r, MPI_BYTE, 0, TAG_ROW, MPI_COMM_WORLD);
    int run = 0;
    MPI_Recv(&run, 1, MPI_INT, 0, TAG_WORK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (run <= 0) return;
    run_case(job, run, stop, &r, h5_clean);
  }
}
