// Glass fibers with bond sub-cycling and implicit bonds (docs/dem.md,
// "Bond sub-cycling", "Implicit bonds"; issue 12 part 4): both integrators
// against the explicit one at E = 72 GPa, the explicit run being the
// reference.
// - a glass fiber in a shear flow's drag (2D and 3D): bond stresses and the
//   fiber's bent shape within 5 % of the explicit run's;
// - the glass cantilever (docs/validation.md section 3) within the
//   explicit test's tolerance;
// - a coupled resin + glass-fiber box: both against explicit within 5 %,
//   on 2-4 ranks bitwise the 1-rank run, and a restart bitwise the run
//   (tests/test_checkpoint.cpp).
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "mpi_test_helpers.hpp"
#include "sphdem/dem/dem.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kR = 0.125e-3, kRho = 2540, kGlass = 72e9;

enum class Bonds { Explicit, Subcycled, Implicit };

template <int D>
DemParams<D> glass_params(Bonds bonds) {
  DemParams<D> p;
  p.youngs_modulus = kGlass;
  p.kbar_star = 0.25;
  p.restitution = 0.5;
  p.dt_safety = 0.3;
  p.kn = contact_stiffness_from_bond(p, kR, 0.01);
  p.subcycle_bonds = bonds != Bonds::Explicit;
  p.implicit_bonds = bonds == Bonds::Implicit;
  return p;
}

// A straight chain of n touching particles through the origin at angle phi
// from +x (in the x-y plane).
template <int D>
DemSystem<D> glass_fiber(int n, double phi, Bonds bonds) {
  DemSystem<D> sys;
  sys.params = glass_params<D>(bonds);
  Vec<D> e = Vec<D>::Zero();
  e[0] = std::cos(phi);
  e[1] = std::sin(phi);
  for (int i = 0; i < n; ++i) {
    sys.add_particle((2 * kR * (i - 0.5 * (n - 1))) * e, kR, kRho, 0);
    if (i > 0) sys.add_bond(i - 1, i);
  }
  // The step: explicit at the bonds' stable step, sub-cycled at the
  // contacts' with the bonds in inner steps of theirs (FiberModule's rule).
  sys.params.bond_dt = sys.stable_dt();
  return sys;
}

template <int D>
double outer_dt(const DemSystem<D>& sys) {
  return sys.params.subcycle_bonds ? stable_dem_outer_dt(sys.params, sys.particles)
                                   : sys.stable_dt();
}

struct FiberResult {
  std::vector<double> sigma, sigma_max;  // per bond: at the end, largest seen
  std::vector<double> deflection;        // per particle: off the end-to-end chord
  double steps = 0;
};

// A fiber held at its middle particle (a clamp: velocity and spin kept at
// zero) across the stream u = (U + G y, 0): each particle is drawn to the
// flow with drag time tau (the coupled runs' drag law, the resin velocity
// at the particle renewed every `pass`, as the coupling pass does each SPH
// step). Both arms bend as cantilevers under an uneven load; ten drag
// times damp the start-up vibration by e^-5.
template <int D>
FiberResult shear_drag(Bonds bonds) {
  const int n = 9;
  DemSystem<D> sys = glass_fiber<D>(n, kPi / 4, bonds);
  const double U = 1, G = 2000, tau = 2e-5, pass = 1e-6, t_end = 10 * tau;
  auto& ps = sys.particles;
  ps.fixed[n / 2] = kFixedMotion;
  const double dt_max = outer_dt(sys);
  const auto per_pass = static_cast<long>(std::ceil(pass / dt_max));
  const double dt = pass / static_cast<double>(per_pass);
  FiberResult r;
  r.sigma_max.assign(n - 1, 0.0);
  for (double t = 0; t < t_end * (1 - 1e-12); t += pass) {
    for (int i = 0; i < n; ++i) {
      ps.drag_coeff[i] = ps.mass[i] / tau;
      ps.drag_velocity[i] = Vec<D>::Zero();
      ps.drag_velocity[i][0] = U + G * ps.x[i][1];
    }
    for (long s = 0; s < per_pass; ++s) sys.step(dt);
    r.steps += static_cast<double>(per_pass);
    for (int b = 0; b + 1 < n; ++b)
      r.sigma_max[b] = std::max(r.sigma_max[b], std::abs(sys.bond(b, b + 1)->sigma));
  }
  for (int b = 0; b + 1 < n; ++b) r.sigma.push_back(sys.bond(b, b + 1)->sigma);
  const Vec<D> a = ps.x[0], chord = (ps.x[n - 1] - a).normalized();
  for (int i = 0; i < n; ++i) {
    const Vec<D> d = ps.x[i] - a;
    r.deflection.push_back((d - d.dot(chord) * chord).norm());
  }
  return r;
}

