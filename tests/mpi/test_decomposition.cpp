// Migration and ghost exchange of the domain decomposition, checked with rank-encoded data
// (value = rank + 1) and gid-encoded data, exactly.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "SharedTempDir.hpp"
#include "comm/DomainDecomposition.hpp"
#include "domain/PairStore.hpp"
#include "engine/TimoshenkoBondTerm.hpp"

namespace ringdem {
namespace {

constexpr double kBlock = 0.01;

class Decomposition : public ::testing::Test {
 protected:
  testing::WorldCopy world_;
  MPI_Comm comm_ = world_.raw();
};

/// A 12 x 12 x 2 lattice of particles, 6 mm apart (several per block); consecutive gids along
/// x are bonded. Field values encode the gid. Rank `rank` of `ranks` holds the particles with
/// gid = rank mod ranks and the bonds with id = rank mod ranks: a spread unlike the blocks',
/// in which a rank may hold a bond but neither of its particles, as after reading a checkpoint.
void make_lattice(ParticleStore& p, BondStore& bonds, int rank = 0, int ranks = 1) {
  // A bond model's own state column travels like the common ones.
  bonds.declare_model_columns({{"model_state", field_flag::kMigrate | field_flag::kCheckpoint}});
  std::int64_t gid = 0;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 12; ++i) {
        ParticleStore::NewParticle np;
        np.gid = gid++;
        if (np.gid % ranks != rank) continue;
        np.position = {0.006 * i, 0.006 * j, 0.006 * k};
        np.radius = 0.002;
        np.density = 1000;
        p.add(np);
      }
  for (std::size_t k = 0; k < p.n_local(); ++k)
    p.torque[k] = {7.0 * p.gid[k] + 1, 0, 0};
  BondTimoshenko::Section s;
  BondTimoshenko::Reference ref;
  std::int64_t id = 0;
  for (std::int64_t g = 0; g + 1 < gid; ++g)
    if ((g + 1) % 12 != 0) {
      if (id % ranks == rank) {
        const std::size_t b = bonds.append(id, g, g + 1, 0);
        TimoshenkoBondTerm::store(bonds, b, s, ref, {1, 1, 1});
        bonds.model_column(0)[b] = 0.5 * static_cast<double>(id);
      }
      ++id;
    }
  p.rebuild_index();
}

/// gid -> owning rank over all ranks; fails if a gid is owned twice or not at all.
std::map<std::int64_t, int> owners(const Communicator& c, const ParticleStore& p,
                                   std::int64_t n_total) {
  std::vector<std::int64_t> mine(p.gid.begin(), p.gid.begin() + static_cast<long>(p.n_local()));
  std::vector<std::int64_t> rank_of_mine(p.n_local(), c.rank());
  const auto gids = c.allgather(mine);
  const auto ranks = c.allgather(rank_of_mine);
  std::map<std::int64_t, int> out;
  for (std::size_t k = 0; k < gids.size(); ++k) {
    EXPECT_TRUE(out.emplace(gids[k], static_cast<int>(ranks[k])).second)
        << "gid " << gids[k] << " owned twice";
  }
  EXPECT_EQ(static_cast<std::int64_t>(out.size()), n_total);
  return out;
}

/// Every particle within one block of an owned particle is here (the brute-force neighbourhood
/// of the whole lattice), and every ghost lies in a block next to a block of an owned particle:
/// the ghost layer is one block thick, whatever the partition cells are.
void expect_one_block_ghost_layer(const ParticleStore& p, const Vec3& shift) {
  ParticleStore all;
  BondStore unused;
  make_lattice(all, unused);
  std::set<std::int64_t> here(p.gid.begin(), p.gid.end());
  for (std::size_t a = 0; a < p.n_local(); ++a)
    for (std::size_t b = 0; b < all.n_local(); ++b)
      if (norm(all.position[b] + shift - p.position[a]) < kBlock) {
        EXPECT_TRUE(here.count(all.gid[b])) << "neighbour " << all.gid[b] << " of " << p.gid[a];
      }
  const auto index = [](double x) { return static_cast<long>(std::floor(x / kBlock)); };
  for (std::size_t g = p.n_local(); g < p.n_total(); ++g) {
    bool next_to_owned = false;
    for (std::size_t a = 0; a < p.n_local() && !next_to_owned; ++a)
      next_to_owned = std::abs(index(p.position[g].x) - index(p.position[a].x)) <= 1 &&
                      std::abs(index(p.position[g].y) - index(p.position[a].y)) <= 1 &&
                      std::abs(index(p.position[g].z) - index(p.position[a].z)) <= 1;
    EXPECT_TRUE(next_to_owned) << "ghost " << p.gid[g] << " is beyond the one-block layer";
  }
}

/// Owners write rank + 1 and their particles' gids into two of the fields refreshed each
/// step; the ghosts' are poisoned (-1).
void encode_owned_and_poison_ghosts(const Communicator& c, ParticleStore& p) {
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const auto gid = static_cast<double>(p.gid[k]);
    p.velocity[k] = {c.rank() + 1.0, gid, 0.5};
    p.omega[k] = {-gid, 2.0, c.rank() + 1.0};
  }
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k)
    p.velocity[k] = p.omega[k] = {-1, -1, -1};
}

