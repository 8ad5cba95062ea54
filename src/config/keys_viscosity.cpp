// `resin.viscosity` as a law, `resin.material` and `resin.melt_temperature`
// (docs/case-file.md, docs/physics.md "Melt viscosity"). A plain number is
// the Newtonian viscosity, as it always was; a mapping names a
// generalized-Newtonian law and its published constants.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "schema.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/sph/viscosity_law.hpp"

namespace sphdem::config {

namespace {

using V = MeltViscosity;

const std::vector<std::string>& law_names() {
  static const std::vector<std::string> names{"newtonian", "power_law", "carreau", "cross",
                                              "cross_wlf"};
  return names;
}

const char* law_name(ViscosityLaw l) {
  return law_names()[static_cast<std::size_t>(l)].c_str();
}

// Which constants each law takes (the others are an error there).
const std::vector<std::string>& law_constants(ViscosityLaw l) {
  static const std::vector<std::vector<std::string>> keys{
      {"zero_shear_viscosity"},
      {"consistency", "n"},
      {"zero_shear_viscosity", "infinite_shear_viscosity", "relaxation_time", "n"},
      {"zero_shear_viscosity", "tau_star", "n"},
      {"n", "tau_star", "d1", "d2", "d3", "a1", "a2_tilde", "no_flow_temperature"}};
  return keys[static_cast<std::size_t>(l)];
}

// Constants a law cannot do without (the rest have defaults).
const std::vector<std::string>& law_required(ViscosityLaw l) {
  static const std::vector<std::vector<std::string>> keys{
      {"zero_shear_viscosity"},
      {"consistency", "n", "max"},
      {"zero_shear_viscosity", "relaxation_time", "n"},
      {"zero_shear_viscosity", "tau_star", "n"},
      {"n", "tau_star", "d1", "d2", "a1", "a2_tilde"}};
  return keys[static_cast<std::size_t>(l)];
}

// The Celsius warning of every temperature key (schema.hpp).
void warn_celsius(const Value& v, double kelvin, Context& ctx) {
  warn_if_celsius(v, kelvin, ctx);
}

Key<V> model() {
  Key<V> k{"model",
           "enum",
           "",
           "required",
           "newtonian, power_law, carreau, cross or cross_wlf",
           "the viscosity law (docs/physics.md \"Melt viscosity\")"};
  k.is_required = true;
  k.read = [](const Value& v, V& m, Context&) {
    const std::string s = v.string();
    const auto& names = law_names();
    const auto it = std::find(names.begin(), names.end(), s);
    if (it == names.end()) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      const std::string near = closest_match(s, names);
      v.fail(fmt::format("unknown viscosity model '{}'{}; the models are: {}", s,
                         near.empty() ? "" : " (did you mean '" + near + "'?)", list));
    }
    m.law = static_cast<ViscosityLaw>(it - names.begin());
  };
  k.show = [](const V& m) { return std::string(law_name(m.law)); };
  return k;
}

Key<V> kelvin(std::string name, std::optional<double> V::*field, std::string doc) {
  Key<V> k = optional_number(std::move(name), "K", positive_number(), field, std::move(doc));
  k.read = [field](const Value& v, V& m, Context& ctx) {
    m.*field = positive(v);
    warn_celsius(v, *(m.*field), ctx);
  };
  return k;
}

// Each given constant belongs to the law; the law's required ones are given.
void finish_law(const Map& m, V& v, Context& ctx) {
  const auto& mine = law_constants(v.law);
  for (const std::string c :
       {"zero_shear_viscosity", "infinite_shear_viscosity", "relaxation_time", "consistency", "n",
        "tau_star", "d1", "d2", "d3", "a1", "a2_tilde", "no_flow_temperature"}) {
    if (std::find(mine.begin(), mine.end(), c) != mine.end()) continue;
    if (const std::optional<Value> x = m.get(c)) {
      std::string list;
      for (const std::string& n : mine) list += (list.empty() ? "" : ", ") + n;
      x->fail(
          fmt::format("does not apply to model '{}' (its constants: {})", law_name(v.law), list));
    }
  }
  for (const std::string& c : law_required(v.law)) {
    const char* why = c == "max" ? " (a power law's viscosity is unbounded at zero or infinite "
                                   "shear rate: give the upper limit)"
                                 : "";
    if (!m.has(c)) m.require(c, fmt::format(" (model '{}'{})", law_name(v.law), why));
  }
  if (v.law != ViscosityLaw::PowerLaw && v.law != ViscosityLaw::Newtonian && v.n > 1.0) {
    m.require("n").fail(fmt::format("{} must be in (0, 1] for model '{}' (shear thinning)",
                                    m.require("n").text(), law_name(v.law)));
  }
  if (v.law == ViscosityLaw::Carreau && v.eta_inf > v.eta0) {
    m.require("infinite_shear_viscosity")
        .fail("must not exceed zero_shear_viscosity (a shear-thinning melt)");
  }
  if (v.max && *v.max < v.min) {
    m.require("max").fail(fmt::format("must be at least min ({} Pa s)", show_number(v.min)));
  }
  if (v.law == ViscosityLaw::CrossWlf) {
    if (const std::optional<Value> d2 = m.get("d2")) warn_celsius(*d2, v.d2, ctx);
  }
}

Section<V> make_viscosity_law() {
  Section<V> s;
  s.keys = {
      model().identity(),
      number("zero_shear_viscosity", "Pa s", positive_number(), &V::eta0,
             "eta0 (newtonian: the viscosity; carreau, cross)")
          .identity(),
      number("infinite_shear_viscosity", "Pa s", non_negative_number(), &V::eta_inf,
             "eta_inf (carreau)")
          .identity(),
      number("relaxation_time", "s", positive_number(), &V::relaxation_time, "lambda (carreau)")
          .identity(),
      number("consistency", "Pa s^n", positive_number(), &V::consistency, "K (power_law)")
          .identity(),
      number("n", "", positive_number(), &V::n,
             "flow index (power_law: > 0; carreau, cross, cross_wlf: in (0, 1])")
          .identity(),
      number("tau_star", "Pa", positive_number(), &V::tau_star,
             "tau*, the shear stress of the transition to shear thinning (cross, cross_wlf)")
          .identity(),
      number("d1", "Pa s", positive_number(), &V::d1, "D1: zero-shear viscosity at T* (cross_wlf)")
          .identity(),
      number(
          "d2", "K", positive_number(), &V::d2,
          "D2: T* at zero pressure (cross_wlf; kelvin: a value below 250 gives a Celsius warning)")
          .identity(),
      number("d3", "K/Pa", non_negative_number(), &V::d3, "D3: pressure shift of T* (cross_wlf)")
          .identity(),
      number("a1", "", positive_number(), &V::a1, "A1 (cross_wlf)").identity(),
      number("a2_tilde", "K", positive_number(), &V::a2_tilde, "A2~ (cross_wlf)").identity(),
      kelvin("no_flow_temperature", &V::no_flow_temperature,
             "below it the melt does not flow (viscosity = max) (cross_wlf)")
          .defaults_to("none")
          .identity(),
      number("min", "Pa s", non_negative_number(), &V::min, "lower viscosity limit").identity(),
      optional_number("max", "Pa s", positive_number(), &V::max,
                      "upper viscosity limit (required for power_law)")
          .defaults_to("none")
          .identity(),
  };
  s.finish = finish_law;
  s.intro =
      "A mapping under `resin.viscosity` (or the `viscosity:` of a material file, "
      "`resin.material`) names a law by `model` and gives its constants; each particle's "
      "viscosity is the law at its shear rate, clamped to [min, max].\n";
  return s;
}

const Section<V>& viscosity_law_keys() {
  static const Section<V> s = make_viscosity_law();
  return s;
}

void read_law(const Value& v, Resin& r, Context& ctx) {
  const std::string material = r.melt.material;
  r.melt = V{};
  r.melt.material = material;
  read_section(viscosity_law_keys(), v, r.melt, ctx);
  if (r.melt.law == ViscosityLaw::Newtonian) r.viscosity = r.melt.eta0;
}

// A material file: name, source, and a viscosity mapping. Relative paths
// are taken from the case file's folder, then from the working directory.
std::string resolve_material(const Value& v) {
  namespace fs = std::filesystem;
  const fs::path given(v.string());
  if (given.is_relative()) {
    const fs::path beside = fs::path(v.source().file()).parent_path() / given;
    std::error_code ec;
    if (fs::is_regular_file(beside, ec)) return beside.string();
  }
  std::error_code ec;
  if (!fs::is_regular_file(given, ec))
    v.fail(
        fmt::format("cannot open material file '{}' (looked beside the case file and in the "
                    "working directory)",
                    given.string()));
  return given.string();
}

void read_material(const Value& v, Resin& r, Context& ctx) {
  const std::string path = resolve_material(v);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line >= 0 ? e.mark.line + 1 : 0, "",
                     "YAML syntax error: " + e.msg);
  }
  const Source src(path, {});
  const Value file(src, root, "", 1);
  const Map m = file.map({"name", "source", "viscosity"});
  m.require("name").string();
  m.require("source").string();
  r.melt.material = v.string();
  read_law(m.require("viscosity"), r, ctx);
}

}  // namespace

