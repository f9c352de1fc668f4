// Re-sorts of the grains by space (Simulation, simulation.sort_every; domain/SpatialBins). After
// a re-sort the owned grains are stored in the order of their bins, each bin that of the grain's
// position at the re-sort; the motion is the same physics in another order of summation, so it
// matches a run that never re-sorts (gid order) to round-off, not bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "TestCases.hpp"
#include "domain/SpatialBins.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

Simulation make_simulation(const CaseConfig& c, const Communicator& comm, std::int64_t sort_every) {
  SimulationSettings s = settings_from_case(c);
  s.dt = 1e-6;
  s.skin = 0.0005;
  s.sort_every = sort_every;
  return Simulation(build_model(c, comm), comm, s);
}

double smallest_radius(const ParticleStore& p) {
  double r_min = INFINITY;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    r_min = std::min(r_min, p.radius[k]);
  return r_min;
}

/// Each owned grain holds the bin of its present position (cubes of twice the smallest radius),
/// the grains are stored in key order, and that order is not the gid order.
void expect_stored_by_bins(const ParticleStore& p, double r_min) {
  std::size_t out_of_gid_order = 0;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    ASSERT_EQ(p.sort_bin[k], SpatialBins::bin_of(p.position[k], 2.0 * r_min)) << "grain " << k;
    if (k == 0) continue;
    ASSERT_TRUE(p.sorts_before(k - 1, k)) << "stored out of key order at " << k;
    out_of_gid_order += p.gid[k - 1] > p.gid[k];
  }
  EXPECT_GT(out_of_gid_order, p.n_local() / 10) << "the bins must reorder the grains";
}

TEST(GrainResort, StoresGrainsByTheirBinsAndMovesThemAsGidOrderDoesToRoundOff) {
  const CaseConfig c = testing::colliding_clouds();
  const Communicator comm = testing::self_comm();
  Simulation sorted = make_simulation(c, comm, 100);
  Simulation by_gid = make_simulation(c, comm, 0);
  // 1000 steps (re-sorts at 0, 100, ..., 900), then the step that re-sorts at 1000: its drift
  // put the grains where they are now (the second half kick moves none), so each bin must be
  // that of the grain's present position.
  sorted.run_steps(1000);
  by_gid.run_steps(1000);
  sorted.run_steps(1);
  by_gid.run_steps(1);
  const ParticleStore& p = sorted.model().particles;
  const ParticleStore& q = by_gid.model().particles;
  ASSERT_EQ(p.n_local(), q.n_local());
  ASSERT_GT(p.n_local(), 200u);
  const double r_min = smallest_radius(p);
  ASSERT_NO_FATAL_FAILURE(expect_stored_by_bins(p, r_min));
  for (std::size_t k = 0; k < q.n_local(); ++k) {
    ASSERT_EQ(q.sort_bin[k], 0u);
    if (k > 0) {
      ASSERT_LT(q.gid[k - 1], q.gid[k]);
    }
  }
  // The same motion, summed in another order: round-off, amplified by the collisions over 1000
  // steps, stays below 1e-9 of the smallest radius (about 4e-19 m was measured, against the
  // 7e-18 m of one rounding of a coordinate of 0.05 m). The sums differ somewhere.
  double largest = 0.0;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const auto j = static_cast<std::size_t>(q.index_of(p.gid[k]));
    largest = std::max(largest, norm(p.position[k] - q.position[j]));
  }
  std::printf("largest position difference by gid after 1001 steps: %.3g m (r_min %.3g m)\n",
              largest, r_min);
  EXPECT_LT(largest, 1e-9 * r_min);
  EXPECT_GT(largest, 0.0) << "no difference at all: the orders did not differ where it counts";
}

// A fresh run sorts its grains before its first lists are built, as LAMMPS sorts at set-up: the
// initial evaluation already walks them in bin order, and the first step, which would re-sort
// at step 0, builds nothing again (it did, a second full rebuild in every fresh run).
TEST(GrainResort, AFreshRunIsSortedAtSetUpAndItsFirstStepDoesNotRebuild) {
  const CaseConfig c = testing::colliding_clouds();
  const Communicator comm = testing::self_comm();
  Simulation sim = make_simulation(c, comm, 100);
  const ParticleStore& p = sim.model().particles;
  ASSERT_GT(p.n_local(), 200u);
  ASSERT_NO_FATAL_FAILURE(expect_stored_by_bins(p, smallest_radius(p)));
  // One rebuild at set-up; the clouds' grains move far less than the skin in 10 steps of 1 us
  // (their speed times 1e-5 s against a skin of 0.5 mm), so nothing rebuilds the lists until
  // the re-sort at step 100.
  EXPECT_EQ(sim.rebuilds(), 1);
  sim.run_steps(10);
  EXPECT_EQ(sim.rebuilds(), 1);
  sim.run_steps(91);
  EXPECT_GE(sim.rebuilds(), 2) << "the re-sort at step 100 rebuilds";
}

}  // namespace
}  // namespace ringdem
