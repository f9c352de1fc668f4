// Batches of steps (Simulation::run_steps) fuse each step's second half kick, the energy
// ledger and the next step's drift into one pass over the particles, and skip the fusion where
// the next step takes grains in or out. The reference is a different code path: the same
// model stepped one step() at a time, which runs the three separately. They must agree bit
// for bit in every column of the particle store and in the ledger.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

/// Every registered column of the owned particles, as bytes, by field name.
std::map<std::string, std::vector<unsigned char>> owned_columns(ParticleStore& p) {
  std::map<std::string, std::vector<unsigned char>> columns;
  const std::size_t n = p.n_local();
  p.for_each_field([&](const FieldInfo& info, auto& v) {
    const std::size_t rows = std::min(n, v.size());  // empty columns stay empty
    std::vector<unsigned char> bytes(rows * sizeof(v[0]));
    if (rows > 0) std::memcpy(bytes.data(), v.data(), bytes.size());
    columns[std::string(info.name)] = std::move(bytes);
  });
  return columns;
}

void expect_same_state(Simulation& one_by_one, Simulation& batched) {
  ASSERT_EQ(one_by_one.steps(), batched.steps());
  EXPECT_EQ(one_by_one.time(), batched.time());
  ASSERT_EQ(one_by_one.model().particles.n_local(), batched.model().particles.n_local());
  const auto a = owned_columns(one_by_one.model().particles);
  const auto b = owned_columns(batched.model().particles);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, bytes] : a)
    EXPECT_TRUE(bytes == b.at(name)) << "column " << name << " differs";
  const Energies ea = one_by_one.energies(), eb = batched.energies();
  EXPECT_EQ(ea.kinetic, eb.kinetic);
  EXPECT_EQ(ea.contact_damping, eb.contact_damping);
  EXPECT_EQ(ea.friction, eb.friction);
  // What the contacts hold: inside a batch the ledger does not sum it, at a batch's end it must.
  EXPECT_EQ(ea.contact_elastic, eb.contact_elastic);
  EXPECT_EQ(ea.global_damping, eb.global_damping);
  EXPECT_EQ(ea.boundary_work, eb.boundary_work);
  EXPECT_EQ(ea.outflow, eb.outflow);
  EXPECT_EQ(ea.inflow, eb.inflow);
  const auto& ba = one_by_one.model().bodies;
  const auto& bb = batched.model().bodies;
  ASSERT_EQ(ba.size(), bb.size());
  for (std::size_t i = 0; i < ba.size(); ++i) {
    EXPECT_EQ(ba[i].position, bb[i].position) << ba[i].name;
    EXPECT_EQ(ba[i].velocity, bb[i].velocity) << ba[i].name;
  }
}

/// Steps `sim` `total` steps in batches of the given sizes, over and over.
void run_in_batches(Simulation& sim, std::int64_t total, const std::vector<std::int64_t>& sizes) {
  std::size_t i = 0;
  for (std::int64_t done = 0; done < total; i = (i + 1) % sizes.size()) {
    const std::int64_t n = std::min(sizes[i], total - done);
    sim.run_steps(n);
    done += n;
  }
}

// A damped net of linked rings (bonds, orientations, the Cundall path of the second half kick,
// fixed corner rings) struck by a free rigid sphere (a body's half kicks on either side of the
// particles' pass, body contacts in the ledger).
TEST(StepBatches, DampedRingNetStruckBySphereGivesTheBitsOfSingleSteps) {
  const CaseConfig c = testing::ring_patch_hit_by_sphere(-0.005, 60.0, 0.5);
  const Communicator self = testing::self_comm();
  Simulation one_by_one(build_model(c, self), self, settings_from_case(c));
  Simulation batched(build_model(c, self), self, settings_from_case(c));
  const std::int64_t steps = 200;  // the sphere starts 5 mm into the rings
  for (std::int64_t k = 0; k < steps; ++k)
    one_by_one.step();
  run_in_batches(batched, steps, {1, 37, 5, 100});
  const Energies e = one_by_one.energies();
  ASSERT_GT(e.contact_damping, 0.0) << "the sphere never touched the rings";
  ASSERT_GT(e.global_damping, 0.0);
  expect_same_state(one_by_one, batched);
}

// Grains in contact on a floor, leaving through an outflow box and coming in through an inlet:
// a batch must not fuse a step with the next one when that one takes grains in or out first.
TEST(StepBatches, GrainsEnteringAndLeavingGiveTheBitsOfSingleSteps) {
  const CaseConfig c = testing::grains_entering_and_leaving();
  const Communicator self = testing::self_comm();
  Simulation one_by_one(build_model(c, self), self, settings_from_case(c));
  Simulation batched(build_model(c, self), self, settings_from_case(c));
  const std::int64_t at_start = one_by_one.global_particles();
  const std::int64_t steps = 1300;  // inlet batches at 0 and 1.2 ms
  for (std::int64_t k = 0; k < steps; ++k)
    one_by_one.step();
  run_in_batches(batched, steps, {250, 3, 1, 600});
  const Simulation::GrainFlux out = one_by_one.outflow_totals();
  const Simulation::GrainFlux in = one_by_one.inflow_totals();
  ASSERT_GT(out.grains, 0) << "no grain left";
  ASSERT_GT(in.grains, at_start / 20) << "the inlet's batches did not come in";
  expect_same_state(one_by_one, batched);
}

// The batch length the scenario loop takes (Simulation::steps_short_of) never passes an event
// on the schedule: checked against the summed times of single steps, with a step that is not
// a binary fraction, for events on and between step times.
TEST(StepBatches, BatchesEndNoLaterThanTheStepThatReachesAnEvent) {
  CaseConfig c = testing::grains_entering_and_leaving();
  c.simulation.dt = 1.1e-6;
  c.inflow.clear();
  c.outflow.clear();
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  const double tolerance = 0.01 * sim.dt();
  std::int64_t longest = 0;
  for (const double event : {5 * 1.1e-6, 5.5 * 1.1e-6, 17 * 1.1e-6, 30.999 * 1.1e-6}) {
    while (sim.time() + tolerance < event) {
      const std::int64_t batch = sim.steps_short_of(event, tolerance);
      ASSERT_GE(batch, 1);
      longest = std::max(longest, batch);
      for (std::int64_t k = 0; k < batch; ++k) {
        // Every step but the batch's last ends before the event is due.
        if (k + 1 < batch) {
          sim.step();
          ASSERT_LT(sim.time() + tolerance, event) << "batch of " << batch << " passed it";
        } else {
          sim.step();
        }
      }
    }
    // The event is due at the first step that reaches it: one step back it was not.
    EXPECT_LT(sim.time() - sim.dt() + tolerance, event);
  }
  EXPECT_GE(longest, 10) << "the batches were too short to tell anything";
}

}  // namespace
}  // namespace ringdem
