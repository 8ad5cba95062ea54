#pragma once
// The field registry of the particle containers (SphParticles, DemParticles;
// docs/architecture.md, "Adding a field"). A container lists its
// per-particle fields once, one line each,
//   X(type, member, policy)
// and SPHDEM_FIELD_REGISTRY(LIST) makes of the list the members
// (std::vector<type> member) and for_each_field(f), which calls
// f("member", vector, policy) in list order. Everything that handles
// particles generically reads the policy: the halo build and its per-step
// forward(group), migration, checkpoints, snapshots and the partition
// report's byte counts. The list order is the record order of migration and
// halo messages and the column order of checkpoints.
//
// A policy combines flags with `|`:
//   kGhost           copied to the ghosts when the halo is built
//   in_group(G)      refreshed on the ghosts by the halo's forward(G), one of
//                    the container's per-step exchange groups
//   kShifted         a position: a copy across a periodic face gains the period
//   kMigrate         travels with a particle that changes rank
//   kCheckpoint      part of the restartable state
//   output_as(n, u)  can be written to snapshots as dataset n, unit u
//   kLocal           none of these: scratch of the rank that owns it
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace sphdem {

// What happens to one field (see above).
struct FieldPolicy {
  bool ghost = false;
  bool migrate = false;
  bool checkpoint = false;
  bool shifted = false;
  std::uint32_t groups = 0;      // bit g: refreshed by forward(group g)
  const char* output = nullptr;  // dataset name; null: never written
  const char* unit = nullptr;    // unit of the dataset (in the XDMF)

  constexpr bool in(std::uint32_t group_bits) const { return (groups & group_bits) != 0; }
};

constexpr FieldPolicy operator|(FieldPolicy a, const FieldPolicy& b) {
  a.ghost = a.ghost || b.ghost;
  a.migrate = a.migrate || b.migrate;
  a.checkpoint = a.checkpoint || b.checkpoint;
  a.shifted = a.shifted || b.shifted;
  a.groups |= b.groups;
  if (b.output) a.output = b.output;
  if (b.unit) a.unit = b.unit;
  return a;
}

inline constexpr FieldPolicy kGhost{.ghost = true};
inline constexpr FieldPolicy kMigrate{.migrate = true};
inline constexpr FieldPolicy kCheckpoint{.checkpoint = true};
inline constexpr FieldPolicy kShifted{.shifted = true};
inline constexpr FieldPolicy kLocal{};  // none of the above: only its rank sees it

// The bit of an exchange group (an enum class of the container: SphGroup,
// DemGroup).
template <class Group>
constexpr std::uint32_t group_bit(Group g) {
  return std::uint32_t{1} << static_cast<unsigned>(g);
}

template <class Group>
constexpr FieldPolicy in_group(Group g) {
  return FieldPolicy{.groups = group_bit(g)};
}

constexpr FieldPolicy output_as(const char* name, const char* unit) {
  return FieldPolicy{.output = name, .unit = unit};
}

// Eigen fixed-size vectors of doubles (positions, velocities, spins).
template <class T, class = void>
struct IsDoubleVector : std::false_type {};
template <class T>
struct IsDoubleVector<T, std::void_t<typename T::Scalar, decltype(T::SizeAtCompileTime)>>
    : std::bool_constant<std::is_same_v<typename T::Scalar, double> && (T::SizeAtCompileTime > 0) &&
                         sizeof(T) == sizeof(double) * T::SizeAtCompileTime> {};

// The zero of a field's type (Eigen's default constructor leaves vectors
// uninitialised).
template <class T>
T zero_value() {
  if constexpr (IsDoubleVector<T>::value) {
    return T::Zero();
  } else {
    return T{};
  }
}

// Bytes per particle of the fields `want` (a test on the policy) selects:
// one record of a migration or halo message.
template <class P, class Want>
std::size_t record_bytes(const P& ps, Want want) {
  std::size_t bytes = 0;
  ps.for_each_field([&](const char*, const auto& field, FieldPolicy p) {
    if (want(p)) bytes += sizeof(typename std::decay_t<decltype(field)>::value_type);
  });
  return bytes;
}

// The widest element of the fields ps holds, in bytes: a field's share of
// the scratch that permute_owned_fields can use.
template <class P>
std::size_t widest_field(const P& ps) {
  std::size_t bytes = 0;
  ps.for_each_field([&](const char*, const auto& field, FieldPolicy) {
    bytes = std::max(bytes, sizeof(typename std::decay_t<decltype(field)>::value_type));
  });
  return bytes;
}

// Reorders the first order.size() particles of any registry container
// (SPH or DEM): new slot k holds old particle order[k]. `order` is either
// increasing (the particles that stay at a migration) or a permutation of
// 0 .. order.size()-1 (the sort by cell); anything else is a logic error.
// In place, so the fields keep their memory across rebuilds (no fresh
// vectors, no page faults; docs/performance.md, "Rebuilds"): an increasing
// list is compacted forward. A permutation is gathered into `spare` and
// copied back when spare holds order.size() elements of the field (the
// sort by cell passes the pair loop's idle record buffer,
// sphdem/core/scratch.hpp): independent loads, where following it cycle by
// cycle chains each load on the one before (docs/performance.md, "The
// rebuild's sorts"). Otherwise it is followed cycle by cycle.
// Index: std::size_t, or std::int32_t (the sort by cell's, half the scratch).
template <class P, class Index>
void permute_owned_fields(P& ps, std::span<const Index> order, std::span<std::byte> spare = {}) {
  static_assert(std::is_integral_v<Index>);
  const std::size_t m = order.size();
  const auto at = [&](std::size_t k) { return static_cast<std::size_t>(order[k]); };
  const bool increasing = std::is_sorted(order.begin(), order.end());
  thread_local std::vector<bool> done;
  if (!increasing) {
    done.assign(m, false);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t j = at(k);  // a negative index wraps to a large one
      if (j >= m || done[j]) throw std::logic_error("sphdem: permute_owned: not a permutation");
      done[j] = true;
    }
  }
  ps.for_each_field([&](const char*, auto& field, FieldPolicy) {
    using T = typename std::decay_t<decltype(field)>::value_type;
    static_assert(std::is_trivially_destructible_v<T>);
    if (increasing) {
      // order[k] >= k: slot order[k] is read before anything overwrites it.
      for (std::size_t k = 0; k < m; ++k) field[k] = field[at(k)];
      return;
    }
    void* room = spare.data();
    std::size_t space = spare.size();
    if (m > 0 && std::align(alignof(T), m * sizeof(T), room, space) != nullptr) {
      T* const gathered = static_cast<T*>(room);
      for (std::size_t k = 0; k < m; ++k) new (gathered + k) T(field[at(k)]);
      std::copy(gathered, gathered + m, field.begin());
      return;
    }
    done.assign(m, false);
    for (std::size_t s = 0; s < m; ++s) {
      if (done[s]) continue;
      const auto first = field[s];
      std::size_t k = s;
      for (std::size_t j = at(k); j != s; k = j, j = at(k)) {
        field[k] = field[j];
        done[k] = true;
      }
      field[k] = first;
      done[k] = true;
    }
  });
}

