#pragma once
// How small the cells of the resin's decomposition may be. Its own header,
// so that `sphdem partition` (src/parallel/partition_report.cpp) builds its
// grid with the run's function without the resin module's headers.
#include "sphdem/config/case.hpp"

namespace sphdem {

// The smallest cell edge of the resin's decomposition (which a coupled
// run's fibers share): the neighbour list's cut-off, or with implicit bonds
// a fiber's chain reach (implicit_chain_reach, fiber_module.hpp) when that
// is larger. The run's grid (ResinModule) and `sphdem partition`'s are both
// built from it.
double resin_min_cell(const Case& c, double neighbor_cutoff);

}  // namespace sphdem
