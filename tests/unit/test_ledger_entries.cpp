// The energy ledger books particle pairs per contact, in the pair loop, or per particle
// (EnergyLedger::PairBooking). Per particle, its contact sums (ContactMoments) are kept either
// per particle touched, behind an index, or at each particle's own index where nearly all are
// touched (EnergyLedger::moments_entry()). That choice is about memory and speed only: either
// way the same sums are made in the same order, so the ledger must be the same bits. Per
// contact is another quadrature of the same work (the midpoint form against the trapezoid), so
// the two agree to the integrator's order, which a halved step shows. Checked on a packing that
// starts with every grain in contact and loosens as it springs apart (the automatic choice
// changes on the way), and on grains entering and leaving.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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
  Energies energies, initial;
  std::vector<Vec3> velocities;
  int per_particle_steps = 0;
};
LedgerRun run(const CaseConfig& c, std::optional<bool> choice, int steps,
              bool per_contact = false) {
  const Communicator self = testing::self_comm();
  SimulationSettings settings = settings_from_case(c);
  settings.pair_ledger_per_contact = per_contact;
  Simulation sim(build_model(c, self), self, settings);
  EXPECT_EQ(sim.energy_ledger().pair_booking(), per_contact
                                                    ? EnergyLedger::PairBooking::kPerContact
                                                    : EnergyLedger::PairBooking::kPerParticle);
  sim.energy_ledger().set_entry_choice(choice);
  const Energies initial = sim.energies();
  LedgerRun r;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    r.per_particle_steps += sim.energy_ledger().entries_per_particle();
  }
  r.energies = sim.energies();
  r.initial = initial;
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

/// |a - b| relative to the larger.
double relative_difference(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(a), std::abs(b));
}

// Per contact, each pair's work over a step is (F^n . u^n + F^{n+1} . u^{n+1}) dt/2 with u the
// relative velocity of the step's middle at each load's own contact point, the load of the
// start carried from the last step; per particle, the trapezoid at the end-of-step velocities.
// Velocity Verlet's synchronised velocity is the mean of the half-step ones, so summed over the
// steps the two are the same but for their first and last half steps (O(dt^2) of one step) and
// the rounding of what is carried in float (about 1e-7 of each load): far below the ledger's
// closure. Without the carried contact point (the start's load at the end's point) they differ
// at first order, 1.5e-5 here; without the carried damping force by half the damping. What the
// contacts hold is the same sum in another order (halves per contact against sums per particle).
TEST(LedgerEntries, PerContactAndPerParticleBookTheSameWork) {
  CaseConfig c = overlapping_lattice();
  c.simulation.dt = 4e-7;
  constexpr int kSteps = 1500;  // 0.6 ms: the packing springs apart, grains turn and slide
  const LedgerRun particle = run(c, false, kSteps);
  const LedgerRun contact = run(c, std::nullopt, kSteps, /*per_contact=*/true);
  ASSERT_GT(particle.energies.contact_damping, 1e-3 * particle.energies.kinetic)
      << "nothing dissipated: the test checks less";
  ASSERT_GT(particle.energies.friction, 1e-3 * particle.energies.kinetic);
  EXPECT_EQ(contact.velocities, particle.velocities);  // the ledger only watches
  const double damping =
      relative_difference(contact.energies.contact_damping, particle.energies.contact_damping);
  const double friction =
      relative_difference(contact.energies.friction, particle.energies.friction);
  std::printf("damping %.6g J, friction %.6g J: relative differences %.3g, %.3g\n",
              particle.energies.contact_damping, particle.energies.friction, damping, friction);
  EXPECT_LT(damping, 1e-7);
  EXPECT_LT(friction, 1e-7);
  EXPECT_GT(damping + friction, 0.0) << "the same numbers: the per-contact path did not run";
  // What the contacts hold: the same sums in another order.
  EXPECT_NEAR(contact.energies.contact_elastic, particle.energies.contact_elastic,
              1e-12 * particle.energies.contact_elastic);
  // The balance closes alike (to the integrator's order, 2e-4 of what was dissipated here).
  const double error_contact = contact.energies.balance_error(contact.initial);
  const double error_particle = particle.energies.balance_error(particle.initial);
  EXPECT_NEAR(error_contact, error_particle, 1e-6 * particle.energies.contact_damping);
}

// Grains that enter and leave: a leaving grain takes its contacts' held energies out with it,
// and its contacts' work stops with its last step, either way. Where a contact ends with a
// grain that leaves (or begins with one that enters), the two quadratures differ in that step's
// half (F^N at the velocity of the step's middle against the end's): O(dt^2) each time, so
// the difference is a small part of the ledger's own closure error and falls with dt (by 3.8
// at half the step: 2.9e-4 J, then 7.6e-5 J, of 2.5 J of damping).
TEST(LedgerEntries, PerContactBooksGrainsEnteringAndLeavingAsPerParticleDoes) {
  CaseConfig c = testing::grains_entering_and_leaving();
  constexpr int kSteps = 2500;
  const auto difference = [](const LedgerRun& a, const LedgerRun& b) {
    return std::abs(a.energies.contact_damping - b.energies.contact_damping) +
           std::abs(a.energies.friction - b.energies.friction);
  };
  const LedgerRun particle = run(c, std::nullopt, kSteps);
  const LedgerRun contact = run(c, std::nullopt, kSteps, /*per_contact=*/true);
  c.simulation.dt = 0.5 * c.simulation.dt.value();
  const LedgerRun particle_fine = run(c, std::nullopt, 2 * kSteps);
  const LedgerRun contact_fine = run(c, std::nullopt, 2 * kSteps, /*per_contact=*/true);
  ASSERT_GT(particle.energies.outflow, 0.0) << "no grain left: the test checks less";
  ASSERT_GT(particle.energies.contact_damping, 0.0);
  EXPECT_EQ(contact.velocities, particle.velocities);
  EXPECT_EQ(contact.energies.outflow, particle.energies.outflow);
  const double closure = std::abs(particle.energies.balance_error(particle.initial));
  std::printf("per contact - per particle: %.3g J, at dt/2 %.3g J; closure error %.3g J\n",
              difference(contact, particle), difference(contact_fine, particle_fine), closure);
  EXPECT_LT(difference(contact, particle), 0.1 * closure);
  EXPECT_LT(difference(contact_fine, particle_fine), 0.5 * difference(contact, particle));
  EXPECT_LT(std::abs(contact.energies.balance_error(contact.initial)), 1.1 * closure);
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
