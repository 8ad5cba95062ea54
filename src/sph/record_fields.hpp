#pragma once
// The per-particle record fields every term may declare in its Reads
// (term_interface.hpp). A term that needs a quantity of its own computed
// once per particle defines its field in its own header (pressure.hpp's
// P/rho^2, anti_clump.hpp's R_a). The pair loop packs the fields the active terms declare, and only
// those, into one record per particle.
#include <cstddef>

#include "term_interface.hpp"

namespace sphdem::terms::field {

// Position; its lane is x_ij = x_i - x_j.
struct Pos : RelativeVectorField<Pos> {
  static constexpr const char* name = "x";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    for (int d = 0; d < D; ++d) out[d] = ps.x[i][d];
  }
};

// Own velocity; its lane is v_ij = v_i - v_j (continuity).
struct Vel : RelativeVectorField<Vel> {
  static constexpr const char* name = "v";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    for (int d = 0; d < D; ++d) out[d] = ps.v[i][d];
  }
};

// The velocity the viscous terms see (a wall's no-slip value); its lane is
// v_i - vw_j.
struct VelWall : RelativeVectorField<Vel> {
  static constexpr const char* name = "vwall";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    for (int d = 0; d < D; ++d) out[d] = ps.vwall[i][d];
  }
};

struct Mass : ScalarField {
  static constexpr const char* name = "m";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.mass[i];
  }
};

struct Rho : ScalarField {
  static constexpr const char* name = "rho";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.rho[i];
  }
};

// m / rho, one division per particle instead of one per pair.
struct Vol : ScalarField {
  static constexpr const char* name = "vol";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.mass[i] / ps.rho[i];
  }
};

// 1 for resin, 0 for wall: a factor instead of a branch in the pair loop.
struct Fluid : ScalarField {
  static constexpr const char* name = "fluid";
  template <int D>
  static void fill(const SphParams&, const SphParticles<D>& ps, std::size_t i, double* out) {
    out[0] = ps.kind[i] == Kind::Fluid ? 1.0 : 0.0;
  }
};

}  // namespace sphdem::terms::field
