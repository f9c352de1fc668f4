// Bond store: a bond model's own columns join the field registry, grow with the bonds and are
// refused when they would shadow a column or come too late. The pair-store protocol
// (domain/PairStore.hpp) that migration and checkpoints use: ends, settling of arrivals, and
// the one counting rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "domain/BondStore.hpp"
#include "domain/PairStore.hpp"

namespace ringdem {
namespace {

TEST(BondStore, ModelColumnsJoinTheRegistryAndGrowWithTheBonds) {
  BondStore b;
  using namespace field_flag;
  b.declare_model_columns({{"plastic_x", kMigrate | kCheckpoint}, {"work", kOutput}});
  ASSERT_EQ(b.n_model_columns(), 2u);
  for (std::int64_t k = 0; k < 3; ++k)
    b.append(10 + k, k, k + 1, 0);
  EXPECT_EQ(b.model_column(0).size(), 3u);
  EXPECT_EQ(b.model_column(1).size(), 3u);
  b.model_column(0)[2] = 4.5;
  // The registry lists them last, with their flags, and hands out the very vectors.
  std::vector<std::string> names;
  unsigned flags_of_work = 0;
  double seen = 0.0;
  b.for_each_field([&](const FieldInfo& f, auto& v) {
    names.emplace_back(f.name);
    if (f.name == "work") flags_of_work = f.flags;
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::vector<double>>)
      if (f.name == "plastic_x") seen = v[2];
  });
  ASSERT_GE(names.size(), 2u);
  EXPECT_EQ(names[names.size() - 2], "plastic_x");
  EXPECT_EQ(names.back(), "work");
  EXPECT_EQ(flags_of_work, kOutput);
  EXPECT_EQ(seen, 4.5);
}

TEST(BondStore, ModelColumnsAreRefusedTwiceLateOrUnderACommonName) {
  BondStore b;
  EXPECT_THROW(b.declare_model_columns({{"length0", 0}}), std::invalid_argument);
  BondStore c;
  EXPECT_THROW(c.declare_model_columns({{"x", 0}, {"x", 0}}), std::invalid_argument);
  BondStore d;
  d.append(0, 0, 1, 0);
  EXPECT_THROW(d.declare_model_columns({{"x", 0}}), std::logic_error);
}

// Migration appends the arrivals after the kept rows; a bond that came from both owners of its
// ends arrives twice. Settling keeps one of each gid pair, in ascending (gid_a, gid_b) order,
// with every column (a model column too) moved with its bond.
TEST(BondStore, SettlingArrivalsDropsDuplicatesAndRestoresTheCanonicalOrder) {
  BondStore b;
  b.declare_model_columns({{"state", field_flag::kMigrate}});
  const std::int64_t pairs[][2] = {{2, 5}, {7, 9}, {1, 3}, {7, 9}, {0, 4}, {2, 5}};
  for (std::size_t k = 0; k < 6; ++k) {
    const std::size_t row =
        b.append(static_cast<std::int64_t>(100 + k), pairs[k][0], pairs[k][1], 0);
    b.model_column(0)[row] = static_cast<double>(pairs[k][0] * 10 + pairs[k][1]);
  }
  b.settle_arrivals(2);  // rows 0 and 1 were kept, 2..5 arrived
  ASSERT_EQ(b.size(), 4u);
  const std::int64_t expected[][2] = {{0, 4}, {1, 3}, {2, 5}, {7, 9}};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(b.gid_a[k], expected[k][0]) << k;
    EXPECT_EQ(b.gid_b[k], expected[k][1]) << k;
    EXPECT_EQ(b.model_column(0)[k], static_cast<double>(expected[k][0] * 10 + expected[k][1]));
    EXPECT_EQ(b.index_a.size(), b.size());
  }
  // The kept rows win over their duplicate arrivals: (2, 5) keeps id 100, (7, 9) id 101.
  EXPECT_EQ(b.id[2], 100);
  EXPECT_EQ(b.id[3], 101);
}

