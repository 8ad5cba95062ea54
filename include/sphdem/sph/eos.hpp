#pragma once
// Tait equation of state (docs/physics.md): P = B ((rho/rho0)^gamma - 1) + Pa,
// B = c0^2 rho0 / gamma, Pa the ambient pressure (resin.ambient_pressure, 0
// by default: gauge pressure). gamma = 7 takes a fast path.
#include <cmath>

namespace sphdem {

class TaitEos {
 public:
  TaitEos(double rho0, double c0, double gamma = 7.0, double ambient = 0.0)
      : rho0_(rho0), c0_(c0), gamma_(gamma), b_(c0 * c0 * rho0 / gamma), ambient_(ambient) {}

  double pressure(double rho) const {
    const double s = rho / rho0_;
    if (gamma_ == 7.0) {
      const double s2 = s * s;
      return b_ * (s2 * s2 * s2 * s - 1.0) + ambient_;
    }
    return b_ * (std::pow(s, gamma_) - 1.0) + ambient_;
  }

  // Inverse: the density at which the pressure is p. Pressures below Pa - B
  // (a vacuum) map to a tiny positive density instead of NaN.
  double density(double p) const {
    const double base = (p - ambient_) / b_ + 1.0;
    return rho0_ * std::pow(base > 1e-12 ? base : 1e-12, 1.0 / gamma_);
  }

  double rho0() const { return rho0_; }
  double c0() const { return c0_; }
  double gamma() const { return gamma_; }
  double b() const { return b_; }
  double ambient() const { return ambient_; }

 private:
  double rho0_, c0_, gamma_, b_, ambient_;
};

}  // namespace sphdem
