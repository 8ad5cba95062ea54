#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sphdem/particles/particle_lanes.hpp"
#include "sphdem/sph/extreme_lanes.hpp"
#include "sphdem/sph/sph.hpp"

namespace sphdem {

SphParams make_sph_params(const Case& c) {
  SphParams sp;
  sp.h = c.h();
  sp.spacing = c.numerics.spacing;
  sp.rho0 = c.resin.density;
  sp.c0 = c.resin.sound_speed;
  sp.gamma = c.resin.gamma;
  sp.mu = c.numerics.viscosity_model == ViscosityModel::None ? 0.0 : c.resin.viscosity;
  sp.variable_viscosity = sp.mu > 0 && c.resin.melt.law != ViscosityLaw::Newtonian;
  sp.implicit_viscosity =
      sp.mu > 0 && c.numerics.viscous_integration == ViscousIntegration::Implicit;
  sp.melt = c.resin.melt;
  sp.melt_temperature = c.resin.melt_temperature.value_or(0.0);
  if (c.numerics.lattice_correction) {
    sp.mu_scale = viscous_lattice_correction(c.dimension, c.numerics.h_over_spacing);
    sp.grad_scale = gradient_lattice_correction(c.dimension, c.numerics.h_over_spacing);
  }
  sp.alpha = c.numerics.artificial_viscosity;
  sp.delta = c.numerics.delta_sph;
  sp.anti_clump = c.numerics.anti_clump;
  sp.anti_clump_eps = c.numerics.anti_clump_epsilon;
  sp.anti_clump_n = c.numerics.anti_clump_exponent;
  sp.anti_clump_at_surface = c.numerics.anti_clump_at_surface;
  sp.front_events = c.output.front_events;
  sp.eta2 = 0.01 * sp.h * sp.h;
  sp.shifting = c.numerics.particle_shifting ? c.numerics.shifting_coefficient : 0.0;
  sp.shifting_continuity = sp.shifting > 0.0 && c.numerics.shifting_continuity;
  sp.wall_repulsion = c.numerics.wall_repulsion;
  sp.free_surface_traction = c.numerics.free_surface_traction;
  sp.body_force = c.body_force;
  sp.mold_wall = resolve_wall_slip(c.mold, c.mold);
  sp.surface_tension = c.resin.surface_tension;
  sp.ambient_pressure = c.resin.ambient_pressure;
  if (c.resin.tensile_strength)
    sp.pressure_floor = 0.0 - (c.resin.ambient_pressure + *c.resin.tensile_strength);
  // A wall's own contact_angle, else the mold's, else 90 degrees.
  const auto angle = [&](const WallConditionKeys& w) {
    return w.contact_angle.value_or(c.mold.contact_angle.value_or(90.0));
  };
  sp.contact_angle = {angle(c.mold)};
  for (const MovingWall& w : c.moving_walls) sp.contact_angle.push_back(angle(w));
  for (const SlidingWall& w : c.sliding_walls) sp.contact_angle.push_back(angle(w));
  sp.output_fields = c.output.fields;
  if (const auto& th = c.resin.thermal) {
    sp.thermal = true;
    sp.heat_capacity = th->heat_capacity;
    sp.conductivity = th->conductivity;
    // The freezing threshold: the thermal key, else the viscosity law's
    // own no-flow temperature (Cross-WLF material data carry one).
    if (th->no_flow_temperature) {
      sp.no_flow_temperature = *th->no_flow_temperature;
    } else if (c.resin.melt.no_flow_temperature) {
      sp.no_flow_temperature = *c.resin.melt.no_flow_temperature;
    }
    sp.viscous_heating = th->viscous_heating && sp.mu > 0;
    sp.thermal_factor = th->time_step_factor;
    sp.mold_thermal = resolve_wall_thermal(c.mold, c.mold);
    // Viscous heating reads the shear rate: its pass runs when its field is
    // requested (src/sph/pass_loop.hpp).
    if (sp.viscous_heating) sp.output_fields.emplace_back("shear_rate");
  }
  // The implicit solve reads a law's viscosity, which reads the shear rate;
  // with the pair term off, nothing else asks for its pass.
  if (sp.implicit_viscosity && sp.variable_viscosity) sp.output_fields.emplace_back("shear_rate");
  return sp;
}

namespace {
// -sum_j F(r_j) w(r_j) x_j^2 over a unit lattice, with w = r^2/(r^2+eta^2)
// (the Morris factor) or w = 1 (the plain gradient).
template <int D>
double lattice_moment(double h, bool morris) {
  const WendlandC2<D> kernel(h);
  const double eta2 = morris ? 0.01 * h * h : 0.0;
  const int n = static_cast<int>(std::ceil(2.0 * h)) + 1;
  double m = 0.0;
  const int nz = D == 3 ? n : 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -nz; k <= nz; ++k) {
        const double r2 = double(i * i + j * j + k * k);
        if (r2 == 0.0) continue;
        m -= kernel.f(std::sqrt(r2)) * r2 * r2 / (r2 + eta2);
      }
  return m / D;  // the moment of one component, x_j^2, by the lattice's symmetry
}
}  // namespace

double viscous_lattice_correction(int dimension, double h_over_spacing) {
  return 1.0 / (dimension == 2 ? lattice_moment<2>(h_over_spacing, true)
                               : lattice_moment<3>(h_over_spacing, true));
}

double gradient_lattice_correction(int dimension, double h_over_spacing) {
  return 1.0 / (dimension == 2 ? lattice_moment<2>(h_over_spacing, false)
                               : lattice_moment<3>(h_over_spacing, false));
}

