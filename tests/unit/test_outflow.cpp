// Outflow boxes (issue 13 item 1): grains in free flight leave a box at the steps the analytic
// trajectory says, and what they carry out (count, mass, momentum, energy) is what the
// analytic state at that step gives; the energy ledger still closes, also for a grain that
// leaves while friction works on it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/OutflowSink.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

constexpr double kStandardGravity = 9.81;
constexpr double kDt = 1e-4;
constexpr double kEdge = 0.05;  ///< the outflow box ends at x = kEdge

/// A 10 x 2 x 2 lattice of separated steel spheres (no contacts) flying at 1 m/s along x
/// under gravity, and an outflow box that ends at x = kEdge.
CaseConfig flying_grains() {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -kStandardGravity};
  c.simulation.dt = kDt;
  LatticeConfig lat;
  lat.group = "debris";
  lat.origin = {0, 0, 0};
  lat.count = {10, 2, 2};
  lat.spacing = 0.01;
  lat.particle_radius = 0.003;
  lat.velocity = {1.0, 0, 0};
  c.lattices.push_back(lat);
  OutflowConfig out;
  out.name = "end";
  out.box_min = {-1, -1, -1};
  out.box_max = {kEdge, 1, 1};
  out.groups = {"debris"};
  c.outflow.push_back(out);
  return c;
}

TEST(Outflow, GrainsLeaveWhenTheirTrajectoryCrossesTheBoxAndCarryTheirState) {
  const CaseConfig c = flying_grains();
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  const double m = sim.model().particles.mass[0];
  const Energies start = sim.energies();
  const int n_steps = 70;
  sim.run_steps(n_steps);
  // Velocity Verlet is exact for constant acceleration: after step n (0-based) the grain of
  // column i is at x = 0.01 i + (n + 1) dt, v = (1, 0, -g (n + 1) dt). It is found outside
  // after the drift of step n (x > kEdge), or of the first step after that whose number is a
  // multiple of the outflow's stride (the next test), within kWait steps. It is taken out at
  // the start of the step after, with the synchronised state of the end of the step it was
  // found at. Expected totals, computed from that alone (free flight keeps each grain's kinetic
  // + potential energy, so that total does not depend on the step it leaves at; its momentum
  // along z is bracketed by the two ends of the wait):
  constexpr int kWait = 64;
  std::int64_t gone = 0;
  double momentum_z_first = 0.0, momentum_z_last = 0.0, energy = 0.0;
  for (int i = 0; i < 10; ++i) {
    int n = 0;
    while (!(0.01 * i + (n + 1) * kDt > kEdge))
      ++n;
    ASSERT_TRUE(n + 1 + kWait <= n_steps - 1 || n + 1 > n_steps - 1) << "column " << i;
    if (n + 1 > n_steps - 1) continue;  // found after the last step's drift: still here
    gone += 4;
    momentum_z_first += 4 * m * -kStandardGravity * (n + 1) * kDt;
    momentum_z_last += 4 * m * -kStandardGravity * (n + 1 + kWait) * kDt;
    // Kinetic + potential (-m g.x = m g z) of the four grains of this column at the start.
    energy += 4 * (0.5 * m * 1.0) + m * kStandardGravity * (2 * 0.0 + 2 * 0.01);
  }
  ASSERT_GT(gone, 0);
  ASSERT_LT(gone, 40);
  const Simulation::GrainFlux out = sim.outflow_totals();
  EXPECT_EQ(out.grains, gone);
  EXPECT_EQ(sim.global_particles(), 40 - gone);
  EXPECT_NEAR(out.mass, gone * m, 1e-15 * gone * m);
  EXPECT_NEAR(out.momentum.x, gone * m * 1.0, 1e-12 * gone * m);
  EXPECT_EQ(out.momentum.y, 0.0);
  EXPECT_LE(out.momentum.z, momentum_z_first);
  EXPECT_GE(out.momentum.z, momentum_z_last);
  const Energies e = sim.energies();
  EXPECT_NEAR(e.outflow, energy, 1e-9 * std::abs(energy));
  // Free flight conserves kinetic + potential energy exactly in velocity Verlet (up to
  // rounding): the ledger with the outflow column closes to rounding.
  EXPECT_NEAR(e.balance_error(start), 0.0, 1e-12 * start.kinetic);
}

// Grains outside an outflow box are looked for at every 64th step only (each removal rebuilds
// the lists, and a steady outflow found one at nearly every step, at every 16th too). The last
// column of flying_grains (x = 0.09) starts outside the box that ends at 0.0895 and is found
// at step 0; the next (x = 0.08) crosses the face after the drift of step 95 (0-based), is
// looked for at step 128, and leaves at the start of step 129 with the state of the end of
// step 128. With any skin: the steps are fixed.
TEST(Outflow, GrainsOutsideAreLookedForAtEverySixtyFourthStep) {
  for (const double skin : {0.001, 0.02}) {
    CaseConfig c = flying_grains();
    c.simulation.skin = skin;
    c.outflow[0].box_max.x = 0.0895;
    const Communicator self = testing::self_comm();
    Simulation sim(build_model(c, self), self, settings_from_case(c));
    sim.run_steps(2);
    EXPECT_EQ(sim.outflow_totals().grains, 4) << "skin " << skin;
    sim.run_steps(127);  // to the end of step 128
    EXPECT_EQ(sim.outflow_totals().grains, 4) << "skin " << skin << ": left before step 128";
    sim.run_steps(1);
    EXPECT_EQ(sim.outflow_totals().grains, 8) << "skin " << skin;
    // The second column's momentum along z: four grains at v_z = -g (128 + 1) dt.
    const double m = sim.model().particles.mass[0];
    const double first = 4 * m * -kStandardGravity * 1 * kDt;
    EXPECT_NEAR(sim.outflow_totals().momentum.z - first, 4 * m * -kStandardGravity * 129 * kDt,
                1e-12 * m);
  }
}

