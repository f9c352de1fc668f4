// Frame files and checkpoints (issue 5, DESIGN §5): a frame file holds the state the run had
// when it was written and does not depend on the rank count, and N steps -> checkpoint ->
// restart (on this rank count and on one rank) -> N steps equals 2N steps, bit for bit. Every
// rank also runs the one-rank reference.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <compare>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"
#include "io/FrameWriter.hpp"
#include "io/Hdf5File.hpp"

namespace ringdem {
namespace {

void write_frames(Simulation& sim, FrameWriter& frames, std::int64_t steps, std::int64_t every) {
  for (std::int64_t k = 0; k <= steps; ++k) {
    if (k % every == 0) {
      sim.refresh_bond_diagnostics();
      frames.write(sim.model().particles, sim.model().bonds, sim.model().bodies, sim.time(),
                   sim.steps());
    }
    if (k < steps) sim.step();
  }
}

struct ParticleSnapshot {
  std::int64_t gid;
  Vec3 position, velocity;
};

/// Every owned particle's gid, position and velocity, of all ranks, ordered by gid.
std::vector<ParticleSnapshot> gather_particles(const Simulation& sim) {
  const ParticleStore& p = sim.model().particles;
  std::vector<ParticleSnapshot> mine;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    mine.push_back({p.gid[k], p.position[k], p.velocity[k]});
  auto all = sim.comm().allgather(mine);
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.gid < b.gid; });
  return all;
}

/// Every dataset below `groups`, byte for byte; returns the number of datasets compared.
int expect_same_datasets(const std::string& a_path, const std::string& b_path,
                         const std::vector<std::string>& groups,
                         const std::vector<std::string>& skip = {}) {
  const Hdf5File a = Hdf5File::open_read(a_path);
  const Hdf5File b = Hdf5File::open_read(b_path);
  int compared = 0;
  for (const auto& g : groups) {
    const auto names = a.list(g);
    EXPECT_EQ(names, b.list(g)) << g;
    for (const auto& n : names) {
      const std::string full = g + "/" + n;
      if (std::find(skip.begin(), skip.end(), full) != skip.end()) continue;
      std::size_t ra = 0, rb = 0;
      EXPECT_EQ(a.dims(full), b.dims(full)) << full;
      EXPECT_TRUE(a.read_bytes(full, ra) == b.read_bytes(full, rb)) << full << " differs";
      ++compared;
    }
  }
  return compared;
}

TEST(FrameFile, SameOnAnyRankCountOrderedByGid) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "frames");
    const CaseConfig c = testing::ring_patch_hit_by_sphere(-0.005, 60.0, 0.5);
    const SimulationSettings s = settings_from_case(c);
    constexpr std::int64_t kSteps = 900, kEvery = 300;
    // The state the run ends with, which its last frame must hold: read from the particle
    // stores, not from a file, so this holds at one rank too, where the comparison with the
    // one-rank file below compares two runs of the same code.
    std::vector<ParticleSnapshot> final_state;
    {
      Simulation sim(build_model(c, comm), comm, s);
      FrameWriter frames(comm, dir + "/parallel.h5", dir + "/parallel.xdmf");
      write_frames(sim, frames, kSteps, kEvery);
      EXPECT_EQ(frames.frames(), kSteps / kEvery + 1);
      final_state = gather_particles(sim);
    }
    if (comm.is_root()) {
      const Communicator self = Communicator::self();
      Simulation sim(build_model(c, self), self, s);
      FrameWriter frames(self, dir + "/serial.h5", dir + "/serial.xdmf");
      write_frames(sim, frames, kSteps, kEvery);
    }
    comm.barrier();
    if (comm.is_root()) {
      const int n =
          expect_same_datasets(dir + "/serial.h5", dir + "/parallel.h5",
                               {"/frames", "/particles", "/bonds", "/bodies", "/bodies/surface"},
                               {"/particles/rank", "/bodies/surface"});
      EXPECT_GE(n, 18);
      const Hdf5File f = Hdf5File::open_read(dir + "/parallel.h5");
      const std::int64_t last = kSteps / kEvery;
      const auto gids = f.read_rows<std::int64_t>("/particles/gid", last);
      const auto positions = f.read_rows<Vec3>("/particles/position", last);
      const auto velocities = f.read_rows<Vec3>("/particles/velocity", last);
      ASSERT_EQ(gids.size(), final_state.size());
      ASSERT_EQ(positions.size(), final_state.size());
      ASSERT_EQ(velocities.size(), final_state.size());
      std::size_t moved = 0;
      for (std::size_t k = 0; k < gids.size(); ++k) {
        ASSERT_EQ(gids[k], static_cast<std::int64_t>(k));
        ASSERT_EQ(final_state[k].gid, gids[k]);
        // Written as they were: exact.
        EXPECT_EQ(positions[k], final_state[k].position) << "gid " << gids[k];
        EXPECT_EQ(velocities[k], final_state[k].velocity) << "gid " << gids[k];
        moved += !(velocities[k] == Vec3{});
      }
      EXPECT_GT(moved, 0u) << "the last frame should be of a moving patch";
      const auto ranks = f.read_rows<std::int32_t>("/particles/rank", 2);
      const auto [lo, hi] = std::minmax_element(ranks.begin(), ranks.end());
      EXPECT_EQ(*lo, 0);
      EXPECT_EQ(*hi, comm.size() - 1) << "every rank owns part of the patch";
      std::filesystem::remove_all(dir);
    }
  }
}

