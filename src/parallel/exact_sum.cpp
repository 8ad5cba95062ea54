#include "sphdem/parallel/exact_sum.hpp"

#include <vector>

namespace sphdem {

// Gathers every rank's integers and adds them; MPI has no 128-bit sum. The
// messages are a few integers per rank.
void exact_sum(const Comm& comm, std::span<Int128> values) {
  if (comm.size() == 1 || values.empty()) return;
  const int bytes = static_cast<int>(values.size_bytes());
  std::vector<Int128> all(values.size() * static_cast<std::size_t>(comm.size()));
  MPI_Allgather(values.data(), bytes, MPI_BYTE, all.data(), bytes, MPI_BYTE, comm.raw());
  for (std::size_t k = 0; k < values.size(); ++k) {
    Int128 s = 0;
    for (int r = 0; r < comm.size(); ++r) s += all[static_cast<std::size_t>(r) * values.size() + k];
    values[k] = s;
  }
}

void max_over_ranks(const Comm& comm, std::span<double> values) {
  if (comm.size() == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_MAX,
                comm.raw());
}

}  // namespace sphdem
