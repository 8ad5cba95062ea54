#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>

#include <fmt/format.h>

#include "cell_candidates.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/core/scratch.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/particles/particle_lanes.hpp"

namespace sphdem {

namespace {

// The cell grid of the list build and the sort by cell: cells at least
// `cell` wide. An axis whose extent would take more than kMaxCellsPerAxis
// cells (a particle far from the others) takes that many wider ones, an
// axis with a non-finite extent one cell: the cells around a particle
// still cover the cut-off. Every double is clamped before its cast to long
// (a cast out of long's range is undefined behaviour, and GCC's
// -fsanitize=undefined does not report it).
constexpr long kMaxCellsPerAxis = 1L << 20;

// About this many particles per slab of sort_by_cell (a slab's walls
// follow its resin): two slabs span fewer than 32,767 particles.
constexpr long kSlabParticles = 8192;

// Cells are numbered along the owned particles' shortest axis first and
// their longest last (stride): sorted by cell, the particles near one
// another in space lie near one another in memory, whatever the domain's
// orientation. A particle's neighbours then span 3^(D-1) short rows of
// cells in memory instead of long ones (on the 99k channel, 720 x 132,
// about 1,100 particles' records instead of 6,000; docs/performance.md,
// "Cells numbered along the short axis first"). No result depends on the
// order: every sum runs in global-id order.
template <int D>
struct Grid {
  Vec<D> lo;
  std::array<double, 3> inv_cell{1, 1, 1};
  std::array<long, 3> n{1, 1, 1};
  std::array<long, 3> stride{1, 1, 1};
  int slow = 0;  // the axis numbered last (stride: the others' cells)

  // A NaN coordinate goes to cell 0.
  long coord(const Vec<D>& x, int k) const {
    const double c = std::floor((x[k] - lo[k]) * inv_cell[k]);
    if (!(c > 0.0)) return 0;
    return c < static_cast<double>(n[k] - 1) ? static_cast<long>(c) : n[k] - 1;
  }
  long cell(long cx, long cy, long cz) const {
    return cx * stride[0] + cy * stride[1] + cz * stride[2];
  }
  long index(const Vec<D>& x) const {
    long id = 0;
    for (int k = 0; k < D; ++k) id += coord(x, k) * stride[k];
    return id;
  }
  long cells() const { return n[0] * n[1] * n[2]; }
};

// Over the first `count` particles. The cells' corners sit on the grid of
// the first `aligned` ones' (where that grid's cells are `cell` wide): the
// list build's cells are then sort_by_cell's, and the particles of a cell
// follow one another (a cell's candidates serve them all in turn).
template <int D>
Grid<D> make_grid(const std::vector<Vec<D>>& x, std::size_t count, double cell,
                  std::size_t aligned = 0) {
  Grid<D> g;
  Vec<D> hi, lo_aligned, hi_aligned;
  g.lo.setConstant(std::numeric_limits<double>::infinity());
  hi.setConstant(-std::numeric_limits<double>::infinity());
  lo_aligned = g.lo;
  hi_aligned = hi;
  for (std::size_t i = 0; i < count; ++i) {
    g.lo = g.lo.cwiseMin(x[i]);
    hi = hi.cwiseMax(x[i]);
    if (i < aligned) {
      lo_aligned = lo_aligned.cwiseMin(x[i]);
      hi_aligned = hi_aligned.cwiseMax(x[i]);
    }
  }
  if (count == 0) {
    g.lo.setZero();
    hi.setZero();
  }
  for (int k = 0; k < D; ++k) {
    // Whole cells below the aligned grid's corner down to the others'.
    const double below = std::ceil((lo_aligned[k] - g.lo[k]) / cell);
    if (std::isfinite(below) && below >= 0.0 && below < static_cast<double>(kMaxCellsPerAxis)) {
      const double lo = lo_aligned[k] - below * cell;
      if (lo <= g.lo[k]) g.lo[k] = lo;
    }
  }
  double cells = 1.0;
  for (int k = 0; k < D; ++k) {
    const double extent = hi[k] - g.lo[k];
    g.inv_cell[k] = 1.0 / cell;
    const double along = std::floor(extent * g.inv_cell[k]) + 1.0;
    if (!std::isfinite(extent)) {
      g.inv_cell[k] = 0.0;
      g.n[k] = 1;
    } else if (along > static_cast<double>(kMaxCellsPerAxis)) {
      g.inv_cell[k] = static_cast<double>(kMaxCellsPerAxis - 1) / extent;
      g.n[k] = kMaxCellsPerAxis;
    } else {
      g.n[k] = std::max(1L, static_cast<long>(along));
    }
    cells *= static_cast<double>(g.n[k]);
  }
  // The axes by the extent of the aligned particles (all of them when none
  // are aligned), shortest first, ties in axis order: sort_by_cell's grid
  // and the list build's then number their cells alike (the ghosts, which
  // only the build's grid holds, do not change the order).
  const Vec<D> span = aligned > 0 ? Vec<D>(hi_aligned - lo_aligned) : Vec<D>(hi - g.lo);
  std::array<int, D> axes;
  std::iota(axes.begin(), axes.end(), 0);
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) {
    // A NaN or infinite extent sorts last (its axis holds one cell).
    const double ea = std::isfinite(span[a]) ? span[a] : std::numeric_limits<double>::max();
    const double eb = std::isfinite(span[b]) ? span[b] : std::numeric_limits<double>::max();
    return ea < eb;
  });
  long stride = 1;
  for (int a : axes) {
    g.stride[static_cast<std::size_t>(a)] = stride;
    stride *= g.n[static_cast<std::size_t>(a)];
  }
  g.slow = axes[D - 1];
  // Cell indices are int32 (the binning's scratch). Particles spread over
  // more: the run cannot continue (SimulationError, exit 3), as for a DEM
  // particle flung far (include/sphdem/dem/cell_list.hpp).
  if (cells >= static_cast<double>(std::numeric_limits<std::int32_t>::max()))
    throw SimulationError(fmt::format(
        "SPH particles spread over {:.3g} neighbour-grid cells of {:g} m or wider, past 2^31 "
        "(some particle far outside the domain: the resin blew up)",
        cells, cell));
  return g;
}

