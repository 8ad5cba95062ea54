// DEM throughput benchmark (issue 4): fibers of 4 bonded particles, run
// through DemDomain::advance on any number of ranks, decomposed with METIS
// on DEM particles per cell (as tests/test_dem_parallel.cpp).
//
//   bench_dem --dim 3 --fibers 175                  # peer deck, 5 x 5 x 7 fibers
//   bench_dem --dim 3 --fibers 4800                 # peer deck, 20 x 20 x 12
//   bench_dem --dim 2 --fibers 175                  # the paper's 30 x 30 mm bath
//   bench_dem --dim 2 --fibers 10000
//   mpirun -n 2 bench_dem --dim 3 --fibers 4800
//
// 3D mirrors bench/peers/lammps/in.bpm_fibers_3d + fiber4.mol in its
// (LJ) units: spheres of diameter 1 and density 1, fibers of 4 touching
// spheres centred on a simple cubic lattice of spacing 4.25 (origin 0.5)
// with random orientations, random velocities at temperature 0.01 (zero
// net momentum), gravity 1e-4 along -z, dt 0.05, box nfx a x nfy a x
// 1.6 nfz a. Contacts: k_n 1, k_t 2/7 k_n, friction 0.1, damping of LAMMPS's
// gamma_n 0.5 for a particle pair (restitution 0.667). Bonds: axial
// stiffness kbar_n A = K_r = 1 and shear K_s = 0.2 (kbar* 5), no breakage.
// Differences (docs/performance.md, "DEM"): the box's sides are walls (the
// deck has x, y periodic), bonds have no damping, and bending/twisting
// stiffness follow from the bond section (0.0625, 0.025 against the deck's
// 0.02, 0.02).
//
// 2D is the paper's bath (inputs/fibers_only.yaml): particles d = 0.25 mm,
// rho 2540, E 72 GPa, sigma_c 2000 MPa, kbar* 0.25, k_n = 0.01 kbar_n A,
// e 0.5, mu 0.3, placed at random (place_fibers) in a 30 x 30 mm box for
// 175 fibers (3.82 %), the box scaled by sqrt(N / 175) for N fibers (same
// fraction), random velocities up to 1 m/s, gravity, dt_safety 0.3.
//
// Prints particle-steps per second over the whole process (set-up
// included, as the peer numbers) and over the stepping loop alone, a
// breakdown of the loop, and a hash of the final state gathered by gid
// (the same on any number of ranks).
#include <mpi.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "sphdem/dem/dem_fibers.hpp"
#include "sphdem/dem/dem_profile.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/parallel/decomposition.hpp"
#include "sphdem/solver/dem_domain.hpp"

