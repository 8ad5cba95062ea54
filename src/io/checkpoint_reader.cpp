// CheckpointReader (checkpoint.hpp): opens a checkpoint's HDF5 file, checks
// its format and reads its attributes and columns back, verifying checksums.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "checkpoint_format.hpp"
#include "sphdem/core/fault.hpp"

namespace sphdem {

namespace {

namespace fs = std::filesystem;
using namespace checkpoint_io;

std::map<std::string, std::int64_t>& rows_read() {
  static std::map<std::string, std::int64_t> rows;
  return rows;
}

}  // namespace

std::int64_t checkpoint_rows_read(const std::string& group) {
  const auto it = rows_read().find(group);
  return it == rows_read().end() ? 0 : it->second;
}

struct CheckpointReader::Impl {
  Comm comm;
  std::string path;
  QuietHdf5 quiet;
  std::optional<Handle> file;
};

CheckpointReader::CheckpointReader(const Comm& comm, std::string path)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.comm = comm;
  m.path = std::move(path);
  std::error_code ec;
  if (!fs::is_regular_file(m.path, ec)) throw InputError(m.path, 0, "", "no such checkpoint file");
  collective(comm, m.path, [&] {
    Handle fapl = file_access(comm, m.path);
    const hid_t id = H5Fopen(m.path.c_str(), H5F_ACC_RDONLY, fapl.get());
    if (id < 0) {
      try {
        h5::fail("open file", m.path);
      } catch (const std::exception& e) {
        throw std::runtime_error(std::string("the checkpoint is truncated or corrupt (") +
                                 e.what() + ")");
      }
    }
    m.file.emplace(id, H5Fclose, "open file", m.path);
    std::int64_t format = 0;
    try {
      format =
          read_scalar_attribute<std::int64_t>(m.file->get(), "format", H5T_NATIVE_INT64, m.path);
    } catch (const std::exception&) {
      throw std::runtime_error("not an sphdem checkpoint (no 'format' attribute)");
    }
    if (format != kCheckpointFormat)
      throw std::runtime_error(fmt::format(
          "checkpoint format {} (written by sphdem {}); this sphdem ({}) reads format {} only",
          format, read_string_attribute(m.file->get(), "sphdem_version", m.path), SPHDEM_VERSION,
          kCheckpointFormat));
  });
}

CheckpointReader::~CheckpointReader() = default;

const std::string& CheckpointReader::path() const {
  return impl_->path;
}

double CheckpointReader::real(const std::string& name) const {
  return collective(impl_->comm, impl_->path, [&] {
    const double v = read_scalar_attribute<double>(impl_->file->get(), name.c_str(),
                                                   H5T_NATIVE_DOUBLE, impl_->path);
    if (!std::isfinite(v))
      throw std::runtime_error(fmt::format("attribute '{}' is {}, not a finite number", name, v));
    return v;
  });
}

std::int64_t CheckpointReader::integer_in(const std::string& name, std::int64_t lo,
                                          std::int64_t hi) const {
  const std::int64_t v = integer(name);
  if (v < lo || v > hi)
    throw InputError(
        impl_->path, 0, "",
        fmt::format("attribute '{}' is {}, outside [{}, {}]: the checkpoint is corrupt", name, v,
                    lo, hi));
  return v;
}

double CheckpointReader::real_in(const std::string& name, double lo, double hi,
                                 bool lo_open) const {
  const double v = real(name);
  if ((lo_open ? !(v > lo) : !(v >= lo)) || !(v <= hi))
    throw InputError(
        impl_->path, 0, "",
        fmt::format("attribute '{}' is {}, outside {}{}, {}]: the checkpoint is corrupt", name, v,
                    lo_open ? '(' : '[', lo, hi));
  return v;
}

std::int64_t CheckpointReader::integer(const std::string& name) const {
  return collective(impl_->comm, impl_->path, [&] {
    return read_scalar_attribute<std::int64_t>(impl_->file->get(), name.c_str(), H5T_NATIVE_INT64,
                                               impl_->path);
  });
}

std::string CheckpointReader::text(const std::string& name) const {
  return collective(impl_->comm, impl_->path, [&] {
    return read_string_attribute(impl_->file->get(), name.c_str(), impl_->path);
  });
}

std::vector<double> CheckpointReader::reals(const std::string& name) const {
  return collective(impl_->comm, impl_->path, [&] {
    const std::string& path = impl_->path;
    if (H5Aexists(impl_->file->get(), name.c_str()) <= 0)
      throw std::runtime_error(fmt::format("attribute '{}' is missing", name));
    Handle attr(H5Aopen(impl_->file->get(), name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute",
                path);
    Handle space(H5Aget_space(attr.get()), H5Sclose, "get attribute space", path);
    const hssize_t n = H5Sget_simple_extent_npoints(space.get());
    std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(0, n)));
    if (!v.empty()) check(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, v.data()), "read attribute", path);
    for (const double x : v)
      if (!std::isfinite(x))
        throw std::runtime_error(
            fmt::format("attribute '{}' holds {}, not a finite number", name, x));
    return v;
  });
}

