// The energy part of the divergence guard (engine/EnergyGuard): it lets a ledger through that
// stays within what the run had (its start, potential released, work put in) and stops one
// that grows past it, with numbers worked out by hand.
#include <gtest/gtest.h>

#include <limits>

#include "engine/EnergyGuard.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

TEST(EnergyGuard, FallingBodyTradesPotentialForKineticEnergy) {
  EnergyGuard guard;
  Energies start;
  start.potential = 100.0;  // J, at rest
  EXPECT_FALSE(guard.check(start));
  Energies fallen;
  fallen.potential = 40.0;  // 60 J released ...
  fallen.kinetic = 59.0;    // ... 1 J of it dissipated
  fallen.friction = 1.0;
  EXPECT_FALSE(guard.check(fallen));
}

TEST(EnergyGuard, EnergyFromNowhereBeyondWhatTheRunHadStopsIt) {
  EnergyGuard guard;
  Energies start;
  start.kinetic = 2.0;
  start.bond_elastic = 1.0;  // the run has 3 J
  EXPECT_FALSE(guard.check(start));
  Energies grown = start;
  grown.kinetic = 2.0 + 2.9;  // 2.9 J more than it should: a large error, but within 3 J
  EXPECT_FALSE(guard.check(grown));
  grown.kinetic = 2.0 + 3.1;  // 3.1 J from nowhere: more than the run ever had
  const auto excess = guard.check(grown);
  ASSERT_TRUE(excess);
  EXPECT_NEAR(excess->created, 3.1, 1e-12);
  EXPECT_NEAR(excess->allowed, 3.0, 1e-6);
}

TEST(EnergyGuard, WorkPutInByDrivenBodiesIsAllowed) {
  EnergyGuard guard;
  EXPECT_FALSE(guard.check(Energies{}));  // at rest, nothing: the floor alone
  Energies pulled;
  pulled.boundary_work = 50.0;  // a pin has pulled 50 J into a ring ...
  pulled.bond_elastic = 45.0;   // ... stored elastically
  pulled.kinetic = 4.0;
  pulled.plastic_work = 1.0;
  EXPECT_FALSE(guard.check(pulled));
  pulled.kinetic = 4.0 + 60.0;  // 60 J from nowhere with only 50 J put in
  EXPECT_TRUE(guard.check(pulled));
}

TEST(EnergyGuard, NonFiniteEnergiesStopTheRun) {
  EnergyGuard guard;
  EXPECT_FALSE(guard.check(Energies{}));
  Energies broken;
  broken.kinetic = std::numeric_limits<double>::quiet_NaN();
  const auto excess = guard.check(broken);
  ASSERT_TRUE(excess);
  EXPECT_NE(EnergyGuard::describe(*excess).find("not finite"), std::string::npos);
}

TEST(EnergyGuard, RebaseAcceptsEnergyPutInFromOutsideTheLedger) {
  // A boulder placed with 24 kJ of kinetic energy (the rockfall's release) is not created by
  // the integrator: after rebase() the new state is the reference.
  EnergyGuard guard;
  EXPECT_FALSE(guard.check(Energies{}));
  Energies released;
  released.kinetic = 24e3;
  EXPECT_TRUE(guard.check(released));  // without rebase: energy from nowhere
  guard.rebase();
  EXPECT_FALSE(guard.check(released));
  Energies later = released;
  later.kinetic = 12e3;
  later.bond_elastic = 11e3;
  later.friction = 1e3;
  EXPECT_FALSE(guard.check(later));
}

}  // namespace
}  // namespace ringdem
