// Periodic wrap and particle migration (docs/parallel.md).
#include <cmath>

#include "migrate.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/particles/dem_particles.hpp"

namespace sphdem {

template <int D, class Ps>
void wrap_positions(Ps& ps, const Box<D>& box, const std::array<bool, 3>& periodic) {
  for (int k = 0; k < D; ++k) {
    if (!periodic[static_cast<std::size_t>(k)]) continue;
    const double len = box.hi[k] - box.lo[k];
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      double& x = ps.x[i][k];
      if (x < box.lo[k] || x >= box.hi[k]) x -= len * std::floor((x - box.lo[k]) / len);
    }
  }
}

template <int D>
void wrap_periodic(SphParticles<D>& ps, const Box<D>& box, const std::array<bool, 3>& periodic) {
  wrap_positions<D>(ps, box, periodic);
}

template <int D>
void wrap_periodic(DemParticles<D>& ps, const Box<D>& box, const std::array<bool, 3>& periodic) {
  wrap_positions<D>(ps, box, periodic);
}

template void wrap_periodic<2>(DemParticles<2>&, const Box<2>&, const std::array<bool, 3>&);
template void wrap_periodic<3>(DemParticles<3>&, const Box<3>&, const std::array<bool, 3>&);
template void wrap_periodic<2>(SphParticles<2>&, const Box<2>&, const std::array<bool, 3>&);
template void wrap_periodic<3>(SphParticles<3>&, const Box<3>&, const std::array<bool, 3>&);
template MigrationCounts migrate<2>(const Decomposition<2>&, SphParticles<2>&);
template MigrationCounts migrate<3>(const Decomposition<3>&, SphParticles<3>&);
template MigrationCounts migrate<2>(const Decomposition<2>&, DemParticles<2>&);
template MigrationCounts migrate<3>(const Decomposition<3>&, DemParticles<3>&);
template MigrationCounts migrate_in_place<2>(const Decomposition<2>&, DemParticles<2>&);
template MigrationCounts migrate_in_place<3>(const Decomposition<3>&, DemParticles<3>&);

}  // namespace sphdem