/// Ghost k holds its owner's rank + 1 and its own gid in each field that
/// encode_owned_and_poison_ghosts() wrote, so that neither ghosts nor fields were mixed up on
/// the way.
void expect_encoded_ghost(const ParticleStore& p, std::size_t k,
                          const std::map<std::int64_t, int>& owner) {
  const auto gid = static_cast<double>(p.gid[k]);
  const double encoded = owner.at(p.gid[k]) + 1.0;
  EXPECT_EQ(p.velocity[k], (Vec3{encoded, gid, 0.5})) << "ghost gid " << p.gid[k];
  EXPECT_EQ(p.omega[k], (Vec3{-gid, 2.0, encoded})) << "ghost gid " << p.gid[k];
}

/// Rank-encoded refresh: every ghost reads its owner's encoded values after update_ghosts().
void expect_rank_encoded_refresh(const Communicator& c, ParticleStore& p, DomainDecomposition& d,
                                 const std::map<std::int64_t, int>& owner) {
  encode_owned_and_poison_ghosts(c, p);
  d.update_ghosts(p);
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k)
    expect_encoded_ghost(p, k, owner);
}

/// make_lattice() spread over the ranks and distributed by `d`: the owner of each gid.
std::map<std::int64_t, int> distribute_lattice(const Communicator& c, ParticleStore& p,
                                               BondStore& bonds, DomainDecomposition& d) {
  make_lattice(p, bonds, c.rank(), c.size());
  const std::int64_t n_total = c.sum(static_cast<std::int64_t>(p.n_local()));
  d.distribute_initial(p, {&bonds});
  return owners(c, p, n_total);
}

/// distribute_lattice()'s lattice with its decomposition, and each particle's owner.
struct DistributedLattice {
  ParticleStore p;
  BondStore bonds;
  DomainDecomposition d;
  std::map<std::int64_t, int> owner;
  explicit DistributedLattice(const Communicator& c) : d(c, kBlock, 0.1) {
    owner = distribute_lattice(c, p, bonds, d);
  }
};

/// The ghost subset of every third particle by gid, selected for this rank when it `reads`:
/// rank-encoded values written after the selection reach the selected ghosts of a rank that
/// reads, and every other ghost keeps its poison. Returns the ghosts refreshed here, which is
/// what the subset says it received; what the owners sent is what the others received.
std::int64_t refresh_every_third(const Communicator& c, ParticleStore& p, DomainDecomposition& d,
                                 const std::map<std::int64_t, int>& owner, bool reads) {
  std::vector<std::uint8_t> selected(p.n_local());
  for (std::size_t k = 0; k < p.n_local(); ++k)
    selected[k] = p.gid[k] % 3 == 0 ? 1 : 0;
  d.select_ghost_subset(p, selected, reads);
  encode_owned_and_poison_ghosts(c, p);
  d.update_ghost_subset(p);
  std::int64_t refreshed = 0;
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k) {
    if (reads && p.gid[k] % 3 == 0) {
      expect_encoded_ghost(p, k, owner);
      ++refreshed;
    } else {
      EXPECT_EQ(p.velocity[k], (Vec3{-1, -1, -1})) << "ghost gid " << p.gid[k];
      EXPECT_EQ(p.omega[k], (Vec3{-1, -1, -1})) << "ghost gid " << p.gid[k];
    }
  }
  EXPECT_EQ(static_cast<std::size_t>(refreshed), d.ghost_subset().n_received());
  EXPECT_EQ(c.sum(static_cast<std::int64_t>(d.ghost_subset().n_sent())), c.sum(refreshed));
  return refreshed;
}

