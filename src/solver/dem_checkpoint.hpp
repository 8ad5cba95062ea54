#pragma once
// The DEM walls' state in a checkpoint (shared by DemRun and the fibers of a
// coupled Simulation): per wall its type (0 plane, 1 segment, 2 rectangle),
// point, normal, end and velocity, and for a rectangle also its edges u and
// v and its edge flags, as one array of numbers (the piston's walls move).
#include <vector>

#include "sphdem/dem.hpp"

namespace sphdem {

template <int D>
double dem_wall_type_code(const DemWall<D>& w) {
  switch (w.type) {
    case DemWall<D>::Type::Plane:
      return 0.0;
    case DemWall<D>::Type::Segment:
      return 1.0;
    case DemWall<D>::Type::Rect:
      return 2.0;
  }
  return -1.0;
}

template <int D>
std::vector<double> dem_wall_state(const std::vector<DemWall<D>>& walls) {
  std::vector<double> out;
  for (const DemWall<D>& w : walls) {
    out.push_back(dem_wall_type_code(w));
    for (const Vec<D>* v : {&w.point, &w.normal, &w.end, &w.velocity})
      for (int k = 0; k < D; ++k) out.push_back((*v)[k]);
    if (w.type != DemWall<D>::Type::Rect) continue;
    for (const Vec<D>* v : {&w.u, &w.v})
      for (int k = 0; k < D; ++k) out.push_back((*v)[k]);
    out.push_back(static_cast<double>(w.edges));
  }
  return out;
}

// False (walls unchanged or partly set: callers use a copy) when `s` does
// not describe walls of the same number and types.
template <int D>
bool set_dem_wall_state(std::vector<DemWall<D>>& walls, const std::vector<double>& s) {
  std::size_t i = 0;
  const auto take = [&](Vec<D>& v) {
    if (i + D > s.size()) return false;
    for (int k = 0; k < D; ++k) v[k] = s[i++];
    return true;
  };
  for (DemWall<D>& w : walls) {
    if (i >= s.size() || s[i++] != dem_wall_type_code(w)) return false;
    for (Vec<D>* v : {&w.point, &w.normal, &w.end, &w.velocity})
      if (!take(*v)) return false;
    if (w.type != DemWall<D>::Type::Rect) continue;
    if (!take(w.u) || !take(w.v) || i >= s.size()) return false;
    w.edges = static_cast<int>(s[i++]);
  }
  return i == s.size();
}

}  // namespace sphdem
