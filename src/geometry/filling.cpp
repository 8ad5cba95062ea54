// Initial particles on a Cartesian lattice of pitch `spacing`, with nodes at
// origin + (i + 1/2) spacing. The origin is the domain's lower corner when
// the case gives one (so a periodic box tiles exactly), else 0.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "initial_fields.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/geometry/lattice_fill.hpp"
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

// Node indices beyond this many spacings from the origin are refused:
// positions origin + (i + 1/2) dx there resolve only a fifth of a spacing.
constexpr double kMaxNodeIndex = 1e15;

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
    // Without a domain the origin is 0, and a mold far from it puts the
    // indices beyond long's range (and the positions beyond a spacing's
    // resolution): checked as doubles before the cast.
    const double first = std::floor((lo - L.origin[k]) / L.dx);
    const double end = std::ceil((hi - L.origin[k]) / L.dx);
    if (!(std::abs(first) <= kMaxNodeIndex && std::abs(end) <= kMaxNodeIndex)) {
      throw input_error_at(
          c, c.domain_lo ? "domain" : "mold",
          fmt::format("lies {:.3g} spacings from the lattice origin along axis {}; "
                      "at most 1e15 (without `domain` the origin is 0: is a "
                      "coordinate or numerics.spacing off by orders of magnitude?)",
                      std::max(std::abs(first), std::abs(end)), k));
    }
    L.first[k] = static_cast<long>(first);
    L.last[k] = static_cast<long>(end) - 1;
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

// The unit vector against the body force (zero when none acts): a
// hydrostatic start measures depth along it. Along a periodic axis a body
// force drives flow, not a column.
template <int D>
Vec<D> up_direction(const Case& c) {
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = c.periodic[k] ? 0.0 : c.body_force[k];
  const double gn = g.norm();
  return gn == 0.0 ? Vec<D>::Zero() : Vec<D>(-g / gn);
}

