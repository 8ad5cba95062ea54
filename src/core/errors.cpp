#include "sphdem/core/errors.hpp"

#include <utility>

namespace sphdem {

namespace {
std::string format_input_error(const std::string& file, int line, const std::string& key,
                               const std::string& what) {
  // Built by appending: GCC 12 at -O3 reports a false -Wrestrict for the
  // same expression written with operator+.
  std::string s = file;
  if (line > 0) s.append(":").append(std::to_string(line));
  s.append(": ");
  if (!key.empty()) s.append("key '").append(key).append("': ");
  s.append(what);
  return s;
}
}  // namespace

InputError::InputError(std::string file, int line, std::string key, const std::string& what)
    : std::runtime_error(format_input_error(file, line, key, what)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)) {}

int exit_status_of(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e)) return kExitInput;
  if (dynamic_cast<const SimulationError*>(&e)) return kExitSimulation;
  return kExitOther;
}

}  // namespace sphdem