namespace {

using namespace sphdem;
using Clock = std::chrono::steady_clock;

struct Options {
  int dim = 3;
  int fibers = 175;
  std::array<int, 3> grid{0, 0, 0};  // 3D lattice nfx x nfy x nfz (0: from --fibers)
  long steps = 20000;
  bool settle = false;    // run --steps untimed first: time the settled pile
  long rebalance = 1000;  // sub-steps between load checks (0: never re-partition)
  double imbalance = 0.05;
  bool breakdown = true;
  double skin = 1.0;  // pair-list skin, in particle radii (DemParams::max_skin)
  std::uint64_t seed = 77231;
};

void usage() {
  std::puts(
      "usage: bench_dem [--dim 2|3] [--fibers N] [--grid NXxNYxNZ] [--steps S] [--settle]\n"
      "                 [--rebalance K] [--imbalance F] [--skin S] [--no-breakdown] [--seed N]\n"
      "  DEM fibers of 4 bonded particles run through DemDomain::advance on every rank of\n"
      "  MPI_COMM_WORLD (METIS on DEM particles per cell).\n"
      "  --dim 3: the LAMMPS peer deck in.bpm_fibers_3d (lattice of fibers settling on a floor;\n"
      "           175 fibers = 5x5x7, 4800 = 20x20x12, else --grid or a near-cube lattice).\n"
      "  --dim 2: the paper's 30 x 30 mm bath (175 fibers), scaled to the same fraction for N.\n"
      "  --steps S      sub-steps (default 20000, as the peer deck)\n"
      "  --settle       run S sub-steps untimed first, then time S more (a settled pile)\n"
      "  --rebalance K  every K sub-steps re-partition when the owned-particle imbalance\n"
      "                 exceeds --imbalance (default 1000, 0.05; 0 = never)\n"
      "  --skin S       a pair-list skin of S R (DemParams::max_skin; decomposition cells of\n"
      "                 at least (2 + S) R leave it room; default 1)\n"
      "  --no-breakdown do not time the phases of the sub-step\n"
      "Prints M particle-steps/s over the whole process (as the peer) and the loop, the\n"
      "breakdown (rank 0 and the slowest rank), and a state hash (same for any rank count).");
}

// ---- 3D: the peer deck ------------------------------------------------------

constexpr double kLatticeA = 4.25;

std::array<int, 3> lattice_for(const Options& o) {
  if (o.grid[0] > 0) return o.grid;
  if (o.fibers == 175) return {5, 5, 7};
  if (o.fibers == 4800) return {20, 20, 12};
  const int n = std::max(1, static_cast<int>(std::floor(std::cbrt(o.fibers))));
  return {n, n, (o.fibers + n * n - 1) / (n * n)};
}

struct Setup {
  double dt = 0;
  Vec<3> lo3, hi3;
  Vec<2> lo2, hi2;
};

DemSystem<3> make_3d(const Options& o, Setup& s) {
  const std::array<int, 3> g = lattice_for(o);
  const int n_fib = o.grid[0] > 0 ? g[0] * g[1] * g[2] : o.fibers;
  const double r = 0.5, density = 1.0;
  DemSystem<3> sys;
  DemParams<3>& p = sys.params;
  p.kn = 1.0;
  p.kt_over_kn = 2.0 / 7.0;
  // LAMMPS hooke: F_n = k_n delta - m_eff gamma_n v_n; for two equal spheres
  // m_eff = m / 2, damping ratio zeta = gamma_n sqrt(m_eff / k_n) / 2.
  const double m = density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double zeta = 0.5 * std::sqrt(0.5 * m / p.kn) / 2.0;
  p.restitution = std::exp(-std::numbers::pi * zeta / std::sqrt(1.0 - zeta * zeta));
  p.friction = 0.1;
  // bpm/rotational K_r = 1 = kbar_n A with A = pi r^2, kbar_n = E / (2 r).
  p.youngs_modulus = 1.0 / (std::numbers::pi * r * r) * (2.0 * r);
  p.kbar_star = 1.0 / 0.2;  // K_s / K_r = 0.2
  p.gravity = Vec<3>(0, 0, -1e-4);
  s.dt = 0.05;
  s.lo3 = Vec<3>::Zero();
  s.hi3 = Vec<3>(g[0] * kLatticeA, g[1] * kLatticeA, 1.6 * g[2] * kLatticeA);
  sys.walls = box_walls<3>(s.lo3, s.hi3);

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  sys.particles.reserve(4 * static_cast<std::size_t>(n_fib));
  int placed = 0;
  for (int k = 0; k < g[2] && placed < n_fib; ++k) {
    for (int j = 0; j < g[1] && placed < n_fib; ++j) {
      for (int i = 0; i < g[0] && placed < n_fib; ++i, ++placed) {
        const Vec<3> c((i + 0.5) * kLatticeA, (j + 0.5) * kLatticeA, (k + 0.5) * kLatticeA);
        // Uniform direction on the sphere.
        const double z = 2.0 * u01(rng) - 1.0, phi = 2.0 * std::numbers::pi * u01(rng);
        const double q = std::sqrt(std::max(0.0, 1.0 - z * z));
        const Vec<3> dir(q * std::cos(phi), q * std::sin(phi), z);
        std::int64_t prev = -1;
        for (int a = 0; a < 4; ++a) {
          const std::int64_t id =
              sys.add_particle(c + (a - 1.5) * 2.0 * r * dir, r, density, placed);
          if (prev >= 0) sys.add_bond(prev, id);
          prev = id;
        }
      }
    }
  }
  // velocity create 0.01: per-component variance T / m, zero net momentum.
  const double vmax = std::sqrt(3.0 * 0.01 / m);
  DemParticles<3>& ps = sys.particles;
  Vec<3> mean = Vec<3>::Zero();
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    for (int d = 0; d < 3; ++d) ps.v[i][d] = vmax * (2.0 * u01(rng) - 1.0);
    mean += ps.v[i];
  }
  mean /= static_cast<double>(std::max<std::size_t>(1, ps.n_owned));
  for (std::size_t i = 0; i < ps.n_owned; ++i) ps.v[i] -= mean;
  return sys;
}

