#pragma once
// Case files: YAML -> validated Case. Every error names file, line and key
// (InputError), and is raised before anything is written.
#include <string>
#include <vector>

#include "sphdem/case.hpp"

namespace sphdem {

// `overrides` are "dotted.key=value" strings from `--set`; the value is
// parsed as YAML (so `--set numerics.spacing=1e-3` or
// `--set periodic=[x]`) and validated exactly like the file.
Case load_case(const std::string& path, const std::vector<std::string>& overrides = {});
Case load_case_from_string(const std::string& text, const std::string& name_for_errors,
                           const std::vector<std::string>& overrides = {});

}  // namespace sphdem
