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
#include <cmath>
#include <cstdint>

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

}  // namespace sphdem
