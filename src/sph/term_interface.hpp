#pragma once
// What an SPH pair term (src/sph/terms/*.hpp) is made of, and what the pair
// loop (pair_loop.hpp) hands it. docs/architecture.md, "Adding a physics
// term", shows a term end to end. A term is a struct with:
//
//   static constexpr const char* name;   // its case-file switch (or what it is)
//   using Reads = Fields<...>;           // record fields read per neighbour
//   using OwnReads = Fields<...>;        // optional: fields read of particle i only
//   static constexpr unsigned writes;    // kDrho | kBracket | kVisc
//   static bool active(const SphParams&);            // optional: absent = always on
//   static constexpr int variants; static int variant(const SphParams&);
//                                        // optional: compile-time variants (pair<V>)
//   explicit T(const TermContext<D>&);   // optional: its parameters
//   T for_particle(const OwnView&) const;            // optional: per-particle part
//   void pair(const PairView&, PairSums&) const;     // its contribution per pair
//   static constexpr bool kVectorPair;   // optional: pair() works on registers too
//
// A record field (record_fields.hpp, or a term's own header for a quantity
// it prepares per particle, like anti-clump's R_a) is a struct with a name,
// a width (scalar or D components), how its lane is formed (the
// neighbour's value, or particle i's value of RelativeTo minus the
// neighbour's) and fill(), which computes it for one particle.
#include <cstddef>
#include <type_traits>

#include "sphdem/particles/particles.hpp"
#include "sphdem/sph/kernel.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem::terms {

// Neighbours per chunk: the pair loop gathers up to this many pairs into
// lane arrays, then computes them in one vectorized loop.
inline constexpr std::size_t kChunk = 64;

// A compile-time list of record fields.
template <class... F>
struct Fields {};

// A compile-time list of terms: the registry (sph_terms.hpp) is one.
template <class... T>
struct TermList {};

template <class F, class L>
struct Contains;
template <class F, class... Fs>
struct Contains<F, Fields<Fs...>> : std::bool_constant<(std::is_same_v<F, Fs> || ...)> {};
template <class F, class L>
inline constexpr bool contains_v = Contains<F, L>::value;

// A scalar record field whose lane is the neighbour's value.
struct ScalarField {
  static constexpr bool kVector = false;
  using RelativeTo = void;
};
// A D-component field whose lane is particle i's Self minus the neighbour's.
template <class Self>
struct RelativeVectorField {
  static constexpr bool kVector = true;
  using RelativeTo = Self;
};

template <class F, int D>
inline constexpr std::size_t width_v = F::kVector ? D : 1;

// What a pair contributes. The loop combines them as
//   a_ij = visc v~_ij - m_j bracket F x_ij,   drho_ij = drho,
// with v~_ij = v_i - vw_j. Each starts at -0.0, the exact additive
// identity (-0.0 + x == x for every x, so the compiler drops the add and
// the first contribution is bitwise the term's own value).
// V is double, or a register of doubles (one pair per lane) for the terms
// that compute in registers (kVectorPair, below).
template <class V>
V splat(double x) {
  if constexpr (std::is_same_v<V, double>)
    return x;
  else
    return x - V{};  // x in every lane, -0.0 included (x - 0 == x)
}
template <class V = double>
struct BasicPairSums {
  V drho = splat<V>(-0.0);
  V bracket = splat<V>(-0.0);  // P_i/rho_i^2 + P_j/rho_j^2 + Pi_ij + R_ij f^n ...
  V visc = splat<V>(-0.0);     // factor of v~_ij
};
using PairSums = BasicPairSums<double>;
enum Writes : unsigned { kDrho = 1, kBracket = 2, kVisc = 4 };

// What a term's constructor may use: the parameters and the kernel.
template <int D>
struct TermContext {
  const SphParams& sp;
  WendlandC2<D> kernel;
  double kw;  // Wendland C2 normalisation C: W(0) = 16 C exactly
};

// Particle i's record, restricted to the fields the term declared.
// O: double, or a register of doubles holding one particle per lane
// (pair_loop.hpp, "one particle per lane").
template <class RecordLayout, class Allowed, class O = double>
struct OwnView {
  const O* own;
  template <class F>
  O own_value(F, int c = 0) const {
    static_assert(contains_v<F, Allowed>, "the term reads a field it does not declare");
    return own[RecordLayout::template offset<F>() + c];
  }
};

// One pair (i, neighbour k of the chunk): its lanes, particle i's record,
// and the kernel values the loop computes for every pair. Pairs beyond the
// support have t = 0, hence F = 0 and W = 0.
template <int D, class LaneLayout, class RecordLayout, class Reads, class OwnReads>
struct PairView {
  static constexpr int kDim = D;
  const double* lanes;  // lane row r of pair k at lanes[r * kChunk + k]
  std::size_t k;
  const double* own;
  double r2, r, q, t, F;  // |x_ij|^2, |x_ij|, r/h, 2 - q (or 0), grad W = F x_ij

  // The neighbour's value, or i's minus the neighbour's for relative fields.
  template <class Fd>
  double lane(Fd, int c = 0) const {
    static_assert(contains_v<Fd, Reads>, "the term reads a lane it does not declare");
    return lanes[(LaneLayout::template offset<Fd>() + c) * kChunk + k];
  }
  // Particle i's own value.
  template <class Fd>
  double own_value(Fd, int c = 0) const {
    static_assert(contains_v<Fd, Reads> || contains_v<Fd, OwnReads>,
                  "the term reads a field it does not declare");
    return own[RecordLayout::template offset<Fd>() + c];
  }
};

// The same pair quantities for a block of pairs held in registers of V
// (one pair per lane): the lane rows the gather transposed
// (GatherLanes::rows) instead of rows stored in memory. A term whose
// pair() is written for any lane type (`auto` locals, no branches) says so
// with `static constexpr bool kVectorPair = true;`; when every active term
// and the side pass do, the pair loop computes the terms on the registers
// straight after the gather (pair_loop.hpp, "steps 1 and 2 in registers").
// O: particle i's values, double (one particle, its pairs in the lanes)
// or V (one particle per lane).
template <int D, class LaneLayout, class RecordLayout, class Reads, class OwnReads, class V,
          class O = double>
struct RegisterPairView {
  static constexpr int kDim = D;
  const V* rows;  // lane row r of the block's pairs
  const O* own;
  V r2, r, q, t, F;

  template <class Fd>
  V lane(Fd, int c = 0) const {
    static_assert(contains_v<Fd, Reads>, "the term reads a lane it does not declare");
    return rows[LaneLayout::template offset<Fd>() + c];
  }
  template <class Fd>
  O own_value(Fd, int c = 0) const {
    static_assert(contains_v<Fd, Reads> || contains_v<Fd, OwnReads>,
                  "the term reads a field it does not declare");
    return own[RecordLayout::template offset<Fd>() + c];
  }
};

template <class T>
concept VectorPairTerm = requires {
  requires T::kVectorPair;
};

}  // namespace sphdem::terms
