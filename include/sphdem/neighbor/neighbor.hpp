#pragma once
// Neighbor search: a cell grid (cells no smaller than the cut-off, counting
// sort, linear in the particle count) builds Verlet lists with a skin.
// Lists are kept for owned particles only and each list is sorted by global
// id, so the sums of the gather formulation run in an order that does not
// depend on the particle layout or the rank count.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// One particle's neighbours: nb[n] for a list position n in [begin(i),
// end(i)) is the neighbour's particle index. Most lists hold 16-bit offsets
// from the particle's own index (particles are sorted by cell, so in 2D a
// neighbour is a few thousand slots away); a list with some neighbour
// farther off (a ghost appended at the end, a 3D slab of cells) keeps
// 32-bit indices. The choice is per list and loop-invariant in a walk.
class NeighborRow {
 public:
  NeighborRow(const std::int16_t* narrow, std::int32_t base) : narrow_(narrow), base_(base) {}
  NeighborRow(const std::int32_t* wide, std::size_t shift) : wide_(wide), shift_(shift) {}
  std::int32_t operator[](std::size_t n) const {
    return wide_ != nullptr ? wide_[n - shift_] : base_ + narrow_[n];
  }
  // A 16-bit row's offsets (null for a 32-bit row) and the index they are
  // offsets from: nb[n] == base() + narrow()[n]. For loops that decode a
  // row several entries at a time (the pair loop's slots, pair_loop.hpp).
  const std::int16_t* narrow() const { return wide_ == nullptr ? narrow_ : nullptr; }
  std::int32_t base() const { return base_; }

 private:
  const std::int16_t* narrow_ = nullptr;
  std::int32_t base_ = 0;
  const std::int32_t* wide_ = nullptr;
  std::size_t shift_ = 0;
};

template <int D>
class NeighborList {
 public:
  // cutoff = support (2h) + skin.
  NeighborList(double support, double skin) : support_(support), skin_(skin) {}

  // Builds lists for every owned particle over all particles (ghosts
  // included). Fluid particles list fluid and wall neighbors; wall particles
  // list only fluid neighbors (what the wall extrapolation needs).
  void build(const SphParticles<D>& ps);

  // True once some owned particle may have moved more than half the skin
  // since the last build (a local answer; the solver reduces it over
  // ranks). Conservative: the rounding of the stored positions comes off
  // the half skin (positions_at_build), so no pair enters the support
  // unlisted; a particle's verdict reads only its own values, the same at
  // every rank count.
  bool needs_rebuild(const SphParticles<D>& ps) const;
  // needs_rebuild's test of owned particles i .. i + 7 (bits of `valid`;
  // positions x, D doubles a particle): true when one moved too far. The
  // drift runs it on the positions it has just written
  // (kick_drift_resin_and_check), so the step does not read them again.
  // Needs a build of the current owned particles; with AVX-512 only.
  bool moved_too_far(const double* x, std::size_t i, std::uint8_t valid) const;
  // The same for particles i .. i + count - 1, one at a time (the builds
  // without AVX-512; needs_rebuild runs it over all owned particles).
  bool moved_too_far(const double* x, std::size_t i, std::size_t count) const {
    for (std::size_t e = i + count; i < e; ++i) {
      double d2 = 0.0;
      for (int k = 0; k < D; ++k) {
        const double d = x[D * i + static_cast<std::size_t>(k)] -
                         static_cast<double>(x_at_build_[i][static_cast<std::size_t>(k)]);
        d2 = lanes::mul_add(d, d, d2);
      }
      if (d2 <= quick_limit2_) continue;
      if (beyond_own_limit(i, d2)) return true;
    }
    return false;
  }
  // The same for particles i .. i + 3, in 2D four at a time (AVX2).
  bool moved_too_far4(const double* x, std::size_t i) const;

