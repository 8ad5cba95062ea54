// The `fibers:` keys: how many fibers, of what, where (docs/case-file.md,
// docs/dem.md).
#include <numbers>

#include "schema.hpp"

namespace sphdem::config {

namespace {

using F = FiberSettings;

// docs/dem.md "Stable time step": a free chain stays stable up to this.
constexpr double kStableDtSafety = 1.2;

// Exactly one of count and area_fraction (each validated by its key).
void finish_fibers(const Map& m, F& f, Context& ctx) {
  f.line = m.self().line();
  const std::optional<Value> count = m.get("count");
  const std::optional<Value> fraction = m.get("area_fraction");
  if (count && fraction) fraction->fail("give either count or area_fraction, not both");
  if (!count && !fraction) m.require("count", " (give count or area_fraction)");
  if (f.initial_bend > 0 && f.particles_per_fiber < 3)
    m.get("initial_bend")->fail("a bend needs at least 3 particles per fiber");
  if (f.dt_safety > kStableDtSafety) {
    ctx.c.warnings.push_back(fmt::format(
        "fibers.dt_safety = {} is above {}, the largest step a free chain of fibers stays stable "
        "at (docs/dem.md, \"Stable time step\"): expect the DEM to blow up",
        f.dt_safety, kStableDtSafety));
  }
}

Key<F> count() {
  Key<F> k{"count", "integer", "", "one of count, area_fraction", ">= 1", "number of fibers"};
  k.read = [](const Value& v, F& f, Context&) {
    f.count = integer_at_least(v, 1);
    f.amount_line = v.line();
  };
  k.show = [](const F& f) { return std::to_string(f.count); };
  return k;
}

Key<F> area_fraction() {
  const Rule rule = in_range(0, 1, true, true);
  Key<F> k{"area_fraction",
           "number",
           "",
           "one of count, area_fraction",
           rule.text(),
           "the smallest count whose particles (disk areas; sphere volumes in 3D) cover this "
           "fraction of `region`"};
  k.read = [rule](const Value& v, F& f, Context&) {
    f.area_fraction = rule.read(v);
    f.amount_line = v.line();
  };
  k.show = [](const F& f) { return show_number(f.area_fraction); };
  return k;
}

Key<F> region() {
  Key<F> k = shape("region", &F::region,
                   "every particle lies fully inside it; inside the mold; must be a box");
  k.read = [](const Value& v, F& f, Context& ctx) {
    f.region = read_shape(v, ctx.c.dimension);
    if (f.region.type != Shape::Type::Box) v.fail("must be a box: {box: {min: [...], max: [...]}}");
  };
  return k;
}

// An angle in degrees, or `random`.
Key<F> orientation() {
  Key<F> k{"orientation",
           "number or random",
           "degrees",
           "",
           "",
           "the angle of every fiber from +x (0: across an injection along -y), in 3D in the x-y "
           "plane; or uniformly random (on the sphere in 3D)"};
  k.read = [](const Value& v, F& f, Context&) {
    if (v.node().IsScalar() && v.text() == "random") {
      f.angle = std::nullopt;
      return;
    }
    if (!v.node().IsScalar())
      v.fail("expected an angle in degrees or 'random', got " + v.describe());
    f.angle = v.number() * std::numbers::pi / 180.0;
  };
  k.show = [](const F& f) {
    return f.angle ? show_number(*f.angle * 180.0 / std::numbers::pi) : "random";
  };
  return k;
}

Key<F> seed() {
  Key<F> k{"seed", "integer", "",
           "",     ">= 0",    "the same seed places the same fibers on any machine"};
  k.read = [](const Value& v, F& f, Context&) {
    f.seed = static_cast<std::uint64_t>(integer_at_least(v, 0));
  };
  k.show = [](const F& f) { return std::to_string(f.seed); };
  return k;
}

// A setting (and identity line) only when not 0, so that a case without
// it keeps the identity lines of older checkpoints.
Key<F> initial_bend() {
  Key<F> k = number("initial_bend", "", in_range(0, 0.25, false, true), &F::initial_bend,
                    "seeds each fiber with a bend: the sagitta of a half-sine arc (its centres) "
                    "over the fiber length, bulging in 3D along e_z x the axis (the x-y plane for "
                    "fibers in it), a stressed perturbation of the straight fiber, which stays "
                    "its rest shape (`docs/dem.md` \"Seeded bend\"; buckling tests); 0: straight");
  const auto show = k.show;
  k.section_settings = [show](const F& f, const std::string& key, std::vector<Setting>& out) {
    if (f.initial_bend != 0) out.push_back({key, show(f), true, false});
  };
  return k;
}

Key<F> bond_integration() {
  Key<F> k{"bond_integration",
           "enum",
           "",
           "explicit",
           "explicit, subcycled or implicit",
           "explicit: every DEM force at the stable step of the bonds; subcycled: the bonds in "
           "inner steps of that size, contacts, walls and drag at the contacts' stable step "
           "(glass fibers at an affordable cost, `docs/dem.md` \"Bond sub-cycling\"); implicit: "
           "contacts, walls and drag as subcycled, each fiber's bonds in one linear solve per "
           "step (`docs/dem.md` \"Implicit bonds\")"};
  k.read = [](const Value& v, F& f, Context&) {
    const std::string mode = one_of(v, {"explicit", "subcycled", "implicit"});
    f.subcycle_bonds = mode != "explicit";
    f.implicit_bonds = mode == "implicit";
  };
  k.show = [](const F& f) {
    return f.implicit_bonds ? "implicit" : f.subcycle_bonds ? "subcycled" : "explicit";
  };
  return k;
}

Key<F> drag_integration() {
  Key<F> k{"drag_integration",
           "enum",
           "",
           "explicit",
           "explicit or exponential",
           "coupled runs: explicit: the resin's drag a force in the fibers' sub-steps, which "
           "then stay below the fibers' drag time and the resin's step below its own; "
           "exponential: each fiber particle and its resin relax towards their common velocity "
           "by the exact exponential of the two-body exchange, the resin getting the opposite "
           "impulse, stable at any step (a viscous melt; `docs/physics.md` \"Exponential "
           "drag\")"};
  k.read = [](const Value& v, F& f, Context&) {
    f.exponential_drag = one_of(v, {"explicit", "exponential"}) == "exponential";
  };
  k.show = [](const F& f) { return f.exponential_drag ? "exponential" : "explicit"; };
  return k;
}

Section<F> make_fibers() {
  Section<F> s;
  s.keys = {
      count().identity(),
      area_fraction().identity(),
      integer("particles_per_fiber", "", 1, &F::particles_per_fiber,
              "touching particles per fiber (fiber length = this x `diameter`)")
          .identity(),
      // From a nanometre to a metre: beyond, masses and stiffnesses leave
      // the range of doubles (a mass of d^2 underflows at d = 1e-160).
      number("diameter", "m", in_range(1e-9, 1, false, false), &F::diameter,
             "particle (fiber) diameter")
          .required()
          .identity(),
      number("density", "kg/m^3", positive_number(), &F::density, "the fibers' density")
          .required()
          .identity(),
      number("youngs_modulus", "Pa", positive_number(), &F::youngs_modulus,
             "E of the parallel bonds, kbar_n = E / (R1 + R2)")
          .required()
          .identity(),
      optional_number("tensile_strength", "Pa", positive_number(), &F::tensile_strength,
                      "a bond breaks when its peak tensile stress reaches it; none: never")
          .identity(),
      optional_number("shear_strength", "Pa", positive_number(), &F::shear_strength,
                      "same for the shear stress")
          .identity(),
      number("stiffness_ratio", "", positive_number(), &F::stiffness_ratio,
             "kbar* = kbar_n / kbar_s (the paper's 0.25)")
          .identity(),
      number("contact_stiffness_fraction", "", in_range(0, 1, true, false),
             &F::contact_stiffness_fraction, "contact k_n = this x kbar_n A (docs/dem.md)")
          .identity(),
      number("restitution", "", in_range(0, 1, true, false), &F::restitution,
             "sets the contact damping")
          .identity(),
      number("friction", "", non_negative_number(), &F::friction,
             "Coulomb coefficient, particle-particle and particle-wall")
          .identity(),
      region().required().identity(),
      orientation().identity(),
      seed().identity(),
      initial_bend().identity(),
      // Below 1e-3 a contact would take thousands of steps: no accuracy gained.
      number("dt_safety", "", in_range(1e-3, 2, false, true), &F::dt_safety,
             "DEM step = dt_safety x min sqrt(m/k) (`docs/dem.md`); stable up to about 1.2 (a "
             "warning above)")
          .identity(),
      bond_integration().identity(),
      drag_integration().identity(),
      number("void_fraction_min", "", in_range(0, 1, true, true), &F::void_fraction_min,
             "the local void fraction is clipped to [void_fraction_min, 1] (coupled runs, "
             "`docs/physics.md` \"Coupling\")")
          .identity(),
      boolean("void_fraction_in_continuity", &F::void_fraction_in_continuity,
              "coupled runs: the resin's continuity equation with the local void fraction (the "
              "paper's \"local averaging\"); false: plain continuity")
          .identity(),
      boolean("hydrodynamic_torque", &F::hydrodynamic_torque,
              "coupled runs: each fiber particle gets the torque of the resin's local rotation "
              "(half its vorticity) against its spin, with the bead model's rotational friction, "
              "and the resin its reaction, so that fibers tumble in Jeffery orbits "
              "(`docs/physics.md` \"Hydrodynamic torque\"); false: drag only, fibers align "
              "with the flow and never flip")
          .identity(),
  };
  s.finish = finish_fibers;
  s.intro =
      "Fibers are straight chains of bonded DEM particles (disks in 2D), placed at\n"
      "random without overlap at the start (`docs/dem.md`). A case with `fibers`\n"
      "and no `fill` is a **fibers-only run**: no resin; the boundary of the mold\n"
      "(the union of its shapes) is DEM walls: in 2D the parts of the shapes' edges\n"
      "on the outline of the union (segments), in 3D, where the mold is a union of\n"
      "boxes, the parts of the boxes' faces on its surface (rectangles); where two\n"
      "shapes meet (the bath and the nozzle) there is no wall and fibers pass. Each\n"
      "moving wall pushes with the edges (3D: faces) of its region that touch the\n"
      "mold (the piston's face). `resin` and\n"
      "`numerics.spacing` are still required but unused; of `numerics` only\n"
      "`end_time` counts (the step is the DEM's, `dt_safety` below). A moving\n"
      "wall's `pressure_limit` has no effect without resin; sliding walls are\n"
      "ignored. `inputs/fibers_only.yaml` (2D) and `inputs/fibers_only_3d.yaml`\n"
      "(3D) are examples.\n"
      "`output.fields` does not apply: the DEM set always has the fields of\n"
      "`docs/dem.md`.\n"
      "\n"
      "With `fill` too, the case is **coupled** (`docs/physics.md`, \"Coupling\"):\n"
      "the fibers are placed in `region` among the resin, the DEM walls are those\n"
      "of a fibers-only run (fibers pass where two shapes meet, e.g. from the bath\n"
      "into the nozzle), the fibers sub-cycle inside each SPH step, and every\n"
      "snapshot has the `dem` set beside the resin's. 2D and 3D\n"
      "(`inputs/validation/coupled_box_3d.yaml`).\n";
  s.notes =
      "`count` and `area_fraction` are exclusive; one is required. When the\n"
      "generator cannot place the fibers (the fraction is too high for random\n"
      "placement, about 40 % for the paper's fibers), the error points at the key\n"
      "that asked: `fibers.yaml:8: key 'fibers.area_fraction': fibers: could not\n"
      "place fiber 1936 of 2751 after 20000 attempts (fraction reached 0.4222,\n"
      "requested 0.6002); ...`. `sphdem check` places the fibers too, so it reports\n"
      "this before a run.\n"
      "\n"
      "```yaml\n"
      "fibers:                          # inputs/fibers_only.yaml: the paper's bath\n"
      "  count: 175                     # 3.82 %\n"
      "  particles_per_fiber: 4\n"
      "  diameter: 2.5e-4\n"
      "  density: 2540\n"
      "  youngs_modulus: 7.2e10         # E-glass; the paper gives none\n"
      "  tensile_strength: 2.0e9\n"
      "  region: {box: {min: [-0.015, 0.030], max: [0.015, 0.060]}}\n"
      "  orientation: 0\n"
      "```\n";
  return s;
}

}  // namespace

const Section<FiberSettings>& fiber_keys() {
  static const Section<FiberSettings> s = make_fibers();
  return s;
}

}  // namespace sphdem::config
