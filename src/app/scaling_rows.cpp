#include "scaling_rows.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <ostream>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace sphdem::app {

namespace {

std::int64_t to_int(const std::string& s) {
  return std::stoll(s);
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

}  // namespace

// The lines of print_run_banner and run_case (src/app/commands.cpp).
RunCounts parse_run_log(const std::string& text) {
  static const std::regex resin(R"(\), (\d+) resin \+ (\d+) wall particles)");
  static const std::regex fibers(R"((?:fibers: |, )(\d+) (?:fibers )?\((\d+) DEM particles)");
  static const std::regex done(R"((^|\n)done: (\d+) steps)");
  RunCounts c;
  std::smatch m;
  const bool has_resin = std::regex_search(text, m, resin);
  if (has_resin) {
    c.resin = to_int(m[1]);
    c.wall = to_int(m[2]);
  }
  const bool has_fibers = std::regex_search(text, m, fibers);
  if (has_fibers) {
    c.fibers = to_int(m[1]);
    c.dem = to_int(m[2]);
  }
  if (!has_resin && !has_fibers) throw std::runtime_error("no 'sphdem run' banner in the log");
  if (!std::regex_search(text, m, done)) throw std::runtime_error("no 'done:' line in the log");
  c.steps = to_int(m[2]);
  return c;
}

PhaseStats read_timings(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  if (!in) throw std::runtime_error(fmt::format("cannot read {}", csv.string()));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_csv_line(line);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end())
      throw std::runtime_error(fmt::format("{}: no column '{}'", csv.string(), name));
    return static_cast<std::size_t>(it - header.begin());
  };
  std::array<std::size_t, kPhaseCount> cols{};
  for (int p = 0; p < kPhaseCount; ++p) cols[p] = column(to_string(Phase(p)));
  const std::size_t total = column("total");
  PhaseStats s;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> v = split_csv_line(line);
    if (v.size() != header.size())
      throw std::runtime_error(fmt::format("{}: a row has {} fields, the header {}", csv.string(),
                                           v.size(), header.size()));
    for (int p = 0; p < kPhaseCount; ++p) {
      const double t = std::stod(v[cols[p]]);
      s.max[p] = std::max(s.max[p], t);
      s.mean[p] += t;
    }
    s.total_max = std::max(s.total_max, std::stod(v[total]));
    ++s.ranks;
  }
  if (s.ranks == 0) throw std::runtime_error(fmt::format("{}: no rows", csv.string()));
  for (double& t : s.mean) t /= s.ranks;
  return s;
}

double ScalingRow::particle_steps_per_second() const {
  const double t = wall_seconds();
  return t > 0 ? static_cast<double>(counts.all()) * static_cast<double>(counts.steps) / t : 0;
}

std::vector<std::string> scaling_csv_columns() {
  std::vector<std::string> c = {
      "mode",      "ranks",     "spacing",         "resin", "wall",   "fibers",
      "dem",       "particles", "moving_per_rank", "steps", "wall_s", "particle_steps_per_s",
      "efficiency"};
  for (int p = 0; p < kPhaseCount; ++p) {
    c.push_back(fmt::format("{}_max", to_string(Phase(p))));
    c.push_back(fmt::format("{}_mean", to_string(Phase(p))));
  }
  c.push_back("run");
  c.push_back("repeats");
  return c;
}

void write_scaling_csv(std::ostream& out, const std::vector<ScalingRow>& rows,
                       const ScalingRow& base, bool weak) {
  const std::vector<std::string> cols = scaling_csv_columns();
  for (std::size_t i = 0; i < cols.size(); ++i) out << (i ? "," : "") << cols[i];
  out << '\n';
  const double base_rate = base.particle_steps_per_second() / base.ranks;
  for (const ScalingRow& r : rows) {
    const double rate = r.particle_steps_per_second();
    out << fmt::format("{},{},{:.9g},{},{},{},{},{},{:.1f},{},{:.6f},{:.6g},{:.4f}",
                       weak ? "weak" : "strong", r.ranks, r.spacing, r.counts.resin, r.counts.wall,
                       r.counts.fibers, r.counts.dem, r.counts.all(),
                       static_cast<double>(r.counts.moving()) / r.ranks, r.counts.steps,
                       r.wall_seconds(), rate, base_rate > 0 ? rate / r.ranks / base_rate : 0.0);
    for (int p = 0; p < kPhaseCount; ++p)
      out << fmt::format(",{:.6f},{:.6f}", r.phases.max[p], r.phases.mean[p]);
    out << fmt::format(",{},{}\n", r.run, r.repeats);
  }
}

}  // namespace sphdem::app
