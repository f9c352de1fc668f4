// Multi-rate stepping (simulation.substeps, docs/physics.md "Two time scales"): coarse grains
// falling in two layers onto a net, so that they strike the net (fast contacts) and each other
// (slow contacts). Run with one rate and with the grains' contacts and gravity taken once every
// r steps of the net: the grains end where the single-rate run ends them, closer the smaller r;
// the momentum balance closes to round-off and the energy ledger to the integrator's order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "CaseLoaderFixtures.hpp"
#include "TestCases.hpp"
#include "app/InfoCommand.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/DivergenceError.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"

namespace ringdem {
namespace {

CaseConfig grains_on_a_net(int substeps) {
  return load_case_from_string(testing::grains_landing_on_a_net(substeps), "substeps.yaml");
}

struct SubsteppedRunEnd {
  std::vector<Vec3> grain_positions;  ///< by gid order
  double lowest_net_z = 0.0;          ///< the net particles' lowest z over the run's samples
  double peak_net_force = 0.0;        ///< largest |load on the held particles| over the samples (N)
  Energies energies, initial;
  MomentumBalance momentum;
};

/// Runs the case for `duration` seconds, sampling the net's sag every 0.5 ms.
SubsteppedRunEnd run_grains_on_a_net(int substeps, double duration) {
  const CaseConfig c = grains_on_a_net(substeps);
  const Communicator self = testing::self_comm();
  Simulation sim(build_scenario_model(c, self), self, settings_from_case(c));
  SubsteppedRunEnd end;
  end.initial = sim.energies();
  const std::int64_t per_sample = sim.steps_until(5e-4);
  while (sim.time() < duration - 1e-9) {
    sim.run_steps(per_sample);
    const ParticleStore& p = sim.model().particles;
    Vec3 held_load;  // what the net pulls on its shackles: their loads less their weight
    for (std::size_t k = 0; k < p.n_local(); ++k) {
      if (p.body[k] >= 0) end.lowest_net_z = std::min(end.lowest_net_z, p.position[k].z);
      if (p.motion[k] != Motion::kFree)
        held_load += p.force[k] - (substeps > 1 ? Vec3{} : c.simulation.gravity * p.mass[k]);
    }
    end.peak_net_force = std::max(end.peak_net_force, norm(held_load));
  }
  const ParticleStore& p = sim.model().particles;
  std::vector<std::pair<std::int64_t, Vec3>> by_gid;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.body[k] < 0 && p.motion[k] == Motion::kFree) by_gid.emplace_back(p.gid[k], p.position[k]);
  std::sort(by_gid.begin(), by_gid.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [gid, x] : by_gid)
    end.grain_positions.push_back(x);
  end.energies = sim.energies();
  end.momentum = sim.momentum_balance();
  return end;
}

double largest_grain_distance(const SubsteppedRunEnd& a, const SubsteppedRunEnd& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < a.grain_positions.size(); ++k)
    d = std::max(d, norm(a.grain_positions[k] - b.grain_positions[k]));
  return d;
}

