// estimate_case_size (case_size.hpp): particle counts and memory from the
// case's geometry, in doubles (a hostile case gives 1e300 or inf, never an
// overflow), without building anything.
#include "sphdem/solver/case_size.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sphdem/geometry/geometry.hpp"
#include "sphdem/io/checkpoint.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/particles/dem_particles.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

namespace {

// Area (2D) or volume (3D) of a shape.
double measure(const Shape& s, int dim) {
  if (s.type == Shape::Type::Box) {
    double m = 1;
    for (int d = 0; d < dim; ++d) m *= s.hi[d] - s.lo[d];
    return m;
  }
  double area2 = 0;
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    const auto& a = s.vertices[i];
    const auto& b = s.vertices[(i + 1) % s.vertices.size()];
    area2 += a[0] * b[1] - b[0] * a[1];
  }
  return 0.5 * std::abs(area2);
}

// Area (volume) of the band of thickness t around a shape, where its wall
// layers lie: the shape grown by t less the shape (a box grows along every
// axis; a polygon by its perimeter times t plus square corners).
double band(const Shape& s, int dim, double t) {
  if (s.type == Shape::Type::Box) {
    double grown = 1;
    for (int d = 0; d < dim; ++d) grown *= s.hi[d] - s.lo[d] + 2 * t;
    return grown - measure(s, dim);
  }
  double length = 0;
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    const auto& a = s.vertices[i];
    const auto& b = s.vertices[(i + 1) % s.vertices.size()];
    length += std::hypot(b[0] - a[0], b[1] - a[1]);
  }
  return length * t + 4 * t * t;
}

// Bytes per particle of a field registry (the fields ps holds, owned or ghost).
template <class P>
double registry_bytes(const P& ps = P()) {
  double bytes = 0;
  ps.for_each_field([&](const char*, const auto& field, FieldPolicy) {
    bytes += sizeof(typename std::decay_t<decltype(field)>::value_type);
  });
  return bytes;
}

// Bytes per SPH particle of the fields the case's options use (drop_unused_fields).
template <int D>
double sph_field_bytes(const Case& c) {
  SphParticles<D> ps;
  drop_unused_fields<D>(make_sph_params(c), any_slip_wall(c), ps);
  return registry_bytes(ps);
}

// Bytes per SPH particle of a checkpoint's rows: the checkpointed fields the
// case holds, and the positions at the neighbour list's build
// (src/solver/simulation_checkpoint.cpp).
template <int D>
double sph_checkpoint_row_bytes(const Case& c) {
  SphParticles<D> ps;
  drop_unused_fields<D>(make_sph_params(c), any_slip_wall(c), ps);
  double bytes = D * sizeof(double);
  for (const CheckpointColumn& col : checkpoint_columns(ps)) bytes += col.row_bytes;
  return bytes;
}

// Cells of a grid over `lo`..`hi` whose cells are at least `cell` wide.
template <int D>
double grid_cells(const Vec<D>& lo, const Vec<D>& hi, double cell) {
  double n = 1;
  for (int d = 0; d < D; ++d) n *= std::max(1.0, std::floor((hi[d] - lo[d]) / cell));
  return n;
}

