// SnapshotWriter: the collective HDF5 part and the atomic publication.
// The XDMF text lives in xdmf.cpp.
#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>

#include "hdf5_helpers.hpp"
#include "io_agreement.hpp"
#include "sphdem/core/fault.hpp"
#include "sphdem/io/io.hpp"

namespace sphdem {

namespace {

namespace fs = std::filesystem;
using h5::check;
using h5::Handle;

// Where this rank's particles go in the file: rows are id - id_min, so the
// file is ordered by global id whatever the decomposition.
struct RowPlan {
  std::int64_t n_global = 0;
  std::int64_t id_min = 0;
  std::vector<std::size_t> order;                 // local indices, sorted by id
  std::vector<std::pair<hsize_t, hsize_t>> runs;  // first row, row count
};

// Every rank throws the same exception type when any rank failed; ranks
// that failed report their own message, the others `elsewhere`.
template <class Error>
void throw_if_any(const Comm& comm, const std::string& error, const std::string& elsewhere) {
  if (comm.any(!error.empty())) throw Error(error.empty() ? elsewhere : error);
}

bool bad_name(const std::string& name) {
  return name.empty() || name == "." || name.find('/') != std::string::npos;
}

std::string check_field(const ParticleSetView& set, const FieldView& f) {
  const std::string where = "sphdem: set '" + set.name + "' field '" + f.name + "': ";
  if (bad_name(f.name) || f.name == "id" || f.name == "position")
    return where + "invalid dataset name";
  if (f.components != 1 && f.components != set.dimension)
    return where + "components must be 1 or the dimension";
  if (set.n_local > 0 && f.data == nullptr) return where + "no data";
  return {};
}

std::string check_set(const ParticleSetView& set, int dimension) {
  const std::string where = "sphdem: set '" + set.name + "': ";
  if (bad_name(set.name)) return where + "invalid group name";
  if (set.dimension != dimension) return where + "dimension differs from the first set's";
  if (dimension != 2 && dimension != 3) return where + "dimension must be 2 or 3";
  if (set.n_local > 0 && (set.id == nullptr || set.position == nullptr))
    return where + "no ids or positions";
  std::set<std::string> names;
  for (const auto& f : set.fields) {
    if (!names.insert(f.name).second) return where + "field '" + f.name + "' appears twice";
    if (auto problem = check_field(set, f); !problem.empty()) return problem;
  }
  if (!set.has_lines) return {};
  if (set.lines.n_local > 0 && (set.lines.id == nullptr || set.lines.nodes == nullptr))
    return where + "lines without ids or nodes";
  names.clear();
  for (const auto& f : set.lines.fields) {
    if (!names.insert(f.name).second) return where + "line field '" + f.name + "' appears twice";
    if (f.name == "nodes") return where + "invalid line field name 'nodes'";
    ParticleSetView as_set;  // the same rules as a particle field, per cell
    as_set.name = set.name;
    as_set.dimension = set.dimension;
    as_set.n_local = set.lines.n_local;
    if (auto problem = check_field(as_set, f); !problem.empty()) return problem;
  }
  return {};
}

// Collective, so a malformed view on one rank cannot leave the others
// waiting inside HDF5.
void check_views(const Comm& comm, const std::vector<ParticleSetView>& sets) {
  std::string problem;
  if (sets.empty()) problem = "sphdem: snapshot has no particle sets";
  std::set<std::string> names;
  for (const auto& set : sets) {
    if (!problem.empty()) break;
    if (!names.insert(set.name).second) problem = "sphdem: set '" + set.name + "' appears twice";
    if (problem.empty()) problem = check_set(set, sets.front().dimension);
  }
  throw_if_any<std::invalid_argument>(comm, problem,
                                      "sphdem: invalid particle set on another rank");
}

std::vector<std::pair<hsize_t, hsize_t>> coalesce(const ParticleSetView& set,
                                                  const std::vector<std::size_t>& order,
                                                  std::int64_t id_min) {
  std::vector<std::pair<hsize_t, hsize_t>> runs;
  for (std::size_t i : order) {
    const auto row = static_cast<hsize_t>(set.id[i] - id_min);
    if (!runs.empty() && runs.back().first + runs.back().second == row)
      ++runs.back().second;
    else
      runs.emplace_back(row, 1);
  }
  return runs;
}

RowPlan plan_rows(const Comm& comm, const ParticleSetView& set) {
  RowPlan plan;
  plan.order.resize(set.n_local);
  std::iota(plan.order.begin(), plan.order.end(), std::size_t{0});
  std::sort(plan.order.begin(), plan.order.end(),
            [&](std::size_t a, std::size_t b) { return set.id[a] < set.id[b]; });
  const auto same_id = [&](std::size_t a, std::size_t b) { return set.id[a] == set.id[b]; };
  const bool duplicate =
      std::adjacent_find(plan.order.begin(), plan.order.end(), same_id) != plan.order.end();
  std::int64_t lo = std::numeric_limits<std::int64_t>::max();
  std::int64_t hi = std::numeric_limits<std::int64_t>::min();
  if (set.n_local > 0) {
    lo = set.id[plan.order.front()];
    hi = set.id[plan.order.back()];
  }
  plan.n_global = comm.sum(static_cast<std::int64_t>(set.n_local));
  plan.id_min = comm.min(lo);
  const std::int64_t id_max = comm.max(hi);
  // A duplicate across ranks that comes with a missing id (0, 1, 1, 3) passes:
  // catching it would need a global exchange, and the view promises unique ids.
  if (comm.any(duplicate) || (plan.n_global > 0 && id_max - plan.id_min + 1 != plan.n_global))
    throw std::runtime_error(fmt::format(
        "sphdem: set '{}': ids are not a dense range of unique values (N = {}, min = {}, max = {})",
        set.name, plan.n_global, plan.id_min, id_max));
  plan.runs = coalesce(set, plan.order, plan.id_min);
  return plan;
}

// `cols` values per particle in id order, zero-padded to `out_cols`.
template <class T>
std::vector<T> pack(const RowPlan& plan, const T* src, int cols, int out_cols) {
  std::vector<T> out(plan.order.size() * static_cast<std::size_t>(out_cols), T{});
  T* dst = out.data();
  for (std::size_t i : plan.order) {
    std::copy_n(src + i * static_cast<std::size_t>(cols), cols, dst);
    dst += out_cols;
  }
  return out;
}

// HDF5 1.10 rescans the whole selection on every H5S_SELECT_OR, so adding R
// runs one by one costs O(R^2) (50 000 runs took minutes). Small groups are
// OR-ed, then halves merged with H5Scombine_select: O(R log R).
constexpr std::size_t kRunsPerLeaf = 32;

Handle select_runs(hid_t base, const RowPlan& plan, std::size_t lo, std::size_t hi, hsize_t cols,
                   const std::string& path) {
  if (hi - lo <= kRunsPerLeaf) {
    Handle space(H5Scopy(base), H5Sclose, "copy file space", path);
    H5S_seloper_t op = H5S_SELECT_SET;
    for (std::size_t k = lo; k < hi; ++k) {
      const hsize_t start[2] = {plan.runs[k].first, 0};
      const hsize_t extent[2] = {plan.runs[k].second, cols};
      check(H5Sselect_hyperslab(space.get(), op, start, nullptr, extent, nullptr), "select rows",
            path);
      op = H5S_SELECT_OR;
    }
    return space;
  }
  const std::size_t mid = lo + (hi - lo) / 2;
  const Handle first = select_runs(base, plan, lo, mid, cols, path);
  const Handle second = select_runs(base, plan, mid, hi, cols, path);
  return Handle(H5Scombine_select(first.get(), H5S_SELECT_OR, second.get()), H5Sclose,
                "merge row selections", path);
}

// This rank's rows of a [N] (cols = 1) or [N][cols] dataset.
Handle file_selection(const RowPlan& plan, hsize_t cols, const std::string& path) {
  const hsize_t dims[2] = {static_cast<hsize_t>(plan.n_global), cols};
  Handle space(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), H5Sclose, "create file space",
               path);
  if (!plan.runs.empty()) return select_runs(space.get(), plan, 0, plan.runs.size(), cols, path);
  check(H5Sselect_none(space.get()), "select no rows", path);
  return space;
}

// How the ranks write one snapshot: every call that can fail runs inside
// `agree` (io_agreement.hpp); rank and step are for the test hook (fault.hpp).
struct Writing {
  const io::Agreement<>& agree;
  hid_t dxpl;
  const std::string& path;
  int rank;
  std::int64_t step;
};

// Where a set's datasets go, with the row selections shared by its columns.
struct Target {
  hid_t group;
  const Writing& w;
  hid_t rows_scalar;  // file selection for [N]
  hid_t rows_vector;  // file selection for [N][3]
  const std::string& path;
  hid_t rows_pair = -1;  // file selection for [N][2] (line nodes)
};

struct Column {
  const char* name;
  const char* units;
  int cols;  // 1 or 3 in the file
  hid_t file_type;
  hid_t mem_type;
};

Handle create_dataset(const Target& t, const Column& c, hsize_t n_global) {
  const hsize_t dims[2] = {n_global, static_cast<hsize_t>(c.cols)};
  Handle space(H5Screate_simple(c.cols == 1 ? 1 : 2, dims, nullptr), H5Sclose, "create file space",
               t.path);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "create dataset properties", t.path);
  // Every row is written, so filling with zeros first would be wasted I/O.
  check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "set fill time", t.path);
  Handle dset(
      H5Dcreate2(t.group, c.name, c.file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      H5Dclose, "create dataset", t.path);
  h5::write_attribute(dset.get(), "units", std::string(c.units), t.path);
  return dset;
}