// Over 0.15 s the lower grains strike the net and the upper ones land on them. The grains'
// contacts with each other taken once every r net steps move them from the single-rate run's
// positions by an amount of first order in the grain step (measured: 56, 114 and 228 um at r =
// 2, 5 and 10); the net's largest sag agrees to 0.13 mm of its 0.37 m, and the force it pulls
// its shackles with to a few parts in 10^4.
TEST(Substeps, GrainsOnANetConvergeToTheSingleRateRun) {
  constexpr double kDuration = 0.15;
  const SubsteppedRunEnd one = run_grains_on_a_net(1, kDuration);
  ASSERT_EQ(one.grain_positions.size(), 12u);
  EXPECT_LT(one.lowest_net_z, -0.3);  // the net caught the grains
  std::vector<double> distance;
  for (const int r : {2, 10}) {
    const SubsteppedRunEnd many = run_grains_on_a_net(r, kDuration);
    ASSERT_EQ(many.grain_positions.size(), 12u);
    distance.push_back(largest_grain_distance(one, many));
    EXPECT_LT(distance.back(), 1e-3) << "r = " << r;
    EXPECT_NEAR(many.lowest_net_z, one.lowest_net_z, 3e-4) << "r = " << r;
    // The barrier force: the net's largest pull on its shackles (815 N) within 0.1 %, and its
    // impulse over the run within 0.2 % (measured: 0.003 % and 0.045 % at r = 10).
    EXPECT_NEAR(many.peak_net_force, one.peak_net_force, 1e-3 * one.peak_net_force) << "r = " << r;
    EXPECT_NEAR(norm(many.momentum.held), norm(one.momentum.held), 2e-3 * norm(one.momentum.held))
        << "r = " << r;
    // The ledger closes as the single-rate run's does: to 1e-3 of what the contacts dissipated.
    const double dissipated = many.energies.contact_damping + many.energies.friction;
    EXPECT_GT(dissipated, 1.0);
    EXPECT_LT(std::abs(many.energies.balance_error(many.initial)), 1e-3 * dissipated)
        << "r = " << r;
    // Every impulse booked as it was applied: the balance closes to round-off (of some 60 N s).
    EXPECT_LT(norm(many.momentum.residual()), 1e-8) << "r = " << r;
  }
  // Converging: a grain step five times shorter comes at least twice as close.
  EXPECT_GT(distance[0], 0.0);
  EXPECT_LT(2.0 * distance[0], distance[1]);
}

/// grains_landing_on_a_net(substeps) above a bed plane at z = -0.3 m, with a third layer of
/// the same grains at rest on the bed under the net: the net, pushed down by the falling
/// grains, pinches the resting ones against the bed.
CaseConfig grains_pinched_between_a_net_and_a_bed(int substeps) {
  return load_case_from_string(
      testing::grains_landing_on_a_net(
          substeps,
          "    - {group: grains, origin: [-0.3, -0.2, -0.292], count: [16, 11, 1], spacing: 0.04, "
          "particle_radius: 0.008, material: rock, velocity: [0, 0, 0]}\n") +
          "rigid_bodies:\n  - {name: bed, shape: plane, position: [0, 0, -0.3], normal: [0, 0, "
          "1], material: rock}\n",
      "pinched.yaml");
}

