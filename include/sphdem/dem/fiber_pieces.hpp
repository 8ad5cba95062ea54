#pragma once
// The fibers as they are now (docs/dem.md, "Broken fibers"): a broken bond
// splits its fiber, and each connected piece of intact bonds is a fiber of
// its own. A piece is named by the smallest global id of its particles, so
// its id does not depend on how the particles are split over ranks, and its
// length is the sum of its particles' diameters (a straight chain of
// touching particles end to end: n particles of radius r are 2 n r long).
#include <cstdint>
#include <utility>
#include <vector>

namespace sphdem {

struct FiberPieceInput {
  std::vector<std::int64_t> gid;    // every particle's global id (any order)
  std::vector<std::int32_t> fiber;  // its fiber as placed, -1 = loose (no piece)
  std::vector<double> radius;       // [m]
  std::vector<std::pair<std::int64_t, std::int64_t>> bonds;  // intact bonds, by gid
};

struct FiberPieces {
  // Per particle, in the order of FiberPieceInput::gid: its piece's id (the
  // smallest gid of the piece, -1 for a loose particle) and length [m].
  std::vector<std::int64_t> piece;
  std::vector<double> length;
};

// Connected components of the intact bonds. The lengths are summed in
// increasing gid, so they are bitwise the same for any input order. Throws
// std::invalid_argument for a bond naming an unknown gid.
FiberPieces fiber_pieces(const FiberPieceInput& in);

}  // namespace sphdem
