#pragma once
// Mold geometry: shapes (2D polygons, 2D/3D boxes), and the initial
// particles - resin on a lattice inside the fill regions, and wall_layers
// of dummy wall particles on the same lattice just outside the cavity.
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// True when p lies inside the shape or within `tol` of its boundary.
template <int D>
bool shape_contains(const Shape& s, const Vec<D>& p, double tol = 0.0);

// Distance from p to the shape (0 when inside).
template <int D>
double shape_distance(const Shape& s, const Vec<D>& p);

// Union of shapes.
template <int D>
bool union_contains(const std::vector<Shape>& shapes, const Vec<D>& p, double tol = 0.0);
template <int D>
double union_distance(const std::vector<Shape>& shapes, const Vec<D>& p);

template <int D>
struct Box {
  Vec<D> lo, hi;
};

// Bounding box of the mold (without wall layers).
template <int D>
Box<D> mold_bounds(const Case& c);

// The simulation domain: `domain` from the case, else the mold's bounds
// grown by the wall layers plus one spacing.
template <int D>
Box<D> simulation_domain(const Case& c);

// How far from the cavity wall particles are made: mold.wall_layers
// spacings, but no farther than the kernel's support 2h. A lattice node
// farther than 2h from the cavity is farther than 2h from every point in
// it, so it is in no resin particle's support: as a wall particle it would
// cost set-up, memory and a neighbour search at every rebuild and change
// no resin value (docs/performance.md, "Wall layers trimmed to the support").
double wall_band(const Case& c);

// How many of mold.wall_layers lie within wall_band along a flat face
// (layer k is (k - 1/2) spacings behind it): 2 of 3 at h = 1.2 spacings.
int wall_layers_made(const Case& c);

struct InitialCounts {
  std::size_t fluid = 0, wall = 0;
};

// Fills `out` (which must be empty) with the case's particles: fluid first
// (gids 0..Nf-1), then walls (gids Nf..Nf+Nw-1). Every rank builds the same
// list; the decomposition then keeps what it owns. Throws InputError when a
// fill region yields no particle or a periodic length is not a multiple of
// the spacing.
template <int D>
InitialCounts build_initial_particles(const Case& c, SphParticles<D>& out);

}  // namespace sphdem
