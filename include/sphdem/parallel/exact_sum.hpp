#pragma once
// The collective half of the exact sums of sphdem/core/exact_sum.hpp.
#include <span>

#include "sphdem/core/exact_sum.hpp"
#include "sphdem/parallel/comm.hpp"

namespace sphdem {

// Collective: every element replaced by its sum over the ranks. The integer
// sum is exact, so its value does not depend on the order of the ranks.
void exact_sum(const Comm& comm, std::span<Int128> values);

// Collective: every element replaced by its maximum over the ranks.
void max_over_ranks(const Comm& comm, std::span<double> values);

}  // namespace sphdem