  // The second look, once some particle moved more than half the skin
  // (docs/performance.md, "Rebuilds on the particles' relative moves"):
  // a list misses a pair only if the two particles' moves since the build
  // differ by more than the skin, and two moves that lie in one box differ
  // by at most its diagonal. MoveBox holds this rank's box of every owned
  // particle's move, each widened by its position's rounding (axis k spans
  // [-box[D + k], box[k]]), then the largest squared move and the largest
  // rounding. Every value is a maximum, so the ranks' boxes reduce with
  // MPI_MAX to the same box at every rank count. Infinite when the
  // particles are not those of the build or a move is not finite.
  using MoveBox = std::array<double, 2 * D + 2>;
  MoveBox move_box(const SphParticles<D>& ps) const;
  // From all ranks' reduced box: true when some pair may have come within
  // the support unlisted (the diagonal beyond the skin), or some particle
  // moved more than max_move skins (at most 1, which keeps every particle
  // within a skin of its place at the build, the cells its rank owned; a
  // coupled run allows less, coupled_skins.hpp; at least the first look's
  // half).
  bool box_needs_rebuild(const MoveBox& box, double max_move = 1.0) const;

  // This list as the pairs of `full` (a build's lists) closer than
  // sqrt(within2) at the particles' positions now (and those whose distance
  // is not a number, as `full` holds them), each list in its order (global
  // id) and storage (16- or 32-bit). Needs full's particles, owned and
  // ghosts, in the same places. A list kept so answers no rebuild question.
  // SupportLists (support_lists.hpp) keeps the 3D step's lists with it.
  void keep_within(const NeighborList& full, const SphParticles<D>& ps, double within2);

  std::size_t begin(std::size_t i) const { return offset_[i]; }
  std::size_t end(std::size_t i) const { return offset_[i + 1]; }
  // Particle i's neighbours, indexed by list position (NeighborRow).
  NeighborRow row(std::size_t i) const {
    const std::size_t b = offset_[i];
    if (all_wide_) return {wide_.data(), std::size_t{0}};
    if (b == offset_[i + 1] || narrow_[b] != kWideRow)
      return {narrow_.data(), static_cast<std::int32_t>(i)};
    return {wide_.data(), b - wide_start(i)};
  }
  std::size_t total_pairs() const { return offset_.empty() ? 0 : offset_.back(); }
  // How the last build stored its lists: the pairs kept as 32-bit indices
  // (lists with an offset beyond 16 bits; every pair when those were more
  // than a quarter of all, then no 16-bit array is kept).
  std::size_t wide_pairs() const { return all_wide_ ? total_pairs() : wide_used_; }
  bool all_wide() const { return all_wide_; }
  double cutoff() const { return support_ + skin_; }
  double skin() const { return skin_; }
  std::int64_t builds() const { return builds_; }
  // The owned particles whose list holds a ghost (an index >= n_owned), in
  // index order: the lists that name a ghost, found once per build (the
  // free-surface flag's second run walks only these for flagged ghosts,
  // src/sph/fluid_rates.cpp).
  const std::vector<std::uint32_t>& ghost_listers() const { return ghost_listers_; }
  // Owned particle i's position at the last build, rounded to float (what
  // needs_rebuild compares with; 8 bytes a particle in 2D, not 16): part of
  // a checkpoint, so a restart rebuilds there and its rebuilds fall on the
  // run's steps.
  Vec<D> position_at_build(std::size_t i) const {
    Vec<D> x;
    for (int k = 0; k < D; ++k) x[k] = static_cast<double>(x_at_build_[i][k]);
    return x;
  }
  std::size_t positions_at_build() const { return x_at_build_.size(); }
#if defined(SPHDEM_PARTICLE_LANES)
  // move_box eight particles at a time, for the drift's pass on the
  // positions it has just written (kick_drift_resin_and_check): add_moves
  // for every group, then box(), the same MoveBox as move_box. With
  // `check`, add_moves also answers moved_too_far(x, i, valid) from the
  // same loads.
  struct MoveLanes {
    __m512d hi[D], lo[D], d2, rounding;
    __mmask8 not_finite = 0;
    MoveLanes();
    MoveBox box() const;
  };
  bool add_moves(const double* x, std::size_t i, __mmask8 valid, bool check, MoveLanes& m) const;
#endif

 private:
  double support_, skin_;
  // The bound of a float position's rounding: 2^-23 of its coordinates'
  // magnitudes, and the smallest float per coordinate (needs_rebuild).
  static constexpr double kRoundingRelative = 0x1p-23;
  static constexpr double kRoundingTiny = std::numeric_limits<float>::denorm_min();
  // A 16-bit list that starts with kWideRow is kept in wide_ instead
  // (wide_rows_ and wide_starts_ say where); offsets are within +-32767.
  static constexpr std::int16_t kWideRow = std::numeric_limits<std::int16_t>::min();
  std::size_t wide_start(std::size_t i) const;
  void store_all_wide();
  void store_mixed();

