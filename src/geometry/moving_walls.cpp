#include <algorithm>
#include <cmath>

#include "sphdem/geometry/walls.hpp"

namespace sphdem {

namespace {
// Index of the table segment [i, i+1] holding t; -1 before the first row,
// size-1 after the last.
long segment(const VelocityTable& tab, double t) {
  const auto it = std::upper_bound(tab.time.begin(), tab.time.end(), t);
  return static_cast<long>(it - tab.time.begin()) - 1;
}
}  // namespace

Vec3a table_velocity(const VelocityTable& tab, double t) {
  if (tab.time.empty()) return {0, 0, 0};
  const long i = segment(tab, t);
  if (i < 0) return tab.velocity.front();
  const auto n = static_cast<long>(tab.time.size());
  if (i >= n - 1) return tab.velocity.back();
  const auto u = static_cast<std::size_t>(i);
  const double s = (t - tab.time[u]) / (tab.time[u + 1] - tab.time[u]);
  Vec3a v{};
  for (int k = 0; k < 3; ++k) v[k] = (1 - s) * tab.velocity[u][k] + s * tab.velocity[u + 1][k];
  return v;
}

Vec3a table_acceleration(const VelocityTable& tab, double t) {
  const long i = segment(tab, t);
  const auto n = static_cast<long>(tab.time.size());
  if (i < 0 || i >= n - 1) return {0, 0, 0};
  const auto u = static_cast<std::size_t>(i);
  const double dt = tab.time[u + 1] - tab.time[u];
  Vec3a a{};
  for (int k = 0; k < 3; ++k) a[k] = (tab.velocity[u + 1][k] - tab.velocity[u][k]) / dt;
  return a;
}

Vec3a WallMotion::velocity(double t) const {
  if (!moves) return surface_velocity;
  Vec3a v = table_velocity(table, t);
  for (double& c : v) c *= scale;
  return v;
}

Vec3a WallMotion::acceleration(double t) const {
  if (!moves) return {0, 0, 0};
  Vec3a a = table_acceleration(table, t);
  for (double& c : a) c *= scale;
  return a;
}

std::vector<WallMotion> make_wall_motions(const Case& c) {
  std::vector<WallMotion> out;
  for (const MovingWall& m : c.moving_walls) {
    WallMotion w;
    w.name = m.name;
    w.moves = true;
    w.table = m.velocity;
    w.pressure_limit = m.pressure_limit.value_or(0.0);
    w.relax_time = m.pressure_relax_time;
    w.adhesion_pressure = m.adhesion_pressure;
    w.slip = resolve_wall_slip(m, c.mold);
    w.thermal = resolve_wall_thermal(m, c.mold);
    out.push_back(w);
  }
  for (const SlidingWall& s : c.sliding_walls) {
    WallMotion w;
    w.name = s.name;
    w.surface_velocity = s.velocity;
    w.slip = resolve_wall_slip(s, c.mold);
    w.thermal = resolve_wall_thermal(s, c.mold);
    out.push_back(w);
  }
  return out;
}

void update_wall_controllers(std::vector<WallMotion>& walls, const std::vector<double>& face,
                             double dt) {
  for (std::size_t k = 0; k < walls.size(); ++k) {
    WallMotion& w = walls[k];
    const double p = k < face.size() ? face[k] : std::nan("");
    w.face_pressure = std::isnan(p) ? 0.0 : p;
    if (!w.moves || w.pressure_limit <= 0 || std::isnan(p)) continue;
    const double rate = (w.pressure_limit - p) / (w.pressure_limit * w.relax_time);
    w.scale = std::clamp(w.scale + dt * rate, 0.0, 1.0);
  }
}

}  // namespace sphdem
