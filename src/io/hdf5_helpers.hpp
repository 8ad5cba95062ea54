#pragma once
// Private to src/io: RAII ownership of HDF5 identifiers and a return-code
// check that turns any HDF5 failure into std::runtime_error naming the file,
// so no call's result is silently ignored.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>

namespace sphdem::h5 {

// Throws std::runtime_error("sphdem: HDF5 <what> failed for '<path>': <detail>"),
// where detail is the innermost message of HDF5's error stack.
[[noreturn]] void fail(const std::string& what, const std::string& path);

// HDF5 returns a negative hid_t or herr_t on failure.
template <class T>
T check(T rc, const char* what, const std::string& path) {
  if (rc < 0) fail(what, path);
  return rc;
}

// Owns one identifier and closes it with the matching H5?close. Closing a
// file is collective in parallel HDF5, so handles go out of scope in the
// same order on every rank.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer close, const char* what, const std::string& path)
      : id_(check(id, what, path)), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&&) = delete;
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }
  // Closes now and reports failure (a destructor cannot): H5Fclose is where
  // buffered metadata reaches the disk.
  void close(const char* what, const std::string& path) {
    check(close_(std::exchange(id_, H5I_INVALID_HID)), what, path);
  }

 private:
  hid_t id_;
  Closer close_;
};

// Scalar attributes on a file, group or dataset (collective: same value on
// every rank).
void write_attribute(hid_t obj, const char* name, double value, const std::string& path);
void write_attribute(hid_t obj, const char* name, std::int64_t value, const std::string& path);
void write_attribute(hid_t obj, const char* name, int value, const std::string& path);
void write_attribute(hid_t obj, const char* name, const std::string& value,
                     const std::string& path);

}  // namespace sphdem::h5
