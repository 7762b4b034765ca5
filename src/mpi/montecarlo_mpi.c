/* The montecarlo command under MPI (mpirun -np N voussoir montecarlo ...): rank 0 hands out the
 * samples one at a time to the ranks that ask for work and passes their results on (to the
 * study's journal and summary, src/study/montecarlo_cmd.c). A sample's result depends only on (case,
 * seed, sample), so the summary is the one a single process writes. In the MPI plugin
 * (libvoussoir-mpi, src/plugin/plugin.h), built only when CMake finds MPI. */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include "voussoir/montecarlo.h"
#include "montecarlo_mpi.h"

#include <mpi.h>
#include <time.h>
#include <string.h>

enum { TAG_RESULT = 1, TAG_WORK = 2 };

/* Receive the next result. Open MPI busy-polls in a blocking receive, which would take a core
 * from the workers on a machine with as many ranks as cores: test, and yield for 1 ms between
 * tests (a sample takes far longer). */
static void wait_result(vs_mc_sample *r, MPI_Status *st) {
  MPI_Request req;
  MPI_Irecv(r, (int)sizeof *r, MPI_BYTE, MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &req);
  const struct timespec pause = {0, 1000000};
  for (int done = 0;;) {
    MPI_Test(&req, &done, st);
    if (done) return;
    nanosleep(&pause, NULL);
  }
}

/* Rank 0: every message from a worker is a result (sample -1: "ready"); the reply is the next
 * sample, or -1 to stop. */
static void dispatch(const vs_mc_server *s, int more, int size) {
  int stopped = 0;
  while (stopped < size - 1) {
    vs_mc_sample r;
    MPI_Status st;
    wait_result(&r, &st);
    if (r.sample >= 0) s->take(s->user, &r);
    int work = more ? s->next(s->user) : -1;
    more = work >= 0;
    stopped += work < 0;
    MPI_Send(&work, 1, MPI_INT, st.MPI_SOURCE, TAG_WORK, MPI_COMM_WORLD);
  }
}

static void work(const vs_case *c) {
  vs_mc_sample r;
  memset(&r, 0, sizeof r);
  r.sample = -1;
  for (;;) {
    MPI_Send(&r, (int)sizeof r, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
    int s = -1;
    MPI_Recv(&s, 1, MPI_INT, 0, TAG_WORK, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (s < 0) return;
    vs_mc_run_sample(c, s, &r);
  }
}

int vs_mc_run_mpi(const vs_case *c, const vs_mc_server *s, int *opened, int *ranks) {
  int rank = 0, size = 1;
  MPI_Init(NULL, NULL);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  *ranks = size;
  if (rank == 0) *opened = s->open(s->user);
  if (rank != 0) {
    work(c);
  } else if (size > 1) {
    dispatch(s, *opened == 0, size);
  } else if (*opened == 0) {
    for (int k = s->next(s->user); k >= 0; k = s->next(s->user)) {
      vs_mc_sample r;
      vs_mc_run_sample(c, k, &r);
      s->take(s->user, &r);
    }
  }
  MPI_Finalize();
  return rank;
}
