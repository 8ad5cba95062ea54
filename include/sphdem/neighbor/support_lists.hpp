#pragma once
// The lists a 3D step's sums walk: the build's lists cut to the pairs within
// the support and a margin, cut again only once some pair they leave out may
// have come within the support (docs/performance.md, "The support lists").
//
// Why: the resin starts on a cubic lattice and stays near it. Within the
// support 2h = 2.4 spacings lie 56 neighbours; the next shell, 24
// neighbours at sqrt(6) = 2.449 spacings, is 2 % beyond it, so the build's
// skin (3 to 18 % of 2h) always lists it, and every sum walks those pairs
// for exact zeros, a quarter of the 3D pair loop. (In 2D no lattice node
// lies between 2.4 and 2.83 spacings: the lists hold almost nothing to cut.)
//
// A pair left out was at least support + margin apart at the cut; it comes
// within the support only when the two particles' moves since the cut
// differ by more than the margin, and two moves that lie in one box differ
// by at most its diagonal. So the cut is kept while the box of every
// particle's move since the cut (owned and ghosts, this rank's own) has a
// diagonal under the margin. The kept lists are then a superset of the
// pairs within the support, in the build's order, and a pair beyond the
// support adds exact zeros to every sum: the sums are the same bits with
// either lists, whenever each rank cuts (tests: SupportLists.*; the 3D
// molds on 2 ranks against 1, Mold3D.*RankIndependent).
#include <cstdint>
#include <vector>

#include "sphdem/neighbor/neighbor.hpp"

namespace sphdem {

template <int D>
class SupportLists {
 public:
  // support: 2h; margin: how far beyond it the cut keeps pairs.
  SupportLists(double support, double margin) : support_(support), margin_(margin) {}

  // The lists for the particles' positions now (full: the build's lists of
  // these particles, owned and ghosts in the same places).
  const NeighborList<D>& lists(const NeighborList<D>& full, const SphParticles<D>& ps);

  std::int64_t cuts() const { return cuts_; }  // how many times the lists were cut

 private:
  // Whether some particle's move since the cut leaves the box of moves
  // with a diagonal of margin_ or more (or not a number).
  bool moved_past_margin(const SphParticles<D>& ps) const;

  double support_, margin_;
  NeighborList<D> kept_{0.0, 0.0};
  std::vector<double> x_cut_;  // every particle's position at the cut, D doubles each
  std::int64_t full_builds_ = -1;
  std::int64_t cuts_ = 0;
};

// The margin the resin's 3D step cuts with, a fraction of the support:
// under the lattice's 2 % gap to its sixth shell, and wide enough that the
// plate's flow keeps a cut for several steps (docs/performance.md, "The
// support lists").
inline constexpr double kSupportListMargin = 0.015;

// Whether the resin's 3D step walks SupportLists or the build's lists: on
// by default; tests switch it off to show that both give the same bits.
inline bool& support_lists_on() {
  static bool on = true;
  return on;
}

}  // namespace sphdem
