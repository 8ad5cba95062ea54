// Counts the MPI calls a run makes and the wall time spent inside them,
// per rank, through the MPI profiling interface (PMPI): built as a shared
// library and preloaded, it needs no change to sphdem.
//   mpicc -O2 -shared -fPIC -o build/mpi_calls.so tools/mpi_calls.c
//   mpirun -n 2 -x LD_PRELOAD=$PWD/build/mpi_calls.so build/release/sphdem run ...
// At MPI_Finalize each rank prints one line per call kind to stderr:
// "mpi_calls rank R NAME COUNT SECONDS". A synchronisation is a collective
// or a MPI_Waitall (one per point-to-point exchange).
#include <mpi.h>
#include <stdio.h>

enum { kAllreduce, kAllgather, kAllgatherv, kAlltoall, kWaitall, kIsend, kIrecv, kBarrier, kBcast, kN };
static const char* kNames[kN] = {"MPI_Allreduce", "MPI_Allgather", "MPI_Allgatherv",
                                 "MPI_Alltoall",  "MPI_Waitall",   "MPI_Isend",
                                 "MPI_Irecv",     "MPI_Barrier",   "MPI_Bcast"};
static long counts[kN];
static double seconds[kN];

#define TIMED(k, call)              \
  do {                              \
    const double t0 = PMPI_Wtime(); \
    const int rc = call;            \
    seconds[k] += PMPI_Wtime() - t0; \
    ++counts[k];                    \
    return rc;                      \
  } while (0)

int MPI_Allreduce(const void* s, void* r, int n, MPI_Datatype t, MPI_Op op, MPI_Comm c) {
  TIMED(kAllreduce, PMPI_Allreduce(s, r, n, t, op, c));
}
int MPI_Allgather(const void* s, int sn, MPI_Datatype st, void* r, int rn, MPI_Datatype rt,
                  MPI_Comm c) {
  TIMED(kAllgather, PMPI_Allgather(s, sn, st, r, rn, rt, c));
}
int MPI_Allgatherv(const void* s, int sn, MPI_Datatype st, void* r, const int* rn, const int* d,
                   MPI_Datatype rt, MPI_Comm c) {
  TIMED(kAllgatherv, PMPI_Allgatherv(s, sn, st, r, rn, d, rt, c));
}
int MPI_Alltoall(const void* s, int sn, MPI_Datatype st, void* r, int rn, MPI_Datatype rt,
                 MPI_Comm c) {
  TIMED(kAlltoall, PMPI_Alltoall(s, sn, st, r, rn, rt, c));
}
int MPI_Waitall(int n, MPI_Request* q, MPI_Status* s) { TIMED(kWaitall, PMPI_Waitall(n, q, s)); }
int MPI_Isend(const void* b, int n, MPI_Datatype t, int d, int tag, MPI_Comm c, MPI_Request* q) {
  TIMED(kIsend, PMPI_Isend(b, n, t, d, tag, c, q));
}
int MPI_Irecv(void* b, int n, MPI_Datatype t, int s, int tag, MPI_Comm c, MPI_Request* q) {
  TIMED(kIrecv, PMPI_Irecv(b, n, t, s, tag, c, q));
}
int MPI_Barrier(MPI_Comm c) { TIMED(kBarrier, PMPI_Barrier(c)); }
int MPI_Bcast(void* b, int n, MPI_Datatype t, int root, MPI_Comm c) {
  TIMED(kBcast, PMPI_Bcast(b, n, t, root, c));
}

int MPI_Finalize(void) {
  int rank = 0;
  PMPI_Comm_rank(MPI_COMM_WORLD, &rank);
  for (int k = 0; k < kN; ++k)
    if (counts[k] > 0)
      fprintf(stderr, "mpi_calls rank %d %s %ld %.3f\n", rank, kNames[k], counts[k], seconds[k]);
  return PMPI_Finalize();
}
