#pragma once
// Structure-of-arrays storage for SPH particles (resin and wall), with the
// field registry (field_registry.hpp, docs/architecture.md "Adding a
// field"): every per-particle field is one line of SPHDEM_SPH_FIELDS, with
// its policy. Owned particles come first, [0, n_owned), ghosts after,
// [n_owned, size()).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sphdem/particles/field_registry.hpp"

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

// The resin's per-step ghost exchanges (Halo::forward): State before the
// rates, to every ghost; WallState after the wall extrapolation, to the
// wall ghosts only (docs/parallel.md, "The step"); ShearRate after the
// shear-rate pass, FreeSurface after the free-surface pass, SurfaceNormal and
// Curvature after the surface-tension passes, when they run
// (src/sph/pass_loop.hpp).
// Viscous: the implicit viscous solve's vector, at each of its iterations.
// Shift: the particle shifts of the step, when the density follows them.
enum class SphGroup : std::uint8_t {
  State = 0,
  WallState = 1,
  ShearRate = 2,
  FreeSurface = 3,
  SurfaceNormal = 4,
  Curvature = 5,
  Viscous = 6,
  Shift = 7
};

// The SPH field registry (field_registry.hpp): X(type, member, policy).
#define SPHDEM_SPH_FIELDS(X)                                                                      \
  /* Identity and constants. */                                                                   \
  X(std::int64_t, gid, kGhost | kMigrate | kCheckpoint) /* global id, dense per kind */           \
  X(Kind, kind, kGhost | kMigrate | kCheckpoint | output_as("kind", "1")) /* fluid or wall */     \
  /* index of the moving/sliding wall, -1 = fixed or fluid */                                     \
  X(std::int32_t, wall, kGhost | kMigrate | kCheckpoint | output_as("wall_id", "1"))              \
  X(double, mass, kGhost | kMigrate | kCheckpoint) /* [kg] (2D: per unit depth, kg/m) */          \
  /* walls: from the particle to the nearest point of the mold's surface (slip walls) [m] */      \
  X(Vec<D>, wall_to_surface, kGhost | kMigrate | kCheckpoint)                                     \
  /* State. */                                                                                    \
  X(Vec<D>, x, kGhost | in_group(SphGroup::State) | kShifted | kMigrate | kCheckpoint) /* [m] */  \
  /* velocity; for walls the wall's own velocity */                                               \
  X(Vec<D>, v,                                                                                    \
    kGhost | in_group(SphGroup::State) | kMigrate | kCheckpoint | output_as("velocity", "m/s"))   \
  /* density; walls: extrapolated (Adami) */                                                      \
  X(double, rho,                                                                                  \
    kGhost | in_group(SphGroup::State) | in_group(SphGroup::WallState) | kMigrate | kCheckpoint | \
        output_as("density", "kg/m^3"))                                                           \
  /* temperature (resin.thermal); walls: the dummy value the resin sees (Adami-style). */         \
  /* Checkpointed by the resin module when the case is thermal (not kCheckpoint: checkpoints */   \
  /* of isothermal cases keep their format). */                                                   \
  X(double, temperature,                                                                          \
    kGhost | in_group(SphGroup::State) | in_group(SphGroup::WallState) | kMigrate |               \
        output_as("temperature", "K"))                                                            \
  X(double, dtemp, kMigrate) /* dT/dt [K/s] (owned resin) */                                      \
  /* 1: below the no-flow temperature this step (holds its position) */                           \
  X(std::int32_t, frozen, kMigrate | output_as("frozen", "1"))                                    \
  /* 1 once two front segments met here (output.front_events, src/sph/front_events.cpp) */        \
  X(std::int32_t, weld_line, kMigrate | kCheckpoint | output_as("weld_line", "1"))                \
  /* Derived every rate evaluation. */                                                            \
  /* pressure; walls: extrapolated */                                                             \
  X(double, p, kGhost | in_group(SphGroup::WallState) | output_as("pressure", "Pa"))              \
  /* walls: the velocity seen by the viscous term (no-slip) */                                    \
  X(Vec<D>, vwall, kGhost | in_group(SphGroup::WallState))                                        \
  /* acceleration, density rate (owned fluid) */                                                  \
  X(Vec<D>, a, kMigrate | kCheckpoint | output_as("acceleration", "m/s^2"))                       \
  X(double, drho, kMigrate | kCheckpoint) /* [kg/m^3/s] */                                        \
  /* sqrt(2 D:D), from a neighbour-sum pass when requested (src/sph/terms/shear_rate.hpp) */      \
  X(double, shear_rate, in_group(SphGroup::ShearRate) | output_as("shear_rate", "1/s"))           \
  /* generalized-Newtonian viscosity [Pa s] of resin particles, owned and ghosts: each rank */    \
  /* evaluates the law at the forwarded shear rate (src/sph/terms/viscosity_variable.hpp); */     \
  /* checkpointed because the next step's viscous limit reads it */                               \
  X(double, viscosity, kMigrate | kCheckpoint | output_as("viscosity", "Pa s"))                   \
  /* free-surface pass (src/sph/terms/free_surface.hpp): 1 on the surface, else 0; the */         \
  /* outward unit normal there (0 inside); div r; the shifting gradient (owned only) */           \
  X(double, free_surface, in_group(SphGroup::FreeSurface) | output_as("free_surface", "1"))       \
  X(Vec<D>, surface_normal, in_group(SphGroup::FreeSurface) | output_as("surface_normal", "1"))   \
  X(double, position_divergence, kLocal | output_as("position_divergence", "1"))                  \
  X(Vec<D>, shifting_gradient, kLocal)                                                            \
  /* the step's particle shift [m], owned and ghosts (numerics.shifting_continuity) */            \
  X(Vec<D>, shift, in_group(SphGroup::Shift))                                                     \
  /* surface tension (src/sph/terms/surface_tension.hpp): the Shepard colour, the unit */         \
  /* outward normal where it is reliable (else 0); the curvature at the surface */                \
  X(double, colour, in_group(SphGroup::SurfaceNormal) | output_as("colour", "1"))                 \
  X(Vec<D>, csf_normal, in_group(SphGroup::SurfaceNormal) | output_as("csf_normal", "1"))         \
  X(double, curvature, in_group(SphGroup::Curvature) | output_as("curvature", "1/m"))             \
  /* implicit viscosity (src/sph/implicit_viscosity.cpp): the vector the operator reads, and */   \
  /* 1 for an unknown of the solve (resin not frozen), 0 for a known value (walls, frozen) */     \
  X(Vec<D>, visc_u, in_group(SphGroup::Viscous))                                                  \
  X(double, visc_free, in_group(SphGroup::Viscous))                                               \
  /* the last solve's viscous acceleration (u - v) / dt: the next solve's first guess; */         \
  /* checkpointed by the resin module when the case is implicit */                                \
  X(Vec<D>, visc_acc, kMigrate)                                                                   \
  /* Integrator state within a step: half-step values (owned only). They */                       \
  /* migrate: the neighbor rebuild (and so migration) sits between the */                         \
  /* drift and the second kick, which reads them. */                                              \
  X(Vec<D>, v_half, kMigrate)                                                                     \
  X(double, rho_half, kMigrate)                                                                   \
  X(double, temp_half, kMigrate)

