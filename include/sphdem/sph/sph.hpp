#pragma once
// Weakly compressible SPH for the resin (docs/physics.md). Each physics term
// lives in its own header under src/sph/terms/; the loops that visit the
// neighbor lists are here (fluid_rates.cpp, wall_boundary.cpp). Nothing in
// this module knows about ranks: it reads ghosts and writes owned particles.
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/neighbor/neighbor.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/sph/eos.hpp"
#include "sphdem/sph/kernel.hpp"

namespace sphdem {

struct SphParams {
  double h = 0;
  double spacing = 0;
  double rho0 = 0, c0 = 0, gamma = 7;
  // The air's pressure Pa [Pa]: pressures are gauge (relative to it); it
  // lowers the wall floors to absolute zero (docs/physics.md "Ambient
  // pressure").
  double ambient_pressure = 0;
  // The resin's least gauge pressure, -(Pa + resin.tensile_strength); -inf: none.
  double pressure_floor = -std::numeric_limits<double>::infinity();
  double mu = 0;  // laminar viscosity (0: none); a law: the largest it reaches
  // A generalized-Newtonian law (variable viscosity, per particle): the
  // law, and the melt temperature it reads until the resin has its own
  // temperature field (particle_temperature, viscosity_variable.hpp).
  bool variable_viscosity = false;
  MeltViscosity melt;
  double melt_temperature = 0;  // [K]
  // numerics.viscous_integration implicit: the pair loop leaves the laminar
  // term out and solve_implicit_viscosity (implicit_viscosity.hpp) applies
  // it after the second kick; no viscous time-step limit.
  bool implicit_viscosity = false;
  double mu_scale = 1;    // lattice correction of the viscous Laplacian
  double grad_scale = 1;  // lattice correction of the kernel gradient
  double alpha = 0;       // Monaghan artificial viscosity
  double delta = 0;       // delta-SPH coefficient (0: off)
  bool anti_clump = true;
  double anti_clump_eps = 0.2;
  int anti_clump_n = 4;
  bool anti_clump_at_surface = false;  // the tension branch on surface particles too
  bool front_events = false;           // weld-line flags (front_events.cpp) need the surface
  double eta2 = 0;                     // 0.01 h^2, keeps 1/r^2 terms finite
  double shifting = 0;                 // particle shifting coefficient A (0: off)
  bool shifting_continuity = false;    // the shift enters the density (particle_shifting.cpp)
  bool wall_repulsion = false;         // Monaghan (1994) wall force (wall_repulsion.cpp)
  bool free_surface_traction = false;  // the surface's viscous traction (surface_traction.cpp)
  Vec3a body_force{};
  WallSlipLaw mold_wall;  // the condition of the fixed mold walls (wall index -1)
  // Surface tension (src/sph/terms/surface_tension.hpp): sigma [N/m], 0 = off;
  // each wall's contact angle [deg], by wall index + 1 (0: the fixed mold).
  double surface_tension = 0;
  std::vector<double> contact_angle{90.0};
  // Temperature (resin.thermal, docs/physics.md "Temperature"); off: T is
  // never touched and nothing below runs.
  bool thermal = false;
  double heat_capacity = 0;                                               // c_p [J/(kg K)]
  double conductivity = 0;                                                // k [W/(m K)]
  double no_flow_temperature = -std::numeric_limits<double>::infinity();  // [K]
  bool viscous_heating = false;
  double thermal_factor = 0.1;  // dt <= thermal_factor h^2 rho0 c_p / k
  WallThermalLaw mold_thermal;  // of the fixed mold walls (wall index -1)
  // output.fields: a neighbour-sum pass whose field is named here runs even
  // when no active term reads it (src/sph/pass_loop.hpp).
  std::vector<std::string> output_fields;
};

SphParams make_sph_params(const Case& c);
// Whether some wall of the case (the mold, a moving or a sliding wall) is not no-slip.
bool any_slip_wall(const Case& c);

// Lattice corrections (numerics.lattice_correction). On a Cartesian lattice
// the discrete moment M = -sum_j V_j F(r_j) x_j^2 is not the continuum's 1:
// at h/dp = 1.2 it is 0.964 in 2D (0.985 in 3D), so the SPH gradient of a
// linear field is 3.6 % short and a resin column at rest settles at a
// pressure 3.6 % above rho g depth. Scaling F by 1/M makes gradients (and
// with the Morris weight r^2/(r^2+eta^2), the viscous Laplacian: 1/0.953)
// exact on the lattice the resin starts on. A constant factor keeps the
// pairwise antisymmetry, so momentum stays conserved; it tends to 1 as h/dp
// grows.
double gradient_lattice_correction(int dimension, double h_over_spacing);
double viscous_lattice_correction(int dimension, double h_over_spacing);

// Pressure of every fluid particle, ghosts included, from its density, and
// not below floor (SphParams::pressure_floor: the resin cavitates there).
template <int D>
void compute_fluid_pressure(const TaitEos& eos, double floor, SphParticles<D>& ps);

// The extrapolated pressure of one owned wall particle that touches resin
// and belongs to a listed (moving or sliding) wall. The solver averages
// them per wall over all ranks, adding them in global-id order so that the
// mean does not depend on the rank count.
struct WallFaceSample {
  std::int64_t gid = 0;
  std::int32_t wall = 0;
  double p = 0;
};

// What the wall extrapolation needs to know of moving or sliding wall k.
template <int D>
struct WallKinematics {
  Vec<D> accel = Vec<D>::Zero();  // the wall's acceleration [m/s^2]
  double pressure_floor = 0.0;    // lowest extrapolated pressure [Pa]
  WallSlipLaw slip;               // what the resin sees at this wall
  WallThermalLaw thermal;         // its thermal condition (resin.thermal)
};

// The velocity the resin sees at a dummy wall particle of velocity vw, given
// the resin's Shepard mean v_mean there and s, the vector from the particle
// to the wall surface (src/sph/wall_boundary.cpp). Affine in v_mean and vw:
// vw = 0 gives its linear part (the implicit viscous solve,
// src/sph/implicit_viscosity.cpp).
template <int D>
Vec<D> dummy_velocity(const WallSlipLaw& law, const Vec<D>& vw, const Vec<D>& v_mean,
                      const Vec<D>& s);

// Dummy-particle walls (Adami, Hu & Adams 2012): every owned wall particle
// takes pressure, density and a no-slip velocity from its resin neighbors.
// Fixed walls (index -1) have a pressure floor of 0. Returns the face
// pressure samples of the walls listed in `walls`, in local order.
template <int D>
std::vector<WallFaceSample> compute_wall_state(const SphParams& sp, const TaitEos& eos,
                                               const NeighborList<D>& nl,
                                               const std::vector<WallKinematics<D>>& walls,
                                               SphParticles<D>& ps);

// Continuity (paper Eq. 3, + optional delta-SPH) and momentum (paper Eq. 5
// with the sign corrected: pressure, artificial viscosity, anti-clump,
// laminar viscosity, body force) for every owned resin particle.
template <int D>
void compute_fluid_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps);

