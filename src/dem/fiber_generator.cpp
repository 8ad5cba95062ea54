// Random sequential placement of straight fibers (dem_fibers.hpp), tile
// by tile so that any share of the region places the same fibers. The
// random numbers of fiber f's attempt a come from SplitMix64 (Steele, Lea
// and Flood, OOPSLA 2014) started from a hash of (seed, f, a), and are
// turned into doubles by hand (53 random bits), not by
// std::uniform_real_distribution, whose output the standard leaves to each
// library: a seed gives the same fibers everywhere, on any rank count.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "sphdem/core/clamped_cast.hpp"
#include "sphdem/dem/dem_fibers.hpp"
#include "sphdem/dem/fiber_bend.hpp"

namespace sphdem {

namespace {

constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ULL;

// SplitMix64's output function.
std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The random numbers of one attempt of one fiber: they depend on (seed,
// fiber, attempt) only, never on what was drawn before.
class CandidateStream {
 public:
  CandidateStream(std::uint64_t seed, std::uint64_t fiber, std::uint64_t attempt)
      : state_(mix64(mix64(mix64(seed + kGolden) ^ (fiber + kGolden)) ^ (attempt + kGolden))) {}
  std::uint64_t operator()() { return mix64(state_ += kGolden); }

 private:
  std::uint64_t state_;
};

template <class Rng>
double uniform01(Rng& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

template <int D>
double region_measure(const FiberSpec<D>& s) {
  double m = 1;
  for (int d = 0; d < D; ++d) m *= s.hi[d] - s.lo[d];
  return m;
}

template <int D, class Rng>
Vec<D> draw_direction(const FiberSpec<D>& s, Rng& rng) {
  if (s.direction) return s.direction->normalized();
  if constexpr (D == 2) {
    const double a = s.angle ? *s.angle : std::numbers::pi * uniform01(rng);
    return Vec<D>(std::cos(a), std::sin(a));
  } else {
    // Uniform on the sphere: z uniform in [-1, 1], azimuth uniform.
    const double z = 2.0 * uniform01(rng) - 1.0, phi = 2.0 * std::numbers::pi * uniform01(rng);
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec<D>(rho * std::cos(phi), rho * std::sin(phi), z);
  }
}

// Where a fiber's particle centres lie relative to its centre c, for its
// axis u: straight (c + (2 r j - half) u, as always), or on the seeded arc
// (fiber_bend.hpp), bulging towards bend_direction(u).
template <int D>
struct Layout {
  double radius = 0, half = 0;  // half: centre to end-particle centre, straight
  std::optional<FiberBend> bend;

  explicit Layout(const FiberSpec<D>& s)
      : radius(s.radius), half((s.particles_per_fiber - 1) * s.radius) {
    if (s.bend > 0) bend = fiber_bend(s.particles_per_fiber, s.radius, s.bend);
  }
  Vec<D> at(const Vec<D>& c, const Vec<D>& u, int j) const {
    if (!bend) return c + (2.0 * radius * j - half) * u;
    return c + (bend->along[j] * u + bend->across[j] * bend_direction<D>(u));
  }
  // The lowest and highest centre offset along axis d.
  std::pair<double, double> extent(const Vec<D>& u, int d) const {
    if (!bend) return {-half * std::abs(u[d]), half * std::abs(u[d])};
    const Vec<D> v = bend_direction<D>(u);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t j = 0; j < bend->along.size(); ++j) {
      const double x = bend->along[j] * u[d] + bend->across[j] * v[d];
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    return {lo, hi};
  }
  // The farthest centre from c.
  double reach() const {
    if (!bend) return half;
    double most = 0;
    for (std::size_t j = 0; j < bend->along.size(); ++j)
      most = std::max(most, std::hypot(bend->along[j], bend->across[j]));
    return most;
  }
  // The distance between the end particles' centres.
  double end_to_end() const { return bend ? bend->along.back() - bend->along.front() : 2 * half; }
};

// Throws when no fiber of the spec can lie in the region (issue 12 part 5:
// long fibers), before the attempts: its fixed direction does not fit
// (along some axis the chain, end particles included, is longer than the
// region), or, at random orientations, it is longer than the region's
// diagonal (no direction fits).
template <int D>
void check_fiber_fits(const FiberSpec<D>& s, const Layout<D>& layout) {
  const double r = s.radius, length = 2.0 * r * s.particles_per_fiber;
  const Vec<D> room = (s.hi - s.lo).array() - 2.0 * r;
  const double half = (s.particles_per_fiber - 1) * r;
  bool fits = (room.array() >= 0).all();
  std::string where;
  if (s.direction || (D == 2 && s.angle)) {
    CandidateStream unused(0, 0, 0);
    const Vec<D> u = draw_direction(s, unused);
    for (int d = 0; d < D; ++d) {
      if (!layout.bend) {
        fits = fits && 2.0 * half * std::abs(u[d]) <= room[d];
      } else {
        const auto [lo, hi] = layout.extent(u, d);
        fits = fits && hi - lo <= room[d];
      }
    }
    where = "at its fixed orientation";
  } else {
    fits = fits && layout.end_to_end() <= room.norm();
    where = "at any orientation";
  }
  if (!fits) {
    throw std::runtime_error(fmt::format(
        "fibers: a fiber of {} particles ({:.4g} m long, aspect ratio {}) cannot lie in the "
        "region {}; lower `particles_per_fiber` or enlarge `region`",
        s.particles_per_fiber, length, s.particles_per_fiber, where));
  }
}

// Points (particle centres) in buckets of a hash grid, for the overlap
// test: memory for the points only, whatever the region's size.
template <int D>
class Buckets {
 public:
  Buckets(const Vec<D>& lo, double cell) : lo_(lo), cell_(cell) {}
  void add(const Vec<D>& x, std::size_t id) { items_[key(coords(x))].push_back(id); }
  // True when a stored point is closer than `dmin` to x.
  bool any_within(const Vec<D>& x, double dmin, const std::vector<Vec<D>>& pts) const {
    const auto c = coords(x);
    std::array<std::int64_t, 3> k{0, 0, 0};
    const std::int64_t zspan = D == 3 ? 1 : 0;
    for (k[2] = c[2] - zspan; k[2] <= c[2] + zspan; ++k[2])
      for (k[1] = c[1] - 1; k[1] <= c[1] + 1; ++k[1])
        for (k[0] = c[0] - 1; k[0] <= c[0] + 1; ++k[0]) {
          const auto it = items_.find(key(k));
          if (it == items_.end()) continue;
          for (std::size_t id : it->second)
            if ((pts[id] - x).squaredNorm() < dmin * dmin) return true;
        }
    return false;
  }

 private:
  std::array<std::int64_t, 3> coords(const Vec<D>& x) const {
    std::array<std::int64_t, 3> c{0, 0, 0};
    for (int d = 0; d < D; ++d) c[d] = fiber_bucket_coord(x[d], lo_[d], cell_);
    return c;
  }
  static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    // 21 bits per axis: the region spans far fewer buckets.
    const auto b = [](std::int64_t v) { return static_cast<std::uint64_t>(v) & 0x1fffffULL; };
    return b(c[0]) | (b(c[1]) << 21) | (b(c[2]) << 42);
  }
  Vec<D> lo_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> items_;
};

// The most tiles of a region (2^31): far beyond any placement that ends.
constexpr double kMaxTiles = 2147483648.0;

// The fixed grid of tiles over the region (the same for every share): at
// least `edge` wide, so that fibers whose centres lie in two tiles that
// share no face, edge or corner never come within the gap of each other.
// A tile's colour is the parity of its coordinates (2^D colours): two
// neighbouring tiles never have the same.
template <int D>
struct Tiles {
  std::array<std::int64_t, 3> n{1, 1, 1};
  Vec<D> lo, hi, size;

  // Counted as doubles first: a region of absurd extent is an error
  // (more than kMaxTiles tiles), not an overflowing cast.
  Tiles(const Vec<D>& region_lo, const Vec<D>& region_hi, double edge)
      : lo(region_lo), hi(region_hi) {
    double tiles = 1.0;
    for (int d = 0; d < D; ++d) {
      const double along = std::max(1.0, std::trunc((hi[d] - lo[d]) / edge));
      tiles *= along;
      if (!(tiles <= kMaxTiles)) {
        throw std::runtime_error(fmt::format(
            "fibers: the region would take more than 2^31 tiles of {:.3g} m (it spans {:.3g} m "
            "along axis {}); is an extent of `region` off by orders of magnitude?",
            edge, hi[d] - lo[d], d));
      }
      n[d] = static_cast<std::int64_t>(along);
      size[d] = (hi[d] - lo[d]) / static_cast<double>(n[d]);
    }
  }
  std::int64_t count() const { return n[0] * n[1] * n[2]; }
  // The tile coordinate of position t along d (clamped; infinities too).
  std::int64_t along(int d, double t) const {
    const double q = (t - lo[d]) / size[d];
    if (!(q >= 0)) return 0;
    if (q >= static_cast<double>(n[d])) return n[d] - 1;
    return std::min<std::int64_t>(static_cast<std::int64_t>(q), n[d] - 1);
  }
  std::int64_t index(const std::array<std::int64_t, 3>& c) const {
    return (c[2] * n[1] + c[1]) * n[0] + c[0];
  }
  std::array<std::int64_t, 3> coords_of(std::int64_t t) const {
    return {t % n[0], (t / n[0]) % n[1], t / (n[0] * n[1])};
  }
  int colour(std::int64_t t) const {
    const auto c = coords_of(t);
    int k = 0;
    for (int d = 0; d < D; ++d) k |= static_cast<int>(c[d] & 1) << d;
    return k;
  }
  void box(std::int64_t t, Vec<D>& blo, Vec<D>& bhi) const {
    const auto c = coords_of(t);
    for (int d = 0; d < D; ++d) {
      blo[d] = lo[d] + static_cast<double>(c[d]) * size[d];
      bhi[d] = c[d] + 1 == n[d] ? hi[d] : lo[d] + static_cast<double>(c[d] + 1) * size[d];
    }
  }
  // Fibers per tile: every tile has the same size, so the same share of
  // the count, the remainder spread evenly over the tile order (Bresenham):
  // tile t holds fibers [first_fiber(t), first_fiber(t + 1)).
  std::int64_t first_fiber(std::int64_t t, std::int64_t target) const {
    const std::int64_t T = count();
    return t * (target / T) + (t * (target % T)) / T;
  }
  std::int64_t tile_of_fiber(std::int64_t f, std::int64_t target) const {
    std::int64_t a = 0, b = count() - 1;  // the last tile whose first fiber is <= f
    while (a < b) {
      const std::int64_t m = (a + b + 1) / 2;
      if (first_fiber(m, target) <= f)
        a = m;
      else
        b = m - 1;
    }
    return a;
  }
  // The neighbours of t (sharing a face, edge or corner) of a lower colour.
  template <class F>
  void lower_neighbours(std::int64_t t, F&& f) const {
    const auto c = coords_of(t);
    const int own = colour(t);
    std::array<std::int64_t, 3> k{0, 0, 0};
    const std::int64_t zspan = D == 3 ? 1 : 0;
    for (k[2] = c[2] - zspan; k[2] <= c[2] + zspan; ++k[2])
      for (k[1] = c[1] - 1; k[1] <= c[1] + 1; ++k[1])
        for (k[0] = c[0] - 1; k[0] <= c[0] + 1; ++k[0]) {
          bool inside = true;
          for (int d = 0; d < 3; ++d) inside = inside && k[d] >= 0 && k[d] < n[d];
          if (!inside) continue;
          const std::int64_t j = index(k);
          if (colour(j) < own) f(j);
        }
  }
};

// About this many fibers per tile: tiles much larger than a fiber, so that
// a fiber's retries (in its tile) see nearly the freedom of the whole
// region, small enough that a rank's share is many tiles.
constexpr double kFibersPerTile = 32;

template <int D>
Tiles<D> fiber_tiles(const FiberSpec<D>& s, const Layout<D>& layout, int target) {
  const double r = s.radius, dmin = 2.0 * r + s.gap, half = layout.reach();
  double measure = 1;
  for (int d = 0; d < D; ++d) measure *= s.hi[d] - s.lo[d];
  // At least a fiber and the gap (a hair more: round-off never brings two
  // tiles of one colour within the gap).
  double edge = (2.0 * half + dmin) * (1.0 + 1e-9);
  if (target > 0) edge = std::max(edge, std::pow(measure * kFibersPerTile / target, 1.0 / D));
  return Tiles<D>(s.lo, s.hi, edge);
}

// The tiles a share places: those that touch its boxes (with a margin
// against round-off: a fiber's centre lies in its tile's closed box), then
// the neighbours of lower colour of every tile in the set, colour by colour
// from the highest (a tile's fibers are tested against those).
template <int D>
std::set<std::int64_t> tiles_of_share(const Tiles<D>& tiles, const FiberShare<D>& share) {
  std::set<std::int64_t> need;
  for (const auto& [blo, bhi] : share.boxes) {
    std::array<std::int64_t, 3> a{0, 0, 0}, b{0, 0, 0};
    for (int d = 0; d < D; ++d) {
      const double margin = 1e-9 * tiles.size[d];
      a[d] = tiles.along(d, blo[d] - margin);
      b[d] = tiles.along(d, bhi[d] + margin);
    }
    std::array<std::int64_t, 3> k{0, 0, 0};
    for (k[2] = a[2]; k[2] <= b[2]; ++k[2])
      for (k[1] = a[1]; k[1] <= b[1]; ++k[1])
        for (k[0] = a[0]; k[0] <= b[0]; ++k[0]) need.insert(tiles.index(k));
  }
  for (int colour = (1 << D) - 1; colour > 0; --colour) {
    std::vector<std::int64_t> these;
    for (const std::int64_t t : need)
      if (tiles.colour(t) == colour) these.push_back(t);
    for (const std::int64_t t : these)
      tiles.lower_neighbours(t, [&](std::int64_t j) { need.insert(j); });
  }
  return need;
}

// One candidate of fiber f: a direction, then a centre uniform where the
// fiber lies inside the region (and, after the first attempt, in its tile).
template <int D>
struct Candidate {
  Vec<D> u, c;
  bool fits = true;
};

template <int D>
Candidate<D> draw_candidate(const FiberSpec<D>& s, const Layout<D>& layout, int f, int attempt,
                            const Vec<D>* tile_lo = nullptr, const Vec<D>* tile_hi = nullptr) {
  CandidateStream rng(s.seed, static_cast<std::uint64_t>(f), static_cast<std::uint64_t>(attempt));
  Candidate<D> k;
  k.u = draw_direction(s, rng);
  const double half = layout.half;
  for (int d = 0; d < D; ++d) {
    double lo = s.lo[d] + s.radius + half * std::abs(k.u[d]);
    double hi = s.hi[d] - s.radius - half * std::abs(k.u[d]);
    if (layout.bend) {
      const auto [below, above] = layout.extent(k.u, d);
      lo = s.lo[d] + s.radius - below;
      hi = s.hi[d] - s.radius - above;
    }
    if (tile_lo) {
      lo = std::max(lo, (*tile_lo)[d]);
      hi = std::min(hi, (*tile_hi)[d]);
    }
    const double t = uniform01(rng);
    k.fits = k.fits && hi >= lo;
    k.c[d] = lo + t * (hi - lo);
  }
  return k;
}

template <int D>
void check_spec(const FiberSpec<D>& s) {
  if (s.radius <= 0 || s.particles_per_fiber < 1) {
    throw std::runtime_error("fibers: radius must be positive and particles_per_fiber >= 1");
  }
  for (int d = 0; d < D; ++d) {
    if (!(s.hi[d] > s.lo[d])) throw std::runtime_error("fibers: the region is empty");
  }
}

// A fiber to place: its tile and where its particles went.
template <int D>
struct Pending {
  int colour;
  std::int64_t tile;
  int fiber;
  std::size_t first = 0;  // its first particle in the points
  std::int64_t tries = 0;
  Vec<D> u = Vec<D>::Zero();  // its axis
};

}  // namespace

template <int D>
double fiber_solid_measure(const FiberSpec<D>& s, int n) {
  const double r = s.radius;
  const double one = D == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return n * s.particles_per_fiber * one;
}

template <int D>
int fiber_target(const FiberSpec<D>& s) {
  if (s.count > 0) return s.count;
  // The smallest count that reaches the fraction (1e-9 absorbs round-off
  // when the fraction is an exact multiple).
  const double n = std::ceil(s.fraction * region_measure(s) / fiber_solid_measure(s, 1) - 1e-9);
  if (!(n <= static_cast<double>(std::numeric_limits<int>::max()))) {
    throw std::runtime_error(
        fmt::format("fibers: the area fraction {:g} of the region takes {:.3g} fibers, more than "
                    "2^31 - 1; is an extent of `region` off by orders of magnitude?",
                    s.fraction, n));
  }
  return static_cast<int>(n);
}

std::int64_t fiber_bucket_coord(double t, double lo, double cell) {
  return clamped_floor<std::int64_t>((t - lo) / cell, -kMaxBucketCoord, kMaxBucketCoord);
}

template <int D>
Vec<D> first_fiber_centre(const FiberSpec<D>& s, int f) {
  const int target = fiber_target(s);
  const Layout<D> layout(s);
  const Tiles<D> tiles = fiber_tiles(s, layout, target);
  Vec<D> tlo, thi;
  tiles.box(tiles.tile_of_fiber(f, target), tlo, thi);
  return draw_candidate(s, layout, f, 0, &tlo, &thi).c;
}

template <int D>
FiberPlacement place_fibers(const FiberSpec<D>& s, DemSystem<D>& sys, const FiberShare<D>* share) {
  check_spec(s);
  const Layout<D> layout(s);
  check_fiber_fits(s, layout);
  if (share && sys.particles.size() > 0)
    throw std::logic_error("place_fibers: a share is placed into an empty system");
  const double region = region_measure(s);
  const int target = fiber_target(s);
  const double r = s.radius, dmin = 2.0 * r + s.gap;
  const Tiles<D> tiles = fiber_tiles(s, layout, target);
  const std::set<std::int64_t> need =
      share ? tiles_of_share(tiles, *share) : std::set<std::int64_t>{};

  // The fibers of the tiles to place, by colour, tile and fiber.
  std::vector<Pending<D>> pending;
  const auto add_tile = [&](std::int64_t t) {
    for (std::int64_t f = tiles.first_fiber(t, target); f < tiles.first_fiber(t + 1, target); ++f)
      pending.push_back({tiles.colour(t), t, static_cast<int>(f)});
  };
  if (share) {
    for (const std::int64_t t : need) add_tile(t);
  } else {
    for (std::int64_t t = 0; t < tiles.count(); ++t) add_tile(t);
  }
  std::stable_sort(pending.begin(), pending.end(), [](const Pending<D>& a, const Pending<D>& b) {
    return a.colour != b.colour ? a.colour < b.colour : a.tile < b.tile;
  });

  std::vector<Vec<D>> pts;  // obstacles: existing particles, then the new ones
  for (std::size_t i = 0; i < sys.particles.size(); ++i) pts.push_back(sys.particles.x[i]);
  Buckets<D> buckets(s.lo, std::max(dmin, 2.0 * r));
  for (std::size_t i = 0; i < pts.size(); ++i) buckets.add(pts[i], i);
  std::vector<Vec<D>> cand(static_cast<std::size_t>(s.particles_per_fiber));
  for (Pending<D>& p : pending) {
    Vec<D> tlo, thi;
    tiles.box(p.tile, tlo, thi);
    bool placed = false;
    for (int a = 0; a < s.attempts_per_fiber && !placed; ++a) {
      ++p.tries;
      const Candidate<D> k = draw_candidate(s, layout, p.fiber, a, &tlo, &thi);
      if (!k.fits) continue;
      bool free = true;
      for (int j = 0; j < s.particles_per_fiber && free; ++j) {
        cand[j] = layout.at(k.c, k.u, j);
        free = !buckets.any_within(cand[j], dmin, pts);
      }
      if (!free) continue;
      p.first = pts.size();
      p.u = k.u;
      for (const Vec<D>& x : cand) {
        buckets.add(x, pts.size());
        pts.push_back(x);
      }
      placed = true;
    }
    if (!placed) {
      throw std::runtime_error(fmt::format(
          "fibers: could not place fiber {} of {} after {} attempts (requested fraction "
          "{:.4g}); lower the count or fraction, or enlarge the region",
          p.fiber + 1, target, s.attempts_per_fiber, fiber_solid_measure(s, target) / region));
    }
  }

  // Added in fiber order.
  std::sort(pending.begin(), pending.end(),
            [](const Pending<D>& a, const Pending<D>& b) { return a.fiber < b.fiber; });
  FiberPlacement out;
  out.fibers = target;
  out.fraction = fiber_solid_measure(s, target) / region;
  const auto ppf = static_cast<std::size_t>(s.particles_per_fiber);
  if (!share) {
    std::int32_t fiber0 = 0;
    for (std::size_t i = 0; i < sys.particles.size(); ++i)
      fiber0 = std::max(fiber0, sys.particles.fiber[i] + 1);
    for (const Pending<D>& p : pending) {
      out.tries += p.tries;
      std::int64_t prev = -1;
      for (std::size_t k = 0; k < ppf; ++k) {
        const std::int64_t id = sys.add_particle(pts[p.first + k], r, s.density, fiber0 + p.fiber);
        if (prev >= 0) {
          sys.add_bond(prev, id);
          if (layout.bend)
            for (DemBond<D>& b : sys.particles.bonds[sys.particles.size() - 2])
              if (b.partner == id)
                preload_bent_bond(sys.params, r, layout.bend->turn[k - 1], p.u, b);
        }
        prev = id;
      }
    }
    return out;
  }
  // A share: its fibers, numbered as the whole placement numbers them
  // (add_particle and add_bond on an empty system: fiber f's particles
  // f ppf + k, its bonds f (ppf - 1) + k, each on its lower particle).
  DemParticles<D>& ps = sys.particles;
  for (const Pending<D>& p : pending) {
    const Vec<D> centre = 0.5 * (pts[p.first] + pts[p.first + ppf - 1]);
    if (!share->owns(centre)) continue;
    out.tries += p.tries;
    const auto f = static_cast<std::int64_t>(p.fiber);
    for (std::size_t k = 0; k < ppf; ++k) {
      const std::int64_t id = f * static_cast<std::int64_t>(ppf) + static_cast<std::int64_t>(k);
      const std::size_t i = ps.push_owned(id, static_cast<std::int32_t>(p.fiber), pts[p.first + k],
                                          r, s.density, sys.params.thickness);
      if (k == 0) continue;
      DemBond<D>& b = ps.bonds[i - 1][0];
      b = DemBond<D>{};
      b.partner = id;
      b.id = f * static_cast<std::int64_t>(ppf - 1) + static_cast<std::int64_t>(k - 1);
      b.rbar = sys.params.lambda * r;
      b.length0 = (ps.x[i] - ps.x[i - 1]).norm();
      if (layout.bend) preload_bent_bond(sys.params, r, layout.bend->turn[k - 1], p.u, b);
    }
  }
  sys.invalidate_forces();
  return out;
}

template FiberPlacement place_fibers<2>(const FiberSpec<2>&, DemSystem<2>&, const FiberShare<2>*);
template FiberPlacement place_fibers<3>(const FiberSpec<3>&, DemSystem<3>&, const FiberShare<3>*);
template int fiber_target<2>(const FiberSpec<2>&);
template int fiber_target<3>(const FiberSpec<3>&);
template Vec<2> first_fiber_centre<2>(const FiberSpec<2>&, int);
template Vec<3> first_fiber_centre<3>(const FiberSpec<3>&, int);
template double fiber_solid_measure<2>(const FiberSpec<2>&, int);
template double fiber_solid_measure<3>(const FiberSpec<3>&, int);

}  // namespace sphdem
