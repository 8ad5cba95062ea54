// Initial particles on a Cartesian lattice of pitch `spacing`, with nodes at
// origin + (i + 1/2) spacing. The origin is the domain's lower corner when
// the case gives one (so a periodic box tiles exactly), else 0.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "initial_fields.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/sph/eos.hpp"

namespace sphdem {

namespace {

template <int D>
struct Lattice {
  Vec<D> origin;
  double dx;
  std::array<long, 3> first{}, last{};  // inclusive index range per axis

  Vec<D> node(const std::array<long, 3>& i) const {
    Vec<D> p;
    for (int k = 0; k < D; ++k) p[k] = origin[k] + (static_cast<double>(i[k]) + 0.5) * dx;
    return p;
  }
};

template <int D>
Lattice<D> make_lattice(const Case& c, const Box<D>& dom) {
  Lattice<D> L;
  L.dx = c.numerics.spacing;
  // Only nodes inside the mold or within its wall layers become particles,
  // so the node range is the domain's clipped to the mold's box plus the
  // wall layers and a node of margin: a domain far larger than the mold
  // (a typo, or a fuzzed extreme number) costs nothing, and the nodes
  // visited that can hold a particle, and their order, are unchanged.
  const Box<D> mold = mold_bounds<D>(c);
  const double reach = (c.mold.wall_layers + 2) * L.dx;
  for (int k = 0; k < D; ++k) {
    L.origin[k] = c.domain_lo ? (*c.domain_lo)[k] : 0.0;
    // Node indices are longs and positions origin + (i + 1/2) dx: beyond
    // 1e9 spacings per axis neither the indices nor the positions hold.
    const double spacings = (dom.hi[k] - dom.lo[k]) / L.dx;
    if (!(spacings <= 1e9)) {
      throw input_error_at(c, "domain",
                           fmt::format("spans {:.3g} spacings along axis {}; at most 1e9 (is an "
                                       "extent or numerics.spacing off by orders of magnitude?)",
                                       spacings, k));
    }
    double lo = dom.lo[k], hi = dom.hi[k];
    if (mold.lo[k] <= mold.hi[k]) {
      lo = std::max(lo, mold.lo[k] - reach);
      hi = std::min(hi, mold.hi[k] + reach);
    }
    L.first[k] = static_cast<long>(std::floor((lo - L.origin[k]) / L.dx));
    L.last[k] = static_cast<long>(std::ceil((hi - L.origin[k]) / L.dx)) - 1;
    if (c.periodic[k]) {
      const double cells = (dom.hi[k] - dom.lo[k]) / L.dx;
      if (std::abs(cells - std::round(cells)) > 1e-6) {
        throw input_error_at(c, "domain",  // names the file and line of the key
                             "a periodic length must be a whole number of spacings (got " +
                                 std::to_string(cells) + " spacings)");
      }
    }
  }
  return L;
}

template <int D, class F>
void for_each_node(const Lattice<D>& L, F&& f) {
  std::array<long, 3> i{0, 0, 0};
  const long z0 = D == 3 ? L.first[2] : 0, z1 = D == 3 ? L.last[2] : 0;
  for (i[2] = z0; i[2] <= z1; ++i[2])
    for (i[1] = L.first[1]; i[1] <= L.last[1]; ++i[1])
      for (i[0] = L.first[0]; i[0] <= L.last[0]; ++i[0]) f(L.node(i));
}

// Index of the moving or sliding wall whose region holds p, -1 if none.
// Moving walls come first, then sliding walls (the solver uses the same order).
template <int D>
std::int32_t wall_index_at(const Case& c, const Vec<D>& p, double tol) {
  std::int32_t idx = 0;
  for (const MovingWall& w : c.moving_walls) {
    if (shape_contains<D>(w.region, p, tol)) return idx;
    ++idx;
  }
  for (const SlidingWall& w : c.sliding_walls) {
    if (shape_contains<D>(w.region, p, tol)) return idx;
    ++idx;
  }
  return -1;
}

// From a wall node to the nearest point of the mold's surface: the gradient
// of the distance to the cavity (central differences) points away from it.
template <int D>
Vec<D> to_mold_surface(const std::vector<Shape>& shapes, const Vec<D>& p, double dx) {
  const double d = union_distance<D>(shapes, p);
  const double e = 1e-4 * dx;
  Vec<D> grad;
  for (int k = 0; k < D; ++k) {
    Vec<D> a = p, b = p;
    a[k] += e;
    b[k] -= e;
    grad[k] = (union_distance<D>(shapes, a) - union_distance<D>(shapes, b)) / (2 * e);
  }
  const double g = grad.norm();
  return g > 0 ? Vec<D>(-d / g * grad) : Vec<D>::Zero();
}

template <int D>
bool inside_domain(const Box<D>& dom, const Vec<D>& p) {
  for (int k = 0; k < D; ++k)
    if (p[k] < dom.lo[k] || p[k] >= dom.hi[k]) return false;
  return true;
}

// Hydrostatic start when a body force acts: p = rho0 |g| depth below the
// highest resin particle along -g, so a column starts at rest.
template <int D>
void hydrostatic_densities(const Case& c, SphParticles<D>& ps, std::size_t n_fluid) {
  Vec<D> g;  // along a periodic axis a body force drives flow, not a column
  for (int k = 0; k < D; ++k) g[k] = c.periodic[k] ? 0.0 : c.body_force[k];
  const double gn = g.norm();
  if (gn == 0.0 || n_fluid == 0) return;
  const Vec<D> up = -g / gn;
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n_fluid; ++i) top = std::max(top, up.dot(ps.x[i]));
  top += 0.5 * c.numerics.spacing;  // the free surface lies half a spacing above
  const TaitEos eos(c.resin.density, c.resin.sound_speed, c.resin.gamma);
  for (std::size_t i = 0; i < n_fluid; ++i) {
    const double depth = top - up.dot(ps.x[i]);
    ps.rho[i] = eos.density(c.resin.density * gn * depth);
    ps.mass[i] = c.resin.density * std::pow(c.numerics.spacing, D);
  }
}

// With resin.thermal: the resin starts at the melt temperature, each wall
// particle at its wall's temperature (the melt's when adiabatic) until the
// first wall extrapolation replaces it.
template <int D>
void initial_temperatures(const Case& c, SphParticles<D>& ps) {
  if (!c.resin.thermal) return;
  const std::size_t n_moving = c.moving_walls.size();
  for (std::size_t i = 0; i < ps.size(); ++i) {
    double t = c.resin.thermal->temperature;
    if (ps.kind[i] == Kind::Wall) {
      const std::int32_t k = ps.wall[i];
      const WallConditionKeys& own =
          k < 0 ? static_cast<const WallConditionKeys&>(c.mold)
          : static_cast<std::size_t>(k) < n_moving
              ? static_cast<const WallConditionKeys&>(c.moving_walls[static_cast<std::size_t>(k)])
              : static_cast<const WallConditionKeys&>(
                    c.sliding_walls[static_cast<std::size_t>(k) - n_moving]);
      const WallThermalLaw law = resolve_wall_thermal(own, c.mold);
      if (!law.adiabatic) t = law.temperature;
    }
    ps.temperature[i] = t;
    ps.temp_half[i] = t;
  }
}

}  // namespace

