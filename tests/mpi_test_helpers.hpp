#pragma once
// Shared by the rank-independence tests: gather per-particle rows to rank 0
// in global-id order, compare them bit for bit, and let the other ranks
// wait for rank 0's serial reference without spinning (ctest runs them
// with more ranks than cores).
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <numeric>
#include <thread>
#include <vector>

#include "sphdem/parallel/comm.hpp"

namespace sphdem::testing_mpi {

// Rows (trivially copyable, with an int64 `gid`) of every rank, on rank 0,
// sorted by gid; empty on the other ranks.
template <class Row>
std::vector<Row> gather_rows(const Comm& comm, const std::vector<Row>& mine) {
  const int bytes = static_cast<int>(mine.size() * sizeof(Row));
  std::vector<int> counts(static_cast<std::size_t>(comm.size())), displs(counts.size(), 0);
  MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm.raw());
  std::partial_sum(counts.begin(), counts.end() - 1, displs.begin() + 1);
  std::vector<Row> all(
      comm.root() ? static_cast<std::size_t>(displs.back() + counts.back()) / sizeof(Row) : 0);
  MPI_Gatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, 0,
              comm.raw());
  std::sort(all.begin(), all.end(), [](const Row& a, const Row& b) { return a.gid < b.gid; });
  return all;
}

// Rows of a and b (both in gid order) whose gid or values differ in any
// bit, plus the rows one side has and the other lacks.
template <class Row>
std::size_t bitwise_mismatches(const std::vector<Row>& a, const std::vector<Row>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  std::size_t bad = std::max(a.size(), b.size()) - n;
  for (std::size_t i = 0; i < n; ++i)
    if (a[i].gid != b[i].gid || std::memcmp(&a[i].value, &b[i].value, sizeof a[i].value) != 0)
      ++bad;
  return bad;
}

inline void wait_for_root(const Comm& comm) {
  MPI_Request req;
  MPI_Ibarrier(comm.raw(), &req);
  int done = 0;
  while (!done) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

}  // namespace sphdem::testing_mpi
