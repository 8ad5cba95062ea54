#pragma once
// The validated contents of a case file (docs/case-file.md), SI units.
// Produced by config/ (load_case), consumed by geometry/ and solver/.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace sphdem {

using Vec3a = std::array<double, 3>;  // D components used, the rest are 0

// A 2D polygon or a box (2D or 3D). `key` and `line` say where it was
// defined so that later checks (e.g. "fill region outside the mold") can
// still point at the case file.
struct Shape {
  enum class Type { Polygon, Box };
  Type type = Type::Box;
  std::vector<std::array<double, 2>> vertices;  // Polygon, counter- or clockwise
  Vec3a lo{}, hi{};                             // Box
  std::string key;
  int line = 0;
};

// The resin's viscosity law (docs/physics.md "Melt viscosity"): a
// generalized-Newtonian eta(shear rate, T, p). Newtonian keeps the plain
// `resin.viscosity` number; the others are a mapping under it.
enum class ViscosityLaw { Newtonian, PowerLaw, Carreau, Cross, CrossWlf };

struct MeltViscosity {
  ViscosityLaw law = ViscosityLaw::Newtonian;
  double consistency = 0;      // K [Pa s^n], power_law
  double n = 1;                // flow index [-], power_law, carreau, cross, cross_wlf
  double eta0 = 0;             // zero-shear viscosity [Pa s], carreau, cross
  double eta_inf = 0;          // infinite-shear viscosity [Pa s], carreau
  double relaxation_time = 0;  // lambda [s], carreau
  double tau_star = 0;         // [Pa], cross, cross_wlf
  double d1 = 0;               // [Pa s], cross_wlf
  double d2 = 0;               // [K]
  double d3 = 0;               // [K/Pa]
  double a1 = 0;               // [-]
  double a2_tilde = 0;         // [K]
  double min = 0;              // lower viscosity limit [Pa s]
  std::optional<double> max;   // upper viscosity limit [Pa s]
  std::optional<double> no_flow_temperature;  // [K], cross_wlf
  std::string material;                       // the material file it came from, if any
};

// The resin's temperature model (docs/physics.md "Temperature"): off
// unless `resin.thermal` is given.
struct Thermal {
  double temperature = 0;                     // melt temperature at t = 0 [K]
  double heat_capacity = 0;                   // c_p [J/(kg K)]
  double conductivity = 0;                    // k [W/(m K)]
  std::optional<double> no_flow_temperature;  // [K], below it the melt stops flowing
  bool viscous_heating = false;               // phi = eta gamma_dot^2
  double time_step_factor = 0.1;              // dt <= factor h^2 rho0 c_p / k
};

struct Resin {
  double density = 0;                      // rho0 [kg/m^3]
  double viscosity = 0;                    // mu [Pa s]; non-Newtonian: the largest the law reaches
  MeltViscosity melt;                      // the law; Newtonian: viscosity above
  std::optional<double> melt_temperature;  // [K], cross_wlf (until the thermal field)
  double sound_speed = 0;                  // c0 [m/s], given or from mach * reference_velocity
  double gamma = 7.0;                      // Tait exponent
  double ambient_pressure = 0;             // [Pa] the air at the free surface (docs/physics.md)
  // [Pa] the resin cavitates (opens) where its absolute pressure would fall
  // below minus this; none: its pressure is not bounded below (docs/physics.md).
  std::optional<double> tensile_strength;
  double surface_tension = 0;      // sigma [N/m], 0 = none (docs/physics.md "Surface tension")
  std::optional<Thermal> thermal;  // none: isothermal (docs/physics.md "Temperature")
};

enum class ViscosityModel { Morris, None };
// How the laminar viscous term is stepped (docs/physics.md "Implicit
// viscosity"): explicitly in the pair loop (dt <= viscous_factor h^2 rho0/mu),
// or by a backward-Euler solve after the second kick (no viscous limit).
enum class ViscousIntegration { Explicit, Implicit };

