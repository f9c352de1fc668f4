// The momentum balance of the free particles (engine/MomentumLedger, issue 13 item 4): grains
// flow along a bed past a post and into a grate of fixed spheres, an inlet adds a batch
// mid-run next to flowing grains, and an outflow box takes the grains that pass the grate,
// some of them while touching. The change of the grains' momentum, with what went out and came
// in, must equal the impulse of the loads the code reports (gravity, the bed's and the post's
// contact forces, the grate's load) to round-off, on this run's ranks, and bit for bit as on
// one rank. Only reported loads are booked, so a load that is applied but not reported, or
// reported but not applied, leaves a residual far above round-off.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>

#include "SameBits.hpp"
#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

CaseConfig flow_through_grate() {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  MaterialConfig rock = testing::soft_rock();
  rock.friction = 0.5;
  rock.restitution = 0.3;
  c.materials.push_back(rock);
  c.rigid_bodies = testing::bed_and_post({0.0, 0.1, 0.1}, 0.02);
  // The grate: fixed spheres across the flow at x = 0.05, gaps that grains squeeze through.
  for (int j = 0; j < 8; ++j)
    for (int k = 0; k < 2; ++k) {
      SphereConfig s;
      s.group = "grate";
      s.position = {0.05, -0.105 + 0.03 * j, 0.012 + 0.03 * k};
      s.radius = 0.01;
      s.material = "rock";
      s.motion = Motion::kFixed;
      c.spheres.push_back(s);
    }
  LatticeConfig grains;
  grains.group = "debris";
  grains.origin = {-0.15, -0.1, 0.011};
  grains.count = {6, 10, 3};
  grains.spacing = 0.021;
  grains.particle_radius = 0.01;
  grains.material = "rock";
  grains.velocity = {2.0, 0.0, 0.0};
  grains.jitter = 0.2;
  c.lattices = {grains};
  InflowConfig in;
  in.name = "inlet";
  in.group = "debris";
  in.material = "rock";
  in.box_min = {-0.28, -0.1, 0.011};
  in.box_max = {-0.18, 0.1, 0.07};
  in.velocity = {2.0, 0.0, 0.0};
  in.discharge = 0.004;
  in.start_time = 0.02;
  in.sizes.min_radius = 0.006;
  in.sizes.max_radius = 0.01;
  c.inflow.push_back(in);
  OutflowConfig out;
  out.name = "past_the_grate";
  out.box_min = {-1.0, -1.0, -1.0};
  out.box_max = {0.04, 1.0, 1.0};  // past the grate spheres' centres
  c.outflow.push_back(out);
  return c;
}

using testing::same_bits;

TEST(MomentumBalance, ClosesWithInflowOutflowAndHeldParticlesOnAnyRankCount) {
  const CaseConfig c = flow_through_grate();
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    SimulationSettings s = settings_from_case(c);
    s.dt = 2e-5;
    Simulation parallel(build_scenario_model(c, comm), comm, s);
    const Communicator self = Communicator::self();
    Simulation serial(build_scenario_model(c, self), self, s);
    MomentumBalance last;
    for (int block = 0; block < 12; ++block) {
      parallel.run_steps(500);
      serial.run_steps(500);
      const MomentumBalance a = serial.momentum_balance(), b = parallel.momentum_balance();
      // Round-off scale: the size of every term, since the residual is their difference.
      double scale = norm(a.momentum) + norm(a.initial) + norm(a.outflow) + norm(a.inflow) +
                     norm(a.gravity) + norm(a.held) + norm(a.exchange);
      for (const Vec3& body : a.bodies)
        scale += norm(body);
      EXPECT_LE(norm(a.residual()), 1e-12 * scale) << "block " << block;
      EXPECT_TRUE(same_bits(a.residual(), b.residual()))
          << "block " << block << ": residual (" << a.residual().x << ", " << a.residual().y << ", "
          << a.residual().z << ") on one rank, (" << b.residual().x << ", " << b.residual().y
          << ", " << b.residual().z << ") here";
      EXPECT_TRUE(same_bits(a.impulse(), b.impulse())) << "block " << block;
      EXPECT_TRUE(same_bits(a.held, b.held)) << "block " << block;
      last = a;
    }
    // Every path was taken: grains came in and went out, some while touching (their missed
    // kicks booked apart from the arrivals' kicks), and the grate, the bed and the post were
    // loaded.
    EXPECT_GT(norm(last.inflow), 0.0);
    EXPECT_GT(norm(last.outflow), 0.0);
    EXPECT_GT(std::abs(last.exchange.x), 0.0);
    EXPECT_GT(norm(last.held), 0.0);
    ASSERT_EQ(last.bodies.size(), 2u);
    EXPECT_GT(norm(last.bodies[0]), 0.0);
    EXPECT_GT(norm(last.bodies[1]), 0.0);
    if (comm.is_root())
      std::printf(
          "momentum balance: |residual| %.3g N s of |impulse| %.3g N s (grate %.3g, "
          "exchange (%.3g, %.3g, %.3g), post %.3g, out %.3g, in %.3g kg m/s)\n",
          norm(last.residual()), norm(last.impulse()), norm(last.held), last.exchange.x,
          last.exchange.y, last.exchange.z, norm(last.bodies[1]), norm(last.outflow),
          norm(last.inflow));
  }
}

}  // namespace
}  // namespace ringdem
