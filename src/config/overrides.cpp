#include "overrides.hpp"

#include <cctype>
#include <cstddef>
#include <string_view>

#include "sphdem/core/errors.hpp"
#include "yaml_reader.hpp"

namespace sphdem::config {

namespace {

// One step of a key path: a map key, or a list index when `key` is empty.
struct Step {
  std::string key;
  std::size_t index = 0;
};

[[noreturn]] void bad(const std::string& key, const std::string& message) {
  throw InputError("--set", 0, key, message);
}

bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
}

// Reads "[N]" at `pos`; returns false if malformed.
bool parse_index(std::string_view path, std::size_t& pos, std::size_t& index) {
  const std::size_t close = path.find(']', pos);
  if (close == std::string_view::npos || close == pos + 1) return false;
  index = 0;
  for (std::size_t i = pos + 1; i < close; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(path[i]))) return false;
    index = index * 10 + static_cast<std::size_t>(path[i] - '0');
  }
  pos = close + 1;
  return true;
}

// "mold.shapes[0].box.min" -> mold, shapes, [0], box, min.
std::vector<Step> parse_path(const std::string& path) {
  std::vector<Step> steps;
  std::size_t pos = 0;
  while (true) {
    const std::size_t start = pos;
    while (pos < path.size() && is_name_char(path[pos])) ++pos;
    if (pos == start) bad(path, "malformed key path (expected e.g. numerics.spacing)");
    steps.push_back({path.substr(start, pos - start), 0});
    while (pos < path.size() && path[pos] == '[') {
      Step s;
      if (!parse_index(path, pos, s.index)) bad(path, "malformed list index in key path");
      steps.push_back(s);
    }
    if (pos == path.size()) return steps;
    if (path[pos] != '.') bad(path, "malformed key path (expected e.g. numerics.spacing)");
    ++pos;
  }
}

std::string join(const std::vector<Step>& steps, std::size_t count) {
  std::string key;
  for (std::size_t i = 0; i < count; ++i)
    key = steps[i].key.empty() ? item_key(key, steps[i].index) : child_key(key, steps[i].key);
  return key;
}

// The child of `node` at step i, created as an empty map when missing so
// that `--set output.every_steps=10` works without an `output:` section;
// created maps are added to `keys`, as they too come from --set.
// "'<key>'<rest>", built by appending: GCC 12 at -O3 reports a false
// -Wrestrict for the same expression written with operator+.
std::string quoted(const std::string& key, const char* rest) {
  std::string msg(1, '\'');
  msg.append(key);
  msg.append(rest);
  return msg;
}

YAML::Node descend(YAML::Node node, const std::vector<Step>& steps, std::size_t i,
                   std::set<std::string>& keys) {
  const Step& s = steps[i];
  if (s.key.empty()) {
    if (!node.IsSequence()) bad(join(steps, i + 1), quoted(join(steps, i), "' is not a list"));
    if (s.index >= node.size()) {
      std::string msg = "index out of range (";
      msg.append(quoted(join(steps, i), "' has "));
      msg.append(std::to_string(node.size()));
      msg.append(" items)");
      bad(join(steps, i + 1), msg);
    }
    return node[s.index];
  }
  if (!node.IsMap() && !node.IsNull())
    bad(join(steps, i + 1), quoted(join(steps, i), "' is not a mapping"));
  YAML::Node child = node[s.key];
  if (!child.IsDefined() || child.IsNull()) {
    child = YAML::Node(YAML::NodeType::Map);
    keys.insert(join(steps, i + 1));
  }
  return child;
}

YAML::Node parse_value(const std::string& key, const std::string& text) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    bad(key, "cannot parse value '" + text + "' as YAML: " + e.msg);
  }
}

void apply_one(YAML::Node& root, const std::string& spec, std::set<std::string>& keys) {
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos) bad(spec, "expected key=value, got '" + spec + "'");
  const std::vector<Step> steps = parse_path(spec.substr(0, eq));
  const std::string key = join(steps, steps.size());
  const YAML::Node value = parse_value(key, spec.substr(eq + 1));
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  YAML::Node node = root;
  // reset() rebinds `node`; plain assignment would overwrite what it refers to.
  for (std::size_t i = 0; i + 1 < steps.size(); ++i) node.reset(descend(node, steps, i, keys));
  const Step& last = steps.back();
  if (last.key.empty()) {
    descend(node, steps, steps.size() - 1, keys) = value;
  } else if (!node.IsMap() && !node.IsNull()) {
    bad(key, "'" + join(steps, steps.size() - 1) + "' is not a mapping");
  } else if (value.IsNull()) {
    node.remove(last.key);
  } else {
    node[last.key] = value;
  }
  keys.insert(key);
}

}  // namespace

std::set<std::string> apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides) {
  std::set<std::string> keys;
  for (const std::string& spec : overrides) apply_one(root, spec, keys);
  return keys;
}

}  // namespace sphdem::config
