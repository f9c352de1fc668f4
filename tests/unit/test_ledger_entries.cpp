// The energy ledger's per-particle contact sums (ContactMoments) are kept either per particle
// touched, behind an index, or at each particle's own index where nearly all are touched
// (EnergyLedger::moments_entry()). The choice is about memory and speed only: either way the
// same sums are made in the same order, so the ledger must be the same bits. Checked on a
// packing that starts with every grain in contact and loosens as it springs apart (the
// automatic choice changes on the way), and on grains entering and leaving.
#include <gtest/gtest.h>

#include <cstring>
#include <optional>
#include <random>

#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

/// 6 x 6 x 6 steel spheres of 5 mm on a 9.9 mm lattice: each overlaps its neighbours by
/// 0.1 mm, on a floor, under gravity. The packing springs apart.
CaseConfig overlapping_lattice() {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.simulation.dt = 2e-7;
  c.simulation.allow_initial_overlap = true;
  c.materials[0].restitution = 0.5;
  c.materials[0].friction = 0.4;
  LatticeConfig grains;
  grains.group = "grains";
  grains.origin = {0.005, 0.005, 0.0049};
  grains.count = {6, 6, 6};
  grains.spacing = 0.0099;
  grains.particle_radius = 0.005;
  c.lattices = {grains};
  RigidBodyConfig floor;
  floor.name = "floor";
  floor.shape = ShapeKind::kPlane;
  c.rigid_bodies = {floor};
  return c;
}

/// Runs `steps` with the entries chosen as `choice` (nullopt: automatically); counts the
/// evaluations that kept them per particle.
struct LedgerRun {
  Energies energies;
  std::vector<Vec3> velocities;
  int per_particle_steps = 0;
};
LedgerRun run(const CaseConfig& c, std::optional<bool> choice, int steps) {
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  sim.energy_ledger().set_entry_choice(choice);
  LedgerRun r;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    r.per_particle_steps += sim.energy_ledger().entries_per_particle();
  }
  r.energies = sim.energies();
  const ParticleStore& p = sim.model().particles;
  r.velocities.assign(p.velocity.begin(), p.velocity.begin() + p.n_local());
  return r;
}

void expect_same_ledger(const LedgerRun& a, const LedgerRun& b) {
  EXPECT_EQ(a.energies.contact_damping, b.energies.contact_damping);
  EXPECT_EQ(a.energies.friction, b.energies.friction);
  EXPECT_EQ(a.energies.contact_elastic, b.energies.contact_elastic);
  EXPECT_EQ(a.energies.boundary_work, b.energies.boundary_work);
  EXPECT_EQ(a.energies.ledger(), b.energies.ledger());
  EXPECT_EQ(a.velocities, b.velocities);  // the ledger only watches
}

TEST(LedgerEntries, PerParticleOrPerTouchedParticleGiveTheSameLedger) {
  const CaseConfig c = overlapping_lattice();
  constexpr int kSteps = 3000;
  const LedgerRun automatic = run(c, std::nullopt, kSteps);
  const LedgerRun touched = run(c, false, kSteps);
  const LedgerRun own = run(c, true, kSteps);
  // The automatic choice took both kinds: the packing starts in contact and loosens.
  EXPECT_GT(automatic.per_particle_steps, 0);
  EXPECT_LT(automatic.per_particle_steps, kSteps) << "the packing never loosened";
  EXPECT_EQ(touched.per_particle_steps, 0);
  EXPECT_EQ(own.per_particle_steps, kSteps);
  ASSERT_GT(touched.energies.contact_damping, 0.0) << "nothing dissipated: the test checks less";
  ASSERT_GT(touched.energies.friction, 0.0);
  expect_same_ledger(automatic, touched);
  expect_same_ledger(own, touched);
}

TEST(LedgerEntries, GrainsEnteringAndLeavingBookTheSameEitherWay) {
  const CaseConfig c = testing::grains_entering_and_leaving();
  constexpr int kSteps = 2500;
  const LedgerRun touched = run(c, false, kSteps);
  const LedgerRun own = run(c, true, kSteps);
  ASSERT_GT(touched.energies.contact_damping, 0.0);
  ASSERT_GT(touched.energies.outflow, 0.0) << "no grain left: the test checks less";
  expect_same_ledger(own, touched);
}

// ContactMoments::add() adds its twelve sums four at a time in vector registers; each must be
// what the scalar Vec3f addition gives (in double, rounded once to float), bit for bit, over a
// long run of contacts whose loads span many magnitudes and both signs (so that the roundings
// differ from lane to lane), and the energies in double.
TEST(LedgerEntries, AnEntryAddsAsTwelveScalarFloatSums) {
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 10);
  const auto draw = [&] { return std::ldexp(mantissa(random), exponent(random)); };
  const auto draw_vec = [&] { return Vec3{draw(), draw(), draw()}; };
  ContactMoments vector_sums;
  Vec3f damping, damping_moment, friction, friction_moment;
  double tangential = 0.0, elastic = 0.0;
  for (int contact = 0; contact < 2000; ++contact) {
    const Vec3 d = draw_vec(), dm = draw_vec(), f = draw_vec(), fm = draw_vec();
    const double t = std::abs(draw()), e = std::abs(draw());
    vector_sums.add(d, dm, f, fm, t, e);
    damping += d;
    damping_moment += dm;
    friction += f;
    friction_moment += fm;
    tangential += t;
    elastic += e;
  }
  const auto same_bits = [](const Vec3f& a, const Vec3f& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
  };
  EXPECT_TRUE(same_bits(vector_sums.damping, damping));
  EXPECT_TRUE(same_bits(vector_sums.damping_moment, damping_moment));
  EXPECT_TRUE(same_bits(vector_sums.friction, friction));
  EXPECT_TRUE(same_bits(vector_sums.friction_moment, friction_moment));
  EXPECT_EQ(vector_sums.tangential_energy, tangential);
  EXPECT_EQ(vector_sums.elastic_energy, elastic);
  EXPECT_NE(damping.x, 0.0f);
}

// Inside a batch of steps the ledger does not sum what the contacts hold (nothing reads it
// before the next step replaces it); a batch's last step does. Asking for it after a step that
// did not book it is a programming error, not a stale number.
TEST(LedgerEntries, HeldEnergiesAreAskedForOnlyAfterAStepThatBookedThem) {
  const CaseConfig c = overlapping_lattice();
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  sim.run_steps(20);
  EnergyLedger& ledger = sim.energy_ledger();
  EXPECT_NO_THROW(ledger.held());
  EXPECT_GT(ledger.held()[EnergyLedger::kContactHeld].value(), 0.0);
  ledger.start_accumulation(sim.model().particles, GatherMap{}, /*book_held=*/false);
  EXPECT_THROW(ledger.held(), std::logic_error);
  EXPECT_THROW(ledger.state(), std::logic_error);
}

}  // namespace
}  // namespace ringdem
