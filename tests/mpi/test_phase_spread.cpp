// The loop's time per phase over the ranks (app/RunCommand: measure_phases), checked against
// every rank's own seconds gathered in full: the least, the mean and the most of each phase.
// The per-step traffic (comm) and the rebuild (neighbour) are booked apart.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/RunCommand.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

TEST(PhaseSpread, LeastMeanAndMostMatchEveryRanksOwnSeconds) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const CaseConfig c = testing::grains_entering_and_leaving();
    Simulation sim(build_model(c, comm), comm, settings_from_case(c));
    sim.run_steps(200);
    ASSERT_GT(sim.rebuilds(), 1) << "the case must rebuild during the steps";
    const PhaseSpread spread = measure_phases(sim);

    constexpr int n = Simulation::kPhaseCount;
    const std::array<double, n>& mine = sim.phase_seconds();
    std::vector<double> all(static_cast<std::size_t>(n * comm.size()));
    MPI_Allgather(mine.data(), n, MPI_DOUBLE, all.data(), n, MPI_DOUBLE, world);
    ASSERT_EQ(spread.names.size(), static_cast<std::size_t>(n));
    double loop_total = 0.0;
    for (int ph = 0; ph < n; ++ph) {
      const auto u = static_cast<std::size_t>(ph);
      EXPECT_EQ(spread.names[u], Simulation::phase_name(ph));
      double least = all[u], most = all[u], sum = 0.0;
      for (int r = 0; r < comm.size(); ++r) {
        const double s = all[static_cast<std::size_t>(r * n + ph)];
        least = std::min(least, s);
        most = std::max(most, s);
        sum += s;
      }
      EXPECT_EQ(spread.min[u], least) << spread.names[u];
      EXPECT_EQ(spread.max[u], most) << spread.names[u];
      // The exact sum rounded once against a plain one: a few ulps of the mean.
      EXPECT_NEAR(spread.mean[u], sum / comm.size(), 1e-12 * (1.0 + sum)) << spread.names[u];
      EXPECT_LE(spread.min[u], spread.mean[u]);
      EXPECT_LE(spread.mean[u], spread.max[u]);
      loop_total += mine[u];
    }
    EXPECT_GT(loop_total, 0.0);
    // Each rebuild is booked as neighbour and each step's refresh and reduction as comm.
    EXPECT_GT(mine[Simulation::kNeighbour], 0.0);
    EXPECT_GT(mine[Simulation::kComm], 0.0);
    EXPECT_EQ(std::string(Simulation::phase_name(Simulation::kComm)), "comm");
    EXPECT_EQ(std::string(Simulation::phase_name(Simulation::kNeighbour)), "neighbour");
  }
}

}  // namespace
}  // namespace ringdem