std::int64_t CheckpointReader::count(const std::string& group) const {
  return collective(impl_->comm, impl_->path, [&] {
    if (H5Lexists(impl_->file->get(), group.c_str(), H5P_DEFAULT) <= 0)
      throw std::runtime_error("the checkpoint has no particle group '" + group + "'");
    Handle g(H5Gopen2(impl_->file->get(), group.c_str(), H5P_DEFAULT), H5Gclose, "open group",
             impl_->path);
    const std::int64_t n =
        read_scalar_attribute<std::int64_t>(g.get(), "count", H5T_NATIVE_INT64, impl_->path);
    if (n < 0) throw std::runtime_error(fmt::format("group '{}' has a count of {}", group, n));
    return n;
  });
}

namespace {

herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->push_back(name);
  return 0;
}

}  // namespace

std::vector<CheckpointColumn> CheckpointReader::particles(const std::string& group,
                                                          bool all_rows) const {
  const Impl& m = *impl_;
  const std::int64_t n_global = count(group);
  const int p = all_rows ? 1 : m.comm.size(), me = all_rows ? 0 : m.comm.rank();
  const std::int64_t first = slice_first(n_global, p, me);
  const std::int64_t n = slice_first(n_global, p, me + 1) - first;
  std::vector<CheckpointColumn> cols;
  std::vector<std::uint64_t> stored;
  // One agreement per HDF5 step (io_agreement.hpp): H5Dread is collective,
  // so a rank that failed before it must not leave the others waiting there.
  const std::string& path = m.path;
  std::optional<Handle> g, dxpl;
  std::vector<std::string> names;
  collective(m.comm, path, [&] {
    g.emplace(H5Gopen2(m.file->get(), group.c_str(), H5P_DEFAULT), H5Gclose, "open group", path);
    check(H5Literate(g->get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names),
          "list datasets", path);
    dxpl.emplace(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "create transfer list", path);
    check(H5Pset_dxpl_mpio(dxpl->get(), H5FD_MPIO_COLLECTIVE), "select collective I/O", path);
  });
  for (const std::string& name : names) {
    std::optional<Handle> dset, fspace, mspace;
    CheckpointColumn c;
    c.name = name;
    collective(m.comm, path, [&] {
      dset.emplace(H5Dopen2(g->get(), name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset", path);
      const hid_t ds = dset->get();
      const int type = read_scalar_attribute<int>(ds, "type", H5T_NATIVE_INT, path);
      if (type < 0 || type > static_cast<int>(ColumnType::Bytes))
        throw std::runtime_error("field '" + name + "' has an unknown type");
      c.type = static_cast<ColumnType>(type);
      c.components = read_scalar_attribute<int>(ds, "components", H5T_NATIVE_INT, path);
      c.row_bytes = static_cast<std::size_t>(
          read_scalar_attribute<std::int64_t>(ds, "row_bytes", H5T_NATIVE_INT64, path));
      stored.push_back(
          read_scalar_attribute<std::uint64_t>(ds, "checksum", H5T_NATIVE_UINT64, path));
      const hsize_t cols_in_file = dataset_columns(c);
      fspace.emplace(H5Dget_space(ds), H5Sclose, "get dataset space", path);
      hsize_t dims[2] = {0, 1};
      const int rank = H5Sget_simple_extent_ndims(fspace->get());
      if (rank < 1 || rank > 2) throw std::runtime_error("field '" + name + "' has a bad shape");
      H5Sget_simple_extent_dims(fspace->get(), dims, nullptr);
      if (dims[0] != static_cast<hsize_t>(n_global) || (rank == 2 ? dims[1] : 1) != cols_in_file ||
          (c.type != ColumnType::Bytes && value_bytes(c.type) * cols_in_file != c.row_bytes))
        throw std::runtime_error("field '" + name + "' does not match its description");
      c.data.resize(static_cast<std::size_t>(n) * c.row_bytes);
      const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
      const hsize_t count[2] = {static_cast<hsize_t>(n), cols_in_file};
      if (n > 0)
        check(H5Sselect_hyperslab(fspace->get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
              "select rows", path);
      else
        check(H5Sselect_none(fspace->get()), "select no rows", path);
      mspace.emplace(H5Screate_simple(rank, count, nullptr), H5Sclose, "create memory space", path);
      if (n == 0) check(H5Sselect_none(mspace->get()), "select nothing", path);
    });
    collective(m.comm, path, [&] {
      char none = 0;
      if (n_global > 0)
        check(H5Dread(dset->get(), types_of(c.type).mem, mspace->get(), fspace->get(), dxpl->get(),
                      c.data.empty() ? &none : c.data.data()),
              "read dataset", path);
      // Testing hook (fault.hpp): the read failed on this rank alone.
      inject_io_fault(FaultKind::RestartRead, m.comm.rank(), 0, path);
    });
    cols.push_back(std::move(c));
  }
  rows_read()[group] += n;
  for (std::size_t k = 0; k < cols.size(); ++k) {
    // Every rank holds every row with all_rows: each checks the whole sum.
    if (checksum(all_rows ? Comm(MPI_COMM_SELF) : m.comm, cols[k], first) != stored[k])
      throw InputError(m.path, 0, "",
                       "field '" + group + "/" + cols[k].name +
                           "' fails its checksum: the checkpoint is corrupt");
  }
  return cols;
}

}  // namespace sphdem
