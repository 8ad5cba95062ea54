// The `resin:` and `numerics:` keys (docs/case-file.md). The resin's
// density and viscosity are read once, here, into Case::resin; the SPH terms
// (make_sph_params) and the drag law (the coupling's CouplingParams) both
// take them from there.
#include <optional>

#include "schema.hpp"

namespace sphdem::config {

namespace {

// c0 is given directly, or as reference_velocity / mach; exactly one way.
void finish_sound_speed(const Map& m, Resin& r, Context&) {
  const std::optional<Value> c0 = m.get("sound_speed");
  const std::optional<Value> mach = m.get("mach");
  const std::optional<Value> vref = m.get("reference_velocity");
  if (c0 && (mach || vref)) {
    const Value& extra = mach ? *mach : *vref;
    extra.fail("give either sound_speed or mach with reference_velocity, not both");
  }
  if (c0) return;
  if (!mach && !vref) {
    m.require("sound_speed", " (give sound_speed, or both mach and reference_velocity)");
  }
  const double ma = positive(m.require("mach", " (needed with reference_velocity)"));
  r.sound_speed = positive(m.require("reference_velocity", " (needed with mach)")) / ma;
}

// A key whose value only feeds another (validated here, combined in finish).
Key<Resin> input_only(std::string name, std::string unit, std::string doc) {
  Key<Resin> k{std::move(name), "number", std::move(unit), "none", "> 0", std::move(doc)};
  k.read = [](const Value& v, Resin&, Context&) { positive(v); };
  return k;
}

// A setting (and identity line) only when it differs from its default, so
// that a case that leaves the key alone keeps the identity lines of older
// checkpoints (keys added with issue 18's free surface).
template <class T>
Key<T> unless_default(Key<T> k) {
  const auto show = k.show;
  k.section_settings = [show](const T& t, const std::string& key, std::vector<Setting>& out) {
    std::string value = show(t);
    if (value != show(T{})) out.push_back({key, std::move(value), true, false});
  };
  return k;
}

// A temperature key [K]: positive; the Celsius warning (schema.hpp).
double kelvin(const Value& v, Context& ctx) {
  const double t = positive(v);
  warn_if_celsius(v, t, ctx);
  return t;
}

// The melt must start above its no-flow temperature.
void finish_thermal(const Map& m, Thermal& t, Context&) {
  if (t.no_flow_temperature && !(t.temperature > *t.no_flow_temperature)) {
    m.require("temperature")
        .fail(fmt::format("the melt temperature {} K is not above no_flow_temperature {} K: the "
                          "resin would start frozen",
                          show_number(t.temperature), show_number(*t.no_flow_temperature)));
  }
}

Section<Thermal> make_thermal() {
  using T = Thermal;
  Section<T> s;
  Key<T> temperature = number("temperature", "K", positive_number(), &T::temperature,
                              "melt temperature at t = 0 (initial_fields may override it)");
  temperature.read = [](const Value& v, T& t, Context& ctx) { t.temperature = kelvin(v, ctx); };
  Key<T> no_flow =
      optional_number("no_flow_temperature", "K", positive_number(), &T::no_flow_temperature,
                      "below it a resin particle stops flowing (holds its position "
                      "and acts as wall for its neighbours)");
  no_flow.read = [](const Value& v, T& t, Context& ctx) { t.no_flow_temperature = kelvin(v, ctx); };
  no_flow.defaults_to("none (never freezes)");
  s.keys = {
      std::move(temperature).required().identity(),
      number("heat_capacity", "J/(kg K)", positive_number(), &T::heat_capacity,
             "specific heat capacity c_p")
          .required()
          .identity(),
      number("conductivity", "W/(m K)", positive_number(), &T::conductivity,
             "thermal conductivity k")
          .required()
          .identity(),
      std::move(no_flow).identity(),
      boolean("viscous_heating", &T::viscous_heating,
              "add the viscous dissipation eta gamma_dot^2 / (rho c_p) to dT/dt")
          .identity(),
      number("time_step_factor", "", in_range(0, 1, true, false), &T::time_step_factor,
             "dt <= time_step_factor h^2 rho0 c_p / k")
          .identity(),
  };
  s.finish = finish_thermal;
  s.intro =
      "Temperature per resin particle, conducted between particles (Cleary & Monaghan\n"
      "1999) and set at the walls by their `temperature` and `heat_transfer_coefficient`\n"
      "(docs/physics.md, \"Temperature\"). Temperatures are in kelvin; every\n"
      "temperature key (the law's `d2` too) below 250 K gives a warning naming the\n"
      "file, line and key (it looks like degrees Celsius; -23 degC is colder than any\n"
      "melt, mold or no-flow temperature).\n";
  return s;
}

const Section<Thermal>& thermal_keys() {
  static const Section<Thermal> s = make_thermal();
  return s;
}

Section<Resin> make_resin() {
  Section<Resin> s;
  s.keys = {
      number("density", "kg/m^3", positive_number(), &Resin::density,
             "rest density rho0 (also the drag law's resin density)")
          .required()
          .identity(),
      resin_viscosity_key(),
      resin_material_key(),
      resin_melt_temperature_key(),
      number("sound_speed", "m/s", positive_number(), &Resin::sound_speed,
             "c0 of the Tait equation of state")
          .defaults_to("reference_velocity / mach")
          .identity(),
      input_only("mach", "", "Mach number, with reference_velocity instead of sound_speed"),
      input_only("reference_velocity", "m/s", "the flow's speed scale, with mach"),
      number("gamma", "", positive_number(), &Resin::gamma, "Tait exponent").identity(),
      unless_default(number("ambient_pressure", "Pa", non_negative_number(),
                            &Resin::ambient_pressure,
                            "the air's pressure at the free surface (101325 for the atmosphere): "
                            "pressures stay gauge, and a wall holds the resin down to absolute "
                            "zero (gauge -Pa), so a decelerating piston keeps its resin; see "
                            "`docs/physics.md` \"Ambient pressure\"")
                         .identity()),
      unless_default(optional_number("tensile_strength", "Pa", non_negative_number(),
                                     &Resin::tensile_strength,
                                     "the most tension the resin holds: where its absolute "
                                     "pressure would fall below minus this it cavitates (gauge "
                                     "pressure floor -(Pa + this)), which keeps impacts and "
                                     "splashes stable; 0: no tension at all; see "
                                     "`docs/physics.md` \"Cavitation\"")
                         .defaults_to("none (unbounded)")
                         .identity()),
      unless_default(number("surface_tension", "N/m", non_negative_number(),
                            &Resin::surface_tension,
                            "surface tension sigma of the resin's free surface, a continuum "
                            "surface force (docs/physics.md \"Surface tension\"); 0 = none; "
                            "needs a free surface")
                         .identity()),
      optional_mapping("thermal", thermal_keys, &Resin::thermal,
                       "temperature, conduction, viscous heating, no-flow temperature; none: "
                       "isothermal"),
  };
  s.finish = [](const Map& m, Resin& r, Context& ctx) {
    finish_sound_speed(m, r, ctx);
    finish_melt(m, r, ctx);
  };
  s.notes =
      "The sound speed is given in exactly one of two ways: `sound_speed`, or both\n"
      "`mach` and `reference_velocity`, in which case c0 = reference_velocity /\n"
      "mach. Giving both ways, or neither, is an error. Weakly compressible SPH\n"
      "needs a Mach number of 0.1 or less (density errors grow like Ma^2); a\n"
      "faster wall than 0.1 c0 gives a warning, not an error.\n"
      "\n"
      "`viscosity` is a number (Newtonian, Pa s) or a mapping that names a law\n"
      "(keys below): e.g. `viscosity: {model: power_law, consistency: 2.5e-4, n: 0.5,\n"
      "max: 1.0e-2}`. Instead of `viscosity`, `material:` loads the law from a\n"
      "material file (`inputs/materials/`; a relative path is looked up beside the\n"
      "case file, then in the working directory), a YAML file with `name`, `source`\n"
      "and a `viscosity:` mapping. `cross_wlf` needs `melt_temperature` (K), above\n"
      "the law's `no_flow_temperature`. A temperature or a `d2` below 200 K gives a\n"
      "warning (degrees Celsius where kelvin is expected). When the expected\n"
      "viscous pressure drop exceeds 0.01 rho0 c0^2, `check` warns and names the\n"
      "sound speed that would carry it (docs/physics.md \"Injection pressure\").\n";
  return s;
}

// A fixed time step must respect the CFL and viscous limits that the
// adaptive step would (with |v|max = 0, the most lenient case).
void check_fixed_dt(const Map& m, Numerics& n, Context& ctx) {
  const std::optional<Value> v = m.get("fixed_dt");
  if (!v) return;
  const Resin& r = ctx.c.resin;
  const double h = n.h_over_spacing * n.spacing;
  const double cfl_limit = n.cfl * h / r.sound_speed;
  if (*n.fixed_dt > cfl_limit) {
    v->fail(fmt::format("{} s exceeds the stable limit cfl*h/c0 = {:.4g} s", v->text(), cfl_limit));
  }
  const double visc_limit = n.viscous_factor * h * h * r.density / r.viscosity;
  const bool explicit_viscosity = n.viscous_integration == ViscousIntegration::Explicit;
  if (explicit_viscosity && r.viscosity > 0 && *n.fixed_dt > visc_limit) {
    v->fail(
        fmt::format("{} s exceeds the stable limit viscous_factor*h^2*density/viscosity = {:.4g} s",
                    v->text(), visc_limit));
  }
  if (!(n.end_time > *n.fixed_dt)) {
    const Value end_time = m.require("end_time");
    end_time.fail(fmt::format("must be greater than numerics.fixed_dt ({} s)", v->text()));
  }
}

void check_numerics(const Map& m, Numerics& n, Context& ctx) {
  check_fixed_dt(m, n, ctx);
}

Key<Numerics> viscosity_model() {
  Key<Numerics> k{"viscosity_model",
                  "enum",
                  "",
                  "",
                  "morris or none",
                  "morris: the Morris et al. (1997) laminar term; none: no physical viscosity"};
  k.read = [](const Value& v, Numerics& n, Context&) {
    n.viscosity_model =
        one_of(v, {"morris", "none"}) == "morris" ? ViscosityModel::Morris : ViscosityModel::None;
  };
  k.show = [](const Numerics& n) {
    return n.viscosity_model == ViscosityModel::Morris ? "morris" : "none";
  };
  return k;
}

Key<Numerics> viscous_integration() {
  Key<Numerics> k{"viscous_integration",
                  "enum",
                  "",
                  "",
                  "explicit or implicit",
                  "explicit: the viscous term in the pair loop (dt <= viscous_factor h^2 rho0 / "
                  "mu); implicit: a backward-Euler solve (BiCGSTAB) after the second kick, no "
                  "viscous limit; see `docs/physics.md` \"Implicit viscosity\""};
  k.read = [](const Value& v, Numerics& n, Context&) {
    n.viscous_integration = one_of(v, {"explicit", "implicit"}) == "implicit"
                                ? ViscousIntegration::Implicit
                                : ViscousIntegration::Explicit;
  };
  k.show = [](const Numerics& n) {
    return n.viscous_integration == ViscousIntegration::Implicit ? "implicit" : "explicit";
  };
  return k;
}

constexpr bool kOpen = true, kClosed = false;

Section<Numerics> make_numerics() {
  using N = Numerics;
  Section<N> s;
  s.keys = {
      number("spacing", "m", positive_number(), &N::spacing, "initial particle spacing dp")
          .required()
          .identity(),
      number("h_over_spacing", "", in_range(1, 3, kClosed, kClosed), &N::h_over_spacing,
             "smoothing length h = h_over_spacing * spacing")
          .identity(),
      number("cfl", "", in_range(0, 1, kOpen, kClosed), &N::cfl, "dt <= cfl h / (c0 + |v|max)")
          .identity(),
      number("force_factor", "", in_range(0, 1, kOpen, kClosed), &N::force_factor,
             "dt <= force_factor sqrt(h / |a|max)")
          .identity(),
      number("viscous_factor", "", in_range(0, 1, kOpen, kClosed), &N::viscous_factor,
             "dt <= viscous_factor h^2 rho0 / mu")
          .identity(),
      optional_number("fixed_dt", "s", positive_number(), &N::fixed_dt,
                      "a fixed time step instead of the adaptive one; see below")
          .defaults_to("none (adaptive)")
          .identity(),
      number("end_time", "s", positive_number(), &N::end_time,
             "simulated time to run; > `fixed_dt`")
          .required(),
      viscosity_model().identity(),
      unless_default(viscous_integration().identity()),
      unless_default(number("implicit_tolerance", "", in_range(0, 1e-2, kOpen, kClosed),
                            &N::implicit_tolerance,
                            "implicit viscosity: the solve stops when the residual is below this "
                            "fraction of the right-hand side (mass-weighted norms)")
                         .identity()),
      unless_default(integer("implicit_max_iterations", "", 1, &N::implicit_max_iterations,
                             "implicit viscosity: BiCGSTAB iterations before the run stops "
                             "with an error")
                         .identity()),
      number("artificial_viscosity", "", non_negative_number(), &N::artificial_viscosity,
             "Monaghan alpha")
          .identity(),
      number("delta_sph", "", non_negative_number(), &N::delta_sph,
             "density diffusion coefficient, 0 = off")
          .identity(),
      boolean("anti_clump", &N::anti_clump, "Monaghan (2000) tensile-instability term").identity(),
      number("anti_clump_epsilon", "", non_negative_number(), &N::anti_clump_epsilon,
             "strength of the anti-clump term")
          .identity(),
      integer("anti_clump_exponent", "", 1, &N::anti_clump_exponent,
              "exponent of the anti-clump term")
          .identity(),
      unless_default(boolean("anti_clump_at_surface", &N::anti_clump_at_surface,
                             "the anti-clump term's tension branch at free-surface particles "
                             "too (Monaghan 2000 as published); off: not there, which keeps "
                             "impacts stable; see `docs/physics.md`")
                         .identity()),
      unless_default(
          boolean("particle_shifting", &N::particle_shifting,
                  "shift resin particles down the gradient of their concentration (Lind et al. "
                  "2012), tangentially at the free surface; see `docs/physics.md`")
              .identity()),
      unless_default(number("shifting_coefficient", "", in_range(0, 6, kOpen, kClosed),
                            &N::shifting_coefficient,
                            "A of the shift -A h |v| dt grad C (Skillen et al. 2013: 1 to 6)")
                         .identity()),
      unless_default(
          boolean("shifting_continuity", &N::shifting_continuity,
                  "the shift enters the continuity density as a velocity would, so the "
                  "density follows the particles' spacing (without it shifting spreads the "
                  "resin); see `docs/physics.md`")
              .identity()),
      unless_default(
          boolean("wall_repulsion", &N::wall_repulsion,
                  "a short-range repulsion of the wall particles on resin closer than 0.9 dp "
                  "(Monaghan 1994): no resin crosses a wall in an impact; see `docs/physics.md`")
              .identity()),
      unless_default(
          boolean("free_surface_traction", &N::free_surface_traction,
                  "at free-surface particles, add the (grad v)^T part of the viscous stress "
                  "that the Morris term lacks there, so the surface is traction-free (a "
                  "fountain front); with implicit viscosity it is part of the viscous solve; "
                  "see `docs/physics.md`")
              .identity()),
      number("neighbor_skin", "", in_range(0, 1, kClosed, kOpen), &N::neighbor_skin,
             "Verlet skin as a fraction of the support 2h; a coupled run's fibers take "
             "a pair-list skin of at most half of it (`docs/parallel.md`, \"The coupled "
             "run's skins\")")
          .identity(),
      boolean("lattice_correction", &N::lattice_correction,
              "scale the kernel gradient (by 1/0.964 in 2D at h/dp = 1.2) and the viscous "
              "Laplacian (1/0.953) so both are exact on the lattice the resin starts on; see "
              "`docs/physics.md`")
          .identity(),
  };
  s.finish = check_numerics;
  s.intro = "h below is the smoothing length, `h_over_spacing * spacing`.\n";
  s.notes =
      "Without `fixed_dt` the step adapts (the minimum of the three limits above).\n"
      "A `fixed_dt` that cannot be stable is rejected before the run: it must not\n"
      "exceed `cfl * h / c0` (the CFL limit at rest, the most lenient it gets) nor,\n"
      "when the viscosity is positive and `viscous_integration` is explicit,\n"
      "`viscous_factor * h^2 * density / viscosity`. The error gives the limit:\n"
      "`key 'numerics.fixed_dt': 2.0e-6 s exceeds the stable limit cfl*h/c0 = 1.5e-06 s`.\n"
      "\n"
      "`viscous_integration: implicit` drops the viscous limit: after the second\n"
      "kick the velocities solve (M - dt M L) u = M v, the walls' dummy values\n"
      "taken from u itself, by Jacobi-preconditioned BiCGSTAB over the neighbour\n"
      "graph, with rank-count independent sums. A solve that does not reach `implicit_tolerance` "
      "within\n"
      "`implicit_max_iterations` stops the run with an error (docs/physics.md\n"
      "\"Implicit viscosity\").\n";
  return s;
}

}  // namespace

const Section<Resin>& resin_keys() {
  static const Section<Resin> s = make_resin();
  return s;
}

const Section<Numerics>& numerics_keys() {
  static const Section<Numerics> s = make_numerics();
  return s;
}

}  // namespace sphdem::config
