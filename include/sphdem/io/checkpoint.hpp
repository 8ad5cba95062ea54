#pragma once
// Checkpoints (docs/checkpoint.md): the complete state of a run
// in one HDF5 file, written collectively to a temporary name, flushed and
// renamed, and readable on any rank count.
//
// Particle containers (SphParticles, DemParticles, any class with the field
// registry for_each_field / n_owned / gid) go through the two templates
// below: every field whose FieldPolicy.checkpoint is set becomes a column of
// raw bytes, so the HDF5 layer needs no knowledge of the particle types.
// Numbers and Eigen vectors of doubles are stored as typed datasets (h5py
// reads them as they are); any other field (bond and contact slots) as an
// opaque [N][sizeof] byte record whose size is checked on read.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "sphdem/config/case.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/particles/particles.hpp"
#include "sphdem/solver/output_cadence.hpp"

namespace sphdem {

// Bumped whenever the layout or the meaning of a stored value changes; a
// checkpoint of another format is refused.
// 2: the wall particles' wall_to_surface (slip walls).
// 3: the resin's viscosity column (a viscosity law's time step reads it).
// 4: the fibers' hydrodynamic torque state (torque_coeff, resin_spin, ...).
// 5: the resin's weld_line flag (output.front_events).
// 6: the fibers' drag_parcel_mass (fibers.drag_integration: exponential).
inline constexpr int kCheckpointFormat = 6;

enum class ColumnType : int { F64 = 0, I64 = 1, I32 = 2, U8 = 3, Bytes = 4 };

// One per-particle field, its rows as raw bytes.
struct CheckpointColumn {
  std::string name;
  ColumnType type = ColumnType::Bytes;
  int components = 1;         // numbers per row (numeric types)
  std::size_t row_bytes = 0;  // sizeof one row in memory
  std::vector<char> data;     // rows * row_bytes
  std::size_t rows() const { return row_bytes ? data.size() / row_bytes : 0; }
};

namespace detail {

template <class T>
constexpr ColumnType column_type() {
  if constexpr (std::is_enum_v<T>) {
    return column_type<std::underlying_type_t<T>>();
  } else if constexpr (std::is_same_v<T, double> || IsDoubleVector<T>::value) {
    return ColumnType::F64;
  } else if constexpr (std::is_same_v<T, std::int64_t>) {
    return ColumnType::I64;
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    return ColumnType::I32;
  } else if constexpr (std::is_same_v<T, std::uint8_t>) {
    return ColumnType::U8;
  } else {
    return ColumnType::Bytes;
  }
}

template <class T>
constexpr int column_components() {
  if constexpr (IsDoubleVector<T>::value) return T::SizeAtCompileTime;
  return 1;
}

}  // namespace detail

// The checkpointed fields of particles [0, n_owned), in registry order. A
// dropped field (one the case's options do not use) is written as zeros,
// its value when it was always held, so the format does not depend on the
// options (docs/checkpoint.md).
template <class P>
std::vector<CheckpointColumn> checkpoint_columns(const P& ps) {
  std::vector<CheckpointColumn> out;
  ps.for_each_declared_field([&](const char* name, auto& field, FieldPolicy p) {
    if (!p.checkpoint) return;
    using T = typename std::decay_t<decltype(field)>::value_type;
    CheckpointColumn c{
        name, detail::column_type<T>(), detail::column_components<T>(), sizeof(T), {}};
    c.data.assign(ps.n_owned * sizeof(T), char{0});
    if (ps.n_owned > 0 && ps.has_field(name))
      std::memcpy(c.data.data(), static_cast<const void*>(field.data()), c.data.size());
    out.push_back(std::move(c));
  });
  return out;
}

// Replaces the particles by `rows` owned ones taken from `cols` (matched by
// name; every checkpointed field must be there, with this build's type and
// row size). Fields that are not checkpointed are value-initialised; the
// column of a dropped field is read past. Throws
// InputError naming `file` on any mismatch (every rank reads the same
// header, so every rank throws).
template <class P>
void assign_checkpoint_columns(P& ps, const std::vector<CheckpointColumn>& cols, std::size_t rows,
                               const std::string& file) {
  ps.resize(0);
  ps.resize(rows);
  ps.n_owned = rows;
  std::size_t used = 0;
  const auto visit = [&](const char* name, auto& field, FieldPolicy p) {
    if (!p.checkpoint) return;
    using T = typename std::decay_t<decltype(field)>::value_type;
    const CheckpointColumn* c = nullptr;
    for (const CheckpointColumn& k : cols)
      if (k.name == name) c = &k;
    if (!c)
      throw InputError(file, 0, "",
                       std::string("the checkpoint has no field '") + name +
                           "': it was written by an incompatible build of sphdem");
    if (c->row_bytes != sizeof(T) || c->type != detail::column_type<T>())
      throw InputError(file, 0, "",
                       "field '" + c->name + "' has " + std::to_string(c->row_bytes) +
                           "-byte records, this build expects " + std::to_string(sizeof(T)) +
                           ": the checkpoint was written by an incompatible build of sphdem");
    if (rows > 0 && field.size() == rows)
      std::memcpy(static_cast<void*>(field.data()), c->data.data(), rows * sizeof(T));
    ++used;
  };
  P::visit_fields(ps, visit, true);
  if (used != cols.size())
    throw InputError(file, 0, "",
                     "the checkpoint has fields this build does not know: it was written by an "
                     "incompatible build of sphdem");
}

// Writes one checkpoint file: <path>.tmp first, renamed to <path> by
// commit(). Every call is collective; every rank passes the same names and
// values (attributes) and its own particles. An uncommitted writer removes
// its temporary file when destroyed.
class CheckpointWriter {
 public:
  CheckpointWriter(const Comm& comm, std::string path);
  ~CheckpointWriter();
  CheckpointWriter(const CheckpointWriter&) = delete;
  CheckpointWriter& operator=(const CheckpointWriter&) = delete;

