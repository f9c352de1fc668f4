// The divergence guard: a run with a time step far above the stable one, one with two
// coincident spheres, and one that goes unstable slowly (caught by the energy guard before any
// particle moves a skin in a step) stop at the same step on every rank count, naming the same
// particle.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "engine/DivergenceError.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

/// How far above the ring patch's stable estimate the unstable run steps.
constexpr double kUnstableFactor = 1.1;
/// A skin no particle of those runs crosses in one step before it runs away (at dt ~ 1e-6 s: 10^4
/// m/s).
constexpr double kSkin = 0.02;

struct Verdict {
  std::int64_t step = -1;
  std::string particle;  ///< "particle <gid> (group <name>"
  std::string message;
};

/// Runs up to `steps` steps, with the energies evaluated every `energy_every` steps (as series
/// rows do; 0: never); the step and the named particle of the divergence, if any.
Verdict run_until_divergence(const CaseConfig& c, const Communicator& comm, std::int64_t steps,
                             std::int64_t energy_every = 0) {
  Simulation sim(build_model(c, comm), comm, settings_from_case(c));
  Verdict v;
  try {
    if (energy_every == 0) {
      sim.run_steps(steps);
    } else {
      for (std::int64_t done = 0; done < steps; done += energy_every) {
        sim.energies();
        sim.run_steps(energy_every);
      }
    }
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

Verdict expect_same_on_every_rank_count(const CaseConfig& c, std::int64_t steps,
                                        const std::string& words, std::int64_t energy_every = 0) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  Verdict parallel;
  {
    const Communicator comm(world);
    parallel = run_until_divergence(c, comm, steps, energy_every);
    EXPECT_GE(parallel.step, 1) << "no divergence detected in " << steps << " steps";
    EXPECT_NE(parallel.message.find(words), std::string::npos) << parallel.message;
    EXPECT_NE(parallel.message.find("Likely cause"), std::string::npos) << parallel.message;
    if (comm.is_root()) {
      const Verdict serial = run_until_divergence(c, Communicator::self(), steps, energy_every);
      EXPECT_EQ(parallel.step, serial.step);
      EXPECT_EQ(parallel.particle, serial.particle);
    }
  }
  return parallel;
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

TEST(Divergence, TheEnergyLedgerCatchesAnInstabilityBeforeAnyParticleRunsAway) {
  // A time step 10 % above the stable estimate: the ring patch's bonds go unstable within
  // tens of steps. With the energies evaluated every 10 steps (as series rows do), the energy
  // guard stops the run at the same step on every rank count, at a step when no particle has
  // yet moved a skin in one step; the step guard alone stops it only later.
  CaseConfig c = testing::ring_patch_hit_by_sphere(0.0, 1.0, 0.0);
  c.simulation.skin = kSkin;
  const Simulation probe(build_model(c, Communicator::self()), Communicator::self(),
                         settings_from_case(c));
  const double dt = kUnstableFactor * probe.limits().min();
  c.simulation.dt = dt;
  const Verdict by_energy = expect_same_on_every_rank_count(c, 2000, "energy ledger grew", 10);
  const auto at = by_energy.message.find("velocity (");
  ASSERT_NE(at, std::string::npos) << by_energy.message;
  double vx = 0, vy = 0, vz = 0;
  ASSERT_EQ(std::sscanf(by_energy.message.c_str() + at, "velocity (%lf, %lf, %lf)", &vx, &vy, &vz),
            3);
  EXPECT_LT(std::sqrt(vx * vx + vy * vy + vz * vz) * dt, kSkin) << by_energy.message;
  const Verdict by_step = expect_same_on_every_rank_count(c, 2000, "in one step");
  EXPECT_LT(by_energy.step, by_step.step);
}

TEST(Divergence, AStableRunIsNotStopped) {
  // The guard must not fire on a run that is fine: the ring patch at its own step, hit by the
  // sphere from the first step on, with the energies checked every 10 steps as in the unstable
  // run above (whose only difference is the step).
  CaseConfig c = testing::ring_patch_hit_by_sphere(0.0, 1.0, 0.0);
  c.simulation.skin = kSkin;
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    EXPECT_EQ(run_until_divergence(c, comm, 3000, 10).step, -1);
  }
}

}  // namespace
}  // namespace ringdem
