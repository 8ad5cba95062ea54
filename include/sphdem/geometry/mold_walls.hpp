#pragma once
// The mold as DEM walls (src/geometry/mold_walls.cpp, docs/dem.md "Walls"):
// what the fibers see of a case's mold shapes and moving walls.
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/dem/dem.hpp"

namespace sphdem {

// The DEM walls of a case: the parts of the mold shapes' edges (2D
// segments) or faces (3D rectangles, a mold of boxes) on the boundary of
// their union (fixed), then the edges or faces of each moving wall's region
// that touch the cavity (moving). In wall_owner, -1 for a fixed wall, else
// the moving wall's index. InputError naming moving_walls[i].region when a
// moving wall touches no part of the mold.
template <int D>
std::vector<DemWall<D>> dem_walls_from_case(const Case& c, std::vector<int>& wall_owner);

}  // namespace sphdem
