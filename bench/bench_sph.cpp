// SPH throughput benchmark (issue 2): the peer deck's 2D periodic channel
// (bench/peers/lammps/in.sph_poiseuille_2d: spacing 0.3 mm, h/dp 1.2,
// 20 neighbours, rho0 900, mu 0.1, c0 50, body force 1000 m/s^2, 3 wall
// layers, fixed dt 1.4e-6 s) at any size, or any case file.
//
//   bench_sph --nx 320 --ny 60 --steps 2000     # 19,200 resin + 1,280 wall = 20,480
//   bench_sph --nx 720 --ny 132 --steps 1000    # 95,040 + 2,880 = 97,920
//   bench_sph --case inputs/plate.yaml --steps 2000
//
// Reports particle-steps per second counting every particle (resin and
// wall, as LAMMPS counts atoms) over the timed loop, and over the whole
// process (set-up included, as the peer numbers were measured). sphdem makes
// only the wall particles within the kernel's support (2 of the 3 layers,
// docs/performance.md "Wall layers trimmed to the support"), the peer deck
// all 3 (21,120 and 99,360 atoms for the two channels above): compare the
// two codes' times on the same resin (tools/bench_vs_lammps.sh), not their
// particle-steps per second.
#include <mpi.h>

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "sphdem/config/config.hpp"
#include "sphdem/solver/solver.hpp"

namespace {

std::string channel_case(int nx, int ny) {
  const double dx = 3e-4, lx = nx * dx, ly = ny * dx;
  return fmt::format(R"(name: channel
dimension: 2
resin: {{density: 900, viscosity: 0.1, sound_speed: 50}}
numerics: {{spacing: 3.0e-4, h_over_spacing: 1.2, fixed_dt: 1.4e-6, end_time: 1.0, anti_clump: true}}
mold: {{wall_layers: 3, shapes: [{{box: {{min: [0, 0], max: [{lx}, {ly}]}}}}]}}
fill: [{{box: {{min: [0, 0], max: [{lx}, {ly}]}}}}]
body_force: [1000, 0]
periodic: [x]
domain: {{min: [0, {ylo}], max: [{lx}, {yhi}]}}
output: {{progress_every: 1000000}}
)",
                     fmt::arg("lx", lx), fmt::arg("ly", ly), fmt::arg("ylo", -4 * dx),
                     fmt::arg("yhi", ly + 4 * dx));
}

void usage() {
  std::puts(
      "usage: bench_sph [--nx N --ny N | --case FILE] [--steps N] [--set key=value ...]\n"
      "  Periodic 2D channel of the LAMMPS peer deck (default 320 x 60) or a case file;\n"
      "  prints particle-steps per second (resin + wall particles; the channel's walls are\n"
      "  the 2 of its 3 layers within the kernel's support, the peer deck has all 3).");
}

}  // namespace

int main(int argc, char** argv) {
  const auto t_start = std::chrono::steady_clock::now();
  MPI_Init(&argc, &argv);
  int nx = 320, ny = 60;
  long steps = 2000;
  std::string case_file;
  std::vector<std::string> sets;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--nx")
      nx = std::stoi(next());
    else if (a == "--ny")
      ny = std::stoi(next());
    else if (a == "--steps")
      steps = std::stol(next());
    else if (a == "--case")
      case_file = next();
    else if (a == "--set")
      sets.push_back(next());
    else {
      usage();
      MPI_Finalize();
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  int status = 0;
  {
    const sphdem::Comm comm;
    const sphdem::Case c =
        case_file.empty() ? sphdem::load_case_from_string(channel_case(nx, ny), "channel", sets)
                          : sphdem::load_case(case_file, sets);
    sphdem::RunOptions opt;
    opt.write_output = false;
    if (c.dimension != 2) {
      std::fprintf(stderr, "bench_sph: 2D cases only\n");
      status = 2;
    } else {
      sphdem::Simulation<2> sim(c, comm, opt);
      const auto t0 = std::chrono::steady_clock::now();
      sim.advance(steps);
      const double loop =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double whole =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
      const double n = static_cast<double>(sim.global_fluid_count() + sim.global_wall_count());
      if (comm.root()) {
        std::printf("case %s: %.0f particles (%lld resin + %lld wall), %ld steps, %d rank(s)\n",
                    c.name.c_str(), n, static_cast<long long>(sim.global_fluid_count()),
                    static_cast<long long>(sim.global_wall_count()), steps, comm.size());
        std::printf("loop:  %.3f s  %.3f M particle-steps/s\n", loop, n * steps / loop / 1e6);
        std::printf("whole: %.3f s  %.3f M particle-steps/s\n", whole, n * steps / whole / 1e6);
        // What the memory per particle is made of (docs/performance.md).
        std::printf(
            "lists: %.2f pairs per particle (rank 0), %.2f %% of them 32-bit, %lld rebuilds\n",
            static_cast<double>(sim.resin()->neighbor_pairs()) /
                static_cast<double>(sim.particles().n_owned),
            100.0 * static_cast<double>(sim.resin()->neighbor_wide_pairs()) /
                static_cast<double>(std::max<std::size_t>(1, sim.resin()->neighbor_pairs())),
            static_cast<long long>(sim.resin()->neighbor_builds()));
        // Load balance (parallel.balance_weight, docs/parallel.md).
        std::printf("balance: %lld re-partitions, imbalance %.1f %% at the last check\n",
                    static_cast<long long>(sim.repartitions()), 100.0 * sim.last_imbalance());
        // A coupled case's fibers (docs/parallel.md, "The coupled run's skins").
        if (sim.dem())
          std::printf("fibers: %lld list builds, skin %.3g m\n",
                      static_cast<long long>(sim.dem()->rebuilds()), sim.dem()->list_skin());
      }
    }
  }
  MPI_Finalize();
  return status;
}