// Multi-rate stepping refreshes some ghosts alone (GhostSubset): on more ranks than one, some.
// A new ghost layer forgets the selection.
TEST_F(Decomposition, AGhostSubsetRefreshesTheSelectedGhostsAlone) {
  const Communicator c(comm_);
  DistributedLattice l(c);
  const std::int64_t refreshed = refresh_every_third(c, l.p, l.d, l.owner, /*reads=*/true);
  if (c.size() > 1) {
    EXPECT_GT(c.sum(refreshed), 0);
  }
  l.d.redistribute(l.p, {&l.bonds});
  EXPECT_THROW(l.d.update_ghost_subset(l.p), std::logic_error);
}

// A rank that reads no ghost between two refreshes of the whole layer (multi-rate stepping:
// one without movers) is sent none: here the first rank says so, and it keeps every ghost
// poisoned while the others receive their selected ones, rank-encoded.
TEST_F(Decomposition, AGhostSubsetSkipsTheRanksThatReadNone) {
  const Communicator c(comm_);
  DistributedLattice l(c);
  const std::int64_t refreshed = refresh_every_third(c, l.p, l.d, l.owner, c.rank() != 0);
  if (c.size() > 1) {
    EXPECT_GT(c.sum(refreshed), 0);  // the other ranks' ghosts of the first rank's
    if (c.rank() == 0) {
      EXPECT_GT(l.p.n_ghost(), 0u);  // it has ghosts, and none was refreshed
      EXPECT_EQ(refreshed, 0);
    }
  }
}

/// The share of the bonds (counted by their first end's owner) that the rank holding the
/// most holds, after distributing make_lattice()'s bonded 12 x 12 x 2 lattice beside a block
/// of 3 200 unbonded particles (20 x 20 x 8, 6 mm apart, from x = 0.1 m on), with each bond
/// weighing `scale` times its store's weight.
double most_bonds_share(const Communicator& c, int scale) {
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds, c.rank(), c.size());
  std::int64_t gid = 288;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i, ++gid) {
        if (gid % c.size() != c.rank()) continue;
        ParticleStore::NewParticle np;
        np.gid = gid;
        np.position = {0.1 + 0.006 * i, 0.006 * j, 0.006 * k};
        np.radius = 0.002;
        np.density = 1000;
        p.add(np);
      }
  p.rebuild_index();
  DomainDecomposition d(c, kBlock, 0.1);
  d.set_row_weight_scale(scale);
  d.distribute_initial(p, {&bonds});
  // The first partition counts only the bonds held with their first end (the spread by gid
  // holds few so); the rebuild's counts them all.
  d.redistribute(p, {&bonds});
  std::int64_t mine = 0;
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    const std::int64_t a = p.index_of(bonds.gid_a[b]);
    mine += a >= 0 && static_cast<std::size_t>(a) < p.n_local() ? 1 : 0;
  }
  const std::vector<std::int64_t> all = c.allgather(std::vector<std::int64_t>{mine});
  std::int64_t total = 0;
  for (const std::int64_t n : all)
    total += n;
  EXPECT_EQ(total, 264);  // every bond counted once
  // The imbalance the pre-flight report prints, against the ranks' weights summed here: each
  // rank's particles, its counted bonds at their store's weight (2) times the scale, and one
  // for each cell it owns.
  const auto ranks = d.report(p, bonds);
  std::vector<double> weight;
  for (std::size_t r = 0; r < ranks.size(); ++r)
    weight.push_back(static_cast<double>(ranks[r].particles + 2 * scale * all[r] + ranks[r].cells));
  double sum = 0.0;
  for (const double w : weight)
    sum += w;
  const double expected = *std::max_element(weight.begin(), weight.end()) / (sum / c.size()) - 1.0;
  EXPECT_NEAR(d.weighted_imbalance(p, {&bonds}), expected, 1e-12) << "scale " << scale;
  return static_cast<double>(*std::max_element(all.begin(), all.end())) /
         static_cast<double>(total);
}

// Multi-rate stepping evaluates a bond at every sub-step (set_row_weight_scale): weighed so, a
// bonded net beside many grains is shared by the ranks, where at one rate's weight one rank
// holds it whole. With 12 sub-steps the lattice weighs 288 + 264 x 2 x 12 = 6 624 against the
// free particles' 3 200: no rank should hold much more of its bonds than a fair share of the
// total weight buys (20 % over it, for the partition cells' granularity; measured: 0.81 of the
// bonds on 2 ranks, 0.52 on 3).
TEST_F(Decomposition, BondsWeighedByTheirSubstepsAreShared) {
  const Communicator c(comm_);
  const double one_rate = most_bonds_share(c, 1);
  const double substepped = most_bonds_share(c, 12);
  if (c.size() == 1) return;  // one rank holds them all either way
  EXPECT_EQ(one_rate, 1.0);
  const double fair = (6624.0 + 3200.0) / c.size();
  EXPECT_LT(substepped, 1.2 * fair / 6624.0);
}