/// The free grains that touch a net particle (a bead or a held particle), by brute force over
/// every pair: what the check at the end of every 16th grain step must have flagged.
std::vector<std::int64_t> grains_touching_the_net(const ParticleStore& p) {
  std::vector<std::int64_t> out;
  for (std::size_t g = 0; g < p.n_local(); ++g) {
    if (p.body[g] >= 0 || p.motion[g] != Motion::kFree) continue;
    for (std::size_t k = 0; k < p.n_local(); ++k)
      if ((p.body[k] >= 0 || p.motion[k] != Motion::kFree) &&
          norm(p.position[k] - p.position[g]) < p.radius[k] + p.radius[g]) {
        out.push_back(p.gid[g]);
        break;
      }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// A single-rate run books every interaction in its one ledger: the fast ledger keeps no
// records there (they were a second copy of the ledger slots' records, 5.5 bytes a grain of a
// 10^6-grain bed on its floor). Sub-stepped, each ledger keeps the records of its own rate.
TEST(Substeps, OnlyASubsteppedRunKeepsAFastLedger) {
  const Communicator self = testing::self_comm();
  for (const int substeps : {1, 4}) {
    const CaseConfig c = grains_pinched_between_a_net_and_a_bed(substeps);
    Simulation sim(build_scenario_model(c, self), self, settings_from_case(c));
    // Until some bed contact is fast (a grain pinched between the net and the bed, or a bead
    // near the bed): the fast ledger then has a slot to record.
    sim.run_steps(16);
    while (substeps > 1 && sim.n_fast_body_contact_candidates() == 0 && sim.time() < 0.4)
      sim.run_steps(16);
    // Records: one per ledger slot (the grains' contacts with the bed), and a scratch one.
    EXPECT_GT(sim.energy_ledger().n_records(), 1u) << substeps << " sub-steps";
    if (substeps == 1) {
      EXPECT_FALSE(sim.fast_energy_ledger().enabled());
      EXPECT_EQ(sim.fast_energy_ledger().n_records(), 0u);
    } else {
      ASSERT_GT(sim.n_fast_body_contact_candidates(), 0u) << "no fast bed contact by 0.4 s";
      EXPECT_TRUE(sim.fast_energy_ledger().enabled());
      EXPECT_GT(sim.fast_energy_ledger().n_records(), 1u);
    }
  }
}

// A grain that touches the net takes all its contacts, with the bed and with other grains, at
// the net's rate from the check at the end of every 16th grain step (Simulation::
// note_net_contacts): pinched between a ring and the bed, its bed contact at the grains' step
// had the ring's sub-steps pump energy into it (the 10^5-grain channel, docs/debris.md). The
// flags are those of a brute-force search at every check; the pinched grains' bed contacts
// are fast; and the ledger closes better than without (measured at r = 10 over 0.4 s: 1.1e-4
// of the dissipated energy with the flags, 2.2e-4 without them, 1.2e-5 with one rate).
TEST(Substeps, GrainsTouchingTheNetStepAtTheNetsRate) {
  const CaseConfig c = grains_pinched_between_a_net_and_a_bed(10);
  const Communicator self = testing::self_comm();
  Simulation sim(build_scenario_model(c, self), self, settings_from_case(c));
  const Energies initial = sim.energies();
  std::size_t most_flagged = 0, most_pinched = 0;
  while (sim.time() < 0.4) {
    sim.run_steps(16 - (sim.steps() - 1) % 16);  // to just after a check
    ASSERT_EQ(sim.steps() % 16, 1);
    const ParticleStore& p = sim.model().particles;
    std::vector<std::int64_t> flagged;
    for (std::size_t k = 0; k < p.n_local(); ++k)
      if (p.net_contact[k] != 0) flagged.push_back(p.gid[k]);
    std::sort(flagged.begin(), flagged.end());
    ASSERT_EQ(flagged, grains_touching_the_net(p)) << "t = " << sim.time();
    most_flagged = std::max(most_flagged, flagged.size());
    sim.run_steps(1);  // the flags' rates are taken at the next step's start
    // A flagged grain that touches the bed (pinched) is a fast bed candidate: at least as many
    // fast candidates as such grains (beads near the bed are fast candidates too).
    std::size_t pinched = 0;
    for (std::size_t k = 0; k < p.n_local(); ++k)
      pinched += p.net_contact[k] != 0 && p.position[k].z - p.radius[k] < -0.3 ? 1 : 0;
    EXPECT_GE(sim.n_fast_body_contact_candidates(), pinched) << "t = " << sim.time();
    most_pinched = std::max(most_pinched, pinched);
  }
  // The falling grains and the resting ones touch the net in turn, and some resting ones are
  // pinched against the bed (measured: 3 and 2 at most at a check).
  EXPECT_GE(most_flagged, 3u);
  EXPECT_GE(most_pinched, 1u);
  // No grain comes or goes here: every changed flag moved rates without a search.
  EXPECT_GT(sim.rate_changes(), 0);
  const Energies e = sim.energies();
  const double dissipated = e.contact_damping + e.friction;
  EXPECT_GT(dissipated, 50.0);
  EXPECT_LT(std::abs(e.balance_error(initial)), 1.6e-4 * dissipated);
}

/// Every owned particle's position, velocity and angular velocity, in gid order.
struct ParticleBits {
  std::int64_t gid;
  Vec3 x, v, w;
};
std::vector<ParticleBits> particle_bits(const Simulation& sim) {
  const ParticleStore& p = sim.model().particles;
  std::vector<ParticleBits> out;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    out.push_back({p.gid[k], p.position[k], p.velocity[k], p.omega[k]});
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.gid < b.gid; });
  return out;
}

