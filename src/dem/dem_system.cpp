// Particle creation, walls, and the DEM-only driver DemSystem.
#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "sphdem/dem/dem.hpp"
#include "terms/parallel_bond.hpp"

namespace sphdem {

template <int D>
std::size_t DemParticles<D>::push_owned(std::int64_t id, std::int32_t fiber_id, const Vec<D>& pos,
                                        double r, double density, double thickness) {
  const std::size_t i = size();
  resize(i + 1);
  zero_particle(i);  // at rest, no forces, empty slots
  gid[i] = id;
  fiber[i] = fiber_id;
  fixed[i] = kFree;
  radius[i] = r;
  if constexpr (D == 2) {
    mass[i] = density * std::numbers::pi * r * r * thickness;
    inertia[i] = 0.5 * mass[i] * r * r;  // disk
  } else {
    mass[i] = density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    inertia[i] = 0.4 * mass[i] * r * r;  // solid sphere
  }
  x[i] = pos;
  void_fraction[i] = 1.0;  // no other particle near
  n_owned = i + 1;
  return i;
}

template <int D>
double contact_stiffness_from_bond(const DemParams<D>& p, double r, double fraction) {
  const terms::BondSection s = terms::bond_section<D>(p.lambda * r, p.thickness);
  return fraction * p.youngs_modulus / (2.0 * r) * s.area;
}

template <int D>
DemWall<D> DemWall<D>::plane(const Vec<D>& p, const Vec<D>& n, const Vec<D>& vel) {
  DemWall w;
  w.type = Type::Plane;
  w.point = p;
  w.normal = n.normalized();
  w.velocity = vel;
  return w;
}

template <int D>
DemWall<D> DemWall<D>::segment(const Vec<D>& a, const Vec<D>& b, const Vec<D>& vel) {
  DemWall w;
  w.type = Type::Segment;
  w.point = a;
  w.end = b;
  w.velocity = vel;
  return w;
}

template <int D>
DemWall<D> DemWall<D>::rect(const Vec<D>& corner, const Vec<D>& eu, const Vec<D>& ev,
                            const Vec<D>& inward, int edge_mask,
                            const Vec<D>& vel) requires(D == 3) {
  DemWall w;
  w.type = Type::Rect;
  w.point = corner;
  w.u = eu;
  w.v = ev;
  w.end = corner + eu + ev;
  w.normal = eu.cross(ev).normalized();
  if (w.normal.dot(inward) < 0) w.normal = -w.normal;
  w.edges = edge_mask;
  w.velocity = vel;
  return w;
}

template <int D>
std::vector<DemWall<D>> box_walls(const Vec<D>& lo, const Vec<D>& hi) {
  std::vector<DemWall<D>> w;
  for (int d = 0; d < D; ++d) {
    const Vec<D> e = Vec<D>::Unit(d);
    w.push_back(DemWall<D>::plane(lo, e));
    w.push_back(DemWall<D>::plane(hi, -e));
  }
  return w;
}

template <int D>
std::int64_t DemSystem<D>::add_particle(const Vec<D>& x, double radius, double density,
                                        std::int32_t fiber) {
  const auto id = static_cast<std::int64_t>(particles.size());
  particles.push_owned(id, fiber, x, radius, density, params.thickness);
  ws_.invalidate();
  return id;
}

template <int D>
std::size_t DemSystem<D>::index_of(std::int64_t gid) const {
  // add_particle numbers densely and nothing reorders yet: try the slot first.
  const auto k = static_cast<std::size_t>(gid);
  if (gid >= 0 && k < particles.size() && particles.gid[k] == gid) return k;
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles.gid[i] == gid) return i;
  throw std::out_of_range(fmt::format("no DEM particle with gid {}", gid));
}

template <int D>
void DemSystem<D>::add_bond(std::int64_t a, std::int64_t b) {
  const std::int64_t owner = std::min(a, b), partner = std::max(a, b);
  const std::size_t i = index_of(owner), j = index_of(partner);
  for (DemBond<D>& s : particles.bonds[i]) {
    if (s.partner >= 0) continue;
    s = DemBond<D>{};
    s.partner = partner;
    s.id = bonds_++;
    s.rbar = params.lambda * std::min(particles.radius[i], particles.radius[j]);
    s.length0 = (particles.x[j] - particles.x[i]).norm();
    ws_.invalidate();
    return;
  }
  throw std::runtime_error(
      fmt::format("DEM particle {} has no free bond slot for {}", owner, partner));
}

template <int D>
const DemBond<D>* DemSystem<D>::bond(std::int64_t a, std::int64_t b) const {
  const std::size_t i = index_of(std::min(a, b));
  for (const DemBond<D>& s : particles.bonds[i])
    if (s.partner == std::max(a, b)) return &s;
  return nullptr;
}

template <int D>
void DemSystem<D>::step(double dt) {
  if (params.subcycle_bonds) {
    const auto settle = [&] {
      if (dem_max_displacement2(particles, walls, ws_) > 0.25 * ws_.skin * ws_.skin) {
        dem_store_pair_state(particles, ws_);
        dem_build_pairs(params, walls, particles, ws_);
      }
    };
    if (!ws_.pairs_valid) dem_build_pairs(params, walls, particles, ws_);
    if (params.implicit_bonds) {
      dem_implicit_step(
          params, dt, walls, particles, ws_, [] {}, settle);
    } else {
      dem_subcycled_step(
          params, dt, dem_bond_substeps(params, dt), walls, particles, ws_, [] {}, settle);
    }
  } else {
    dem_step(params, dt, walls, particles, ws_);
  }
  // Serial: keep the slots current after every step, for the tests' eyes.
  dem_store_pair_state(particles, ws_);
  time_ += dt;
  ++steps_;
}

template struct DemParticles<2>;
template struct DemParticles<3>;
template struct DemWall<2>;
template struct DemWall<3>;
template class DemSystem<2>;
template class DemSystem<3>;
template double contact_stiffness_from_bond<2>(const DemParams<2>&, double, double);
template double contact_stiffness_from_bond<3>(const DemParams<3>&, double, double);
template std::vector<DemWall<2>> box_walls<2>(const Vec<2>&, const Vec<2>&);
template std::vector<DemWall<3>> box_walls<3>(const Vec<3>&, const Vec<3>&);

}  // namespace sphdem
