// The seeded bend of a placed fiber (fiber_bend.hpp; docs/dem.md "Seeded bend").
#include "sphdem/dem/fiber_bend.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "terms/parallel_bond.hpp"

namespace sphdem {

namespace {

// Particle k's tangent angle and bond k's chord angle for the amplitude theta0.
double tangent(double theta0, int n, double k) {
  return theta0 * std::cos(std::numbers::pi * k / (n - 1));
}

// The centres for theta0, the first at the origin, the axis along x.
void centres(int n, double radius, double theta0, std::vector<double>& x, std::vector<double>& y) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  y.assign(static_cast<std::size_t>(n), 0.0);
  for (int k = 0; k + 1 < n; ++k) {
    const double a = tangent(theta0, n, k + 0.5);
    x[k + 1] = x[k] + 2 * radius * std::cos(a);
    y[k + 1] = y[k] + 2 * radius * std::sin(a);
  }
}

double sagitta_of(int n, double radius, double theta0) {
  std::vector<double> x, y;
  centres(n, radius, theta0, x, y);
  double most = 0;
  for (double v : y) most = std::max(most, v);
  return most / (2 * radius * n);
}

}  // namespace

FiberBend fiber_bend(int n, double radius, double sagitta) {
  if (n < 3 || !(sagitta > 0 && sagitta < 0.25))
    throw std::invalid_argument("fiber_bend: needs n >= 3 and a sagitta in (0, 0.25)");
  // Every chord's rise grows with theta0 while the steepest (the first)
  // stays below 90 degrees; there the sagitta is at least 0.25 (n = 4).
  double lo = 0, hi = 0.5 * std::numbers::pi / std::cos(0.5 * std::numbers::pi / (n - 1));
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (sagitta_of(n, radius, mid) < sagitta ? lo : hi) = mid;
  }
  const double theta0 = 0.5 * (lo + hi);
  FiberBend b;
  centres(n, radius, theta0, b.along, b.across);
  const double middle = 0.5 * b.along.back();
  for (double& x : b.along) x -= middle;
  for (int k = 0; k + 1 < n; ++k)
    b.turn.push_back(tangent(theta0, n, k + 1) - tangent(theta0, n, k));
  return b;
}

template <int D>
Vec<D> bend_direction(const Vec<D>& u) {
  if constexpr (D == 2) {
    return Vec<D>(-u[1], u[0]);
  } else {
    const Vec<D> w(-u[1], u[0], 0.0);
    return w.norm() > 1e-9 ? Vec<D>(w.normalized()) : Vec<D>(1.0, 0.0, 0.0);
  }
}

template <int D>
void preload_bent_bond(const DemParams<D>& p, double radius, double turn, const Vec<D>& u,
                       DemBond<D>& b) {
  const terms::BondSection s = terms::bond_section<D>(p.lambda * radius, p.thickness);
  const double moment = -p.youngs_modulus / (2 * radius) * s.inertia * turn;
  if constexpr (D == 2) {
    b.mb[0] = moment;
  } else {
    b.mb = moment * u.cross(bend_direction<D>(u)).normalized();
  }
}

template Vec<2> bend_direction<2>(const Vec<2>&);
template Vec<3> bend_direction<3>(const Vec<3>&);
template void preload_bent_bond<2>(const DemParams<2>&, double, double, const Vec<2>&, DemBond<2>&);
template void preload_bent_bond<3>(const DemParams<3>&, double, double, const Vec<3>&, DemBond<3>&);

}  // namespace sphdem