struct SpringKey {
  std::uint8_t kind;
  std::int64_t gid, partner;
  auto operator<=>(const SpringKey&) const = default;
};

struct HistoryRow {
  std::string term;
  std::int64_t gid, partner;
  Vec3 spring;
};

/// The springs of a checkpoint as a sorted set (ranks write them in their own order).
std::vector<HistoryRow> history_of(const std::string& path) {
  const Hdf5File f = Hdf5File::open_read(path);
  std::vector<HistoryRow> rows;
  for (const std::string term : {"particle_contacts", "body_contacts"}) {
    const auto gid = f.read_rows<std::int64_t>("/history/" + term + ".gid");
    const auto partner = f.read_rows<std::int64_t>("/history/" + term + ".partner");
    const auto spring = f.read_rows<Vec3>("/history/" + term + ".spring");
    for (std::size_t k = 0; k < gid.size(); ++k)
      rows.push_back({term, gid[k], partner[k], spring[k]});
  }
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return std::tie(a.term, a.gid, a.partner) < std::tie(b.term, b.gid, b.partner);
  });
  return rows;
}

void expect_same_checkpoint_state(const std::string& ref, const std::string& got) {
  expect_same_datasets(ref, got, {"/particles", "/bonds", "/bodies", "/driver"});
  const auto a = history_of(ref), b = history_of(got);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(std::tie(a[k].term, a[k].gid, a[k].partner),
              std::tie(b[k].term, b[k].gid, b[k].partner));
    EXPECT_EQ(a[k].spring, b[k].spring) << "spring of " << a[k].gid << "-" << a[k].partner;
  }
  const CheckpointInfo ia = read_checkpoint_info(ref), ib = read_checkpoint_info(got);
  EXPECT_EQ(ia.time, ib.time);
  EXPECT_EQ(ia.step, ib.step);
  EXPECT_EQ(ia.dt, ib.dt);
  // The neighbour lists are rebuilt at the same steps: a restart neither adds a rebuild nor
  // moves the next one (issue 15 item 9).
  EXPECT_EQ(ia.rebuilds, ib.rebuilds);
}

std::unique_ptr<Simulation> restart(const CaseConfig& c, const std::string& path,
                                    const Communicator& comm) {
  Model model = build_model_without_particles(c);
  DriverState driver;
  const RestartState state = read_checkpoint(comm, path, c, model, driver);
  EXPECT_EQ(driver.get("marker"), 42.0);
  return std::make_unique<Simulation>(std::move(model), comm, settings_from_case(c), state);
}

