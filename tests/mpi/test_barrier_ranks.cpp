// The barrier measures (app/BarrierMonitor, issue 13 item 3) on this run's ranks equal, bit
// for bit, those of the same run on one rank: grains flow along a bed into a fixed ring (the
// "frame"), a free ring (the "net") and a post, so the frame's contact load, the post's force,
// the net's deflection and bond utilisation, and the flow measures are all non-zero. Every
// rank also runs the one-rank reference on Communicator::self().
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>

#include "SameBits.hpp"
#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/BarrierMonitor.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

CaseConfig flow_into_barrier() {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.bonds[0].youngs_modulus = 200e9;
  c.bonds[0].radius_multiplier = 0.43;
  c.bonds[0].tensile_strength = c.bonds[0].compressive_strength = c.bonds[0].shear_strength = 1e9;
  c.materials.push_back(testing::soft_rock());
  c.rigid_bodies = testing::bed_and_post({0.02, 0.2, 0.1}, 0.03);
  // A fixed ring (the frame) and a free one (the net) standing across the flow at x = 0.
  RingConfig frame = testing::paper_ring({0.0, -0.17, 0.16}, {1, 0, 0});
  frame.group = "frame";
  frame.motion = Motion::kFixed;
  RingConfig net = testing::paper_ring({0.0, 0.17, 0.16}, {1, 0, 0});
  net.group = "net";
  c.rings = {frame, net};
  LatticeConfig grains;
  grains.group = "debris";
  grains.origin = {-0.12, -0.3, 0.011};
  grains.count = {5, 30, 4};
  grains.spacing = 0.021;
  grains.particle_radius = 0.01;
  grains.material = "rock";
  grains.velocity = {6.0, 0.0, 0.0};
  grains.jitter = 0.2;
  c.lattices = {grains};
  BarrierConfig b;
  b.direction = {1, 0, 0};
  b.grain_groups = {"debris"};
  b.net_group = "net";
  b.frame_group = "frame";
  b.posts = {"post"};
  b.bed = "bed";
  b.gauge_distance = 0.02;
  b.gauge_length = 0.08;
  b.retention_length = 0.05;
  b.width = 0.6;
  c.scenario.barrier = b;
  return c;
}

using testing::same_bits;

TEST(BarrierRanks, MeasuresAreTheSameBitsOnAnyRankCount) {
  const CaseConfig c = flow_into_barrier();
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    SimulationSettings s = settings_from_case(c);
    s.dt = 2e-7;
    Simulation parallel(build_scenario_model(c, comm), comm, s);
    const Communicator self = Communicator::self();
    Simulation serial(build_scenario_model(c, self), self, s);
    const BarrierMonitor on_ranks(*c.scenario.barrier, parallel);
    const BarrierMonitor on_one(*c.scenario.barrier, serial);
    double largest_force = 0.0, largest_utilisation = 0.0;
    for (int block = 0; block < 10; ++block) {
      parallel.run_steps(2000);
      serial.run_steps(2000);
      parallel.energies();  // refreshes the bonds' utilisation
      serial.energies();
      const BarrierSample a = on_one.sample(serial), b = on_ranks.sample(parallel);
      for (const auto& [x, y, name] :
           {std::tuple{a.net_force, b.net_force, "net_force"},
            std::tuple{a.posts_force, b.posts_force, "posts_force"},
            std::tuple{a.gauge_mass, b.gauge_mass, "gauge_mass"},
            std::tuple{a.flow_depth, b.flow_depth, "flow_depth"},
            std::tuple{a.flow_velocity, b.flow_velocity, "flow_velocity"},
            std::tuple{a.bulk_density, b.bulk_density, "bulk_density"},
            std::tuple{a.front, b.front, "front"},
            std::tuple{a.retained_mass, b.retained_mass, "retained_mass"},
            std::tuple{a.overflow_mass, b.overflow_mass, "overflow_mass"},
            std::tuple{a.net_reach, b.net_reach, "net_reach"},
            std::tuple{a.max_utilisation, b.max_utilisation, "max_utilisation"},
            std::tuple{a.utilisation_at.x, b.utilisation_at.x, "utilisation_at.x"},
            std::tuple{a.utilisation_at.y, b.utilisation_at.y, "utilisation_at.y"},
            std::tuple{a.utilisation_at.z, b.utilisation_at.z, "utilisation_at.z"}})
        EXPECT_TRUE(same_bits(x, y)) << name << " at block " << block << ": " << x << " vs " << y;
      largest_force = std::max(largest_force, std::abs(a.net_force) + std::abs(a.posts_force));
      largest_utilisation = std::max(largest_utilisation, a.max_utilisation);
    }
    // The comparison saw loads: grains reached the frame or the post, and bent the net.
    EXPECT_GT(largest_force, 0.0);
    EXPECT_GT(largest_utilisation, 0.0);
  }
}

}  // namespace
}  // namespace ringdem
