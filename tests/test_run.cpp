// The run driver (include/sphdem/solver/run.hpp, docs/architecture.md): every case
// goes through one Run, whose modules the case decides (a fibers-only run
// is a run without the resin); the step, the health check and the progress
// line are the run's, whatever its modules.
#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "sphdem/config/config.hpp"
#include "sphdem/core/errors.hpp"
#include "sphdem/io/checkpoint.hpp"
#include "sphdem/parallel/comm.hpp"
#include "sphdem/solver/coupled_skins.hpp"
#include "sphdem/solver/dem_run.hpp"
#include "sphdem/solver/output_cadence.hpp"
#include "sphdem/solver/solver.hpp"
#include "validation_helpers.hpp"

namespace sphdem {
namespace {

using testing::quiet;

Case input(const std::string& file, const std::vector<std::string>& sets = {}) {
  return load_case(std::string(SPHDEM_SOURCE_DIR) + "/inputs/" + file, sets);
}

using Names = std::vector<std::string>;

TEST(RunDriver, TheCaseChoosesTheModules) {
  const Comm comm;
  const sphdem::Run<2> fibers(input("fibers_only.yaml"), comm, quiet());
  EXPECT_EQ(fibers.module_names(), Names({"fibers"}));
  EXPECT_EQ(fibers.resin(), nullptr);
  ASSERT_NE(fibers.fibers(), nullptr);
  EXPECT_FALSE(fibers.fibers()->coupled());

  const sphdem::Run<2> coupled(input("validation/coupled_box.yaml"), comm, quiet());
  EXPECT_EQ(coupled.module_names(), Names({"resin", "fibers", "coupling"}));
  ASSERT_NE(coupled.fibers(), nullptr);
  EXPECT_TRUE(coupled.fibers()->coupled());
  // The coupled fibers' ghosts reach as far as the resin's kernel.
  EXPECT_GE(coupled.fibers()->dem().halo_range(), coupled.resin()->neighbor_cutoff());

  const sphdem::Run<2> resin(input("validation/poiseuille.yaml"), comm, quiet());
  EXPECT_EQ(resin.module_names(), Names({"resin"}));
  EXPECT_EQ(resin.fibers(), nullptr);
  EXPECT_EQ(resin.coupling(), nullptr);

  // The wrappers are the same driver with the same modules.
  const DemRun<2> dem_run(input("fibers_only.yaml"), comm, quiet());
  EXPECT_EQ(dem_run.module_names(), Names({"fibers"}));
  const Simulation<2> sim(input("validation/coupled_box.yaml"), comm, quiet());
  EXPECT_EQ(sim.module_names(), Names({"resin", "fibers", "coupling"}));
}

// The coupling's partners are owned or ghosts on every rank
// (coupled_skins.hpp): a fiber strays at most half the fibers' skin from
// its rank's cells, a resin particle at most kCoupledResinMoveShare of the
// resin's skin from its place at the build, and the two together stay
// within the resin's skin, which the ghosts cover beyond the support. This
// case's fibers alone would take a skin of their radius, 0.125 mm, more
// than the resin's 0.108 mm: half of each, 0.1165 mm, would have been
// beyond the ghosts' reach even with the resin's half-skin rule.
TEST(RunDriver, CoupledSkinsKeepTheCouplingsPartnersInTheHalo) {
  const Comm comm;
  const sphdem::Run<2> coupled(input("validation/coupled_box.yaml"), comm, quiet());
  const double resin_skin = coupled.resin()->neighbor_skin();
  const double fiber_skin = coupled.fibers()->dem().list_skin();
  EXPECT_GT(0.5 * 2.5e-4, resin_skin);
  EXPECT_EQ(fiber_skin, kFiberSkinShare * resin_skin);
  EXPECT_LE(kCoupledResinMoveShare * resin_skin + 0.5 * fiber_skin, resin_skin);
  EXPECT_GE(coupled.fibers()->dem().halo_range(), coupled.resin()->neighbor_cutoff());
  // A resin without a skin rebuilds at every move; so do the fibers, on
  // the smallest positive skin (0 would mean a quarter of their radius).
  const sphdem::Run<2> no_skin(input("validation/coupled_box.yaml", {"numerics.neighbor_skin=0"}),
                               comm, quiet());
  EXPECT_EQ(no_skin.resin()->neighbor_skin(), 0.0);
  EXPECT_EQ(no_skin.fibers()->dem().list_skin(), std::numeric_limits<double>::min());
}

TEST(RunDriver, WrappersRefuseTheOtherKindOfCase) {
  const Comm comm;
  EXPECT_THROW(Simulation<2>(input("fibers_only.yaml"), comm, quiet()), std::invalid_argument);
  EXPECT_THROW(DemRun<2>(input("validation/poiseuille.yaml"), comm, quiet()),
               std::invalid_argument);
}

// Fibers alone step at the stable DEM step; coupled fibers sub-step within
// the resin's step, which the resin limits.
TEST(RunDriver, TheStepComesFromTheModules) {
  const Comm comm;
  sphdem::Run<2> fibers(input("fibers_only.yaml"), comm, quiet());
  fibers.advance(5);
  EXPECT_EQ(fibers.step(), 5);
  EXPECT_EQ(fibers.last_dt_limit(), DtLimit::Dem);
  EXPECT_EQ(fibers.last_dt(), fibers.fibers()->dem_dt());
  double t = 0;
  for (int s = 0; s < 5; ++s) t += fibers.fibers()->dem_dt();
  EXPECT_EQ(fibers.time(), t);

  sphdem::Run<2> coupled(input("validation/coupled_box.yaml"), comm, quiet());
  coupled.advance(2);
  EXPECT_EQ(coupled.step(), 2);
  EXPECT_NE(coupled.last_dt_limit(), DtLimit::Dem);
  EXPECT_GT(coupled.last_dt(), coupled.fibers()->dem_dt());
  EXPECT_GE(coupled.fibers()->substeps(), 1);
  EXPECT_EQ(coupled.fibers()->coupled_dt(), coupled.last_dt());
}

// One progress line for every run: the limit of the step and, fibers alone,
// the piston's speed.
TEST(RunDriver, OneProgressLine) {
  const Comm comm;
  std::ostringstream log;
  RunOptions opt = quiet();
  opt.max_steps = 2;
  opt.log = &log;
  sphdem::Run<2> fibers(input("fibers_only.yaml", {"output.progress_every=1"}), comm, opt);
  const RunSummary s = fibers.run();
  EXPECT_EQ(s.steps, 2);
  EXPECT_GT(s.particle_steps_per_second, 0);
  if (comm.root()) {
    EXPECT_NE(log.str().find("step        2  t="), std::string::npos) << log.str();
    EXPECT_NE(log.str().find("(dem)"), std::string::npos) << log.str();
    EXPECT_NE(log.str().find("piston v="), std::string::npos) << log.str();
  }
}

// The health check covers every module and stops every rank together; the
// lowest rank with a problem names it.
TEST(RunDriver, HealthCheckOfEveryModule) {
  const Comm comm;
  sphdem::Run<2> fibers(input("fibers_only.yaml"), comm, quiet());
  DemParticles<2>& f = fibers.fibers()->dem().particles();
  const bool last = comm.rank() == comm.size() - 1;
  if (last && f.n_owned > 0) f.x[0][1] = 1.0;  // far above the mold
  // When the last rank owns no fiber particle, nothing fails.
  if (comm.any(last && f.n_owned > 0)) {
    try {
      fibers.advance(0);
      ADD_FAILURE() << "no error for a fiber out of the mold";
    } catch (const SimulationError& e) {
      const std::string what = e.what();
      if (last)
        EXPECT_NE(what.find("left the mold"), std::string::npos) << what;
      else  // the failing rank and its particle, on every rank
        EXPECT_NE(what.find("rank " + std::to_string(comm.size() - 1) + ": "), std::string::npos)
            << what;
      EXPECT_NE(what.find("left the mold"), std::string::npos) << what;
    }
  }

  sphdem::Run<2> resin(input("validation/poiseuille.yaml"), comm, quiet());
  SphParticles<2>& ps = resin.resin()->particles();
  if (comm.root() && ps.n_owned > 0) ps.x[0][1] = -1.0;  // below the plates
  ASSERT_TRUE(comm.any(comm.root() && ps.n_owned > 0));
  try {
    resin.advance(0);
    ADD_FAILURE() << "no error for a resin particle out of the domain";
  } catch (const SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("left the domain along axis y"), std::string::npos) << what;
    if (!comm.root()) {
      EXPECT_NE(what.find("rank 0: "), std::string::npos) << what;
    }
  }
}

// Issue 15, defect 4: an interval below the resolution of the time made the
// catch-up loops spin for ever (the app refuses such an interval, these
// loops end all the same).
TEST(OutputCadence, AnIntervalBelowTheTimesResolutionEnds) {
  Output out;
  out.every_time = 1e-300;
  OutputCadence cadence(out, 0.0);
  EXPECT_TRUE(cadence.due(1, 1e-3));
  EXPECT_TRUE(cadence.due(2, 2e-3));  // once per step, at most
  OutputCadence resumed = resumed_output_cadence(out, 1e-3);
  EXPECT_TRUE(resumed.due(3, 3e-3));
}

TEST(OutputCadence, ACatchUpWritesOnce) {
  Output out;
  out.every_time = 1e-3;
  OutputCadence cadence(out, 0.0);
  EXPECT_FALSE(cadence.due(1, 0.5e-3));
  EXPECT_TRUE(cadence.due(2, 3.5e-3));  // jumps over three multiples
  EXPECT_FALSE(cadence.due(3, 3.9e-3));
  EXPECT_TRUE(cadence.due(4, 4.0e-3));
}

// Where a key was set, for errors found after loading (config.hpp).
TEST(KeyLocation, FileLineOrSet) {
  const Case c = input("validation/poiseuille.yaml", {"numerics.end_time=1"});
  const KeyLocation spacing = key_location(c, "numerics.spacing");
  EXPECT_EQ(spacing.file, c.source_file);
  EXPECT_GT(spacing.line, 1);
  EXPECT_EQ(key_location(c, "numerics.end_time").file, "--set");
  EXPECT_EQ(key_location(c, "output.no_such_key").line, 0);
  // The lookup leaves the case's text as it was.
  EXPECT_EQ(key_location(c, "numerics.spacing").line, spacing.line);
}

}  // namespace
}  // namespace sphdem
