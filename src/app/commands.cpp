#include "commands.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <cmath>
#include <exception>
#include <iostream>
#include <optional>

#include "fiber_cost.hpp"
#include "memory_guard.hpp"
#include "output_dir.hpp"
#include "output_interval.hpp"
#include "partition_command.hpp"
#include "scaling_command.hpp"
#include "signals.hpp"
#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/core/fault.hpp"
#include "sphdem/geometry/geometry.hpp"
#include "sphdem/parallel/agreement.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/coupled_window.hpp"
#include "sphdem/solver/dem_run.hpp"
#include "sphdem/solver/run.hpp"
#include "sphdem/solver/solver.hpp"

namespace sphdem::app {

namespace {

struct RunArgs {
  std::string case_file;
  std::string output_dir;
  std::int64_t steps = -1;
  std::vector<std::string> sets;
  bool quiet = false;
  std::string restart;                // checkpoint path or "latest" (docs/checkpoint.md)
  std::int64_t checkpoint_every = 0;  // 0: the case's checkpoint.every_steps
  bool overwrite = false;
  std::string max_memory;  // --max-memory; empty: the node's MemAvailable
  // `check` only: estimate for this many ranks, against this much per rank.
  int estimate_ranks = 0;  // 0: the ranks it runs on
  std::string memory_per_rank;
};

// After a stop request (SIGTERM, SIGUSR1) the run wrote a checkpoint: say
// how to continue. Exit status 0, so a job chain goes on.
// Printed even with -q: job scripts look for this line.
void report_stop(const RunSummary& s, const Comm& comm) {
  if (!s.stopped || !comm.root()) return;
  std::cout << fmt::format(
      "stopped by signal {} at t = {:.6g} s: checkpoint {}; continue with --restart latest\n",
      app::stop_signal(), s.time, s.last_checkpoint);
}

// Every rank reads the case file on its own, then they agree: a rank that
// cannot read it (a file system missing on one node) stops every rank with
// exit status 2, where going on would leave the others waiting for it in
// the first collective (docs/architecture.md, "Errors").
Case load_case_on_every_rank(const Comm& comm, const RunArgs& a) {
  std::optional<Case> c;
  std::optional<std::string> error;
  std::exception_ptr mine;
  try {
    inject_load_fault(comm.rank(), a.case_file.c_str());
    c = load_case(a.case_file, a.sets);
  } catch (const std::exception& e) {
    error = e.what();
    mine = std::current_exception();
  }
  const std::optional<RankFailure> failed = first_failure(comm, error);
  if (!failed) return std::move(*c);
  if (failed->rank == comm.rank()) {
    try {
      std::rethrow_exception(mine);
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(a.case_file, 0, "", e.what());
    }
  }
  throw InputError(a.case_file, 0, "",
                   fmt::format("on rank {}: {}", failed->rank, failed->message));
}

// Measured one-rank resin throughput (docs/performance.md), used only for
// the run-time estimate of `sphdem check`.
constexpr double kParticleStepsPerSecond = 5e6;
// Measured one-rank DEM throughput of inputs/fibers_only.yaml (docs/dem.md).
constexpr double kDemParticleStepsPerSecond = 8e6;

// `sphdem check`: the keys whose values differ from their defaults, from the
// key schema (docs/case-file.md), as the loader understood them.
void print_settings(const Case& c) {
  std::cout << "  keys not at their default (docs/case-file.md):\n";
  for (const Setting& s : case_settings(c))
    if (!s.is_default) std::cout << fmt::format("    {} = {}\n", s.key, s.value);
}

// Remarks that do not stop a run (Case::warnings), once.
void print_warnings(const Case& c, const Comm& comm) {
  if (!comm.root()) return;
  for (const std::string& w : c.warnings) std::cerr << "sphdem: warning: " << w << "\n";
}

// `sphdem check`: the estimate made before anything was built (the memory
// guard, memory_guard.hpp), beside the counts of the built case.
void print_estimate(const CaseSize& s, int ranks) {
  std::cout << fmt::format(
      "  memory: about {} per rank at {} rank(s) (estimated before building, from about {:.3g} "
      "resin, {:.3g} wall and {:.3g} DEM particles; set-up {}, running {}{})\n",
      format_bytes(s.bytes_per_rank()), ranks, s.resin, s.walls, s.dem, format_bytes(s.setup_bytes),
      format_bytes(s.run_bytes), s.setup_bytes >= s.run_bytes ? ": the peak is at set-up" : "");
}

// `sphdem check`: wall layers beyond the kernel's support are not made
// (wall_band, geometry.hpp).
void print_wall_trim(const Case& c) {
  const int made = wall_layers_made(c);
  if (made >= c.mold.wall_layers) return;
  std::cout << fmt::format(
      "  walls: {} of mold.wall_layers {} layers made; wall particles farther than the kernel's "
      "support 2h = {:.3g} spacings from the cavity are in no resin particle's support and are "
      "not made\n",
      made, c.mold.wall_layers, 2.0 * c.numerics.h_over_spacing);
}

// `sphdem check --ranks P`: the estimate for P ranks, nothing built (the
// case may be far too big for this machine).
int print_rank_estimate(const Case& c, const CaseSize& s, int ranks, const Comm& comm) {
  if (!comm.root()) return 0;
  std::cout << fmt::format("case '{}' ({}D) is valid (estimated for {} ranks, not built)\n", c.name,
                           c.dimension, ranks);
  print_estimate(s, ranks);
  return 0;
}

RunOptions run_options(const Case& c, const RunArgs& a) {
  RunOptions opt;
  opt.output_dir = a.output_dir.empty() ? c.output.directory : a.output_dir;
  if (a.steps >= 0) opt.max_steps = a.steps;
  opt.log = a.quiet ? nullptr : &std::cout;
  if (a.checkpoint_every > 0) opt.checkpoint_every = a.checkpoint_every;
  opt.stop_requested = stop_requested;
  return opt;
}

template <int D>
int check_dem_case(const Case& c, const Comm& comm, const CaseSize& size) {
  RunOptions opt;
  opt.write_output = false;
  const DemRun<D> run(c, comm, opt);
  check_output_interval(c, run.dt());
  if (!comm.root()) return 0;
  const double n = static_cast<double>(run.dem().global_count());
  const double steps = std::ceil(c.numerics.end_time / run.dt());
  std::cout << fmt::format(
      "case '{}' ({}D) is valid\n"
      "  particles: {} DEM in {} fibers (fraction {:.2f} %), no resin; {} DEM walls\n"
      "  time step: {:.4g} s, limited by dem (fibers.dt_safety {})\n"
      "  steps to end_time {:.4g} s: about {:.0f}\n"
      "  run time: about {:.0f} s on one core (at {:.1g} particle-steps/s)\n",
      c.name, D, run.dem().global_count(), run.placement().fibers, 100 * run.placement().fraction,
      run.dem().walls().size(), run.dt(), c.fibers->dt_safety, c.numerics.end_time, steps,
      n * steps / kDemParticleStepsPerSecond, kDemParticleStepsPerSecond);
  print_estimate(size, comm.size());
  print_settings(c);
  return 0;
}

// What the run holds, before it starts.
template <int D>
void print_run_banner(const Run<D>& run, const Case& c, const Comm& comm) {
  const FiberModule<D>* fibers = run.fibers();
  if (const ResinModule<D>* resin = run.resin()) {
    std::cout << fmt::format(
        "sphdem {}: case '{}' ({}D), {} resin + {} wall particles, {} rank(s)\n", SPHDEM_VERSION,
        c.name, D, resin->global_fluid_count(), resin->global_wall_count(), comm.size());
    if (fibers) {
      std::cout << fmt::format(
          "  fibers: {} ({} DEM particles, fraction {:.2f} %), DEM step {:.3g} s\n",
          fibers->placement().fibers, fibers->dem().global_count(),
          100 * fibers->placement().fraction, fibers->dem_dt());
    }
    return;
  }
  std::cout << fmt::format(
      "sphdem {}: case '{}' ({}D), {} fibers ({} DEM particles, fraction {:.2f} %), no resin, "
      "{} DEM walls, {} rank(s)\n",
      SPHDEM_VERSION, c.name, D, fibers->placement().fibers, fibers->dem().global_count(),
      100 * fibers->placement().fraction, fibers->dem().walls().size(), comm.size());
}

// Every case, with resin, fibers or both, is one Run (run.hpp).
template <int D>
int run_case(const Case& c, const RunArgs& a, const Comm& comm) {
  const RunOptions opt = run_options(c, a);
  // Bad input leaves the output directory as it was: the interval is
  // checked first (a fibers-only run knows its step once its fibers are
  // placed, which writes nothing).
  const bool resin = !c.fill.empty();
  if (resin) check_output_interval(c, estimated_resin_dt(c));
  std::optional<Run<D>> fibers_only;
  if (!resin) {
    fibers_only.emplace(c, comm, opt);
    check_output_interval(c, fibers_only->fibers()->dem_dt());
  }
  prepare_output_dir(comm, opt.output_dir, !a.restart.empty(), a.overwrite);
  std::optional<Run<D>> with_resin;
  if (resin) with_resin.emplace(c, comm, opt);
  Run<D>& run = resin ? *with_resin : *fibers_only;
  if (!a.restart.empty()) run.restart_from(a.restart);
  if (comm.root() && !a.quiet) print_run_banner(run, c, comm);
  const RunSummary s = run.run();
  report_stop(s, comm);
  if (comm.root() && !a.quiet) {
    std::cout << fmt::format(
        "done: {} steps to t = {:.6g} s in {:.2f} s ({:.3g} particle-steps/s), {} snapshots in "
        "{}\n",
        s.steps, s.time, s.wall_seconds, s.particle_steps_per_second, s.snapshots, opt.output_dir);
  }
  return 0;
}

template <int D>
int check_case(const Case& c, const Comm& comm, const CaseSize& size) {
  RunOptions opt;
  opt.write_output = false;
  Simulation<D> sim(c, comm, opt);
  check_output_interval(c, estimated_resin_dt(c));
  if (!comm.root()) return 0;
  const SphParams sp = make_sph_params(c);
  // A run's speed is bounded by Mach 0.1 (c0 >= 10 |v|max): estimate with it.
  const double v_est = 0.1 * sp.c0;
  const TimeStep ts = choose_time_step(c.numerics, sp, v_est, 0.0);
  const double steps = std::ceil(c.numerics.end_time / ts.dt);
  const double seconds =
      static_cast<double>(sim.global_fluid_count()) * steps / kParticleStepsPerSecond;
  std::cout << fmt::format(
      "case '{}' ({}D) is valid\n"
      "  particles: {} resin, {} wall\n"
      "  spacing {:.4g} m, h {:.4g} m, c0 {:.4g} m/s\n"
      "  time step: {:.4g} s, limited by {} (at |v| = 0.1 c0)\n"
      "  steps to end_time {:.4g} s: about {:.0f}\n"
      "  run time: about {:.0f} s on one core (at {:.1g} particle-steps/s)\n",
      c.name, D, sim.global_fluid_count(), sim.global_wall_count(), c.numerics.spacing, sp.h, sp.c0,
      ts.dt, to_string(ts.limit), c.numerics.end_time, steps, seconds, kParticleStepsPerSecond);
  print_wall_trim(c);
  if (sp.implicit_viscosity) {
    const double dt_v = explicit_viscous_time_step(c.numerics, sp);
    std::cout << fmt::format(
        "  viscosity: implicit (docs/physics.md \"Implicit viscosity\"); the explicit limit "
        "would be {:.3g} s, {:.3g} times smaller, plus the solve's iterations per step\n",
        dt_v, ts.dt / dt_v);
  }
  if (sim.dem()) {
    // Measured on the coupled plate (docs/performance.md): DEM and coupling
    // together cost about as much again as the resin.
    const double sub = std::ceil(ts.dt / sim.dem_dt());
    std::cout << fmt::format(
        "  fibers: {} ({} DEM particles, fraction {:.2f} %), DEM step {:.3g} s: {:.0f} sub-steps "
        "per SPH step\n"
        "  with the fibers and the coupling: about {:.0f} s on one core\n",
        sim.placement().fibers, sim.dem()->global_count(), 100 * sim.placement().fraction,
        sim.dem_dt(), sub, 2.2 * seconds);
    print_coupled_window(coupled_window<D>(c, sim, ts.dt), c, std::cout);
    check_fiber_cost(
        c, fiber_cost(c, ts.dt, sim.dem_dt(), sim.fibers()->bond_dt(), sim.dem()->global_count()),
        std::cout);
  }
  print_estimate(size, comm.size());
  print_settings(c);
  return 0;
}

}  // namespace

int dispatch(int argc, char** argv) {
  const Comm comm;
  CLI::App app{"sphdem: SPH-DEM simulator of injection molding of short-fiber composites"};
  app.set_version_flag("--version", std::string(SPHDEM_VERSION));
  app.require_subcommand(1);

  RunArgs run;
  CLI::App* run_cmd = app.add_subcommand("run", "Run a case (mpirun -n N sphdem run case.yaml)");
  run_cmd->add_option("case", run.case_file, "Case file (YAML), see docs/case-file.md")->required();
  run_cmd->add_option("-o,--output", run.output_dir,
                      "Output directory (default: output.directory)");
  run_cmd->add_option("--steps", run.steps, "Stop when the step counter reaches N");
  run_cmd->add_option("--set", run.sets, "Override a case key: --set numerics.spacing=1e-3")
      ->allow_extra_args(false);
  run_cmd->add_flag("-q,--quiet", run.quiet, "No progress lines");
  CLI::Option* restart_opt = run_cmd->add_option(
      "--restart", run.restart,
      "Continue from a checkpoint: its path, or 'latest' (the newest in the output directory)");
  run_cmd
      ->add_option("--checkpoint-every", run.checkpoint_every,
                   "Write a checkpoint every N steps (overrides checkpoint.every_steps)")
      ->check(CLI::PositiveNumber);
  const std::string memory_help =
      "Memory the ranks on one node may use, e.g. 16G (default: the node's MemAvailable); a "
      "case estimated to need more is refused before it is built";
  run_cmd->add_option("--max-memory", run.max_memory, memory_help);
  run_cmd
      ->add_flag("--overwrite", run.overwrite,
                 "Replace the output of an earlier run in the output directory")
      ->excludes(restart_opt);

  RunArgs check;
  CLI::App* check_cmd =
      app.add_subcommand("check", "Validate a case and print counts, time step and estimates");
  check_cmd->add_option("case", check.case_file, "Case file (YAML)")->required();
  check_cmd->add_option("--set", check.sets, "Override a case key")->allow_extra_args(false);
  check_cmd->add_option("--max-memory", check.max_memory, memory_help);
  check_cmd
      ->add_option("--ranks", check.estimate_ranks,
                   "Estimate the peak memory per rank for this many ranks and stop (nothing is "
                   "built); exit 2 if it does not fit --memory-per-rank")
      ->check(CLI::PositiveNumber);
  check_cmd->add_option("--memory-per-rank", check.memory_per_rank,
                        "Memory one rank may use, e.g. 4G (default: the node's MemAvailable, or "
                        "--max-memory, divided by the ranks on the node)");

  bool markdown = false;
  CLI::App* keys_cmd =
      app.add_subcommand("keys", "List every case-file key with its type, unit, default and doc");
  keys_cmd->add_flag("--markdown", markdown,
                     "Print the case-file reference page instead (docs/case-file.md)");

  PartitionArgs part;
  CLI::App* part_cmd = add_partition_command(app, part);
  ScalingArgs scaling;  // listed here; main runs it before MPI_Init (scaling_command.hpp)
  CLI::App* scaling_cmd = add_scaling_command(app, scaling);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::ostream null_stream(nullptr);  // ranks other than 0 stay silent
    const int code =
        app.exit(e, comm.root() ? std::cout : null_stream, comm.root() ? std::cerr : null_stream);
    return code == 0 ? 0 : 2;
  }