// Multi-rate stepping changes rates without a new ghost layer (Simulation::change_rates()):
// update_ghosts() of the kGhostRates fields sends the owners' net_contact, rank-encoded here,
// to every ghost, and nothing else (the per-step fields keep their poison).
TEST_F(Decomposition, GhostsTakeTheirOwnersNewRatesAndNothingElse) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds, c.rank(), c.size());
  p.set_tracks_slow_loads(true);  // the net_contact column
  DomainDecomposition d(c, kBlock, 0.1);
  d.distribute_initial(p, {&bonds});
  const auto owner = owners(c, p, c.sum(static_cast<std::int64_t>(p.n_local())));
  const auto encoded = [](std::int64_t gid, int rank) {
    return static_cast<std::uint8_t>(1 + rank + 8 * (gid % 3));
  };
  for (std::size_t k = 0; k < p.n_local(); ++k)
    p.net_contact[k] = encoded(p.gid[k], c.rank());
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k) {
    p.net_contact[k] = 255;
    p.velocity[k] = {-1, -1, -1};
  }
  d.update_ghosts(p, field_flag::kGhostRates);
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k) {
    EXPECT_EQ(p.net_contact[k], encoded(p.gid[k], owner.at(p.gid[k]))) << "ghost " << p.gid[k];
    EXPECT_EQ(p.velocity[k], (Vec3{-1, -1, -1})) << "ghost " << p.gid[k];
  }
  if (c.size() > 1) {
    EXPECT_GT(c.sum(static_cast<std::int64_t>(p.n_ghost())), 0);
  }
}

TEST_F(Decomposition, GhostsCarryTheirOwnersRankEncodedValues) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  DomainDecomposition d(c, kBlock, 0.1);
  const auto owner = distribute_lattice(c, p, bonds, d);
  expect_rank_encoded_refresh(c, p, d, owner);
  // Gid-encoded once-only field came with the ghost.
  for (std::size_t k = 0; k < p.n_total(); ++k)
    EXPECT_EQ(p.radius[k], 0.002);
  expect_one_block_ghost_layer(p, {});
  ParticleStore all;
  BondStore unused;
  make_lattice(all, unused);
  // Bonds: exactly those with an owned end.
  std::size_t expected_bonds = 0;
  for (std::size_t b = 0; b < unused.size(); ++b) {
    const std::int64_t ia = p.index_of(unused.gid_a[b]);
    const std::int64_t ib = p.index_of(unused.gid_b[b]);
    expected_bonds += (ia >= 0 && static_cast<std::size_t>(ia) < p.n_local()) ||
                      (ib >= 0 && static_cast<std::size_t>(ib) < p.n_local());
  }
  EXPECT_EQ(bonds.size(), expected_bonds);
}

