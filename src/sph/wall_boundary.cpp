// Dummy wall particles, Adami, Hu & Adams (2012), JCP 231:7057.
// For a wall particle w with resin neighbors f:
//   P_w = (sum_f P_f W_wf + (g - a_w) . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf
//   rho_w = EOS^-1(P_w)
//   v_w(no-slip) = 2 v_w - v~,  v~ = sum_f v_f W_wf / sum_f W_wf
// and, with resin.thermal, the temperature the wall shows the resin the
// same way: T_w = 2 T_s - T~ (dummy_temperature, src/sph/heat.cpp).
// Slip walls (docs/physics.md "Wall conditions") keep the normal part of the
// no-slip velocity (the wall stays impermeable) and change the tangential
// part, see dummy_velocity below.
// A wall particle with no resin neighbor gets P = 0 (gauge: the ambient
// pressure), rho = rho0 and its own velocity. Wall pressures are clipped
// at the wall's floor: -Pa (absolute zero: the wall holds the resin until it
// would cavitate, Pa = resin.ambient_pressure, 0 by default), less a moving
// wall's adhesion_pressure.
// The resin sees the wall through these values in the rate loop.
#include <algorithm>

#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

// The velocity the resin sees at a dummy particle of velocity vw, at depth
// d = |s| behind the wall (s: from the particle to the wall surface, along
// the normal into the resin), given the resin's Shepard mean v~. With
// r = v~ - vw split into normal and tangential parts r_n, r_t:
//   u = vw - r_n + f r_t,
// f = -1: no-slip (u = 2 vw - v~, Adami et al. 2012); f = 1: free slip
// (the tangential velocity is the resin's; the wall exerts no shear);
// Navier slip with length b: f = (b - d) / (b + d), the value at depth d of
// the linear profile that reaches vw at b behind the wall (the Navier
// condition u_slip = b du/dn), mirrored as in the no-slip case; this is the
// fictitious-particle extrapolation of Morris, Fox & Zhu (1997, JCP
// 136:214) with the profile's zero moved from the wall to b behind
// it. b = 0 gives no-slip, b -> infinity free slip.
template <int D>
Vec<D> dummy_velocity(const WallSlipLaw& law, const Vec<D>& vw, const Vec<D>& v_mean,
                      const Vec<D>& s) {
  const double d = s.norm();
  if (law.type == WallSlip::NoSlip || !(d > 0.0)) return 2.0 * vw - v_mean;
  const Vec<D> n = s / d;
  const Vec<D> r = v_mean - vw;
  const Vec<D> r_n = n.dot(r) * n;
  const double b = law.slip_length;
  const double f = law.type == WallSlip::FreeSlip ? 1.0 : (b - d) / (b + d);
  return vw - r_n + f * (r - r_n);
}

template <int D>
std::vector<WallFaceSample> compute_wall_state(const SphParams& sp, const TaitEos& eos,
                                               const NeighborList<D>& nl,
                                               const std::vector<WallKinematics<D>>& walls,
                                               SphParticles<D>& ps) {
  const WendlandC2<D> kernel(sp.h);
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = sp.body_force[k];
  std::vector<WallFaceSample> face;
  lanes::for_each_of_kind(ps.kind.data(), ps.n_owned, Kind::Wall, [&](std::size_t w) {
    const Vec<D> xw = ps.x[w];
    double sum_w = 0.0, sum_p = 0.0, sum_t = 0.0;
    Vec<D> sum_rho_r = Vec<D>::Zero(), sum_v = Vec<D>::Zero();
    const NeighborRow nb = nl.row(w);
    for (std::size_t n = nl.begin(w), e = nl.end(w); n < e; ++n) {
      const std::int32_t f = nb[n];
      const Vec<D> r_wf = xw - ps.x[f];
      const double W = kernel.w(r_wf.norm());
      if (W == 0.0) continue;
      sum_w += W;
      sum_p += ps.p[f] * W;
      sum_rho_r += (ps.rho[f] * W) * r_wf;
      sum_v += W * ps.v[f];
      if (sp.thermal) sum_t += W * ps.temperature[f];
    }
    const std::int32_t k = ps.wall[w];
    const bool listed = k >= 0 && static_cast<std::size_t>(k) < walls.size();
    if (sp.thermal) {
      const WallThermalLaw& heat =
          listed ? walls[static_cast<std::size_t>(k)].thermal : sp.mold_thermal;
      if (sum_w > 0.0)
        ps.temperature[w] =
            dummy_temperature(heat, sp.conductivity, sum_t / sum_w, ps.wall_to_surface[w].norm());
      else if (!heat.adiabatic)
        ps.temperature[w] = heat.temperature;
    }
    if (sum_w <= 0.0) {
      ps.p[w] = 0.0;
      ps.rho[w] = eos.rho0();
      ps.vwall[w] = ps.v[w];
      return;
    }
    const Vec<D> a_w = listed ? walls[static_cast<std::size_t>(k)].accel : Vec<D>::Zero();
    // A wall pulls the resin at most down to absolute zero, gauge -Pa: the
    // air pushes on the resin's free surface with Pa and nothing pushes back
    // in a gap at the wall until the resin cavitates (Pa = 0, the default: a
    // wall pushes but does not pull). A moving wall may hold the resin
    // further, by its adhesion pressure (pressure_floor = -adhesion_pressure).
    const double floor =
        (listed ? walls[static_cast<std::size_t>(k)].pressure_floor : 0.0) - sp.ambient_pressure;
    const double p = std::max(floor, (sum_p + (g - a_w).dot(sum_rho_r)) / sum_w);
    ps.p[w] = p;
    ps.rho[w] = eos.density(p);
    const WallSlipLaw& law = listed ? walls[static_cast<std::size_t>(k)].slip : sp.mold_wall;
    // Held only when some wall slips (drop_unused_fields); no-slip does not read it.
    const Vec<D> to_surface =
        ps.wall_to_surface.empty() ? Vec<D>::Zero() : Vec<D>(ps.wall_to_surface[w]);
    ps.vwall[w] = dummy_velocity<D>(law, ps.v[w], sum_v / sum_w, to_surface);
    if (listed) face.push_back({ps.gid[w], k, p});
  });
  return face;
}

