#include "memory_guard.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/agreement.hpp"

namespace sphdem::app {

double parse_memory_size(const std::string& text) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = text.substr(used);
  if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
  if (!unit.empty() && (unit.back() == 'i')) unit.pop_back();
  double scale = 1;
  if (unit.size() == 1) {
    const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(unit[0])));
    const std::string units = "KMGT";
    const std::size_t k = units.find(u);
    if (k != std::string::npos) {
      scale = std::pow(1024.0, static_cast<double>(k + 1));
      unit.clear();
    }
  }
  if (used == 0 || !unit.empty() || !(v > 0) || !std::isfinite(v))
    throw InputError("--max-memory", 0, "",
                     "expected a size such as 16G, 512M or a number of bytes, got '" + text + "'");
  return v * scale;
}

std::optional<double> available_memory() {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string name;
    double kib = 0;
    if (fields >> name >> kib && name == "MemAvailable:") return kib * 1024.0;
  }
  return std::nullopt;
}

CaseSize check_case_fits(const Case& c, const Comm& comm, std::optional<double> max_memory) {
  const CaseSize size = estimate_case_size(c, comm.size());
  const int sharing = comm.ranks_on_node();
  const std::optional<double> limit = max_memory ? max_memory : available_memory();
  const double need = size.bytes_per_rank() * sharing;
  std::optional<std::string> error;
  // NaN and inf (a spacing of 1e-300) never fit.
  if (limit && !(need <= *limit)) {
    error = fmt::format(
        "the case needs about {} on this node ({} rank(s) of {}; about {:.3g} resin, {:.3g} wall "
        "and {:.3g} DEM particles), more than the {} {}: coarsen it or use more nodes",
        format_bytes(need), sharing, format_bytes(size.bytes_per_rank()), size.resin, size.walls,
        size.dem, format_bytes(*limit),
        max_memory ? "of --max-memory" : "available (MemAvailable in /proc/meminfo)");
  }
  // Nodes differ in free memory: the lowest failing rank speaks for all.
  if (const std::optional<RankFailure> failed = first_failure(comm, error)) {
    const std::string where = failed->rank == 0 ? "" : fmt::format("on rank {}: ", failed->rank);
    throw input_error_at(c, size.dominant_key, where + failed->message);
  }
  return size;
}

}  // namespace sphdem::app
