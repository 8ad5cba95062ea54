#pragma once
// Sums whose value does not depend on the order or grouping of their terms,
// so not on the rank count either (docs/physics.md "Implicit viscosity").
// Floating-point addition is not associative: a dot product summed per rank
// and then over ranks changes in its last bits with the partition. Here
// every term is rounded to a multiple of 2^-s, with s chosen from the
// largest |term| over all ranks so that that term times 2^s is at most
// 2^62; the rounded terms are integers and their sum in 128-bit integers is
// exact (up to 2^65 terms), whatever the order. Each rounding is below
// 2^-63 of the largest term. The MPI part (the max and the integer sum over
// ranks) is the solver's: src/parallel/exact_sum.cpp.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace sphdem {

__extension__ typedef __int128 Int128;

// The scale s for terms whose largest magnitude is max_abs (0: every term is 0).
inline int exact_sum_scale(double max_abs) {
  if (!(max_abs > 0.0)) return 0;
  int e = 0;
  std::frexp(max_abs, &e);  // max_abs < 2^e
  return 62 - e;
}

// One term rounded to the grid of scale s, as an integer (|x| <= max_abs).
inline Int128 exact_term(double x, int scale) {
  return static_cast<Int128>(std::llrint(std::ldexp(x, scale)));
}

// 2^scale when it is a normal double (then x * exact_power(s) is ldexp(x, s)
// exactly: both round x 2^s once, to nearest), else 0: use exact_term.
inline double exact_power(int scale) {
  return scale >= -1022 && scale <= 1023 ? std::ldexp(1.0, scale) : 0.0;
}

// exact_term(x, scale) from x * exact_power(scale) (a multiplication
// instead of an ldexp per term: the sums' hot loop).
inline Int128 exact_term_scaled(double x_times_power) {
  return static_cast<Int128>(std::llrint(x_times_power));
}

// The sum of the rounded terms, back in floating point (one rounding).
inline double exact_value(Int128 total, int scale) {
  return std::ldexp(static_cast<double>(total), -scale);
}

// The dot products below run in kExactLanes independent lanes (then combined;
// integer max and sums are associative), which lets the compiler vectorise
// them at -O2 as well as -O3.
inline constexpr std::size_t kExactLanes = 8;

// The largest |a_i b_i| over n products, +inf when one is not finite. For
// doubles >= 0 the order of the bit patterns is the order of the values and
// every inf or NaN pattern lies above the largest finite one, so an integer
// max (which vectorises, unlike a max of doubles with NaNs) gives both.
inline double exact_dot_max(const double* a, const double* b, std::size_t n) {
  constexpr std::uint64_t magnitude = 0x7fff'ffff'ffff'ffffULL;
  constexpr std::uint64_t inf = 0x7ff0'0000'0000'0000ULL;
  const auto bits = [&](std::size_t i) {
    return std::bit_cast<std::uint64_t>(a[i] * b[i]) & magnitude;
  };
  std::uint64_t lane[kExactLanes] = {};
  std::size_t i = 0;
  for (; i + kExactLanes <= n; i += kExactLanes)
    for (std::size_t k = 0; k < kExactLanes; ++k) lane[k] = std::max(lane[k], bits(i + k));
  std::uint64_t m = 0;
  for (; i < n; ++i) m = std::max(m, bits(i));
  for (std::uint64_t x : lane) m = std::max(m, x);
  return m >= inf ? std::numeric_limits<double>::infinity() : std::bit_cast<double>(m);
}

// sum_i exact_term_scaled((a_i b_i) * power), the same integer, for
// products within the max given to exact_sum_scale (|q_i| <= 2^62, q_i =
// (a_i b_i) * power). Each q is split as h 2^31 + l, h = round(q 2^-31)
// and l = round(q - h 2^31) (q - h 2^31 is representable, so exact; both
// rounded to nearest-even by adding and removing 1.5 2^52, valid below
// 2^51): h 2^31 + l = llrint(q) since h 2^31 is an even integer. The h
// and the l are summed in 64-bit integers (no overflow below 2^31 terms),
// loops that vectorise where the 128-bit sum does not.
inline Int128 exact_dot_scaled(const double* a, const double* b, std::size_t n, double power) {
  constexpr double round_shift = 0x1.8p52;
  const auto add = [&](std::size_t i, std::int64_t& hi, std::int64_t& lo) {
    const double q = (a[i] * b[i]) * power;
    const double h = (q * 0x1p-31 + round_shift) - round_shift;
    const double l = ((q - h * 0x1p31) + round_shift) - round_shift;
    hi += static_cast<std::int64_t>(h);
    lo += static_cast<std::int64_t>(l);
  };
  std::int64_t hi[kExactLanes] = {}, lo[kExactLanes] = {};
  std::size_t i = 0;
  for (; i + kExactLanes <= n; i += kExactLanes)
    for (std::size_t k = 0; k < kExactLanes; ++k) add(i + k, hi[k], lo[k]);
  std::int64_t h = 0, l = 0;
  for (; i < n; ++i) add(i, h, l);
  for (std::size_t k = 0; k < kExactLanes; ++k) {
    h += hi[k];
    l += lo[k];
  }
  return static_cast<Int128>(h) * (Int128{1} << 31) + l;
}

}  // namespace sphdem
