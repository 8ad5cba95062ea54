#include "front_events_output.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace sphdem {

namespace {
constexpr const char* kHeader = "time_s,kind,x_m,y_m,z_m,id,size";

// The rows of an existing list at or before `time`.
std::string rows_until(const std::filesystem::path& path, double time) {
  std::ifstream in(path);
  std::string line, kept;
  while (std::getline(in, line)) {
    if (line.empty() || line == kHeader) continue;
    std::istringstream row(line);
    std::string t;
    if (!std::getline(row, t, ',')) continue;
    if (std::stod(t) <= time) kept += line + "\n";
  }
  return kept;
}
}  // namespace

void append_front_events(const std::string& dir, const std::string& case_name, double time,
                         const std::vector<FrontEvent>& events, bool first_of_run) {
  const std::filesystem::path path = std::filesystem::path(dir) / (case_name + "_front_events.csv");
  if (first_of_run) {
    const std::string kept = time > 0 ? rows_until(path, time) : std::string();
    std::ofstream(path, std::ios::trunc) << kHeader << "\n" << kept;
  }
  std::ofstream out(path, std::ios::app);
  for (const FrontEvent& e : events) {
    out << fmt::format("{:.9g},{},{:.9g},{:.9g},{:.9g},{},{:.6g}\n", e.time,
                       e.kind == FrontEvent::Kind::WeldLine ? "weld_line" : "trapped_air", e.x[0],
                       e.x[1], e.x[2], e.id, e.size);
  }
}

}  // namespace sphdem