Key<Resin> resin_viscosity_key() {
  Key<Resin> k{"viscosity",
               "number or mapping",
               "Pa s",
               "required (or `material`)",
               ">= 0",
               "a number: the Newtonian viscosity mu, 0 = inviscid (read by the SPH viscosity "
               "term and the drag law); a mapping: a shear-thinning law, see below"};
  k.read = [](const Value& v, Resin& r, Context& ctx) {
    if (v.node().IsScalar()) {
      r.viscosity = non_negative(v);
      r.melt = V{};
    } else {
      read_law(v, r, ctx);
    }
  };
  k.absent = [](const Map& m, Resin&, Context&) {
    if (!m.has("material")) m.require("viscosity", " (or resin.material)");
  };
  k.in_identity = true;
  k.section_doc = [] { return section_doc(viscosity_law_keys()); };
  // Newtonian shows as the number it always was (the checkpoint identity of
  // older cases stays the same); a law shows every constant.
  k.section_settings = [](const Resin& r, const std::string& key, std::vector<Setting>& out) {
    if (r.melt.law == ViscosityLaw::Newtonian) {
      out.push_back({key, show_number(r.viscosity), true, false});
    } else {
      section_settings(viscosity_law_keys(), r.melt, key, out);
    }
  };
  return k;
}

