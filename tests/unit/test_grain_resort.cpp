// Re-sorts of the grains by space (Simulation, simulation.sort_every; domain/SpatialBins). After
// a re-sort the owned grains are stored in the order of their bins, each bin that of the grain's
// position at the re-sort; the motion is the same physics in another order of summation, so it
// matches a run that never re-sorts (gid order) to round-off, not bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
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

/// Each owned grain holds the bin of its present position (cubes of twice the smallest radius,
/// numbered slowest along the longest side of the grains' box, here `slowest`), the grains are
/// stored in key order, and that order is not the gid order.
void expect_stored_by_bins(const ParticleStore& p, double r_min, SpatialBins::Axis slowest) {
  Vec3 lo = p.position[0], hi = p.position[0];
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    lo = {std::min(lo.x, p.position[k].x), std::min(lo.y, p.position[k].y),
          std::min(lo.z, p.position[k].z)};
    hi = {std::max(hi.x, p.position[k].x), std::max(hi.y, p.position[k].y),
          std::max(hi.z, p.position[k].z)};
  }
  const Vec3 side = hi - lo;
  const double sides[3] = {side.x, side.y, side.z};
  for (int a = 0; a < 3; ++a) {
    if (a != slowest) {
      ASSERT_GT(sides[slowest], sides[a]) << "axis " << a;
    }
  }
  const SpatialBins::Order order{2.0 * r_min, slowest};
  std::size_t out_of_gid_order = 0;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    ASSERT_EQ(p.sort_bin[k], SpatialBins::bin_of(p.position[k], order)) << "grain " << k;
    if (k == 0) continue;
    ASSERT_TRUE(p.sorts_before(k - 1, k)) << "stored out of key order at " << k;
    out_of_gid_order += p.gid[k - 1] > p.gid[k];
  }
  EXPECT_GT(out_of_gid_order, p.n_local() / 10) << "the bins must reorder the grains";
}

TEST(GrainResort, StoresGrainsByTheirBinsAndMovesThemAsGidOrderDoesToRoundOff) {
  // The clouds 0.14 m deep along y, longer than the 0.1 m of both along x: the bins go slowest
  // along y. (Slowest along x, the clouds' own length, the bins ordered each grain's partners
  // as the gids do, and the two runs were the same bits: no test of the other order.)
  CaseConfig c = testing::colliding_clouds();
  for (auto& cloud : c.grains)
    cloud.box_max.y = 0.14;
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
  ASSERT_NO_FATAL_FAILURE(expect_stored_by_bins(p, r_min, SpatialBins::kY));
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
  // The clouds lie side by side along x: 0.1 m there against 0.06 m along y and 0.03 m along z.
  ASSERT_NO_FATAL_FAILURE(expect_stored_by_bins(p, smallest_radius(p), SpatialBins::kX));
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
