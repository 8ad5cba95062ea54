// CheckpointWriter / CheckpointReader (checkpoint.hpp): the HDF5 file of a
// checkpoint. Layout (docs/checkpoint.md):
//   /            attributes: format, sphdem_version and the run's scalars
//   /<group>/    attributes count, id_min; one dataset per column, rows in
//                global-id order, each with attributes type, components,
//                row_bytes and checksum
// The checksum of a column is the sum (mod 2^64) over its rows of a hash of
// (row index, row bytes): ranks add their slices in any order and agree,
// and a single changed byte anywhere in the data changes it. HDF5's own
// metadata checksums (latest file format) guard the rest of the file.
#include <fcntl.h>
#include <fmt/format.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "hdf5_helpers.hpp"
#include "sphdem/checkpoint.hpp"

namespace sphdem {

namespace {

namespace fs = std::filesystem;
using h5::check;
using h5::Handle;

std::uint64_t row_hash(std::uint64_t row, const char* p, std::size_t n) {
  // FNV-1a over the bytes, seeded by a splitmix64 of the row index.
  std::uint64_t h = row + 0x9e3779b97f4a7c15ULL;
  h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
  h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
  h ^= h >> 31;
  h ^= 0xcbf29ce484222325ULL;
  for (std::size_t k = 0; k < n; ++k) {
    h ^= static_cast<unsigned char>(p[k]);
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::uint64_t checksum(const Comm& comm, const CheckpointColumn& c, std::int64_t first_row) {
  std::uint64_t local = 0;
  for (std::size_t r = 0; r < c.rows(); ++r)
    local += row_hash(static_cast<std::uint64_t>(first_row) + r, c.data.data() + r * c.row_bytes,
                      c.row_bytes);
  std::uint64_t total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_UINT64_T, MPI_SUM, comm.raw());
  return total;
}

// First row of rank r's slice of n rows over p ranks (balanced).
std::int64_t slice_first(std::int64_t n, int p, int r) {
  // floor(n r / p) without overflowing n r.
  return n / p * r + (n % p) * r / p;
}

struct FileTypes {
  hid_t file, mem;
};

FileTypes types_of(ColumnType t) {
  switch (t) {
    case ColumnType::F64:
      return {H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE};
    case ColumnType::I64:
      return {H5T_STD_I64LE, H5T_NATIVE_INT64};
    case ColumnType::I32:
      return {H5T_STD_I32LE, H5T_NATIVE_INT32};
    default:
      return {H5T_STD_U8LE, H5T_NATIVE_UINT8};
  }
}

// Columns of a dataset: numbers per row for numeric types, bytes for records.
hsize_t dataset_columns(const CheckpointColumn& c) {
  if (c.type == ColumnType::Bytes) return c.row_bytes;
  return static_cast<hsize_t>(c.components);
}

std::size_t value_bytes(ColumnType t) {
  switch (t) {
    case ColumnType::F64:
    case ColumnType::I64:
      return 8;
    case ColumnType::I32:
      return 4;
    default:
      return 1;
  }
}

// HDF5 prints its error stack by default; a refused checkpoint already says
// why, so printing is off while a reader or writer works.
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietHdf5(const QuietHdf5&) = delete;
  QuietHdf5& operator=(const QuietHdf5&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

Handle file_access(const Comm& comm, const std::string& path) {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "create file access list", path);
  check(H5Pset_fapl_mpio(fapl.get(), comm.raw(), MPI_INFO_NULL), "select MPI-IO driver", path);
  // The latest format checksums every piece of metadata.
  check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST),
        "select file format", path);
  return fapl;
}

void write_u64_attribute(hid_t obj, const char* name, std::uint64_t v, const std::string& path) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create attribute space", path);
  Handle attr(H5Acreate2(obj, name, H5T_STD_U64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "create attribute", path);
  check(H5Awrite(attr.get(), H5T_NATIVE_UINT64, &v), "write attribute", path);
}

template <class T>
T read_scalar_attribute(hid_t obj, const char* name, hid_t mem, const std::string& path) {
  if (H5Aexists(obj, name) <= 0)
    throw std::runtime_error(fmt::format("attribute '{}' is missing", name));
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, "open attribute", path);
  T v{};
  check(H5Aread(attr.get(), mem, &v), "read attribute", path);
  return v;
}