Key<Resin> resin_material_key() {
  Key<Resin> k{"material",
               "path",
               "",
               "none",
               "",
               "a material file (inputs/materials/) whose `viscosity:` mapping is the law; "
               "instead of `viscosity`"};
  k.read = [](const Value& v, Resin& r, Context& ctx) { read_material(v, r, ctx); };
  k.show = [](const Resin& r) { return r.melt.material.empty() ? "none" : r.melt.material; };
  return k;
}

Key<Resin> resin_melt_temperature_key() {
  Key<Resin> k =
      optional_number("melt_temperature", "K", positive_number(), &Resin::melt_temperature,
                      "the melt's temperature (cross_wlf; a value below 250 gives a "
                      "warning: kelvin expected)");
  k.read = [](const Value& v, Resin& r, Context& ctx) {
    r.melt_temperature = positive(v);
    warn_celsius(v, *r.melt_temperature, ctx);
  };
  k.defaults_to("none").identity();
  // In the identity only when given: older cases keep their identity lines.
  k.section_settings = [](const Resin& r, const std::string& key, std::vector<Setting>& out) {
    if (r.melt_temperature) out.push_back({key, show_number(*r.melt_temperature), true, false});
  };
  return k;
}

// After every resin key: exactly one of viscosity and material; Cross-WLF's
// melt temperature above the no-flow temperature and T*; the largest
// viscosity the law reaches (the viscous time step of `sphdem check`).
void finish_melt(const Map& m, Resin& r, Context&) {
  const std::optional<Value> visc = m.get("viscosity");
  const std::optional<Value> mat = m.get("material");
  if (visc && mat) mat->fail("give either viscosity or material, not both");
  V& law = r.melt;
  if (law.law == ViscosityLaw::Newtonian) return;
  if (law.law == ViscosityLaw::CrossWlf) {
    // With resin.thermal each particle carries its temperature and the law
    // reads it; the melt temperature is then thermal.temperature, given once.
    if (r.thermal && m.get("melt_temperature")) {
      m.require("melt_temperature")
          .fail(
              "with resin.thermal the melt temperature is resin.thermal.temperature; give it "
              "once");
    }
    const Value t = r.thermal ? m.require("thermal")
                              : m.require("melt_temperature",
                                          " (model 'cross_wlf' needs the melt's "
                                          "temperature, K)");
    const double T = r.thermal ? r.thermal->temperature : *r.melt_temperature;
    if (law.no_flow_temperature && T < *law.no_flow_temperature) {
      t.fail(fmt::format("{} K is below the no-flow temperature {} K: the melt would not flow",
                         show_number(T), show_number(*law.no_flow_temperature)));
    }
    if (!(T - law.d2 + law.a2_tilde > 0.0)) {
      t.fail(fmt::format("{} K is at or below T* - A2~ = {} K, where the WLF shift is singular",
                         show_number(T), show_number(law.d2 - law.a2_tilde)));
    }
  }
  // The largest viscosity: max, or the zero-shear value (shear thinning).
  const double T = r.thermal ? r.thermal->temperature : r.melt_temperature.value_or(0.0);
  r.viscosity = law.max ? *law.max : std::max(law.min, viscosity_law(law, 0.0, 0.0, T, 0.0));
}

}  // namespace sphdem::config

