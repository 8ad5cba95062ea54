// No-slip dummy wall particles, Adami, Hu & Adams (2012), JCP 231:7057.
// For a wall particle w with resin neighbors f:
//   P_w = (sum_f P_f W_wf + (g - a_w) . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf
//   rho_w = EOS^-1(P_w)
//   v_w(no-slip) = 2 v_w - sum_f v_f W_wf / sum_f W_wf
// A wall particle with no resin neighbor gets P = 0, rho = rho0 and its own
// velocity. Negative wall pressures are clipped at the wall's floor: 0, or
// minus a moving wall's adhesion_pressure.
// The resin sees the wall through these values in the rate loop.
#include <algorithm>

#include "sphdem/sph/sph.hpp"

namespace sphdem {

template <int D>
std::vector<WallFaceSample> compute_wall_state(const SphParams& sp, const TaitEos& eos,
                                               const NeighborList<D>& nl,
                                               const std::vector<WallKinematics<D>>& walls,
                                               SphParticles<D>& ps) {
  const WendlandC2<D> kernel(sp.h);
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = sp.body_force[k];
  std::vector<WallFaceSample> face;
  const std::int32_t* nb = nl.indices();
  for (std::size_t w = 0; w < ps.n_owned; ++w) {
    if (ps.kind[w] != Kind::Wall) continue;
    const Vec<D> xw = ps.x[w];
    double sum_w = 0.0, sum_p = 0.0;
    Vec<D> sum_rho_r = Vec<D>::Zero(), sum_v = Vec<D>::Zero();
    for (std::size_t n = nl.begin(w), e = nl.end(w); n < e; ++n) {
      const std::int32_t f = nb[n];
      const Vec<D> r_wf = xw - ps.x[f];
      const double W = kernel.w(r_wf.norm());
      if (W == 0.0) continue;
      sum_w += W;
      sum_p += ps.p[f] * W;
      sum_rho_r += (ps.rho[f] * W) * r_wf;
      sum_v += W * ps.v[f];
    }
    const std::int32_t k = ps.wall[w];
    if (sum_w <= 0.0) {
      ps.p[w] = 0.0;
      ps.rho[w] = eos.rho0();
      ps.vwall[w] = ps.v[w];
      continue;
    }
    const bool listed = k >= 0 && static_cast<std::size_t>(k) < walls.size();
    const Vec<D> a_w = listed ? walls[static_cast<std::size_t>(k)].accel : Vec<D>::Zero();
    // A wall pushes but does not pull (floor 0): resin may leave it, the gap
    // filling with air at ambient (gauge 0) pressure. A moving wall may hold
    // the resin up to its adhesion pressure (floor = -adhesion_pressure).
    const double floor = listed ? walls[static_cast<std::size_t>(k)].pressure_floor : 0.0;
    const double p = std::max(floor, (sum_p + (g - a_w).dot(sum_rho_r)) / sum_w);
    ps.p[w] = p;
    ps.rho[w] = eos.density(p);
    ps.vwall[w] = 2.0 * ps.v[w] - sum_v / sum_w;
    if (listed) face.push_back({ps.gid[w], k, p});
  }
  return face;
}

template <int D>
void compute_fluid_pressure(const TaitEos& eos, SphParticles<D>& ps) {
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (ps.kind[i] == Kind::Fluid) {
      ps.p[i] = eos.pressure(ps.rho[i]);
      ps.vwall[i] = ps.v[i];  // resin neighbors are seen with their own velocity
    }
  }
}

template std::vector<WallFaceSample> compute_wall_state<2>(const SphParams&, const TaitEos&,
                                                           const NeighborList<2>&,
                                                           const std::vector<WallKinematics<2>>&,
                                                           SphParticles<2>&);
template std::vector<WallFaceSample> compute_wall_state<3>(const SphParams&, const TaitEos&,
                                                           const NeighborList<3>&,
                                                           const std::vector<WallKinematics<3>>&,
                                                           SphParticles<3>&);
template void compute_fluid_pressure<2>(const TaitEos&, SphParticles<2>&);
template void compute_fluid_pressure<3>(const TaitEos&, SphParticles<3>&);

}  // namespace sphdem