TEST_F(Decomposition, MigrationCarriesParticlesBondsAndHistory) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds, c.rank(), c.size());
  const std::int64_t n_total = c.sum(static_cast<std::int64_t>(p.n_local()));
  DomainDecomposition d(c, kBlock, /*imbalance_threshold=*/0.0);
  d.distribute_initial(p, {&bonds});
  // Mark state that must travel: a broken bond with its break time, a history entry per
  // owned particle (spring = gid-encoded), and rank-encoded velocities.
  for (std::size_t b = 0; b < bonds.size(); ++b)
    if (bonds.gid_a[b] == 30) {
      bonds.broken[b] = 1;
      bonds.break_time[b] = 0.125;
    }
  ContactSpringStore history(ContactSpringStore::Partner::kRigidBody);
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    p.velocity[k] = {c.rank() + 1.0, 0, 0};
    history.append(p.gid[k], 0, Vec3{3.0 * p.gid[k], 0, 0});
  }
  const auto before = owners(c, p, n_total);
  // Shift the lattice by 4 blocks along x and mirror it in y, so that most particles land in
  // blocks that other ranks own (imbalance threshold 0: the blocks are partitioned again).
  for (std::size_t k = 0; k < p.n_total(); ++k)
    p.position[k] = {p.position[k].x + 4 * kBlock, 0.066 - p.position[k].y, p.position[k].z};
  d.redistribute(p, {&bonds, &history});
  const auto after = owners(c, p, n_total);
  int moved = 0;
  for (const auto& [gid, rank] : after)
    moved += rank != before.at(gid);
  if (c.size() > 1) {
    EXPECT_GT(c.sum(std::int64_t{moved}), 0) << "some particles should change rank";
  }
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    EXPECT_EQ(p.torque[k].x, 7.0 * p.gid[k] + 1) << "gid-encoded field lost";
    EXPECT_EQ(p.velocity[k].x, before.at(p.gid[k]) + 1.0) << "rank-encoded value of old owner";
  }
  // Owned particles sit in gid order.
  EXPECT_TRUE(std::is_sorted(p.gid.begin(), p.gid.begin() + static_cast<long>(p.n_local())));
  // History: exactly one entry per owned particle, with its value.
  std::map<std::int64_t, double> springs;
  for (std::size_t h = 0; h < history.size(); ++h)
    springs[history.gid[h]] = history.spring[h].x;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    EXPECT_EQ(springs.at(p.gid[k]), 3.0 * p.gid[k]);
  // The broken bond is held by the owner(s) of its ends with its state.
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    EXPECT_EQ(bonds.broken[b], bonds.gid_a[b] == 30 ? 1 : 0);
    if (bonds.gid_a[b] == 30) {
      EXPECT_EQ(bonds.break_time[b], 0.125);
    }
  }
  std::int64_t holders_of_30 = 0;
  for (std::size_t b = 0; b < bonds.size(); ++b)
    holders_of_30 += bonds.gid_a[b] == 30;
  const bool own_an_end = after.at(30) == c.rank() || after.at(31) == c.rank();
  EXPECT_EQ(holders_of_30, own_an_end ? 1 : 0);
}

// Partition cells of 3 x 3 x 3 blocks (what large models get, so that no rank holds a map entry
// per grain): particles go to the owner of their cell, the ghost layer stays one block thick,
// after the first distribution and after a migration, and only occupied cells are held.
TEST_F(Decomposition, CellsOfSeveralBlocksKeepTheGhostLayerOneBlockThick) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds, c.rank(), c.size());
  const std::int64_t n_total = c.sum(static_cast<std::int64_t>(p.n_local()));
  DomainDecomposition d(c, kBlock, /*imbalance_threshold=*/0.0, /*cell_blocks=*/3);
  d.distribute_initial(p, {&bonds});
  EXPECT_EQ(d.cell_blocks(), 3);
  owners(c, p, n_total);
  expect_one_block_ghost_layer(p, {});
  // The lattice spans 0..66 mm: blocks 0..6 along x and y, 0 along z; cells 0..2 along x and
  // y (blocks 0-2, 3-5, 6), one layer: 9 cells, against 49 occupied blocks.
  EXPECT_EQ(d.cells(), 9);
  // Rank-encoded refresh through the cells' ghost lists.
  std::map<std::int64_t, int> owner = owners(c, p, n_total);
  expect_rank_encoded_refresh(c, p, d, owner);
  // Shift by 4 blocks and repartition: the cells are other ones, the layer is the same.
  const Vec3 shift{4 * kBlock, 2 * kBlock, 0};
  for (std::size_t k = 0; k < p.n_total(); ++k)
    p.position[k] += shift;
  d.redistribute(p, {&bonds});
  owner = owners(c, p, n_total);
  expect_one_block_ghost_layer(p, shift);
  if (c.size() > 1) {
    std::set<int> ranks_used;
    for (const auto& [gid, rank] : owner)
      ranks_used.insert(rank);
    EXPECT_EQ(static_cast<int>(ranks_used.size()), c.size()) << "every rank owns some cells";
  }
}

// Cells of one block, no repartition: a lattice that creeps along x by a third of a block per
// rebuild keeps occupying new cells, which go to a rank without a new partition. Each rebuild's
// ghost layer must still be the whole one-block neighbourhood (the halo ranks a rank keeps per
// block must follow each new cell), and a refresh must bring the owners' values.
TEST_F(Decomposition, GhostLayerFollowsNewCellsWithoutARepartition) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds, c.rank(), c.size());
  const std::int64_t n_total = c.sum(static_cast<std::int64_t>(p.n_local()));
  DomainDecomposition d(c, kBlock, /*imbalance_threshold=*/100.0, /*cell_blocks=*/1);
  d.distribute_initial(p, {&bonds});
  const std::int64_t partitions = d.repartitions();
  Vec3 shift{};
  for (int move = 0; move < 9; ++move) {
    const Vec3 step{kBlock / 3.0, move % 2 == 0 ? kBlock / 4.0 : -kBlock / 4.0, 0.0};
    shift += step;
    for (std::size_t k = 0; k < p.n_total(); ++k)
      p.position[k] += step;
    d.redistribute(p, {&bonds});
    const auto owner = owners(c, p, n_total);
    expect_one_block_ghost_layer(p, shift);
    expect_rank_encoded_refresh(c, p, d, owner);
  }
  EXPECT_EQ(d.repartitions(), partitions) << "the cells were to be assigned, not partitioned";
}

