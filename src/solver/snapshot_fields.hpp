#pragma once
// Packs the owned particles of each kind into contiguous arrays for the
// snapshot writer: set "fluid" (resin) and set "wall".
#include <algorithm>
#include <string>
#include <vector>

#include "sphdem/io.hpp"
#include "sphdem/particles.hpp"

namespace sphdem {

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
      for (const Field& f : s.fields)
        v.fields.push_back({f.name, f.units, f.components, f.data.data()});
      out.push_back(std::move(v));
    }
    return out;
  }

 private:
  struct Field {
    std::string name, units;
    int components;
    std::vector<double> data;
  };
  struct Set {
    std::string name;
    std::vector<std::int64_t> id;
    std::vector<double> position;
    std::vector<Field> fields;
  };

  static bool wanted(const std::vector<std::string>& f, const char* name) {
    return std::find(f.begin(), f.end(), name) != f.end();
  }

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
    auto vector_field = [&](const char* fname, const char* units, const std::vector<Vec<D>>& src) {
      Field f{fname, units, D, {}};
      for (std::size_t i : idx)
        for (int k = 0; k < D; ++k) f.data.push_back(src[i][k]);
      s.fields.push_back(std::move(f));
    };
    auto scalar_field = [&](const char* fname, const char* units, auto&& get) {
      Field f{fname, units, 1, {}};
      for (std::size_t i : idx) f.data.push_back(get(i));
      s.fields.push_back(std::move(f));
    };
    if (wanted(wanted_fields, "velocity")) vector_field("velocity", "m/s", ps.v);
    if (wanted(wanted_fields, "density"))
      scalar_field("density", "kg/m^3", [&](std::size_t i) { return ps.rho[i]; });
    if (wanted(wanted_fields, "pressure"))
      scalar_field("pressure", "Pa", [&](std::size_t i) { return ps.p[i]; });
    if (wanted(wanted_fields, "acceleration")) vector_field("acceleration", "m/s^2", ps.a);
    if (wanted(wanted_fields, "kind"))
      scalar_field("kind", "1", [&](std::size_t i) { return static_cast<double>(ps.kind[i]); });
    if (wanted(wanted_fields, "wall_id"))
      scalar_field("wall_id", "1", [&](std::size_t i) { return static_cast<double>(ps.wall[i]); });
    return s;
  }

  std::vector<Set> sets_;
};

}  // namespace sphdem
