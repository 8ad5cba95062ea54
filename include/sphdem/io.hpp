#pragma once
// Snapshot output: one HDF5 file per snapshot, written collectively through
// the parallel HDF5 API (also at one rank), and an XDMF temporal collection
// that points into them so ParaView opens the series with no plugin.
//
// Layout of <dir>/<case>_<step:08d>.h5:
//   /              attributes: time [s], step, dimension, case name, sphdem version
//   /<set>/        one group per particle set ("fluid", "wall"), attribute count
//   /<set>/id      int64 [N]        global ids
//   /<set>/position double [N][3]   (z = 0 in 2D, so ParaView sees XYZ)
//   /<set>/<field> double [N] or [N][3] (vectors padded to 3), attribute "units"
// Rows are ordered by global id within each set, whatever the rank count.
#include <cstdint>
#include <string>
#include <vector>

#include "sphdem/comm.hpp"

namespace sphdem {

struct FieldView {
  std::string name;   // dataset name, e.g. "velocity"
  std::string units;  // e.g. "m/s"
  int components = 1;  // 1 (scalar) or D (vector, padded to 3 in the file)
  const double* data = nullptr;  // n_local * components values, row-major
};

struct ParticleSetView {
  std::string name;          // "fluid", "wall", ...
  std::size_t n_local = 0;   // this rank's owned particles
  const std::int64_t* id = nullptr;  // global ids; within a set they form a dense
                                     // range [min, min + N) over all ranks
  int dimension = 2;
  const double* position = nullptr;  // n_local * dimension
  std::vector<FieldView> fields;
};

class SnapshotWriter {
 public:
  // Creates `directory` if needed. `xdmf_name` is the XDMF file's name
  // inside it (e.g. "plate.xdmf").
  SnapshotWriter(const Comm& comm, std::string directory, std::string case_name);

  // Collective. Writes the HDF5 file to a temporary name, closes it and
  // renames it (complete or absent), then rewrites the XDMF (also atomically)
  // with this snapshot appended. Returns the HDF5 file path.
  std::string write(std::int64_t step, double time, const std::vector<ParticleSetView>& sets);

  const std::string& xdmf_path() const { return xdmf_path_; }

 private:
  struct Entry {
    std::int64_t step;
    double time;
    std::string file;  // relative to the directory
    std::vector<std::pair<std::string, std::int64_t>> sets;  // name, count
    std::vector<std::vector<std::pair<std::string, int>>> fields;  // per set: name, components
  };
  void write_xdmf() const;

  const Comm& comm_;
  std::string directory_;
  std::string case_name_;
  std::string xdmf_path_;
  std::vector<Entry> entries_;
};

}  // namespace sphdem