TEST_F(Decomposition, FirstDistributionSendsBondsAndSpringsHeldAnywhereToTheirParticles) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds, c.rank(), c.size());
  const std::int64_t n_total = c.sum(static_cast<std::int64_t>(p.n_local()));
  // Springs between gid g and g + 12, held by a rank unrelated to either particle.
  ContactSpringStore history(ContactSpringStore::Partner::kParticle);
  for (std::int64_t g = 0; g + 12 < n_total; ++g)
    if ((5 * g + 1) % c.size() == c.rank())
      history.append(g, g + 12, Vec3{static_cast<double>(g), 0, 0});
  DomainDecomposition d(c, kBlock, 0.1);
  d.distribute_initial(p, {&bonds, &history});
  const auto owner = owners(c, p, n_total);
  // Brute force: every bond of the whole lattice is held exactly by the owners of its ends.
  ParticleStore all;
  BondStore all_bonds;
  make_lattice(all, all_bonds);
  std::set<std::pair<std::int64_t, std::int64_t>> expected, held;
  for (std::size_t b = 0; b < all_bonds.size(); ++b)
    if (owner.at(all_bonds.gid_a[b]) == c.rank() || owner.at(all_bonds.gid_b[b]) == c.rank())
      expected.emplace(all_bonds.gid_a[b], all_bonds.gid_b[b]);
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    EXPECT_TRUE(held.emplace(bonds.gid_a[b], bonds.gid_b[b]).second) << "bond held twice";
    // Bond ids of the lattice: the gid pair determines it (11 bonds per row of 12).
    EXPECT_EQ(bonds.id[b], bonds.gid_a[b] - bonds.gid_a[b] / 12) << "bond id lost";
    EXPECT_EQ(bonds.model_column(0)[b], 0.5 * static_cast<double>(bonds.id[b]))
        << "model column lost";
  }
  EXPECT_EQ(held, expected);
  // Springs: each on the owners of its two particles, with its value.
  std::set<std::int64_t> springs_expected, springs_held;
  for (std::int64_t g = 0; g + 12 < n_total; ++g)
    if (owner.at(g) == c.rank() || owner.at(g + 12) == c.rank()) springs_expected.insert(g);
  for (std::size_t h = 0; h < history.size(); ++h) {
    EXPECT_EQ(history.partner[h], history.gid[h] + 12);
    EXPECT_EQ(history.spring[h].x, static_cast<double>(history.gid[h]));
    EXPECT_TRUE(springs_held.insert(history.gid[h]).second)
        << "spring " << history.gid[h] << " held twice";
  }
  EXPECT_EQ(springs_held, springs_expected);
  // Ghosts: the far end of every held bond is here.
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    EXPECT_GE(p.index_of(bonds.gid_a[b]), 0);
    EXPECT_GE(p.index_of(bonds.gid_b[b]), 0);
  }
}

/// Every field of every particle a store holds (owned and ghosts), as bytes by field name.
std::map<std::string, std::vector<char>> field_bytes(ParticleStore& p) {
  std::map<std::string, std::vector<char>> out;
  p.for_each_field([&](const FieldInfo& f, auto& v) {
    const char* data = reinterpret_cast<const char*>(v.data());
    out[std::string(f.name)].assign(data, data + v.size() * sizeof(v[0]));
  });
  return out;
}

/// A spring store's rows as a sorted list of (gid, partner, spring.x): what it holds, in any
/// order (a term finds its springs by key).
std::vector<std::tuple<std::int64_t, std::int64_t, double>> spring_rows(
    const ContactSpringStore& h) {
  std::vector<std::tuple<std::int64_t, std::int64_t, double>> rows;
  for (std::size_t k = 0; k < h.size(); ++k)
    rows.emplace_back(h.gid[k], h.partner[k], h.spring[k].x);
  std::sort(rows.begin(), rows.end());
  return rows;
}