TEST(Checkpoint, RestartOnSameAndOtherRankCountIsBitwise) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "restart");
    const CaseConfig c = testing::ring_patch_hit_by_sphere(-0.005, 60.0, 0.5);
    const SimulationSettings s = settings_from_case(c);
    constexpr std::int64_t kHalf = 1000;
    DriverState driver;
    driver.set("marker", 42.0);
    // 2N steps straight through.
    std::string straight;
    std::size_t straight_springs = 0;
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(2 * kHalf);
      straight = CheckpointStore(dir + "/straight")
                     .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
      // Each tangential spring is held by exactly one rank (a contact across ranks is
      // evaluated on both), and the checkpoint holds each once.
      std::vector<SpringKey> springs;
      const auto owned = sim.owned_springs();
      for (std::size_t t = 0; t < owned.size(); ++t)
        for (std::size_t h = 0; h < owned[t].store.size(); ++h)
          springs.push_back(
              {static_cast<std::uint8_t>(t), owned[t].store.gid[h], owned[t].store.partner[h]});
      springs = comm.allgather(springs);
      std::sort(springs.begin(), springs.end());
      EXPECT_EQ(std::adjacent_find(springs.begin(), springs.end()), springs.end())
          << "a spring is owned by two ranks";
      EXPECT_GT(springs.size(), 0u) << "the case should carry tangential springs";
      straight_springs = springs.size();
    }
    // N steps, checkpoint, restart here, N steps.
    std::string middle, resumed;
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(kHalf);
      middle = CheckpointStore(dir + "/middle")
                   .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    {
      auto sim = restart(c, middle, comm);
      EXPECT_EQ(sim->steps(), kHalf);
      sim->run_steps(kHalf);
      resumed = CheckpointStore(dir + "/resumed")
                    .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    // And on one rank (another rank count whenever this run has more than one).
    std::string resumed_serial;
    if (comm.is_root()) {
      const Communicator self = Communicator::self();
      auto sim = restart(c, middle, self);
      sim->run_steps(kHalf);
      resumed_serial = CheckpointStore(dir + "/serial")
                           .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    comm.barrier();
    if (comm.is_root()) {
      const auto info = read_checkpoint_info(straight);
      EXPECT_EQ(info.history_entries, static_cast<std::int64_t>(straight_springs));
      EXPECT_GT(info.rebuilds, read_checkpoint_info(middle).rebuilds + 1)
          << "the neighbour lists should be rebuilt after the checkpoint too";
      expect_same_checkpoint_state(straight, resumed);
      expect_same_checkpoint_state(straight, resumed_serial);
      std::filesystem::remove_all(dir);
    }
  }
}

// A checkpoint builds each contact term's springs part by part as it writes them
// (RestartState::TermSprings::part). In parts of 3 rows, in one part, and from the springs held
// whole (Simulation::owned_springs(), written as one store, the path of a checkpoint read
// back), the file must hold the same springs datasets, byte for byte, each passing its checksum.
TEST(Checkpoint, SpringsWrittenInPartsAreTheDatasetsOfTheWholeStore) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "spring_parts");
    const CaseConfig c = testing::ring_patch_hit_by_sphere(-0.005, 60.0, 0.5);
    Simulation sim(build_model(c, comm), comm, settings_from_case(c));
    sim.run_steps(1000);
    const DriverState driver;
    RestartState whole = sim.restart_state(), one_part = sim.restart_state(),
                 small_parts = sim.restart_state();
    const auto owned = sim.owned_springs();
    ASSERT_EQ(whole.springs.size(), owned.size());
    std::int64_t rows = 0, sources = 0;
    for (std::size_t t = 0; t < owned.size(); ++t) {
      whole.springs[t].part = nullptr;  // written as a whole store
      whole.springs[t].store = owned[t].store;
      small_parts.springs[t].rows_per_part = 3;
      rows += static_cast<std::int64_t>(owned[t].store.size());
      sources += static_cast<std::int64_t>(small_parts.springs[t].sources);
    }
    EXPECT_GT(comm.sum(rows), 10) << "the case should carry tangential springs";
    EXPECT_LT(comm.max(sources), static_cast<std::int64_t>(RestartState::kSpringRowsPerPart))
        << "one part by default";
    const auto write = [&](const RestartState& state, const std::string& name) {
      return CheckpointStore(dir + "/" + name).write(comm, sim.model(), state, driver, 0, c);
    };
    const std::string whole_path = write(whole, "whole"), one_path = write(one_part, "one"),
                      parts_path = write(small_parts, "parts");
    if (comm.is_root()) {
      EXPECT_GE(expect_same_datasets(whole_path, parts_path, {"/history"}), 6);
      EXPECT_GE(expect_same_datasets(whole_path, one_path, {"/history"}), 6);
      for (const std::string& path : {whole_path, one_path, parts_path})
        EXPECT_NO_THROW(verify_checkpoint(path)) << path;
      std::filesystem::remove_all(dir);
    }
  }
}