// Bytes per top-level cell of a decomposition on every rank
// (decomposition.hpp): its owner (int) and the work per cell (int64) that
// partitioning sums, twice over.
constexpr double kBytesPerCell = 4 + 2 * 8;
// The resident size of a rank before any particle: code, MPI and HDF5
// (measured: 36.6 MiB on one rank, 39.0 MiB on each of four, for the plate
// at spacing 6e-4 m; docs/scaling.md, "Memory per rank").
constexpr double kProcessBytes = 38.0 * 1024 * 1024;
// What the fields and lists leave out (the pair loop's records, the
// snapshots' buffers, the allocator's slack), as a factor over them:
// fitted to the measured peak of the 2 M particle box at 1 rank once the
// fields were held only when used (docs/scaling.md, "Memory per rank",
// where 2, 4 and 8 ranks are within 20 % of it).
constexpr double kSphOverhead = 1.35;
// Writing a checkpoint, which any run may do (a cadence, a signal, its last
// state when it fails), holds a rank's rows about three times over on top
// of the running fields: the columns, then the send and receive buffers
// that regroup them by id range (src/io/checkpoint_writer.cpp). Measured:
// 2.83 x the checkpoint's bytes for the 2 M box at 1 rank, 2.66 x for the
// coarse 3D plate (docs/scaling.md, "Memory per rank").
constexpr double kCheckpointCopies = 2.8;
// The fibers' part, measured against `sphdem check`'s peak resident size
// before the resin's calibration (allocator slack, pair-list growth).
constexpr double kDemOverhead = 1.6;

