// Braked shackles (docs/physics.md "Brake elements") and support ropes ("Support ropes"): a
// small net falls into shackles held by brakes, or sliding on ropes whose brakes pay out rope,
// that slide under its weight. Brakes and ropes are replicated like the bodies they hold, so a
// run on this run's ranks must give the same bits as on one rank, a checkpoint taken while they
// slide must restart (here and on one rank) into the run never interrupted, and the ledger,
// with the brakes' work and the springs and ropes in it, must close.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

struct ParticleRow {
  std::int64_t gid;
  Vec3 position, velocity;
};

/// What the comparison reads: every particle by gid, the bodies, the brakes, the ropes, the
/// ledger.
struct BrakedRun {
  std::vector<ParticleRow> particles;
  std::vector<Vec3> body_position, body_velocity, slip;
  std::vector<double> travel, work, rope_slip, rope_work, rope_friction, rope_segments;
  Energies energies;
  /// How far the brakes (of shackles or ropes) have slid: the largest travel.
  double largest_travel() const {
    double t = 0.0;
    for (const auto* v : {&travel, &rope_slip})
      for (const double x : *v)
        t = std::max(t, x);
    return t;
  }
};

BrakedRun snapshot(Simulation& sim) {
  BrakedRun r;
  const ParticleStore& p = sim.model().particles;
  std::vector<ParticleRow> mine;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    mine.push_back({p.gid[k], p.position[k], p.velocity[k]});
  r.particles = sim.comm().allgather(mine);
  std::sort(r.particles.begin(), r.particles.end(),
            [](const auto& a, const auto& b) { return a.gid < b.gid; });
  for (const RigidBody& b : sim.model().bodies) {
    r.body_position.push_back(b.position);
    r.body_velocity.push_back(b.velocity);
  }
  r.slip = sim.model().brakes.slip;
  r.travel = sim.model().brakes.travel;
  r.work = sim.model().brakes.work;
  r.rope_slip = sim.model().ropes.slip;
  r.rope_work = sim.model().ropes.brake_work;
  r.rope_friction = sim.model().ropes.friction_work;
  r.rope_segments = sim.model().ropes.segment_rest;
  r.energies = sim.energies();
  return r;
}

void expect_same(const BrakedRun& a, const BrakedRun& b, const char* what) {
  ASSERT_EQ(a.particles.size(), b.particles.size()) << what;
  for (std::size_t k = 0; k < a.particles.size(); ++k) {
    EXPECT_EQ(a.particles[k].gid, b.particles[k].gid) << what;
    EXPECT_EQ(a.particles[k].position, b.particles[k].position) << what << " gid " << k;
    EXPECT_EQ(a.particles[k].velocity, b.particles[k].velocity) << what << " gid " << k;
  }
  EXPECT_EQ(a.body_position, b.body_position) << what;
  EXPECT_EQ(a.body_velocity, b.body_velocity) << what;
  EXPECT_EQ(a.slip, b.slip) << what;
  EXPECT_EQ(a.travel, b.travel) << what;
  EXPECT_EQ(a.work, b.work) << what;
  EXPECT_EQ(a.rope_slip, b.rope_slip) << what;
  EXPECT_EQ(a.rope_work, b.rope_work) << what;
  EXPECT_EQ(a.rope_friction, b.rope_friction) << what;
  EXPECT_EQ(a.rope_segments, b.rope_segments) << what;
  EXPECT_EQ(a.energies.ledger(), b.energies.ledger()) << what;
}

