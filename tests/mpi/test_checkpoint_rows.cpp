// Checkpoint rows with sparse gids and bond ids: written by every rank in gid order, read back
// collectively in blocks by any rank count, each row exactly once with its values.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <filesystem>
#include <map>

#include "SharedTempDir.hpp"
#include "engine/Model.hpp"
#include "io/Checkpoint.hpp"

namespace ringdem {
namespace {

constexpr std::int64_t kParticles = 50;

/// Particle i has gid 7 i + 3 (sparse), held by rank i mod P; bond i joins particles i and
/// i + 1 with id 100 + 3 i, held by the holder of its end a.
Model sparse_model(int rank, int ranks) {
  Model m;
  for (std::int64_t i = 0; i < kParticles; ++i) {
    if (i % ranks != rank) continue;
    ParticleStore::NewParticle np;
    np.gid = 7 * i + 3;
    np.position = {0.01 * static_cast<double>(i), 0.5, -1.0};
    np.radius = 0.002 + 1e-5 * static_cast<double>(i);
    np.density = 1000;
    m.particles.add(np);
    if (i + 1 < kParticles) {
      const std::size_t b = m.bonds.append(100 + 3 * i, 7 * i + 3, 7 * (i + 1) + 3, 0);
      m.bonds.length0[b] = 0.25 * static_cast<double>(i);
    }
  }
  m.particles.rebuild_index();
  return m;
}

TEST(CheckpointRows, SparseGidsRoundTripOnAnyRankCount) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "rows");
    Model written = sparse_model(comm.rank(), comm.size());
    RestartState state;
    state.dt = 1e-6;
    const std::string path =
        CheckpointStore(dir).write(comm, written, state, DriverState{}, 0, CaseConfig{});
    // Read back by every rank count up to this one (sub-communicators of the first k ranks).
    for (int k = 1; k <= comm.size(); ++k) {
      MPI_Comm sub;
      MPI_Comm_split(world, comm.rank() < k ? 0 : MPI_UNDEFINED, comm.rank(), &sub);
      if (sub == MPI_COMM_NULL) continue;
      {
        const Communicator reader(sub);
        Model read;  // its sources create no particles: the checkpoint's counts are the truth
        DriverState driver;
        read_checkpoint(reader, path, CaseConfig{}, read, driver);
        const ParticleStore& p = read.particles;
        std::vector<std::int64_t> gids(p.gid.begin(),
                                       p.gid.begin() + static_cast<long>(p.n_local()));
        std::vector<double> radii(p.radius.begin(),
                                  p.radius.begin() + static_cast<long>(p.n_local()));
        const auto all_gids = reader.allgather(gids);
        const auto all_radii = reader.allgather(radii);
        ASSERT_EQ(static_cast<std::int64_t>(all_gids.size()), kParticles) << k << " readers";
        for (std::size_t r = 0; r < all_gids.size(); ++r) {
          // Rows in gid order across the blocks, each with its own value.
          EXPECT_EQ(all_gids[r], 7 * static_cast<std::int64_t>(r) + 3);
          EXPECT_EQ(all_radii[r], 0.002 + 1e-5 * static_cast<double>(r));
        }
        std::vector<std::int64_t> ids(read.bonds.id);
        std::vector<double> lengths(read.bonds.length0);
        const auto all_ids = reader.allgather(ids);
        const auto all_lengths = reader.allgather(lengths);
        ASSERT_EQ(static_cast<std::int64_t>(all_ids.size()), kParticles - 1);
        for (std::size_t r = 0; r < all_ids.size(); ++r) {
          EXPECT_EQ(all_ids[r], 100 + 3 * static_cast<std::int64_t>(r));
          EXPECT_EQ(all_lengths[r], 0.25 * static_cast<double>(r));
        }
      }
      MPI_Comm_free(&sub);
    }
    comm.barrier();
    if (comm.is_root()) std::filesystem::remove_all(dir);
  }
}

}  // namespace
}  // namespace ringdem
