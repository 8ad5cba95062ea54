// NeighborList::keep_within and SupportLists (support_lists.hpp): the
// build's lists cut to the pairs within a radius at the step's positions,
// kept while no pair they leave out can have come within the support
// (docs/performance.md, "The support lists").
#include "sphdem/neighbor/support_lists.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/particles/particle_lanes.hpp"

namespace sphdem {
namespace {

// The entries of one list (k-th neighbour index row[k] + own, count m) whose
// squared distance from xi is below within2 or not a number, copied to out
// in order; returns
// how many. x: D doubles a particle. Index is the list's entry type (16-bit
// offsets or 32-bit indices). out has room for m entries and 8 more (the
// vector form stores whole blocks).
template <int D, class Index>
std::size_t keep_row(const Index* row, std::size_t m, std::int32_t own, const double* x,
                     const double* xi, double within2, Index* out) {
  std::size_t kept = 0;
#if defined(SPHDEM_PARTICLE_LANES)
  // Eight entries at a time: their positions loaded one particle a register
  // and transposed to one register an axis (plain loads: a gather costs
  // about one load per double on Zen 4 and 5), the squared distances
  // compared, the kept entries compressed in a register and stored whole (a
  // compressing store to memory is microcoded on Zen 4).
  __m512d c[D];
  for (int d = 0; d < D; ++d) c[d] = _mm512_set1_pd(xi[d]);
  const __m512d limit = _mm512_set1_pd(within2);
  const __m256i base = _mm256_set1_epi32(own);
  constexpr auto kAxes = static_cast<__mmask8>((1u << D) - 1);
  const __m512i lo = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i hi = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
  for (std::size_t k = 0; k < m; k += 8) {
    const auto in = static_cast<__mmask8>(m - k >= 8 ? 0xFF : (1u << (m - k)) - 1);
    __m256i entry;
    if constexpr (sizeof(Index) == 2)
      entry = _mm256_cvtepi16_epi32(_mm_maskz_loadu_epi16(in, row + k));
    else
      entry = _mm256_maskz_loadu_epi32(in, row + k);
    // Entries past the list's end read the own particle (offset 0 + own).
    alignas(32) std::int32_t j[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(j), _mm256_add_epi32(entry, base));
    __m512d a[4];  // particles l and l + 4: x y (z) 0 | x y (z) 0
    // (Masked forms with every lane set: the unmasked intrinsics pass GCC 12
    // an undefined vector that -Wmaybe-uninitialized reports.)
    for (int l = 0; l < 4; ++l) {
      const __m512d first = _mm512_maskz_loadu_pd(kAxes, x + D * std::size_t(j[l]));
      a[l] = _mm512_mask_insertf64x4(
          first, 0xFF, first, _mm256_maskz_loadu_pd(kAxes, x + D * std::size_t(j[l + 4])), 1);
    }
    const __m512d t0 =
        _mm512_mask_unpacklo_pd(a[0], 0xFF, a[0], a[1]);  // x0 x1 z0 z1 | x4 x5 z4 z5
    const __m512d t1 =
        _mm512_mask_unpackhi_pd(a[0], 0xFF, a[0], a[1]);  // y0 y1 .. .. | y4 y5 .. ..
    const __m512d t2 = _mm512_mask_unpacklo_pd(a[2], 0xFF, a[2], a[3]);
    const __m512d t3 = _mm512_mask_unpackhi_pd(a[2], 0xFF, a[2], a[3]);
    __m512d xj[3];
    xj[0] = _mm512_permutex2var_pd(t0, lo, t2);
    xj[1] = _mm512_permutex2var_pd(t1, lo, t3);
    xj[2] = _mm512_permutex2var_pd(t0, hi, t2);
    __m512d r2 = _mm512_setzero_pd();
    for (int d = 0; d < D; ++d) {
      const __m512d dx = _mm512_sub_pd(c[d], xj[d]);
      r2 = _mm512_fmadd_pd(dx, dx, r2);
    }
    const __mmask8 keep = _mm512_mask_cmp_pd_mask(in, r2, limit, _CMP_NGE_UQ);
    const __m256i packed = _mm256_maskz_compress_epi32(keep, entry);
    if constexpr (sizeof(Index) == 2)
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + kept), _mm256_cvtepi32_epi16(packed));
    else
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + kept), packed);
    kept += static_cast<std::size_t>(__builtin_popcount(keep));
  }
#else
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t j = static_cast<std::size_t>(static_cast<std::int32_t>(row[k]) + own);
    double r2 = 0.0;
    for (int d = 0; d < D; ++d) {
      const double dx = xi[d] - x[D * j + static_cast<std::size_t>(d)];
      r2 += dx * dx;
    }
    if (!(r2 >= within2)) out[kept++] = row[k];
  }
#endif
  return kept;
}

// Room past the last entry for keep_row's whole-block stores.
constexpr std::size_t kKeepSpare = 8;

}  // namespace

