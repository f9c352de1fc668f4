// The energy ledger's per-particle columns exist only where the ledger is booked
// (ParticleStore::tracks_ledger, simulation.energy_ledger). Without them a run must move the
// same bits as with them, grains arriving and leaving included, and a checkpoint must cross the
// switch both ways: written without the columns it restarts with the ledger from zero; written
// with them it restarts without. The oracle is the uninterrupted run with the ledger on.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "TempDir.hpp"
#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"
#include "io/Hdf5File.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

bool registers_ledger(ParticleStore& p) {
  bool found = false;
  p.for_each_field([&](const FieldInfo& f, auto&) {
    found = found || f.name == "dissipated_global" || f.name == "power_global";
  });
  return found;
}

/// Position and velocity of every particle by gid (one rank holds them all).
std::map<std::int64_t, std::pair<Vec3, Vec3>> motion_by_gid(const Simulation& sim) {
  const ParticleStore& p = sim.model().particles;
  std::map<std::int64_t, std::pair<Vec3, Vec3>> out;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    out[p.gid[k]] = {p.position[k], p.velocity[k]};
  return out;
}

void expect_same_bits(const Simulation& a, const Simulation& b) {
  const auto ma = motion_by_gid(a), mb = motion_by_gid(b);
  ASSERT_EQ(ma.size(), mb.size());
  for (const auto& [gid, m] : ma) {
    const auto it = mb.find(gid);
    ASSERT_NE(it, mb.end()) << "gid " << gid;
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(m.first[c], it->second.first[c]) << "gid " << gid;
      ASSERT_EQ(m.second[c], it->second.second[c]) << "gid " << gid;
    }
  }
}

/// With a little global damping, so that the grains carry the ledger's columns (an undamped
/// model keeps none: ParticleStore::tracks_damping()).
CaseConfig with_ledger(bool on) {
  CaseConfig c = testing::grains_entering_and_leaving();
  c.simulation.energy_ledger = on;
  c.damping.global = 0.02;
  return c;
}

TEST(LedgerColumns, OnlyABookedLedgerKeepsThemAndTheMotionIsTheSame) {
  const Communicator self = testing::self_comm();
  const CaseConfig on = with_ledger(true), off = with_ledger(false);
  Model built = build_model(off, self);
  EXPECT_FALSE(built.particles.tracks_ledger());
  EXPECT_FALSE(registers_ledger(built.particles));
  EXPECT_EQ(built.particles.dissipated_global.capacity(), 0u);
  Simulation without(std::move(built), self, settings_from_case(off));
  Simulation with(build_model(on, self), self, settings_from_case(on));
  EXPECT_TRUE(with.model().particles.tracks_ledger());
  without.run_steps(2500);
  with.run_steps(2500);
  ASSERT_GT(without.inflow_totals().grains, 0) << "no grain arrived: the test checks less";
  ASSERT_GT(without.outflow_totals().grains, 0) << "no grain left: the test checks less";
  ASSERT_GT(with.energies().contact_damping, 0.0) << "no contact dissipated: nothing booked";
  EXPECT_EQ(without.model().particles.dissipated_global.capacity(), 0u);
  EXPECT_EQ(without.model().particles.power_global.capacity(), 0u);
  expect_same_bits(without, with);
}

