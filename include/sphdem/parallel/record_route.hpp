#pragma once
// Records sent to chosen ranks, and one answer per record sent back: a
// request and its reply. The "owner computes" pattern of the fiber pieces
// (src/solver/fiber_homes.hpp): each rank sends what it holds of a fiber
// to the fiber's home rank, the home computes and answers. Point to point
// (counts by MPI_Alltoall, records by nonblocking pairs): a rank holds only
// what it sends and what is sent to it, never a global array.
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "sphdem/parallel/comm.hpp"

namespace sphdem {

class RecordRoute {
 public:
  // Collective. Record k (`record_bytes` bytes at records + k * record_bytes)
  // goes to rank dest[k], 0 <= dest[k] < comm.size().
  RecordRoute(const Comm& comm, const void* records, std::size_t n, std::size_t record_bytes,
              const std::vector<int>& dest);

  // The records that arrived, by source rank, then in the order sent.
  std::size_t received() const { return received_; }
  const std::vector<char>& data() const { return data_; }

  // Collective. One answer (`answer_bytes` each) per received record, in
  // the order of data(); returns the answers to this rank's records, in the
  // order they were given to the constructor.
  std::vector<char> reply(const void* answers, std::size_t answer_bytes) const;

 private:
  Comm comm_;
  std::vector<std::int64_t> send_counts_, recv_counts_;  // per rank
  std::vector<std::size_t> order_;  // position in the send buffer -> record index
  std::size_t received_ = 0;
  std::vector<char> data_;
};

// Typed wrappers for trivially copyable records.
template <class T>
RecordRoute route_records(const Comm& comm, const std::vector<T>& records,
                          const std::vector<int>& dest) {
  static_assert(std::is_trivially_copyable_v<T>);
  return RecordRoute(comm, records.data(), records.size(), sizeof(T), dest);
}

template <class T>
std::vector<T> received_records(const RecordRoute& route) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<T> out(route.data().size() / sizeof(T));
  if (!out.empty())
    std::memcpy(static_cast<void*>(out.data()), route.data().data(), route.data().size());
  return out;
}

template <class T>
std::vector<T> reply_records(const RecordRoute& route, const std::vector<T>& answers) {
  static_assert(std::is_trivially_copyable_v<T>);
  const std::vector<char> bytes = route.reply(answers.data(), sizeof(T));
  std::vector<T> out(bytes.size() / sizeof(T));
  if (!out.empty()) std::memcpy(static_cast<void*>(out.data()), bytes.data(), bytes.size());
  return out;
}

}  // namespace sphdem