// Largest difference over the largest reference value.
double relative_gap(const std::vector<double>& ref, const std::vector<double>& got) {
  double scale = 0, gap = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    scale = std::max(scale, std::abs(ref[k]));
    gap = std::max(gap, std::abs(got[k] - ref[k]));
  }
  return gap / scale;
}

template <int D>
void check_shear_drag(const FiberResult& ref, const FiberResult& got, const char* method) {
  const double e_sigma = relative_gap(ref.sigma, got.sigma);
  const double e_peak = relative_gap(ref.sigma_max, got.sigma_max);
  const double e_shape = relative_gap(ref.deflection, got.deflection);
  const double peak = *std::max_element(ref.sigma_max.begin(), ref.sigma_max.end());
  std::printf(
      "glass fiber in shear D=%d: peak stress %.4g Pa, deflection %.3g m; %s vs explicit: "
      "stress %.2e, peak %.2e, shape %.2e; outer steps %.0f vs %.0f explicit\n",
      D, peak, *std::max_element(ref.deflection.begin(), ref.deflection.end()), method, e_sigma,
      e_peak, e_shape, got.steps, ref.steps);
  EXPECT_LT(e_sigma, 0.05);
  EXPECT_LT(e_peak, 0.05);
  EXPECT_LT(e_shape, 0.05);
  EXPECT_GT(ref.steps, 10 * got.steps) << "no saving: the outer step is the bonds'";
}

// One explicit reference for both methods (it is the expensive run).
template <int D>
void check_shear_drag_both() {
  const FiberResult ref = shear_drag<D>(Bonds::Explicit);
  check_shear_drag<D>(ref, shear_drag<D>(Bonds::Subcycled), "sub-cycled");
  check_shear_drag<D>(ref, shear_drag<D>(Bonds::Implicit), "implicit");
}

TEST(GlassBonds, SubcycledAndImplicitMatchExplicitInShear2D) {
  check_shear_drag_both<2>();
}
TEST(GlassBonds, SubcycledAndImplicitMatchExplicitInShear3D) {
  check_shear_drag_both<3>();
}

// The cantilever of tests/test_dem_validation.cpp (10 glass bonds, tip
// load for a 1 % deflection, critical damping of the first mode, which is
// a slow force here), sub-cycled: the same chain's error and tolerance.
template <int D>
void check_cantilever(Bonds bonds) {
  const int n_bonds = 10;
  DemSystem<D> sys = glass_fiber<D>(n_bonds + 1, 0.0, bonds);
  auto& ps = sys.particles;
  ps.fixed[0] = kFixedMotion;
  const double L = n_bonds * 2 * kR;
  const double I = D == 2 ? 2.0 / 3.0 * std::pow(kR, 3) : kPi * std::pow(kR, 4) / 4;
  const double A = D == 2 ? 2.0 * kR : kPi * kR * kR;
  const double delta_target = 0.01 * L;
  const double F = 3 * kGlass * I * delta_target / std::pow(L, 3);
  ps.f_ext.back() = -F * Vec<D>::Unit(1);
  const double rho_l = ps.mass[0] / (2 * kR);
  const double omega_1 = 1.875104 * 1.875104 * std::sqrt(kGlass * I / (rho_l * std::pow(L, 4)));
  sys.params.global_damping = 2 * omega_1;
  sys.invalidate_forces();
  const Vec<D> x0 = ps.x.back();
  const double dt = outer_dt(sys);
  const auto steps = static_cast<long>(40.0 / (omega_1 * dt));
  for (long s = 0; s < steps; ++s) sys.step(dt);
  const double err = -(ps.x.back() - x0)[1] / delta_target - 1;
  const double l = 2 * kR, n2 = n_bonds * n_bonds;
  const double expected = -0.25 / n2 + 3 * sys.params.kbar_star * I / A / (l * l * n2);
  std::printf(
      "glass cantilever %s D=%d: err %.3e (chain's own %.3e), %ld steps of %.3g s, "
      "%ld inner each\n",
      bonds == Bonds::Implicit ? "implicit" : "sub-cycled", D, err, expected, steps, dt,
      static_cast<long>(dem_bond_substeps(sys.params, dt)));
  EXPECT_GT(dem_bond_substeps(sys.params, dt), 10);
  EXPECT_LT(std::abs(err), 0.05);
  EXPECT_NEAR(err, expected, 5e-4);
}

