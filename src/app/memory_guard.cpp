#include "memory_guard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/agreement.hpp"

namespace sphdem::app {

double parse_memory_size(const std::string& text, const std::string& option) {
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
    throw InputError(option, 0, "",
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

int local_ranks(const Comm& comm, int ranks) {
  const int here = comm.ranks_on_node();
  if (ranks == comm.size()) return here;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(std::max(here, cores), 1, std::max(ranks, 1));
}

CaseSize check_case_fits(const Case& c, const Comm& comm, const MemoryLimits& limits) {
  const int ranks = limits.ranks.value_or(comm.size());
  const CaseSize size = estimate_case_size(c, ranks);
  const int sharing = local_ranks(comm, ranks);
  std::optional<double> per_rank = limits.per_rank;
  std::string source = "of --memory-per-rank";
  if (!per_rank) {
    const std::optional<double> node = limits.node ? limits.node : available_memory();
    if (node) per_rank = *node / sharing;
    source = fmt::format(
        "{} divided by {} rank(s) on the node",
        limits.node ? "of --max-memory" : "available (MemAvailable in /proc/meminfo)", sharing);
  }
  const double need = size.bytes_per_rank();
  std::optional<std::string> error;
  // NaN and inf (a spacing of 1e-300) never fit.
  if (per_rank && !(need <= *per_rank)) {
    error = fmt::format(
        "the case needs about {} per rank at {} rank(s) ({} for the {} rank(s) on this node; "
        "about {:.3g} resin, {:.3g} wall and {:.3g} DEM particles; {}), more than the {} per "
        "rank {}: coarsen it or use more nodes",
        format_bytes(need), ranks, format_bytes(need * sharing), sharing, size.resin, size.walls,
        size.dem,
        size.setup_bytes >= size.run_bytes ? "the peak is at set-up" : "the peak is while running",
        format_bytes(*per_rank), source);
  }
  // Nodes differ in free memory: the lowest failing rank speaks for all.
  if (const std::optional<RankFailure> failed = first_failure(comm, error)) {
    const std::string where = failed->rank == 0 ? "" : fmt::format("on rank {}: ", failed->rank);
    throw input_error_at(c, size.dominant_key, where + failed->message);
  }
  return size;
}

}  // namespace sphdem::app
