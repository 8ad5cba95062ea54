// Case files: YAML text (+ `--set` overrides) -> validated Case, by walking
// the key schema (schema.hpp); and back: the effective case as YAML.
#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "overrides.hpp"
#include "schema.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"

namespace sphdem {

namespace {

// A case file is one YAML document: a second one (after `---`) would be
// ignored silently, so it is an error.
YAML::Node parse_yaml(const std::string& text, const std::string& file) {
  std::vector<YAML::Node> docs;
  try {
    docs = YAML::LoadAll(text);
  } catch (const YAML::Exception& e) {
    throw InputError(file, e.mark.line >= 0 ? e.mark.line + 1 : 0, "",
                     "YAML syntax error: " + e.msg);
  }
  if (docs.size() > 1) {
    const int line = docs[1].Mark().line >= 0 ? docs[1].Mark().line + 1 : 0;
    throw InputError(file, line, "",
                     "a second YAML document (after '---'): a case file holds one document");
  }
  return docs.empty() ? YAML::Node() : docs.front();
}

// Case files are small text files: anything else (a directory, a device
// such as /dev/zero, a huge file) is refused before it is read.
constexpr std::uintmax_t kMaxCaseFileBytes = 16u << 20;

std::string read_case_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw InputError(path, 0, "", "cannot open case file (no such file)");
  if (fs::is_directory(st)) throw InputError(path, 0, "", "is a directory, not a case file");
  if (!fs::is_regular_file(st))
    throw InputError(path, 0, "", "not a regular file (a device, pipe or socket), not a case file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxCaseFileBytes) {
    throw InputError(path, 0, "",
                     fmt::format("the file is {} bytes; a case file is at most {} MiB", size,
                                 kMaxCaseFileBytes >> 20));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open case file");
  std::string text(kMaxCaseFileBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxCaseFileBytes)  // grew while we looked
    throw InputError(path, 0, "",
                     fmt::format("a case file is at most {} MiB", kMaxCaseFileBytes >> 20));
  return text;
}

// yaml-cpp's emitter drops the quotes of a quoted scalar ('900' would come
// back as a number), so the tree is emitted node by node.
void emit(YAML::Emitter& out, const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map:
      if (n.Style() == YAML::EmitterStyle::Flow) out << YAML::Flow;
      out << YAML::BeginMap;
      for (auto it = n.begin(); it != n.end(); ++it) {
        out << YAML::Key;
        emit(out, it->first);
        out << YAML::Value;
        emit(out, it->second);
      }
      out << YAML::EndMap;
      break;
    case YAML::NodeType::Sequence:
      if (n.Style() == YAML::EmitterStyle::Flow) out << YAML::Flow;
      out << YAML::BeginSeq;
      for (const YAML::Node& item : n) emit(out, item);
      out << YAML::EndSeq;
      break;
    case YAML::NodeType::Scalar:
      if (n.Tag() == "!") out << YAML::DoubleQuoted;
      out << n.Scalar();
      break;
    default:
      out << YAML::Null;
  }
}

std::string one_line(std::string s) {
  for (char& ch : s)
    if (ch == '\n' || ch == '\r') ch = ' ';
  return s;
}

}  // namespace

Case load_case_from_string(const std::string& text, const std::string& name_for_errors,
                           const std::vector<std::string>& overrides) {
  YAML::Node root = parse_yaml(text, name_for_errors);
  if (root.IsNull() && overrides.empty())
    throw InputError(name_for_errors, 1, "", "the case file is empty");
  const config::Source src(name_for_errors, config::apply_overrides(root, overrides));
  const int root_line = root.Mark().line >= 0 ? root.Mark().line + 1 : 1;
  Case c;
  config::Context ctx{c, {}};
  try {
    config::read_section(config::top_keys(), config::Value(src, root, "", root_line), c, ctx);
  } catch (const YAML::Exception& e) {
    // The reader checks node types before use, so this is a safety net that
    // keeps "bad input -> InputError" true even for a case it did not foresee.
    throw InputError(name_for_errors, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", e.what());
  }
  c.source_file = name_for_errors;
  c.source_text = text;
  c.overrides = overrides;
  return c;
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  return load_case_from_string(read_case_file(path), path, overrides);
}

std::string effective_case_yaml(const Case& c) {
  YAML::Node root = parse_yaml(c.source_text, c.source_file);
  config::apply_overrides(root, c.overrides);
  // The default name is the file's stem: written elsewhere, it must be explicit.
  const YAML::Node& given = root;  // const: looking up "name" must not add it
  YAML::Node out(YAML::NodeType::Map);
  out["name"] = given["name"] ? given["name"] : YAML::Node(c.name);
  for (auto it = root.begin(); it != root.end(); ++it)
    if (it->first.Scalar() != "name") out[it->first] = it->second;
  YAML::Emitter e;
  e << YAML::Comment("The case sphdem " SPHDEM_VERSION " ran: " + one_line(c.source_file) +
                     (c.overrides.empty() ? "" : " with overrides applied"));
  for (const std::string& o : c.overrides)
    e << YAML::Newline << YAML::Comment("--set " + one_line(o));
  e << YAML::Newline;
  emit(e, out);
  return std::string(e.c_str()) + "\n";
}

}  // namespace sphdem
