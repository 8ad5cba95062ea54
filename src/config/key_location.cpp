// key_location and input_error_at (config.hpp): where a key of a loaded case
// was set, found again in the case file's text, for errors found after
// loading that must still name file, line and key.
#include <yaml-cpp/yaml.h>

#include <exception>
#include <string>

#include "overrides.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "yaml_reader.hpp"

namespace sphdem {

namespace {

// The 1-based line of the dotted key `key` (plain mapping keys only) in
// `text`, 0 when it is not there.
int key_line(const std::string& text, const std::string& key) {
  try {
    YAML::Node node = YAML::Load(text);
    std::size_t start = 0;
    int line = 0;
    while (start <= key.size()) {
      const std::size_t dot = key.find('.', start);
      const std::string part = key.substr(start, dot == std::string::npos ? dot : dot - start);
      if (!node.IsMap()) return 0;
      YAML::Node next;
      bool found = false;  // a default Node is a defined null: test by flag
      for (auto it = node.begin(); it != node.end(); ++it) {
        if (it->first.IsScalar() && it->first.Scalar() == part) {
          line = it->first.Mark().line + 1;
          next = it->second;
          found = true;
        }
      }
      if (!found) return 0;
      node = next;
      if (dot == std::string::npos) return line;
      start = dot + 1;
    }
  } catch (const YAML::Exception&) {
  }
  return 0;
}

}  // namespace

KeyLocation key_location(const Case& c, const std::string& key) {
  try {
    YAML::Node tree = YAML::Load(c.source_text);
    const config::Source src(c.source_file, config::apply_overrides(tree, c.overrides));
    if (src.overridden(key)) return {"--set", 0};
  } catch (const std::exception&) {
    // The case loaded, so this does not happen; the file's line is still right.
  }
  return {c.source_file, key_line(c.source_text, key)};
}

InputError input_error_at(const Case& c, const std::string& key, const std::string& message) {
  const KeyLocation where = key_location(c, key);
  return InputError(where.file, where.line, key, message);
}

}  // namespace sphdem
