#include "exchange.hpp"

#include <limits>
#include <stdexcept>

namespace sphdem::detail {

namespace {
constexpr int kTag = 7341;  // one tag: every exchange completes before the next starts

int as_count(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("sphdem: an MPI message exceeds 2^31 elements");
  return static_cast<int>(n);
}
}  // namespace

Route route_from_counts(const std::vector<std::int64_t>& counts) {
  Route r;
  for (std::size_t rank = 0; rank < counts.size(); ++rank) {
    if (counts[rank] == 0) continue;
    r.ranks.push_back(static_cast<int>(rank));
    r.offsets.push_back(r.offsets.back() + static_cast<std::size_t>(counts[rank]));
  }
  return r;
}

std::vector<std::int64_t> transpose_counts(MPI_Comm comm, const std::vector<std::int64_t>& send) {
  std::vector<std::int64_t> recv(send.size(), 0);
  MPI_Alltoall(send.data(), 1, MPI_INT64_T, recv.data(), 1, MPI_INT64_T, comm);
  return recv;
}

void exchange(MPI_Comm comm, const Route& send, const void* send_buf, const Route& recv,
              void* recv_buf, MPI_Datatype base, std::size_t per) {
  if (send.ranks.empty() && recv.ranks.empty()) return;
  int base_bytes = 0;
  MPI_Type_size(base, &base_bytes);
  const std::size_t bytes = per * static_cast<std::size_t>(base_bytes);
  std::vector<MPI_Request> req(send.ranks.size() + recv.ranks.size());
  std::size_t r = 0;
  for (std::size_t k = 0; k < recv.ranks.size(); ++k) {
    char* at = static_cast<char*>(recv_buf) + recv.offsets[k] * bytes;
    MPI_Irecv(at, as_count((recv.offsets[k + 1] - recv.offsets[k]) * per), base, recv.ranks[k],
              kTag, comm, &req[r++]);
  }
  for (std::size_t k = 0; k < send.ranks.size(); ++k) {
    const char* at = static_cast<const char*>(send_buf) + send.offsets[k] * bytes;
    MPI_Isend(at, as_count((send.offsets[k + 1] - send.offsets[k]) * per), base, send.ranks[k],
              kTag, comm, &req[r++]);
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
}

}  // namespace sphdem::detail
