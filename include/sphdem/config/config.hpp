#pragma once
// Case files: YAML -> validated Case. Every error names file, line and key
// (InputError), and is raised before anything is written.
#include <memory>
#include <string>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/core/errors.hpp"

namespace sphdem {

// `overrides` are "dotted.key=value" strings from `--set`; the value is
// parsed as YAML (so `--set numerics.spacing=1e-3` or
// `--set periodic=[x]`; list items as `mold.shapes[0].box.max=[1,2]`; a
// null value `~` removes the key) and validated exactly like the file.
// Errors about an overridden key (or anything below it) name file "--set",
// line 0. Non-fatal remarks (a Mach number above 0.1) go to Case::warnings.
// A file that cannot be opened: InputError(path, 0, "", "cannot open case file").
Case load_case(const std::string& path, const std::vector<std::string>& overrides = {});
// `name_for_errors` is the file name that errors report; its stem is the
// default case name.
Case load_case_from_string(const std::string& text, const std::string& name_for_errors,
                           const std::vector<std::string>& overrides = {});

// An InputError about key `key` (dotted, e.g. "numerics.spacing") of a
// loaded case, for checks made after loading (the size estimate): it names
// the key's file and line, or "--set" when an override gave it.
InputError input_error_at(const Case& c, const std::string& key, const std::string& message);

// The case a run actually ran: the file's YAML with every `--set` override
// applied and `name` filled in, as YAML text (comments are lost; a header
// names the source file and the overrides). Loading it gives the same Case
// (and checkpoint identity) as loading the file with the overrides. Written
// to <output>/case.yaml and into every snapshot and checkpoint.
std::string effective_case_yaml(const Case& c);

// Where `key` (dotted, "output.every_time") of a loaded case was set: its
// case file and line, or "--set" (line 0) when an override set it or a
// mapping above it; line 0 when the file does not say (a default).
struct KeyLocation {
  std::string file;
  int line = 0;
};
KeyLocation key_location(const Case& c, const std::string& key);

// --- the key schema (src/config/schema.hpp, docs/case-file.md) ---------------

struct KeysDoc;

// One key as `sphdem keys` and docs/case-file.md show it.
struct KeyDoc {
  std::string name;                  // within its mapping
  std::string type, unit;            // unit in SI, "" when dimensionless
  std::string default_text;          // "required", a value, or how it is derived
  std::string rule;                  // the validator as text ("> 0", "in (0, 1]")
  std::string doc;                   // one line
  bool identity = false;             // part of the checkpoint identity
  std::shared_ptr<KeysDoc> section;  // the keys inside a mapping (or its items)
  bool list = false;                 // a list of such mappings: name[].key
};

// The keys of one mapping, with the prose around its table.
struct KeysDoc {
  std::string intro, notes;
  std::vector<KeyDoc> keys;
};

// The schema from the top level down.
KeysDoc case_keys();
// Every key's dotted path, list items as [] ("moving_walls[].region.box.min").
std::vector<std::string> case_key_paths();
// `sphdem keys`: one line per key with type, unit, default and doc.
std::string keys_text();
// `sphdem keys --markdown`: the whole of docs/case-file.md.
std::string case_file_markdown();

// A key of a loaded case and its value as text (list items as key[k]).
struct Setting {
  std::string key, value;
  bool identity = false;    // part of the checkpoint identity
  bool is_default = false;  // equal to the key's default
};
// Every shown key of `c`, in schema order.
std::vector<Setting> case_settings(const Case& c);

}  // namespace sphdem