/// Runs `c` for 2 half-steps straight through, and for one half, a checkpoint, a restart on
/// this run's ranks and on one rank, and the other half: both restarts end as the run never
/// interrupted (particles, bonds, springs, bodies, the ledgers' energies, what crossed and the
/// momentum balance), the same bits. `crossing`: grains enter and leave on both sides of the
/// checkpoint.
void expect_restarts_bitwise(const CaseConfig& c, std::int64_t half, const std::string& name,
                             bool crossing) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, name);
    const SimulationSettings s = settings_from_case(c);
    DriverState driver;
    driver.set("marker", 42.0);
    std::string straight, middle, resumed;
    Energies straight_energies;
    Simulation::GrainFlux straight_out, straight_in;
    MomentumBalance straight_momentum;
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(2 * half);
      straight_energies = sim.energies();
      straight_momentum = sim.momentum_balance();
      straight_out = sim.outflow_totals();
      straight_in = sim.inflow_totals();
      EXPECT_GT(straight_energies.friction, 0.0) << "the case should slide in contacts";
      straight = CheckpointStore(dir + "/straight")
                     .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    std::int64_t gone_at_middle = 0, in_at_middle = 0;
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(half);
      gone_at_middle = sim.outflow_totals().grains;
      in_at_middle = sim.inflow_totals().grains;
      middle = CheckpointStore(dir + "/middle")
                   .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    if (crossing) {
      EXPECT_GT(gone_at_middle, 0);
      EXPECT_GT(straight_out.grains, gone_at_middle) << "grains should leave after the restart";
      EXPECT_GT(straight_in.grains, in_at_middle) << "a batch should enter after the restart too";
    }
    const auto check = [&](Simulation& sim) {
      sim.run_steps(half);
      const Energies e = sim.energies();
      EXPECT_EQ(e.outflow, straight_energies.outflow);
      EXPECT_EQ(e.kinetic, straight_energies.kinetic);
      EXPECT_EQ(e.bond_elastic, straight_energies.bond_elastic);
      EXPECT_EQ(e.contact_elastic, straight_energies.contact_elastic);
      EXPECT_EQ(e.friction, straight_energies.friction);
      EXPECT_EQ(e.contact_damping, straight_energies.contact_damping);
      EXPECT_EQ(e.boundary_work, straight_energies.boundary_work);
      const Simulation::GrainFlux out = sim.outflow_totals();
      EXPECT_EQ(out.grains, straight_out.grains);
      EXPECT_EQ(out.mass, straight_out.mass);
      EXPECT_EQ(out.momentum, straight_out.momentum);
      const Simulation::GrainFlux in = sim.inflow_totals();
      EXPECT_EQ(in.grains, straight_in.grains);
      EXPECT_EQ(in.mass, straight_in.mass);
      EXPECT_EQ(e.inflow, straight_energies.inflow);
      // The momentum ledger goes on from its checkpointed totals and booked half kick.
      const MomentumBalance m = sim.momentum_balance();
      EXPECT_EQ(m.initial, straight_momentum.initial);
      EXPECT_EQ(m.impulse(), straight_momentum.impulse());
      EXPECT_EQ(m.exchange, straight_momentum.exchange);
      EXPECT_EQ(m.residual(), straight_momentum.residual());
    };
    {
      auto sim = restart(c, middle, comm);
      check(*sim);
      resumed = CheckpointStore(dir + "/resumed")
                    .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    std::string resumed_serial;
    if (comm.is_root()) {
      const Communicator self = Communicator::self();
      auto sim = restart(c, middle, self);
      check(*sim);
      resumed_serial = CheckpointStore(dir + "/serial")
                           .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    comm.barrier();
    if (comm.is_root()) {
      expect_same_checkpoint_state(straight, resumed);
      expect_same_checkpoint_state(straight, resumed_serial);
      std::filesystem::remove_all(dir);
    }
  }
}