// One int32 scratch array shared by the binning of the list build and the
// sort by cell (never live at once), kept across rebuilds (no fresh pages
// at every rebuild): 8 bytes per particle where the two held 24
// (docs/performance.md, "Memory per particle"). It lives in the pair loop's
// record buffer, unused during a rebuild ("16-bit neighbour lists").
std::int32_t* int_scratch(std::size_t n) {
  return reinterpret_cast<std::int32_t*>(shared_scratch((n + 1) / 2));
}

// Counting sort of the first `count` particles into cells: items[start[c]
// .. start[c + 1]) are cell c's particles, in index order. cell_of and
// items hold `count` entries each.
template <int D>
void bin(const Grid<D>& g, const std::vector<Vec<D>>& x, std::size_t count,
         std::vector<std::int32_t>& start, std::int32_t* cell_of, std::int32_t* items) {
  start.assign(static_cast<std::size_t>(g.cells()) + 1, 0);
  thread_local std::vector<std::int32_t> fill;
  for (std::size_t i = 0; i < count; ++i) {
    cell_of[i] = static_cast<std::int32_t>(g.index(x[i]));
    ++start[static_cast<std::size_t>(cell_of[i]) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  fill.assign(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < count; ++i) items[fill[cell_of[i]]++] = static_cast<std::int32_t>(i);
}

// A counting sort of the particles into cells, each cell's resin before
// its walls: items[start[c] .. resin_end[c]) are cell c's resin particles,
// items[resin_end[c] .. start[c + 1]) its walls, in index order. Wall
// particles list only resin, so their search skips the walls' part of
// every cell (in 3D the walls outnumber the resin near a wall) instead of
// testing each one.
template <int D>
void bin_resin_first(const Grid<D>& g, const SphParticles<D>& ps, std::vector<std::int32_t>& start,
                     std::vector<std::int32_t>& resin_end, std::int32_t* cell_of,
                     std::int32_t* items) {
  const std::size_t count = ps.size();
  start.assign(static_cast<std::size_t>(g.cells()) + 1, 0);
  for (std::size_t i = 0; i < count; ++i) {
    cell_of[i] = static_cast<std::int32_t>(g.index(ps.x[i]));
    ++start[static_cast<std::size_t>(cell_of[i]) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  resin_end.assign(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < count; ++i)
    if (ps.kind[i] != Kind::Wall) items[resin_end[cell_of[i]]++] = static_cast<std::int32_t>(i);
  thread_local std::vector<std::int32_t> fill;
  fill.assign(resin_end.begin(), resin_end.end());
  for (std::size_t i = 0; i < count; ++i)
    if (ps.kind[i] == Kind::Wall) items[fill[cell_of[i]]++] = static_cast<std::int32_t>(i);
}

// A position rounded to float; beyond float's range, an infinity (the
// cast would be undefined), which the rebuild test answers with a rebuild.
float to_float(double v) {
  constexpr double kMax = std::numeric_limits<float>::max();
  if (v > kMax) return std::numeric_limits<float>::infinity();
  if (v < -kMax) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(v);
}

// An offset a 16-bit list holds (kWideRow, -32768, marks a wide list).
bool fits_16(std::int32_t offset) {
  return offset >= -32767 && offset <= 32767;
}

// The largest gid a packed candidate key holds (the upper 32 bits).
constexpr std::int64_t kMaxPackedGid = std::numeric_limits<std::uint32_t>::max();

// The same order when some gid does not fit 32 bits: the keys' indices
// sorted by (gid, position) read from the particles.
template <int D>
void sort_unpacked(const SphParticles<D>& ps, std::uint64_t* key, std::size_t m) {
  std::sort(key, key + m, [&](std::uint64_t p, std::uint64_t q) {
    const auto a = static_cast<std::int32_t>(p & 0xffffffffU);
    const auto b = static_cast<std::int32_t>(q & 0xffffffffU);
    if (ps.gid[a] != ps.gid[b]) return ps.gid[a] < ps.gid[b];
    return neighbor_detail::image_before<D>(ps, a, b);
  });
}

}  // namespace

template <int D>
void NeighborList<D>::build(const SphParticles<D>& ps) {
  const std::size_t n = ps.size(), n_own = ps.n_owned;
  const double rc = cutoff(), rc2 = rc * rc;
  // In 3D, cells of half the cut-off: the 5^3 cells around a particle
  // hold 125 (rc/2)^3 = 15.6 rc^3 of candidates where 3^3 cells of rc hold
  // 27 rc^3 (about 290 against 500 at the plate's 2.64 spacings).
  constexpr long kReach = D == 3 ? 2 : 1;  // cells per cut-off
  const Grid<D> g = make_grid<D>(ps.x, n, rc / static_cast<double>(kReach), n_own);
  std::int32_t* scratch = int_scratch(2 * n);
  const std::int32_t* cell_items = scratch + n;
  bin_resin_first<D>(g, ps, cell_start_, cell_resin_end_, scratch, scratch + n);

  // Each candidate as one 64-bit key, gid << 32 | index, when every gid
  // fits 32 bits: a plain integer sort gives the gid order (the index
  // breaks no tie that matters: ties are periodic images, ordered by
  // position afterwards). Otherwise the (gid, index) pairs with the same
  // comparator (sort_unpacked).
  const bool packed = std::all_of(ps.gid.begin(), ps.gid.begin() + static_cast<std::ptrdiff_t>(n),
                                  [](std::int64_t id) { return id >= 0 && id <= kMaxPackedGid; });
  // 2D: one sorted candidate list per cell, shared by the cell's particles
  // (cell_candidates.hpp). In 3D a cell's 5^3 block holds about 290
  // candidates for about 2 particles: sorting those would cost more than
  // the per-particle sort of about 60 kept ones.
  const bool shared = D == 2 && packed;
#if defined(SPHDEM_CANDIDATES_AVX512)
  // 3D with packed keys: the search eight candidates at a time, in the
  // order of the grid's fast axis (cell_candidates.hpp).
  thread_local neighbor_detail::BinnedCandidates<D> binned;
  const bool binned_ready = D == 3 && packed && n > 0;
  int fast = 0;
  for (int k = 0; k < D; ++k)
    if (g.stride[static_cast<std::size_t>(k)] == 1 && g.n[static_cast<std::size_t>(k)] > 1)
      fast = k;
#else
  constexpr bool binned_ready = false;
#endif
  thread_local neighbor_detail::CellCandidates<D> cell_candidates;
  long prepared = -1;  // the cell whose candidates cell_candidates holds
  thread_local std::vector<std::uint64_t> keys, spare;
  thread_local std::vector<std::int32_t> list;
#if defined(SPHDEM_CANDIDATES_AVX512)
  if (binned_ready) {
    binned.fill(ps, cell_items, n);
    // Room for any particle's candidates: its 5^3 cells at most the fullest
    // cell's count each (no per-particle count of its candidates).
    std::int32_t fullest = 0;
    for (std::size_t c = 0; c + 1 < cell_start_.size(); ++c)
      fullest = std::max(fullest, cell_start_[c + 1] - cell_start_[c]);
    const std::size_t room = std::min<std::size_t>(n, 125 * static_cast<std::size_t>(fullest));
    if (keys.size() < room + 8) keys.resize(room + 8);  // near() stores whole vectors
    if (list.size() < room + 8) list.resize(room + 8);
  }
#endif
  // The storage of the last build to start with (3D lists rarely fit 16
  // bits: no 16-bit array and its conversion at every build there).
  const bool wide_first = all_wide_;
  offset_.assign(n_own + 1, 0);
  narrow_.clear();
  wide_.clear();
  wide_rows_.clear();
  wide_starts_.clear();
  ghost_listers_.clear();
  const std::size_t expected = n_own * (D == 2 ? 24 : 60);
  if (wide_first)
    wide_.reserve(expected);
  else
    narrow_.reserve(expected);
  std::size_t pairs = 0, far_pairs = 0;  // far: in lists with an offset beyond 16 bits
  for (std::size_t i = 0; i < n_own; ++i) {
    const Vec<D>& xi = ps.x[i];
    const bool wall_i = ps.kind[i] == Kind::Wall;
    std::array<long, 3> c{0, 0, 0}, lo{0, 0, 0}, hi{0, 0, 0};
    for (int k = 0; k < D; ++k) {
      c[k] = g.coord(xi, k);
      lo[k] = std::max(0L, c[k] - kReach);
      hi[k] = std::min(g.n[k] - 1, c[k] + kReach);
    }
    // Walls list resin only: in the shared form a wall's candidates
    // include the walls, masked out by near().
    const bool resin_only = wall_i && !shared;
    std::size_t candidates = 0;
    for (long cz = lo[2]; !binned_ready && cz <= hi[2]; ++cz)
      for (long cy = lo[1]; cy <= hi[1]; ++cy) {
        for (long cx = lo[0]; cx <= hi[0]; ++cx) {
          const long cell = g.cell(cx, cy, cz);
          candidates += static_cast<std::size_t>(
              (resin_only ? cell_resin_end_[cell] : cell_start_[cell + 1]) - cell_start_[cell]);
        }
      }
    if (keys.size() < candidates) keys.resize(candidates);
    if (list.size() < candidates + 8) list.resize(candidates + 8);  // near() stores whole vectors
    // Every candidate is written; per particle, kept when inside the
    // cut-off: no branch on the distance test, taken about a third of the time.
    std::uint64_t* key = keys.data();
    const long own_cell = g.cell(c[0], c[1], c[2]);
    const bool gather = !shared || own_cell != prepared;
    std::size_t m = 0;
#if defined(SPHDEM_CANDIDATES_AVX512)
    if constexpr (D == 3) {
      if (binned_ready) {
        // Along the axis numbered first (stride 1) a row of cells is one run
        // of candidates (a wall's: each cell's resin part).
        const int a = fast, b = (fast + 1) % 3, e = (fast + 2) % 3;
        const auto self =
            static_cast<std::uint64_t>(ps.gid[i]) << 32 | static_cast<std::uint32_t>(i);
        std::uint64_t* out = key;
        std::array<long, 3> cc{};
        for (cc[e] = lo[e]; cc[e] <= hi[e]; ++cc[e])
          for (cc[b] = lo[b]; cc[b] <= hi[b]; ++cc[b]) {
            cc[a] = lo[a];
            const long first = g.cell(cc[0], cc[1], cc[2]);
            const long last = first + (hi[a] - lo[a]);
            if (!resin_only) {
              out = binned.near(xi, rc2, self, static_cast<std::size_t>(cell_start_[first]),
                                static_cast<std::size_t>(cell_start_[last + 1]), out);
            } else {
              for (long cell = first; cell <= last; ++cell)
                out = binned.near(xi, rc2, self, static_cast<std::size_t>(cell_start_[cell]),
                                  static_cast<std::size_t>(cell_resin_end_[cell]), out);
            }
          }
        m = static_cast<std::size_t>(out - key);
      }
    }
#endif
    for (long cz = lo[2]; gather && !binned_ready && cz <= hi[2]; ++cz)
      for (long cy = lo[1]; cy <= hi[1]; ++cy)
        for (long cx = lo[0]; cx <= hi[0]; ++cx) {
          const long cell = g.cell(cx, cy, cz);
          const std::int32_t last = resin_only ? cell_resin_end_[cell] : cell_start_[cell + 1];
          for (std::int32_t s = cell_start_[cell]; s < last; ++s) {
            const std::int32_t j = cell_items[s];
            key[m] = static_cast<std::uint64_t>(ps.gid[j]) << 32 | static_cast<std::uint32_t>(j);
            m += static_cast<std::size_t>(shared ||
                                          ((neighbor_detail::distance2<D>(xi, ps.x[j]) < rc2) &
                                           (static_cast<std::size_t>(j) != i)));
          }
        }
    if (shared) {
      if (gather) cell_candidates.prepare(ps, keys, m);
      prepared = own_cell;
      m = cell_candidates.near(xi, static_cast<std::int32_t>(i), wall_i, rc2, list.data());
    } else {
      if (packed)
        neighbor_detail::sort_packed<D>(ps, key, m, spare);
      else
        sort_unpacked<D>(ps, key, m);
      for (std::size_t k = 0; k < m; ++k) list[k] = static_cast<std::int32_t>(key[k] & 0xffffffffU);
    }
    const auto own = static_cast<std::int32_t>(i);
    const std::int32_t* const nb = list.data();
    const bool fits = std::all_of(nb, nb + m, [&](std::int32_t j) { return fits_16(j - own); });
    if (std::any_of(nb, nb + m,
                    [&](std::int32_t j) { return static_cast<std::size_t>(j) >= n_own; }))
      ghost_listers_.push_back(static_cast<std::uint32_t>(i));
    if (wide_first || !fits) {
      if (!wide_first) {  // its 16-bit slots only say "kept wide"
        narrow_.resize(narrow_.size() + m, kWideRow);
        wide_rows_.push_back(static_cast<std::uint32_t>(i));
        wide_starts_.push_back(static_cast<std::uint32_t>(wide_.size()));
      }
      wide_.insert(wide_.end(), nb, nb + m);
    } else {
      const std::size_t at = narrow_.size();
      narrow_.resize(at + m);
      for (std::size_t k = 0; k < m; ++k) narrow_[at + k] = static_cast<std::int16_t>(nb[k] - own);
    }
    if (!fits) far_pairs += m;
    pairs += m;
    if (pairs > std::numeric_limits<std::uint32_t>::max())
      throw std::length_error("sphdem: more than 2^32 neighbour pairs on one rank");
    offset_[i + 1] = static_cast<std::uint32_t>(pairs);
  }
  const bool all_wide = 4 * far_pairs > pairs;
  if (wide_first && !all_wide)
    store_mixed();
  else if (!wide_first && all_wide)
    store_all_wide();
  all_wide_ = all_wide;
  wide_used_ = wide_.size();
  resize_field(x_at_build_, n_own);
  double largest = 0.0;  // of the bounds' sums |f_x| + |f_y| (+ |f_z|); a NaN stays out
  for (std::size_t i = 0; i < n_own; ++i) {
    double size = 0.0;
    for (int k = 0; k < D; ++k) {
      x_at_build_[i][k] = to_float(ps.x[i][k]);
      size += std::abs(static_cast<double>(x_at_build_[i][k]));
    }
    if (size > largest) largest = size;
  }
  const double quick = 0.5 * skin_ - (kRoundingRelative * largest + D * kRoundingTiny);
  quick_limit2_ = quick > 0.0 ? quick * quick : -1.0;
  ++builds_;
}

template <int D>
std::size_t NeighborList<D>::wide_start(std::size_t i) const {
  const auto at = std::lower_bound(wide_rows_.begin(), wide_rows_.end(), i);
  return wide_starts_[static_cast<std::size_t>(at - wide_rows_.begin())];
}

// Every list as 32-bit indices, from the mixed storage (all_wide_ false).
template <int D>
void NeighborList<D>::store_all_wide() {
  std::vector<std::int32_t> all(total_pairs());
  for (std::size_t i = 0; i + 1 < offset_.size(); ++i) {
    const NeighborRow nb = row(i);
    for (std::size_t n = begin(i); n < end(i); ++n) all[n] = nb[n];
  }
  wide_.swap(all);
  std::vector<std::int16_t>().swap(narrow_);  // its memory back
  wide_rows_.clear();
  wide_starts_.clear();
}

// The mixed storage from every list in wide_ (all_wide_ true).
template <int D>
void NeighborList<D>::store_mixed() {
  std::vector<std::int16_t> narrow(total_pairs());
  std::vector<std::int32_t> far;
  wide_rows_.clear();
  wide_starts_.clear();
  for (std::size_t i = 0; i + 1 < offset_.size(); ++i) {
    const auto own = static_cast<std::int32_t>(i);
    const auto first = wide_.begin() + begin(i), last = wide_.begin() + end(i);
    if (std::all_of(first, last, [&](std::int32_t j) { return fits_16(j - own); })) {
      for (std::size_t n = begin(i); n < end(i); ++n)
        narrow[n] = static_cast<std::int16_t>(wide_[n] - own);
    } else {
      for (std::size_t n = begin(i); n < end(i); ++n) narrow[n] = kWideRow;
      wide_rows_.push_back(static_cast<std::uint32_t>(i));
      wide_starts_.push_back(static_cast<std::uint32_t>(far.size()));
      far.insert(far.end(), first, last);
    }
  }
  narrow_.swap(narrow);
  wide_.swap(far);
}

// The stored position f of a coordinate x is within 2^-24 |x| of it
// (round to nearest), so within 2^-23 |f| with room for this test's own
// rounding, or within the smallest float near zero: the particle has moved
// at most |x_now - f| + that bound since the build.
// A move under the build's quick limit is under every particle's own
// limit: only the others compute theirs (the verdict is the per-particle
// one either way).
// The squared move of every particle is fma(dz, dz, fma(dy, dy, dx dx)) in
// both forms (the one GCC gave the scalar loop), so the verdict does not
// depend on the form.
template <int D>
bool NeighborList<D>::beyond_own_limit(std::size_t i, double d2) const {
  double size = 0.0;
  for (int k = 0; k < D; ++k) size += std::abs(static_cast<double>(x_at_build_[i][k]));
  const double limit = 0.5 * skin_ - (kRoundingRelative * size + D * kRoundingTiny);
  return limit <= 0.0 || d2 > limit * limit;
}

template <int D>
bool NeighborList<D>::needs_rebuild(const SphParticles<D>& ps) const {
  if (x_at_build_.size() != ps.n_owned) return true;
#if defined(SPHDEM_PARTICLE_LANES)
  for (std::size_t i = 0; i < ps.n_owned; i += 8)
    if (moved_too_far(ps.x.data()->data(), i, lanes::first(ps.n_owned - i))) return true;
  return false;
#elif defined(SPHDEM_PARTICLE_LANES4)
  if (ps.n_owned == 0) return false;
  const double* const x = ps.x.data()->data();
  std::size_t i = 0;
  for (; i + 4 <= ps.n_owned; i += 4)
    if (moved_too_far4(x, i)) return true;
  return moved_too_far(x, i, ps.n_owned - i);
#else
  return ps.n_owned > 0 && moved_too_far(ps.x.data()->data(), 0, ps.n_owned);
#endif
}

template <int D>
typename NeighborList<D>::MoveBox NeighborList<D>::move_box(const SphParticles<D>& ps) const {
  MoveBox box;
  if (x_at_build_.size() != ps.n_owned) {
    box.fill(std::numeric_limits<double>::infinity());
    return box;
  }
  // From -inf: a rank without owned particles adds nothing to the maxima.
  box.fill(-std::numeric_limits<double>::infinity());
  bool finite = true;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    // The build's position is within `rounding` of the float kept
    // (beyond_own_limit), so the true move lies within `rounding` of
    // `move` along every axis.
    double size = 0.0, d2 = 0.0;
    Vec<D> move;
    for (int k = 0; k < D; ++k) {
      const double then = static_cast<double>(x_at_build_[i][static_cast<std::size_t>(k)]);
      move[k] = ps.x[i][k] - then;
      size += std::abs(then);
      d2 = lanes::mul_add(move[k], move[k], d2);
    }
    const double rounding = lanes::mul_add(size, kRoundingRelative, D * kRoundingTiny);
    for (int k = 0; k < D; ++k) {
      box[static_cast<std::size_t>(k)] =
          std::max(box[static_cast<std::size_t>(k)], move[k] + rounding);
      box[static_cast<std::size_t>(D + k)] =
          std::max(box[static_cast<std::size_t>(D + k)], rounding - move[k]);
    }
    box[2 * D] = std::max(box[2 * D], d2);
    box[2 * D + 1] = std::max(box[2 * D + 1], rounding);
    finite = finite && d2 < std::numeric_limits<double>::infinity();
  }
  if (!finite) box.fill(std::numeric_limits<double>::infinity());
  return box;
}

template <int D>
bool NeighborList<D>::box_needs_rebuild(const MoveBox& box, double max_move) const {
  double diagonal2 = 0.0;
  for (int k = 0; k < D; ++k) {
    const double side = box[static_cast<std::size_t>(k)] + box[static_cast<std::size_t>(D + k)];
    diagonal2 += side * side;
  }
  const double farthest = std::sqrt(box[2 * D]) + box[2 * D + 1];
  // A relative hair for the rounding of these few operations; a NaN rebuilds.
  const double margin = 1.0 - 1e-12;
  return !(diagonal2 <= skin_ * skin_ * margin) || !(farthest <= max_move * skin_ * margin);
}

template <int D>
void sort_by_cell(SphParticles<D>& ps, double cell) {
  const std::size_t n = ps.n_owned;
  const Grid<D> g = make_grid<D>(ps.x, n, cell);
  // By cell (a counting sort), then by global id within each cell: the
  // order of sorting by the pair (cell, gid), with 8 bytes of scratch per
  // particle instead of a long key and a size_t order.
  thread_local std::vector<std::int32_t> start;
  // The scratch holds cell_of and order, then room for one field's values,
  // which the permutation at the end gathers into.
  const std::size_t field_bytes = widest_field(ps) * n + 64;  // 64: room to align
  std::int32_t* cell_of = int_scratch(2 * n + field_bytes / sizeof(std::int32_t));
  std::int32_t* order = cell_of + n;
  const std::span<std::byte> spare(reinterpret_cast<std::byte*>(order + n), field_bytes);
  bin<D>(g, ps.x, n, start, cell_of, order);
  for (std::size_t c = 0; c + 1 < start.size(); ++c)
    std::sort(order + start[c], order + start[c + 1],
              [&](std::int32_t a, std::int32_t b) { return ps.gid[a] < ps.gid[b]; });
  // Then in slabs of whole cell layers across the slowest axis, each
  // slab's resin first, then its walls (into cell_of's half of the
  // scratch, no longer needed): the lanes of the passes and the pair loop
  // meet few walls among the resin (a wall in every column of cells slowed
  // the 21k channel by 2-3 %), and a resin particle's wall neighbours lie
  // at most two slabs away, within a 16-bit list's offsets (walls after
  // all the resin put 2.9 % of the 99k channel's pairs in 32-bit lists).
  // docs/performance.md, "Cells numbered along the short axis first".
  const long cells = g.cells();
  const long layer = g.stride[static_cast<std::size_t>(g.slow)];  // cells per layer
  const long per_layer =
      std::max<long>(1, static_cast<long>(n) / g.n[static_cast<std::size_t>(g.slow)]);
  const long slab = layer * std::max<long>(1, kSlabParticles / per_layer);  // cells per slab
  std::int32_t* const sorted = cell_of;
  std::size_t at = 0;
  for (long first = 0; first < cells; first += slab) {
    const std::int32_t* const from = order + start[static_cast<std::size_t>(first)];
    const std::int32_t* const to =
        order + start[static_cast<std::size_t>(std::min(cells, first + slab))];
    for (const std::int32_t* p = from; p < to; ++p)
      if (ps.kind[*p] != Kind::Wall) sorted[at++] = *p;
    for (const std::int32_t* p = from; p < to; ++p)
      if (ps.kind[*p] == Kind::Wall) sorted[at++] = *p;
  }
  permute_owned_fields(ps, std::span<const std::int32_t>(sorted, n), spare);
}

template class NeighborList<2>;
template class NeighborList<3>;
template void sort_by_cell<2>(SphParticles<2>&, double);
template void sort_by_cell<3>(SphParticles<3>&, double);

}  // namespace sphdem