template <int D>
InitialCounts build_initial_particles(const Case& c, SphParticles<D>& out) {
  const Box<D> dom = simulation_domain<D>(c);
  const Lattice<D> L = make_lattice<D>(c, dom);
  const double tol = 1e-9 * L.dx;
  const double wall_reach = c.mold.wall_layers * L.dx + tol;
  const double rho0 = c.resin.density;
  const double mass = rho0 * std::pow(L.dx, D);

  std::vector<Vec<D>> fluid, wall;
  std::vector<std::size_t> fill_of;  // per resin node: the fill shape it is in
  std::vector<std::size_t> fill_hits(c.fill.size(), 0);
  std::size_t cavity_nodes = 0;
  for_each_node<D>(L, [&](const Vec<D>& p) {
    if (!inside_domain<D>(dom, p)) return;
    if (union_contains<D>(c.mold.shapes, p)) {
      ++cavity_nodes;
      for (std::size_t f = 0; f < c.fill.size(); ++f) {
        if (shape_contains<D>(c.fill[f], p, tol)) {
          fluid.push_back(p);
          fill_of.push_back(f);
          ++fill_hits[f];
          break;
        }
      }
    } else if (union_distance<D>(c.mold.shapes, p) <= wall_reach) {
      wall.push_back(p);
    }
  });
  for (std::size_t f = 0; f < c.fill.size(); ++f) {
    if (fill_hits[f] == 0) {
      throw InputError(c.source_file, c.fill[f].line, c.fill[f].key,
                       "fill region holds no lattice node inside the mold (smaller than the "
                       "spacing, or outside the mold)");
    }
  }

  // Surface tension acts on a free surface; a filled cavity has none.
  if (c.resin.surface_tension > 0 && fluid.size() == cavity_nodes) {
    throw input_error_at(c, "resin.surface_tension",
                         "the resin fills the whole cavity, so there is no free surface for "
                         "surface tension to act on; remove the key or fill part of the mold");
  }
  Vec<D> v0;
  for (int k = 0; k < D; ++k) v0[k] = c.initial_velocity[k];
  std::int64_t id = 0;
  for (const Vec<D>& p : fluid) {
    out.push_owned(id++, Kind::Fluid, -1, mass, p, v0, rho0);
  }
  for (const Vec<D>& p : wall) {
    out.push_owned(id++, Kind::Wall, wall_index_at<D>(c, p, tol), mass, p, Vec<D>::Zero(), rho0);
    out.wall_to_surface.back() = to_mold_surface<D>(c.mold.shapes, p, L.dx);
  }
  hydrostatic_densities<D>(c, out, fluid.size());
  initial_temperatures<D>(c, out);
  apply_initial_fields<D>(c, fill_of, out);
  return InitialCounts{fluid.size(), wall.size()};
}

template InitialCounts build_initial_particles<2>(const Case&, SphParticles<2>&);
template InitialCounts build_initial_particles<3>(const Case&, SphParticles<3>&);

}  // namespace sphdem
