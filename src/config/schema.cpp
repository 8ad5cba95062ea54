// The schema's shared parts: validators, value formats, and the walks that
// `sphdem keys`, `sphdem check` and the checkpoint identity make over it.
#include "schema.hpp"

#include <algorithm>
#include <cstddef>

namespace sphdem::config {

double Rule::read(const Value& v) const {
  switch (kind) {
    case Kind::Positive:
      return positive(v);
    case Kind::NonNegative:
      return non_negative(v);
    case Kind::Range:
      return in_interval(v, range);
    case Kind::Any:
      break;
  }
  return v.number();
}

std::string Rule::text() const {
  switch (kind) {
    case Kind::Positive:
      return "> 0";
    case Kind::NonNegative:
      return ">= 0";
    case Kind::Range:
      return fmt::format("in {}{}, {}{}", range.lo_open ? '(' : '[', range.lo, range.hi,
                         range.hi_open ? ')' : ']');
    case Kind::Any:
      break;
  }
  return "";
}

std::string show_number(double v) {
  return fmt::format("{}", v);
}

std::string show_vector(const Vec3a& v) {
  return fmt::format("[{}, {}, {}]", show_number(v[0]), show_number(v[1]), show_number(v[2]));
}

std::string show_shape(const Shape& s) {
  if (s.type == Shape::Type::Box) return "box " + show_vector(s.lo) + " " + show_vector(s.hi);
  std::string out = "polygon";
  for (const auto& p : s.vertices)
    out += fmt::format(" [{}, {}]", show_number(p[0]), show_number(p[1]));
  return out;
}

std::string show_table(const VelocityTable& t) {
  std::string out;
  for (std::size_t k = 0; k < t.time.size(); ++k)
    out +=
        fmt::format("{}{}: {}", k ? ", " : "", show_number(t.time[k]), show_vector(t.velocity[k]));
  return out;
}

std::string show_bool(bool b) {
  return b ? "true" : "false";
}

std::string one_of(const Value& v, const std::vector<std::string>& allowed) {
  const std::string s = v.string();
  if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
    v.fail("unknown value " + v.describe() + suggestion(s, allowed));
  }
  return s;
}

std::string format_point(const Vec3a& p, int dim) {
  std::string s = "(";
  for (int d = 0; d < dim; ++d) s += fmt::format("{}{:.6g}", d ? ", " : "", p[d]);
  return s + ")";
}

void warn_if_celsius(const Value& v, double kelvin, Context& ctx) {
  if (!(kelvin < kCelsiusSuspect)) return;
  const int line = v.line();
  const std::string file = v.source().overridden(v.key()) ? "--set" : v.source().file();
  ctx.c.warnings.push_back(fmt::format(
      "{}{}: key '{}': {} K looks like degrees Celsius (temperatures are in kelvin, below {} K "
      "a warning: {} degC is {} K)",
      file, line > 0 ? ":" + std::to_string(line) : "", v.key(), v.text(),
      show_number(kCelsiusSuspect), v.text(), show_number(kelvin + 273.15)));
}

namespace {

void collect_paths(const KeysDoc& doc, const std::string& prefix, std::vector<std::string>& out) {
  for (const KeyDoc& k : doc.keys) {
    const std::string path = child_key(prefix, k.name);
    out.push_back(path);
    if (k.section) collect_paths(*k.section, k.list ? path + "[]" : path, out);
  }
}

struct Row {
  std::string name, type, unit, default_text, doc;
};

void collect_rows(const KeysDoc& doc, const std::string& prefix, std::vector<Row>& out) {
  for (const KeyDoc& k : doc.keys) {
    const std::string path = child_key(prefix, k.name);
    std::string text = k.rule;
    if (!k.doc.empty()) text += (text.empty() ? "" : "; ") + k.doc;
    if (k.identity) text += " [identity]";
    out.push_back({path, k.type, k.unit.empty() ? "-" : k.unit, k.default_text, text});
    if (k.section) collect_rows(*k.section, k.list ? path + "[]" : path, out);
  }
}

}  // namespace

}  // namespace sphdem::config

namespace sphdem {

KeysDoc case_keys() {
  return config::section_doc(config::top_keys());
}

std::vector<std::string> case_key_paths() {
  std::vector<std::string> paths;
  config::collect_paths(case_keys(), "", paths);
  return paths;
}

std::string keys_text() {
  std::vector<config::Row> rows;
  config::collect_rows(case_keys(), "", rows);
  std::size_t w_name = 3, w_type = 4, w_unit = 4, w_default = 7;
  for (const config::Row& r : rows) {
    w_name = std::max(w_name, r.name.size());
    w_type = std::max(w_type, r.type.size());
    w_unit = std::max(w_unit, r.unit.size());
    w_default = std::max(w_default, std::min<std::size_t>(r.default_text.size(), 24));
  }
  std::string out = fmt::format("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {}\n", "key", w_name, "type",
                                w_type, "unit", w_unit, "default", w_default,
                                "constraints; doc ([identity]: a restart must "
                                "not change it, docs/checkpoint.md)");
  for (const config::Row& r : rows) {
    out += fmt::format("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {}\n", r.name, w_name, r.type, w_type,
                       r.unit, w_unit, r.default_text, w_default, r.doc);
  }
  return out;
}

std::vector<Setting> case_settings(const Case& c) {
  std::vector<Setting> out;
  config::section_settings(config::top_keys(), c, "", out);
  return out;
}

}  // namespace sphdem
