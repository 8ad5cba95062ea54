#pragma once
// The fountain channel (inputs/validation/fountain_channel_2d.yaml) run and
// sampled for tests/test_fountain.cpp and tests/test_fountain_implicit.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "validation_helpers.hpp"

namespace sphdem::testing_fountain {

using testing::quiet;

struct Row {
  std::int64_t gid = 0;
  double value[4] = {};  // x, y, v_x, v_y
};

struct Channel {
  double width = 0, dp = 0, speed = 0;  // W, the spacing, the piston's U
  std::vector<double> t, tip, contact;  // the samples: the tip, the wall contact (mean of both)
  std::vector<Row> rows;                // every resin particle at the end (rank 0)
  std::vector<std::int64_t> tracers;    // the core's particles at the initial front
  std::vector<Row> start;               // every resin particle at the start (rank 0)
  double front = 0;                     // the initial front: the largest x of the resin
};

// Runs the channel case on comm to end_time, sampling the front every
// `every` seconds from `from` on: the tip is the largest x of the resin; the
// wall contact at each wall the largest x of the resin particles closer than
// one spacing to it (the row laid on the wall), their mean the contact.
// sets: further overrides (numerics.viscous_integration=implicit).
inline Channel run_channel(const Comm& comm, double end_time, double from, double every,
                           std::vector<std::string> sets = {}) {
  sets.push_back("numerics.end_time=" + std::to_string(end_time));
  const Case c = testing::load_input("validation/fountain_channel_2d.yaml", sets);
  Simulation<2> sim(c, comm, quiet());
  Channel ch;
  ch.dp = c.numerics.spacing;
  ch.width = c.mold.shapes[0].hi[1] - c.mold.shapes[0].lo[1];
  ch.speed = c.moving_walls[0].velocity.velocity[0][0];
  const double centre = 0.5 * ch.width;
  {  // the tracers: the core's rows (within W/4 of the centre line), in the
     // two columns of the initial front
    const SphParticles<2>& ps = sim.particles();
    double front = -1e300;
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid) front = std::max(front, ps.x[i][0]);
    front = comm.max(front);
    std::vector<Row> mine;
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid && std::abs(ps.x[i][1] - centre) < 0.25 * ch.width &&
          ps.x[i][0] > front - 1.5 * ch.dp)
        mine.push_back({ps.gid[i], {}});
    for (const Row& r : testing_mpi::gather_rows(comm, mine)) ch.tracers.push_back(r.gid);
    ch.front = front;
    mine.clear();
    for (std::size_t i = 0; i < ps.n_owned; ++i)
      if (ps.kind[i] == Kind::Fluid)
        mine.push_back({ps.gid[i], {ps.x[i][0], ps.x[i][1], ps.v[i][0], ps.v[i][1]}});
    ch.start = testing_mpi::gather_rows(comm, mine);
  }
  double next = from;
  while (sim.time() < end_time * (1 - 1e-12)) {
    sim.advance(1);
    if (sim.time() < next * (1 - 1e-12)) continue;
    next += every;
    const SphParticles<2>& ps = sim.particles();
    double tip = -1e300, low = -1e300, high = -1e300;
    for (std::size_t i = 0; i < ps.n_owned; ++i) {
      if (ps.kind[i] != Kind::Fluid) continue;
      const double x = ps.x[i][0], y = ps.x[i][1];
      tip = std::max(tip, x);
      if (y < ch.dp) low = std::max(low, x);
      if (y > ch.width - ch.dp) high = std::max(high, x);
    }
    ch.t.push_back(sim.time());
    ch.tip.push_back(comm.max(tip));
    ch.contact.push_back(0.5 * (comm.max(low) + comm.max(high)));
  }
  std::vector<Row> mine;
  const SphParticles<2>& ps = sim.particles();
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    if (ps.kind[i] == Kind::Fluid)
      mine.push_back({ps.gid[i], {ps.x[i][0], ps.x[i][1], ps.v[i][0], ps.v[i][1]}});
  ch.rows = testing_mpi::gather_rows(comm, mine);
  return ch;
}

// Least-squares slope of y(t).
inline double slope(const std::vector<double>& t, const std::vector<double>& y) {
  const double n = static_cast<double>(t.size());
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    st += t[k];
    sy += y[k];
    stt += t[k] * t[k];
    sty += t[k] * y[k];
  }
  return (n * sty - st * sy) / (n * stt - st * st);
}

}  // namespace sphdem::testing_fountain