  if (keys_cmd->parsed()) {
    if (comm.root()) std::cout << (markdown ? case_file_markdown() : keys_text());
    return 0;
  }
  if (part_cmd->parsed()) return run_partition_command(part, comm);
  if (scaling_cmd->parsed())
    throw InputError("scaling", 0, "",
                     "give it first on the command line: sphdem scaling CASE ...");
  if (run_cmd->parsed()) install_stop_signals();
  const RunArgs& a = run_cmd->parsed() ? run : check;
  MemoryLimits limits;
  if (!a.max_memory.empty()) limits.node = parse_memory_size(a.max_memory);
  if (!a.memory_per_rank.empty())
    limits.per_rank = parse_memory_size(a.memory_per_rank, "--memory-per-rank");
  if (a.estimate_ranks > 0) limits.ranks = a.estimate_ranks;
  const Case c = load_case_on_every_rank(comm, a);
  print_warnings(c, comm);
  // Before anything is built: a case too big for the node is refused.
  const CaseSize size = check_case_fits(c, comm, limits);
  if (limits.ranks) return print_rank_estimate(c, size, *limits.ranks, comm);
  if (run_cmd->parsed())
    return c.dimension == 2 ? run_case<2>(c, a, comm) : run_case<3>(c, a, comm);
  if (c.fill.empty())  // fibers only (the loader requires one of the two)
    return c.dimension == 2 ? check_dem_case<2>(c, comm, size) : check_dem_case<3>(c, comm, size);
  return c.dimension == 2 ? check_case<2>(c, comm, size) : check_case<3>(c, comm, size);
}

}  // namespace sphdem::app
