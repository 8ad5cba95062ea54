// The checkpoint file's format helpers (checkpoint_format.hpp): checksums,
// HDF5 types, file access and attributes, the commit's test hook.
#include "checkpoint_format.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace sphdem::checkpoint_io {

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

std::int64_t slice_first(std::int64_t n, int p, int r) {
  // floor(n r / p) without overflowing n r.
  return n / p * r + (n % p) * r / p;
}

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

void maybe_abort_for_test() {
  static int commits = 0;
  ++commits;
  const char* k = std::getenv("SPHDEM_TEST_ABORT_IN_CHECKPOINT");
  if (k && std::atoi(k) == commits) std::raise(SIGKILL);
}

void fsync_path(const std::string& path, bool required) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) {
    if (!required) return;  // a directory: best effort, the rename is what makes it atomic
    throw std::runtime_error(fmt::format("cannot open '{}': {}", path, std::strerror(errno)));
  }
  // A full disk may show only here (delayed allocation): then the data is
  // not on disk, and the file must not replace a good checkpoint.
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && required && err != EINVAL)
    throw std::runtime_error(fmt::format("fsync of '{}' failed: {}", path, std::strerror(err)));
}

}  // namespace sphdem::checkpoint_io
