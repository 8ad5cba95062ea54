#pragma once
// `sphdem partition case.yaml --ranks 64,256,...`: the decomposition at rank
// counts this machine cannot run (docs/scaling.md).
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "sphdem/parallel/comm.hpp"

namespace sphdem::app {

struct PartitionArgs {
  std::string case_file;
  std::string ranks;  // comma-separated, parsed by parse_rank_list
  std::vector<std::string> sets;
  double scale = 1.0;
  std::int64_t fiber_substeps = 0;  // > 0: weigh the fibers as a re-partition does
  std::string csv;
};

// Registers the sub-command and its options on `app`.
CLI::App* add_partition_command(CLI::App& app, PartitionArgs& args);

// "64,256" -> {64, 256}; anything but positive integers is an InputError
// naming --ranks.
std::vector<int> parse_rank_list(const std::string& text);

// Loads the case (refined by --scale), reports on rank 0; returns the exit
// status.
int run_partition_command(const PartitionArgs& args, const Comm& comm);

}  // namespace sphdem::app
