#pragma once
// The case-file schema (private to config/, docs/case-file.md): every key of
// a case file is declared once, as a Key of the mapping (Section) it belongs
// to: its name, type, unit, default, validator, one-line doc, whether it
// belongs to the checkpoint identity, how it is read into the Case and how
// its value is shown. The loader, `sphdem keys`, `sphdem check`, the
// checkpoint identity and docs/case-file.md all walk these tables, so they
// cannot drift apart.
#include <fmt/format.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "shapes.hpp"
#include "sphdem/config/case.hpp"
#include "sphdem/config/config.hpp"
#include "yaml_reader.hpp"

namespace sphdem::config {

// Wall names are unique across both kinds: the output's wall_id and the
// log refer to walls by name.
class WallNames {
 public:
  std::string claim(const Value& name) {
    const auto [it, fresh] = first_use_.emplace(name.string(), name.key());
    if (!fresh) name.fail("duplicate wall name '" + it->first + "' (also " + it->second + ")");
    return it->first;
  }

 private:
  std::map<std::string, std::string> first_use_;  // name -> key where first used
};

// What a reader may use besides its own value: the case read so far (the
// top-level keys are read in schema order, so `dimension` and `resin` are
// there before the sections that need them) and the wall names.
struct Context {
  Case& c;
  WallNames walls;
};

// One rule for every temperature key, D2 of the Cross-WLF law included
// (docs/case-file.md): temperatures are in kelvin, and one below
// kCelsiusSuspect (-23 degC, colder than any melt, mold, wall or no-flow
// temperature) gets a warning naming the file, line and key, since a value
// typed in degrees Celsius (a mold at 40, a melt at 230, a D2 of 50) mostly
// lands there. A warning, not an error: a polyethylene's D2 (about 153 K)
// is meant.
inline constexpr double kCelsiusSuspect = 250.0;
void warn_if_celsius(const Value& v, double kelvin, Context& ctx);

// How a number is validated, and the same rule as text for the docs.
struct Rule {
  enum class Kind { Any, Positive, NonNegative, Range };
  Kind kind = Kind::Any;
  Interval range{};
  double read(const Value& v) const;
  std::string text() const;  // "> 0", "in (0, 1]", ""
};
inline Rule any_number() {
  return {};
}
inline Rule positive_number() {
  return {Rule::Kind::Positive, {}};
}
inline Rule non_negative_number() {
  return {Rule::Kind::NonNegative, {}};
}
inline Rule in_range(double lo, double hi, bool lo_open, bool hi_open) {
  return {Rule::Kind::Range, {lo, hi, lo_open, hi_open}};
}

// Values as text: doubles as the shortest text that reads back to the same
// bits (the checkpoint identity compares them).
std::string show_number(double v);
std::string show_vector(const Vec3a& v);  // "[x, y, z]", always 3 components
std::string show_shape(const Shape& s);   // "box [..] [..]" or "polygon [x, y] ..."
std::string show_table(const VelocityTable& t);
std::string show_bool(bool b);

// One key of a mapping whose values go into a T.
template <class T>
struct Key {
  Key(std::string name_, std::string type_, std::string unit_, std::string default_,
      std::string rule_, std::string doc_)
      : name(std::move(name_)),
        type(std::move(type_)),
        unit(std::move(unit_)),
        default_text(std::move(default_)),
        rule(std::move(rule_)),
        doc(std::move(doc_)) {}

  std::string name, type, unit;
  std::string default_text;  // empty: shown from a default-constructed T
  std::string rule;          // the validator as text
  std::string doc;           // one line
  bool is_required = false;
  bool in_identity = false;  // part of the checkpoint identity
  // Validates the value and stores it.
  std::function<void(const Value&, T&, Context&)> read;
  // When the key is not given (optional; e.g. a default that depends on
  // other keys, or "required unless").
  std::function<void(const Map&, T&, Context&)> absent;
  // The value as text; null for keys that only feed another (resin.mach).
  std::function<std::string(const T&)> show;
  // Lists of values (mold.shapes): one text per item, shown as key[k].
  std::function<std::vector<std::string>(const T&)> show_items;
  // Mappings and lists of mappings: the keys inside.
  std::function<KeysDoc()> section_doc;
  bool list_of_sections = false;
  std::function<void(const T&, const std::string&, std::vector<Setting>&)> section_settings;

