#pragma once
// `--set key=value` overrides, applied to the YAML tree before validation
// so that an overridden value is checked exactly like one from the file.
#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

namespace sphdem::config {

// Applies each "a.b[2].c=value" to `root` (the value is parsed as YAML; a
// null value such as `~` removes the key). Returns the normalised key
// paths that were set, so errors about them can be reported as "--set".
// Throws InputError("--set", 0, key, ...) for a malformed override.
std::set<std::string> apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides);

}  // namespace sphdem::config
