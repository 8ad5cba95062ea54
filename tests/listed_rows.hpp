#pragma once
// Particle i's neighbour list as indices in list order, whatever its
// storage (16- or 32-bit rows): what the list tests compare.
#include <cstdint>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"

namespace sphdem::testing {

template <int D>
std::vector<std::int32_t> listed(const NeighborList<D>& nl, std::size_t i) {
  std::vector<std::int32_t> l;
  const NeighborRow nb = nl.row(i);
  for (std::size_t n = nl.begin(i); n < nl.end(i); ++n) l.push_back(nb[n]);
  return l;
}

}  // namespace sphdem::testing