// Hydrostatic start when a body force acts: p = rho0 |g| depth below the
// highest resin particle along -g (`top`, over every rank), so a column
// starts at rest.
template <int D>
void hydrostatic_densities(const Case& c, SphParticles<D>& ps, std::size_t n_fluid, double top) {
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = c.periodic[k] ? 0.0 : c.body_force[k];
  const double gn = g.norm();
  if (gn == 0.0 || n_fluid == 0 || !std::isfinite(top)) return;
  const Vec<D> up = up_direction<D>(c);
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
struct LatticeFill<D>::Impl {
  explicit Impl(const Case& kase)
      : c(kase),
        dom(simulation_domain<D>(kase)),
        L(make_lattice<D>(kase, dom)),
        tol(1e-9 * L.dx),
        wall_reach(wall_band(kase) + tol),
        mass(kase.resin.density * std::pow(L.dx, D)),
        up(up_direction<D>(kase)),
        nx(std::max(0L, L.last[0] - L.first[0] + 1)),
        ny(std::max(0L, L.last[1] - L.first[1] + 1)) {
    for (int k = 0; k < D; ++k) v0[k] = kase.initial_velocity[k];
  }
  const Case& c;
  Box<D> dom;
  Lattice<D> L;
  double tol, wall_reach, mass;
  Vec<D> v0, up;
  long nx, ny;
};

template <int D>
LatticeFill<D>::LatticeFill(const Case& c) : impl_(std::make_unique<Impl>(c)) {}

template <int D>
LatticeFill<D>::~LatticeFill() = default;

template <int D>
std::int64_t LatticeFill<D>::rows() const {
  const Impl& m = *impl_;
  const long nz = D == 3 ? std::max(0L, m.L.last[2] - m.L.first[2] + 1) : 1;
  return m.nx == 0 ? 0 : static_cast<std::int64_t>(m.ny) * nz;
}

template <int D>
long LatticeFill<D>::x_first() const {
  return impl_->L.first[0];
}

template <int D>
long LatticeFill<D>::x_last() const {
  return impl_->L.last[0];
}

template <int D>
std::size_t LatticeFill<D>::fill_shapes() const {
  return impl_->c.fill.size();
}

template <int D>
Vec<D> LatticeFill<D>::node(std::int64_t row, long i) const {
  const Impl& m = *impl_;
  std::array<long, 3> n{i, m.L.first[1] + static_cast<long>(row % m.ny), 0};
  if (D == 3) n[2] = m.L.first[2] + static_cast<long>(row / m.ny);
  return m.L.node(n);
}

template <int D>
NodeClass LatticeFill<D>::classify(const Vec<D>& p) const {
  const Impl& m = *impl_;
  if (!inside_domain<D>(m.dom, p)) return {};
  if (union_contains<D>(m.c.mold.shapes, p)) {
    for (std::size_t f = 0; f < m.c.fill.size(); ++f)
      if (shape_contains<D>(m.c.fill[f], p, m.tol)) return {static_cast<int>(f)};
    return {NodeClass::kEmptyCavity};
  }
  if (union_distance<D>(m.c.mold.shapes, p) <= m.wall_reach) return {NodeClass::kWall};
  return {};
}

template <int D>
void LatticeFill<D>::push(SphParticles<D>& out, std::int64_t gid, const Vec<D>& p, NodeClass cls,
                          std::vector<std::size_t>& fill_of) const {
  const Impl& m = *impl_;
  const double rho0 = m.c.resin.density;
  if (cls.fluid()) {
    out.push_owned(gid, Kind::Fluid, -1, m.mass, p, m.v0, rho0);
    fill_of.push_back(static_cast<std::size_t>(cls.value));
  } else if (cls.wall()) {
    out.push_owned(gid, Kind::Wall, wall_index_at<D>(m.c, p, m.tol), m.mass, p, Vec<D>::Zero(),
                   rho0);
    if (!out.wall_to_surface.empty())  // dropped unless some option reads it
      out.wall_to_surface.back() = to_mold_surface<D>(m.c.mold.shapes, p, m.L.dx);
  }
}

template <int D>
void LatticeFill<D>::check_fill_hits(const std::vector<std::int64_t>& hits) const {
  const Case& c = impl_->c;
  for (std::size_t f = 0; f < c.fill.size(); ++f) {
    if (hits[f] == 0) {
      throw InputError(c.source_file, c.fill[f].line, c.fill[f].key,
                       "fill region holds no lattice node inside the mold (smaller than the "
                       "spacing, or outside the mold)");
    }
  }
  // Surface tension acts on a free surface; a filled cavity has none.
  if (c.resin.surface_tension > 0 && hits[c.fill.size()] == 0) {
    throw input_error_at(c, "resin.surface_tension",
                         "the resin fills the whole cavity, so there is no free surface for "
                         "surface tension to act on; remove the key or fill part of the mold");
  }
}

template <int D>
double LatticeFill<D>::height(const Vec<D>& p) const {
  const Vec<D>& up = impl_->up;
  return up.squaredNorm() == 0.0 ? -std::numeric_limits<double>::infinity() : up.dot(p);
}

template <int D>
void LatticeFill<D>::finish(SphParticles<D>& out, const std::vector<std::size_t>& fill_of,
                            double top) const {
  const Case& c = impl_->c;
  hydrostatic_densities<D>(c, out, fill_of.size(), top);
  initial_temperatures<D>(c, out);
  apply_initial_fields<D>(c, fill_of, out);
}

template class LatticeFill<2>;
template class LatticeFill<3>;

// One rank's whole set: every row, resin numbered first, then walls.
template <int D>
InitialCounts build_initial_particles(const Case& c, SphParticles<D>& out) {
  const LatticeFill<D> lattice(c);
  std::vector<Vec<D>> fluid, wall;
  std::vector<NodeClass> fluid_class;
  std::vector<std::int64_t> hits(lattice.fill_shapes() + 1, 0);
  for (std::int64_t q = 0; q < lattice.rows(); ++q) {
    for (long i = lattice.x_first(); i <= lattice.x_last(); ++i) {
      const Vec<D> p = lattice.node(q, i);
      const NodeClass cls = lattice.classify(p);
      if (cls.fluid()) {
        fluid.push_back(p);
        fluid_class.push_back(cls);
        ++hits[static_cast<std::size_t>(cls.value)];
      } else if (cls.wall()) {
        wall.push_back(p);
      } else if (cls.empty_cavity()) {
        ++hits.back();
      }
    }
  }
  lattice.check_fill_hits(hits);
  std::vector<std::size_t> fill_of;
  std::int64_t id = 0;
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < fluid.size(); ++k) {
    lattice.push(out, id++, fluid[k], fluid_class[k], fill_of);
    top = std::max(top, lattice.height(fluid[k]));
  }
  for (const Vec<D>& p : wall) lattice.push(out, id++, p, NodeClass{NodeClass::kWall}, fill_of);
  lattice.finish(out, fill_of, top);
  return InitialCounts{fluid.size(), wall.size()};
}

template InitialCounts build_initial_particles<2>(const Case&, SphParticles<2>&);
template InitialCounts build_initial_particles<3>(const Case&, SphParticles<3>&);

}  // namespace sphdem