TEST(GlassBonds, CantileverSubcycled2D) {
  check_cantilever<2>(Bonds::Subcycled);
}
TEST(GlassBonds, CantileverSubcycled3D) {
  check_cantilever<3>(Bonds::Subcycled);
}
TEST(GlassBonds, CantileverImplicit2D) {
  check_cantilever<2>(Bonds::Implicit);
}
TEST(GlassBonds, CantileverImplicit3D) {
  check_cantilever<3>(Bonds::Implicit);
}

// ------------------------------------------------------- coupled, ranks

struct FiberRow {
  std::int64_t gid = 0;
  double value[7] = {};
};

// The coupled box's columns: x, y, u, v, spin, and each particle's first
// bond's (the bond to the next particle) peak stresses.
constexpr int kSampledPeak = 5;  // largest |sigma| at the SPH steps' ends
constexpr int kRunPeak = 6;      // largest tensile sigma at every DEM evaluation (sigma_run)

std::vector<FiberRow> coupled_box(const Comm& comm, const std::string& integration, int steps) {
  const Case c = testing::load_input(
      "validation/coupled_box.yaml",
      {"fibers.youngs_modulus=7.2e10", "fibers.bond_integration=" + integration});
  RunOptions opt;
  opt.write_output = false;
  Simulation<2> sim(c, comm, opt);
  // Per bond (by its owner's gid) the largest |sigma| seen at a step's end.
  std::map<std::int64_t, double> peak;
  for (int s = 0; s < steps; ++s) {
    sim.advance(1);
    const auto& f = sim.dem()->particles();
    for (std::size_t i = 0; i < f.n_owned; ++i) {
      const double sigma = f.bonds[i][0].partner >= 0 ? std::abs(f.bonds[i][0].sigma) : 0.0;
      peak[f.gid[i]] = std::max(peak[f.gid[i]], sigma);
    }
  }
  const auto& f = sim.dem()->particles();
  std::vector<FiberRow> rows;
  for (std::size_t i = 0; i < f.n_owned; ++i) {
    const double run_peak = f.bonds[i][0].partner >= 0 ? f.bond_peaks[i][0].sigma_run : 0.0;
    rows.push_back(
        {f.gid[i], {f.x[i][0], f.x[i][1], f.v[i][0], f.v[i][1], f.omega[i][0], 0.0, run_peak}});
  }
  rows = testing_mpi::gather_rows(comm, rows);
  // A particle's sampled peak is spread over the ranks that owned it in
  // turn (it migrates): the largest of theirs.
  struct PeakRow {
    std::int64_t gid = 0;
    double value[1] = {};
  };
  std::vector<PeakRow> seen;
  for (const auto& [gid, p] : peak) seen.push_back({gid, {p}});
  for (const PeakRow& r : testing_mpi::gather_rows(comm, seen)) {
    const auto row = std::lower_bound(rows.begin(), rows.end(), r.gid,
                                      [](const FiberRow& a, std::int64_t g) { return a.gid < g; });
    if (row != rows.end() && row->gid == r.gid)
      row->value[kSampledPeak] = std::max(row->value[kSampledPeak], r.value[0]);
  }
  return rows;
}

struct PeakGap {
  double largest = 0;  // the reference's largest peak [Pa]
  double e_peak = 0;   // relative gap of the largest peaks
  double e_rms = 0;    // RMS gap over the bonds / RMS of the reference
  double e_bond = 0;   // largest single-bond gap / the largest peak
};

PeakGap peak_gap(const std::vector<FiberRow>& ref, const std::vector<FiberRow>& got, int column) {
  std::vector<double> s_ref, s_got;
  double peak_got = 0, d2 = 0, r2 = 0;
  PeakGap g;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const double a = ref[k].value[column], b = got[k].value[column];
    s_ref.push_back(a);
    s_got.push_back(b);
    g.largest = std::max(g.largest, std::abs(a));
    peak_got = std::max(peak_got, std::abs(b));
    d2 += (b - a) * (b - a);
    r2 += a * a;
  }
  g.e_peak = std::abs(peak_got / g.largest - 1);
  g.e_rms = std::sqrt(d2 / r2);
  g.e_bond = relative_gap(s_ref, s_got);
  return g;
}

