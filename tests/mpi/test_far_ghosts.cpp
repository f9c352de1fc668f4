// Far ghosts (comm/FarGhosts): particles that a term couples beyond the blocks' width reach
// every rank that needs them, checked against the brute-force neighbourhoods of the whole
// model and with rank-encoded values; the other particles keep the one-block layer.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "SharedTempDir.hpp"
#include "comm/DomainDecomposition.hpp"
#include "domain/PairStore.hpp"

namespace ringdem {
namespace {

constexpr double kFarBlock = 0.01;
constexpr double kFarReach = 0.045;  // 4.5 blocks: zones of 5
constexpr double kPartnerRadius = 0.002;

/// A 24 x 24 x 2 lattice, 6 mm apart, of grains with radii 1.5 mm (every third: too small to
/// be a partner) and 2 mm, and a ring of 16 anchors (body 0) of 30 mm radius at its centre,
/// standing in the x-z plane. Rank `rank` of `ranks` holds the particles with gid = rank mod
/// ranks.
void make_far_model(ParticleStore& p, int rank = 0, int ranks = 1) {
  std::int64_t gid = 0;
  const auto add = [&](const Vec3& x, double radius, std::int32_t body) {
    ParticleStore::NewParticle np;
    np.gid = gid++;
    if (np.gid % ranks != rank) return;
    np.position = x;
    np.radius = radius;
    np.density = 1000;
    np.body = body;
    p.add(np);
  };
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i)
        add({0.006 * i, 0.006 * j, 0.006 * k}, (i + j + k) % 3 == 0 ? 0.0015 : kPartnerRadius, -1);
  for (int b = 0; b < 16; ++b) {
    const double angle = 2.0 * M_PI * b / 16.0;
    add({0.069 + 0.03 * std::cos(angle), 0.0705, 0.006 + 0.03 * std::sin(angle)}, 0.002, 0);
  }
  p.rebuild_index();
}

FarGhostRule ring_rule() {
  FarGhostRule rule;
  rule.reach = kFarReach;
  rule.anchor = [](const ParticleStore& q, std::size_t k) { return q.body[k] == 0; };
  rule.partner = [](const ParticleStore& q, std::size_t k) {
    return q.body[k] < 0 && q.radius[k] >= kPartnerRadius;
  };
  return rule;
}

/// On this rank: every anchor within the reach of an owned anchor or partner is here, and
/// every partner within the reach of an owned anchor (the brute-force neighbourhoods of the
/// whole model, shifted by `shift`); every particle within one block of an owned one is here;
/// and, with cells of one block (`one_block_cells`), a ghost beyond the one-block layer is an
/// anchor or a partner (with larger cells, a cell's blocks without owned particles get their
/// own layers). Returns the ghosts held.
std::size_t expect_far_neighbourhoods(const ParticleStore& p, const Vec3& shift,
                                      bool one_block_cells = true) {
  ParticleStore all;
  make_far_model(all);
  const FarGhostRule rule = ring_rule();
  std::set<std::int64_t> here(p.gid.begin(), p.gid.end());
  for (std::size_t a = 0; a < p.n_local(); ++a) {
    const bool anchor = p.body[a] == 0;
    const bool partner = rule.partner(p, a);
    for (std::size_t b = 0; b < all.n_local(); ++b) {
      const double distance = norm(all.position[b] + shift - p.position[a]);
      const bool needed = distance < kFarBlock ||
                          (distance < kFarReach && ((anchor || partner) && all.body[b] == 0)) ||
                          (distance < kFarReach && anchor && rule.partner(all, b));
      if (needed) {
        EXPECT_TRUE(here.count(all.gid[b])) << "gid " << all.gid[b] << " (" << distance
                                            << " m) missing beside owned gid " << p.gid[a];
      }
    }
  }
  const auto index = [](double x) { return static_cast<long>(std::floor(x / kFarBlock)); };
  for (std::size_t g = p.n_local(); g < p.n_total() && one_block_cells; ++g) {
    if (p.body[g] == 0 || rule.partner(p, g)) continue;
    bool next_to_owned = false;
    for (std::size_t a = 0; a < p.n_local() && !next_to_owned; ++a)
      next_to_owned = std::abs(index(p.position[g].x) - index(p.position[a].x)) <= 1 &&
                      std::abs(index(p.position[g].y) - index(p.position[a].y)) <= 1 &&
                      std::abs(index(p.position[g].z) - index(p.position[a].z)) <= 1;
    EXPECT_TRUE(next_to_owned) << "ghost " << p.gid[g]
                               << " couples with no far particle and lies beyond one block";
  }
  return p.n_ghost();
}

class FarGhostLayer : public ::testing::Test {
 protected:
  testing::WorldCopy world_;
  MPI_Comm comm_ = world_.raw();
};

TEST_F(FarGhostLayer, ReachesEveryRankThatCouplesAndNoOtherGhostIsFar) {
  const Communicator c(comm_);
  ParticleStore p;
  make_far_model(p, c.rank(), c.size());
  DomainDecomposition d(c, kFarBlock, /*imbalance_threshold=*/0.0);
  d.add_far_ghosts(ring_rule());
  d.distribute_initial(p, {});
  ASSERT_EQ(d.cell_blocks(), 1);  // (a model this small: cells of one block)
  const std::size_t far_ghosts = expect_far_neighbourhoods(p, {});

  // The same after a migration that moves most particles to other blocks' owners.
  const Vec3 shift{3.5 * kFarBlock, 0.0, -0.25 * kFarBlock};
  for (std::size_t k = 0; k < p.n_total(); ++k)
    p.position[k] += shift;
  d.redistribute(p, {});
  expect_far_neighbourhoods(p, shift);

  // Rank-encoded refresh: every ghost, far ones too, reads its owner's rank + 1.
  std::map<std::int64_t, int> owner;
  {
    std::vector<std::int64_t> gids(p.gid.begin(), p.gid.begin() + static_cast<long>(p.n_local()));
    std::vector<std::int64_t> ranks(p.n_local(), c.rank());
    const auto all_gids = c.allgather(gids);
    const auto all_ranks = c.allgather(ranks);
    for (std::size_t k = 0; k < all_gids.size(); ++k)
      owner[all_gids[k]] = static_cast<int>(all_ranks[k]);
  }
  for (std::size_t k = 0; k < p.n_local(); ++k)
    p.velocity[k] = {c.rank() + 1.0, static_cast<double>(p.gid[k]), 0.0};
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k)
    p.velocity[k] = {-1, -1, -1};
  d.update_ghosts(p);
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k)
    EXPECT_EQ(p.velocity[k], (Vec3{owner.at(p.gid[k]) + 1.0, static_cast<double>(p.gid[k]), 0.0}))
        << "ghost gid " << p.gid[k];

  // Blocks as wide as the reach (a ghost width of the reach) hold more ghosts in all.
  if (c.size() > 1) {
    ParticleStore q;
    make_far_model(q, c.rank(), c.size());
    DomainDecomposition wide(c, kFarReach, 0.0);
    wide.distribute_initial(q, {});
    const std::int64_t far_total = c.sum(static_cast<std::int64_t>(far_ghosts));
    const std::int64_t wide_total = c.sum(static_cast<std::int64_t>(q.n_ghost()));
    EXPECT_LT(far_total, wide_total);
  }
}