template <class T>
void write_column(const Target& t, const Column& c, const RowPlan& plan,
                  const std::vector<T>& packed) {
  std::optional<Handle> dset;
  std::optional<Handle> mspace;
  t.w.agree([&] {
    dset.emplace(create_dataset(t, c, static_cast<hsize_t>(plan.n_global)));
    const hsize_t mdims[2] = {plan.order.size(), static_cast<hsize_t>(c.cols)};
    mspace.emplace(H5Screate_simple(c.cols == 1 ? 1 : 2, mdims, nullptr), H5Sclose,
                   "create memory space", t.path);
    if (plan.order.empty()) check(H5Sselect_none(mspace->get()), "select nothing", t.path);
  });
  if (plan.n_global == 0) return;  // every rank agrees: nothing to transfer
  const hid_t fspace = c.cols == 1 ? t.rows_scalar : (c.cols == 2 ? t.rows_pair : t.rows_vector);
  const T none{};  // HDF5 wants a buffer even when this rank writes nothing
  const T* buf = packed.empty() ? &none : packed.data();
  t.w.agree([&] {
    check(H5Dwrite(dset->get(), c.mem_type, mspace->get(), fspace, t.w.dxpl, buf), "write dataset",
          t.path);
    // Testing hook (fault.hpp): the write failed on this rank alone.
    inject_io_fault(FaultKind::SnapshotWrite, t.w.rank, t.w.step, t.path);
  });
}