template <int D>
void NeighborList<D>::keep_within(const NeighborList& full, const SphParticles<D>& ps,
                                  double within2) {
  const std::size_t n_own = full.offset_.empty() ? 0 : full.offset_.size() - 1;
  support_ = full.support_;
  skin_ = 0.0;
  all_wide_ = full.all_wide_;
  ghost_listers_ = full.ghost_listers_;  // a superset is what its readers need
  wide_rows_ = full.wide_rows_;
  wide_starts_.resize(full.wide_starts_.size());
  offset_.resize(n_own + 1);
  // Sized as full's and never shrunk: the same capacity at every step, and
  // no growth to clear (only offset_ says where the lists end).
  if (narrow_.size() < full.narrow_.size() + kKeepSpare)
    narrow_.resize(full.narrow_.size() + kKeepSpare);
  if (wide_.size() < full.wide_.size() + kKeepSpare) wide_.resize(full.wide_.size() + kKeepSpare);
  x_at_build_.clear();
  quick_limit2_ = -1.0;

  const double* const x = ps.x.data()->data();
  std::size_t kept = 0, wide_kept = 0, wide_row = 0;
  if (n_own > 0) offset_[0] = 0;
  for (std::size_t i = 0; i < n_own; ++i) {
    const std::size_t b = full.offset_[i], m = full.offset_[i + 1] - b;
    const auto own = static_cast<std::int32_t>(i);
    const double* const xi = x + D * i;
    if (all_wide_) {
      kept += keep_row<D>(full.wide_.data() + b, m, 0, x, xi, within2, wide_.data() + kept);
    } else if (m == 0 || full.narrow_[b] != kWideRow) {
      kept += keep_row<D>(full.narrow_.data() + b, m, own, x, xi, within2, narrow_.data() + kept);
    } else {  // a 32-bit list of the mixed storage: its 16-bit slots say so
      const std::size_t from = full.wide_starts_[wide_row];
      wide_starts_[wide_row++] = static_cast<std::uint32_t>(wide_kept);
      const std::size_t k =
          keep_row<D>(full.wide_.data() + from, m, 0, x, xi, within2, wide_.data() + wide_kept);
      for (std::size_t t = 0; t < k; ++t) narrow_[kept + t] = kWideRow;
      kept += k;
      wide_kept += k;
    }
    offset_[i + 1] = static_cast<std::uint32_t>(kept);
  }
  wide_used_ = all_wide_ ? kept : wide_kept;
}

template void NeighborList<2>::keep_within(const NeighborList<2>&, const SphParticles<2>&, double);
template void NeighborList<3>::keep_within(const NeighborList<3>&, const SphParticles<3>&, double);

template <int D>
bool SupportLists<D>::moved_past_margin(const SphParticles<D>& ps) const {
  // Eight particles' D doubles at a time, each double's lane keeping the
  // smallest and largest move of its axis (lane c holds axis c % D), and
  // d - d, which is 0 unless d is infinite or not a number.
  constexpr std::size_t kBlock = 8 * D;
  const std::size_t m = D * ps.size();
  const double* const x = ps.x.data()->data();
  const double* const at_cut = x_cut_.data();
  double lo[kBlock], hi[kBlock], probe[kBlock];
  for (std::size_t c = 0; c < kBlock; ++c) {
    lo[c] = std::numeric_limits<double>::infinity();
    hi[c] = -std::numeric_limits<double>::infinity();
    probe[c] = 0.0;
  }
  std::size_t b = 0;
  for (; b + kBlock <= m; b += kBlock)
    for (std::size_t c = 0; c < kBlock; ++c) {
      const double d = x[b + c] - at_cut[b + c];
      lo[c] = d < lo[c] ? d : lo[c];
      hi[c] = d > hi[c] ? d : hi[c];
      probe[c] += d - d;
    }
  for (std::size_t c = 0; b + c < m; ++c) {
    const double d = x[b + c] - at_cut[b + c];
    lo[c] = d < lo[c] ? d : lo[c];
    hi[c] = d > hi[c] ? d : hi[c];
    probe[c] += d - d;
  }
  double diagonal2 = 0.0;
  for (int a = 0; a < D; ++a) {
    double low = std::numeric_limits<double>::infinity();
    double high = -std::numeric_limits<double>::infinity();
    for (std::size_t c = static_cast<std::size_t>(a); c < kBlock; c += D) {
      low = std::min(low, lo[c]);
      high = std::max(high, hi[c]);
      diagonal2 += probe[c];  // not a number once some move is not finite
    }
    if (high >= low) diagonal2 += (high - low) * (high - low);
  }
  return !(diagonal2 < margin_ * margin_);
}

template <int D>
const NeighborList<D>& SupportLists<D>::lists(const NeighborList<D>& full,
                                              const SphParticles<D>& ps) {
  // A new build (new lists, particles in new places) or a box of moves
  // past the margin: cut again. The radius holds a relative 1e-6 more, so
  // that every sum's own test (r^2 < 4h^2, its own rounding) sees no pair
  // the cut dropped.
  const bool fresh = full.builds() == full_builds_ && x_cut_.size() == D * ps.size();
  if (fresh && !moved_past_margin(ps)) return kept_;
  const double radius = support_ * (1.0 + 1e-6) + margin_;
  kept_.keep_within(full, ps, radius * radius);
  const double* const x = ps.x.data()->data();
  x_cut_.assign(x, x + D * ps.size());
  full_builds_ = full.builds();
  ++cuts_;
  return kept_;
}

template class SupportLists<2>;
template class SupportLists<3>;

}  // namespace sphdem