// A law: its largest particle viscosity now (before the first rates, the
// law's ceiling sp.mu).
double explicit_viscous_time_step(const Numerics& num, const SphParams& sp, double mu_max) {
  const double mu = sp.variable_viscosity && mu_max > 0 ? mu_max : sp.mu;
  return mu > 0 ? num.viscous_factor * sp.h * sp.h * sp.rho0 / mu
                : std::numeric_limits<double>::infinity();
}

double thermal_time_step(const SphParams& sp) {
  return sp.thermal_factor * sp.h * sp.h * sp.rho0 * sp.heat_capacity / sp.conductivity;
}

namespace {

// |u|^2 as x x + y y with each product rounded, then fma(z, z, .) in 3D: the
// operations of local_extremes' vector form, and those GCC gave this loop's
// Eigen squaredNorm at -O3 with AVX-512 before there was a vector form. Its
// own flag, so no build fuses a product into the sum (-ffp-contract=fast).
template <int D>
__attribute__((optimize("fp-contract=off"))) LocalExtremes local_extremes_one_at_a_time(
    const SphParticles<D>& ps) {
  double v2 = 0.0, a2 = 0.0, mu = 0.0;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    // No helper function or lambda: it would be compiled with the default flag.
    const double* const v = ps.v[i].data();
    double vi = v[0] * v[0] + v[1] * v[1];
    if constexpr (D == 3) vi = lanes::mul_add(v[2], v[2], vi);
    v2 = vi > v2 ? vi : v2;  // std::max(v2, vi): a NaN keeps v2
    if (ps.kind[i] != Kind::Fluid || (!ps.frozen.empty() && ps.frozen[i] != 0)) continue;
    const double* const a = ps.a[i].data();
    double ai = a[0] * a[0] + a[1] * a[1];
    if constexpr (D == 3) ai = lanes::mul_add(a[2], a[2], ai);
    a2 = ai > a2 ? ai : a2;
    if (!ps.viscosity.empty()) mu = ps.viscosity[i] > mu ? ps.viscosity[i] : mu;
  }
  return {v2, a2, mu};
}

}  // namespace

// A frozen particle (below the no-flow temperature) holds its position: its
// acceleration does not move it, so it does not limit the step either.
// With AVX-512, eight particles at a time with the one-particle form's
// operations, with AVX2 four in 2D: the maxima have its bits.
template <int D>
LocalExtremes local_extremes(const SphParticles<D>& ps) {
#if defined(SPHDEM_PARTICLE_LANES)
  ExtremeLanes<D> ex;
  for (std::size_t i = 0; i < ps.n_owned; i += 8) ex.add(ps, i, lanes::first(ps.n_owned - i));
  return ex.result();
#elif defined(SPHDEM_PARTICLE_LANES4)
  ExtremesOneByOne<D> ex;
  std::size_t i = 0;
  for (; i + 4 <= ps.n_owned; i += 4) ex.add4(ps, i);
  ex.add(ps, i, ps.n_owned);
  return ex.result();
#else
  const LocalExtremes squares = local_extremes_one_at_a_time<D>(ps);
  return {std::sqrt(squares.v_max), std::sqrt(squares.a_max), squares.mu_max};
#endif
}

bool any_slip_wall(const Case& c) {
  bool slip = resolve_wall_slip(c.mold, c.mold).type != WallSlip::NoSlip;
  for (const MovingWall& m : c.moving_walls)
    slip = slip || resolve_wall_slip(m, c.mold).type != WallSlip::NoSlip;
  for (const SlidingWall& s : c.sliding_walls)
    slip = slip || resolve_wall_slip(s, c.mold).type != WallSlip::NoSlip;
  return slip;
}

const char* to_string(DtLimit l) {
  switch (l) {
    case DtLimit::Cfl:
      return "cfl";
    case DtLimit::Force:
      return "force";
    case DtLimit::Viscous:
      return "viscous";
    case DtLimit::Fixed:
      return "fixed";
    case DtLimit::Dem:
      return "dem";
    case DtLimit::Drag:
      return "drag";
    case DtLimit::Thermal:
      return "thermal";
    case DtLimit::Capillary:
      return "capillary";
  }
  return "?";
}

TimeStep choose_time_step(const Numerics& num, const SphParams& sp, double v_max, double a_max,
                          double mu_max) {
  if (num.fixed_dt) return {*num.fixed_dt, DtLimit::Fixed};
  TimeStep ts{num.cfl * sp.h / (sp.c0 + v_max), DtLimit::Cfl};
  if (a_max > 0) {
    const double dt_f = num.force_factor * std::sqrt(sp.h / a_max);
    if (dt_f < ts.dt) ts = {dt_f, DtLimit::Force};
  }
  if (!sp.implicit_viscosity) {
    const double dt_v = explicit_viscous_time_step(num, sp, mu_max);
    if (dt_v < ts.dt) ts = {dt_v, DtLimit::Viscous};
  }
  if (sp.thermal) {
    const double dt_t = thermal_time_step(sp);
    if (dt_t < ts.dt) ts = {dt_t, DtLimit::Thermal};
  }
  // Capillary waves (Brackbill, Kothe & Zemach 1992, Eq. 61; Morris 2000):
  // dt <= 0.25 sqrt(rho0 h^3 / (2 pi sigma)).
  if (sp.surface_tension > 0) {
    const double dt_s = 0.25 * std::sqrt(sp.rho0 * sp.h * sp.h * sp.h /
                                         (2.0 * std::numbers::pi * sp.surface_tension));
    if (dt_s < ts.dt) ts = {dt_s, DtLimit::Capillary};
  }
  return ts;
}

template LocalExtremes local_extremes<2>(const SphParticles<2>&);
template LocalExtremes local_extremes<3>(const SphParticles<3>&);

}  // namespace sphdem
