#pragma once
// The snapshot fields of the particle containers, read from the field
// registry (field_registry.hpp): every field with an output name
// (output_as) can be written, as doubles, under that name and unit. The
// resin's owned particles go into set "fluid" (resin) and set "wall", with
// the fields `output.fields` names.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "sphdem/io/io.hpp"
#include "sphdem/particles/particles.hpp"

namespace sphdem {

// One dataset of a particle set: components doubles per particle.
struct OutputField {
  std::string name, units;
  int components = 1;
  std::vector<double> data;
};

// The registry fields of `ps` with an output name that `wanted(name)`
// accepts, at particles idx, in registry order.
template <class P, class Wanted>
std::vector<OutputField> registry_output_fields(const P& ps, const std::vector<std::size_t>& idx,
                                                Wanted wanted) {
  std::vector<OutputField> out;
  ps.for_each_field([&](const char* name, const auto& field, FieldPolicy p) {
    if (!p.output || !wanted(p.output)) return;
    using T = typename std::decay_t<decltype(field)>::value_type;
    OutputField f{p.output, p.unit ? p.unit : "1", 1, {}};
    if constexpr (IsDoubleVector<T>::value) {
      f.components = T::SizeAtCompileTime;
      for (std::size_t i : idx)
        for (int k = 0; k < f.components; ++k) f.data.push_back(field[i][k]);
    } else if constexpr (std::is_enum_v<T>) {
      for (std::size_t i : idx)
        f.data.push_back(static_cast<double>(static_cast<std::underlying_type_t<T>>(field[i])));
    } else if constexpr (std::is_arithmetic_v<T>) {
      for (std::size_t i : idx) f.data.push_back(static_cast<double>(field[i]));
    } else {
      throw std::logic_error(std::string("sphdem: field '") + name +
                             "' has an output name but is not a number or a vector");
    }
    out.push_back(std::move(f));
  });
  return out;
}

template <int D>
class SnapshotBuffers {
 public:
  SnapshotBuffers(const SphParticles<D>& ps, const std::vector<std::string>& fields)
      : sets_{pack(ps, Kind::Fluid, "fluid", fields), pack(ps, Kind::Wall, "wall", fields)} {}

  std::vector<ParticleSetView> views() const {
    std::vector<ParticleSetView> out;
    for (const Set& s : sets_) {
      ParticleSetView v;
      v.name = s.name;
      v.n_local = s.id.size();
      v.id = s.id.data();
      v.dimension = D;
      v.position = s.position.data();
      for (const OutputField& f : s.fields)
        v.fields.push_back({f.name, f.units, f.components, f.data.data()});
      out.push_back(std::move(v));
    }
    return out;
  }

 private:
  struct Set {
    std::string name;
    std::vector<std::int64_t> id;
    std::vector<double> position;
    std::vector<OutputField> fields;
  };

  static Set pack(const SphParticles<D>& ps, Kind kind, const char* name,
                  const std::vector<std::string>& wanted_fields) {
    Set s;
    s.name = name;
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == kind) idx.push_back(i);
    for (std::size_t i : idx) {
      s.id.push_back(ps.gid[i]);
      for (int k = 0; k < D; ++k) s.position.push_back(ps.x[i][k]);
    }
    s.fields = registry_output_fields(ps, idx, [&](const char* field) {
      return std::find(wanted_fields.begin(), wanted_fields.end(), field) != wanted_fields.end();
    });
    return s;
  }

  std::vector<Set> sets_;
};

}  // namespace sphdem