struct Numerics {
  double spacing = 0;  // dp [m]
  double h_over_spacing = 1.2;
  double cfl = 0.25;              // dt <= cfl h / (c0 + |v|max)
  double force_factor = 0.25;     // dt <= force_factor sqrt(h/|a|max)
  double viscous_factor = 0.125;  // dt <= viscous_factor h^2 rho0/mu
  std::optional<double> fixed_dt;
  double end_time = 0;
  ViscosityModel viscosity_model = ViscosityModel::Morris;
  ViscousIntegration viscous_integration = ViscousIntegration::Explicit;
  double implicit_tolerance = 1e-8;  // CG: |r| <= tol |b| (M-weighted norms)
  int implicit_max_iterations = 500;
  // Scale the kernel gradient and the viscous Laplacian so they are exact on
  // the lattice the resin starts on (see gradient_lattice_correction, sph.hpp).
  bool lattice_correction = true;
  double artificial_viscosity = 0.0;  // Monaghan alpha
  double delta_sph = 0.0;             // Molteni-Colagrossi delta, 0 = off
  bool anti_clump = true;             // Monaghan (2000) tensile-instability term
  double anti_clump_epsilon = 0.2;
  int anti_clump_exponent = 4;
  // The tension branch at free-surface particles too (Monaghan 2000 as
  // published); off: R_a = 0 where the free-surface pass flags a particle.
  bool anti_clump_at_surface = false;
  // Particle shifting (Lind et al. 2012; Skillen et al. 2013), free-surface aware.
  bool particle_shifting = false;
  double shifting_coefficient = 2.0;
  // The shift enters the continuity density (src/sph/particle_shifting.cpp).
  bool shifting_continuity = false;
  // Monaghan (1994) repulsive force of the wall particles on the resin.
  bool wall_repulsion = true;
  // The viscous traction at the free surface: the (grad v)^T part the
  // Morris term lacks there (src/sph/surface_traction.cpp).
  bool free_surface_traction = false;
  double neighbor_skin = 0.15;  // Verlet skin as a fraction of the support 2h
};

// What the resin sees at a wall (docs/physics.md "Wall conditions"): the
// velocity of the dummy wall particles in the viscous term.
enum class WallSlip { NoSlip, FreeSlip, NavierSlip };

// A wall condition as given in the case file: unset fields fall back to the
// mold's (for a moving or sliding wall) or to no-slip (for the mold).
struct WallConditionKeys {
  std::optional<WallSlip> wall_condition;
  std::optional<double> slip_length;    // [m], navier_slip only
  std::optional<double> contact_angle;  // [deg], with resin.surface_tension
  // Thermal condition (resin.thermal only): held at `temperature` [K], or
  // through a heat-transfer coefficient [W/(m^2 K)] to it; none: adiabatic.
  std::optional<double> temperature;
  std::optional<double> heat_transfer_coefficient;
};

// A resolved wall condition.
struct WallSlipLaw {
  WallSlip type = WallSlip::NoSlip;
  double slip_length = 0;  // [m], navier_slip
};

// A resolved thermal wall condition: the dummy particles show the resin the
// temperature that makes the surface obey -k dT/dn = htc (T_s - T_wall)
// (htc = infinity: T_s = T_wall; no temperature: adiabatic).
struct WallThermalLaw {
  bool adiabatic = true;
  double temperature = 0;  // [K]
  double htc = 0;          // [W/(m^2 K)], infinity: held at temperature
};

inline WallThermalLaw resolve_wall_thermal(const WallConditionKeys& own,
                                           const WallConditionKeys& mold) {
  const WallConditionKeys& from = own.temperature ? own : mold;
  if (!from.temperature) return {};
  return {false, *from.temperature,
          from.heat_transfer_coefficient.value_or(std::numeric_limits<double>::infinity())};
}

// The condition of a wall that gives `own` keys, falling back to the mold's.
inline WallSlipLaw resolve_wall_slip(const WallConditionKeys& own, const WallConditionKeys& mold) {
  const WallConditionKeys& from = own.wall_condition ? own : mold;
  return {from.wall_condition.value_or(WallSlip::NoSlip), from.slip_length.value_or(0.0)};
}

struct Mold : WallConditionKeys {
  std::vector<Shape> shapes;  // the cavity is their union
  int wall_layers = 3;
  std::vector<Shape> vents;  // where air leaves (output.front_events); empty: every wall
};

// Piecewise-linear velocity table; constant before the first and after the
// last row.
struct VelocityTable {
  std::vector<double> time;
  std::vector<Vec3a> velocity;
};

struct MovingWall : WallConditionKeys {
  std::string name;
  Shape region;  // wall particles inside it belong to this wall
  VelocityTable velocity;
  std::optional<double> pressure_limit;  // [Pa], V/P switchover
  double pressure_relax_time = 1e-3;     // [s], how fast the controller reacts
  double adhesion_pressure = 0;          // [Pa] tension the resin takes before leaving the wall
  int line = 0;
};

struct SlidingWall : WallConditionKeys {
  std::string name;
  Shape region;
  Vec3a velocity{};  // tangential surface velocity [m/s]; the particles stay put
  int line = 0;
};

// An expression of x, y, z [m] (muParser syntax, docs/case-file.md
// "initial_fields"), with where it was given for errors found later (a
// value that is not finite at some particle).
struct Expression {
  std::string text;
  std::string key;
  int line = 0;
};

// Initial fields of the resin of some fill regions, as expressions.
struct InitialFields {
  std::optional<int> fill;                // index into Case::fill; none: every fill region
  std::vector<Expression> velocity;       // D components, or empty: initial_velocity
  std::optional<Expression> density;      // [kg/m^3]
  std::optional<Expression> pressure;     // [Pa], density from the equation of state
  std::optional<Expression> temperature;  // [K], with resin.thermal only
  int line = 0;
};

