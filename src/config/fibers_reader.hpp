#pragma once
// The `fibers:` section of a case file (docs/case-file.md), private to config/.
#include "sphdem/case.hpp"
#include "yaml_reader.hpp"

namespace sphdem::config {

// Reads and range-checks the section; the region must be a box inside the
// mold (checked by the caller with the other regions).
FiberSettings read_fibers(const Value& v, int dim);

}  // namespace sphdem::config