std::string read_string_attribute(hid_t obj, const char* name, const std::string& path) {
  if (H5Aexists(obj, name) <= 0)
    throw std::runtime_error(fmt::format("attribute '{}' is missing", name));
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, "open attribute", path);
  Handle type(H5Aget_type(attr.get()), H5Tclose, "get attribute type", path);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
    throw std::runtime_error(fmt::format("attribute '{}' is not a fixed-length string", name));
  std::string s(H5Tget_size(type.get()), '\0');
  check(H5Aread(attr.get(), type.get(), s.data()), "read attribute", path);
  return s.substr(0, s.find('\0'));
}

// Runs `f` on every rank; if it throws on any rank, every rank throws an
// InputError naming the file (the failing ranks' own message, or a note).
template <class F>
auto collective(const Comm& comm, const std::string& path, F&& f) -> decltype(f()) {
  std::string error;
  using R = decltype(f());
  if constexpr (std::is_void_v<R>) {
    try {
      f();
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (comm.any(!error.empty()))
      throw InputError(path, 0, "",
                       error.empty() ? "the checkpoint failed on another rank" : error);
  } else {
    R out{};
    try {
      out = f();
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (comm.any(!error.empty()))
      throw InputError(path, 0, "",
                       error.empty() ? "the checkpoint failed on another rank" : error);
    return out;
  }
}

// The test hook of docs/checkpoint.md: SPHDEM_TEST_ABORT_IN_CHECKPOINT=K
// kills the process in its K-th commit, after the data is written and before
// the rename, as a node failure would.
void maybe_abort_for_test() {
  static int commits = 0;
  ++commits;
  const char* k = std::getenv("SPHDEM_TEST_ABORT_IN_CHECKPOINT");
  if (k && std::atoi(k) == commits) std::raise(SIGKILL);
}

void fsync_path(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return;  // best effort: the rename is what makes it atomic
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

// ---------------------------------------------------------------- writer

struct CheckpointWriter::Impl {
  Comm comm;
  std::string path, tmp;
  QuietHdf5 quiet;
  std::optional<Handle> file;
  std::optional<Handle> dxpl;
  bool committed = false;
};

CheckpointWriter::CheckpointWriter(const Comm& comm, std::string path)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.comm = comm;
  m.path = std::move(path);
  const fs::path p(m.path);
  m.tmp = (p.parent_path() / ("." + p.filename().string() + ".tmp")).string();
  std::string error;
  if (comm.root()) {
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec) error = "cannot create '" + p.parent_path().string() + "': " + ec.message();
  }
  if (comm.any(!error.empty()))
    throw std::runtime_error("sphdem: checkpoint " + m.path + ": " +
                             (error.empty() ? "rank 0 could not create the directory" : error));
  Handle fapl = file_access(comm, m.tmp);
  m.file.emplace(H5Fcreate(m.tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose,
                 "create file", m.tmp);
  m.dxpl.emplace(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "create transfer list", m.tmp);
  check(H5Pset_dxpl_mpio(m.dxpl->get(), H5FD_MPIO_COLLECTIVE), "select collective I/O", m.tmp);
  h5::write_attribute(m.file->get(), "format", std::int64_t{kCheckpointFormat}, m.tmp);
  h5::write_attribute(m.file->get(), "sphdem_version", std::string(SPHDEM_VERSION), m.tmp);
}

CheckpointWriter::~CheckpointWriter() {
  if (!impl_ || impl_->committed) return;
  impl_->dxpl.reset();
  impl_->file.reset();
  if (impl_->comm.root()) {
    std::error_code ec;
    fs::remove(impl_->tmp, ec);
  }
}

void CheckpointWriter::attribute(const std::string& name, double v) {
  h5::write_attribute(impl_->file->get(), name.c_str(), v, impl_->tmp);
}
void CheckpointWriter::attribute(const std::string& name, std::int64_t v) {
  h5::write_attribute(impl_->file->get(), name.c_str(), v, impl_->tmp);
}
void CheckpointWriter::attribute(const std::string& name, const std::string& v) {
  h5::write_attribute(impl_->file->get(), name.c_str(), v, impl_->tmp);
}
void CheckpointWriter::attribute(const std::string& name, const std::vector<double>& v) {
  const std::string& path = impl_->tmp;
  const hsize_t n = v.size();
  Handle space(n == 0 ? H5Screate(H5S_NULL) : H5Screate_simple(1, &n, nullptr), H5Sclose,
               "create attribute space", path);
  Handle attr(H5Acreate2(impl_->file->get(), name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                         H5P_DEFAULT),
              H5Aclose, "create attribute", path);
  if (n > 0) check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, v.data()), "write attribute", path);
}