// 30 glass fibers falling through a sloshing resin (the coupled box of the
// parallel tests), 40 SPH steps: the sub-cycled and the implicit bonds'
// peak stresses and the fibers' positions against the explicit run's.
//
// The bond stresses of these free fibers are mostly the ring-down of their
// start from rest (a few kPa, bending vibrations the resin damps over a
// drag time, 0.1 ms, of thousands of periods of the explicit bond step),
// whose phase the integrators do not share: the implicit (trapezoidal)
// rule keeps a mode's amplitude but lowers its frequency (by 5 % at
// omega dt = 0.8), so after a few hundred periods the phase at a given
// instant is unrelated. Sampled at the 40 SPH steps' ends, each bond's
// peak is the envelope times |cos| of an arbitrary phase: 5.4 % (largest)
// and 7.6 % (RMS) apart. The bond's peak over every evaluation of it (the
// explicit run's bond steps, the implicit run's outer steps: the peaks the
// run writes, docs/dem.md "Bond stress peaks") is the envelope in both,
// and it is what the test compares (docs/validation.md section 10).
void check_coupled_box(const std::vector<FiberRow>& ref, const std::vector<FiberRow>& got,
                       const char* method) {
  ASSERT_EQ(ref.size(), got.size());
  double travel = 0, gap = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    gap = std::max(
        gap, std::hypot(got[k].value[0] - ref[k].value[0], got[k].value[1] - ref[k].value[1]));
    travel = std::max(travel, std::hypot(ref[k].value[2], ref[k].value[3]));
  }
  const PeakGap sampled = peak_gap(ref, got, kSampledPeak), run = peak_gap(ref, got, kRunPeak);
  std::printf(
      "coupled glass box, %s vs explicit: bond peaks over every DEM evaluation: largest %.4g Pa, "
      "%.2e off, RMS gap %.2e, largest single-bond gap %.2e of the largest; sampled at the SPH "
      "steps' ends: largest %.4g Pa, %.2e off, RMS %.2e, single bond %.2e; position gap %.3g m "
      "= %.2e fiber diameters\n",
      method, run.largest, run.e_peak, run.e_rms, run.e_bond, sampled.largest, sampled.e_peak,
      sampled.e_rms, sampled.e_bond, gap, gap / (2 * kR));
  EXPECT_LT(run.e_peak, 0.05) << method;
  EXPECT_LT(run.e_rms, 0.05) << method;
  EXPECT_LT(gap, 0.05 * 2 * kR) << method << ": fibers moved apart by more than 5 % of a diameter";
  EXPECT_GT(travel, 0.0);
}

constexpr int kBoxSteps = 40;

// One rank: both methods against the explicit run.
TEST(GlassBonds, CoupledBoxSubcycledAndImplicitMatchExplicit) {
  const Comm self(MPI_COMM_SELF);
  const std::vector<FiberRow> ref = coupled_box(self, "explicit", kBoxSteps);
  check_coupled_box(ref, coupled_box(self, "subcycled", kBoxSteps), "sub-cycled");
  check_coupled_box(ref, coupled_box(self, "implicit", kBoxSteps), "implicit");
}

// N ranks: bitwise the 1-rank run, sub-cycled and implicit.
TEST(GlassBonds, CoupledBoxRanksAreBitwise) {
  const Comm world;
  for (const char* method : {"subcycled", "implicit"}) {
    std::vector<FiberRow> one;
    if (world.root()) one = coupled_box(Comm(MPI_COMM_SELF), method, kBoxSteps);
    testing_mpi::wait_for_root(world);
    const std::vector<FiberRow> got = coupled_box(world, method, kBoxSteps);
    if (!world.root()) continue;
    EXPECT_EQ(testing_mpi::bitwise_mismatches(one, got), 0u)
        << method << ": " << world.size() << " ranks change the result";
    for (std::size_t k = 0; k < std::min(one.size(), got.size()); ++k)
      for (int c = 0; c < 7; ++c)
        if (std::memcmp(&one[k].value[c], &got[k].value[c], sizeof(double)) != 0)
          std::printf("%s: particle %lld column %d: %.17g on 1 rank, %.17g on %d\n", method,
                      static_cast<long long>(one[k].gid), c, one[k].value[c], got[k].value[c],
                      world.size());
  }
}

}  // namespace
}  // namespace sphdem
