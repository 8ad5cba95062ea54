#pragma once
// Particle records for migration: the fields a policy selects
// (FieldPolicy.migrate), in registry order, one particle after another
// (record_bytes: field_registry.hpp). Driven by the container's
// for_each_field (SPH or DEM), so a new field travels as soon as it is
// registered with the right policy.
#include <cstring>
#include <vector>

#include "sphdem/particles/particles.hpp"

namespace sphdem::detail {

// Appends the records of particles idx[0..n) to `out`.
template <class P, class Want>
void pack_records(P& ps, const std::vector<std::size_t>& idx, Want want, std::vector<char>& out) {
  const std::size_t rec = record_bytes(ps, want), base = out.size();
  out.resize(base + rec * idx.size());
  std::size_t offset = 0;
  ps.for_each_field([&](const char*, auto& field, FieldPolicy p) {
    if (!want(p)) return;
    const std::size_t size = sizeof(typename std::decay_t<decltype(field)>::value_type);
    char* dst = out.data() + base + offset;
    for (std::size_t k = 0; k < idx.size(); ++k) {
      std::memcpy(dst + k * rec, static_cast<const void*>(&field[idx[k]]), size);
    }
    offset += size;
  });
}

// Writes n records from `in` to particles [first, first + n).
template <class P, class Want>
void unpack_records(P& ps, std::size_t first, std::size_t n, Want want, const char* in) {
  const std::size_t rec = record_bytes(ps, want);
  std::size_t offset = 0;
  ps.for_each_field([&](const char*, auto& field, FieldPolicy p) {
    if (!want(p)) return;
    const std::size_t size = sizeof(typename std::decay_t<decltype(field)>::value_type);
    for (std::size_t k = 0; k < n; ++k) {
      std::memcpy(static_cast<void*>(&field[first + k]), in + k * rec + offset, size);
    }
    offset += size;
  });
}

}  // namespace sphdem::detail