// The neighbour-sum preparation passes that sp needs (src/sph/sph_terms.hpp,
// SphPasses), in order: each writes one per-particle field of the owned
// resin particles, then calls forward(group) so that the caller (the
// solver; physics never calls MPI) refreshes that field's exchange group on
// the ghosts before the next pass and the pair loop read it. Call it after
// the wall state is current, before compute_fluid_rates. A pass that no
// active term reads and output.fields does not name does not run.
template <int D>
void compute_fluid_passes(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                          const std::function<void(SphGroup)>& forward);

// Drops the particle fields (SphParticles::drop_field) that no option of sp
// reads or writes: temperature, shear rate, viscosity, the free-surface,
// surface-tension and implicit-viscosity fields, the walls' distance to the
// surface (slip_walls: some wall is not no-slip). Call it before filling.
template <int D>
void drop_unused_fields(const SphParams& sp, bool slip_walls, SphParticles<D>& ps);

// Particle shifting after the second kick of a step of dt (src/sph/particle_shifting.cpp):
// reads the free-surface pass's fields; nothing when sp.shifting is 0. With
// sp.shifting_continuity the shifts are forwarded to the ghosts (forward,
// SphGroup::Shift) and each resin density gains the continuity equation's
// sum over the shift, so the density follows the particles' spacing.
template <int D>
void shift_particles(const SphParams& sp, double dt, const NeighborList<D>& nl, SphParticles<D>& ps,
                     const std::function<void(SphGroup)>& forward);

// The wall's short-range repulsion on the resin (src/sph/wall_repulsion.cpp),
// added to the accelerations of the owned candidates (every owned particle
// without them); compute_fluid_rates calls it when sp.wall_repulsion with the
// particles the pair loop found within wall_repulsion_range2 of a neighbour
// (-1 when the repulsion is off). Particles left out must have no wall
// neighbour that close.
template <int D>
void add_wall_repulsion(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps,
                        std::span<const std::uint32_t> candidates);
