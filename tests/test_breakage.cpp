// Bond stress peaks and broken fibers against hand computations (docs/dem.md,
// "Bond stress peaks", "Broken fibers"): the peaks a bond keeps over the run
// and over an output interval, sub-step by sub-step, and the pieces a
// broken bond splits a fiber into (ids and lengths).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "../src/solver/dem_checkpoint.hpp"
#include "sphdem/dem/dem.hpp"
#include "sphdem/dem/fiber_pieces.hpp"

namespace sphdem {
namespace {

// Two disks bonded in 2D, both driven (kFixedMotion): the right one moves
// at u along the bond, so the bond's stretch after k steps is k u dt and
// its tensile stress sigma = kbar_n (L - L0) = E / (2 R) k u dt
// (src/dem/terms/parallel_bond.hpp).
struct DrivenPair {
  DemSystem<2> sys;
  double dt = 1e-4, u = 1e-3, r = 0.1;
  explicit DrivenPair(double strength) {
    sys.params.kn = 1e3;
    sys.params.youngs_modulus = 1e6;
    sys.params.tensile_strength = strength;
    sys.params.shear_strength = 1e30;
    sys.add_particle(Vec<2>(0, 0), r, 1000, 0);
    sys.add_particle(Vec<2>(2 * r, 0), r, 1000, 0);
    sys.add_bond(0, 1);
    for (std::size_t i = 0; i < 2; ++i) sys.particles.fixed[i] = kFixedMotion;
  }
  void steps(int n, double v) {
    sys.particles.v[1] = Vec<2>(v, 0);
    for (int k = 0; k < n; ++k) sys.step(dt);
  }
  // sigma after a net stretch of k steps at speed u.
  double sigma(int k) const { return sys.params.youngs_modulus / (2 * r) * k * u * dt; }
  const BondPeak& peak() const { return sys.particles.bond_peaks[0][0]; }
};

// Pulled for 30 steps, pushed back for 20: the run's peak is the stress at
// step 30 (a snapshot at step 50 would not see it), the interval started
// at step 40 (a snapshot there) peaks at step 41.
TEST(BondPeaks, RunAndIntervalMaximaEverySubstep) {
  DrivenPair p(1e30);
  p.steps(30, p.u);
  EXPECT_NEAR(p.sys.particles.bonds[0][0].sigma, p.sigma(30), 1e-9 * p.sigma(30));
  p.steps(10, -p.u);
  for (BondPeak& b : p.sys.particles.bond_peaks[0]) b.start_interval();
  p.steps(10, -p.u);
  EXPECT_NEAR(p.sys.particles.bonds[0][0].sigma, p.sigma(10), 1e-9 * p.sigma(30));
  EXPECT_NEAR(p.peak().sigma_run, p.sigma(30), 1e-9 * p.sigma(30));
  EXPECT_NEAR(p.peak().sigma_interval, p.sigma(19), 1e-9 * p.sigma(30));
  EXPECT_EQ(p.peak().tau_run, 0.0);  // no shear: the pair moves along the bond
  // The peaks are the owner's (smaller gid): the partner's slot stays empty.
  EXPECT_EQ(p.sys.particles.bond_peaks[1][0].sigma_run, 0.0);
}

// A bond that breaks keeps the stress that broke it as its peak, and
// records nothing after (a contact pair now).
TEST(BondPeaks, BreakingStressIsThePeak) {
  DrivenPair probe(1e30);
  const double strength = 0.5 * (probe.sigma(12) + probe.sigma(13));  // breaks at step 13
  DrivenPair p(strength);
  p.steps(12, p.u);
  EXPECT_FALSE(p.sys.particles.bonds[0][0].broken);
  p.steps(1, p.u);
  ASSERT_TRUE(p.sys.particles.bonds[0][0].broken);
  EXPECT_NEAR(p.peak().sigma_run, p.sigma(13), 1e-9 * p.sigma(13));
  p.steps(40, p.u);
  EXPECT_NEAR(p.peak().sigma_run, p.sigma(13), 1e-9 * p.sigma(13));
  EXPECT_NEAR(p.peak().sigma_interval, p.sigma(13), 1e-9 * p.sigma(13));
}

// A checkpoint written before the peaks were kept has no "bond_peaks"
// column: it reads as zero peaks, any other column list is untouched.
TEST(BondPeaks, OldCheckpointColumnsReadAsZeroPeaks) {
  DrivenPair p(1e30);
  p.steps(5, p.u);
  std::vector<CheckpointColumn> cols = checkpoint_columns(p.sys.particles);
  const auto has_peaks = [](const CheckpointColumn& c) { return c.name == "bond_peaks"; };
  ASSERT_EQ(std::count_if(cols.begin(), cols.end(), has_peaks), 1);
  add_missing_bond_peaks(cols, 2);  // present: nothing added
  EXPECT_EQ(std::count_if(cols.begin(), cols.end(), has_peaks), 1);
  cols.erase(std::remove_if(cols.begin(), cols.end(), has_peaks), cols.end());
  add_missing_bond_peaks(cols, 2);
  DemParticles<2> back;
  assign_checkpoint_columns(back, cols, 2, "old.ckpt.h5");
  EXPECT_EQ(back.bond_peaks[0][0].sigma_run, 0.0);
  EXPECT_EQ(back.x[1], p.sys.particles.x[1]);
  EXPECT_EQ(back.bonds[0][0].sigma, p.sys.particles.bonds[0][0].sigma);
}

// Fiber 0: 0-1-2-3-4 with bond 2-3 broken (absent from the intact bonds),
// then 4 alone after 3-4 broke too; fiber 1: 5-6-7 intact; 8 loose. Radii
// differ per particle; the input order is shuffled.
TEST(FiberPieces, IdsAndLengthsByHand) {
  const std::vector<double> radius{1, 2, 3, 4, 5, 6, 7, 8, 9};
  const std::vector<std::int32_t> fiber{0, 0, 0, 0, 0, 1, 1, 1, -1};
  std::vector<std::size_t> order(9);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937_64(3));
  FiberPieceInput in;
  for (std::size_t g : order) {
    in.gid.push_back(static_cast<std::int64_t>(g));
    in.fiber.push_back(fiber[g]);
    in.radius.push_back(radius[g]);
  }
  in.bonds = {{6, 7}, {1, 2}, {3, 4}, {0, 1}, {5, 6}};
  const std::vector<std::int64_t> piece{0, 0, 0, 3, 3, 5, 5, 5, -1};
  const std::vector<double> length{12, 12, 12, 18, 18, 42, 42, 42, 0};  // 2 (r_a + r_b + ...)
  FiberPieces out = fiber_pieces(in);
  for (std::size_t k = 0; k < order.size(); ++k) {
    EXPECT_EQ(out.piece[k], piece[order[k]]) << "gid " << order[k];
    EXPECT_EQ(out.length[k], length[order[k]]) << "gid " << order[k];
  }
  in.bonds.erase(in.bonds.begin() + 2);  // 3-4 breaks: 3 and 4 are one-particle fibers
  out = fiber_pieces(in);
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (order[k] == 3 || order[k] == 4) {
      EXPECT_EQ(out.piece[k], static_cast<std::int64_t>(order[k]));
      EXPECT_EQ(out.length[k], 2 * radius[order[k]]);
    }
  }
  in.bonds.emplace_back(4, 11);
  EXPECT_THROW(fiber_pieces(in), std::invalid_argument);
}

}  // namespace
}  // namespace sphdem
