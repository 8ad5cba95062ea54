#pragma once
// Shared by the wall tests: the wall force on one particle at rest.
#include <vector>

#include "sphdem/dem/dem.hpp"

namespace sphdem::testing {

// The wall force on one particle of radius r at rest at x (contact
// stiffness kn, so kn delta along the push) and, if asked, the number of
// walls it touches.
template <int D>
Vec<D> wall_force(const std::vector<DemWall<D>>& walls, const Vec<D>& x, double kn, double r,
                  int* contacts = nullptr) {
  DemParams<D> p;
  p.kn = kn;
  DemParticles<D> ps;
  ps.push_owned(0, -1, x, r, 1000, 1.0);
  DemWorkspace<D> ws;
  dem_build_pairs(p, walls, ps, ws);
  compute_dem_forces(p, 0.0, walls, ps, ws);
  if (contacts) {
    *contacts = 0;
    for (const auto& c : ps.wall_contacts[0]) *contacts += c.partner != DemContact<D>::kNone;
  }
  return ps.force[0];
}

}  // namespace sphdem::testing
