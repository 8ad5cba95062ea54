// CheckpointWriter (checkpoint.hpp): writes the HDF5 file of a checkpoint
// collectively, column by column, and publishes it by an atomic rename.
// Layout (docs/checkpoint.md):
//   /            attributes: format, sphdem_version and the run's scalars
//   /<group>/    attributes count, id_min; one dataset per column, rows in
//                global-id order, each with attributes type, components,
//                row_bytes and checksum
// The checksum of a column is the sum (mod 2^64) over its rows of a hash of
// (row index, row bytes): ranks add their slices in any order and agree,
// and a single changed byte anywhere in the data changes it. HDF5's own
// metadata checksums (latest file format) guard the rest of the file.
// Every call that can fail runs inside `agree` (io_agreement.hpp): a write
// that fails on one rank (a full disk) throws CollectiveIoError on every rank
// at the same point, and the temporary file is removed.
#include <algorithm>
#include <climits>
#include <filesystem>
#include <stdexcept>

#include "checkpoint_format.hpp"
#include "io_agreement.hpp"
#include "sphdem/core/fault.hpp"

namespace sphdem {

namespace {

namespace fs = std::filesystem;
using namespace checkpoint_io;

}  // namespace

struct CheckpointWriter::Impl {
  Comm comm;
  std::string path, tmp;
  QuietHdf5 quiet;
  std::optional<io::Agreement<>> agree;
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
  m.agree.emplace(m.comm, "checkpoint '" + m.path + "'");
  (*m.agree)([&] {
    if (!comm.root()) return;
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec)
      throw std::runtime_error("cannot create '" + p.parent_path().string() + "': " + ec.message());
  });
  (*m.agree)([&] {
    Handle fapl = file_access(comm, m.tmp);
    m.file.emplace(H5Fcreate(m.tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose,
                   "create file", m.tmp);
  });
  (*m.agree)([&] {
    m.dxpl.emplace(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "create transfer list", m.tmp);
    check(H5Pset_dxpl_mpio(m.dxpl->get(), H5FD_MPIO_COLLECTIVE), "select collective I/O", m.tmp);
    h5::write_attribute(m.file->get(), "format", std::int64_t{kCheckpointFormat}, m.tmp);
    h5::write_attribute(m.file->get(), "sphdem_version", std::string(SPHDEM_VERSION), m.tmp);
  });
}

CheckpointWriter::~CheckpointWriter() {
  if (!impl_ || impl_->committed) return;
  // Only after an error every rank threw (a one-rank error aborts the job
  // before anything unwinds, docs/architecture.md "Errors").
  impl_->dxpl.reset();
  io::close_failed_file(impl_->comm, impl_->tmp, impl_->file);
  if (impl_->comm.root()) {
    std::error_code ec;
    fs::remove(impl_->tmp, ec);
  }
}

void CheckpointWriter::attribute(const std::string& name, double v) {
  Impl& m = *impl_;
  (*m.agree)([&] { h5::write_attribute(m.file->get(), name.c_str(), v, m.tmp); });
}
void CheckpointWriter::attribute(const std::string& name, std::int64_t v) {
  Impl& m = *impl_;
  (*m.agree)([&] { h5::write_attribute(m.file->get(), name.c_str(), v, m.tmp); });
}
void CheckpointWriter::attribute(const std::string& name, const std::string& v) {
  Impl& m = *impl_;
  (*m.agree)([&] { h5::write_attribute(m.file->get(), name.c_str(), v, m.tmp); });
}
void CheckpointWriter::attribute(const std::string& name, const std::vector<double>& v) {
  Impl& m = *impl_;
  (*m.agree)([&] {
    const std::string& path = m.tmp;
    const hsize_t n = v.size();
    Handle space(n == 0 ? H5Screate(H5S_NULL) : H5Screate_simple(1, &n, nullptr), H5Sclose,
                 "create attribute space", path);
    Handle attr(H5Acreate2(m.file->get(), name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                           H5P_DEFAULT),
                H5Aclose, "create attribute", path);
    if (n > 0) check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, v.data()), "write attribute", path);
  });
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

  const io::Agreement<>& agree = *m.agree;
  std::optional<Handle> g;
  agree([&] {
    g.emplace(H5Gcreate2(m.file->get(), group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Gclose, "create group", path);
    h5::write_attribute(g->get(), "count", s.n_global, path);
    h5::write_attribute(g->get(), "id_min", s.id_min, path);
  });
  for (const CheckpointColumn& c : s.columns) {
    const hsize_t cols = dataset_columns(c);
    const int rank = cols == 1 ? 1 : 2;
    const hsize_t dims[2] = {static_cast<hsize_t>(s.n_global), cols};
    const FileTypes t = types_of(c.type);
    if (c.type != ColumnType::Bytes && value_bytes(c.type) * cols != c.row_bytes)
      throw std::invalid_argument("sphdem: checkpoint column '" + c.name + "': row size mismatch");
    std::optional<Handle> fspace, dset, mspace;
    const hsize_t start[2] = {static_cast<hsize_t>(s.first), 0};
    const hsize_t count[2] = {static_cast<hsize_t>(s.n), cols};
    agree([&] {
      fspace.emplace(H5Screate_simple(rank, dims, nullptr), H5Sclose, "create file space", path);
      Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "create dataset properties", path);
      check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "set fill time", path);
      dset.emplace(H5Dcreate2(g->get(), c.name.c_str(), t.file, fspace->get(), H5P_DEFAULT,
                              dcpl.get(), H5P_DEFAULT),
                   H5Dclose, "create dataset", path);
      if (s.n > 0)
        check(H5Sselect_hyperslab(fspace->get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
              "select rows", path);
      else
        check(H5Sselect_none(fspace->get()), "select no rows", path);
      mspace.emplace(H5Screate_simple(rank, count, nullptr), H5Sclose, "create memory space", path);
      if (s.n == 0) check(H5Sselect_none(mspace->get()), "select nothing", path);
    });
    const char none = 0;
    agree([&] {
      if (s.n_global > 0)
        check(H5Dwrite(dset->get(), t.mem, mspace->get(), fspace->get(), m.dxpl->get(),
                       c.data.empty() ? &none : c.data.data()),
              "write dataset", path);
      // Testing hook (fault.hpp): the write failed on this rank alone.
      inject_io_fault(FaultKind::CheckpointWrite, m.comm.rank(), current_step(), path);
    });
    // A reduction: outside `agree`, which every rank leaves together.
    const std::uint64_t sum = checksum(m.comm, c, s.first);
    agree([&] {
      h5::write_attribute(dset->get(), "type", static_cast<int>(c.type), path);
      h5::write_attribute(dset->get(), "components", c.components, path);
      h5::write_attribute(dset->get(), "row_bytes", static_cast<std::int64_t>(c.row_bytes), path);
      write_u64_attribute(dset->get(), "checksum", sum, path);
    });
  }
}

void CheckpointWriter::commit() {
  Impl& m = *impl_;
  m.dxpl.reset();
  // H5Fclose is where buffered data and metadata reach the file system:
  // its failure is a failed checkpoint too. The agreement is also the
  // barrier: every rank's data is in the file after it.
  (*m.agree)([&] { m.file->close("close file", m.tmp); });
  m.file.reset();
  maybe_abort_for_test();
  (*m.agree)([&] {
    if (!m.comm.root()) return;
    fsync_path(m.tmp, /*required=*/true);
    fs::rename(m.tmp, m.path);
    fsync_path(fs::path(m.path).parent_path().string());
  });
  m.committed = true;
}

}  // namespace sphdem
