#include "sphdem/core/fault.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "sphdem/core/errors.hpp"

namespace sphdem {

namespace {

std::atomic<std::int64_t> g_step{-1};

constexpr const char* kVariable = "SPHDEM_INJECT_FAULT";

std::optional<InjectedFault> parse(const std::string& spec) {
  const auto bad = [&] {
    return InputError(kVariable, 0, "",
                      "'" + spec +
                          "': expected RANK:STEP:KIND with KIND one of input, "
                          "simulation, runtime, snapshot_write (hdf5), checkpoint_write, "
                          "restart_read, enospc");
  };
  const std::size_t a = spec.find(':');
  const std::size_t b = a == std::string::npos ? a : spec.find(':', a + 1);
  if (b == std::string::npos) throw bad();
  InjectedFault f;
  try {
    std::size_t used = 0;
    f.rank = std::stoi(spec.substr(0, a), &used);
    if (used != a) throw bad();
    f.step = std::stoll(spec.substr(a + 1, b - a - 1), &used);
    if (used != b - a - 1) throw bad();
  } catch (const std::logic_error&) {  // stoi: not a number, out of range
    throw bad();
  }
  const std::string kind = spec.substr(b + 1);
  if (kind == "input")
    f.kind = FaultKind::Input;
  else if (kind == "simulation")
    f.kind = FaultKind::Simulation;
  else if (kind == "runtime")
    f.kind = FaultKind::Runtime;
  else if (kind == "hdf5" || kind == "snapshot_write")
    f.kind = FaultKind::SnapshotWrite;
  else if (kind == "checkpoint_write")
    f.kind = FaultKind::CheckpointWrite;
  else if (kind == "restart_read")
    f.kind = FaultKind::RestartRead;
  else if (kind == "enospc")
    f.kind = FaultKind::Enospc;
  else
    throw bad();
  return f;
}

}  // namespace

void set_current_step(std::int64_t step) {
  g_step = step;
}

std::int64_t current_step() {
  return g_step;
}

std::optional<InjectedFault> injected_fault() {
  const char* spec = std::getenv(kVariable);
  if (spec == nullptr || *spec == '\0') return std::nullopt;
  static const std::optional<InjectedFault> fault = parse(spec);
  return fault;
}

bool fault_due(FaultKind kind, int rank, std::int64_t step) {
  const std::optional<InjectedFault> f = injected_fault();
  if (!f || f->kind != kind || f->rank != rank) return false;
  if (kind == FaultKind::Input || kind == FaultKind::RestartRead) return true;
  return kind == FaultKind::Enospc ? step >= f->step : step == f->step;
}

void inject_load_fault(int rank, const char* case_file) {
  if (fault_due(FaultKind::Input, rank, 0))
    throw InputError(case_file, 0, "", fmt::format("fault injected ({})", kVariable));
}

void inject_io_fault(FaultKind kind, int rank, std::int64_t step, const std::string& path) {
  const bool write = kind != FaultKind::RestartRead;
  if (write && fault_due(FaultKind::Enospc, rank, step))
    throw std::runtime_error(fmt::format(
        "sphdem: HDF5 write dataset failed for '{}': No space left on device (injected, {})", path,
        kVariable));
  if (fault_due(kind, rank, step))
    throw std::runtime_error(fmt::format("sphdem: HDF5 {} dataset failed for '{}' (injected, {})",
                                         write ? "write" : "read", path, kVariable));
}

void inject_step_fault(int rank, std::int64_t step) {
  if (fault_due(FaultKind::Simulation, rank, step))
    throw SimulationError(fmt::format("fault injected after step {} ({})", step, kVariable));
  if (fault_due(FaultKind::Runtime, rank, step))
    throw std::runtime_error(fmt::format("fault injected after step {} ({})", step, kVariable));
}

}  // namespace sphdem
