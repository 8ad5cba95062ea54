#pragma once
// Random fiber placement (docs/dem.md, 2.4): straight chains of touching
// equal particles, bonded along the chain, placed in a box without overlap.
#include <cstdint>
#include <optional>

#include "sphdem/dem/dem.hpp"

namespace sphdem {

template <int D>
struct FiberSpec {
  // How many: a count, or a target area (2D, disk areas) / volume (3D)
  // fraction of the region; the count is then the smallest that reaches it.
  int count = 0;
  double fraction = 0;
  int particles_per_fiber = 4;
  double radius = 0.125e-3;                         // particle radius [m] (fiber diameter 2r)
  double density = 2540;                            // [kg/m^3]
  Vec<D> lo = Vec<D>::Zero(), hi = Vec<D>::Zero();  // region; particles lie fully inside
  // Orientation: a fixed direction (2D: angle from +x [rad]; 3D: a vector),
  // or uniformly random when unset.
  std::optional<double> angle;      // 2D
  std::optional<Vec<D>> direction;  // 3D (2D also accepted)
  std::uint64_t seed = 1;
  double gap = 0;  // extra clearance between particles of different fibers [m]
  int attempts_per_fiber = 20000;
};

struct FiberPlacement {
  int fibers = 0;          // placed
  double fraction = 0;     // area/volume fraction reached
  std::int64_t tries = 0;  // candidate positions drawn
};

// Appends the fibers to `sys` (gids continue after the existing particles,
// fiber ids after the largest existing one) and bonds each chain. Existing
// particles count as obstacles. Deterministic for a seed (std::mt19937_64).
// Throws std::runtime_error naming the count and fraction reached when a
// fiber finds no free place in `attempts_per_fiber` tries; sys is then left
// unchanged.
template <int D>
FiberPlacement place_fibers(const FiberSpec<D>& spec, DemSystem<D>& sys);

// Area (2D) or volume (3D) of the particles of n fibers.
template <int D>
double fiber_solid_measure(const FiberSpec<D>& spec, int n);

}  // namespace sphdem