  Key& required() {
    is_required = true;
    default_text = "required";
    return *this;
  }
  Key& identity() {
    in_identity = true;
    return *this;
  }
  Key& defaults_to(std::string text) {
    default_text = std::move(text);
    return *this;
  }
  Key& when_absent(std::function<void(const Map&, T&, Context&)> f) {
    absent = std::move(f);
    return *this;
  }
  Key& constraint(std::string text) {
    rule = std::move(text);
    return *this;
  }
};

// The keys of one mapping, in the order they are read (and documented),
// and the rules that span several of them.
template <class T>
struct Section {
  std::vector<Key<T>> keys;
  // Checks across keys, after every key was read (keeping the exact
  // messages of docs/case-file.md).
  std::function<void(const Map&, T&, Context&)> finish;
  std::string intro, notes;  // markdown around the key table of docs/case-file.md

  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const Key<T>& k : keys) n.push_back(k.name);
    return n;
  }
};

// Reads a mapping: unknown keys are rejected (with a suggestion) before
// anything else, then every key in schema order, then the cross-key rules.
template <class T>
void read_section(const Section<T>& s, const Value& v, T& t, Context& ctx) {
  const Map m = v.map(s.names());
  for (const Key<T>& k : s.keys) {
    if (const std::optional<Value> x = m.get(k.name)) {
      if (k.read) k.read(*x, t, ctx);
    } else if (k.is_required) {
      m.require(k.name);
    } else if (k.absent) {
      k.absent(m, t, ctx);
    }
  }
  if (s.finish) s.finish(m, t, ctx);
}

template <class T>
KeysDoc section_doc(const Section<T>& s) {
  KeysDoc d;
  d.intro = s.intro;
  d.notes = s.notes;
  const T defaults{};
  for (const Key<T>& k : s.keys) {
    KeyDoc kd;
    kd.name = k.name;
    kd.type = k.type;
    kd.unit = k.unit;
    kd.default_text = k.default_text;
    if (kd.default_text.empty() && k.show) kd.default_text = k.show(defaults);
    kd.rule = k.rule;
    kd.doc = k.doc;
    kd.identity = k.in_identity;
    if (k.section_doc) kd.section = std::make_shared<KeysDoc>(k.section_doc());
    kd.list = k.list_of_sections;
    d.keys.push_back(std::move(kd));
  }
  return d;
}

// Every shown key of `t` under `prefix`, in schema order.
template <class T>
void section_settings(const Section<T>& s, const T& t, const std::string& prefix,
                      std::vector<Setting>& out) {
  const T defaults{};
  for (const Key<T>& k : s.keys) {
    const std::string key = child_key(prefix, k.name);
    if (k.section_settings) {
      k.section_settings(t, key, out);
    } else if (k.show_items) {
      const std::vector<std::string> items = k.show_items(t);
      for (std::size_t i = 0; i < items.size(); ++i)
        out.push_back({item_key(key, i), items[i], k.in_identity, false});
    } else if (k.show) {
      std::string value = k.show(t);
      const bool is_default = !k.is_required && value == k.show(defaults);
      out.push_back({key, std::move(value), k.in_identity, is_default});
    }
  }
}

// --- key makers: the common types -------------------------------------------

template <class T>
Key<T> number(std::string name, std::string unit, Rule rule, double T::*field, std::string doc) {
  Key<T> k{std::move(name), "number", std::move(unit), "", rule.text(), std::move(doc)};
  k.read = [rule, field](const Value& v, T& t, Context&) { t.*field = rule.read(v); };
  k.show = [field](const T& t) { return show_number(t.*field); };
  return k;
}

