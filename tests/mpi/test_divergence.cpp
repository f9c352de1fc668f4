// The divergence guard: a run with a time step far above the stable one, and one with two
// coincident spheres, stop at the same step on every rank count, naming the same particle.
#include <gtest/gtest.h>
#include <mpi.h>

#include <string>

#include "TestCases.hpp"
#include "engine/DivergenceError.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

struct Verdict {
  std::int64_t step = -1;
  std::string particle;  ///< "particle <gid> (group <name>"
  std::string message;
};

/// Runs up to `steps` steps; the step and the named particle of the divergence, if any.
Verdict run_until_divergence(const CaseConfig& c, const Communicator& comm, std::int64_t steps) {
  Simulation sim(build_model(c, comm), comm, settings_from_case(c));
  Verdict v;
  try {
    sim.run_steps(steps);
  } catch (const DivergenceError& e) {
    v.step = e.step();
    v.message = e.what();
    const auto at = v.message.find("particle ");
    const auto comma = v.message.find(',', at);
    if (at != std::string::npos && comma != std::string::npos)
      v.particle = v.message.substr(at, comma - at);
  }
  return v;
}

void expect_same_on_every_rank_count(const CaseConfig& c, std::int64_t steps,
                                     const std::string& words) {
  MPI_Comm world;
  MPI_Comm_dup(MPI_COMM_WORLD, &world);
  {
    const Communicator comm(world);
    const Verdict parallel = run_until_divergence(c, comm, steps);
    ASSERT_GE(parallel.step, 1) << "no divergence detected in " << steps << " steps";
    EXPECT_NE(parallel.message.find(words), std::string::npos) << parallel.message;
    EXPECT_NE(parallel.message.find("Likely cause"), std::string::npos) << parallel.message;
    if (comm.is_root()) {
      const Verdict serial = run_until_divergence(c, Communicator::self(), steps);
      EXPECT_EQ(parallel.step, serial.step);
      EXPECT_EQ(parallel.particle, serial.particle);
    }
  }
  MPI_Comm_free(&world);
}

TEST(Divergence, TimeStepFarAboveTheStableOneStopsEveryRankAtOneStep) {
  CaseConfig c = testing::ring_patch_hit_by_sphere(0.01, 1.0, 0.0);
  c.simulation.dt = 60 * 7.87e-7;  // 60 times the case's step, far above the bond limit
  expect_same_on_every_rank_count(c, 2000, "times the stable estimate");
}

TEST(Divergence, CoincidentSpheresAreNotFiniteAndNamed) {
  CaseConfig c = testing::base_case();
  c.simulation.dt = 1e-7;
  for (double x : {0.0, 0.0, 0.05, 0.1}) {
    SphereConfig s;
    s.position = {x, 0, 0};
    s.radius = 0.01;
    c.spheres.push_back(s);
  }
  expect_same_on_every_rank_count(c, 10, "not finite");
}

TEST(Divergence, AStableRunIsNotStopped) {
  // The guard must not fire on a run that is fine: the ring patch at its own step.
  const CaseConfig c = testing::ring_patch_hit_by_sphere(0.01, 1.0, 0.0);
  MPI_Comm world;
  MPI_Comm_dup(MPI_COMM_WORLD, &world);
  {
    const Communicator comm(world);
    EXPECT_EQ(run_until_divergence(c, comm, 500).step, -1);
  }
  MPI_Comm_free(&world);
}

}  // namespace
}  // namespace ringdem
