#include "sphdem/parallel/agreement.hpp"

#include <cstdint>

namespace sphdem {

std::optional<RankFailure> first_failure(const Comm& comm,
                                         const std::optional<std::string>& error) {
  const std::int64_t first = comm.min(static_cast<std::int64_t>(error ? comm.rank() : comm.size()));
  if (first == comm.size()) return std::nullopt;
  RankFailure f;
  f.rank = static_cast<int>(first);
  if (f.rank == comm.rank()) f.message = *error;
  std::int64_t length = static_cast<std::int64_t>(f.message.size());
  MPI_Bcast(&length, 1, MPI_INT64_T, f.rank, comm.raw());
  f.message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(f.message.data(), static_cast<int>(length), MPI_CHAR, f.rank, comm.raw());
  return f;
}

}  // namespace sphdem
