// Random sequential placement of straight fibers (dem_fibers.hpp).
// Candidates are drawn with std::mt19937_64 and turned into doubles by hand
// (53 random bits), not by std::uniform_real_distribution, whose output the
// standard leaves to each library: a seed gives the same fibers everywhere.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphdem/dem/dem_fibers.hpp"

namespace sphdem {

namespace {

double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

template <int D>
double region_measure(const FiberSpec<D>& s) {
  double m = 1;
  for (int d = 0; d < D; ++d) m *= s.hi[d] - s.lo[d];
  return m;
}

template <int D>
Vec<D> draw_direction(const FiberSpec<D>& s, std::mt19937_64& rng) {
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

// Throws when no fiber of the spec can lie in the region (issue 12 part 5:
// long fibers), before the attempts: its fixed direction does not fit
// (along some axis the chain, end particles included, is longer than the
// region), or, at random orientations, it is longer than the region's
// diagonal (no direction fits).
template <int D>
void check_fiber_fits(const FiberSpec<D>& s) {
  const double r = s.radius, length = 2.0 * r * s.particles_per_fiber;
  const Vec<D> room = (s.hi - s.lo).array() - 2.0 * r;
  const double half = (s.particles_per_fiber - 1) * r;
  bool fits = (room.array() >= 0).all();
  std::string where;
  if (s.direction || (D == 2 && s.angle)) {
    std::mt19937_64 unused(0);
    const Vec<D> u = draw_direction(s, unused);
    for (int d = 0; d < D; ++d) fits = fits && 2.0 * half * std::abs(u[d]) <= room[d];
    where = "at its fixed orientation";
  } else {
    fits = fits && 2.0 * half <= room.norm();
    where = "at any orientation";
  }
  if (!fits) {
    throw std::runtime_error(fmt::format(
        "fibers: a fiber of {} particles ({:.4g} m long, aspect ratio {}) cannot lie in the "
        "region {}; lower `particles_per_fiber` or enlarge `region`",
        s.particles_per_fiber, length, s.particles_per_fiber, where));
  }
}

// A uniform grid of buckets over the region for the overlap test.
template <int D>
class Buckets {
 public:
  Buckets(const Vec<D>& lo, const Vec<D>& hi, double cell) : lo_(lo), cell_(cell) {
    std::size_t n = 1;
    for (int d = 0; d < D; ++d) {
      dims_[d] = std::max<std::int64_t>(1, static_cast<std::int64_t>((hi[d] - lo[d]) / cell));
      n *= static_cast<std::size_t>(dims_[d]);
    }
    items_.resize(n);
  }
  void add(const Vec<D>& x, std::size_t id) { items_[key(coords(x))].push_back(id); }
  // True when a stored point is closer than `dmin` to x.
  bool any_within(const Vec<D>& x, double dmin, const std::vector<Vec<D>>& pts) const {
    const auto c = coords(x);
    std::array<std::int64_t, 3> k{0, 0, 0};
    const std::int64_t zspan = D == 3 ? 1 : 0;
    for (k[2] = c[2] - zspan; k[2] <= c[2] + zspan; ++k[2])
      for (k[1] = c[1] - 1; k[1] <= c[1] + 1; ++k[1])
        for (k[0] = c[0] - 1; k[0] <= c[0] + 1; ++k[0]) {
          bool inside = true;
          for (int d = 0; d < D; ++d) inside = inside && k[d] >= 0 && k[d] < dims_[d];
          if (!inside) continue;
          for (std::size_t id : items_[key(k)])
            if ((pts[id] - x).squaredNorm() < dmin * dmin) return true;
        }
    return false;
  }

 private:
  std::array<std::int64_t, 3> coords(const Vec<D>& x) const {
    std::array<std::int64_t, 3> c{0, 0, 0};
    for (int d = 0; d < D; ++d) {
      c[d] = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor((x[d] - lo_[d]) / cell_)), 0, dims_[d] - 1);
    }
    return c;
  }
  std::size_t key(const std::array<std::int64_t, 3>& c) const {
    return static_cast<std::size_t>(c[0] + dims_[0] * (c[1] + dims_[1] * c[2]));
  }
  Vec<D> lo_;
  double cell_;
  std::array<std::int64_t, 3> dims_{1, 1, 1};
  std::vector<std::vector<std::size_t>> items_;
};

}  // namespace