// Settling against an independent reference (a map of gid pairs, first row wins, in key order)
// on random rounds: held rows in canonical order (a rebuild's usual case, settled by merging
// the sorted arrivals in) and held rows out of order (after a checkpoint is read back), with
// arrivals that repeat each other and the held rows, and rounds with no arrivals at all.
TEST(BondStore, SettlingMatchesAFirstRowWinsReferenceInOrderOrNot) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::int64_t> gid(0, 40);
  for (int round = 0; round < 200; ++round) {
    const bool held_sorted = round % 2 == 0;
    const std::size_t n_arrivals = round % 5 == 0 ? 0 : static_cast<std::size_t>(round % 13);
    std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> held;
    while (held.size() < static_cast<std::size_t>(round % 17)) {
      const std::int64_t a = gid(rng), b = gid(rng);
      if (a < b) held.emplace(std::make_pair(a, b), static_cast<std::int64_t>(held.size()));
    }
    std::vector<std::pair<std::int64_t, std::int64_t>> rows;
    for (const auto& [key, unused] : held)
      rows.push_back(key);
    if (!held_sorted) std::shuffle(rows.begin(), rows.end(), rng);
    const std::size_t first = rows.size();
    while (rows.size() < first + n_arrivals) {
      const std::int64_t a = gid(rng), b = gid(rng);
      if (a < b) rows.emplace_back(a, b);
    }
    BondStore store;
    store.declare_model_columns({{"state", field_flag::kMigrate}});
    std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> reference;  // key -> id
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const auto id = static_cast<std::int64_t>(1000 * round + static_cast<int>(k));
      const std::size_t row = store.append(id, rows[k].first, rows[k].second, 0);
      store.model_column(0)[row] = 0.5 * static_cast<double>(id);
      reference.emplace(rows[k], id);
    }
    store.settle_arrivals(first);
    ASSERT_EQ(store.size(), reference.size()) << "round " << round;
    std::size_t k = 0;
    for (const auto& [key, id] : reference) {
      EXPECT_EQ(store.gid_a[k], key.first) << "round " << round << " row " << k;
      EXPECT_EQ(store.gid_b[k], key.second) << "round " << round << " row " << k;
      EXPECT_EQ(store.id[k], id) << "round " << round << " row " << k;
      EXPECT_EQ(store.model_column(0)[k], 0.5 * static_cast<double>(id));
      ++k;
    }
    EXPECT_EQ(store.index_a.size(), store.size());
  }
}

// A row counts on the rank that owns its first end: not where that end is a ghost or absent,
// whatever the second end is. A spring's rigid-body partner is no particle.
TEST(PairStore, ARowCountsWhereItsFirstEndIsOwned) {
  ParticleStore p;
  for (std::int64_t g : {4, 8}) {
    ParticleStore::NewParticle np;
    np.gid = g;
    np.radius = 0.01;
    np.density = 1000.0;
    p.add(np);
  }
  p.resize_ghosts(1);
  p.gid[2] = 6;  // a ghost
  p.rebuild_index();
  BondStore b;
  b.append(0, 4, 6, 0);  // first end owned, second a ghost
  b.append(1, 6, 8, 0);  // first end a ghost
  b.append(2, 3, 4, 0);  // first end absent
  EXPECT_TRUE(counted_here(p, b, 0));
  EXPECT_FALSE(counted_here(p, b, 1));
  EXPECT_FALSE(counted_here(p, b, 2));

  ContactSpringStore bodies(ContactSpringStore::Partner::kRigidBody);
  bodies.append(8, 0, Vec3{1, 0, 0});
  EXPECT_EQ(bodies.ends(0)[0], 8);
  EXPECT_EQ(bodies.ends(0)[1], -1);
  EXPECT_TRUE(counted_here(p, bodies, 0));
  ContactSpringStore pairs;
  pairs.append(6, 8, Vec3{1, 0, 0});
  EXPECT_EQ(pairs.ends(0)[1], 8);
  EXPECT_FALSE(counted_here(p, pairs, 0));
}

}  // namespace
}  // namespace ringdem
