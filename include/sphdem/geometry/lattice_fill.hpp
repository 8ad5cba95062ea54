#pragma once
// The initial lattice by rows (docs/parallel.md, "Distributed set-up"): row
// q is the line of nodes along x at one (y, z) index; nodes are visited row
// by row, x fastest, which is the order build_initial_particles numbers
// them in (resin first, then walls). A rank can classify and fill any range
// of a row on its own, so the set-up never needs every particle on one
// rank. No MPI here: the solver sums the counts (src/solver/distributed_fill.cpp).
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// What a lattice node becomes: nothing, a wall particle, or resin made in
// fill shape `fill` (>= 0).
struct NodeClass {
  static constexpr int kNone = -2;
  static constexpr int kWall = -1;
  static constexpr int kEmptyCavity = -3;  // inside the mold, in no fill region: no particle
  int value = kNone;
  bool none() const { return value == kNone || value == kEmptyCavity; }
  bool empty_cavity() const { return value == kEmptyCavity; }
  bool wall() const { return value == kWall; }
  bool fluid() const { return value >= 0; }
};

template <int D>
class LatticeFill {
 public:
  // Throws InputError at `domain` for a domain of more than 1e9 spacings
  // along an axis or a periodic length that is not whole spacings, and at
  // `domain` (or `mold` without one) for nodes more than 1e15 spacings from
  // the lattice's origin.
  explicit LatticeFill(const Case& c);
  ~LatticeFill();
  LatticeFill(const LatticeFill&) = delete;
  LatticeFill& operator=(const LatticeFill&) = delete;

  std::int64_t rows() const;
  long x_first() const;  // node index range along x, inclusive
  long x_last() const;
  Vec<D> node(std::int64_t row, long i) const;
  NodeClass classify(const Vec<D>& p) const;
  std::size_t fill_shapes() const;

  // Appends the particle of a classified node (not kNone) to `out`; resin
  // also records its fill shape in `fill_of` (one entry per resin particle).
  void push(SphParticles<D>& out, std::int64_t gid, const Vec<D>& p, NodeClass cls,
            std::vector<std::size_t>& fill_of) const;

  // Throws InputError at the first fill shape with no node (hits: the
  // number of resin nodes of each fill shape over the whole lattice, then
  // the number of empty cavity nodes: fill_shapes() + 1 entries), and at
  // resin.surface_tension when the resin leaves no empty cavity (no free
  // surface for it to act on).
  void check_fill_hits(const std::vector<std::int64_t>& hits) const;

  // The height of p along -body force, which the hydrostatic start measures
  // depth from; -inf when no body force acts along a closed axis.
  double height(const Vec<D>& p) const;

  // The fields that follow from the whole set: hydrostatic densities below
  // `top` (the largest height() of any resin particle, on any rank), initial
  // temperatures, then the initial_fields expressions. Resin particles come
  // first in `out` (fill_of.size() of them). Throws InputError at an
  // expression that is not finite at some particle.
  void finish(SphParticles<D>& out, const std::vector<std::size_t>& fill_of, double top) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sphdem