  std::vector<std::uint32_t> offset_;  // 4 bytes per particle (build checks the count)
  std::vector<std::int16_t> narrow_;   // per pair: neighbour index - own index
  std::vector<std::int32_t> wide_;     // the lists that do not fit (all of them if all_wide_)
  std::size_t wide_used_ = 0;          // of wide_ (a kept list does not shrink it)
  std::vector<std::uint32_t> wide_rows_, wide_starts_;  // those lists' particles and starts
  std::vector<std::uint32_t> ghost_listers_;
  bool all_wide_ = false;
  std::vector<std::array<float, D>> x_at_build_;
  // Below this squared move no particle of the build needs the per-particle
  // bound (the largest bound of the build taken off the half skin; -1: none).
  double quick_limit2_ = -1.0;
  std::int64_t builds_ = 0;
  // Particle i's own test, for a squared move d2 beyond the quick limit.
  bool beyond_own_limit(std::size_t i, double d2) const;
#if defined(SPHDEM_PARTICLE_LANES)
  // The same for the lanes of `valid` of particles i .. i + 7 (moved_too_far, add_moves).
  bool beyond_limits(std::size_t i, __m512d d2, __mmask8 valid) const;
#endif
  // The cell grid's starts, kept to avoid reallocations (the binning's
  // per-particle scratch is shared with sort_by_cell: neighbor_list.cpp).
  std::vector<std::int32_t> cell_start_;
  std::vector<std::int32_t> cell_resin_end_;  // each cell's resin first, then its walls
};

#if defined(SPHDEM_PARTICLE_LANES)
// Eight particles' squared moves against the quick limit; the few beyond it
// one at a time against their own.
template <int D>
__attribute__((always_inline)) inline bool NeighborList<D>::beyond_limits(std::size_t i, __m512d d2,
                                                                          __mmask8 valid) const {
  __mmask8 far = _mm512_mask_cmp_pd_mask(valid, d2, _mm512_set1_pd(quick_limit2_), _CMP_NLE_UQ);
  if (far == 0) return false;
  alignas(64) double each[8];
  _mm512_store_pd(each, d2);
  for (; far != 0; far &= static_cast<__mmask8>(far - 1)) {
    const int l = __builtin_ctz(far);
    if (beyond_own_limit(i + static_cast<std::size_t>(l), each[l])) return true;
  }
  return false;
}

// Eight particles at a time for the quick limit; the few beyond it one at a time.
template <int D>
inline bool NeighborList<D>::moved_too_far(const double* x, std::size_t i,
                                           std::uint8_t valid) const {
  __m512d now[D], then[D];
  lanes::load_vectors<D>(x, i, valid, now);
  lanes::load_vectors<D>(x_at_build_.data()->data(), i, valid, then);
  __m512d d2 = _mm512_setzero_pd();
  for (int k = 0; k < D; ++k) {
    const __m512d d = _mm512_sub_pd(lanes::component<D>(now, k), lanes::component<D>(then, k));
    d2 = k == 0 ? lanes::mul(d, d) : _mm512_fmadd_pd(d, d, d2);
  }
  return beyond_limits(i, d2, valid);
}
#endif

#if defined(SPHDEM_PARTICLE_LANES)
template <int D>
inline NeighborList<D>::MoveLanes::MoveLanes() {
  const __m512d none = _mm512_set1_pd(-std::numeric_limits<double>::infinity());
  for (int k = 0; k < D; ++k) hi[k] = lo[k] = none;
  d2 = rounding = none;
}

template <int D>
inline typename NeighborList<D>::MoveBox NeighborList<D>::MoveLanes::box() const {
  MoveBox b;
  if (not_finite != 0) {
    b.fill(std::numeric_limits<double>::infinity());
    return b;
  }
  for (int k = 0; k < D; ++k) {
    b[static_cast<std::size_t>(k)] = lanes::largest(hi[k]);
    b[static_cast<std::size_t>(D + k)] = lanes::largest(lo[k]);
  }
  b[2 * D] = lanes::largest(d2);
  b[2 * D + 1] = lanes::largest(rounding);
  return b;
}