  void attribute(const std::string& name, double v);
  void attribute(const std::string& name, std::int64_t v);
  void attribute(const std::string& name, const std::string& v);
  void attribute(const std::string& name, const std::vector<double>& v);

  // Group `group` holds the columns in global-id order (the column named
  // "gid", int64, whose values over all ranks must be a dense range), each
  // with a checksum. Ranks first exchange rows so that each holds a
  // contiguous slice of ids, then write one hyperslab per column.
  void particles(const std::string& group, const std::vector<CheckpointColumn>& columns);

  // Closes the file, flushes it to disk and renames it to its final name:
  // the checkpoint is then complete, or (after a crash) absent.
  void commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Reads a checkpoint; any failure (unreadable, truncated, corrupt, another
// format) is an InputError naming the file, thrown on every rank.
class CheckpointReader {
 public:
  CheckpointReader(const Comm& comm, std::string path);
  ~CheckpointReader();
  CheckpointReader(const CheckpointReader&) = delete;
  CheckpointReader& operator=(const CheckpointReader&) = delete;

  const std::string& path() const;
  // Scalar attributes. A real must be finite (every stored real is); a
  // checkpoint is input: an attribute edited to garbage is refused.
  double real(const std::string& name) const;
  std::int64_t integer(const std::string& name) const;
  // The same, refused (InputError naming the file and the attribute) when
  // outside [lo, hi] (for reals (lo, hi] with `lo_open`).
  std::int64_t integer_in(const std::string& name, std::int64_t lo, std::int64_t hi) const;
  double real_in(const std::string& name, double lo, double hi, bool lo_open = false) const;
  std::string text(const std::string& name) const;
  std::vector<double> reals(const std::string& name) const;

  // The total particle count of a group (>= 0), and this rank's contiguous slice of
  // its rows in global-id order (a balanced share), checksums verified;
  // with `all_rows`, every row on every rank (for drivers that start from
  // the whole set, as DemDomain does).
  std::int64_t count(const std::string& group) const;
  std::vector<CheckpointColumn> particles(const std::string& group, bool all_rows = false) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The rows of particle group `group` (e.g. "sph", "dem") this process has
// read from checkpoints since it started: every CheckpointReader::particles
// call adds the rows it read. A restart on P ranks reads about N / P of each
// group per rank (docs/checkpoint.md "At scale"; tests/test_restart_share.cpp).
std::int64_t checkpoint_rows_read(const std::string& group);

// Moves the column named `name` out of `cols` (InputError naming `file` if absent).
CheckpointColumn take_column(std::vector<CheckpointColumn>& cols, const std::string& name,
                             const std::string& file);

// Where checkpoints live: <output>/checkpoints/<case>_<step:08d>.ckpt.h5.
std::string checkpoint_directory(const std::string& output_dir);
std::string checkpoint_path(const std::string& output_dir, const std::string& case_name,
                            std::int64_t step);
// The checkpoints of a case in an output directory, oldest first (by step).
std::vector<std::pair<std::int64_t, std::string>> list_checkpoints(const std::string& output_dir,
                                                                   const std::string& case_name);
// Rank 0 deletes all but the newest `keep`, and stale temporary files.
void prune_checkpoints(const Comm& comm, const std::string& output_dir,
                       const std::string& case_name, int keep);

// The checkpoint a restart uses: `spec` is a path, or "latest" (the newest
// of the case in the output directory). Calls load(path) on it; with
// "latest", a checkpoint whose load throws InputError is skipped (logged on
// rank 0 to `log` when given) and the next older one tried. Returns the
// path loaded; InputError when there is none.
std::string restart_from_checkpoint(const std::string& spec, const std::string& output_dir,
                                    const std::string& case_name, const Comm& comm,
                                    std::ostream* log,
                                    const std::function<void(const std::string&)>& load);

// Collective: rank 0 deletes the temporary files of checkpoint writes that
// never finished (a crash, an abort). A restart calls it first, so they go
// even when the restart is then refused.
void remove_stale_checkpoint_temporaries(const Comm& comm, const std::string& output_dir,
                                         const std::string& case_name);

// A restart at `step` abandons what the run did after it: rank 0 deletes
// the checkpoints of later steps (a later `--restart latest` must not jump
// back into that abandoned future, whose snapshots are gone) and stale
// temporary files.
void discard_checkpoints_after(const Comm& comm, const std::string& output_dir,
                               const std::string& case_name, std::int64_t step);

// What identifies the case a checkpoint belongs to: every key that changes
// the state a run evolves, one "key = value" line each (output, end_time,
// parallel and checkpoint keys may change between restarts). Keys added to
// Case that change the physics belong here too.
std::vector<std::string> case_identity(const Case& c);
std::string case_identity_text(const Case& c);  // the lines, each ending in '\n'
// Throws InputError naming `file` when the stored identity differs from the
// case's, listing the keys that differ.
void check_case_identity(const Case& c, const std::string& stored, const std::string& file);

// The output cadence of a run resumed at `time`: it next writes when an
// uninterrupted run from t = 0 would (the same chain of additions of
// every_time, so the same doubles). At time 0, the plain cadence.
inline OutputCadence resumed_output_cadence(const Output& out, double time) {
  const double every = out.every_time.value_or(0.0);
  double base = 0;
  if (every > 0) {
    // The chain, unless absurdly long (an interval the app refuses, as
    // 1e-300 s: OutputCadence::due does the same).
    if (time / every > 1e9) return OutputCadence(out, std::floor(time / every) * every);
    for (double next = every; next <= time * (1 + 1e-12); next += every) base = next;
  }
  return OutputCadence(out, base);
}

// When to write a checkpoint after a step: every N steps (case file or
// --checkpoint-every), every M wall-clock minutes, and at once when a stop
// was requested (SIGTERM, SIGUSR1) on any rank. Collective: the wall clock
// of rank 0 decides, and a request on any rank stops every rank.
class CheckpointCadence {
 public:
  CheckpointCadence(const CheckpointSettings& s, std::optional<std::int64_t> every_steps,
                    std::function<bool()> stop_requested);
  // A cadence is set (a final checkpoint is due at the end of the run).
  bool enabled() const { return every_steps_ > 0 || every_seconds_ > 0; }
  struct Decision {
    bool write = false;
    bool stop = false;
  };
  Decision after_step(const Comm& comm, std::int64_t step) const;
  void written();  // restarts the wall clock
  int keep() const { return keep_; }

 private:
  std::int64_t every_steps_ = 0;
  double every_seconds_ = 0;
  int keep_ = 2;
  std::function<bool()> stop_;
  double last_ = 0;  // steady-clock seconds at the last checkpoint (or the start)
};

}  // namespace sphdem