struct Output {
  std::string directory;             // default: out/<name>
  std::optional<double> every_time;  // [s] of simulated time
  std::optional<int> every_steps;
  std::vector<std::string> fields{"velocity", "density", "pressure"};
  int progress_every = 100;
  // Weld lines and trapped air (docs/physics.md "Weld lines and trapped air").
  bool front_events = false;
};

// What the imbalance check and a re-partition balance (docs/parallel.md,
// "Balancing measured time"): the work model's counts, or the compute time
// each rank measured (parts sized by each rank's seconds per unit of work).
enum class BalanceWeight { Model, Time };

// Dynamic load balancing (docs/parallel.md).
struct ParallelSettings {
  int balance_every = 100;            // steps between imbalance checks, 0: never re-partition
  double imbalance_threshold = 0.10;  // re-partition past max/mean - 1 of the per-rank work
  BalanceWeight balance_weight = BalanceWeight::Model;
  int min_top_cells = 1 << 20;  // top-level cells: at most max(per rank x ranks, this)
  int top_cells_per_rank = 64;
};

// Checkpoints for restart (docs/checkpoint.md). Off unless a cadence is
// given (here, or `--checkpoint-every` on the command line).
struct CheckpointSettings {
  std::optional<int> every_steps;       // steps between checkpoints
  std::optional<double> every_minutes;  // wall-clock minutes between checkpoints
  int keep = 2;                         // newest checkpoints kept, older ones deleted
};

// Fibers as chains of bonded DEM particles (docs/dem.md),
// placed at random in a box at the start. Lines are kept so that a
// placement that fails later can still point at the case file.
struct FiberSettings {
  int count = 0;             // fibers; 0 when area_fraction is given
  double area_fraction = 0;  // target area (2D) / volume (3D) fraction of the region
  int particles_per_fiber = 4;
  double diameter = 0;                       // particle diameter [m]
  double density = 0;                        // [kg/m^3]
  double youngs_modulus = 0;                 // E [Pa]
  std::optional<double> tensile_strength;    // sigma_c [Pa], none: never breaks in tension
  std::optional<double> shear_strength;      // tau_c [Pa], none: never breaks in shear
  double stiffness_ratio = 0.25;             // kbar* = kbar_n / kbar_s
  double contact_stiffness_fraction = 0.01;  // k_n = fraction * kbar_n * A
  double restitution = 0.9;
  double friction = 0.3;
  Shape region;                 // a box: particles lie fully inside
  std::optional<double> angle;  // orientation [rad] from +x; none: random
  std::uint64_t seed = 1;
  double initial_bend =
      0;  // seeded sagitta / fiber length (docs/dem.md "Seeded bend"); 0: straight
  double dt_safety = 0.2;
  bool subcycle_bonds = false;    // bond_integration: subcycled or implicit (docs/dem.md)
  bool implicit_bonds = false;    // bond_integration: implicit
  bool exponential_drag = false;  // drag_integration: exponential (docs/physics.md)
  // Coupling with the resin (docs/physics.md "Coupling").
  double void_fraction_min = 0.4;           // clip of the local void fraction
  bool void_fraction_in_continuity = true;  // the "local averaging" continuity form
  bool hydrodynamic_torque = true;          // the resin's torque on the fibers (Jeffery orbits)
  int line = 0;                             // of the `fibers:` mapping
  int amount_line = 0;                      // of `count` or `area_fraction`
};

struct Case {
  std::string name;
  std::string source_file;
  std::string source_text;             // the case file as read
  std::vector<std::string> overrides;  // the `--set` key=value strings applied to it
  int dimension = 2;
  Resin resin;
  Numerics numerics;
  Mold mold;
  std::vector<Shape> fill;              // empty: no resin (a DEM-only case)
  std::optional<FiberSettings> fibers;  // none: resin only
  std::vector<MovingWall> moving_walls;
  std::vector<SlidingWall> sliding_walls;
  Vec3a body_force{};        // [m/s^2]
  Vec3a initial_velocity{};  // [m/s] of the resin at t = 0
  // Expressions per fill region, applied after initial_velocity and the
  // hydrostatic start, in list order (a later item wins).
  std::vector<InitialFields> initial_fields;
  std::array<bool, 3> periodic{false, false, false};
  std::optional<Vec3a> domain_lo, domain_hi;  // default: mold bbox + wall layers
  Output output;
  ParallelSettings parallel;
  CheckpointSettings checkpoint;
  // Remarks that do not stop a run (e.g. a Mach number above 0.1), for
  // `sphdem check` and the run log.
  std::vector<std::string> warnings;

  double h() const { return numerics.h_over_spacing * numerics.spacing; }
};

}  // namespace sphdem
