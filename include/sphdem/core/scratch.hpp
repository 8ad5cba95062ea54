#pragma once
// One scratch buffer per thread for work that is never live at once, so
// its pages are paid once (docs/performance.md, "16-bit neighbour lists"):
// the pair loop's records (filled at every evaluation of the rates, read
// only within it) and the cell grid's binning and sort at a rebuild of the
// lists, when no records are in use. Kept across steps: no fresh pages at
// every use.
#include <cstddef>

namespace sphdem {

// Room for at least `doubles` doubles (8-byte aligned). The contents are
// what the last user left as long as the buffer does not grow.
double* shared_scratch(std::size_t doubles);

}  // namespace sphdem
