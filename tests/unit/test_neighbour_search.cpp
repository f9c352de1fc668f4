#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <random>
#include <set>
#include <utility>

#include "domain/NeighbourSearch.hpp"
#include "domain/SpatialBins.hpp"

namespace ringdem {
namespace {

std::set<std::pair<std::int64_t, std::int64_t>> as_gid_set(const ParticleStore& p,
                                                           const PairCandidates& c) {
  std::set<std::pair<std::int64_t, std::int64_t>> s;
  for (std::size_t m = 0; m < c.size(); ++m)
    s.emplace(p.gid[c.i[m]], p.gid[c.j[m]]);
  return s;
}

/// Pair m's ends in key order, as (bin, gid) of the first end and of the other.
std::array<std::int64_t, 4> key_pair(const ParticleStore& p, const PairCandidates& c,
                                     std::size_t m) {
  std::uint32_t a = c.i[m], b = c.j[m];
  if (p.sorts_before(b, a)) std::swap(a, b);
  return {p.sort_bin[a], p.gid[a], p.sort_bin[b], p.gid[b]};
}

/// Each pair oriented with the lower gid first, the list in strictly ascending key order
/// (which PairContactTerm's sums rely on); returns how many neighbours in the list are out of
/// (gid, gid) order, which is positive only where the bins reorder.
std::size_t expect_key_order(const ParticleStore& p, const PairCandidates& c) {
  std::size_t out_of_gid_order = 0;
  for (std::size_t m = 0; m < c.size(); ++m) {
    EXPECT_LT(p.gid[c.i[m]], p.gid[c.j[m]]) << "pair " << m;
    if (m == 0) continue;
    EXPECT_LT(key_pair(p, c, m - 1), key_pair(p, c, m)) << "pair " << m;
    out_of_gid_order += std::make_pair(p.gid[c.i[m - 1]], p.gid[c.j[m - 1]]) >
                        std::make_pair(p.gid[c.i[m]], p.gid[c.j[m]]);
  }
  return out_of_gid_order;
}

/// `bin_width` > 0: the particles binned by space (SpatialBins), as after a re-sort; the store
/// is left in index order, which is then neither gid nor key order.
ParticleStore random_cloud(int n, double box, double r_min, double r_max, unsigned seed,
                           double bin_width = 0.0) {
  ParticleStore p;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, box), rad(r_min, r_max);
  // gids shuffled so that index order and gid order differ.
  std::vector<std::int64_t> gids(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    gids[static_cast<std::size_t>(k)] = 1000 + 7 * k;
  std::shuffle(gids.begin(), gids.end(), rng);
  for (int k = 0; k < n; ++k) {
    ParticleStore::NewParticle np;
    np.gid = gids[static_cast<std::size_t>(k)];
    np.position = {pos(rng), pos(rng), pos(rng)};
    np.radius = rad(rng);
    np.density = 1000.0;
    p.add(np);
  }
  if (bin_width > 0.0) SpatialBins::assign(p, {bin_width});
  p.rebuild_index();
  return p;
}

// The cell grid must find exactly the pairs of the O(N^2) search, each once, lower gid first,
// in key order (grains binned by space, as after a re-sort).
TEST(NeighbourSearch, EqualsBruteForceForPolydisperseCloud) {
  const ParticleStore p = random_cloud(2000, 0.2, 0.002, 0.006, 42, 0.01);
  PairExclusions none;
  NeighbourSearch search;
  search.set_dense_cell_floor(0);
  PairCandidates cells;
  const double skin = 0.001;
  search.build(p, skin, none, cells);
  EXPECT_FALSE(search.used_dense_grid()) << "4096 cells for 2000 particles: hashed";
  const PairCandidates brute = brute_force_pairs(p, skin, none);
  ASSERT_GT(brute.size(), 100u) << "the cloud must be dense enough to test anything";
  EXPECT_EQ(cells.size(), brute.size());  // no duplicates
  EXPECT_EQ(as_gid_set(p, cells), as_gid_set(p, brute));
  EXPECT_GT(expect_key_order(p, cells), cells.size() / 10) << "the bins must reorder the pairs";
}

/// The cell search's pairs are exactly those of the O(N^2) search (each once), more than
/// `at_least`, and in key order with the bins reordering a tenth of them or more.
void expect_brute_force_pairs_binned(const ParticleStore& p, const PairCandidates& cells,
                                     double skin, std::size_t at_least) {
  const PairCandidates brute = brute_force_pairs(p, skin, PairExclusions{});
  ASSERT_GT(brute.size(), at_least);
  EXPECT_EQ(cells.size(), brute.size());  // no duplicates
  EXPECT_EQ(as_gid_set(p, cells), as_gid_set(p, brute));
  EXPECT_GT(expect_key_order(p, cells), cells.size() / 10) << "the bins must reorder the pairs";
}

// The same sparse cloud at the default floor: its box of 4096 cells is under the floor, so it
// takes the dense grid, and finds the pairs of the O(N^2) search in key order all the same.
TEST(NeighbourSearch, SparseBoxUnderTheFloorTakesTheDenseGrid) {
  const ParticleStore p = random_cloud(2000, 0.2, 0.002, 0.006, 42, 0.01);
  NeighbourSearch search;
  PairCandidates cells;
  search.build(p, 0.001, PairExclusions{}, cells);
  EXPECT_TRUE(search.used_dense_grid()) << "4096 cells, under CellGrid::kDenseCellFloor";
  expect_brute_force_pairs_binned(p, cells, 0.001, 100);
}

// Under the floor, the dense grid still takes at most CellGrid::kDenseCellsPerMember (32) cells
// per member. Cells of 2 x 4.5 + 6 mm in a box of 0.2 m: 13 or 14 a side, 2197 to 2744 cells.
// 50 particles (1600 cells at most) take the hashed cells, 100 (3200) the dense grid; both find
// the pairs of the O(N^2) search.
TEST(NeighbourSearch, FewMembersInABoxUnderTheFloorTakeTheHashedCells) {
  const double skin = 0.006;
  for (const int count : {50, 100}) {
    const ParticleStore p = random_cloud(count, 0.2, 0.004, 0.0045, 7, 0.01);
    NeighbourSearch search;
    PairCandidates cells;
    search.build(p, skin, PairExclusions{}, cells);
    EXPECT_EQ(search.used_dense_grid(), count == 100) << count << " particles";
    const PairCandidates brute = brute_force_pairs(p, skin, PairExclusions{});
    ASSERT_GT(brute.size(), 0u) << count << " particles";
    EXPECT_EQ(cells.size(), brute.size());
    EXPECT_EQ(as_gid_set(p, cells), as_gid_set(p, brute));
  }
}

// A cloud that fills its box takes the dense grid; it must find the same pairs as the O(N^2)
// search, in key order (binned by space).
TEST(NeighbourSearch, DenseGridEqualsBruteForce) {
  const ParticleStore p = random_cloud(3000, 0.1, 0.002, 0.006, 5, 0.02);
  NeighbourSearch search;
  PairCandidates cells;
  search.build(p, 0.001, PairExclusions{}, cells);
  EXPECT_TRUE(search.used_dense_grid()) << "512 cells for 3000 particles: dense";
  expect_brute_force_pairs_binned(p, cells, 0.001, 1000);
}

// As the store is after a migration (DomainDecomposition::migrate): the owned particles in
// ascending key order, so that the search orders two owned ends by their indices without
// reading their keys, and ghosts after them. The same pairs as the O(N^2) search, in key order.
TEST(NeighbourSearch, OwnedStoredInKeyOrderEqualsBruteForce) {
  ParticleStore full = random_cloud(3000, 0.1, 0.002, 0.006, 5, 0.02);
  std::vector<std::size_t> order(full.n_local());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&full](std::size_t x, std::size_t y) { return full.sorts_before(x, y); });
  full.permute_local(order);
  // The last 800 in key order become ghosts.
  ParticleStore p = full;
  p.resize_local(2200);
  p.resize_ghosts(800);
  p.for_each_field([&](const FieldInfo& info, auto& v) {
    full.for_each_field([&](const FieldInfo& other, auto& w) {
      if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::decay_t<decltype(w)>>)
        if (info.name == other.name)
          for (std::size_t k = 2200; k < 3000; ++k)
            v[k] = w[k];
    });
  });
  p.rebuild_index();
  NeighbourSearch search;
  PairCandidates cells;
  search.build(p, 0.001, PairExclusions{}, cells);
  EXPECT_TRUE(search.used_dense_grid());
  const PairCandidates brute = brute_force_pairs(p, 0.001, PairExclusions{});
  ASSERT_GT(brute.size(), 1000u);
  EXPECT_EQ(cells.size(), brute.size());
  EXPECT_EQ(as_gid_set(p, cells), as_gid_set(p, brute));
  EXPECT_GT(expect_key_order(p, cells), cells.size() / 10) << "the bins must reorder the pairs";
}

