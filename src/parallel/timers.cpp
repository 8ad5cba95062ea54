#include "sphdem/parallel/timers.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <ostream>
#include <vector>

namespace sphdem {

const char* to_string(Phase p) {
  switch (p) {
    case Phase::Compute:
      return "compute";
    case Phase::Halo:
      return "halo";
    case Phase::Migration:
      return "migration";
    case Phase::Rebalance:
      return "rebalance";
    case Phase::Io:
      return "io";
    case Phase::Wait:
      return "wait";
    case Phase::Dem:
      return "dem";
    case Phase::Coupling:
      return "coupling";
  }
  return "?";
}

std::array<double, kPhaseCount> PhaseTimers::split(double total) const {
  std::array<double, kPhaseCount> out = seconds_;
  double others = 0;
  for (int p = 1; p < kPhaseCount; ++p) others += out[static_cast<std::size_t>(p)];
  out[0] = std::max(0.0, total - others);
  return out;
}

namespace {

constexpr int kColumns = kPhaseCount + 1;  // the phases, then the total

std::string table(const std::vector<double>& rows, int ranks) {
  std::string s = fmt::format("{:>6}", "rank");
  for (int p = 0; p < kPhaseCount; ++p) s += fmt::format(" {:>10}", to_string(Phase(p)));
  s += fmt::format(" {:>10}\n", "total [s]");
  for (int r = 0; r < ranks; ++r) {
    s += fmt::format("{:>6}", r);
    for (int c = 0; c < kColumns; ++c) s += fmt::format(" {:>10.3f}", rows[r * kColumns + c]);
    s += "\n";
  }
  return s;
}

void write_csv(const std::filesystem::path& file, const std::vector<double>& rows, int ranks) {
  std::ofstream out(file);
  out << "rank";
  for (int p = 0; p < kPhaseCount; ++p) out << ',' << to_string(Phase(p));
  out << ",total\n";
  for (int r = 0; r < ranks; ++r) {
    out << r;
    for (int c = 0; c < kColumns; ++c) out << fmt::format(",{:.6f}", rows[r * kColumns + c]);
    out << '\n';
  }
}

void write_json(const std::filesystem::path& file, const std::vector<double>& rows, int ranks) {
  std::ofstream out(file);
  out << "{\n  \"units\": \"s\",\n  \"ranks\": [\n";
  for (int r = 0; r < ranks; ++r) {
    out << "    {\"rank\": " << r;
    for (int p = 0; p < kPhaseCount; ++p)
      out << fmt::format(", \"{}\": {:.6f}", to_string(Phase(p)), rows[r * kColumns + p]);
    out << fmt::format(", \"total\": {:.6f}}}{}\n", rows[r * kColumns + kPhaseCount],
                       r + 1 < ranks ? "," : "");
  }
  out << "  ]\n}\n";
}

}  // namespace

std::string report_timings(const Comm& comm, const PhaseTimers& timers, double total,
                           std::ostream* log, const std::string& directory) {
  const std::array<double, kPhaseCount> mine = timers.split(total);
  std::array<double, kColumns> row{};
  std::copy(mine.begin(), mine.end(), row.begin());
  row[kPhaseCount] = total;
  std::vector<double> rows(comm.root() ? static_cast<std::size_t>(comm.size() * kColumns) : 0);
  MPI_Gather(row.data(), kColumns, MPI_DOUBLE, rows.data(), kColumns, MPI_DOUBLE, 0, comm.raw());
  if (!comm.root()) return {};
  const std::string text = table(rows, comm.size());
  if (log) *log << "time per rank [s]:\n" << text << std::flush;
  if (!directory.empty()) {
    write_csv(std::filesystem::path(directory) / "timings.csv", rows, comm.size());
    write_json(std::filesystem::path(directory) / "timings.json", rows, comm.size());
  }
  return text;
}

}  // namespace sphdem
