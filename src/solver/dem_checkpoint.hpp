#pragma once
// The fibers in a checkpoint, alone or coupled (the fiber module,
// src/solver/dem_run_checkpoint.cpp): the DEM particles (set "dem", every
// field marked for checkpoints, contact history in the slots) and the
// walls' state, per wall its type (0 plane, 1 segment, 2 rectangle), point,
// normal, end and velocity, and for a rectangle also its edges u and v and
// its edge flags, as one array of numbers (the piston's walls move).
#include <fmt/format.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sphdem/core/errors.hpp"
#include "sphdem/dem/dem.hpp"
#include "sphdem/io/checkpoint.hpp"
#include "sphdem/solver/dem_domain.hpp"

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

// Writes the fibers (collective), their contact history stored first.
template <int D>
void write_dem_checkpoint(CheckpointWriter& w, DemDomain<D>& dem) {
  dem.store_state();  // the contact history into the particles' slots
  w.particles("dem", checkpoint_columns(dem.particles()));
  w.attribute("dem_walls", dem_wall_state(dem.walls()));
}

// The fibers as read back, before anything is committed.
template <int D>
struct DemCheckpoint {
  DemParticles<D> particles;  // this rank's slice of the rows (gid order)
  std::vector<DemWall<D>> walls;
};

// A checkpoint written before the bond stress peaks were kept (same format,
// docs/checkpoint.md) has no column "bond_peaks": its peaks start at zero.
inline void add_missing_bond_peaks(std::vector<CheckpointColumn>& cols, std::size_t rows) {
  for (const CheckpointColumn& c : cols)
    if (c.name == "bond_peaks") return;
  CheckpointColumn c{"bond_peaks", ColumnType::Bytes, 1, sizeof(BondPeakSlots), {}};
  c.data.assign(rows * sizeof(BondPeakSlots), 0);
  cols.push_back(std::move(c));
}

// Reads the fibers of checkpoint `path` for the domain `dem` (collective):
// this rank's slice of the rows, a balanced share by global id
// (docs/checkpoint.md "At scale"); InputError naming `path` when the
// particle count or the walls differ from the case's.
template <int D>
DemCheckpoint<D> read_dem_checkpoint(CheckpointReader& r, const DemDomain<D>& dem,
                                     const std::string& path) {
  DemCheckpoint<D> out;
  const std::int64_t n = r.count("dem");
  if (n != dem.global_count())
    throw InputError(path, 0, "",
                     fmt::format("the checkpoint holds {} DEM particles, the case makes {}", n,
                                 dem.global_count()));
  std::vector<CheckpointColumn> cols = r.particles("dem");
  const std::size_t rows = cols.empty() ? 0 : cols.front().rows();
  add_missing_bond_peaks(cols, rows);
  assign_checkpoint_columns(out.particles, cols, rows, path);
  out.walls = dem.walls();
  if (!set_dem_wall_state(out.walls, r.reals("dem_walls")))
    throw InputError(path, 0, "", "the checkpoint's DEM walls do not match the case's");
  return out;
}

// Replaces `dem` by a domain of the checkpoint's fibers on decomposition
// `dec` (each rank's slice migrates once to the owners), whose forces are
// the checkpoint's (an evaluation would re-project the contacts'
// tangential springs: not bitwise).
template <int D>
void restore_dem(std::unique_ptr<DemDomain<D>>& dem, const Decomposition<D>& dec,
                 DemCheckpoint<D>&& loaded) {
  dem = std::make_unique<DemDomain<D>>(dec, dem->params(), std::move(loaded.walls),
                                       std::move(loaded.particles), dem->halo_range(),
                                       DemDomain<D>::Input::Share);
  dem->adopt_forces();
}

}  // namespace sphdem
