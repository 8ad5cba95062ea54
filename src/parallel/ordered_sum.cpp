#include "sphdem/parallel/ordered_sum.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace sphdem {

std::vector<OrderedTerm> gather_terms(const Comm& comm, const std::vector<OrderedTerm>& terms) {
  static_assert(sizeof(OrderedTerm) == 24, "OrderedTerm travels as raw bytes");
  const int n_ranks = comm.size();
  const int bytes = static_cast<int>(terms.size() * sizeof(OrderedTerm));
  std::vector<int> counts(static_cast<std::size_t>(n_ranks)), displs(counts.size(), 0);
  MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm.raw());
  std::partial_sum(counts.begin(), counts.end() - 1, displs.begin() + 1);
  std::vector<OrderedTerm> all(static_cast<std::size_t>(displs.back() + counts.back()) /
                               sizeof(OrderedTerm));
  MPI_Allgatherv(terms.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE,
                 comm.raw());
  std::sort(all.begin(), all.end(), [](const OrderedTerm& a, const OrderedTerm& b) {
    return a.order != b.order ? a.order < b.order : a.key < b.key;
  });
  return all;
}

std::vector<KeySum> ordered_sums(const Comm& comm, const std::vector<OrderedTerm>& terms,
                                 std::size_t keys) {
  const std::vector<OrderedTerm> all = gather_terms(comm, terms);
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