template <class T>
Key<T> optional_number(std::string name, std::string unit, Rule rule,
                       std::optional<double> T::*field, std::string doc) {
  Key<T> k{std::move(name), "number", std::move(unit), "", rule.text(), std::move(doc)};
  k.read = [rule, field](const Value& v, T& t, Context&) { t.*field = rule.read(v); };
  k.show = [field](const T& t) { return t.*field ? show_number(*(t.*field)) : "none"; };
  return k;
}

template <class T>
Key<T> integer(std::string name, std::string unit, int min, int T::*field, std::string doc) {
  Key<T> k{std::move(name),           "integer",     std::move(unit), "",
           fmt::format(">= {}", min), std::move(doc)};
  k.read = [min, field](const Value& v, T& t, Context&) { t.*field = integer_at_least(v, min); };
  k.show = [field](const T& t) { return std::to_string(t.*field); };
  return k;
}

template <class T>
Key<T> optional_integer(std::string name, std::string unit, int min, std::optional<int> T::*field,
                        std::string doc) {
  Key<T> k{std::move(name),           "integer",     std::move(unit), "",
           fmt::format(">= {}", min), std::move(doc)};
  k.read = [min, field](const Value& v, T& t, Context&) { t.*field = integer_at_least(v, min); };
  k.show = [field](const T& t) { return t.*field ? std::to_string(*(t.*field)) : "none"; };
  return k;
}

template <class T>
Key<T> boolean(std::string name, bool T::*field, std::string doc) {
  Key<T> k{std::move(name), "boolean", "", "", "", std::move(doc)};
  k.read = [field](const Value& v, T& t, Context&) { t.*field = v.boolean(); };
  k.show = [field](const T& t) { return show_bool(t.*field); };
  return k;
}

template <class T>
Key<T> string(std::string name, std::string T::*field, std::string doc) {
  Key<T> k{std::move(name), "string", "", "", "", std::move(doc)};
  k.read = [field](const Value& v, T& t, Context&) { t.*field = v.string(); };
  k.show = [field](const T& t) { return t.*field; };
  return k;
}

// D numbers, D = dimension.
template <class T>
Key<T> vector(std::string name, std::string unit, Vec3a T::*field, std::string doc) {
  Key<T> k{std::move(name), "vector", std::move(unit), "", "", std::move(doc)};
  k.read = [field](const Value& v, T& t, Context& ctx) { t.*field = v.vector(ctx.c.dimension); };
  k.show = [field](const T& t) { return show_vector(t.*field); };
  return k;
}

template <class T>
Key<T> shape(std::string name, Shape T::*field, std::string doc) {
  Key<T> k{std::move(name), "shape", "m", "", "", std::move(doc)};
  k.read = [field](const Value& v, T& t, Context& ctx) {
    t.*field = read_shape(v, ctx.c.dimension);
  };
  k.show = [field](const T& t) { return show_shape(t.*field); };
  k.section_doc = shape_keys_doc;
  return k;
}

template <class T>
Key<T> shape_list(std::string name, std::vector<Shape> T::*field, std::string doc) {
  Key<T> k{std::move(name), "list of shapes", "m", "", "non-empty", std::move(doc)};
  k.read = [field](const Value& v, T& t, Context& ctx) {
    t.*field = read_shape_list(v, ctx.c.dimension);
  };
  k.show_items = [field](const T& t) {
    std::vector<std::string> items;
    for (const Shape& s : t.*field) items.push_back(show_shape(s));
    return items;
  };
  k.section_doc = shape_keys_doc;
  k.list_of_sections = true;
  return k;
}

// --- key makers: nested mappings ----------------------------------------------