// The one-particle form's operations (move_box), lane by lane.
// Inline always: the drift's loop keeps the box in registers.
template <int D>
__attribute__((always_inline)) inline bool NeighborList<D>::add_moves(const double* x,
                                                                      std::size_t i, __mmask8 valid,
                                                                      bool check,
                                                                      MoveLanes& m) const {
  __m512d now[D], then[D];
  for (int q = 0; q < D; ++q) {  // lanes::load_vectors, inline
    const __mmask8 v = lanes::vector_mask<D>(valid, q);
    now[q] = _mm512_maskz_loadu_pd(v, x + D * i + 8 * q);
    then[q] = _mm512_maskz_cvtps_pd(
        v, _mm256_maskz_loadu_ps(v, x_at_build_.data()->data() + D * i + 8 * q));
  }
  __m512d move[D], size = _mm512_setzero_pd(), d2 = _mm512_setzero_pd();
  for (int k = 0; k < D; ++k) {
    const __m512d t = lanes::component<D>(then, k);
    move[k] = _mm512_sub_pd(lanes::component<D>(now, k), t);
    size = k == 0 ? _mm512_abs_pd(t) : _mm512_add_pd(size, _mm512_abs_pd(t));
    d2 = k == 0 ? lanes::mul(move[k], move[k]) : _mm512_fmadd_pd(move[k], move[k], d2);
  }
  const __m512d rounding =
      _mm512_fmadd_pd(size, _mm512_set1_pd(kRoundingRelative), _mm512_set1_pd(D * kRoundingTiny));
  for (int k = 0; k < D; ++k) {
    m.hi[k] = _mm512_mask_max_pd(m.hi[k], valid, m.hi[k], _mm512_add_pd(move[k], rounding));
    m.lo[k] = _mm512_mask_max_pd(m.lo[k], valid, m.lo[k], _mm512_sub_pd(rounding, move[k]));
  }
  m.d2 = _mm512_mask_max_pd(m.d2, valid, m.d2, d2);
  m.rounding = _mm512_mask_max_pd(m.rounding, valid, m.rounding, rounding);
  m.not_finite = static_cast<__mmask8>(
      m.not_finite |
      _mm512_mask_cmp_pd_mask(valid, d2, _mm512_set1_pd(std::numeric_limits<double>::infinity()),
                              _CMP_NLT_UQ));
  return check && beyond_limits(i, d2, valid);  // moved_too_far's test on the same d2
}
#endif

#if defined(SPHDEM_PARTICLE_LANES4)
template <int D>
inline bool NeighborList<D>::moved_too_far4(const double* x, std::size_t i) const {
  if constexpr (D != 2) {
    return moved_too_far(x, i, std::size_t{4});
  } else {
    // x_at_build_'s floats of the four particles, widened exactly: the
    // same layout as x (x0 y0 x1 y1 | x2 y2 x3 y3).
    const __m256 then = _mm256_loadu_ps(x_at_build_[i].data());
    const __m256d d[2] = {
        _mm256_sub_pd(_mm256_loadu_pd(x + 2 * i), _mm256_cvtps_pd(_mm256_castps256_ps128(then))),
        _mm256_sub_pd(_mm256_loadu_pd(x + 2 * i + 4),
                      _mm256_cvtps_pd(_mm256_extractf128_ps(then, 1)))};
    // Lanes 0 and 2: fma(dy, dy, dx dx), the one-particle form's d2.
    alignas(32) double d2[2][4];
    int far = 0;
    for (int q = 0; q < 2; ++q) {
      const __m256d swapped = _mm256_permute_pd(d[q], 0b0101);
      const __m256d r = _mm256_fmadd_pd(swapped, swapped, _mm256_mul_pd(d[q], d[q]));
      _mm256_store_pd(d2[q], r);
      const int lanes =
          _mm256_movemask_pd(_mm256_cmp_pd(r, _mm256_set1_pd(quick_limit2_), _CMP_NLE_UQ));
      far |= (lanes & 1) << (2 * q) | ((lanes >> 2) & 1) << (2 * q + 1);
    }
    for (; far != 0; far &= far - 1) {
      const int l = __builtin_ctz(static_cast<unsigned>(far));
      if (beyond_own_limit(i + static_cast<std::size_t>(l), d2[l / 2][2 * (l % 2)])) return true;
    }
    return false;
  }
}
#endif

// Reorders owned particles by cell of size `cell` (then by global id) for
// cache locality. Call before rebuilding ghosts and lists.
template <int D>
void sort_by_cell(SphParticles<D>& ps, double cell);

}  // namespace sphdem
