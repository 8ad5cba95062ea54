#pragma once
// The checkpoint file's format helpers shared by its writer and reader
// (checkpoint_writer.cpp, checkpoint_reader.cpp; docs/checkpoint.md): column
// checksums, HDF5 types and attributes, the collective-error rule.
#include <fmt/format.h>
#include <hdf5.h>

#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "hdf5_helpers.hpp"
#include "io_agreement.hpp"
#include "sphdem/io/checkpoint.hpp"

namespace sphdem::checkpoint_io {

using h5::check;
using h5::Handle;

// Hash of one row (its index and bytes); a column's checksum sums them.
std::uint64_t row_hash(std::uint64_t row, const char* p, std::size_t n);

// The checksum of a column over every rank, this rank's rows starting at
// first_row.
std::uint64_t checksum(const Comm& comm, const CheckpointColumn& c, std::int64_t first_row);

// First row of rank r's slice of n rows over p ranks (balanced).
std::int64_t slice_first(std::int64_t n, int p, int r);

struct FileTypes {
  hid_t file, mem;
};

FileTypes types_of(ColumnType t);

// Columns of a dataset: numbers per row for numeric types, bytes for records.
hsize_t dataset_columns(const CheckpointColumn& c);

std::size_t value_bytes(ColumnType t);

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

Handle file_access(const Comm& comm, const std::string& path);

void write_u64_attribute(hid_t obj, const char* name, std::uint64_t v, const std::string& path);

template <class T>
T read_scalar_attribute(hid_t obj, const char* name, hid_t mem, const std::string& path) {
  if (H5Aexists(obj, name) <= 0)
    throw std::runtime_error(fmt::format("attribute '{}' is missing", name));
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, "open attribute", path);
  T v{};
  check(H5Aread(attr.get(), mem, &v), "read attribute", path);
  return v;
}

std::string read_string_attribute(hid_t obj, const char* name, const std::string& path);

// Runs `f` on every rank; if it throws on any rank, every rank throws an
// InputError naming the file and the first failing rank's cause
// (io_agreement.hpp). `f` must not communicate: a rank that failed in it
// would skip what the others wait for.
template <class F>
auto collective(const Comm& comm, const std::string& path, F&& f) -> decltype(f()) {
  return io::Agreement<InputError>(comm, path)(std::forward<F>(f));
}

// The test hook of docs/checkpoint.md: SPHDEM_TEST_ABORT_IN_CHECKPOINT=K
// kills the process in its K-th commit, after the data is written and before
// the rename, as a node failure would.
void maybe_abort_for_test();

// fsync of a file or directory; throws std::runtime_error when `required`
// and it fails (otherwise best effort).
void fsync_path(const std::string& path, bool required = false);

}  // namespace sphdem::checkpoint_io