int file_columns(int components) {
  return components == 1 ? 1 : 3;
}

// The line cells of a set: ids, node rows (id - the set's id_min), fields.
void write_lines(hid_t set_group, const Writing& w, const ParticleSetView& set, const RowPlan& plan,
                 const std::vector<std::int64_t>& node_rows) {
  const std::string& path = w.path;
  std::optional<Handle> group, rows_scalar, rows_pair, rows_vector;
  w.agree([&] {
    group.emplace(H5Gcreate2(set_group, "lines", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                  "create group", path);
    h5::write_attribute(group->get(), "count", plan.n_global, path);
    rows_scalar.emplace(file_selection(plan, 1, path));
    rows_pair.emplace(file_selection(plan, 2, path));
    rows_vector.emplace(file_selection(plan, 3, path));
  });
  const Target t{group->get(), w, rows_scalar->get(), rows_vector->get(), path, rows_pair->get()};
  write_column(t, {"id", "1", 1, H5T_STD_I64LE, H5T_NATIVE_INT64}, plan,
               pack(plan, set.lines.id, 1, 1));
  write_column(t, {"nodes", "1", 2, H5T_STD_I64LE, H5T_NATIVE_INT64}, plan,
               pack(plan, node_rows.data(), 2, 2));
  for (const auto& f : set.lines.fields) {
    const int cols = file_columns(f.components);
    write_column(t, {f.name.c_str(), f.units.c_str(), cols, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE},
                 plan, pack(plan, f.data, f.components, cols));
  }
}

// The row plan of a set's line cells, as if they were a set of their own.
RowPlan plan_line_rows(const Comm& comm, const ParticleSetView& set) {
  ParticleSetView cells;
  cells.name = set.name + "/lines";
  cells.n_local = set.has_lines ? set.lines.n_local : 0;
  cells.id = set.lines.id;
  return plan_rows(comm, cells);
}

// Node ids -> rows of the set; every node must be one of the set's ids.
std::vector<std::int64_t> node_rows(const Comm& comm, const ParticleSetView& set,
                                    const RowPlan& plan) {
  std::vector<std::int64_t> rows(2 * set.lines.n_local);
  bool bad = false;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    rows[k] = set.lines.nodes[k] - plan.id_min;
    bad = bad || rows[k] < 0 || rows[k] >= plan.n_global;
  }
  if (comm.any(bad))
    throw std::runtime_error("sphdem: set '" + set.name + "': a line refers to a missing particle");
  return rows;
}

