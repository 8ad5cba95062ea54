#pragma once
// How big a case is, estimated from its geometry alone, before anything is
// built (docs/case-file.md, "Size estimate"): `sphdem check` prints it, and
// `check` and `run` refuse a case that cannot fit in memory instead of
// building it for minutes and dying of bad_alloc.
#include <string>

#include "sphdem/config/case.hpp"

namespace sphdem {

struct CaseSize {
  // Particle counts (estimates: fill volumes over spacing^D, the mold's
  // boundary times the wall layers, fibers times particles per fiber).
  double resin = 0, walls = 0, dem = 0;
  double lattice_nodes = 0;  // the filling visits every node of the domain
  double cells = 0;          // the decomposition's top-level cells (every rank holds their map)
  // Peak resident bytes of one rank (docs/scaling.md, "Memory per rank"):
  // at set-up every rank builds every SPH and DEM particle before keeping
  // its share, and keeps their fields' memory; running adds its share's
  // neighbour lists and buffers. Both include the process itself.
  double setup_bytes = 0, run_bytes = 0;
  double bytes_per_rank() const { return setup_bytes > run_bytes ? setup_bytes : run_bytes; }
  // Which part of the case dominates the memory: "numerics.spacing" (the
  // resin and its walls) or the fibers' amount key.
  std::string dominant_key;
};

// `ranks`: the MPI ranks the case runs on (at least 1). Never throws; a
// degenerate case gives infinite or NaN sizes, which no memory fits.
CaseSize estimate_case_size(const Case& c, int ranks);

// "about 1.2 GiB", "about 340 MiB", for messages.
std::string format_bytes(double bytes);

}  // namespace sphdem
