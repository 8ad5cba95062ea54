// The `initial_fields:` keys (docs/case-file.md): the resin's velocity and
// density or pressure at t = 0 as expressions of x, y, z, per fill region.
// Each expression is parsed here, so a bad one is reported at its line;
// whether it is finite at every fill particle is checked where the
// particles are made (src/geometry/initial_fields.cpp).
#include <stdexcept>

#include "schema.hpp"
#include "sphdem/config/expression.hpp"

namespace sphdem::config {

namespace {

// A number or an expression string, parsed now.
Expression read_expression(const Value& v) {
  Expression e{v.string(), v.key(), v.line()};
  try {
    PointExpression check(e.text);
  } catch (const std::invalid_argument& err) {
    v.fail(fmt::format("bad expression '{}': {}", e.text, err.what()));
  }
  return e;
}

std::string show_expression(const std::optional<Expression>& e) {
  return e ? e->text : "none";
}

Key<InitialFields> fill_index() {
  Key<InitialFields> k{"fill",
                       "integer",
                       "",
                       "every fill region",
                       ">= 0, < the number of fill shapes",
                       "the index of the fill shape (fill[k]) whose resin these fields set"};
  k.read = [](const Value& v, InitialFields& f, Context& ctx) {
    const int i = integer_at_least(v, 0);
    if (static_cast<std::size_t>(i) >= ctx.c.fill.size()) {
      v.fail(fmt::format("no fill[{}]: the case has {} fill shape(s)", i, ctx.c.fill.size()));
    }
    f.fill = i;
  };
  k.show = [](const InitialFields& f) { return f.fill ? std::to_string(*f.fill) : "none"; };
  return k;
}

Key<InitialFields> velocity() {
  Key<InitialFields> k{"velocity",
                       "list of expressions",
                       "m/s",
                       "initial_velocity",
                       "D expressions (or numbers)",
                       "the velocity components as expressions of x, y, z, e.g. "
                       "['sin(2*pi*x/L)', 0] with L written out"};
  k.read = [](const Value& v, InitialFields& f, Context& ctx) {
    const std::vector<Value> items = v.list();
    if (items.size() != static_cast<std::size_t>(ctx.c.dimension)) {
      v.fail(fmt::format("expected {} expressions (dimension {}), got {}", ctx.c.dimension,
                         ctx.c.dimension, items.size()));
    }
    for (const Value& item : items) f.velocity.push_back(read_expression(item));
  };
  k.show = [](const InitialFields& f) {
    std::string s = "[";
    for (const Expression& e : f.velocity) s += (s.size() > 1 ? ", " : "") + e.text;
    return s + "]";
  };
  return k;
}

Key<InitialFields> scalar(std::string name, std::string unit,
                          std::optional<Expression> InitialFields::*field, std::string doc) {
  Key<InitialFields> k{std::move(name), "expression", std::move(unit), "none", "", std::move(doc)};
  k.read = [field](const Value& v, InitialFields& f, Context&) { f.*field = read_expression(v); };
  k.show = [field](const InitialFields& f) { return show_expression(f.*field); };
  return k;
}

// Shown only when given, so that the identity of a case without it keeps
// its earlier lines (checkpoints of those cases still restart).
Key<InitialFields> temperature() {
  Key<InitialFields> k = scalar("temperature", "K", &InitialFields::temperature,
                                "with resin.thermal: the temperature as an expression of x, y, z");
  k.section_settings = [](const InitialFields& f, const std::string& key,
                          std::vector<Setting>& out) {
    if (f.temperature) out.push_back({key, f.temperature->text, true, false});
  };
  return k;
}

Section<InitialFields> make_initial_fields() {
  using F = InitialFields;
  Section<F> s;
  s.keys = {
      fill_index().identity(),
      velocity().identity(),
      scalar("density", "kg/m^3", &F::density, "the density as an expression of x, y, z")
          .identity(),
      scalar("pressure", "Pa", &F::pressure,
             "the pressure as an expression of x, y, z; the density follows from the equation of "
             "state")
          .identity(),
      temperature().identity(),
  };
  s.finish = [](const Map& m, F& f, Context& ctx) {
    f.line = m.self().line();
    if (f.density && f.pressure) m.require("pressure").fail("give density or pressure, not both");
    if (f.temperature && !ctx.c.resin.thermal)
      m.require("temperature").fail("needs resin.thermal (the resin is isothermal)");
  };
  s.intro =
      "Each item sets the resin of one fill region (`fill: k`, the shape `fill[k]`) or of\n"
      "all of them at t = 0. Values are numbers or expressions of the position\n"
      "x, y, z [m] in muParser syntax (`+ - * / ^`, `sin cos tan exp log sqrt abs`, ...;\n"
      "the constants `pi` and `_e`), quoted when they hold a comma or start with a\n"
      "bracket, e.g. `velocity: ['sin(2*pi*x/1e-3)*cos(2*pi*y/1e-3)', 0]`. Items apply\n"
      "in order, after `initial_velocity` and the hydrostatic start; a later item\n"
      "overrides an earlier one where both apply.\n";
  s.notes =
      "Errors name the expression's key and line: one muParser cannot read\n"
      "(`bad expression 'sin(x': Unexpected end of expression at position 6`), and one\n"
      "that is not a finite number at some particle of its fill region (the position is\n"
      "given), and a temperature that is not positive.\n";
  return s;
}

}  // namespace

const Section<InitialFields>& initial_field_keys() {
  static const Section<InitialFields> s = make_initial_fields();
  return s;
}

}  // namespace sphdem::config