/// How many particles of `a` differ from those of `e` in any bit (both in gid order, of the
/// same gids; a failure, counting all, where they are not).
std::size_t particles_of_other_bits(const std::vector<ParticleBits>& a,
                                    const std::vector<ParticleBits>& e) {
  if (a.size() != e.size()) {
    ADD_FAILURE() << a.size() << " particles against " << e.size();
    return std::max(a.size(), e.size());
  }
  std::size_t differ = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const bool same = a[k].gid == e[k].gid && std::memcmp(&a[k].x, &e[k].x, sizeof(Vec3)) == 0 &&
                      std::memcmp(&a[k].v, &e[k].v, sizeof(Vec3)) == 0 &&
                      std::memcmp(&a[k].w, &e[k].w, sizeof(Vec3)) == 0;
    differ += same ? 0 : 1;
  }
  return differ;
}

/// The fewest and most particles the sub-steps moved, as fractions of those owned.
struct MoverShares {
  double fewest = 1.0, most = 0.0;
};

/// Runs `c` twice in lockstep, `batches` batches of `grain_steps` grain steps: the sub-steps
/// moving only the particles that fast interactions can load (the default), and moving every
/// particle. Both must hold the same bits after every batch.
MoverShares expect_movers_alone_step_alike(const CaseConfig& c, int batches,
                                           std::int64_t grain_steps) {
  const Communicator self = testing::self_comm();
  Simulation movers(build_scenario_model(c, self), self, settings_from_case(c));
  Simulation all(build_scenario_model(c, self), self, settings_from_case(c));
  all.set_substeps_move_all(true);
  MoverShares shares;
  for (int b = 0; b < batches; ++b) {
    movers.run_steps(grain_steps);
    all.run_steps(grain_steps);
    const std::size_t n = movers.model().particles.n_local();
    EXPECT_EQ(all.n_substep_movers(), n);
    const double share = static_cast<double>(movers.n_substep_movers()) / static_cast<double>(n);
    shares.fewest = std::min(shares.fewest, share);
    shares.most = std::max(shares.most, share);
    const auto a = particle_bits(movers), e = particle_bits(all);
    EXPECT_EQ(movers.rebuilds(), all.rebuilds()) << "batch " << b;
    const std::size_t differ = particles_of_other_bits(a, e);
    EXPECT_EQ(differ, 0u) << "particles of other bits after batch " << b << " of " << a.size();
    if (differ != 0) return shares;
  }
  const Energies ea = movers.energies(), ee = all.energies();
  EXPECT_EQ(ea.kinetic, ee.kinetic);
  EXPECT_EQ(ea.friction, ee.friction);
  EXPECT_EQ(ea.contact_damping, ee.contact_damping);
  EXPECT_EQ(norm(movers.momentum_balance().residual()), norm(all.momentum_balance().residual()));
  return shares;
}

// The sub-steps move only the net, the particles held and the grains that a fast interaction
// can load before the next rebuild; the others take their sub-steps' drifts together when
// their positions are next read (SubstepParticles). That is the same operations on the same
// values: the same bits as moving every particle at every sub-step, while the grains fall
// towards the net (few move), strike it and land on each other (rebuilds inside grain steps).
TEST(Substeps, MovingOnlyWhatFastLoadsReachGivesTheSameBits) {
  const MoverShares shares = expect_movers_alone_step_alike(
      load_case_from_string(testing::three_layers_landing_on_a_net(4), "movers.yaml"), 40, 300);
  // The net and its shackles (180 of 256 particles) move throughout; the coarse grains that
  // strike the net join them (measured: 186 at most).
  EXPECT_LT(shares.fewest, 0.75);
  EXPECT_GT(shares.most, shares.fewest);
}