// ---- 2D: the paper's bath ---------------------------------------------------

DemSystem<2> make_2d(const Options& o, Setup& s) {
  DemSystem<2> sys;
  DemParams<2>& p = sys.params;
  const double r = 1.25e-4;
  p.youngs_modulus = 7.2e10;
  p.tensile_strength = 2.0e9;
  p.kbar_star = 0.25;
  p.kn = contact_stiffness_from_bond(p, r, 0.01);
  p.restitution = 0.5;
  p.friction = 0.3;
  p.dt_safety = 0.3;
  p.gravity = Vec<2>(0, -9.81);
  const double side = 0.030 * std::sqrt(o.fibers / 175.0);
  FiberSpec<2> spec;
  spec.count = o.fibers;
  spec.radius = r;
  spec.density = 2540;
  spec.lo = Vec<2>(-0.5 * side, 0.0);
  spec.hi = Vec<2>(0.5 * side, side);
  spec.seed = o.seed;
  place_fibers(spec, sys);
  s.lo2 = spec.lo;
  s.hi2 = spec.hi;
  sys.walls = box_walls<2>(spec.lo, spec.hi);
  std::mt19937_64 rng(o.seed + 1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < sys.particles.n_owned; ++i)
    for (int d = 0; d < 2; ++d) sys.particles.v[i][d] = u(rng);
  s.dt = sys.stable_dt();
  return sys;
}

// ---- running ---------------------------------------------------------------

template <int D>
std::vector<std::int64_t> particles_per_cell(const Decomposition<D>& dec,
                                             const DemParticles<D>& ps) {
  std::vector<std::int64_t> work(static_cast<std::size_t>(dec.blocks()), 0);
  for (std::size_t i = 0; i < ps.n_owned; ++i)
    ++work[static_cast<std::size_t>(dec.block_of(ps.x[i]))];
  return work;
}

// FNV-1a over (gid, x, v, omega) of every particle in gid order, on rank 0.
template <int D>
std::uint64_t state_hash(const Comm& comm, const DemParticles<D>& ps) {
  constexpr int R = D == 2 ? 1 : 3;
  constexpr int per = 1 + 2 * D + R;
  std::vector<double> mine;
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    mine.push_back(static_cast<double>(ps.gid[i]));
    for (int d = 0; d < D; ++d) mine.push_back(ps.x[i][d]);
    for (int d = 0; d < D; ++d) mine.push_back(ps.v[i][d]);
    for (int d = 0; d < R; ++d) mine.push_back(ps.omega[i][d]);
  }
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(comm.size())), displs(counts.size(), 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm.raw());
  std::partial_sum(counts.begin(), counts.end() - 1, displs.begin() + 1);
  std::vector<double> all(comm.root() ? static_cast<std::size_t>(displs.back() + counts.back())
                                      : 0);
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE,
              0, comm.raw());
  if (!comm.root()) return 0;
  const std::size_t n = all.size() / per;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return all[a * per] < all[b * per]; });
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t k : order) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(&all[k * per]);
    for (std::size_t b = 0; b < per * sizeof(double); ++b) {
      h ^= bytes[b];
      h *= 1099511628211ull;
    }
  }
  return h;
}

