// The `fibers:` section: how many fibers, of what, where (docs/case-file.md).
#include "fibers_reader.hpp"

#include <numbers>

#include "shapes.hpp"

namespace sphdem::config {

namespace {

// Exactly one of count and area_fraction.
void read_amount(const Map& m, FiberSettings& f) {
  const std::optional<Value> count = m.get("count");
  const std::optional<Value> fraction = m.get("area_fraction");
  if (count && fraction) fraction->fail("give either count or area_fraction, not both");
  if (!count && !fraction) m.require("count", " (give count or area_fraction)");
  if (count) {
    f.count = integer_at_least(*count, 1);
    f.amount_line = count->line();
  } else {
    f.area_fraction = in_interval(*fraction, {0, 1, true, true});
    f.amount_line = fraction->line();
  }
}

// An angle in degrees, or `random`.
std::optional<double> read_orientation(const Value& v) {
  if (v.node().IsScalar() && v.text() == "random") return std::nullopt;
  if (!v.node().IsScalar()) v.fail("expected an angle in degrees or 'random', got " + v.describe());
  return v.number() * std::numbers::pi / 180.0;
}

}  // namespace

FiberSettings read_fibers(const Value& v, int dim) {
  const Map m =
      v.map({"count", "area_fraction", "particles_per_fiber", "diameter", "density",
             "youngs_modulus", "tensile_strength", "shear_strength", "stiffness_ratio",
             "contact_stiffness_fraction", "restitution", "friction", "region", "orientation",
             "seed", "dt_safety", "void_fraction_min", "void_fraction_in_continuity"});
  FiberSettings f;
  f.line = v.line();
  read_amount(m, f);
  if (auto x = m.get("particles_per_fiber")) f.particles_per_fiber = integer_at_least(*x, 1);
  f.diameter = positive(m.require("diameter"));
  f.density = positive(m.require("density"));
  f.youngs_modulus = positive(m.require("youngs_modulus"));
  if (auto x = m.get("tensile_strength")) f.tensile_strength = positive(*x);
  if (auto x = m.get("shear_strength")) f.shear_strength = positive(*x);
  if (auto x = m.get("stiffness_ratio")) f.stiffness_ratio = positive(*x);
  if (auto x = m.get("contact_stiffness_fraction")) {
    f.contact_stiffness_fraction = in_interval(*x, {0, 1, true, false});
  }
  if (auto x = m.get("restitution")) f.restitution = in_interval(*x, {0, 1, true, false});
  if (auto x = m.get("friction")) f.friction = non_negative(*x);
  const Value region = m.require("region");
  f.region = read_shape(region, dim);
  if (f.region.type != Shape::Type::Box)
    region.fail("must be a box: {box: {min: [...], max: [...]}}");
  if (auto x = m.get("orientation")) f.angle = read_orientation(*x);
  if (auto x = m.get("seed")) f.seed = static_cast<std::uint64_t>(integer_at_least(*x, 0));
  if (auto x = m.get("dt_safety")) f.dt_safety = in_interval(*x, {0, 2, true, false});
  if (auto x = m.get("void_fraction_min"))
    f.void_fraction_min = in_interval(*x, {0, 1, true, true});
  if (auto x = m.get("void_fraction_in_continuity")) f.void_fraction_in_continuity = x->boolean();
  return f;
}

}  // namespace sphdem::config
