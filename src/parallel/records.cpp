// route_records (records.hpp): one count transpose, then the exchange of
// migration and halo (exchange.hpp).
#include "sphdem/parallel/records.hpp"

#include <algorithm>
#include <numeric>

#include "exchange.hpp"

namespace sphdem {

std::vector<std::int64_t> route_records(const Comm& comm, const std::vector<int>& dest,
                                        const std::vector<std::int64_t>& records,
                                        std::size_t width) {
  const auto ranks = static_cast<std::size_t>(comm.size());
  std::vector<std::int64_t> send_counts(ranks, 0);
  for (int d : dest) ++send_counts[static_cast<std::size_t>(d)];
  // Grouped by destination, each group in its listed order.
  std::vector<std::size_t> order(dest.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&dest](std::size_t a, std::size_t b) { return dest[a] < dest[b]; });
  std::vector<std::int64_t> send;
  send.reserve(records.size());
  for (std::size_t r : order)
    send.insert(send.end(), records.begin() + static_cast<std::ptrdiff_t>(r * width),
                records.begin() + static_cast<std::ptrdiff_t>((r + 1) * width));
  const std::vector<std::int64_t> recv_counts = detail::transpose_counts(comm.raw(), send_counts);
  const detail::Route to = detail::route_from_counts(send_counts);
  const detail::Route from = detail::route_from_counts(recv_counts);
  std::vector<std::int64_t> recv(from.total() * width);
  detail::exchange(comm.raw(), to, send.data(), from, recv.data(), MPI_INT64_T, width);
  return recv;
}

}  // namespace sphdem