namespace {

// Rows of every column regrouped so that this rank holds the contiguous
// slice [first, first + n) of the ids, in id order.
struct Slices {
  std::int64_t n_global = 0, id_min = 0, first = 0, n = 0;
  std::vector<CheckpointColumn> columns;
};

Slices regroup(const Comm& comm, const std::vector<CheckpointColumn>& columns,
               const std::string& group) {
  const auto gid_it = std::find_if(columns.begin(), columns.end(),
                                   [](const CheckpointColumn& c) { return c.name == "gid"; });
  if (gid_it == columns.end() || gid_it->type != ColumnType::I64)
    throw std::invalid_argument("sphdem: checkpoint group '" + group + "' has no int64 gid");
  const std::size_t n_local = gid_it->rows();
  std::vector<std::int64_t> gid(n_local);
  if (n_local > 0) std::memcpy(gid.data(), gid_it->data.data(), n_local * sizeof(std::int64_t));
  Slices s;
  s.n_global = comm.sum(static_cast<std::int64_t>(n_local));
  std::int64_t lo = INT64_MAX, hi = INT64_MIN;
  for (std::int64_t g : gid) lo = std::min(lo, g), hi = std::max(hi, g);
  s.id_min = comm.min(lo);
  const std::int64_t id_max = comm.max(hi);
  if (s.n_global > 0 && id_max - s.id_min + 1 != s.n_global)
    throw std::runtime_error(fmt::format(
        "sphdem: checkpoint group '{}': ids are not a dense range (N = {}, min = {}, max = {})",
        group, s.n_global, s.id_min, id_max));
  const int p = comm.size(), me = comm.rank();
  s.first = slice_first(s.n_global, p, me);
  s.n = slice_first(s.n_global, p, me + 1) - s.first;

  // Destination of each row, rows grouped by destination (stable).
  std::vector<int> dest(n_local);
  std::vector<int> count(static_cast<std::size_t>(p), 0);
  for (std::size_t i = 0; i < n_local; ++i) {
    const std::int64_t row = gid[i] - s.id_min;
    // A guess, corrected to the exact slice below.
    int r = static_cast<int>(static_cast<double>(row) * p / static_cast<double>(s.n_global));
    r = std::clamp(r, 0, p - 1);
    while (r + 1 < p && slice_first(s.n_global, p, r + 1) <= row) ++r;
    while (r > 0 && slice_first(s.n_global, p, r) > row) --r;
    dest[i] = r;
    ++count[static_cast<std::size_t>(r)];
  }
  std::vector<int> recv_count(static_cast<std::size_t>(p));
  MPI_Alltoall(count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, comm.raw());
  std::vector<std::size_t> order(n_local);
  {
    std::vector<std::size_t> next(static_cast<std::size_t>(p) + 1, 0);
    for (int r = 0; r < p; ++r)
      next[static_cast<std::size_t>(r) + 1] =
          next[static_cast<std::size_t>(r)] +
          static_cast<std::size_t>(count[static_cast<std::size_t>(r)]);
    for (std::size_t i = 0; i < n_local; ++i) order[next[static_cast<std::size_t>(dest[i])]++] = i;
  }
  std::int64_t received = 0;
  for (int c : recv_count) received += c;
  if (received != s.n)
    throw std::logic_error("sphdem: checkpoint regroup received the wrong number of rows");

  // The gids first: they say where each received row goes.
  std::vector<std::int64_t> slot;
  for (const CheckpointColumn& col : columns) {
    const std::size_t rb = col.row_bytes;
    if (col.rows() != n_local)
      throw std::invalid_argument("sphdem: checkpoint column '" + col.name + "' has " +
                                  std::to_string(col.rows()) + " rows, gid has " +
                                  std::to_string(n_local));
    std::vector<int> sc(static_cast<std::size_t>(p)), sd(static_cast<std::size_t>(p)),
        rc(static_cast<std::size_t>(p)), rd(static_cast<std::size_t>(p));
    long long so = 0, ro = 0;
    for (std::size_t r = 0; r < static_cast<std::size_t>(p); ++r) {
      const long long sb = static_cast<long long>(count[r]) * static_cast<long long>(rb);
      const long long rbb = static_cast<long long>(recv_count[r]) * static_cast<long long>(rb);
      if (so + sb > INT_MAX || ro + rbb > INT_MAX)
        throw std::runtime_error("sphdem: checkpoint column '" + col.name +
                                 "' exceeds 2 GiB per rank: use more ranks");
      sc[r] = static_cast<int>(sb), sd[r] = static_cast<int>(so), so += sb;
      rc[r] = static_cast<int>(rbb), rd[r] = static_cast<int>(ro), ro += rbb;
    }
    std::vector<char> out(static_cast<std::size_t>(so)), in(static_cast<std::size_t>(ro));
    for (std::size_t k = 0; k < n_local; ++k)
      std::memcpy(out.data() + k * rb, col.data.data() + order[k] * rb, rb);
    MPI_Alltoallv(out.data(), sc.data(), sd.data(), MPI_BYTE, in.data(), rc.data(), rd.data(),
                  MPI_BYTE, comm.raw());
    if (&col == &columns.front()) {                // the gid column (callers put it first)
      slot.resize(static_cast<std::size_t>(s.n));  // s.n rows arrive, one per slot
      for (std::size_t k = 0; k < slot.size(); ++k) {
        std::int64_t g = 0;
        std::memcpy(&g, in.data() + k * rb, sizeof g);
        slot[k] = g - s.id_min - s.first;
      }
    }
    CheckpointColumn placed{col.name, col.type, col.components, rb, {}};
    placed.data.resize(in.size());
    for (std::size_t k = 0; k < slot.size(); ++k)
      std::memcpy(placed.data.data() + static_cast<std::size_t>(slot[k]) * rb, in.data() + k * rb,
                  rb);
    s.columns.push_back(std::move(placed));
  }
  return s;
}

}  // namespace

