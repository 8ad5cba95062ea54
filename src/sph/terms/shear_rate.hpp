#pragma once
// The shear rate, a neighbour-sum pass (pass_loop.hpp): per resin particle
//   L_i = sum_j V_j (v~_j - v_i) (x) grad W_ij,   grad W_ij = F_ij x_ij,
//   D_i = (L_i + L_i^T) / 2,   gamma_dot_i = sqrt(2 D_i : D_i),
// with V_j = m_j / rho_j, v~_j the no-slip velocity a wall neighbour shows
// the viscous term (vwall; a resin neighbour's own velocity) and F the
// lattice-corrected kernel gradient factor, so L is exact for a linear
// velocity field on the full lattice (docs/physics.md, "Shear rate"). It
// is the input of a shear-thinning viscosity; output.fields: shear_rate.
#include <cmath>
#include <cstddef>
#include <vector>

#include "../record_fields.hpp"

namespace sphdem::terms {

// gamma_dot = sqrt(2 D:D) of a velocity gradient L (row-major, L[a D + b]
// = dv_a/dx_b).
template <int D>
double shear_rate_of_gradient(const double* L) {
  double dd = 0.0;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) {
      const double d = 0.5 * (L[a * D + b] + L[b * D + a]);
      dd += d * d;
    }
  return std::sqrt(2.0 * dd);
}

namespace field {
// The pass's result, for a term that reads it (its Reads or OwnReads).
struct ShearRate : ScalarField {
  static constexpr const char* name = "shear_rate";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.shear_rate[i];
  }
};
}  // namespace field

struct ShearRatePass {
  static constexpr const char* name = "shear_rate";
  using Reads = Fields<field::Pos, field::VelWall, field::Vol>;
  using Output = field::ShearRate;
  static constexpr SphGroup group = SphGroup::ShearRate;
  template <int D>
  static constexpr std::size_t kSums = D* D;
  template <int D>
  static std::vector<double>& output(SphParticles<D>& ps) {
    return ps.shear_rate;
  }

  // L_ab += V_j (v~_j - v_i)_a F x_ij,b; the VelWall lane is v_i - v~_j.
  template <class P>
  void pair(const P& p, double* s) const {
    constexpr int D = P::kDim;
    const double w = -p.lane(field::Vol{}) * p.F;
    for (int a = 0; a < D; ++a) {
      const double dv = w * p.lane(field::VelWall{}, a);
      for (int b = 0; b < D; ++b) s[a * D + b] = dv * p.lane(field::Pos{}, b);
    }
  }
  template <int D>
  double finish(const double* sums) const {
    return shear_rate_of_gradient<D>(sums);
  }
};

}  // namespace sphdem::terms
