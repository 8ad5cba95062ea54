#pragma once
// Private to src/io: failure agreement for the collective I/O paths
// (snapshot, XDMF, checkpoint write, restart read; docs/checkpoint.md,
// "Guarantees"). Parallel HDF5 needs every rank to make the same sequence of
// calls: a rank whose call fails (a full disk) and that skipped ahead would
// leave the others waiting in the next collective call, or in a checksum's
// reduction, for good. So every call that can fail for a reason of the file
// system runs inside `agree`: each rank catches its own error, and one
// reduction later every rank knows whether any failed and throws the same
// error (the first failing rank's cause) at the same point. The unwinding is
// then the same on every rank, so the collective H5Fclose of the file handles
// is too.
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include <unistd.h>

#include "hdf5_helpers.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/agreement.hpp"
#include "sphdem/parallel/comm.hpp"

namespace sphdem::io {

// `Error` is what every rank throws: CollectiveIoError for writes (`what`
// names the operation and its file: "checkpoint 'out/c/x.ckpt.h5'"), or
// InputError, a refused checkpoint, for the restart read (`what` is the path).
template <class Error = CollectiveIoError>
class Agreement {
 public:
  Agreement(const Comm& comm, std::string what) : comm_(comm), what_(std::move(what)) {}

  // Runs f on this rank, then agrees (one reduction): if f threw on any
  // rank, every rank throws Error. Returns what f returns.
  template <class F>
  auto operator()(F&& f) const -> decltype(f()) {
    std::optional<std::string> error;
    if constexpr (std::is_void_v<decltype(f())>) {
      try {
        f();
      } catch (const std::exception& e) {
        error = e.what();
      }
      settle(error);
    } else {
      decltype(f()) out{};
      try {
        out = f();
      } catch (const std::exception& e) {
        error = e.what();
      }
      settle(error);
      return out;
    }
  }

  // The agreement itself, for a failure found without an exception.
  void settle(const std::optional<std::string>& error) const {
    const std::optional<RankFailure> failed = first_failure(comm_, error);
    if (!failed) return;
    const std::string cause =
        failed->message.rfind("sphdem: ", 0) == 0 ? failed->message.substr(8) : failed->message;
    // Every rank is here: one more reduction tells whether the cause is
    // one rank's (named) or every rank's (a corrupt file).
    const bool everywhere = comm_.sum(static_cast<std::int64_t>(error ? 1 : 0)) == comm_.size();
    const std::string where =
        everywhere ? std::string() : " on rank " + std::to_string(failed->rank);
    if constexpr (std::is_same_v<Error, InputError>)
      throw InputError(what_, 0, "", (where.empty() ? "" : where.substr(1) + ": ") + cause);
    else
      throw Error(what_ + " failed" + where + ": " + cause);
  }

 private:
  const Comm& comm_;
  std::string what_;
};

// Closes a file whose collective write failed (every rank calls it, after
// the agreement). Its content is lost anyway, so rank 0 first empties it:
// on a full disk the close's metadata flush then finds room. Otherwise the
// flush fails on some ranks only, and HDF5's ranks part ways inside
// H5Fclose (one waiting in a metadata sync point, another in the file's
// truncation), for good.
inline void close_failed_file(const Comm& comm, const std::string& path,
                              std::optional<h5::Handle>& file) {
  if (!file) return;
  if (comm.root()) (void)::truncate(path.c_str(), 0);
  comm.barrier();
  file.reset();
}

}  // namespace sphdem::io
