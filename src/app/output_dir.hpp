#pragma once
// An output directory that holds an earlier run is neither overwritten by
// accident nor mixed with a new run (docs/checkpoint.md): `sphdem run` needs
// --restart to continue that run or --overwrite to replace it.
#include <string>

#include "sphdem/parallel/comm.hpp"

namespace sphdem::app {

// Collective. Throws InputError when `dir` holds sphdem output and neither
// flag is set; with `overwrite`, rank 0 first deletes what sphdem wrote
// there (snapshots, XDMF, checkpoints, case.yaml, timings), nothing else.
void prepare_output_dir(const Comm& comm, const std::string& dir, bool restart, bool overwrite);

}  // namespace sphdem::app