class LedgerSwitchAtRestart : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::temp_dir("ledger"); }
  void TearDown() override { fs::remove_all(dir_); }

  /// Runs `first` steps with the ledger `before`, checkpoints, restarts with it `after`, runs
  /// `second` more steps; returns the resumed simulation's state next to an uninterrupted
  /// ledger-on run of first + second steps.
  void cross(bool before, bool after) {
    const Communicator self = testing::self_comm();
    const CaseConfig written = with_ledger(before), read = with_ledger(after);
    std::string path;
    {
      Simulation sim(build_model(written, self), self, settings_from_case(written));
      sim.run_steps(kFirst);
      path = CheckpointStore(dir_ + (before ? "/on" : "/off"))
                 .write(self, sim.model(), sim.restart_state(), DriverState{}, 0, written);
    }
    EXPECT_EQ(Hdf5File::open_read(path).exists("/particles/dissipated_global"), before);
    Model model = build_model_without_particles(read);
    DriverState d;
    const RestartState state = read_checkpoint(self, path, read, model, d);
    EXPECT_EQ(model.particles.tracks_ledger(), after);
    if (after) {
      ASSERT_EQ(model.particles.dissipated_global.size(), model.particles.n_local());
      for (std::size_t k = 0; k < model.particles.n_local() && !before; ++k)
        ASSERT_EQ(model.particles.dissipated_global[k], 0.0) << "a tally that was never booked";
    }
    Simulation resumed(std::move(model), self, settings_from_case(read), state);
    resumed.run_steps(kSecond);
    const CaseConfig on = with_ledger(true);
    Simulation reference(build_model(on, self), self, settings_from_case(on));
    reference.run_steps(kFirst + kSecond);
    expect_same_bits(resumed, reference);
    if (!after) return;
    // Booked since the restart only, when the ledger was off before it.
    const double booked = resumed.energies().contact_damping;
    const double all = reference.energies().contact_damping;
    EXPECT_GT(booked, 0.0);
    if (before)
      EXPECT_EQ(booked, all);
    else
      EXPECT_LT(booked, all);
  }

  static constexpr int kFirst = 1500, kSecond = 1000;
  std::string dir_;
};

TEST_F(LedgerSwitchAtRestart, WrittenWithoutTheColumnsRestartsWithTheLedgerFromZero) {
  cross(false, true);
}
TEST_F(LedgerSwitchAtRestart, WrittenWithThemRestartsWithout) {
  cross(true, false);
}
TEST_F(LedgerSwitchAtRestart, WrittenWithThemRestartsWithThemExactly) {
  cross(true, true);
}

/// An undamped case keeps no damping columns. A coefficient set while it runs turns them on;
/// the run is then the same bits as one that kept them (all zero) from the start, and a
/// checkpoint written after that restarts into a model built from the undamped case with
/// its coefficients and tallies.
TEST_F(LedgerSwitchAtRestart, DampingColumnsOnlyOnceSomethingIsDamped) {
  const Communicator self = testing::self_comm();
  const CaseConfig c = testing::grains_entering_and_leaving();
  ASSERT_EQ(c.damping.global, 0.0);
  Model undamped = build_model(c, self);
  EXPECT_FALSE(undamped.particles.tracks_damping());
  EXPECT_EQ(undamped.particles.damping.capacity(), 0u);
  EXPECT_EQ(undamped.particles.dissipated_global.capacity(), 0u);
  Model kept = build_model(c, self);
  kept.particles.set_tracks_damping(true);
  ASSERT_EQ(kept.particles.damping.size(), kept.particles.n_local());
  Simulation without(std::move(undamped), self, settings_from_case(c));
  Simulation with(std::move(kept), self, settings_from_case(c));
  without.run_steps(kFirst);
  with.run_steps(kFirst);
  expect_same_bits(without, with);
  EXPECT_EQ(without.energies().total(), with.energies().total());
  EXPECT_EQ(with.energies().global_damping, 0.0);
  for (Simulation* sim : {&without, &with})
    sim->set_group_damping(0, 0.3);
  EXPECT_TRUE(without.model().particles.tracks_damping());
  const std::string path =
      CheckpointStore(dir_ + "/damped")
          .write(self, without.model(), without.restart_state(), DriverState{}, 0, c);
  without.run_steps(kSecond);
  with.run_steps(kSecond);
  expect_same_bits(without, with);
  const double damped = with.energies().global_damping;
  EXPECT_GT(damped, 0.0) << "the coefficient took nothing out: the test checks less";
  EXPECT_EQ(without.energies().global_damping, damped);
  Model model = build_model_without_particles(c);
  EXPECT_FALSE(model.particles.tracks_damping());
  DriverState d;
  const RestartState state = read_checkpoint(self, path, c, model, d);
  EXPECT_TRUE(model.particles.tracks_damping());
  Simulation resumed(std::move(model), self, settings_from_case(c), state);
  resumed.run_steps(kSecond);
  expect_same_bits(resumed, with);
  EXPECT_EQ(resumed.energies().global_damping, damped);
}

}  // namespace
}  // namespace ringdem