template <int D>
int run(const Options& o, DemSystem<D> sys, double dt, const Box<D>& box,
        Clock::time_point t_start) {
  const Comm comm;
  dem_detail::DemProfile& prof = dem_detail::dem_profile();
  const double r = sys.particles.radius.empty() ? 0.0 : sys.particles.radius[0];
  const std::int64_t n = static_cast<std::int64_t>(sys.particles.n_owned);
  std::int64_t bonds = 0;
  for (std::size_t i = 0; i < sys.particles.n_owned; ++i)
    for (const auto& b : sys.particles.bonds[i]) bonds += b.partner >= 0;

  // Cells of at least (2 + skin) R: DemDomain then takes a pair-list skin
  // of up to 1 R (the peer deck: 0.6 R), rebuilding less often than with
  // the minimal cell. And at least a fiber's length (8 R, 8.5 R: the 3D
  // lattice spacing): with smaller cells the graph of non-empty cells of a
  // sparse set of fibers falls apart into islands, which METIS deals out
  // to the ranks like a checkerboard (on 2 ranks 64 % of the particles
  // were ghosts, against 5-10 % with fiber-sized cells).
  Decomposition<D> dec(comm, box, {false, false, false},
                       std::max({DemDomain<D>::reach(r, r), (2.0 + o.skin) * r, 8.5 * r}));
  dec.partition(particles_per_cell(dec, sys.particles), true);
  sys.params.max_skin = o.skin;
  DemDomain<D> dom(dec, sys.params, sys.walls, std::move(sys.particles));
  const double t_setup = std::chrono::duration<double>(Clock::now() - t_start).count();

  std::int64_t repartitions = 0;
  double max_imbalance = 0;
  const auto imbalance = [&] {
    const auto mine = static_cast<std::int64_t>(dom.particles().n_owned);
    const double mean = static_cast<double>(n) / comm.size();
    return static_cast<double>(comm.max(mine)) / mean - 1.0;
  };
  // Sub-steps in chunks of --rebalance; between chunks, re-partition when
  // the owned counts drift apart (a global decision from integer counts).
  const auto advance = [&](long steps, bool timed) {
    double t_rebalance = 0;
    const long chunk = o.rebalance > 0 && comm.size() > 1 ? o.rebalance : steps;
    for (long done = 0; done < steps;) {
      const long k = std::min(chunk, steps - done);
      dom.advance(k, dt);
      done += k;
      if (chunk < steps && done < steps) {
        const auto t0 = Clock::now();
        const double imb = imbalance();
        if (timed) max_imbalance = std::max(max_imbalance, imb);
        if (imb > o.imbalance) {
          dec.partition(particles_per_cell(dec, dom.particles()), false);
          dom.rebuild();
          ++repartitions;
        }
        t_rebalance += std::chrono::duration<double>(Clock::now() - t0).count();
      }
    }
    return t_rebalance;
  };

  if (o.settle) advance(o.steps, false);
  prof.enabled = o.breakdown;
  prof.reset();
  const std::int64_t rebuilds0 = dom.rebuilds();
  const auto t0 = Clock::now();
  const double t_rebalance = advance(o.steps, true);
  const double loop = std::chrono::duration<double>(Clock::now() - t0).count();
  prof.enabled = false;
  const std::int64_t rebuilds = dom.rebuilds() - rebuilds0;

  dom.store_state();
  std::int64_t contacts = 0, wall_contacts = 0, ghosts = 0;
  const DemParticles<D>& ps = dom.particles();
  for (std::size_t i = 0; i < ps.n_owned; ++i) {
    for (const auto& c : ps.contacts[i]) contacts += c.partner >= 0;
    for (const auto& c : ps.wall_contacts[i]) wall_contacts += c.partner != c.kNone;
  }
  ghosts = static_cast<std::int64_t>(ps.n_ghost());
  contacts = comm.sum(contacts);
  wall_contacts = comm.sum(wall_contacts);
  const std::int64_t ghosts_total = comm.sum(ghosts);
  const double final_imbalance = imbalance();
  const std::uint64_t hash = state_hash<D>(comm, ps);

  const double whole = std::chrono::duration<double>(Clock::now() - t_start).count();
  const double whole_max = comm.max(whole);
  const double total_steps = static_cast<double>(o.settle ? 2 * o.steps : o.steps);
  // Breakdown: rank 0's and the slowest rank's (by loop time).
  const double others = loop - prof.pairs - prof.gather - prof.walls - prof.kick_drift - prof.halo -
                        prof.collective - prof.rebuild - t_rebalance;
  std::vector<double> mine{
      prof.pairs,         prof.gather,          prof.walls,         prof.kick_drift, prof.halo,
      prof.collective,    prof.rebuild,         t_rebalance,        others,          loop,
      prof.rebuild_pairs, prof.rebuild_migrate, prof.rebuild_ghosts};
  std::vector<double> all(comm.root() ? mine.size() * static_cast<std::size_t>(comm.size()) : 0);
  MPI_Gather(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(),
             static_cast<int>(mine.size()), MPI_DOUBLE, 0, comm.raw());
  if (comm.root()) {
    std::printf("dem %dD: %d fibers, %lld particles, %lld bonds, %d rank(s), dt %.4g\n", D,
                static_cast<int>(n / 4), static_cast<long long>(n), static_cast<long long>(bonds),
                comm.size(), dt);
    std::printf(
        "steps %ld%s, rebuilds %lld, re-partitions %lld, imbalance max %.1f %% end %.1f %%\n",
        o.steps, o.settle ? " (after as many untimed)" : "", static_cast<long long>(rebuilds),
        static_cast<long long>(repartitions), 100 * max_imbalance, 100 * final_imbalance);
    std::printf("end: %lld particle contacts, %lld wall contacts, %lld ghosts\n",
                static_cast<long long>(contacts), static_cast<long long>(wall_contacts),
                static_cast<long long>(ghosts_total));
    std::printf("setup: %.3f s\n", t_setup);
    std::printf("loop:  %.3f s  %.3f M particle-steps/s\n", loop,
                static_cast<double>(n) * static_cast<double>(o.steps) / loop / 1e6);
    std::printf("whole: %.3f s  %.3f M particle-steps/s\n", whole_max,
                static_cast<double>(n) * total_steps / whole_max / 1e6);
    if (o.breakdown) {
      const char* names[] = {"pair evaluation",
                             "gather/sum",
                             "walls",
                             "kick/drift",
                             "halo update",
                             "rebuild decision (allreduce + wait)",
                             "rebuilds (store, migrate, ghosts, pairs)",
                             "re-partitions (METIS + rebuild)",
                             "other"};
      std::size_t slow = 0;
      for (int rk = 1; rk < comm.size(); ++rk)
        if (all[rk * mine.size() + 9] > all[slow * mine.size() + 9]) slow = rk;
      std::printf("breakdown (s, %% of loop)          rank 0");
      if (comm.size() > 1) std::printf("            slowest (rank %zu)", slow);
      std::printf("\n");
      for (std::size_t k = 0; k < 9; ++k) {
        std::printf("  %-42s %7.3f %5.1f %%", names[k], all[k], 100 * all[k] / all[9]);
        if (comm.size() > 1) {
          const double* b = &all[slow * mine.size()];
          std::printf("   %7.3f %5.1f %%", b[k], 100 * b[k] / b[9]);
        }
        std::printf("\n");
      }
      std::printf(
          "  (of the rebuilds, rank 0: pair-list build %.3f s, migration %.3f s, ghost build %.3f "
          "s)\n",
          all[10], all[11], all[12]);
    }
    std::printf("state hash %016llx\n", static_cast<unsigned long long>(hash));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const auto t_start = Clock::now();
  MPI_Init(&argc, &argv);
  Options o;
  int status = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    try {
      if (a == "--dim") {
        o.dim = std::stoi(next());
      } else if (a == "--fibers") {
        o.fibers = std::stoi(next());
      } else if (a == "--grid") {
        const std::string g = next();
        if (std::sscanf(g.c_str(), "%dx%dx%d", &o.grid[0], &o.grid[1], &o.grid[2]) != 3) status = 2;
      } else if (a == "--steps") {
        o.steps = std::stol(next());
      } else if (a == "--settle") {
        o.settle = true;
      } else if (a == "--rebalance") {
        o.rebalance = std::stol(next());
      } else if (a == "--imbalance") {
        o.imbalance = std::stod(next());
      } else if (a == "--skin") {
        o.skin = std::stod(next());
      } else if (a == "--no-breakdown") {
        o.breakdown = false;
      } else if (a == "--seed") {
        o.seed = std::stoull(next());
      } else if (a == "--help" || a == "-h") {
        status = 1;
      } else {
        status = 2;
      }
    } catch (const std::exception&) {
      status = 2;
    }
  }
  if (status == 0 && ((o.dim != 2 && o.dim != 3) || o.fibers < 1 || o.steps < 1)) status = 2;
  if (status != 0) {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) usage();
    MPI_Finalize();
    return status == 1 ? 0 : 2;
  }
  Setup s;
  if (o.dim == 3) {
    DemSystem<3> sys = make_3d(o, s);
    // The decomposition box: the walls' box, a radius of slack around it.
    const Box<3> box{s.lo3 - Vec<3>::Constant(1.0), s.hi3 + Vec<3>::Constant(1.0)};
    status = run<3>(o, std::move(sys), s.dt, box, t_start);
  } else {
    DemSystem<2> sys = make_2d(o, s);
    const double pad = 2.5e-4;
    const Box<2> box{s.lo2 - Vec<2>::Constant(pad), s.hi2 + Vec<2>::Constant(pad)};
    status = run<2>(o, std::move(sys), s.dt, box, t_start);
  }
  MPI_Finalize();
  return status;
}
