#pragma once
// Typed, located access to a parsed YAML tree (private to config/).
//
// Every value carries its dotted key path and its line, so any check made
// on it can raise an InputError that points at the case file. Maps are
// opened with the list of keys they accept: unknown keys (with a
// "did you mean" suggestion) and duplicate keys are reported at once,
// before any missing key, because a typo is the likeliest cause of both.
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sphdem/config/case.hpp"

namespace sphdem::config {

// Where errors are reported: the case file, except for key paths whose
// value came from `--set`, which are reported as file "--set", line 0.
class Source {
 public:
  Source(std::string file, std::set<std::string> overridden)
      : file_(std::move(file)), overridden_(std::move(overridden)) {}

  const std::string& file() const { return file_; }
  bool overridden(const std::string& key) const;
  [[noreturn]] void fail(int line, const std::string& key, const std::string& message) const;

 private:
  std::string file_;
  std::set<std::string> overridden_;
};

class Map;

// One node of the tree, with its key path and 1-based line.
class Value {
 public:
  Value(const Source& src, YAML::Node node, std::string key, int line)
      : src_(&src), node_(std::move(node)), key_(std::move(key)), line_(line) {}

  const YAML::Node& node() const { return node_; }
  const std::string& key() const { return key_; }
  int line() const;  // 0 when the value came from --set
  const Source& source() const { return *src_; }
  [[noreturn]] void fail(const std::string& message) const { src_->fail(line_, key_, message); }

  // "'abc'", "a list", "a mapping", "nothing": for "expected X, got Y".
  std::string describe() const;
  // The scalar as written (for "must be positive, got -3").
  const std::string& text() const { return node_.Scalar(); }

  double number() const;  // finite floating-point number
  int integer() const;
  bool boolean() const;
  std::string string() const;
  Map map(std::initializer_list<std::string_view> allowed) const;
  Map map(std::vector<std::string> allowed) const;
  std::vector<Value> list() const;
  // Exactly `dim` numbers; unused components of the result are 0.
  Vec3a vector(int dim) const;

 private:
  const Source* src_;
  YAML::Node node_;
  std::string key_;
  int line_;
};

// A mapping whose keys were checked against an allowed list.
class Map {
 public:
  Map(const Value& self, std::initializer_list<std::string_view> allowed);
  Map(const Value& self, std::vector<std::string> allowed);

  const Value& self() const { return self_; }
  bool has(std::string_view key) const;
  std::optional<Value> get(std::string_view key) const;
  // Raises "missing required key" + hint at this map's line when absent.
  Value require(std::string_view key, std::string_view hint = "") const;

 private:
  Value self_;
  std::vector<std::string> allowed_;
};

// Range-checked numbers: "must be positive, got -3" and the like.
struct Interval {
  double lo, hi;
  bool lo_open, hi_open;
};
double positive(const Value& v);
double non_negative(const Value& v);
double in_interval(const Value& v, Interval range);
int integer_at_least(const Value& v, int min);

// The closest candidate within a small edit distance, or "" if none.
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);
// " (did you mean 'x'?)" or " (expected one of: a, b, c)".
std::string suggestion(std::string_view word, const std::vector<std::string>& candidates);

// Key paths: "a" + "b" -> "a.b", "a" + [2] -> "a[2]".
std::string child_key(const std::string& parent, std::string_view key);
std::string item_key(const std::string& parent, std::size_t index);

}  // namespace sphdem::config