// A mapping read into the field `field` of T by the section `sec`.
template <class T, class S>
Key<T> mapping(std::string name, const Section<S>& (*sec)(), S T::*field, std::string doc) {
  Key<T> k{std::move(name), "mapping", "", "see below", "", std::move(doc)};
  k.read = [sec, field](const Value& v, T& t, Context& ctx) {
    read_section(sec(), v, t.*field, ctx);
  };
  k.section_doc = [sec] { return section_doc(sec()); };
  k.section_settings = [sec, field](const T& t, const std::string& key, std::vector<Setting>& out) {
    section_settings(sec(), t.*field, key, out);
  };
  return k;
}

// A mapping that may be absent (none: the feature is off).
template <class T, class S>
Key<T> optional_mapping(std::string name, const Section<S>& (*sec)(), std::optional<S> T::*field,
                        std::string doc) {
  Key<T> k{std::move(name), "mapping", "", "none", "", std::move(doc)};
  k.read = [sec, field](const Value& v, T& t, Context& ctx) {
    S s{};
    read_section(sec(), v, s, ctx);
    t.*field = std::move(s);
  };
  k.section_doc = [sec] { return section_doc(sec()); };
  k.section_settings = [sec, field](const T& t, const std::string& key, std::vector<Setting>& out) {
    if (t.*field) section_settings(sec(), *(t.*field), key, out);
  };
  return k;
}

// A list whose items are mappings of the section `sec` (key[] in the docs).
template <class T, class S>
Key<T> mapping_list(std::string name, const Section<S>& (*sec)(), std::vector<S> T::*field,
                    std::string doc) {
  Key<T> k{std::move(name), "list", "", "none", "", std::move(doc)};
  k.read = [sec, field](const Value& v, T& t, Context& ctx) {
    for (const Value& item : v.list()) {
      S s{};
      read_section(sec(), item, s, ctx);
      (t.*field).push_back(std::move(s));
    }
  };
  k.section_doc = [sec] { return section_doc(sec()); };
  k.list_of_sections = true;
  k.section_settings = [sec, field](const T& t, const std::string& key, std::vector<Setting>& out) {
    for (std::size_t i = 0; i < (t.*field).size(); ++i)
      section_settings(sec(), (t.*field)[i], item_key(key, i), out);
  };
  return k;
}

// --- the sections (keys_*.cpp) -------------------------------------------------

const Section<Case>& top_keys();  // keys_case.cpp
const Section<Resin>& resin_keys();
const Section<Numerics>& numerics_keys();
// resin.viscosity (a number or a law), resin.material, resin.melt_temperature
// and their cross-key checks (keys_viscosity.cpp).
Key<Resin> resin_viscosity_key();
Key<Resin> resin_material_key();
Key<Resin> resin_melt_temperature_key();
void finish_melt(const Map& m, Resin& r, Context& ctx);
// `sphdem check`'s warning when the viscous pressure drop needs more
// compression than 1 % (docs/physics.md "Injection pressure").
void warn_viscous_pressure(Case& c);
const Section<Mold>& mold_keys();  // keys_walls.cpp
const Section<MovingWall>& moving_wall_keys();
const Section<SlidingWall>& sliding_wall_keys();
const Section<FiberSettings>& fiber_keys();  // keys_fibers.cpp
const Section<Output>& output_keys();        // keys_output.cpp
// The output defaults that depend on other keys (name, end_time).
void output_defaults(Output& o, const Case& c);
const Section<ParallelSettings>& parallel_keys();
const Section<CheckpointSettings>& checkpoint_keys();
const Section<InitialFields>& initial_field_keys();  // keys_initial.cpp

// "unknown value 'x' (did you mean 'y'?)" unless `v` is one of `allowed`.
std::string one_of(const Value& v, const std::vector<std::string>& allowed);
// "(x, y)" with D components, for messages.
std::string format_point(const Vec3a& p, int dim);

}  // namespace sphdem::config
