#include "partition_command.hpp"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <iostream>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/partition_report.hpp"

namespace sphdem::app {

namespace {

InputError option_error(const std::string& option, const std::string& what) {
  return InputError(option, 0, "", what);
}

// The case with numerics.spacing divided by `scale`, as one more --set so
// that it is validated like any other value (a periodic length must stay a
// multiple of the spacing).
Case load_scaled_case(const PartitionArgs& a) {
  if (!(a.scale > 0))
    throw option_error("--scale", fmt::format("must be positive, got {}", a.scale));
  const Case base = load_case(a.case_file, a.sets);
  if (a.scale == 1.0) return base;
  std::vector<std::string> sets = a.sets;
  sets.push_back(fmt::format("numerics.spacing={:.17g}", base.numerics.spacing / a.scale));
  return load_case(a.case_file, sets);
}

}  // namespace

std::vector<int> parse_rank_list(const std::string& text) {
  std::vector<int> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, end - start);
    int value = 0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
    if (item.empty() || ec != std::errc() || ptr != item.data() + item.size() || value < 1) {
      throw option_error("--ranks", fmt::format("'{}' is not a positive integer rank count "
                                                "(expected a list like 64,256,1024)",
                                                item));
    }
    out.push_back(value);
    start = end + 1;
  }
  return out;
}

CLI::App* add_partition_command(CLI::App& app, PartitionArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "partition",
      "Partition a case for many rank counts without running it: imbalance, ghosts, halo, "
      "neighbor ranks (docs/scaling.md)");
  cmd->add_option("case", a.case_file, "Case file (YAML)")->required();
  cmd->add_option("--ranks", a.ranks, "Rank counts, comma-separated: --ranks 64,256,1024,4096")
      ->required();
  cmd->add_option("--set", a.sets, "Override a case key: --set numerics.spacing=1e-4")
      ->allow_extra_args(false);
  cmd->add_option("--scale", a.scale,
                  "Refine the case: numerics.spacing / N (N^D times the particles; default 1)");
  cmd->add_option("--fiber-substeps", a.fiber_substeps,
                  "Weigh the fibers as a coupled run's re-partitions do, at N DEM sub-steps per "
                  "resin step (default 0: a run's first partition, fibers not weighted)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--csv", a.csv, "Also write the table as CSV to this file");
  cmd->footer(
      "Builds the initial particles serially (run it on one rank), the cell grid and METIS call\n"
      "of a run, and partitions once per rank count with the weights of a run's first\n"
      "partition: 10 per resin particle, 3 per wall particle with resin in its top-level cell\n"
      "or the next, 1 per other wall particle. A coupled run places its fibers after that\n"
      "partition (a restart partitions so too) and weighs them only when it re-partitions\n"
      "(parallel.balance_every, parallel.imbalance_threshold): 5 per fiber particle and DEM\n"
      "sub-step of the last resin step. --fiber-substeps N places the fibers as a run does and\n"
      "weighs them so, at N sub-steps (the sub-steps per SPH step `sphdem check` prints).\n"
      "Columns: particles per rank (resin + wall); imbalance = max/mean - 1 of the work;\n"
      "ghosts/owned in total and the largest per rank (ghosts: particles in cells of another\n"
      "rank's 3^D stencil, an upper bound of the run's halo); halo kB received per step by a\n"
      "rank (the bytes of the field registry's State group per ghost + WallState group per wall\n"
      "ghost, printed above the table); neighbor ranks exchanged with; METIS = serial partition\n"
      "time; top cells = the non-empty top-level cells a run partitions (blocks of edge^D\n"
      "cells, at most max(64 x ranks, parallel.min_top_cells)); map MB = the block map and\n"
      "work vector every rank holds; rank 0 MB = its graph, summed work and parts\n"
      "(docs/parallel.md, \"Which weights, when\"; docs/scaling.md).\n"
      "A rank count above the number of non-empty top-level cells is reported, not partitioned.");
  return cmd;
}

int run_partition_command(const PartitionArgs& a, const Comm& comm) {
  const std::vector<int> ranks = parse_rank_list(a.ranks);
  const Case c = load_scaled_case(a);
  if (!comm.root()) return 0;  // serial work: the other ranks just wait
  const PartitionReport r = partition_report(c, ranks, a.fiber_substeps);
  std::cout << format_partition_table(r) << std::flush;
  if (!a.csv.empty()) {
    std::ofstream out(a.csv);
    if (!out) throw option_error("--csv", fmt::format("cannot write '{}'", a.csv));
    write_partition_csv(out, r);
  }
  return 0;
}

}  // namespace sphdem::app
