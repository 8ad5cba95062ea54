#include "scaling_rows.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <ostream>
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

// The lines of print_run_banner and run_case (src/app/commands.cpp). Parsed
// by hand: std::regex trips GCC 12's -Wmaybe-uninitialized in the sanitize
// build.
namespace {

bool is_digit(char ch) {
  return ch >= '0' && ch <= '9';
}

// The number that ends just before `end` in `text`, or -1.
std::int64_t number_before(const std::string& text, std::size_t end) {
  std::size_t begin = end;
  while (begin > 0 && is_digit(text[begin - 1])) --begin;
  return begin == end ? -1 : to_int(text.substr(begin, end - begin));
}

// The number that starts at `begin` in `text`, or -1.
std::int64_t number_at(const std::string& text, std::size_t begin) {
  std::size_t end = begin;
  while (end < text.size() && is_digit(text[end])) ++end;
  return begin == end ? -1 : to_int(text.substr(begin, end - begin));
}

// "..., R resin + W wall particles": R and W.
bool find_resin(const std::string& text, RunCounts& c) {
  const std::string mid = " resin + ";
  for (std::size_t at = text.find(mid); at != std::string::npos; at = text.find(mid, at + 1)) {
    const std::int64_t resin = number_before(text, at);
    const std::int64_t wall = number_at(text, at + mid.size());
    if (resin < 0 || wall < 0) continue;
    if (text.compare(at + mid.size() + std::to_string(wall).size(), 15, " wall particles") != 0)
      continue;
    c.resin = resin;
    c.wall = wall;
    return true;
  }
  return false;
}

// "N fibers (M DEM particles" or "N (M DEM particles": N and M.
bool find_fibers(const std::string& text, RunCounts& c) {
  const std::string tail = " DEM particles";
  for (std::size_t at = text.find(tail); at != std::string::npos; at = text.find(tail, at + 1)) {
    const std::int64_t dem = number_before(text, at);
    if (dem < 0) continue;
    std::size_t open = at - std::to_string(dem).size();
    if (open < 2 || text[open - 1] != '(' || text[open - 2] != ' ') continue;
    std::size_t end = open - 2;
    const std::string word = " fibers";
    if (end >= word.size() && text.compare(end - word.size(), word.size(), word) == 0)
      end -= word.size();
    const std::int64_t fibers = number_before(text, end);
    if (fibers < 0) continue;
    c.fibers = fibers;
    c.dem = dem;
    return true;
  }
  return false;
}

// A line "done: S steps ...": S.
bool find_done(const std::string& text, RunCounts& c) {
  const std::string head = "done: ";
  for (std::size_t at = text.find(head); at != std::string::npos; at = text.find(head, at + 1)) {
    if (at != 0 && text[at - 1] != '\n') continue;
    const std::int64_t steps = number_at(text, at + head.size());
    if (steps < 0) continue;
    if (text.compare(at + head.size() + std::to_string(steps).size(), 6, " steps") != 0) continue;
    c.steps = steps;
    return true;
  }
  return false;
}

}  // namespace

RunCounts parse_run_log(const std::string& text) {
  RunCounts c;
  const bool has_resin = find_resin(text, c);
  const bool has_fibers = find_fibers(text, c);
  if (!has_resin && !has_fibers) throw std::runtime_error("no 'sphdem run' banner in the log");
  if (!find_done(text, c)) throw std::runtime_error("no 'done:' line in the log");
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
  // The per-step columns came later: read when present.
  auto optional_column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? header.size() : static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t lag = optional_column("step_lag"), imbalance = optional_column("imbalance");
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
    if (lag < v.size()) s.step_lag_max = std::max(s.step_lag_max, std::stod(v[lag]));
    if (imbalance < v.size()) s.imbalance_max = std::max(s.imbalance_max, std::stod(v[imbalance]));
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
  c.push_back("step_lag_max");
  c.push_back("imbalance_max");
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
    out << fmt::format(",{:.6f},{:.6f}", r.phases.step_lag_max, r.phases.imbalance_max);
    out << fmt::format(",{},{}\n", r.run, r.repeats);
  }
}

}  // namespace sphdem::app
