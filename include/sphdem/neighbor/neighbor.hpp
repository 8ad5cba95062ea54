#pragma once
// Neighbor search: a cell grid (cells no smaller than the cut-off, counting
// sort, linear in the particle count) builds Verlet lists with a skin.
// Lists are kept for owned particles only and each list is sorted by global
// id, so the sums of the gather formulation run in an order that does not
// depend on the particle layout or the rank count.
#include <cstdint>
#include <vector>

#include "sphdem/particles/particles.hpp"

namespace sphdem {

template <int D>
class NeighborList {
 public:
  // cutoff = support (2h) + skin.
  NeighborList(double support, double skin) : support_(support), skin_(skin) {}

  // Builds lists for every owned particle over all particles (ghosts
  // included). Fluid particles list fluid and wall neighbors; wall particles
  // list only fluid neighbors (what the wall extrapolation needs).
  void build(const SphParticles<D>& ps);

  // True once some owned particle has moved more than half the skin since
  // the last build (a local answer; the solver reduces it over ranks).
  bool needs_rebuild(const SphParticles<D>& ps) const;

  std::size_t begin(std::size_t i) const { return offset_[i]; }
  std::size_t end(std::size_t i) const { return offset_[i + 1]; }
  const std::int32_t* indices() const { return index_.data(); }
  std::size_t total_pairs() const { return index_.size(); }
  double cutoff() const { return support_ + skin_; }
  double skin() const { return skin_; }
  std::int64_t builds() const { return builds_; }
  // Owned positions at the last build (what needs_rebuild compares with):
  // part of a checkpoint, so a restart rebuilds where the run did.
  const std::vector<Vec<D>>& positions_at_build() const { return x_at_build_; }

 private:
  double support_, skin_;
  std::vector<std::uint32_t> offset_;  // 4 bytes per particle (build checks the count)
  std::vector<std::int32_t> index_;
  std::vector<Vec<D>> x_at_build_;
  std::int64_t builds_ = 0;
  // The cell grid's starts, kept to avoid reallocations (the binning's
  // per-particle scratch is shared with sort_by_cell: neighbor_list.cpp).
  std::vector<std::int32_t> cell_start_;
  std::vector<std::int32_t> cell_resin_end_;  // each cell's resin first, then its walls
};

// Reorders owned particles by cell of size `cell` (then by global id) for
// cache locality. Call before rebuilding ghosts and lists.
template <int D>
void sort_by_cell(SphParticles<D>& ps, double cell);

}  // namespace sphdem
