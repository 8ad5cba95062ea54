#include "yaml_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <system_error>

#include "sphdem/core/errors.hpp"

namespace sphdem::config {

namespace {

// yaml-cpp tags plain scalars "?" and quoted ones "!": a quoted "900" is a
// string to YAML, and we keep it so rather than guess.
bool is_plain_scalar(const YAML::Node& n) {
  return n.IsScalar() && n.Tag() != "!";
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// A scalar as echoed in a message: long ones (junk, a pasted blob) cut short.
std::string quoted(const std::string& s) {
  constexpr std::size_t kMaxShown = 60;
  if (s.size() <= kMaxShown) return "'" + s + "'";
  return fmt::format("'{}...' ({} characters)", s.substr(0, kMaxShown), s.size());
}

int line_of(const YAML::Node& n) {
  return n.Mark().line >= 0 ? n.Mark().line + 1 : 0;
}

}  // namespace

bool Source::overridden(const std::string& key) const {
  return std::any_of(overridden_.begin(), overridden_.end(), [&](const std::string& p) {
    if (key.size() < p.size() || key.compare(0, p.size(), p) != 0) return false;
    return key.size() == p.size() || key[p.size()] == '.' || key[p.size()] == '[';
  });
}

void Source::fail(int line, const std::string& key, const std::string& message) const {
  if (overridden(key)) throw InputError("--set", 0, key, message);
  throw InputError(file_, line, key, message);
}

int Value::line() const {
  return src_->overridden(key_) ? 0 : line_;
}

std::string Value::describe() const {
  switch (node_.Type()) {
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
    case YAML::NodeType::Scalar:
      return is_plain_scalar(node_) ? quoted(node_.Scalar())
                                    : "the quoted string " + quoted(node_.Scalar());
    default:
      return "nothing";
  }
}

double Value::number() const {
  if (is_plain_scalar(node_)) {
    std::string_view s = node_.Scalar();
    if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);  // from_chars rejects '+'
    double x = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
    if (ec == std::errc() && end == s.data() + s.size()) {
      if (!std::isfinite(x)) fail("expected a finite number, got " + describe());
      return x;
    }
  }
  fail("expected a number, got " + describe());
}

int Value::integer() const {
  if (is_plain_scalar(node_)) {
    std::string_view s = node_.Scalar();
    if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);
    int i = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), i);
    if (ec == std::errc() && end == s.data() + s.size()) return i;
  }
  fail("expected an integer, got " + describe());
}

bool Value::boolean() const {
  bool b = false;
  if (is_plain_scalar(node_) && YAML::convert<bool>::decode(node_, b)) return b;
  fail("expected true or false, got " + describe());
}

std::string Value::string() const {
  if (!node_.IsScalar() || node_.Scalar().empty()) fail("expected a string, got " + describe());
  return node_.Scalar();
}

Map Value::map(std::initializer_list<std::string_view> allowed) const {
  return Map(*this, allowed);
}

std::vector<Value> Value::list() const {
  if (!node_.IsSequence()) fail("expected a list, got " + describe());
  std::vector<Value> items;
  for (std::size_t i = 0; i < node_.size(); ++i) {
    const YAML::Node item = node_[i];
    const int line = line_of(item) > 0 ? line_of(item) : line_;
    items.emplace_back(*src_, item, item_key(key_, i), line);
  }
  return items;
}

Vec3a Value::vector(int dim) const {
  if (!node_.IsSequence())
    fail(fmt::format("expected a list of {} numbers, got {}", dim, describe()));
  if (node_.size() != static_cast<std::size_t>(dim))
    fail(fmt::format("expected {} numbers (dimension {}), got {}", dim, dim, node_.size()));
  Vec3a v{};
  const std::vector<Value> items = list();
  for (int d = 0; d < dim; ++d) v[d] = items[d].number();
  return v;
}

Map Value::map(std::vector<std::string> allowed) const {
  return Map(*this, std::move(allowed));
}

Map::Map(const Value& self, std::initializer_list<std::string_view> allowed)
    : Map(self, std::vector<std::string>(allowed.begin(), allowed.end())) {}

Map::Map(const Value& self, std::vector<std::string> allowed)
    : self_(self), allowed_(std::move(allowed)) {
  if (!self_.node().IsMap()) self_.fail("expected a mapping, got " + self_.describe());
  std::set<std::string> seen;
  for (auto it = self_.node().begin(); it != self_.node().end(); ++it) {
    const std::string& name = it->first.Scalar();
    const std::string key = child_key(self_.key(), name);
    const int line = line_of(it->first);
    if (!it->first.IsScalar() || name.empty())
      self_.source().fail(line, self_.key(), "keys must be plain names");
    if (std::find(allowed_.begin(), allowed_.end(), name) == allowed_.end())
      self_.source().fail(line, key, "unknown key" + suggestion(name, allowed_));
    if (!seen.insert(name).second) self_.source().fail(line, key, "duplicate key");
  }
}

bool Map::has(std::string_view key) const {
  return get(key).has_value();
}

std::optional<Value> Map::get(std::string_view key) const {
  for (auto it = self_.node().begin(); it != self_.node().end(); ++it) {
    if (it->first.Scalar() != key) continue;
    // The key's line, not the value's: a null value's mark is on the next
    // line, and a block value starts below its key.
    return Value(self_.source(), it->second, child_key(self_.key(), key), line_of(it->first));
  }
  return std::nullopt;
}

Value Map::require(std::string_view key, std::string_view hint) const {
  std::optional<Value> v = get(key);
  if (!v) {
    self_.source().fail(self_.line(), child_key(self_.key(), key),
                        "missing required key" + std::string(hint));
  }
  return *v;
}

double positive(const Value& v) {
  const double x = v.number();
  if (!(x > 0)) v.fail("must be positive, got " + v.text());
  return x;
}

double non_negative(const Value& v) {
  const double x = v.number();
  if (!(x >= 0)) v.fail("must be zero or positive, got " + v.text());
  return x;
}

double in_interval(const Value& v, Interval range) {
  const double x = v.number();
  const bool above = range.lo_open ? x > range.lo : x >= range.lo;
  const bool below = range.hi_open ? x < range.hi : x <= range.hi;
  if (!above || !below) {
    v.fail(fmt::format("must be in {}{}, {}{}, got {}", range.lo_open ? '(' : '[', range.lo,
                       range.hi, range.hi_open ? ')' : ']', v.text()));
  }
  return x;
}

int integer_at_least(const Value& v, int min) {
  const int i = v.integer();
  if (i < min) v.fail(fmt::format("must be at least {}, got {}", min, v.text()));
  return i;
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  // About one typo per three letters; never a complete rewrite ('z' is not
  // a misspelt 'x').
  const std::size_t budget = std::clamp<std::size_t>((word.size() + 2) / 3, 1, 3);
  std::string best;
  std::size_t best_distance = budget + 1;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(lower(word), lower(c));
    if (d >= word.size()) continue;
    if (d < best_distance) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
  const std::string best = closest_match(word, candidates);
  if (!best.empty()) return " (did you mean '" + best + "'?)";
  std::string all;
  for (const std::string& c : candidates) all += (all.empty() ? "" : ", ") + c;
  return " (expected one of: " + all + ")";
}

std::string child_key(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

std::string item_key(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

}  // namespace sphdem::config
