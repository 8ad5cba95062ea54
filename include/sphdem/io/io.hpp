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
//   /<set>/lines/  optional two-node line cells between the set's particles
//                  (bonds of fibers), attribute count M:
//   /<set>/lines/id        int64 [M]     cell ids, rows in cell-id order
//   /<set>/lines/nodes     int64 [M][2]  the ends' rows in the set (id - id_min)
//   /<set>/lines/<field>   double [M] or [M][3]
// Rows are ordered by global id within each set, whatever the rank count.
// <dir>/<case>.xdmf lists every snapshot this writer wrote: one Temporal
// collection per set, named after it, with a Polyvertex grid of the same name
// for each snapshot where the set has N > 0 particles, then one collection
// "<set>_lines" of Polyline grids over the same points for a set with M > 0
// lines. It opens in ParaView with XDMFReader (blocks named fluid, wall, dem,
// dem_lines at every step) or Xdmf3ReaderS (docs/tools.md, "ParaView").
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sphdem/parallel/comm.hpp"

namespace sphdem {

struct FieldView {
  std::string name;              // dataset name, e.g. "velocity"
  std::string units;             // e.g. "m/s"
  int components = 1;            // 1 (scalar) or D (vector, padded to 3 in the file)
  const double* data = nullptr;  // n_local * components values, row-major
};

// Two-node line cells between particles of one set (fiber bonds).
struct LineSetView {
  std::size_t n_local = 0;              // this rank's cells
  const std::int64_t* id = nullptr;     // cell ids, a dense range over all ranks
  const std::int64_t* nodes = nullptr;  // 2 per cell: the ends' particle ids (any rank's)
  std::vector<FieldView> fields;        // per cell
};

struct ParticleSetView {
  std::string name;                  // "fluid", "wall", ...
  std::size_t n_local = 0;           // this rank's owned particles
  const std::int64_t* id = nullptr;  // global ids; within a set they form a dense
                                     // range [min, min + N) over all ranks
  int dimension = 2;
  const double* position = nullptr;  // n_local * dimension
  std::vector<FieldView> fields;
  bool has_lines = false;  // every rank agrees
  LineSetView lines{};
};

class SnapshotWriter {
 public:
  // Creates `directory` if needed (rank 0; every rank throws on failure).
  // The XDMF index is <directory>/<case_name>.xdmf. The communicator is
  // copied, so the writer may outlive `comm`, not the MPI_Comm behind it.
  // `case_yaml`, the effective case (effective_case_yaml, config.hpp), is
  // stored in every file as the root attribute `case_yaml`.
  SnapshotWriter(const Comm& comm, std::string directory, std::string case_name,
                 std::string case_yaml = {});

  // Collective. Writes the HDF5 file to a temporary name, closes it and
  // renames it (complete or absent), then rewrites the XDMF (also atomically)
  // with this snapshot appended (or replacing an earlier one of the same
  // step). Returns the HDF5 file path. Every rank passes the same sets, in
  // the same order, with the same fields. Throws std::invalid_argument for
  // malformed views and std::runtime_error when a set's ids are not a dense
  // range, and CollectiveIoError when the file system or HDF5 fails on any
  // rank (the ranks agree after every call that can fail, so none is left
  // waiting; the temporary file is removed); in every case on every rank.
  std::string write(std::int64_t step, double time, const std::vector<ParticleSetView>& sets);

  const std::string& xdmf_path() const { return xdmf_path_; }

  // Collective. Continues the series of an earlier run in the directory
  // from its checkpoint at `step` (src/io/snapshot_resume.cpp): the
  // snapshots up to `step` are listed again (read back from their files),
  // later ones (written after that checkpoint) are deleted, and the XDMF is
  // rewritten. Throws std::runtime_error if a kept snapshot is unreadable.
  void resume(std::int64_t step);

 private:
  struct SetEntry {
    std::string name;
    std::int64_t count = 0;
    std::int64_t id_min = 0;  // row = id - id_min, also the XDMF vertex index
    std::vector<std::pair<std::string, int>> fields;  // name, columns in the file (1 or 3)
    std::int64_t line_count = 0;                      // cells of "<set>/lines"
    std::vector<std::pair<std::string, int>> line_fields;
  };
  struct Entry {
    std::int64_t step = 0;
    double time = 0.0;
    std::string file;  // relative to the directory
    std::vector<SetEntry> sets;
  };
  Entry write_hdf5(const std::string& path, const std::string& final_path, std::int64_t step,
                   double time, const std::vector<ParticleSetView>& sets) const;
  void write_xdmf(const std::vector<Entry>& entries) const;
  static std::string xdmf_text(const std::string& title, const std::vector<Entry>& entries);

  Comm comm_;
  std::string directory_;
  std::string case_name_;
  std::string case_yaml_;
  std::string xdmf_path_;
  std::vector<Entry> entries_;
};

}  // namespace sphdem
