#pragma once
// Random fiber placement (docs/dem.md, 2.4): straight chains of touching
// equal particles, bonded along the chain, placed in a box without overlap.
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

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
  // Seeded bend (fiber_bend.hpp): the sagitta of every fiber's half-sine arc
  // over its length 2 r n, in [0, 0.25); 0: straight.
  double bend = 0;
  int attempts_per_fiber = 20000;
};

struct FiberPlacement {
  int fibers = 0;          // placed
  double fraction = 0;     // area/volume fraction reached
  std::int64_t tries = 0;  // candidate positions drawn
};

// The fibers one rank of several places (docs/dem.md, 2.4): those whose
// centre lies in its top-level cells.
template <int D>
struct FiberShare {
  std::vector<std::pair<Vec<D>, Vec<D>>> boxes;  // its top-level cells (lo, hi; may be infinite)
  std::function<bool(const Vec<D>&)> owns;       // whether a centre is in its cells
};

// Appends the fibers to `sys` (gids continue after the existing particles,
// fiber ids after the largest existing one) and bonds each chain. Existing
// particles count as obstacles. Deterministic for a seed, whatever the
// share (docs/dem.md, "Fiber generator"): fiber f's candidates come from a
// stream keyed by (seed, f, attempt) (SplitMix64); a fixed grid of equal
// tiles over the region (at least a fiber plus the gap wide, about 32
// fibers each) holds the fibers, the count split evenly over the tiles,
// each fiber's centre drawn in its tile; tiles are placed by colour (2^D
// colours, no two neighbours alike), so a fiber's overlap test sees
// exactly the fibers of its tile and of its neighbours of lower colours,
// on any rank. With a share, `sys` must be empty: only the fibers whose
// centre the share owns are added, with the gids, fiber ids and bond ids
// the whole placement gives them (fiber f: particles f ppf + k); the share
// places the tiles that touch its boxes and those their results depend
// on. Throws std::runtime_error naming the fiber when it finds no free
// place in `attempts_per_fiber` tries (in its tile); sys is then left
// unchanged. `tries` counts the owned fibers' tries.
template <int D>
FiberPlacement place_fibers(const FiberSpec<D>& spec, DemSystem<D>& sys,
                            const FiberShare<D>* share = nullptr);

// The number of fibers of the spec (its count, or the smallest that reaches its fraction).
template <int D>
int fiber_target(const FiberSpec<D>& spec);

// The centre of fiber f's first candidate (in its tile; where it lies
// unless that candidate overlaps): every rank can weigh the fibers' work
// per cell without placing them.
template <int D>
Vec<D> first_fiber_centre(const FiberSpec<D>& spec, int f);

// The overlap test's bucket coordinate of position t along an axis whose
// buckets are `cell` wide from lo: floor((t - lo) / cell), clamped as a
// double into [-kMaxBucketCoord, kMaxBucketCoord] (NaN: the lowest), so a
// far or non-finite particle never makes an out-of-range cast. The buckets
// hash 21 bits per axis, so the clamp costs nothing the hash kept.
inline constexpr std::int64_t kMaxBucketCoord = std::int64_t{1} << 40;
std::int64_t fiber_bucket_coord(double t, double lo, double cell);

// Area (2D) or volume (3D) of the particles of n fibers.
template <int D>
double fiber_solid_measure(const FiberSpec<D>& spec, int n);

}  // namespace sphdem
