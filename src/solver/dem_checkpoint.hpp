#pragma once
// The DEM walls' state in a checkpoint (shared by DemRun and the fibers of a
// coupled Simulation): per wall its type, point, normal, end and velocity,
// as one array of numbers (the piston's segments move).
#include <vector>

#include "sphdem/dem.hpp"

namespace sphdem {

template <int D>
std::vector<double> dem_wall_state(const std::vector<DemWall<D>>& walls) {
  std::vector<double> out;
  for (const DemWall<D>& w : walls) {
    out.push_back(w.type == DemWall<D>::Type::Plane ? 0.0 : 1.0);
    for (const Vec<D>* v : {&w.point, &w.normal, &w.end, &w.velocity})
      for (int k = 0; k < D; ++k) out.push_back((*v)[k]);
  }
  return out;
}

// False (walls unchanged or partly set: callers use a copy) when `s` does
// not describe walls of the same number and types.
template <int D>
bool set_dem_wall_state(std::vector<DemWall<D>>& walls, const std::vector<double>& s) {
  if (s.size() != walls.size() * (1 + 4 * D)) return false;
  std::size_t i = 0;
  for (DemWall<D>& w : walls) {
    if (s[i++] != (w.type == DemWall<D>::Type::Plane ? 0.0 : 1.0)) return false;
    for (Vec<D>* v : {&w.point, &w.normal, &w.end, &w.velocity})
      for (int k = 0; k < D; ++k) (*v)[k] = s[i++];
  }
  return true;
}

}  // namespace sphdem
