// Start-up without a rank holding the whole model: each rank builds a slice of every source,
// the first distribution hands the particles to the owners of their blocks, and no rank's
// store ever holds much more than N / ranks (plus its ghost layer).
#include <gtest/gtest.h>
#include <mpi.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/Checkpoint.hpp"

namespace ringdem {
namespace {

/// One lattice source of jittered 5 mm spheres, 10.5 mm apart.
struct Bed {
  std::array<int, 3> count;
  Vec3 origin;
  std::uint64_t seed;
};

CaseConfig lattice_beds(const std::vector<Bed>& beds) {
  CaseConfig c = testing::base_case();
  c.simulation.dt = 1e-6;
  for (const Bed& bed : beds) {
    LatticeConfig lattice;
    lattice.origin = bed.origin;
    lattice.count = bed.count;
    lattice.spacing = 0.0105;
    lattice.particle_radius = 0.005;
    lattice.jitter = 0.3;
    lattice.seed = bed.seed;
    c.lattices.push_back(lattice);
  }
  return c;
}

/// A bed of 24 x 24 x 8 jittered spheres and a second bed of 16 x 16 x 4 above it (two
/// sources). Free grains only: METIS balances block weights (particles plus bonds), which for
/// grains alone is the particle count.
CaseConfig bed_and_net() {
  return lattice_beds({{{24, 24, 8}, {0, 0, 0}, 1}, {{16, 16, 4}, {0.02, 0.02, 0.1}, 7}});
}

TEST(StartUp, LargestPerRankStoreIsAboutNOverRanks) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const CaseConfig c = bed_and_net();
    Model model = build_model(c, comm);
    const std::int64_t n = model.initial_particles;
    const double share = static_cast<double>(n) / comm.size();
    // The slices: one per source, each split evenly.
    const auto built = static_cast<std::int64_t>(model.particles.n_local());
    EXPECT_EQ(comm.sum(built), n);
    EXPECT_LE(static_cast<double>(comm.max(built)), share + 2.0);
    Simulation sim(std::move(model), comm, settings_from_case(c));
    const ParticleStore& p = sim.model().particles;
    const auto owned = static_cast<std::int64_t>(p.n_local());
    const auto held = static_cast<std::int64_t>(p.n_total());
    // Collectives first: a failure message must not call one on a single rank.
    const std::int64_t total = comm.sum(owned);
    const std::int64_t most_owned = comm.max(owned);
    const std::int64_t most_held = comm.max(held);
    if (comm.is_root())
      std::printf("[ startup  ] %d ranks: N = %lld, largest owned %lld, largest store %lld\n",
                  comm.size(), static_cast<long long>(n), static_cast<long long>(most_owned),
                  static_cast<long long>(most_held));
    EXPECT_EQ(total, n);
    // Owned: METIS balances the block weights within a few per cent (blocks are indivisible).
    EXPECT_LE(static_cast<double>(most_owned), 1.15 * share);
    // Owned plus ghosts: one block-wide layer along the cuts, far below N for more ranks.
    EXPECT_LE(static_cast<double>(most_held), comm.size() == 1 ? n : 1.6 * share);
  }
}

/// A bed 8 times longer than wide (96 x 12 x 6 spheres): the partition cuts it across, each
/// rank's ghost layer is a few per cent of what it owns, as in a large run.
CaseConfig long_bed() {
  return lattice_beds({{{96, 12, 6}, {0, 0, 0}, 1}});
}

/// Starts a simulation from `model` and checks that its first distribution stayed in the
/// store's reservation: no rank holds more, no column moved (collective).
void expect_distribution_in_reservation(Model model, const Communicator& comm, const CaseConfig& c,
                                        const RestartState* state) {
  const std::size_t reserved = model.particles.position.capacity();
  const Vec3* column = model.particles.position.data();
  const Simulation sim = state != nullptr
                             ? Simulation(std::move(model), comm, settings_from_case(c), *state)
                             : Simulation(std::move(model), comm, settings_from_case(c));
  const ParticleStore& p = sim.model().particles;
  const auto held = static_cast<std::int64_t>(p.n_total());
  const std::int64_t over = comm.max(held - static_cast<std::int64_t>(reserved));
  const std::int64_t moved =
      comm.sum(std::int64_t{p.position.data() != column || p.position.capacity() != reserved ||
                            p.gid.capacity() != reserved});
  EXPECT_LE(over, 0) << "a rank holds more than its reservation";
  EXPECT_EQ(moved, 0) << "a rank's columns were reallocated by the first distribution";
}

// The store is reserved once, before the first particle, with room for what the first
// distribution leaves (the partition's share and the ghost layer): its columns are never
// reallocated there, so the heap keeps no outgrown copies of them (ParticleStore::reserve_share).
TEST(StartUp, FirstDistributionStaysInTheStoresReservation) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const CaseConfig c = long_bed();
    expect_distribution_in_reservation(build_model(c, comm), comm, c, nullptr);
  }
}

// A restart reads a block of the checkpoint's rows on each rank and distributes them as a start
// does: the same room.
TEST(StartUp, RestartedDistributionStaysInTheStoresReservation) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const CaseConfig c = long_bed();
    const std::string dir = testing::shared_temp_dir(comm, "startup_restart");
    DriverState driver;
    std::string path;
    {
      Simulation sim(build_model(c, comm), comm, settings_from_case(c));
      sim.run_steps(3);
      path = CheckpointStore(dir).write(sim.comm(), sim.model(), sim.restart_state(), driver, 0, c);
    }
    Model model = build_model_without_particles(c);
    const RestartState state = read_checkpoint(comm, path, c, model, driver);
    expect_distribution_in_reservation(std::move(model), comm, c, &state);
  }
}

}  // namespace
}  // namespace ringdem