// A grain whose contact with the net changed moves its interactions to the other rate without
// a new search (Simulation::change_rates()): the candidates are those of the last rebuild, the
// rates and the gather order those a rebuild would give. The same bits as rebuilding at every
// change, with fewer rebuilds, while grains land on the net, leave it and are pinched against
// the bed.
TEST(Substeps, RatesChangedWithoutASearchGiveTheBitsOfARebuild) {
  const CaseConfig c = grains_pinched_between_a_net_and_a_bed(10);
  const Communicator self = testing::self_comm();
  Simulation changes(build_scenario_model(c, self), self, settings_from_case(c));
  Simulation rebuilds(build_scenario_model(c, self), self, settings_from_case(c));
  rebuilds.set_rebuild_on_rate_change(true);
  for (int b = 0; b < 8; ++b) {
    changes.run_steps(1000);
    rebuilds.run_steps(1000);
    EXPECT_EQ(changes.n_fast_body_contact_candidates(), rebuilds.n_fast_body_contact_candidates())
        << "batch " << b;
    const std::size_t differ =
        particles_of_other_bits(particle_bits(changes), particle_bits(rebuilds));
    ASSERT_EQ(differ, 0u) << "particles of other bits after batch " << b;
  }
  EXPECT_EQ(rebuilds.rate_changes(), 0);
  // Measured: 79 changes of rate in 0.16 s, 1 143 rebuilds against 1 183.
  EXPECT_GE(changes.rate_changes(), 20);
  EXPECT_LT(changes.rebuilds(), rebuilds.rebuilds());
  const Energies ea = changes.energies(), ee = rebuilds.energies();
  EXPECT_EQ(ea.friction, ee.friction);
  EXPECT_EQ(ea.contact_damping, ee.contact_damping);
  EXPECT_EQ(ea.boundary_work, ee.boundary_work);
  EXPECT_EQ(norm(changes.momentum_balance().residual()),
            norm(rebuilds.momentum_balance().residual()));
}

// With no net every grain's loads are slow: the sub-steps move none, and the outflow's test,
// the inlets' batches and the rebuilds read the grains after they caught up.
TEST(Substeps, GrainsWithoutANetCatchUpBeforeTheyAreRead) {
  CaseConfig c = testing::grains_entering_and_leaving();
  c.simulation.substeps = 3;
  const MoverShares shares = expect_movers_alone_step_alike(c, 10, 100);
  EXPECT_EQ(shares.most, 0.0);
}

// A run that diverges inside a grain step hands its state over for an inspection frame
// (ScenarioRunner): the particles that the sub-steps left behind have caught up, and the state
// is the bits of moving every particle. A grain's velocity set to NaN is caught at the first
// sub-step's rebuild test.
TEST(Substeps, ADivergenceInsideAGrainStepLeavesEveryParticleWhereItIs) {
  const CaseConfig c =
      load_case_from_string(testing::three_layers_landing_on_a_net(4), "diverging.yaml");
  const Communicator self = testing::self_comm();
  Simulation movers(build_scenario_model(c, self), self, settings_from_case(c));
  Simulation all(build_scenario_model(c, self), self, settings_from_case(c));
  all.set_substeps_move_all(true);
  std::int64_t nan_gid = -1;
  for (Simulation* sim : {&movers, &all}) {
    sim->run_steps(10);
    ParticleStore& p = sim->model().particles;
    for (std::size_t k = 0; k < p.n_local(); ++k)
      if (p.body[k] < 0 && p.motion[k] == Motion::kFree) {
        nan_gid = p.gid[k];
        p.velocity[k].x = std::numeric_limits<double>::quiet_NaN();
        break;
      }
    EXPECT_THROW(sim->run_steps(1), DivergenceError);
  }
  const auto a = particle_bits(movers), e = particle_bits(all);
  ASSERT_EQ(a.size(), e.size());
  std::size_t differ = 0, compared = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].gid == nan_gid) continue;  // its position is NaN either way
    ++compared;
    differ += std::memcmp(&a[k].x, &e[k].x, sizeof(Vec3)) == 0 ? 0 : 1;
  }
  EXPECT_GT(compared, 200u);
  EXPECT_EQ(differ, 0u);
}