// Grains entering and leaving: a checkpoint in the middle of the flow restarts on this run's
// ranks and on one rank and ends as the run never interrupted, with the same totals of what
// crossed (rank 0 holds them after a restart), the same batches and the same ledger. The
// grains are re-sorted by space every 700 steps, at the start and at the restart's first step,
// which must re-sort as the run never interrupted does: the bins are compared with the rest of
// the particles' state (a restart between re-sorts: tests/scripts/debris_ranks_restart.sh).
TEST(Checkpoint, InflowAndOutflowRestartBitwiseOnAnyRankCount) {
  CaseConfig c = testing::grains_entering_and_leaving();
  c.simulation.sort_every = 700;
  expect_restarts_bitwise(c, 700, "outflow", /*crossing=*/true);
}

// Multi-rate stepping (simulation.substeps): a checkpoint between two grain steps, at 0.048 s,
// after the falling net has caught on its shackles (fast loads on held particles, in the fast
// momentum ledger) and grains on it and on each other, holds the slow loads of the last grain
// step and the fast rate's ledgers; the restart goes on as the run never interrupted. (Seen
// failing without each of the three.)
TEST(Checkpoint, SubsteppedRunRestartsBitwiseOnAnyRankCount) {
  const CaseConfig c =
      load_case_from_string(testing::three_layers_landing_on_a_net(4), "substepped.yaml");
  expect_restarts_bitwise(c, 6000, "substepped", /*crossing=*/false);
}

// A restart between two neighbour-list rebuilds keeps the reference positions of the last one
// (the skin criterion measures moves from there): the next rebuild comes at the same step as
// in the run never interrupted, and the restart itself is no rebuild of the trajectory. The
// slow net of the SIGUSR1 test rebuilds every few hundred steps; the checkpoint is taken
// half-way between the first two rebuilds after the start, and both runs end just after the
// second (issue 15 item 9: a restart used to rebuild at once and count one rebuild less).
TEST(Checkpoint, RestartKeepsTheNeighbourRebuildSteps) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "rebuilds");
    const CaseConfig c =
        load_case(std::string(RINGDEM_SOURCE_DIR) + "/tests/data/restart_net.yaml");
    const SimulationSettings s = settings_from_case(c);
    DriverState driver;
    driver.set("marker", 42.0);
    std::vector<std::int64_t> rebuild_steps;
    std::int64_t end = 0;
    std::string straight, middle, resumed;
    {
      Simulation sim(build_model(c, comm), comm, s);
      while (rebuild_steps.size() < 2 && sim.steps() < 20000) {
        const std::int64_t before = sim.rebuilds();
        sim.step();
        if (sim.rebuilds() > before) rebuild_steps.push_back(sim.steps());
      }
      ASSERT_EQ(rebuild_steps.size(), 2u) << "the net should rebuild twice in 20000 steps";
      end = rebuild_steps[1] + 10;
      sim.run_steps(end - sim.steps());
      straight = CheckpointStore(dir + "/straight")
                     .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    const std::int64_t half_way = (rebuild_steps[0] + rebuild_steps[1]) / 2;
    ASSERT_GT(rebuild_steps[1] - rebuild_steps[0], 20) << "rebuilds too close together";
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(half_way);
      middle = CheckpointStore(dir + "/middle")
                   .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    const auto resume = [&](const Communicator& on, const std::string& to) {
      auto sim = restart(c, middle, on);
      sim->run_steps(end - half_way);
      return CheckpointStore(dir + to).write(sim->comm(), sim->model(), sim->restart_state(),
                                             driver, 0, c);
    };
    resumed = resume(comm, "/resumed");
    std::string resumed_serial;
    if (comm.is_root()) resumed_serial = resume(Communicator::self(), "/serial");
    comm.barrier();
    if (comm.is_root()) {
      EXPECT_EQ(read_checkpoint_info(straight).rebuilds, read_checkpoint_info(middle).rebuilds + 1);
      expect_same_checkpoint_state(straight, resumed);
      expect_same_checkpoint_state(straight, resumed_serial);
      std::filesystem::remove_all(dir);
    }
  }
}