namespace sphdem::config {

namespace {
// The narrowest passage (the smallest extent of any mold shape's bounding
// box) and the flow length (the largest extent of the whole mold's box).
std::pair<double, double> mold_extents(const Case& c) {
  Vec3a lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  double small = 1e300;
  for (const Shape& s : c.mold.shapes) {
    Vec3a slo{1e300, 1e300, 1e300}, shi{-1e300, -1e300, -1e300};
    const auto grow = [&](int d, double v) {
      slo[d] = std::min(slo[d], v);
      shi[d] = std::max(shi[d], v);
    };
    if (s.type == Shape::Type::Box) {
      for (int d = 0; d < c.dimension; ++d) grow(d, s.lo[d]), grow(d, s.hi[d]);
    } else {
      for (const auto& p : s.vertices) grow(0, p[0]), grow(1, p[1]);
    }
    for (int d = 0; d < c.dimension; ++d) {
      small = std::min(small, shi[d] - slo[d]);
      lo[d] = std::min(lo[d], slo[d]);
      hi[d] = std::max(hi[d], shi[d]);
    }
  }
  double large = 0;
  for (int d = 0; d < c.dimension; ++d) large = std::max(large, hi[d] - lo[d]);
  return {small, large};
}
}  // namespace

// docs/physics.md "Injection pressure": the weakly compressible resin
// carries a pressure difference dp only by compressing, by dp / (rho c0^2);
// a viscous pressure drop beyond 1 % of rho c0^2 is more compression than
// the model allows. The drop is estimated as plane Poiseuille flow through
// the narrowest mold shape (W, its smallest extent) over the mold's largest
// extent L at the fastest wall's
// speed U: dp = 12 eta U L / W^2, eta the law at the wall shear rate 6 U / W.
void warn_viscous_pressure(Case& c) {
  constexpr double kAllowedCompression = 0.01;
  double u = 0;
  for (const MovingWall& w : c.moving_walls)
    for (const Vec3a& v : w.velocity.velocity) u = std::max(u, std::hypot(v[0], v[1], v[2]));
  if (u <= 0 || c.mold.shapes.empty() || c.numerics.viscosity_model == ViscosityModel::None) return;
  const auto [gap, length] = mold_extents(c);
  if (!(gap > 0)) return;
  // The melt as it enters: at the melt temperature (resin.thermal's
  // initial temperature when the particles carry one), not the cold law's max.
  const double melt_t =
      c.resin.thermal ? c.resin.thermal->temperature : c.resin.melt_temperature.value_or(0.0);
  const double eta = melt_viscosity(c.resin.melt, c.resin.viscosity, 6.0 * u / gap, melt_t, 0.0);
  const double dp = 12.0 * eta * u * length / (gap * gap);
  const double carried =
      kAllowedCompression * c.resin.density * c.resin.sound_speed * c.resin.sound_speed;
  if (dp > carried) {
    c.warnings.push_back(fmt::format(
        "the expected viscous pressure drop {:.3g} Pa (12 eta U L / W^2: eta {:.3g} Pa s, wall "
        "speed U {:.3g} m/s, mold {:.3g} m long, narrowest shape {:.3g} m) exceeds what the sound "
        "speed "
        "carries at 1 % density variation, 0.01 rho c0^2 = {:.3g} Pa: the resin compresses by "
        "about {:.2g} %, and pressures are not physical; a sound speed of {:.3g} m/s or more "
        "would carry it (docs/physics.md \"Injection pressure\")",
        dp, eta, u, length, gap, carried,
        100.0 * dp / (c.resin.density * c.resin.sound_speed * c.resin.sound_speed),
        std::sqrt(dp / (kAllowedCompression * c.resin.density))));
  }
}

}  // namespace sphdem::config