template <class P, class Index>
void permute_owned_fields(P& ps, const std::vector<Index>& order) {
  permute_owned_fields(ps, std::span<const Index>(order));
}

// Grows a field by a small margin instead of doubling (std::vector's
// growth): the particle containers grow one particle at a time at set-up
// and by the ghosts at every rebuild, and a doubled capacity is memory the
// run never uses (docs/performance.md, "Memory per particle").
template <class V>
void resize_field(V& field, std::size_t n) {
  if (n > field.capacity()) field.reserve(n + n / 16 + 64);
  field.resize(n);
}

}  // namespace sphdem

// Expanded inside a container by SPHDEM_FIELD_REGISTRY (the `policy`
// argument is an expression of the flags above). `k` counts the fields in
// list order: bit k of `absent_fields_` marks field k as dropped.
#define SPHDEM_FIELD_MEMBER(type, member, policy) std::vector<type> member;
#define SPHDEM_FIELD_COUNT(type, member, policy) +1
#define SPHDEM_FIELD_VISIT(type, member, policy)                                    \
  if (all || !((self.absent_fields_ >> k) & 1u)) f(#member, self.member, (policy)); \
  ++k;

// The members of the list and the registry functions over them:
// for_each_field (const and not), resize, copy_particle (every field of
// slot src onto slot dst) and zero_particle (every field of slot i zero).
// A field can be dropped (drop_field): its vector stays empty and every
// registry function skips it (halo, migration, snapshots, the reserve of
// the set-up), so a case pays memory only for the fields its options use
// (docs/performance.md, "Memory per particle"). for_each_declared_field
// visits every field of the list, dropped or not (checkpoints keep their
// columns; listings of the registry).
#define SPHDEM_FIELD_REGISTRY(LIST)                                                         \
  LIST(SPHDEM_FIELD_MEMBER)                                                                 \
  static_assert(0 LIST(SPHDEM_FIELD_COUNT) <= 64, "absent_fields_ has a bit per field");    \
  std::uint64_t absent_fields_ = 0;                                                         \
  template <class Self, class F>                                                            \
  static void visit_fields(Self& self, F& f, bool all) {                                    \
    unsigned k = 0;                                                                         \
    LIST(SPHDEM_FIELD_VISIT)                                                                \
    (void)k;                                                                                \
  }                                                                                         \
  template <class F>                                                                        \
  void for_each_field(F&& f) {                                                              \
    visit_fields(*this, f, false);                                                          \
  }                                                                                         \
  template <class F>                                                                        \
  void for_each_field(F&& f) const {                                                        \
    visit_fields(*this, f, false);                                                          \
  }                                                                                         \
  template <class F>                                                                        \
  void for_each_declared_field(F&& f) const {                                               \
    visit_fields(*this, f, true);                                                           \
  }                                                                                         \
  /* Whether field `name` holds values (not dropped). */                                    \
  bool has_field(std::string_view name) const {                                             \
    bool found = false, present = false;                                                    \
    unsigned k = 0;                                                                         \
    for_each_declared_field([&](const char* n, const auto&, ::sphdem::FieldPolicy) {        \
      if (name == n) {                                                                      \
        found = true;                                                                       \
        present = !((absent_fields_ >> k) & 1u);                                            \
      }                                                                                     \
      ++k;                                                                                  \
    });                                                                                     \
    if (!found) throw std::logic_error("sphdem: no particle field " + std::string(name));   \
    return present;                                                                         \
  }                                                                                         \
  /* Drops field `name`: its memory is freed and no registry function visits it. */         \
  void drop_field(std::string_view name) {                                                  \
    bool found = false;                                                                     \
    unsigned k = 0;                                                                         \
    auto drop = [&](const char* n, auto& field, ::sphdem::FieldPolicy) {                    \
      if (name == n) {                                                                      \
        found = true;                                                                       \
        absent_fields_ |= std::uint64_t{1} << k;                                            \
        std::decay_t<decltype(field)>().swap(field);                                        \
      }                                                                                     \
      ++k;                                                                                  \
    };                                                                                      \
    visit_fields(*this, drop, true);                                                        \
    if (!found) throw std::logic_error("sphdem: no particle field " + std::string(name));   \
  }                                                                                         \
  void resize(std::size_t n) {                                                              \
    for_each_field([n](const char*, auto& field, ::sphdem::FieldPolicy) {                   \
      ::sphdem::resize_field(field, n);                                                     \
    });                                                                                     \
  }                                                                                         \
  void copy_particle(std::size_t dst, std::size_t src) {                                    \
    for_each_field(                                                                         \
        [=](const char*, auto& field, ::sphdem::FieldPolicy) { field[dst] = field[src]; }); \
  }                                                                                         \
  void zero_particle(std::size_t i) {                                                       \
    for_each_field([i](const char*, auto& field, ::sphdem::FieldPolicy) {                   \
      using T = typename std::decay_t<decltype(field)>::value_type;                         \
      field[i] = ::sphdem::zero_value<T>();                                                 \
    });                                                                                     \
  }
