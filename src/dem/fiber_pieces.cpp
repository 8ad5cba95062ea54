// Fibers split by broken bonds (include/sphdem/dem/fiber_pieces.hpp):
// union-find over the intact bonds, each set rooted at its smallest gid.
#include "sphdem/dem/fiber_pieces.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace sphdem {

namespace {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t root(std::size_t a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  // The smaller index (the smaller gid: indices follow gid order) stays the root.
  void join(std::size_t a, std::size_t b) {
    a = root(a);
    b = root(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace

FiberPieces fiber_pieces(const FiberPieceInput& in) {
  const std::size_t n = in.gid.size();
  std::vector<std::size_t> order(n);  // rank in gid order -> input row
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return in.gid[a] < in.gid[b]; });
  std::vector<std::int64_t> sorted(n);
  for (std::size_t k = 0; k < n; ++k) sorted[k] = in.gid[order[k]];
  const auto rank_of = [&](std::int64_t g) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), g);
    if (it == sorted.end() || *it != g)
      throw std::invalid_argument("fiber_pieces: a bond names particle " + std::to_string(g) +
                                  ", which is not among the particles");
    return static_cast<std::size_t>(it - sorted.begin());
  };
  UnionFind sets(n);
  for (const auto& [a, b] : in.bonds) sets.join(rank_of(a), rank_of(b));
  std::vector<double> length(n, 0.0);  // by root rank
  for (std::size_t k = 0; k < n; ++k)
    if (in.fiber[order[k]] >= 0) length[sets.root(k)] += 2.0 * in.radius[order[k]];
  FiberPieces out;
  out.piece.assign(n, -1);
  out.length.assign(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t row = order[k];
    if (in.fiber[row] < 0) continue;
    const std::size_t r = sets.root(k);
    out.piece[row] = sorted[r];
    out.length[row] = length[r];
  }
  return out;
}

}  // namespace sphdem
