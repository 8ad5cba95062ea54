#include "sphdem/core/errors.hpp"

#include <utility>

namespace sphdem {

namespace {

// Length of the valid UTF-8 sequence at s[i] (0 if invalid).
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  std::size_t n = 0;
  if (c >= 0xC2 && c <= 0xDF)
    n = 2;
  else if (c >= 0xE0 && c <= 0xEF)
    n = 3;
  else if (c >= 0xF0 && c <= 0xF4)
    n = 4;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
  return n;
}

}  // namespace

std::string printable(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      // Valid UTF-8 stays, but for the C1 controls (U+0080..U+009F, 0xC2
      // 0x80..0x9F): a terminal may act on them (U+009B starts a sequence).
      const std::size_t n = utf8_length(s, i);
      const bool c1 = n == 2 && c == 0xC2 && static_cast<unsigned char>(s[i + 1]) < 0xA0;
      if (n > 0 && !c1) {
        out.append(s, i, n);
        i += n;
        continue;
      }
    }
    if ((c < 0x20 && c != '\n' && c != '\t') || c == 0x7F || c >= 0x80) {
      static constexpr char kHex[] = "0123456789abcdef";
      out.append("\\x").push_back(kHex[c >> 4]);
      out.push_back(kHex[c & 15]);
    } else {
      out.push_back(static_cast<char>(c));
    }
    ++i;
  }
  return out;
}

namespace {

std::string format_input_error(const std::string& file, int line, const std::string& key,
                               const std::string& what) {
  // Built by appending: GCC 12 at -O3 reports a false -Wrestrict for the
  // same expression written with operator+.
  std::string s = printable(file);
  if (line > 0) s.append(":").append(std::to_string(line));
  s.append(": ");
  // A key path built from junk can be long: keep the message readable.
  constexpr std::size_t kMaxKey = 120;
  const std::string shown_key = key.size() > kMaxKey ? key.substr(0, kMaxKey) + "..." : key;
  if (!key.empty()) s.append("key '").append(printable(shown_key)).append("': ");
  s.append(printable(what));
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