// Grains of 2-100 mm and two 0.3 m boulders: five size levels, each with its own cells. The
// boulders' neighbours are found by scanning the grains' small cells; the pairs must be those
// of the O(N^2) search, in (gid, gid) order (no particle binned: every key is (0, gid)).
TEST(NeighbourSearch, SizeLevelsEqualBruteForce) {
  ParticleStore p = random_cloud(3000, 0.5, 0.002, 0.1, 9);
  for (int k = 0; k < 2; ++k) {
    ParticleStore::NewParticle boulder;
    boulder.gid = 5 + 100000 * k;  // one below every grain's gid, one above
    boulder.position = {0.15 + 0.2 * k, 0.25, 0.25};
    boulder.radius = 0.3;
    boulder.density = 2600.0;
    p.add(boulder);
  }
  p.rebuild_index();
  NeighbourSearch search;
  PairCandidates cells;
  search.build(p, 0.001, PairExclusions{}, cells);
  EXPECT_GE(search.n_levels(), 5u);
  const PairCandidates brute = brute_force_pairs(p, 0.001, PairExclusions{});
  std::size_t with_boulder = 0;
  for (std::size_t m = 0; m < brute.size(); ++m)
    with_boulder += p.radius[brute.i[m]] == 0.3 || p.radius[brute.j[m]] == 0.3;
  ASSERT_GT(with_boulder, 50u);
  EXPECT_EQ(cells.size(), brute.size());
  EXPECT_EQ(as_gid_set(p, cells), as_gid_set(p, brute));
  EXPECT_EQ(expect_key_order(p, cells), 0u);
}