// A rebuild asked for but not yet done when the checkpoint is written (a driver placed a
// body: Simulation::place_body; here the fixed floor, where it was) still happens at the next
// step after the restart, and is counted once: the same rebuild count and state as the run
// never interrupted. The slow net would not rebuild at that step by itself (checked).
TEST(Checkpoint, PendingRebuildSurvivesRestart) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "pending");
    const CaseConfig c =
        load_case(std::string(RINGDEM_SOURCE_DIR) + "/tests/data/restart_net.yaml");
    const SimulationSettings s = settings_from_case(c);
    constexpr std::int64_t kHalf = 60;
    DriverState driver;
    driver.set("marker", 42.0);
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(kHalf);
      const std::int64_t before = sim.rebuilds();
      sim.step();
      ASSERT_EQ(sim.rebuilds(), before) << "the test needs a step without a rebuild of its own";
    }
    const auto place = [](Simulation& sim) {
      const RigidBody& b = sim.model().bodies.at(0);
      sim.place_body(0, b.position, b.velocity, b.motion);
    };
    std::string straight, middle, resumed;
    std::int64_t rebuilds_before = 0, rebuilds_after = 0;
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(kHalf);
      place(sim);
      rebuilds_before = sim.rebuilds();
      sim.step();
      rebuilds_after = sim.rebuilds();
      sim.run_steps(kHalf - 1);
      straight = CheckpointStore(dir + "/straight")
                     .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    EXPECT_EQ(rebuilds_after, rebuilds_before + 1) << "place_body forces a rebuild";
    {
      Simulation sim(build_model(c, comm), comm, s);
      sim.run_steps(kHalf);
      place(sim);
      middle = CheckpointStore(dir + "/middle")
                   .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    {
      auto sim = restart(c, middle, comm);
      EXPECT_EQ(sim->rebuilds(), rebuilds_before);
      sim->step();
      EXPECT_EQ(sim->rebuilds(), rebuilds_after) << "the pending rebuild, once";
      sim->run_steps(kHalf - 1);
      resumed = CheckpointStore(dir + "/resumed")
                    .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    comm.barrier();
    if (comm.is_root()) {
      expect_same_checkpoint_state(straight, resumed);
      std::filesystem::remove_all(dir);
    }
  }
}

