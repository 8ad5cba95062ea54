#pragma once
// Dashpot coefficient of a linear spring-dashpot for a restitution
// coefficient e (docs/validation.md section 2; Cundall & Strack 1979):
//   c = -2 ln e sqrt(m_eff k) / sqrt(pi^2 + ln^2 e),
// i.e. the damping ratio zeta = -ln e / sqrt(pi^2 + ln^2 e). With the
// normal force left unclipped (contact_linear.hpp) a head-on impact then
// rebounds with exactly e and lasts t_c = pi / sqrt(k/m_eff - (c/2m_eff)^2).
#include <cmath>
#include <numbers>

namespace sphdem::terms {

inline double restitution_damping(double e, double m_eff, double k) {
  if (e >= 1.0) return 0.0;
  const double le = std::log(e);
  return -2.0 * le * std::sqrt(m_eff * k) /
         std::sqrt(std::numbers::pi * std::numbers::pi + le * le);
}

}  // namespace sphdem::terms