template <int D>
void add_wall_repulsion(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps);
template <int D>
double wall_repulsion_range2(const SphParams& sp);

// The viscous traction at the free surface (src/sph/surface_traction.cpp):
// at the particles the free-surface pass flags, the (grad v)^T part of the
// stress that the Morris term lacks there, added to the accelerations;
// compute_fluid_rates calls it when sp.free_surface_traction with explicit
// viscosity (implicit: SurfaceTractionOperator in the viscous solve).
template <int D>
void add_free_surface_traction(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps);

// Temperature (docs/physics.md "Temperature"), with sp.thermal only.
// Conduction in the pairwise form of Cleary & Monaghan (1999, JCP 148:227),
//   dT_i/dt = 1/c_p sum_j 4 m_j / (rho_i rho_j) k_i k_j / (k_i + k_j)
//             (T_i - T_j) x_ij . grad_i W_ij / (r_ij^2 + eta^2),
// antisymmetric in i and j, so sum_i m_i c_p dT_i/dt = 0 over resin pairs
// (energy is conserved exactly), plus viscous heating mu gamma_dot^2 /
// (rho_i c_p) when asked (reads the shear-rate field). Wall neighbours are
// the dummy particles of compute_wall_state, whose temperature holds the
// wall's condition. Writes dtemp of the owned resin particles.
template <int D>
void compute_heat_rates(const SphParams& sp, const NeighborList<D>& nl, SphParticles<D>& ps);

// One pair's part of du_i/dt = c_p dT_i/dt [W/kg]: the Cleary-Monaghan
// term above, with F = grad W_ij / x_ij (F < 0) and r2 = |x_ij|^2.
inline double conduction_pair(double m_j, double rho_i, double rho_j, double k_i, double k_j,
                              double F, double r2, double eta2, double T_i, double T_j) {
  return 4.0 * m_j / (rho_i * rho_j) * (k_i * k_j / (k_i + k_j)) * F * r2 / (r2 + eta2) *
         (T_i - T_j);
}

// The temperature a dummy wall particle at depth d = |s| behind the wall
// shows the resin, given the resin's Shepard mean T~ near it: the surface
// temperature T_s obeys k (T~ - T_s) / d = htc (T_s - T_wall) (T~ seen at
// depth d in front of the wall), and the dummy holds the mirror value
// 2 T_s - T~ (as the no-slip velocity 2 v_w - v~ of Adami et al. 2012).
// Held (htc infinite): 2 T_wall - T~; adiabatic: T~.
double dummy_temperature(const WallThermalLaw& law, double conductivity, double t_mean, double d);

// Largest speed (resin and walls) and resin acceleration over owned particles.
struct LocalExtremes {
  double v_max = 0;
  double a_max = 0;
  double mu_max = 0;  // largest resin viscosity (a law), else 0
};
template <int D>
LocalExtremes local_extremes(const SphParticles<D>& ps);

// Adaptive time step (docs/physics.md): the smallest of the CFL, force and
// viscous limits, and which one binds.
// Dem: the stable DEM step of a fibers-only run (run.hpp).
// New limits go at the end (checkpoints store the number; the restart
// accepts up to the last one, src/solver/run.cpp).
// Thermal: dt <= thermal_factor h^2 rho0 c_p / k (resin.thermal).
enum class DtLimit { Cfl, Force, Viscous, Fixed, Dem, Drag, Thermal, Capillary };
const char* to_string(DtLimit l);
struct TimeStep {
  double dt = 0;
  DtLimit limit = DtLimit::Cfl;
};
// mu_max: the largest particle viscosity of a law (negative: sp.mu).
// With sp.implicit_viscosity there is no viscous limit.
TimeStep choose_time_step(const Numerics& num, const SphParams& sp, double v_max, double a_max,
                          double mu_max = -1.0);
// The explicit viscous limit viscous_factor h^2 rho0 / mu (infinite when
// mu is 0), whether or not the case integrates the viscosity implicitly.
double explicit_viscous_time_step(const Numerics& num, const SphParams& sp, double mu_max = -1.0);
// The thermal limit thermal_factor h^2 rho0 c_p / k (sp.thermal only).
double thermal_time_step(const SphParams& sp);

}  // namespace sphdem
