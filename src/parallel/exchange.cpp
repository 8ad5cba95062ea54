#include "exchange.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace sphdem::detail {

namespace {
constexpr int kTag = 7341;  // one tag: every exchange completes before the next starts
constexpr int kVoteTag = 7342;

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

namespace {

// Posts the receives and sends of one exchange into req from index r.
void post_exchange(MPI_Comm comm, const Route& send, const void* send_buf, const Route& recv,
                   void* recv_buf, MPI_Datatype base, std::size_t per,
                   std::vector<MPI_Request>& req, std::size_t& r) {
  int base_bytes = 0;
  MPI_Type_size(base, &base_bytes);
  const std::size_t bytes = per * static_cast<std::size_t>(base_bytes);
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
}

}  // namespace

void exchange(MPI_Comm comm, const Route& send, const void* send_buf, const Route& recv,
              void* recv_buf, MPI_Datatype base, std::size_t per) {
  if (send.ranks.empty() && recv.ranks.empty()) return;
  std::vector<MPI_Request> req(send.ranks.size() + recv.ranks.size());
  std::size_t r = 0;
  post_exchange(comm, send, send_buf, recv, recv_buf, base, per, req, r);
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
}

double exchange_max(MPI_Comm comm, const Route& send, const void* send_buf, const Route& recv,
                    void* recv_buf, MPI_Datatype base, std::size_t per, double vote) {
  int ranks = 1, me = 0;
  MPI_Comm_size(comm, &ranks);
  MPI_Comm_rank(comm, &me);
  if (ranks > kVoteMessageRanks) {
    exchange(comm, send, send_buf, recv, recv_buf, base, per);
    double out = vote;
    MPI_Allreduce(&vote, &out, 1, MPI_DOUBLE, MPI_MAX, comm);
    return out;
  }
  std::vector<double> votes(static_cast<std::size_t>(ranks), vote);  // by rank
  std::vector<MPI_Request> req(send.ranks.size() + recv.ranks.size() + 2 * (votes.size() - 1));
  std::size_t r = 0;
  post_exchange(comm, send, send_buf, recv, recv_buf, base, per, req, r);
  for (int other = 0; other < ranks; ++other) {
    if (other == me) continue;
    MPI_Irecv(&votes[static_cast<std::size_t>(other)], 1, MPI_DOUBLE, other, kVoteTag, comm,
              &req[r++]);
    MPI_Isend(&vote, 1, MPI_DOUBLE, other, kVoteTag, comm, &req[r++]);
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  // In rank order, a NaN kept: every rank folds the same list the same way.
  double out = votes.front();
  for (const double v : votes)
    if (v > out || std::isnan(v)) out = v;
  return out;
}

}  // namespace sphdem::detail