// The first distribution in many small rounds must give every rank what one round gives: the
// same particles and ghosts in the same order, every field the same bits, the same bonds, and
// the same springs (held anywhere at first, as a restart reads them).
TEST_F(Decomposition, FirstDistributionInRoundsGivesWhatOneRoundGives) {
  const Communicator c(comm_);
  ParticleStore one_p, rounds_p;
  BondStore one_b, rounds_b;
  make_lattice(one_p, one_b, c.rank(), c.size());
  make_lattice(rounds_p, rounds_b, c.rank(), c.size());
  ContactSpringStore one_h(ContactSpringStore::Partner::kParticle);
  ContactSpringStore rounds_h(ContactSpringStore::Partner::kParticle);
  for (std::int64_t g = 0; g + 12 < 12 * 12 * 2; ++g)
    if ((5 * g + 1) % c.size() == c.rank()) {
      one_h.append(g, g + 12, Vec3{static_cast<double>(g), 0, 0});
      rounds_h.append(g, g + 12, Vec3{static_cast<double>(g), 0, 0});
    }
  DomainDecomposition one(c, kBlock, 0.1), in_rounds(c, kBlock, 0.1);
  in_rounds.set_migration_round_bytes(1);  // an eighth of the store a round
  one.distribute_initial(one_p, {&one_b, &one_h});
  in_rounds.distribute_initial(rounds_p, {&rounds_b, &rounds_h});
  EXPECT_EQ(one.last_migration_rounds(), 1);
  EXPECT_EQ(one.last_row_migration_rounds(), 1);
  if (c.size() > 1) {
    EXPECT_GE(in_rounds.last_migration_rounds(), 3);
    EXPECT_GE(in_rounds.last_row_migration_rounds(), 3);
  }
  EXPECT_EQ(spring_rows(rounds_h), spring_rows(one_h)) << "rank " << c.rank();
  // Each spring on the owners of its particles, as one round puts it (checked by the test
  // above): none lost, none doubled.
  EXPECT_EQ(c.sum(static_cast<std::int64_t>(rounds_h.size())),
            c.sum(static_cast<std::int64_t>(one_h.size())));
  ASSERT_EQ(rounds_p.n_local(), one_p.n_local());
  ASSERT_EQ(rounds_p.n_total(), one_p.n_total());
  EXPECT_TRUE(field_bytes(rounds_p) == field_bytes(one_p)) << "rank " << c.rank();
  ASSERT_EQ(rounds_b.size(), one_b.size());
  for (std::size_t b = 0; b < one_b.size(); ++b) {
    EXPECT_EQ(rounds_b.id[b], one_b.id[b]);
    EXPECT_EQ(rounds_b.model_column(0)[b], one_b.model_column(0)[b]);
  }
  // And nothing lost or doubled: every gid of the lattice is owned exactly once.
  const std::int64_t n_total = c.sum(static_cast<std::int64_t>(rounds_p.n_local()));
  EXPECT_EQ(n_total, 12 * 12 * 2);
  std::int64_t gid_sum = 0;
  for (std::size_t k = 0; k < rounds_p.n_local(); ++k)
    gid_sum += rounds_p.gid[k];
  EXPECT_EQ(c.sum(gid_sum), n_total * (n_total - 1) / 2);
}

// The partition weighs a cell by its particles plus kBlockWeight per bond (plus 1): a strip of
constexpr int kNetNx = 40, kNetNy = 12;

/// 40 x 12 particles, one a block, whose left half is a bonded net (every particle bonded to its
/// x neighbour) and whose right half is loose grains, spread over the ranks by gid. Returns the
/// number of bonds.
std::int64_t make_net_beside_grains(const Communicator& c, ParticleStore& p, BondStore& bonds) {
  std::int64_t bond_id = 0;
  for (int j = 0; j < kNetNy; ++j)
    for (int i = 0; i < kNetNx; ++i) {
      const std::int64_t gid = j * kNetNx + i;
      if (i + 1 < kNetNx / 2) {  // the net: bonded to the next particle along x
        // Held with its first particle, as the ring sources emit them.
        if (gid % c.size() == c.rank()) bonds.append(bond_id, gid, gid + 1, 0);
        ++bond_id;
      }
      if (gid % c.size() != c.rank()) continue;
      ParticleStore::NewParticle np;
      np.gid = gid;
      np.position = {kBlock * (i + 0.5), kBlock * (j + 0.5), 0.5 * kBlock};
      np.radius = 0.002;
      np.density = 1000;
      p.add(np);
    }
  p.rebuild_index();
  return bond_id;
}