// A set's line cells, planned before the file exists.
struct LinePlan {
  RowPlan rows;
  std::vector<std::int64_t> nodes;  // 2 per local cell, rows of the set
};

void write_set(hid_t file, const Writing& w, const ParticleSetView& set, const RowPlan& plan,
               const LinePlan* lines) {
  const std::string& path = w.path;
  std::optional<Handle> group, rows_scalar, rows_vector;
  w.agree([&] {
    group.emplace(H5Gcreate2(file, set.name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  H5Gclose, "create group", path);
    h5::write_attribute(group->get(), "count", plan.n_global, path);
    rows_scalar.emplace(file_selection(plan, 1, path));
    rows_vector.emplace(file_selection(plan, 3, path));
  });
  const Target t{group->get(), w, rows_scalar->get(), rows_vector->get(), path};
  write_column(t, {"id", "1", 1, H5T_STD_I64LE, H5T_NATIVE_INT64}, plan, pack(plan, set.id, 1, 1));
  write_column(t, {"position", "m", 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE}, plan,
               pack(plan, set.position, set.dimension, 3));
  for (const auto& f : set.fields) {
    const int cols = file_columns(f.components);
    write_column(t, {f.name.c_str(), f.units.c_str(), cols, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE},
                 plan, pack(plan, f.data, f.components, cols));
  }
  if (lines) write_lines(group->get(), w, set, lines->rows, lines->nodes);
}

void write_root_attributes(hid_t file, std::int64_t step, double time, int dimension,
                           const std::string& case_name, const std::string& case_yaml,
                           const std::string& path) {
  h5::write_attribute(file, "time", time, path);
  h5::write_attribute(file, "step", step, path);
  h5::write_attribute(file, "dimension", dimension, path);
  h5::write_attribute(file, "case", case_name, path);
  h5::write_attribute(file, "sphdem_version", std::string(SPHDEM_VERSION), path);
  if (!case_yaml.empty()) h5::write_attribute(file, "case_yaml", case_yaml, path);
}

std::string make_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return "sphdem: cannot create output directory '" + dir + "': " + ec.message();
  return {};
}

}  // namespace

SnapshotWriter::SnapshotWriter(const Comm& comm, std::string directory, std::string case_name,
                               std::string case_yaml)
    : comm_(comm),
      directory_(std::move(directory)),
      case_name_(std::move(case_name)),
      case_yaml_(std::move(case_yaml)),
      xdmf_path_((fs::path(directory_) / (case_name_ + ".xdmf")).string()) {
  if (bad_name(case_name_))
    throw std::invalid_argument("sphdem: invalid case name '" + case_name_ + "'");
  io::Agreement<>(comm_, "output directory '" + directory_ + "'")([&] {
    if (!comm_.root()) return;
    if (const std::string error = make_directory(directory_); !error.empty())
      throw std::runtime_error(error);
  });
}

