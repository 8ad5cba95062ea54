#pragma once
// `sphdem scaling case.yaml --ranks 1,2,4 --steps N [--weak]`: strong or
// weak scaling study of any case, each rank count run through a launcher
// (mpiexec, srun), one CSV row per rank count with where the time went
// (docs/scaling.md, "Scaling studies of any case").
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace sphdem::app {

struct ScalingArgs {
  std::string case_file;
  std::string ranks;  // comma-separated, increasing
  std::int64_t steps = 0;
  bool weak = false;
  int repeat = 1;
  std::string output_dir = "scaling";
  std::string csv;  // default <output_dir>/scaling.csv
  std::string launcher = "mpiexec -n {n}";
  int slots = 0;         // 0: SLURM_NTASKS, the PBS node file's lines, else this machine's cores
  double memory_gb = 0;  // 0: this machine's available memory
  std::vector<std::string> sets;
  bool collect = false;  // only build the CSV from runs already in output_dir
  bool dry_run = false;  // check and print the run commands, run nothing
};

// Registers the sub-command and its options on `app`.
CLI::App* add_scaling_command(CLI::App& app, ScalingArgs& args);

// `sphdem scaling ...`, called by main before MPI_Init: the study launches
// its runs with mpiexec/srun, which an MPI process (an Open MPI singleton)
// cannot do. Returns the exit status (2 for bad input, before any run).
int scaling_main(int argc, char** argv);

}  // namespace sphdem::app
