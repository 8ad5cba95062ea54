#include "sphdem/core/scratch.hpp"

#include <vector>

namespace sphdem {

double* shared_scratch(std::size_t doubles) {
  thread_local std::vector<double> scratch;
  if (doubles > scratch.size()) {
    if (doubles > scratch.capacity()) scratch.reserve(doubles + doubles / 16 + 64);
    scratch.resize(doubles);
  }
  return scratch.data();
}

}  // namespace sphdem