template <int D>
struct SphParticles {
  std::size_t n_owned = 0;

  SPHDEM_FIELD_REGISTRY(SPHDEM_SPH_FIELDS)

  std::size_t size() const { return x.size(); }
  std::size_t n_ghost() const { return size() - n_owned; }

  // Appends one owned particle (only valid while there are no ghosts);
  // the fields not given here start at zero.
  void push_owned(std::int64_t id, Kind k, std::int32_t wall_index, double m, const Vec<D>& pos,
                  const Vec<D>& vel, double density) {
    const std::size_t i = size();
    resize(i + 1);
    zero_particle(i);
    gid[i] = id;
    kind[i] = k;
    wall[i] = wall_index;
    mass[i] = m;
    x[i] = pos;
    v[i] = vel;
    rho[i] = density;
    vwall[i] = vel;
    v_half[i] = vel;
    rho_half[i] = density;
    n_owned = i + 1;
  }

  // Whether particle i holds its position this step (below the no-flow
  // temperature); only thermal cases hold the flag (drop_unused_fields).
  bool is_frozen(std::size_t i) const { return !frozen.empty() && frozen[i] != 0; }

  // Drops every ghost.
  void clear_ghosts() { resize(n_owned); }

  // Reorders the owned particles: new slot k holds old particle order[k].
  void permute_owned(const std::vector<std::size_t>& order) { permute_owned_fields(*this, order); }
};

// What `output.fields` may name: the output names of the registry, in
// registry order (docs/case-file.md, "output").
inline std::vector<std::string> sph_output_fields() {
  std::vector<std::string> names;
  SphParticles<2>().for_each_field([&](const char*, const auto&, FieldPolicy p) {
    if (p.output) names.emplace_back(p.output);
  });
  return names;
}

}  // namespace sphdem
