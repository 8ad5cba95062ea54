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

// Collective (MPI_Allgatherv): per key, the sum of its terms over all ranks
// in increasing `order`, and how many there were. Every rank gets the same
// result. Meant for small sets (a few thousand terms per step).
// Collective (MPI_Allgatherv): every rank's terms, on every rank, sorted
// by (order, key): the same list at any rank count.
std::vector<OrderedTerm> gather_terms(const Comm& comm, const std::vector<OrderedTerm>& terms);

std::vector<KeySum> ordered_sums(const Comm& comm, const std::vector<OrderedTerm>& terms,
                                 std::size_t keys);

}  // namespace sphdem