// A polydisperse bed's layout (docs/performance.md, `poly`): columns of stacked grains of 5-25 mm
// on a grid 50 mm apart, around the origin (negative cells too), binned by space. Each size
// level is sparse in its bounding box, so it is hashed, and its rows along x hold many cells: a
// query's range of x is found in them by a binary search (CellGrid's hashed rows).
TEST(NeighbourSearch, HashedRowsOfManyCellsEqualBruteForce) {
  ParticleStore p;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> radius(0.005, 0.025), shift(-0.004, 0.004);
  std::int64_t gid = 0;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) {
      double z = -0.1;
      for (int k = 0; k < 6; ++k) {
        ParticleStore::NewParticle np;
        np.gid = gid++;
        np.radius = radius(rng);
        z += 0.0002 + np.radius;
        np.position = {0.05 * i + shift(rng), 0.05 * j + shift(rng), z};
        z += np.radius;
        np.density = 2600.0;
        p.add(np);
      }
    }
  SpatialBins::assign(p, {0.01});
  p.rebuild_index();
  NeighbourSearch search;
  search.set_dense_cell_floor(0);
  PairCandidates cells;
  search.build(p, 0.001, PairExclusions{}, cells);
  ASSERT_GE(search.n_levels(), 2u);
  for (std::size_t l = 0; l < search.n_levels(); ++l)
    EXPECT_FALSE(search.used_dense_grid(l)) << "level " << l;
  const PairCandidates brute = brute_force_pairs(p, 0.001, PairExclusions{});
  ASSERT_GT(brute.size(), 1500u);  // mostly each stack's neighbours
  EXPECT_EQ(cells.size(), brute.size());
  EXPECT_EQ(as_gid_set(p, cells), as_gid_set(p, brute));
  EXPECT_GT(expect_key_order(p, cells), cells.size() / 10) << "the bins must reorder the pairs";
}