/// Runs `c` on this run's ranks with a checkpoint halfway, restarts it here and on one rank,
/// and runs it on one rank from the start: every run must end in the same bits, the brakes
/// must slide in both halves, the energy ledger must close, and so must the momentum balance
/// of the net's particles (the tori's contact loads on them; the brakes and ropes act on the
/// tori alone).
void expect_rank_independent_restartable_and_balanced(const CaseConfig& c, const char* name) {
  SimulationSettings s = settings_from_case(c);
  s.momentum_ledger = true;  // a rockfall books none; here it checks the restraints' loads
  constexpr std::int64_t kHalf = 4000;
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    long long pid = comm.is_root() ? static_cast<long long>(getpid()) : 0;
    MPI_Bcast(&pid, 1, MPI_LONG_LONG, 0, world);
    const fs::path dir =
        fs::temp_directory_path() / ("ringdem_" + std::string(name) + "_" + std::to_string(pid));
    DriverState driver;
    BrakedRun straight, initial;
    std::string middle;
    {
      Simulation sim(build_scenario_model(c, comm), comm, s);
      ASSERT_FALSE(sim.model().brakes.empty() && sim.model().ropes.empty());
      initial = snapshot(sim);
      sim.run_steps(kHalf);
      middle = CheckpointStore((dir / "middle").string())
                   .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
      const BrakedRun half = snapshot(sim);
      sim.run_steps(kHalf);
      straight = snapshot(sim);
      // The brakes slide in both halves, so the checkpoint holds a sliding state, and the net
      // presses on the shackles by the end (friction and contact damping at work).
      const double travel_half = half.largest_travel();
      const double travel_end = straight.largest_travel();
      EXPECT_GT(travel_half, 0.0);
      EXPECT_GT(travel_end, 1.2 * travel_half);
      EXPECT_GT(straight.energies.contact_damping, 0.0);
      // Ropes with friction slide through the shackles as well as out of their brakes.
      const std::vector<double>& mu = sim.model().ropes.friction;
      if (std::any_of(mu.begin(), mu.end(), [](double f) { return f > 0.0; })) {
        double friction_work = 0.0;
        for (const double w : straight.rope_friction)
          friction_work += w;
        EXPECT_GT(friction_work, 0.0);
        EXPECT_GT(straight.energies.friction, friction_work);  // with the contacts'
      }
      // The ledger closes: what the balance moved is a small part of what the brakes took.
      EXPECT_GT(straight.energies.brake_work, 0.0);
      EXPECT_LT(std::abs(straight.energies.balance_error(initial.energies)),
                1e-3 * straight.energies.brake_work);
      // Round-off scale: the size of every term, since the residual is their difference.
      const MomentumBalance m = sim.momentum_balance();
      double scale = norm(m.momentum) + norm(m.initial) + norm(m.gravity) + norm(m.held);
      for (const Vec3& body : m.bodies)
        scale += norm(body);
      EXPECT_LE(norm(m.residual()), 1e-12 * scale)
          << "|residual| " << norm(m.residual()) << " N s of " << scale;
    }
    {
      Model model = build_model_without_particles(c);
      const RestartState state = read_checkpoint(comm, middle, c, model, driver);
      Simulation sim(std::move(model), comm, s, state);
      sim.run_steps(kHalf);
      expect_same(straight, snapshot(sim), "restarted on this run's ranks");
    }
    if (comm.is_root()) {
      const Communicator self = Communicator::self();
      {
        Simulation sim(build_scenario_model(c, self), self, s);
        sim.run_steps(2 * kHalf);
        expect_same(straight, snapshot(sim), "one rank");
      }
      Model model = build_model_without_particles(c);
      const RestartState state = read_checkpoint(self, middle, c, model, driver);
      Simulation sim(std::move(model), self, s, state);
      sim.run_steps(kHalf);
      expect_same(straight, snapshot(sim), "restarted on one rank");
      fs::remove_all(dir);
    }
    comm.barrier();
  }
}

TEST(Brakes, BrakedShacklesSlideAlikeOnEveryRankCountAndRestartBitwise) {
  // Under 400 m/s^2 a shackle (0.375 kg) weighs 150 N: its brake (140 N) slides from the first
  // step, and the net falling freely catches up with the shackles (relative 373 m/s^2) and
  // presses its outer wires into them from about 5900 steps on.
  expect_rank_independent_restartable_and_balanced(
      load_case_from_string(testing::kTinyRockfall, "tiny.yaml",
                            {"simulation.gravity=[0, 0, -400]",
                             "particles.nets[0].shackles.brake.activation_force=140",
                             "particles.nets[0].shackles.brake.stiffness=1e5"}),
      "brakes");
}

TEST(Brakes, ShacklesOnRopesSlideAlikeOnEveryRankCountAndRestartBitwise) {
  // Under 400 m/s^2 the shackles (0.375 kg, 150 N each) and the net pull the ropes down and
  // in: the ropes' brakes pay out rope at 1.5 kN in both halves (0.4 mm of the most paid out
  // by step 4000, 5 mm by 8000), and the net presses on the shackles.
  expect_rank_independent_restartable_and_balanced(
      load_case_from_string(testing::kTinyRockfall, "tiny.yaml",
                            {"simulation.gravity=[0, 0, -400]",
                             "particles.nets[0].shackles.ropes.axial_stiffness=2e6",
                             "particles.nets[0].shackles.ropes.brake.activation_force=1500"}),
      "ropes");
}

TEST(Brakes, ShacklesOnFrictionalRopesSlideAlikeOnEveryRankCountAndRestartBitwise) {
  // The same pull with friction 0.3 between the ropes and the shackles: the corner shackles,
  // where the ropes turn most, hold until the capstan ratio and then slide.
  expect_rank_independent_restartable_and_balanced(
      load_case_from_string(testing::kTinyRockfall, "tiny.yaml",
                            {"simulation.gravity=[0, 0, -400]",
                             "particles.nets[0].shackles.ropes.axial_stiffness=2e6",
                             "particles.nets[0].shackles.ropes.friction=0.3",
                             "particles.nets[0].shackles.ropes.brake.activation_force=1500"}),
      "frictional_ropes");
}

}  // namespace
}  // namespace ringdem