SnapshotWriter::Entry SnapshotWriter::write_hdf5(const std::string& path,
                                                 const std::string& final_path, std::int64_t step,
                                                 double time,
                                                 const std::vector<ParticleSetView>& sets) const {
  // Validate everything before the file exists, so bad input leaves no trace.
  check_views(comm_, sets);
  std::vector<RowPlan> plans;
  for (const auto& set : sets) plans.push_back(plan_rows(comm_, set));
  std::vector<LinePlan> line_plans(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) {
    if (!sets[s].has_lines) continue;
    line_plans[s].rows = plan_line_rows(comm_, sets[s]);
    line_plans[s].nodes = node_rows(comm_, sets[s], plans[s]);
  }

  // From here every rank makes the same HDF5 calls and agrees after each
  // one that can fail (io_agreement.hpp).
  const io::Agreement<> agree(comm_, "snapshot '" + final_path + "'");
  std::optional<Handle> file, dxpl;
  agree([&] {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "create file access list", path);
    check(H5Pset_fapl_mpio(fapl.get(), comm_.raw(), MPI_INFO_NULL), "select MPI-IO driver", path);
    file.emplace(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose,
                 "create file", path);
  });
  try {
    agree([&] {
      dxpl.emplace(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "create transfer list", path);
      check(H5Pset_dxpl_mpio(dxpl->get(), H5FD_MPIO_COLLECTIVE), "select collective I/O", path);
      write_root_attributes(file->get(), step, time, sets.front().dimension, case_name_, case_yaml_,
                            path);
    });
    const Writing w{agree, dxpl->get(), path, comm_.rank(), step};
    Entry entry{step, time, {}, {}};
    for (std::size_t s = 0; s < sets.size(); ++s) {
      write_set(file->get(), w, sets[s], plans[s], sets[s].has_lines ? &line_plans[s] : nullptr);
      SetEntry& e = entry.sets.emplace_back(
          SetEntry{sets[s].name, plans[s].n_global, plans[s].id_min, {}, 0, {}});
      for (const auto& f : sets[s].fields)
        e.fields.emplace_back(f.name, file_columns(f.components));
      if (!sets[s].has_lines) continue;
      e.line_count = line_plans[s].rows.n_global;
      for (const auto& f : sets[s].lines.fields)
        e.line_fields.emplace_back(f.name, file_columns(f.components));
    }
    dxpl.reset();
    agree([&] { file->close("close file", path); });
    return entry;
  } catch (const CollectiveIoError&) {
    dxpl.reset();
    io::close_failed_file(comm_, path, file);
    throw;
  }
}

std::string SnapshotWriter::write(std::int64_t step, double time,
                                  const std::vector<ParticleSetView>& sets) {
  const std::string name = fmt::format("{}_{:08d}.h5", case_name_, step);
  const std::string final_path = (fs::path(directory_) / name).string();
  const std::string tmp_path = (fs::path(directory_) / ("." + name + ".tmp")).string();
  Entry entry;
  try {
    entry = write_hdf5(tmp_path, final_path, step, time, sets);
  } catch (const CollectiveIoError&) {
    // Every rank is here; the file is closed (the unwinding closed it on
    // every rank alike). No partial snapshot stays behind.
    if (comm_.root()) {
      std::error_code ec;
      fs::remove(tmp_path, ec);
    }
    throw;
  }
  entry.file = name;

  // A rewrite of the same step replaces its entry rather than listing it twice.
  std::vector<Entry> entries = entries_;
  const auto same =
      std::find_if(entries.begin(), entries.end(), [&](const Entry& e) { return e.step == step; });
  if (same != entries.end())
    *same = std::move(entry);
  else
    entries.push_back(std::move(entry));

  // The reduction is also the barrier: no rank returns before the HDF5 file
  // and the XDMF naming it are in place.
  io::Agreement<>(comm_, "snapshot '" + final_path + "'")([&] {
    if (!comm_.root()) return;
    fs::rename(tmp_path, final_path);
    write_xdmf(entries);
  });
  entries_ = std::move(entries);
  return final_path;
}

}  // namespace sphdem
