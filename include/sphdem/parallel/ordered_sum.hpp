#pragma once
// Reproducible sums over ranks. MPI_SUM adds in an order that depends on the
// rank count (and floating-point addition is not associative), so a sum such
// as the mean pressure on a piston face would differ in its last bits
// between a 1-rank and an N-rank run, and the difference would grow through
// the wall controller. Here every rank contributes its terms tagged with a
// global order (a global id); all terms are gathered and added in that
// order, so the result is bitwise the same at every rank count.
#include <cstdint>
#include <vector>

#include "sphdem/parallel/comm.hpp"

namespace sphdem {

struct OrderedTerm {
  std::int64_t order = 0;  // position in the sum, unique over all ranks (a global id)
  std::int64_t key = 0;    // which sum the term belongs to, in [0, keys)
  double value = 0;
};

struct KeySum {
  double sum = 0;
  std::int64_t count = 0;
};

// Collective (MPI_Allgatherv): every rank's terms, on every rank, sorted
// by (order, key): the same list at any rank count.
// With `capacity` (terms per rank, the same on every rank; a caller that
// gathers every step keeps it between calls, starting at 0): one
// MPI_Allgather of blocks that size with their counts, instead of a count
// gather and an Allgatherv, while no rank has more terms; when one has,
// every rank sees it, gathers again as above and raises the capacity to
// the largest count and a quarter. The same list either way.
std::vector<OrderedTerm> gather_terms(const Comm& comm, const std::vector<OrderedTerm>& terms,
                                      std::size_t* capacity = nullptr);

// Collective: per key, the sum of its terms over all ranks in increasing
// `order`, and how many there were (gather_terms, `capacity` as there).
// Every rank gets the same result. Meant for small sets (a few thousand
// terms per step).
std::vector<KeySum> ordered_sums(const Comm& comm, const std::vector<OrderedTerm>& terms,
                                 std::size_t keys, std::size_t* capacity = nullptr);

}  // namespace sphdem
