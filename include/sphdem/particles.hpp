#pragma once
// Structure-of-arrays storage for SPH particles (resin and wall), with the
// field registry (STYLE habit 1): every per-particle field is listed once in
// for_each_field(), with its policy. Owned particles come first,
// [0, n_owned), ghosts after, [n_owned, size()).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace sphdem {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

// The first D components of a case-file vector (stored with 3).
template <int D>
Vec<D> to_vec(const std::array<double, 3>& a) {
  Vec<D> v;
  for (int k = 0; k < D; ++k) v[k] = a[k];
  return v;
}

enum class Kind : std::uint8_t { Fluid = 0, Wall = 1 };

// Which stages of the step a field takes part in.
struct FieldPolicy {
  bool ghost;       // copied to ghost particles by the halo exchange
  bool migrate;     // travels with a particle that changes rank
  bool checkpoint;  // part of the restartable state
};

// Reorders the first order.size() particles of any registry container
// (SPH or DEM): new slot k holds old particle order[k].
template <class P>
void permute_owned_fields(P& ps, const std::vector<std::size_t>& order) {
  ps.for_each_field([&](const char*, auto& field, FieldPolicy) {
    using Field = std::decay_t<decltype(field)>;
    Field tmp(field.size());
    for (std::size_t k = 0; k < order.size(); ++k) tmp[k] = field[order[k]];
    for (std::size_t k = order.size(); k < field.size(); ++k) tmp[k] = field[k];
    field.swap(tmp);
  });
}

template <int D>
struct SphParticles {
  std::size_t n_owned = 0;

  // Identity and constants.
  std::vector<std::int64_t> gid;   // global id, dense per kind
  std::vector<Kind> kind;          // fluid or wall
  std::vector<std::int32_t> wall;  // index of the moving/sliding wall, -1 = fixed or fluid
  std::vector<double> mass;        // [kg] (per unit depth in 2D: kg/m)
  // State.
  std::vector<Vec<D>> x;    // position [m]
  std::vector<Vec<D>> v;    // velocity [m/s]; for walls the wall's own velocity
  std::vector<double> rho;  // density [kg/m^3]; walls: extrapolated (Adami)
  // Derived every rate evaluation.
  std::vector<double> p;      // pressure [Pa]; walls: extrapolated
  std::vector<Vec<D>> vwall;  // walls: velocity seen by the viscous term (no-slip)
  std::vector<Vec<D>> a;      // acceleration [m/s^2] (owned fluid)
  std::vector<double> drho;   // density rate [kg/m^3/s] (owned fluid)
  // Integrator state within a step: half-step values (owned only).
  std::vector<Vec<D>> v_half;
  std::vector<double> rho_half;

  std::size_t size() const { return x.size(); }
  std::size_t n_ghost() const { return size() - n_owned; }

  // The registry. f(name, vector, policy) for every per-particle field.
  template <class F>
  void for_each_field(F&& f) {
    f("gid", gid, FieldPolicy{true, true, true});
    f("kind", kind, FieldPolicy{true, true, true});
    f("wall", wall, FieldPolicy{true, true, true});
    f("mass", mass, FieldPolicy{true, true, true});
    f("x", x, FieldPolicy{true, true, true});
    f("v", v, FieldPolicy{true, true, true});
    f("rho", rho, FieldPolicy{true, true, true});
    f("p", p, FieldPolicy{true, false, false});
    f("vwall", vwall, FieldPolicy{true, false, false});
    f("a", a, FieldPolicy{false, true, true});
    f("drho", drho, FieldPolicy{false, true, true});
    // The half-step values migrate: the neighbor rebuild (and so migration)
    // sits between the drift and the second kick, which reads them.
    f("v_half", v_half, FieldPolicy{false, true, false});
    f("rho_half", rho_half, FieldPolicy{false, true, false});
  }

  void resize(std::size_t n) {
    for_each_field([n](const char*, auto& field, FieldPolicy) { field.resize(n); });
  }

  // Appends one owned particle (only valid while there are no ghosts).
  void push_owned(std::int64_t id, Kind k, std::int32_t wall_index, double m, const Vec<D>& pos,
                  const Vec<D>& vel, double density) {
    const std::size_t i = size();
    resize(i + 1);
    gid[i] = id;
    kind[i] = k;
    wall[i] = wall_index;
    mass[i] = m;
    x[i] = pos;
    v[i] = vel;
    rho[i] = density;
    p[i] = 0.0;
    vwall[i] = vel;
    a[i].setZero();
    drho[i] = 0.0;
    v_half[i] = vel;
    rho_half[i] = density;
    n_owned = i + 1;
  }

  // Drops every ghost.
  void clear_ghosts() { resize(n_owned); }

  // Copies particle `src` onto slot `dst` for every field.
  void copy_particle(std::size_t dst, std::size_t src) {
    for_each_field([=](const char*, auto& field, FieldPolicy) { field[dst] = field[src]; });
  }

  // Reorders the owned particles: new slot k holds old particle order[k].
  void permute_owned(const std::vector<std::size_t>& order) { permute_owned_fields(*this, order); }
};

}  // namespace sphdem