void CheckpointWriter::particles(const std::string& group,
                                 const std::vector<CheckpointColumn>& columns) {
  Impl& m = *impl_;
  const std::string& path = m.tmp;
  // gid first, so regroup() learns each row's slot before the other columns.
  std::vector<CheckpointColumn> ordered;
  for (const CheckpointColumn& c : columns)
    if (c.name == "gid") ordered.push_back(c);
  for (const CheckpointColumn& c : columns)
    if (c.name != "gid") ordered.push_back(c);
  const Slices s = regroup(m.comm, ordered, group);

  Handle g(H5Gcreate2(m.file->get(), group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Gclose, "create group", path);
  h5::write_attribute(g.get(), "count", s.n_global, path);
  h5::write_attribute(g.get(), "id_min", s.id_min, path);
  for (const CheckpointColumn& c : s.columns) {
    const hsize_t cols = dataset_columns(c);
    const int rank = cols == 1 ? 1 : 2;
    const hsize_t dims[2] = {static_cast<hsize_t>(s.n_global), cols};
    const FileTypes t = types_of(c.type);
    if (c.type != ColumnType::Bytes && value_bytes(c.type) * cols != c.row_bytes)
      throw std::invalid_argument("sphdem: checkpoint column '" + c.name + "': row size mismatch");
    Handle fspace(H5Screate_simple(rank, dims, nullptr), H5Sclose, "create file space", path);
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "create dataset properties", path);
    check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "set fill time", path);
    Handle dset(H5Dcreate2(g.get(), c.name.c_str(), t.file, fspace.get(), H5P_DEFAULT, dcpl.get(),
                           H5P_DEFAULT),
                H5Dclose, "create dataset", path);
    const hsize_t start[2] = {static_cast<hsize_t>(s.first), 0};
    const hsize_t count[2] = {static_cast<hsize_t>(s.n), cols};
    if (s.n > 0)
      check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
            "select rows", path);
    else
      check(H5Sselect_none(fspace.get()), "select no rows", path);
    Handle mspace(H5Screate_simple(rank, count, nullptr), H5Sclose, "create memory space", path);
    if (s.n == 0) check(H5Sselect_none(mspace.get()), "select nothing", path);
    const char none = 0;
    if (s.n_global > 0)
      check(H5Dwrite(dset.get(), t.mem, mspace.get(), fspace.get(), m.dxpl->get(),
                     c.data.empty() ? &none : c.data.data()),
            "write dataset", path);
    h5::write_attribute(dset.get(), "type", static_cast<int>(c.type), path);
    h5::write_attribute(dset.get(), "components", c.components, path);
    h5::write_attribute(dset.get(), "row_bytes", static_cast<std::int64_t>(c.row_bytes), path);
    write_u64_attribute(dset.get(), "checksum", checksum(m.comm, c, s.first), path);
  }
}

