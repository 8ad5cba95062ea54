#pragma once
// Doubles to integers without undefined behaviour: a cast of a double that
// is NaN or outside the integer's range is undefined (GCC's
// -fsanitize=undefined does not report it; x86 gives the lowest integer),
// and cell coordinates and counts come from positions (a runaway particle)
// and case-file values (an absurd extent). The double is clamped first,
// then cast; within the bounds the result is the plain cast's.
#include <fmt/format.h>

#include <cmath>
#include <concepts>
#include <cstdint>

#include "sphdem/core/errors.hpp"

namespace sphdem {

// floor(v) clamped into [lo, hi]; NaN gives lo. lo <= hi, and both well
// inside the integer's range (hi's double must not round up past it).
template <std::integral I>
I clamped_floor(double v, I lo, I hi) {
  const double f = std::floor(v);
  if (!(f > static_cast<double>(lo))) return lo;
  if (!(f < static_cast<double>(hi))) return hi;
  return static_cast<I>(f);
}

// The most sub-steps of one step: far beyond any run that can finish.
inline constexpr std::int64_t kMaxSubsteps = std::int64_t{1} << 31;

// ceil(q) sub-steps, at least 1. Past kMaxSubsteps (a step ratio that
// overflowed, a NaN from a step of 0) the run cannot continue: a
// SimulationError naming `what`, not an out-of-range cast.
inline std::int64_t substep_count(double q, const char* what) {
  const double n = std::ceil(q);
  if (!(n <= static_cast<double>(kMaxSubsteps))) {
    throw SimulationError(
        fmt::format("{}: {:.3g} (step ratio {:.3g}), more than 2^31", what, n, q));
  }
  return n > 1.0 ? static_cast<std::int64_t>(n) : 1;
}

}  // namespace sphdem