// What the sub-steps cannot take yet is refused before the run starts, with the reason: by the
// loader (a scenario other than a free run; checkpoints are written, a sub-stepped run restarts:
// tests/mpi/test_output.cpp) ...
TEST(Substeps, TheLoaderRefusesOtherScenariosAndTakesCheckpoints) {
  using case_fixture::errors_of;
  const std::string yaml =
      testing::net_free_run("dt: 2.0e-6, end_time: 1.0, substeps: 4", "rows: 2, columns: 3", "") +
      "output: {checkpoint_interval: 0.01}\n";
  const CaseConfig c = load_case_from_string(yaml, "checkpointed.yaml");
  EXPECT_EQ(c.simulation.substeps, 4);
  EXPECT_EQ(c.output.checkpoint_interval, 0.01);
  std::string rockfall = testing::kTinyRockfall;
  rockfall.replace(rockfall.find("progress_interval"), 0, "substeps: 4, ");
  const auto diags = errors_of(rockfall);
  ASSERT_EQ(diags.size(), 1u) << case_fixture::all(diags);
  EXPECT_EQ(diags[0].key_path, "simulation.substeps");
}

// A sub-stepped run's checkpoint says so: `ringdem info` gives its dt as a grain step of so many
// sub-steps and lists the fast ledgers' datasets, whose checksums it verifies with the rest.
TEST(Substeps, InfoTellsASubsteppedCheckpoint) {
  const std::string dir = ::testing::TempDir() + "/ringdem_substeps_info";
  std::filesystem::remove_all(dir);
  std::string path[2];
  for (int r : {1, 4}) {
    const CaseConfig c = grains_on_a_net(r);
    const Communicator self = testing::self_comm();
    Simulation sim(build_scenario_model(c, self), self, settings_from_case(c));
    sim.run_steps(10);
    path[r > 1] = CheckpointStore(dir + "/r" + std::to_string(r))
                      .write(self, sim.model(), sim.restart_state(), DriverState{}, 0, c);
  }
  EXPECT_EQ(read_checkpoint_info(path[0]).substeps, 1);
  EXPECT_EQ(read_checkpoint_info(path[1]).substeps, 4);
  std::ostringstream one, four;
  ASSERT_EQ(print_file_info(path[0], one), 0);
  ASSERT_EQ(print_file_info(path[1], four), 0);
  EXPECT_EQ(one.str().find("sub-steps"), std::string::npos) << one.str();
  EXPECT_EQ(one.str().find("/substeps/"), std::string::npos) << one.str();
  EXPECT_NE(four.str().find("dt = 8e-06 s (a grain step of 4 sub-steps)"), std::string::npos)
      << four.str();
  for (const char* name : {"/particles/slow_force", "/particles/net_contact", "/substeps/momentum",
                           "/substeps/ledger"})
    EXPECT_NE(four.str().find(name), std::string::npos) << name << " in\n" << four.str();
  // The fast ledgers' datasets are checksummed like the others: two more than one rate's file,
  // besides the slow loads' two particle columns and the grains' net contacts.
  EXPECT_EQ(verify_checkpoint(path[1]).size(), verify_checkpoint(path[0]).size() + 5);
  std::filesystem::remove_all(dir);
}

// ... and by the simulation (global damping, free bodies, brakes and ropes).
TEST(Substeps, ACaseWithGlobalDampingIsRefused) {
  CaseConfig c = grains_on_a_net(4);
  const Communicator self = testing::self_comm();
  Model model = build_scenario_model(c, self);
  model.particles.set_tracks_damping(true);
  try {
    Simulation sim(std::move(model), self, settings_from_case(c));
    FAIL() << "a damped model was sub-stepped";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("damping"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ringdem