void CheckpointWriter::commit() {
  Impl& m = *impl_;
  m.dxpl.reset();
  m.file->close("close file", m.tmp);
  m.file.reset();
  m.comm.barrier();  // every rank's data is in the file
  maybe_abort_for_test();
  std::string error;
  if (m.comm.root()) {
    try {
      fsync_path(m.tmp);
      fs::rename(m.tmp, m.path);
      fsync_path(fs::path(m.path).parent_path().string());
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (m.comm.any(!error.empty()))
    throw std::runtime_error("sphdem: could not publish checkpoint '" + m.path +
                             "': " + (error.empty() ? "rank 0 failed" : error));
  m.committed = true;
}

// ---------------------------------------------------------------- reader

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
    return read_scalar_attribute<double>(impl_->file->get(), name.c_str(), H5T_NATIVE_DOUBLE,
                                         impl_->path);
  });
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
    return v;
  });
}

std::int64_t CheckpointReader::count(const std::string& group) const {
  return collective(impl_->comm, impl_->path, [&] {
    if (H5Lexists(impl_->file->get(), group.c_str(), H5P_DEFAULT) <= 0)
      throw std::runtime_error("the checkpoint has no particle group '" + group + "'");
    Handle g(H5Gopen2(impl_->file->get(), group.c_str(), H5P_DEFAULT), H5Gclose, "open group",
             impl_->path);
    return read_scalar_attribute<std::int64_t>(g.get(), "count", H5T_NATIVE_INT64, impl_->path);
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
  collective(m.comm, m.path, [&] {
    const std::string& path = m.path;
    Handle g(H5Gopen2(m.file->get(), group.c_str(), H5P_DEFAULT), H5Gclose, "open group", path);
    std::vector<std::string> names;
    check(H5Literate(g.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names),
          "list datasets", path);
    Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "create transfer list", path);
    check(H5Pset_dxpl_mpio(dxpl.get(), H5FD_MPIO_COLLECTIVE), "select collective I/O", path);
    for (const std::string& name : names) {
      Handle dset(H5Dopen2(g.get(), name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset", path);
      CheckpointColumn c;
      c.name = name;
      const int type = read_scalar_attribute<int>(dset.get(), "type", H5T_NATIVE_INT, path);
      if (type < 0 || type > static_cast<int>(ColumnType::Bytes))
        throw std::runtime_error("field '" + name + "' has an unknown type");
      c.type = static_cast<ColumnType>(type);
      c.components = read_scalar_attribute<int>(dset.get(), "components", H5T_NATIVE_INT, path);
      c.row_bytes = static_cast<std::size_t>(
          read_scalar_attribute<std::int64_t>(dset.get(), "row_bytes", H5T_NATIVE_INT64, path));
      stored.push_back(
          read_scalar_attribute<std::uint64_t>(dset.get(), "checksum", H5T_NATIVE_UINT64, path));
      const hsize_t cols_in_file = dataset_columns(c);
      Handle fspace(H5Dget_space(dset.get()), H5Sclose, "get dataset space", path);
      hsize_t dims[2] = {0, 1};
      const int rank = H5Sget_simple_extent_ndims(fspace.get());
      if (rank < 1 || rank > 2) throw std::runtime_error("field '" + name + "' has a bad shape");
      H5Sget_simple_extent_dims(fspace.get(), dims, nullptr);
      if (dims[0] != static_cast<hsize_t>(n_global) || (rank == 2 ? dims[1] : 1) != cols_in_file ||
          (c.type != ColumnType::Bytes && value_bytes(c.type) * cols_in_file != c.row_bytes))
        throw std::runtime_error("field '" + name + "' does not match its description");
      c.data.resize(static_cast<std::size_t>(n) * c.row_bytes);
      const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
      const hsize_t count[2] = {static_cast<hsize_t>(n), cols_in_file};
      if (n > 0)
        check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
              "select rows", path);
      else
        check(H5Sselect_none(fspace.get()), "select no rows", path);
      Handle mspace(H5Screate_simple(rank, count, nullptr), H5Sclose, "create memory space", path);
      if (n == 0) check(H5Sselect_none(mspace.get()), "select nothing", path);
      char none = 0;
      if (n_global > 0)
        check(H5Dread(dset.get(), types_of(c.type).mem, mspace.get(), fspace.get(), dxpl.get(),
                      c.data.empty() ? &none : c.data.data()),
              "read dataset", path);
      cols.push_back(std::move(c));
    }
  });
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