// A sphere sliding on a plane (friction 0.3, restitution 1: no contact damping) leaves a box
// while friction works on it (power mu m g v_slip). The ledger books that power over the steps
// the grain is there and not over the step after (EnergyLedger ends a leaving grain's
// trapezoid with its last step): the balance, read every step, does not move when it leaves.
// Booking its last power over one more half step would move it by dt/2 mu m g v_slip.
TEST(Outflow, AGrainLeavingWhileSlidingTakesNoFrictionPastItsLastStep) {
  const double v0 = 1.0;
  CaseConfig c = testing::sliding_sphere(0.3, v0);
  OutflowConfig out;
  out.name = "end";
  out.box_min = {-1, -1, -1};
  out.box_max = {0.002, 1, 1};
  out.groups = {c.spheres[0].group};
  c.outflow = {out};
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  const double m = sim.model().particles.mass[0];
  const Energies start = sim.energies();
  // The grain is taken out at the start of the step after the one whose drift took it out of
  // the box: compare the ledger at the end of that step with the one at the end of the last.
  Energies last = start, now = start;
  for (int k = 0; k < 20000 && sim.global_particles() == 1; ++k) {
    last = now;
    sim.run_steps(1);
    now = sim.energies();
  }
  ASSERT_EQ(sim.global_particles(), 0) << "the grain never left";
  ASSERT_GT(last.friction, 0.0);
  sim.run_steps(5);
  const Energies e = sim.energies();
  EXPECT_EQ(now.friction, last.friction) << "friction booked after the grain's last step";
  EXPECT_EQ(e.friction, last.friction) << "friction booked after the grain left";
  const double before = last.balance_error(start), after = e.balance_error(start);
  const double half_step_of_friction = 0.5 * sim.dt() * 0.3 * m * kStandardGravity * v0;
  EXPECT_LT(std::abs(after - before), 0.01 * half_step_of_friction)
      << "balance " << before << " J before, " << after << " J after the grain left";
}

TEST(Outflow, AGrainOutsideNoBoxOfItsGroupStays) {
  CaseConfig c = flying_grains();
  c.lattices[0].group = "other";
  c.lattices.push_back(c.lattices[0]);
  c.lattices[1].group = "debris";
  c.lattices[1].origin = {0, 0.5, 0};
  c.outflow[0].groups = {"debris"};
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  sim.run_steps(70);
  const std::int64_t gone = sim.outflow_totals().grains;
  EXPECT_GT(gone, 0);
  // Only the debris lattice leaves; the other group flies on past the edge.
  EXPECT_EQ(sim.global_particles(), 80 - gone);
  const ParticleStore& p = sim.model().particles;
  int past_edge = 0;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.group[k] == sim.model().group_id("debris")) {
      EXPECT_LE(p.position[k].x, kEdge + kDt);
    }
    past_edge += p.position[k].x > kEdge;
  }
  EXPECT_GT(past_edge, 0);
}

// The step's test skips its scan while the particles cannot have moved as far as the nearest
// grain's face (note_positions at a rebuild): against the particle-by-particle test on random
// clouds moved by up to a bound, the answer is the same for every cloud. Grains near a face,
// fixed particles outside the box and grains of another group make the clearance matter.
TEST(Outflow, TheScanThatASmallMoveSkipsAgreesWithEveryParticleTested) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
  OutflowBox box{"box", {0, 0, 0}, {1, 0.5, 0.25}, {1}};
  int leaving_clouds = 0;
  for (int cloud = 0; cloud < 400; ++cloud) {
    OutflowSink sink({box});
    ParticleStore p;
    const int n = 1 + static_cast<int>(rng() % 30);
    for (int k = 0; k < n; ++k) {
      ParticleStore::NewParticle np;
      np.gid = k;
      np.position = {unit(rng) * box.hi.x, unit(rng) * box.hi.y, unit(rng) * box.hi.z};
      np.radius = 0.01;
      np.density = 2600.0;
      np.group = k % 7 == 6 ? 2 : 1;  // another group: never leaves this box
      np.motion = k % 11 == 10 ? Motion::kFixed : Motion::kFree;
      if (np.group == 2 || np.motion == Motion::kFixed) np.position.x += 2.0;  // outside
      p.add(np);
    }
    sink.note_positions(p);
    // Each particle moved by at most `moved` in every direction (|d| <= moved).
    const double moved = 0.05 * unit(rng);
    for (int k = 0; k < n; ++k) {
      Vec3 d{sym(rng), sym(rng), sym(rng)};
      d = d * (moved * unit(rng) / std::max(norm(d), 1e-300));
      p.position[static_cast<std::size_t>(k)] += d;
    }
    bool expected = false;
    for (std::size_t k = 0; k < p.n_local(); ++k)
      expected = expected || sink.leaving(p, k);
    EXPECT_EQ(sink.any_leaving(p, moved), expected) << "cloud " << cloud;
    leaving_clouds += expected;
  }
  // The draw covers both answers.
  EXPECT_GT(leaving_clouds, 20);
  EXPECT_LT(leaving_clouds, 380);
}

}  // namespace
}  // namespace ringdem