// Ghosts: pairs of two ghosts are never candidates; owned–ghost pairs are, in one key order.
TEST(NeighbourSearch, SkipsGhostGhostPairs) {
  ParticleStore p = random_cloud(600, 0.08, 0.003, 0.003, 7, 0.01);
  p.resize_local(400);  // drop 200, then re-add them as ghosts
  ParticleStore full = random_cloud(600, 0.08, 0.003, 0.003, 7, 0.01);
  p.resize_ghosts(200);
  p.for_each_field([&](const FieldInfo& info, auto& v) {
    full.for_each_field([&](const FieldInfo& other, auto& w) {
      if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::decay_t<decltype(w)>>)
        if (info.name == other.name)
          for (std::size_t k = 400; k < 600; ++k)
            v[k] = w[k];
    });
  });
  p.rebuild_index();
  PairExclusions none;
  NeighbourSearch search;
  PairCandidates cells;
  search.build(p, 0.0005, none, cells);
  const PairCandidates brute = brute_force_pairs(p, 0.0005, none);
  EXPECT_EQ(as_gid_set(p, cells), as_gid_set(p, brute));
  std::size_t owned_ghost = 0;
  for (std::size_t m = 0; m < cells.size(); ++m) {
    EXPECT_FALSE(cells.i[m] >= 400 && cells.j[m] >= 400);
    owned_ghost += (cells.i[m] >= 400 || cells.j[m] >= 400);
  }
  EXPECT_GT(owned_ghost, 0u);
  // Owned and ghost ends merged in one key order.
  EXPECT_GT(expect_key_order(p, cells), 0u);
}

// Excluded (bonded) pairs are left out; nothing else is.
TEST(NeighbourSearch, ExcludesBondedPairs) {
  const ParticleStore p = random_cloud(500, 0.05, 0.003, 0.003, 3);
  NeighbourSearch search;
  PairCandidates all;
  search.build(p, 0.001, PairExclusions{}, all);
  ASSERT_GT(all.size(), 10u);
  // Exclude the first 10 pairs found.
  std::vector<std::vector<std::int64_t>> partners(p.n_total());
  for (std::size_t m = 0; m < 10; ++m) {
    partners[all.i[m]].push_back(p.gid[all.j[m]]);
    partners[all.j[m]].push_back(p.gid[all.i[m]]);
  }
  PairExclusions ex;
  ex.offset.push_back(0);
  for (const auto& list : partners) {
    for (auto g : list)
      ex.partner_gid.push_back(g);
    ex.offset.push_back(static_cast<std::uint32_t>(ex.partner_gid.size()));
  }
  PairCandidates some;
  search.build(p, 0.001, ex, some);
  EXPECT_EQ(some.size(), all.size() - 10);
}

// A 0.4 m sphere is a rigid body, not a particle: a single very large particle would make
// every cell huge. Here: particles far apart (sparse domain, 7 million cells of a box) cost
// nothing extra: they take the hashed cells.
TEST(NeighbourSearch, SparseDomainUsesHashedCells) {
  ParticleStore p;
  for (int k = 0; k < 4; ++k) {
    ParticleStore::NewParticle np;
    np.gid = k;
    np.position = {k * 10000.0, 0.0, (k % 2) * 0.0085};
    np.radius = 0.0045;
    np.density = 7800;
    p.add(np);
  }
  ParticleStore::NewParticle np;
  np.gid = 4;
  np.position = {0.0085, 0.0, 0.0};
  np.radius = 0.0045;
  np.density = 7800;
  p.add(np);
  p.rebuild_index();
  NeighbourSearch search;
  PairCandidates c;
  search.build(p, 0.0, PairExclusions{}, c);
  EXPECT_FALSE(search.used_dense_grid());
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(p.gid[c.i[0]], 0);
  EXPECT_EQ(p.gid[c.j[0]], 4);
}

}  // namespace
}  // namespace ringdem
