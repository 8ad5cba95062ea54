#pragma once
// Weld lines and trapped air (output.front_events; docs/physics.md "Weld
// lines and trapped air"). Physics only: the solver reduces the void grid
// over ranks and gathers the events (src/solver/front_events_output.cpp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sphdem/geometry/geometry.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

// Two front segments meet at owned resin particle i when i and a resin
// neighbour j within the kernel support are both on the free surface and
//   n_i . n_j < -0.5                 (opposed normals, within 60 degrees)
//   x_ji . n_i > 0.5 |x_ji|, x_ij . n_j > 0.5 |x_ij|   (each lies in front of
//                                     the other's surface: not the two sides
//                                     of one thin sheet)
//   v_ij . x_ij < 0                   (they approach)
// Then ps.weld_line[i] = 1 for good (the weld-line material is carried with
// the flow). Reads the free-surface pass's flag and normal and the velocity
// on ghosts, so the result does not depend on the rank count. Returns the
// owned particles flagged in this call, each with the midpoint of the pair
// that met there (on the meeting plane).
template <int D>
struct WeldMark {
  std::size_t i = 0;
  Vec<D> at;
};
template <int D>
std::vector<WeldMark<D>> mark_weld_lines(const SphParams& sp, const NeighborList<D>& nl,
                                         SphParticles<D>& ps);

// A grid over the domain for finding closed voids: cells of dp/2.
template <int D>
struct VoidGrid {
  Vec<D> lo;
  double cell = 0;
  std::array<std::int64_t, 3> n{1, 1, 1};
  std::int64_t size() const { return n[0] * n[1] * n[2]; }
};

// The most cells of a VoidGrid (3 doubles each, on every rank).
inline constexpr std::int64_t kMaxVoidCells = std::int64_t{1} << 31;

// Throws std::length_error past kMaxVoidCells (a domain far larger than
// the spacing; the resin module turns it into an input error at the start).
template <int D>
VoidGrid<D> make_void_grid(const Box<D>& domain, double spacing);

// Adds this rank's owned particles to marks (3 per cell: resin, wall, vent):
// a particle marks every cell whose centre is within one spacing of it; a
// wall particle inside one of the vents (mold.vents; empty: every wall
// particle) marks the vent slot too. Summed over ranks (exact: counts), the
// marks are the same at any rank count. With vents, a cell whose centre is
// outside the cavity (the union of `cavity`; e.g. inside an insert beyond
// the wall layers, or behind a piston) marks the vent slot: not air of the
// cavity, and open.
template <int D>
void mark_void_grid(const VoidGrid<D>& g, double spacing, const SphParticles<D>& ps,
                    const std::vector<Shape>& cavity, const std::vector<Shape>& vents,
                    std::vector<double>& marks);

struct AirPocket {
  std::array<double, 3> centroid{};
  double size = 0;  // area (2D, m^2) or volume (3D, m^3)
};

// The connected empty regions (neither resin nor wall, face neighbours)
// that touch no vent cell and not the grid's border: air closed in by resin,
// or by resin and walls that do not vent. In the order of their first cell
// (deterministic).
template <int D>
std::vector<AirPocket> find_air_pockets(const VoidGrid<D>& g, const std::vector<double>& marks);

// One row of <output>/<case>_front_events.csv.
struct FrontEvent {
  enum class Kind { WeldLine, TrappedAir } kind = Kind::WeldLine;
  double time = 0;            // [s]
  std::array<double, 3> x{};  // the particle, or the pocket's centroid [m]
  std::int64_t id = 0;        // the particle's id, or the pocket's number at that time
  double size = 0;            // the pocket's area or volume; 0 for a weld line
};

}  // namespace sphdem
