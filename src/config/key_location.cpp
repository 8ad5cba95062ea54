// Where a key of a loaded case was set (config.hpp): for errors found after
// loading, which must still name file, line and key.
#include <yaml-cpp/yaml.h>

#include <sstream>
#include <utility>

#include "sphdem/config/config.hpp"

namespace sphdem {

KeyLocation key_location(const Case& c, const std::string& key) {
  // An override of the key or of a mapping above it set the value.
  for (const std::string& o : c.overrides) {
    const std::string set = o.substr(0, o.find('='));
    if (key == set || key.rfind(set + ".", 0) == 0) return {"--set", 0};
  }
  KeyLocation where{c.source_file, 0};
  try {
    YAML::Node node = YAML::Load(c.source_text);
    std::istringstream parts(key);
    for (std::string part; std::getline(parts, part, '.');) {
      if (!node.IsMap()) return where;
      const YAML::Node child = std::as_const(node)[part];  // const: no insertion
      if (!child.IsDefined()) return where;
      node.reset(child);  // rebinds (operator= would assign into the tree)
    }
    if (node.Mark().line >= 0) where.line = node.Mark().line + 1;
  } catch (const YAML::Exception&) {
    // The file loaded before, so this does not happen; the line stays unknown.
  }
  return where;
}

}  // namespace sphdem