template <int D>
CaseSize estimate(const Case& c, int ranks) {
  CaseSize s;
  const double dx = c.numerics.spacing;
  const double p = std::max(1, ranks);
  // Neighbours within the cut-off 2h (1 + skin), in spacings.
  const double reach = 2 * c.numerics.h_over_spacing * (1 + c.numerics.neighbor_skin);
  const double neighbours =
      D == 2 ? std::numbers::pi * reach * reach : 4.0 / 3.0 * std::numbers::pi * std::pow(reach, 3);
  double sph_setup = 0, sph_run = 0, dem_bytes = 0, dem_cells_bytes = 0;

  if (!c.fill.empty()) {
    for (const Shape& f : c.fill) s.resin += measure(f, D) / std::pow(dx, D);
    for (const Shape& m : c.mold.shapes) s.walls += band(m, D, wall_band(c)) / std::pow(dx, D);
    const Box<D> dom = simulation_domain<D>(c);
    s.lattice_nodes = 1;
    for (int d = 0; d < D; ++d) s.lattice_nodes *= (dom.hi[d] - dom.lo[d]) / dx + 1;
    s.cells = std::min(grid_cells<D>(dom.lo, dom.hi, reach * dx),
                       static_cast<double>(max_blocks(ranks, c.parallel.min_top_cells,
                                                      c.parallel.top_cells_per_rank)));
    // Overlapping shapes count twice above; no more particles than nodes.
    s.resin = std::min(s.resin, s.lattice_nodes);
    s.walls = std::min(s.walls, s.lattice_nodes);
    const double n = s.resin + s.walls;
    const double per_particle = sph_field_bytes<D>(c);
    const double owned = n / p;
    // A rank's ghosts: a layer `reach` spacings deep around its share.
    const double ghosts =
        p > 1 ? std::min(n - owned, 2.0 * D * std::pow(owned, (D - 1.0) / D) * reach) : 0.0;
    // Set-up (distributed, docs/parallel.md): its share's fields, reserved
    // to their count, each resin particle's fill shape, and the per-row
    // counts of the lattice (16 bytes per row: rows are the nodes along x).
    const double rows = s.lattice_nodes / ((dom.hi[0] - dom.lo[0]) / dx + 1);
    sph_setup = owned * (per_particle + sizeof(std::size_t)) + 16.0 * rows;
    // Running: for its share and ghosts the fields, the neighbour list
    // (int32 per neighbour) and about a registry's worth again (the sort by
    // cell, the pair loop's records, halo and snapshot buffers). Fitted to
    // the measured peak at 1 to 8 ranks (docs/scaling.md).
    sph_run =
        kSphOverhead * (owned + ghosts) * (2.0 * per_particle + neighbours * sizeof(std::int32_t));
    // 3D: the list build's copy of the binned coordinates and keys, four
    // doubles per particle, kept between builds (src/neighbor/neighbor_list.cpp).
    if (D == 3) sph_run += (owned + ghosts) * 4.0 * sizeof(double);
    // 3D: the lists cut to the support, sized as the build's 16-bit lists,
    // their offsets and every particle's position at the cut
    // (include/sphdem/neighbor/support_lists.hpp).
    if (D == 3)
      sph_run += (owned + ghosts) *
                 (neighbours * sizeof(std::int16_t) + sizeof(std::uint32_t) + D * sizeof(double));
    // Implicit viscosity: a coefficient and a wall's Shepard weight per
    // neighbour, the solve's ten vectors, the diagonal and a wall's weight
    // sum per owned particle (src/sph/implicit_viscosity.cpp).
    if (c.numerics.viscous_integration == ViscousIntegration::Implicit)
      sph_run += owned * (2.0 * neighbours + 10.0 * D + 2.0) * sizeof(double);
    sph_run += kCheckpointCopies * owned * sph_checkpoint_row_bytes<D>(c);
  }
  if (c.fibers) {
    const FiberSettings& f = *c.fibers;
    double fibers = f.count;
    if (f.count == 0) {
      const double d = f.diameter;
      const double particle =
          D == 2 ? std::numbers::pi * d * d / 4 : std::numbers::pi * d * d * d / 6;
      fibers =
          std::ceil(f.area_fraction * measure(f.region, D) / (particle * f.particles_per_fiber));
    }
    s.dem = fibers * f.particles_per_fiber;
    // Each rank places and holds its share of the fibers (place_fibers by
    // tiles, docs/dem.md); its cell list has up to 16 cells per particle.
    // The stable step's index by gid is the one array of every fiber
    // particle (4 bytes each).
    dem_bytes = kDemOverhead * s.dem / p *
                    (registry_bytes<DemParticles<D>>() + 16 * 2 * sizeof(std::int32_t)) +
                sizeof(std::int32_t) * s.dem;
    if (c.fill.empty()) {
      // A fibers-only run's cells, about one diameter wide, over the mold
      // and a margin of a tenth of it (src/solver/dem_run.cpp).
      const Box<D> mold = mold_bounds<D>(c);
      Vec<D> lo = mold.lo, hi = mold.hi;
      const double margin = 0.1 * (hi - lo).maxCoeff();
      lo.array() -= margin;
      hi.array() += margin;
      s.cells = std::min(grid_cells<D>(lo, hi, f.diameter), static_cast<double>(max_blocks(ranks)));
      dem_cells_bytes = s.cells * kBytesPerCell;
    }
  }
  const double cell_bytes = c.fill.empty() ? 0.0 : s.cells * kBytesPerCell;
  const double common = kProcessBytes + dem_bytes + cell_bytes + dem_cells_bytes;
  s.setup_bytes = common + sph_setup;
  s.run_bytes = common + sph_run;
  const double sph_part = std::max(sph_setup, sph_run) + cell_bytes;
  if (!c.fibers || sph_part >= std::max(dem_bytes, dem_cells_bytes))
    s.dominant_key = "numerics.spacing";
  else if (dem_cells_bytes > dem_bytes)
    s.dominant_key = "fibers.diameter";
  else
    s.dominant_key = c.fibers->count > 0 ? "fibers.count" : "fibers.area_fraction";
  return s;
}

}  // namespace

CaseSize estimate_case_size(const Case& c, int ranks) {
  return c.dimension == 2 ? estimate<2>(c, ranks) : estimate<3>(c, ranks);
}

std::string format_bytes(double bytes) {
  if (!std::isfinite(bytes)) return "more than any machine has";
  constexpr double kMiB = 1024.0 * 1024.0, kGiB = 1024.0 * kMiB, kTiB = 1024.0 * kGiB;
  if (bytes >= kTiB) return fmt::format("{:.3g} TiB", bytes / kTiB);
  if (bytes >= kGiB) return fmt::format("{:.3g} GiB", bytes / kGiB);
  return fmt::format("{:.3g} MiB", bytes / kMiB);
}

}  // namespace sphdem
