#include "sphdem/errors.hpp"

#include <utility>

namespace sphdem {

namespace {
std::string format_input_error(const std::string& file, int line, const std::string& key,
                               const std::string& what) {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line);
  s += ": ";
  if (!key.empty()) s += "key '" + key + "': ";
  return s + what;
}
}  // namespace

InputError::InputError(std::string file, int line, std::string key, const std::string& what)
    : std::runtime_error(format_input_error(file, line, key, what)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)) {}

}  // namespace sphdem
