// Requests and replies between chosen ranks (record_route.hpp).
#include "sphdem/parallel/record_route.hpp"

#include <stdexcept>

#include "exchange.hpp"

namespace sphdem {

RecordRoute::RecordRoute(const Comm& comm, const void* records, std::size_t n,
                         std::size_t record_bytes, const std::vector<int>& dest)
    : comm_(comm) {
  if (dest.size() != n) throw std::invalid_argument("sphdem: RecordRoute: one rank per record");
  const auto p = static_cast<std::size_t>(comm.size());
  send_counts_.assign(p, 0);
  for (const int r : dest) {
    if (r < 0 || static_cast<std::size_t>(r) >= p)
      throw std::out_of_range("sphdem: RecordRoute: no such rank");
    ++send_counts_[static_cast<std::size_t>(r)];
  }
  // Records grouped by destination, each group in the given order.
  std::vector<std::size_t> next(p + 1, 0);
  for (std::size_t r = 0; r < p; ++r)
    next[r + 1] = next[r] + static_cast<std::size_t>(send_counts_[r]);
  order_.resize(n);
  for (std::size_t k = 0; k < n; ++k) order_[next[static_cast<std::size_t>(dest[k])]++] = k;
  std::vector<char> out(n * record_bytes);
  const char* in = static_cast<const char*>(records);
  for (std::size_t s = 0; s < n; ++s)
    std::memcpy(out.data() + s * record_bytes, in + order_[s] * record_bytes, record_bytes);
  recv_counts_ = detail::transpose_counts(comm.raw(), send_counts_);
  const detail::Route send = detail::route_from_counts(send_counts_);
  const detail::Route recv = detail::route_from_counts(recv_counts_);
  received_ = recv.total();
  data_.resize(received_ * record_bytes);
  detail::exchange(comm.raw(), send, out.data(), recv, data_.data(), MPI_BYTE, record_bytes);
}

std::vector<char> RecordRoute::reply(const void* answers, std::size_t answer_bytes) const {
  // The way back: what arrived from rank r returns to r, in the same order.
  const detail::Route send = detail::route_from_counts(recv_counts_);
  const detail::Route recv = detail::route_from_counts(send_counts_);
  std::vector<char> back(order_.size() * answer_bytes);
  detail::exchange(comm_.raw(), send, answers, recv, back.data(), MPI_BYTE, answer_bytes);
  std::vector<char> out(back.size());
  for (std::size_t s = 0; s < order_.size(); ++s)
    std::memcpy(out.data() + order_[s] * answer_bytes, back.data() + s * answer_bytes,
                answer_bytes);
  return out;
}

}  // namespace sphdem
