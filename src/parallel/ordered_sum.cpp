#include "sphdem/parallel/ordered_sum.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace sphdem {

namespace {

void sort_terms(std::vector<OrderedTerm>& all) {
  std::sort(all.begin(), all.end(), [](const OrderedTerm& a, const OrderedTerm& b) {
    return a.order != b.order ? a.order < b.order : a.key < b.key;
  });
}

// One Allgather of [count, `capacity` terms] per rank; false (and the
// capacity raised, the same on every rank) when some rank has more.
bool gather_blocks(const Comm& comm, const std::vector<OrderedTerm>& terms, std::size_t& capacity,
                   std::vector<OrderedTerm>& all) {
  const std::size_t block = capacity + 1;
  std::vector<OrderedTerm> mine(block);
  mine[0].order = static_cast<std::int64_t>(terms.size());
  std::copy_n(terms.begin(), std::min(terms.size(), capacity), mine.begin() + 1);
  std::vector<OrderedTerm> blocks(block * static_cast<std::size_t>(comm.size()));
  const int bytes = static_cast<int>(block * sizeof(OrderedTerm));
  MPI_Allgather(mine.data(), bytes, MPI_BYTE, blocks.data(), bytes, MPI_BYTE, comm.raw());
  std::size_t largest = 0;
  for (std::size_t at = 0; at < blocks.size(); at += block)
    largest = std::max(largest, static_cast<std::size_t>(blocks[at].order));
  if (largest > capacity) {
    capacity = largest + largest / 4;
    return false;
  }
  all.clear();
  for (std::size_t at = 0; at < blocks.size(); at += block) {
    const auto first = blocks.begin() + static_cast<std::ptrdiff_t>(at + 1);
    all.insert(all.end(), first, first + blocks[at].order);
  }
  return true;
}

}  // namespace

std::vector<OrderedTerm> gather_terms(const Comm& comm, const std::vector<OrderedTerm>& terms,
                                      std::size_t* capacity) {
  static_assert(sizeof(OrderedTerm) == 24, "OrderedTerm travels as raw bytes");
  if (std::vector<OrderedTerm> all; capacity && gather_blocks(comm, terms, *capacity, all)) {
    sort_terms(all);
    return all;
  }
  const int n_ranks = comm.size();
  const int bytes = static_cast<int>(terms.size() * sizeof(OrderedTerm));
  std::vector<int> counts(static_cast<std::size_t>(n_ranks)), displs(counts.size(), 0);
  MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw());
  std::partial_sum(counts.begin(), counts.end() - 1, displs.begin() + 1);
  std::vector<OrderedTerm> all(static_cast<std::size_t>(displs.back() + counts.back()) /
                               sizeof(OrderedTerm));
  MPI_Allgatherv(terms.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE,
                 comm.raw());
  sort_terms(all);
  return all;
}

std::vector<KeySum> ordered_sums(const Comm& comm, const std::vector<OrderedTerm>& terms,
                                 std::size_t keys, std::size_t* capacity) {
  const std::vector<OrderedTerm> all = gather_terms(comm, terms, capacity);
  std::vector<KeySum> out(keys);
  for (const OrderedTerm& t : all) {
    if (t.key < 0 || static_cast<std::size_t>(t.key) >= keys)
      throw std::out_of_range("sphdem: ordered_sums: key out of range");
    KeySum& s = out[static_cast<std::size_t>(t.key)];
    s.sum += t.value;
    ++s.count;
  }
  return out;
}

}  // namespace sphdem
