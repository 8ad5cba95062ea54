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

// A row per rank: the phases, the total, then the per-step columns
// (StepTimes::Summary) and the imbalance, which rank 0 fills in.
constexpr int kStepColumns = 9;  // busy, steps, mean, p10, p50, p90, max, lag, imbalance
constexpr int kColumns = kPhaseCount + 1 + kStepColumns;
constexpr int kBusy = kPhaseCount + 1;
constexpr int kImbalance = kColumns - 1;
constexpr std::array<const char*, kStepColumns> kStepNames = {"busy",     "steps",    "step_mean",
                                                              "step_p10", "step_p50", "step_p90",
                                                              "step_max", "step_lag", "imbalance"};

double cell(const std::vector<double>& rows, int r, int c) {
  return rows[r * kColumns + c];
}

std::string phase_table(const std::vector<double>& rows, int ranks) {
  std::string s = fmt::format("{:>6}", "rank");
  for (int p = 0; p < kPhaseCount; ++p) s += fmt::format(" {:>10}", to_string(Phase(p)));
  s += fmt::format(" {:>10}\n", "total [s]");
  for (int r = 0; r < ranks; ++r) {
    s += fmt::format("{:>6}", r);
    for (int c = 0; c <= kPhaseCount; ++c) s += fmt::format(" {:>10.3f}", cell(rows, r, c));
    s += "\n";
  }
  return s;
}

// Per step in milliseconds, the sums in seconds; then what the lag says.
std::string step_table(const std::vector<double>& rows, int ranks) {
  std::string s =
      fmt::format("{:>6} {:>9} {:>10} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10}\n", "rank",
                  "steps", "busy [s]", "mean", "p10", "p50", "p90", "max", "lag [s]", "imbal. [s]");
  int worst = 0;
  for (int r = 0; r < ranks; ++r) {
    s += fmt::format("{:>6} {:>9.0f} {:>10.3f}", r, cell(rows, r, kBusy + 1), cell(rows, r, kBusy));
    for (int c = kBusy + 2; c <= kBusy + 6; ++c)
      s += fmt::format(" {:>9.3f}", 1e3 * cell(rows, r, c));
    s += fmt::format(" {:>10.3f} {:>10.3f}\n", cell(rows, r, kBusy + 7), cell(rows, r, kImbalance));
    if (cell(rows, r, kBusy + 7) > cell(rows, worst, kBusy + 7)) worst = r;
  }
  if (ranks > 1) {
    const double lag = cell(rows, worst, kBusy + 7), imbalance = cell(rows, worst, kImbalance);
    s += fmt::format(
        "waiting for the step's slowest rank: up to {:.3f} s (rank {}), of which {:.3f} s a "
        "steady imbalance and {:.3f} s step-to-step changes of speed (docs/parallel.md, "
        "\"Per-step times\")\n",
        lag, worst, std::min(imbalance, lag), std::max(0.0, lag - imbalance));
  }
  return s;
}

std::vector<std::string> column_names() {
  std::vector<std::string> names;
  for (int p = 0; p < kPhaseCount; ++p) names.emplace_back(to_string(Phase(p)));
  names.emplace_back("total");
  for (const char* n : kStepNames) names.emplace_back(n);
  return names;
}

void write_csv(const std::filesystem::path& file, const std::vector<double>& rows, int ranks) {
  std::ofstream out(file);
  out << "rank";
  for (const std::string& n : column_names()) out << ',' << n;
  out << '\n';
  for (int r = 0; r < ranks; ++r) {
    out << r;
    for (int c = 0; c < kColumns; ++c)
      out << (c == kBusy + 1 ? fmt::format(",{:.0f}", cell(rows, r, c))
                             : fmt::format(",{:.6f}", cell(rows, r, c)));
    out << '\n';
  }
}

void write_json(const std::filesystem::path& file, const std::vector<double>& rows, int ranks) {
  const std::vector<std::string> names = column_names();
  std::ofstream out(file);
  out << "{\n  \"units\": \"s\",\n  \"ranks\": [\n";
  for (int r = 0; r < ranks; ++r) {
    out << "    {\"rank\": " << r;
    for (int c = 0; c < kColumns; ++c)
      out << (c == kBusy + 1 ? fmt::format(", \"{}\": {:.0f}", names[c], cell(rows, r, c))
                             : fmt::format(", \"{}\": {:.6f}", names[c], cell(rows, r, c)));
    out << "}" << (r + 1 < ranks ? "," : "") << "\n";
  }
  out << "  ]\n}\n";
}

}  // namespace

std::string report_timings(const Comm& comm, const PhaseTimers& timers, double total,
                           const StepTimes::Summary& steps, std::ostream* log,
                           const std::string& directory) {
  const std::array<double, kPhaseCount> mine = timers.split(total);
  std::array<double, kColumns> row{};
  std::copy(mine.begin(), mine.end(), row.begin());
  row[kPhaseCount] = total;
  const std::array<double, kStepColumns - 1> per_step = {
      steps.busy, static_cast<double>(steps.steps),
      steps.mean, steps.p10,
      steps.p50,  steps.p90,
      steps.max,  steps.lag};
  std::copy(per_step.begin(), per_step.end(), row.begin() + kBusy);
  std::vector<double> rows(comm.root() ? static_cast<std::size_t>(comm.size() * kColumns) : 0);
  MPI_Gather(row.data(), kColumns, MPI_DOUBLE, rows.data(), kColumns, MPI_DOUBLE, 0, comm.raw());
  if (!comm.root()) return {};
  // The busiest rank sets the pace of the totals: what each other rank
  // would wait if the work stayed where it is.
  double busiest = 0;
  for (int r = 0; r < comm.size(); ++r) busiest = std::max(busiest, cell(rows, r, kBusy));
  for (int r = 0; r < comm.size(); ++r)
    rows[r * kColumns + kImbalance] = busiest - cell(rows, r, kBusy);
  const std::string text = phase_table(rows, comm.size());
  const std::string per_step_text = step_table(rows, comm.size());
  if (log)
    *log << "time per rank [s]:\n"
         << text << "busy time per step [ms] and waiting for the slowest rank [s]:\n"
         << per_step_text << std::flush;
  if (!directory.empty()) {
    write_csv(std::filesystem::path(directory) / "timings.csv", rows, comm.size());
    write_json(std::filesystem::path(directory) / "timings.json", rows, comm.size());
  }
  return text + per_step_text;
}

}  // namespace sphdem
