// Inlets (issue 13 item 1): batches of grains enter at the discharge and the times the inlet's
// geometry gives, without overlaps, with what they bring in booked so that the ledger closes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

/// A 0.1 m inlet box shooting 2-4 mm steel grains along x at 1 m/s (a batch every 0.1 s) at a
/// discharge of 3e-4 m^3/s (solid fraction 0.3), under gravity; one fixed sphere far away is
/// the model's start-up particle.
CaseConfig inlet_in_free_flight() {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.simulation.dt = 1e-4;
  SphereConfig anchor;
  anchor.position = {0, 5, 0};
  anchor.motion = Motion::kFixed;
  c.spheres.push_back(anchor);
  InflowConfig in;
  in.name = "inlet";
  in.material = "steel";
  in.box_min = {0, 0, 0};
  in.box_max = {0.1, 0.1, 0.1};
  in.velocity = {1.0, 0, 0};
  in.discharge = 3e-4;
  in.sizes.min_radius = 0.002;
  in.sizes.max_radius = 0.004;
  c.inflow.push_back(in);
  return c;
}

TEST(Inflow, BatchesDeliverTheDischargeWithoutOverlapsAndTheLedgerCloses) {
  const CaseConfig c = inlet_in_free_flight();
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  const Energies start = sim.energies();
  sim.run_steps(3500);  // 0.35 s: batches at 0, 0.1, 0.2 and 0.3 s
  const Simulation::GrainFlux in = sim.inflow_totals();
  EXPECT_EQ(sim.global_particles(), 1 + in.grains);
  // Solid volume: 4 batches of discharge x interval, each packing cell at most one largest
  // grain short (one cell here: the box is less than 8 largest diameters wide).
  const double density = c.materials[0].density;
  const double expected = 4 * 3e-4 * 0.1;
  const double largest = 4.0 / 3.0 * M_PI * std::pow(0.004, 3);
  EXPECT_LE(in.mass / density, expected + 1e-12);
  EXPECT_GT(in.mass / density, expected - 4 * largest);
  EXPECT_NEAR(in.momentum.x, in.mass * 1.0, 1e-12 * in.mass);
  EXPECT_EQ(in.momentum.z, 0.0);
  // No two grains overlap (brute force): batches fly in formation, one box depth apart.
  const ParticleStore& p = sim.model().particles;
  double gap = 1e300;
  for (std::size_t a = 0; a < p.n_local(); ++a)
    for (std::size_t b = a + 1; b < p.n_local(); ++b)
      gap = std::min(gap, norm(p.position[a] - p.position[b]) - p.radius[a] - p.radius[b]);
  EXPECT_GE(gap, 0.0);
  // Free flight conserves kinetic + potential energy exactly in velocity Verlet (up to
  // rounding): the ledger with what came in closes to rounding.
  const Energies e = sim.energies();
  EXPECT_GT(e.inflow, 0.0);
  EXPECT_NEAR(e.balance_error(start), 0.0, 1e-12 * e.inflow);
}

TEST(Inflow, ABackedUpInletWaitsUntilItsBoxIsFree) {
  CaseConfig c = inlet_in_free_flight();
  // A fixed sphere in the way of the first batch's exit: grains pile against it and keep the
  // box occupied, so the second batch must wait past its time.
  SphereConfig wall;
  wall.position = {0.13, 0.05, 0.05};
  wall.radius = 0.06;
  wall.motion = Motion::kFixed;
  c.spheres.push_back(wall);
  c.simulation.gravity = {0, 0, 0};
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  sim.run_steps(1000);  // to t = 0.1 s, when the second batch is due
  const std::int64_t first = sim.inflow_totals().grains;
  sim.run_steps(5);
  EXPECT_EQ(sim.inflow_totals().grains, first) << "the second batch entered an occupied box";
}

}  // namespace
}  // namespace ringdem