template <int D>
double fiber_solid_measure(const FiberSpec<D>& s, int n) {
  const double r = s.radius;
  const double one = D == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
  return n * s.particles_per_fiber * one;
}

template <int D>
FiberPlacement place_fibers(const FiberSpec<D>& s, DemSystem<D>& sys) {
  if (s.radius <= 0 || s.particles_per_fiber < 1) {
    throw std::runtime_error("fibers: radius must be positive and particles_per_fiber >= 1");
  }
  for (int d = 0; d < D; ++d) {
    if (!(s.hi[d] > s.lo[d])) throw std::runtime_error("fibers: the region is empty");
  }
  check_fiber_fits(s);
  const double region = region_measure(s);
  int target = s.count;
  if (target <= 0) {
    // The smallest count that reaches the fraction (1e-9 absorbs round-off
    // when the fraction is an exact multiple).
    target = static_cast<int>(std::ceil(s.fraction * region / fiber_solid_measure(s, 1) - 1e-9));
  }
  const double r = s.radius, dmin = 2.0 * r + s.gap;
  const double half = (s.particles_per_fiber - 1) * r;  // centre to end-particle centre
  std::vector<Vec<D>> pts;  // obstacles: existing particles, then the new ones
  for (std::size_t i = 0; i < sys.particles.size(); ++i) pts.push_back(sys.particles.x[i]);
  Buckets<D> buckets(s.lo, s.hi, std::max(dmin, 2.0 * r));
  for (std::size_t i = 0; i < pts.size(); ++i) buckets.add(pts[i], i);
  const std::size_t first_new = pts.size();

  std::mt19937_64 rng(s.seed);
  FiberPlacement out;
  std::vector<Vec<D>> cand(static_cast<std::size_t>(s.particles_per_fiber));
  for (int f = 0; f < target; ++f) {
    bool placed = false;
    for (int a = 0; a < s.attempts_per_fiber && !placed; ++a) {
      ++out.tries;
      const Vec<D> u = draw_direction(s, rng);
      Vec<D> c;
      bool fits = true;
      for (int d = 0; d < D; ++d) {
        const double lo = s.lo[d] + r + half * std::abs(u[d]);
        const double hi = s.hi[d] - r - half * std::abs(u[d]);
        const double t = uniform01(rng);
        fits = fits && hi >= lo;
        c[d] = lo + t * (hi - lo);
      }
      if (!fits) continue;
      for (int k = 0; k < s.particles_per_fiber; ++k) {
        cand[k] = c + (2.0 * r * k - half) * u;
        if (buckets.any_within(cand[k], dmin, pts)) {
          fits = false;
          break;
        }
      }
      if (!fits) continue;
      for (const Vec<D>& p : cand) {
        buckets.add(p, pts.size());
        pts.push_back(p);
      }
      placed = true;
    }
    if (!placed) {
      throw std::runtime_error(fmt::format(
          "fibers: could not place fiber {} of {} after {} attempts (fraction reached {:.4g}, "
          "requested {:.4g}); lower the count or fraction, or enlarge the region",
          f + 1, target, s.attempts_per_fiber, fiber_solid_measure(s, f) / region,
          fiber_solid_measure(s, target) / region));
    }
  }

  std::int32_t fiber0 = 0;
  for (std::size_t i = 0; i < sys.particles.size(); ++i)
    fiber0 = std::max(fiber0, sys.particles.fiber[i] + 1);
  for (int f = 0; f < target; ++f) {
    std::int64_t prev = -1;
    for (int k = 0; k < s.particles_per_fiber; ++k) {
      const std::size_t p = first_new + static_cast<std::size_t>(f * s.particles_per_fiber + k);
      const std::int64_t id = sys.add_particle(pts[p], r, s.density, fiber0 + f);
      if (prev >= 0) sys.add_bond(prev, id);
      prev = id;
    }
  }
  out.fibers = target;
  out.fraction = fiber_solid_measure(s, target) / region;
  return out;
}

template FiberPlacement place_fibers<2>(const FiberSpec<2>&, DemSystem<2>&);
template FiberPlacement place_fibers<3>(const FiberSpec<3>&, DemSystem<3>&);
template double fiber_solid_measure<2>(const FiberSpec<2>&, int);
template double fiber_solid_measure<3>(const FiberSpec<3>&, int);

}  // namespace sphdem
