#pragma once
// Case files: YAML -> validated Case. Every error names file, line and key
// (InputError), and is raised before anything is written.
#include <string>
#include <vector>

#include "sphdem/case.hpp"

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

}  // namespace sphdem