// A bond that broke in the last force evaluation before the checkpoint forces a rebuild at
// the first step after the restart, as it would have in the run never interrupted, and the
// step reports the break (Simulation::bonds_broke_anywhere, which the tensile driver reads).
// A 4-pin tensile ring with bonds a thousand times too weak breaks within a few hundred steps.
TEST(Checkpoint, BondBrokenBeforeTheCheckpointRebuildsAfterTheRestart) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "broke");
    const CaseConfig c =
        load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_reference.yaml",
                  {"scenario.tensile_test.loading_rate=0.5", "bonds[0].tensile_strength=1e7",
                   "bonds[0].shear_strength=1e7"});
    const SimulationSettings s = settings_from_case(c);
    DriverState driver;
    driver.set("marker", 42.0);
    std::int64_t seen = 0, rebuilds_seen = 0;  // the step that reports the first break
    std::string straight, middle, resumed;
    {
      Simulation sim(build_scenario_model(c, comm), comm, s);
      while (!sim.bonds_broke_anywhere() && sim.steps() < 20000)
        sim.step();
      ASSERT_TRUE(sim.bonds_broke_anywhere()) << "no bond broke in 20000 steps";
      seen = sim.steps();
      rebuilds_seen = sim.rebuilds();
      sim.run_steps(20);
      straight = CheckpointStore(dir + "/straight")
                     .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    ASSERT_GT(seen, 10);
    std::int64_t rebuilds_middle = 0;
    {
      Simulation sim(build_scenario_model(c, comm), comm, s);
      sim.run_steps(seen - 1);  // the break happened in this last step's force evaluation
      rebuilds_middle = sim.rebuilds();
      middle = CheckpointStore(dir + "/middle")
                   .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    EXPECT_EQ(rebuilds_seen, rebuilds_middle + 1) << "the break should force a rebuild";
    {
      auto sim = restart(c, middle, comm);
      sim->step();
      EXPECT_TRUE(sim->bonds_broke_anywhere());
      EXPECT_EQ(sim->rebuilds(), rebuilds_seen);
      sim->run_steps(20);
      resumed = CheckpointStore(dir + "/resumed")
                    .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    comm.barrier();
    if (comm.is_root()) {
      expect_same_checkpoint_state(straight, resumed);
      std::filesystem::remove_all(dir);
    }
  }
}

// The elastoplastic bond (model timoshenko_plastic) checkpointed while its bonds yield: the
// plastic state columns (deformations, strain, work) are in the checkpoint and a restart on
// this rank count and on one rank continues bit for bit (checkpoint datasets compared byte for
// byte, the bond columns included). The 4-pin tensile ring with a weak wire (f_y = 15 MPa)
// yields from the first millimetre; the ring is cut between ranks.
TEST(Checkpoint, PlasticBondStateRestartsBitwiseMidYield) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "plastic");
    const CaseConfig c =
        load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_plastic.yaml",
                  {"scenario.tensile_test.loading_rate=0.5", "bonds[0].plastic.yield_stress=15e6"});
    const SimulationSettings s = settings_from_case(c);
    constexpr std::int64_t kHalf = 8000;
    DriverState driver;
    driver.set("marker", 42.0);
    std::string straight, middle, resumed;
    double work_middle = 0.0, work_end = 0.0;
    {
      Simulation sim(build_scenario_model(c, comm), comm, s);
      sim.run_steps(2 * kHalf);
      work_end = sim.energies().plastic_work;
      straight = CheckpointStore(dir + "/straight")
                     .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    {
      Simulation sim(build_scenario_model(c, comm), comm, s);
      sim.run_steps(kHalf);
      work_middle = sim.energies().plastic_work;
      middle = CheckpointStore(dir + "/middle")
                   .write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    EXPECT_GT(work_middle, 0.0) << "bonds should yield before the checkpoint";
    EXPECT_GT(work_end, 1.5 * work_middle) << "and go on yielding after it";
    {
      auto sim = restart(c, middle, comm);
      EXPECT_EQ(sim->energies().plastic_work, work_middle);
      sim->run_steps(kHalf);
      EXPECT_EQ(sim->energies().plastic_work, work_end);
      resumed = CheckpointStore(dir + "/resumed")
                    .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    std::string resumed_serial;
    if (comm.is_root()) {
      const Communicator self = Communicator::self();
      auto sim = restart(c, middle, self);
      sim->run_steps(kHalf);
      EXPECT_EQ(sim->energies().plastic_work, work_end);
      resumed_serial = CheckpointStore(dir + "/serial")
                           .write(sim->comm(), sim->model(), sim->restart_state(), driver, 0, c);
    }
    comm.barrier();
    if (comm.is_root()) {
      const Hdf5File f = Hdf5File::open_read(middle);
      const auto names = f.list("/bonds");
      for (const char* column : {"plastic_elongation", "plastic_strain", "plastic_work"})
        EXPECT_NE(std::find(names.begin(), names.end(), column), names.end())
            << column << " should be in the checkpoint";
      expect_same_checkpoint_state(straight, resumed);
      expect_same_checkpoint_state(straight, resumed_serial);
      std::filesystem::remove_all(dir);
    }
  }
}

}  // namespace
}  // namespace ringdem