// With AVX-512 and the fast Tait path (gamma = 7), eight particles at a
// time, with AVX2 four (tait_pressure7: the bits of TaitEos::pressure).
template <int D>
void compute_fluid_pressure(const TaitEos& eos, double floor, SphParticles<D>& ps) {
  const std::size_t n = ps.size();
  std::size_t i = 0;
#if defined(SPHDEM_PARTICLE_LANES)
  if (eos.gamma() == 7.0 && n > 0) {
    const Kind* const kind = ps.kind.data();
    const double* const rho = ps.rho.data();
    double* const p = ps.p.data();
    const double* const v = ps.v.data()->data();
    double* const vwall = ps.vwall.data()->data();
    const __m512d lowest = _mm512_set1_pd(floor);
    for (; i + 8 <= n; i += 8) {
      const __mmask8 fluid = lanes::resin(kind, i);
      if (fluid == 0) continue;
      __m512d pi = tait_pressure7(eos, _mm512_maskz_loadu_pd(fluid, rho + i));
      pi = _mm512_mask_mov_pd(pi, _mm512_cmp_pd_mask(pi, lowest, _CMP_LT_OQ), lowest);
      _mm512_mask_storeu_pd(p + i, fluid, pi);
      for (int q = 0; q < D; ++q) {
        const std::size_t k = D * i + 8 * static_cast<std::size_t>(q);
        const __mmask8 m = lanes::vector_mask<D>(fluid, q);
        _mm512_mask_storeu_pd(vwall + k, m, _mm512_maskz_loadu_pd(m, v + k));
      }
    }
  }
#elif defined(SPHDEM_PARTICLE_LANES4)
  // Four at a time (AVX2): the walls' values blended back as they were read.
  if (eos.gamma() == 7.0 && n > 0) {
    const Kind* const kind = ps.kind.data();
    const double* const rho = ps.rho.data();
    double* const p = ps.p.data();
    const double* const v = ps.v.data()->data();
    double* const vwall = ps.vwall.data()->data();
    const __m256d lowest = _mm256_set1_pd(floor);
    for (; i + 4 <= n; i += 4) {
      const unsigned fluid = lanes::resin4(kind, i);
      if (fluid == 0) continue;
      __m256d pi = tait_pressure7(eos, _mm256_loadu_pd(rho + i));
      pi = _mm256_blendv_pd(pi, lowest, _mm256_cmp_pd(pi, lowest, _CMP_LT_OQ));
      _mm256_storeu_pd(
          p + i, _mm256_blendv_pd(_mm256_loadu_pd(p + i), pi, lanes::vector_mask4<1>(fluid, 0)));
      for (int q = 0; q < D; ++q) {
        const std::size_t k = D * i + 4 * static_cast<std::size_t>(q);
        _mm256_storeu_pd(vwall + k,
                         _mm256_blendv_pd(_mm256_loadu_pd(vwall + k), _mm256_loadu_pd(v + k),
                                          lanes::vector_mask4<D>(fluid, q)));
      }
    }
  }
#endif
  for (; i < n; ++i) {
    if (ps.kind[i] == Kind::Fluid) {
      // Where the resin would pull harder than it can it opens instead: no
      // more tension than the floor (no floor: -inf, the Tait value as is).
      const double p = eos.pressure(ps.rho[i]);
      ps.p[i] = p < floor ? floor : p;
      ps.vwall[i] = ps.v[i];  // resin neighbors are seen with their own velocity
    }
  }
}

template Vec<2> dummy_velocity<2>(const WallSlipLaw&, const Vec<2>&, const Vec<2>&, const Vec<2>&);
template Vec<3> dummy_velocity<3>(const WallSlipLaw&, const Vec<3>&, const Vec<3>&, const Vec<3>&);
template std::vector<WallFaceSample> compute_wall_state<2>(const SphParams&, const TaitEos&,
                                                           const NeighborList<2>&,
                                                           const std::vector<WallKinematics<2>>&,
                                                           SphParticles<2>&);
template std::vector<WallFaceSample> compute_wall_state<3>(const SphParams&, const TaitEos&,
                                                           const NeighborList<3>&,
                                                           const std::vector<WallKinematics<3>>&,
                                                           SphParticles<3>&);
template void compute_fluid_pressure<2>(const TaitEos&, double, SphParticles<2>&);
template void compute_fluid_pressure<3>(const TaitEos&, double, SphParticles<3>&);

}  // namespace sphdem
