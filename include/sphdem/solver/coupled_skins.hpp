#pragma once
// How far the resin and the fibers of a coupled run may move between their
// list builds (docs/parallel.md, "The coupled run's skins"). The coupling's
// drag reads the resin near an owned fiber, its reaction the fibers near an
// owned resin particle; both must be owned or ghosts on the rank. The resin's
// ghosts are those within support + skin (the resin's) of a rank's cells at
// the resin's build, and the fibers' those within at least that much at the
// fibers' own build. A fiber stays within half its skin of its rank's cells
// (its own rebuild rule), and a resin particle within `max_move` of its
// place at the resin's build, so both passes see every partner within the
// support when
//   max_move + fiber skin / 2 <= resin skin.
// The fibers' skin is capped at kFiberSkinShare of the resin's; the resin
// keeps its lists (the box of relative moves) while no particle has moved
// kCoupledResinMoveShare of its skin.
namespace sphdem {

inline constexpr double kFiberSkinShare = 0.5;
inline constexpr double kCoupledResinMoveShare = 1.0 - 0.5 * kFiberSkinShare;
// Past half the skin the box decides (NeighborList::box_needs_rebuild): its
// cap must not be below the first look's half skin.
static_assert(kCoupledResinMoveShare >= 0.5 && kCoupledResinMoveShare <= 1.0);

}  // namespace sphdem