/// This rank's bonds counted here, and its weight in the partition's graph counted by hand: a
/// cell weighs its particles, its weighted bonds and 1 (no cell weighs nothing; with one
/// particle a cell that 1 counts too).
std::pair<std::int64_t, std::int64_t> hand_counted_weight(const Communicator& c,
                                                          const ParticleStore& p,
                                                          const BondStore& bonds,
                                                          const DomainDecomposition& d) {
  std::int64_t counted = 0;
  for (std::size_t b = 0; b < bonds.size(); ++b)
    counted += counted_here(p, bonds, b) ? 1 : 0;
  const std::int64_t cells = d.report(p, bonds)[static_cast<std::size_t>(c.rank())].cells;
  return {counted,
          static_cast<std::int64_t>(p.n_local()) + BondStore::kBlockWeight * counted + cells};
}

// The net beside the grains in one-block cells. Each rank's particles plus weighted bonds are
// the same to within METIS's tolerance; counted by particles alone, the net's rank would look
// light.
TEST_F(Decomposition, BondsWeighTheirCellsSoANetIsShared) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  const std::int64_t n_bonds = make_net_beside_grains(c, p, bonds);
  DomainDecomposition d(c, kBlock, /*imbalance_threshold=*/0.0, /*cell_blocks=*/1);
  d.distribute_initial(p, {&bonds});
  const auto [counted, weight] = hand_counted_weight(c, p, bonds, d);
  const double mean = static_cast<double>(c.sum(weight)) / c.size();
  const double most = static_cast<double>(c.max(weight));
  EXPECT_EQ(c.sum(counted), n_bonds);
  EXPECT_LE(most / mean, 1.08) << "rank " << c.rank() << ": " << p.n_local() << " particles, "
                               << counted << " bonds";
  if (c.size() > 1) {
    // The net's share is heavier per particle: its rank holds fewer particles than the mean.
    const double mean_particles = static_cast<double>(kNetNx * kNetNy) / c.size();
    const double fewest = static_cast<double>(c.min(static_cast<std::int64_t>(p.n_local())));
    EXPECT_LT(fewest, 0.9 * mean_particles);
  }
}

// The repartition test weighs what the partition balances. After a weighted partition the
// particle counts stay uneven (the net's rank holds fewer); tested by particles alone, every
// rebuild partitioned again. Rebuilds of the unmoved particles keep this partition, whose
// weights (counted by hand) are within the threshold.
TEST_F(Decomposition, ABalancedLoadIsNotPartitionedAgainForItsParticleCounts) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  make_net_beside_grains(c, p, bonds);
  DomainDecomposition d(c, kBlock, /*imbalance_threshold=*/0.1, /*cell_blocks=*/1);
  d.distribute_initial(p, {&bonds});
  const std::int64_t partitions = d.repartitions();
  for (int rebuild = 0; rebuild < 3; ++rebuild)
    d.redistribute(p, {&bonds});
  EXPECT_EQ(d.repartitions(), partitions) << "a balanced load was partitioned again";
  const std::int64_t weight = hand_counted_weight(c, p, bonds, d).second;
  const double mean = static_cast<double>(c.sum(weight)) / c.size();
  EXPECT_LE(static_cast<double>(c.max(weight)) / mean - 1.0, 0.1);
  if (c.size() > 1) {
    EXPECT_GT(d.imbalance(p), 0.1) << "the particle counts alone would repartition";
  }
}

TEST_F(Decomposition, FirstDistributionRefusesABondToAMissingParticle) {
  const Communicator c(comm_);
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds, c.rank(), c.size());
  // On the last rank only: a bond to a particle nobody has. Every rank must throw.
  if (c.rank() == c.size() - 1) bonds.append(999, 0, 100000, 0);
  DomainDecomposition d(c, kBlock, 0.1);
  EXPECT_THROW(d.distribute_initial(p, {&bonds}), std::runtime_error);
}

TEST_F(Decomposition, FirstDistributionRefusesAParticleHeldTwice) {
  const Communicator c(comm_);
  if (c.size() == 1) GTEST_SKIP() << "needs two ranks to hold a particle twice";
  ParticleStore p;
  BondStore bonds;
  make_lattice(p, bonds);  // the whole lattice on every rank
  DomainDecomposition d(c, kBlock, 0.1);
  EXPECT_THROW(d.distribute_initial(p, {&bonds}), std::logic_error);
}

}  // namespace
}  // namespace ringdem