TEST_F(FarGhostLayer, CellsOfSeveralBlocksReachTheSameNeighbourhoods) {
  const Communicator c(comm_);
  ParticleStore p;
  make_far_model(p, c.rank(), c.size());
  DomainDecomposition d(c, kFarBlock, 0.0, /*cell_blocks=*/3);
  d.add_far_ghosts(ring_rule());
  d.distribute_initial(p, {});
  EXPECT_EQ(d.cell_blocks(), 3);
  expect_far_neighbourhoods(p, {}, /*one_block_cells=*/false);
}

// A model held in one block: one rank owns every particle, the others none. The far ghosts'
// index is collective, so a rank that owns nothing still takes part (it had skipped it and
// left the others waiting in their gather).
TEST_F(FarGhostLayer, ARankThatOwnsNothingStillTakesPart) {
  const Communicator c(comm_);
  ParticleStore p;
  if (c.rank() == 0)
    for (int i = 0; i < 4; ++i) {
      ParticleStore::NewParticle np;
      np.gid = i;
      np.position = {0.001 + 0.002 * i, 0.005, 0.005};
      np.radius = kPartnerRadius;
      np.density = 1000;
      np.body = i == 0 ? 0 : -1;  // one anchor, three partners
      p.add(np);
    }
  p.rebuild_index();
  DomainDecomposition d(c, kFarBlock, 0.0);
  d.add_far_ghosts(ring_rule());
  d.distribute_initial(p, {});
  d.redistribute(p, {});
  EXPECT_EQ(c.sum(static_cast<std::int64_t>(p.n_local())), 4);
  EXPECT_EQ(p.n_ghost(), 0u);  // nobody else owns anything near
}

}  // namespace
}  // namespace ringdem
