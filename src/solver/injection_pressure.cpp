#include "injection_pressure.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace sphdem {

namespace {
constexpr const char* kHeader = "time_s,step,wall,speed_m_per_s,pressure_pa";

// The rows of an existing series written before `step`.
std::string rows_before(const std::filesystem::path& path, std::int64_t step) {
  std::ifstream in(path);
  std::string line, kept;
  while (std::getline(in, line)) {
    if (line.empty() || line == kHeader) continue;
    std::istringstream row(line);
    std::string time, row_step;
    if (!std::getline(row, time, ',') || !std::getline(row, row_step, ',')) continue;
    if (std::stoll(row_step) < step) kept += line + "\n";
  }
  return kept;
}
}  // namespace

void append_injection_pressure(const std::string& dir, const std::string& case_name,
                               std::int64_t step, double time, const std::vector<WallMotion>& walls,
                               bool first_of_run) {
  bool any = false;
  for (const WallMotion& w : walls) any = any || w.moves;
  if (!any) return;
  const std::filesystem::path path =
      std::filesystem::path(dir) / (case_name + "_injection_pressure.csv");
  if (first_of_run) {
    const std::string kept = step > 0 ? rows_before(path, step) : std::string();
    std::ofstream(path, std::ios::trunc) << kHeader << "\n" << kept;
  }
  std::ofstream out(path, std::ios::app);
  for (const WallMotion& w : walls) {
    if (!w.moves) continue;
    const auto v = w.velocity(time);
    out << fmt::format("{:.9g},{},{},{:.6g},{:.6g}\n", time, step, w.name,
                       std::hypot(v[0], v[1], v[2]), w.face_pressure);
  }
}

}  // namespace sphdem
