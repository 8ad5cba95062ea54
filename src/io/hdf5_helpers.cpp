#include "hdf5_helpers.hpp"

#include <sys/statvfs.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace sphdem::h5 {

namespace {
// H5Ewalk2 callback: keeps the first (innermost) description, which is the
// specific cause ("unable to open file ... errno = 13") rather than the
// generic API-level message.
herr_t keep_innermost(unsigned n, const H5E_error2_t* err, void* out) {
  if (n == 0 && err != nullptr && err->desc != nullptr) *static_cast<std::string*>(out) = err->desc;
  return 0;
}

// The errno of MPI-IO's failing write is gone by the time HDF5 returns; a
// file system with no block left for the user says why instead.
bool disk_full(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  struct statvfs fs {};
  return statvfs(dir.c_str(), &fs) == 0 && fs.f_bavail == 0;
}

void write_scalar(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, const void* value,
                  const std::string& path) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "create attribute space", path);
  Handle attr(H5Acreate2(obj, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "create attribute", path);
  check(H5Awrite(attr.get(), mem_type, value), "write attribute", path);
}
}  // namespace

void fail(const std::string& what, const std::string& path) {
  // Through MPI-IO HDF5 says only "file write failed"; the system call's
  // errno is still there. Only errors a write can cause are named, so a
  // stale errno from an unrelated call never passes for the cause.
  const int err = errno;
  std::string detail;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keep_innermost, &detail);
  std::string msg = "sphdem: HDF5 " + what + " failed for '" + path + "'";
  if (!detail.empty()) msg += ": " + detail;
  const bool write_errno = err == ENOSPC || err == EDQUOT || err == EFBIG || err == EIO;
  if (write_errno && detail.find(std::strerror(err)) == std::string::npos) {
    msg += std::string(" (") + std::strerror(err) + ")";
  } else if (disk_full(path)) {
    msg += std::string(" (") + std::strerror(ENOSPC) + ": the file system holding it is full)";
  }
  throw std::runtime_error(msg);
}

void write_attribute(hid_t obj, const char* name, double value, const std::string& path) {
  write_scalar(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value, path);
}

void write_attribute(hid_t obj, const char* name, std::int64_t value, const std::string& path) {
  write_scalar(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value, path);
}

void write_attribute(hid_t obj, const char* name, int value, const std::string& path) {
  write_scalar(obj, name, H5T_STD_I32LE, H5T_NATIVE_INT, &value, path);
}

void write_attribute(hid_t obj, const char* name, const std::string& value,
                     const std::string& path) {
  // Fixed-length, NUL-terminated UTF-8: readable by h5py, h5dump and ParaView
  // without variable-length memory management.
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy string type", path);
  check(H5Tset_size(type.get(), value.size() + 1), "set string size", path);
  check(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), "set string padding", path);
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set string charset", path);
  write_scalar(obj, name, type.get(), type.get(), value.c_str(), path);
}

}  // namespace sphdem::h5
