// comm/RowBlocks with sparse keys (gids of several sources, bond ids): each key's row is its
// position among all keys in increasing order, whatever the rank count and however the keys
// are spread, checked against a brute-force reference (every key gathered and sorted).
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "SharedTempDir.hpp"
#include "comm/RowBlocks.hpp"

namespace ringdem {
namespace {

class RowBlocksTest : public ::testing::Test {
 protected:
  testing::WorldCopy world_;
  MPI_Comm comm_ = world_.raw();
};

/// The same sparse, duplicate-free keys on every rank (one seed): a few dense runs with gaps
/// (one gid range per source), scattered keys, negative ones, and keys near the int64 limits.
std::vector<std::int64_t> global_keys() {
  std::mt19937_64 rng(23);
  std::vector<std::int64_t> keys;
  for (std::int64_t start : {std::int64_t{0}, std::int64_t{1000}, std::int64_t{1} << 40})
    for (std::int64_t k = 0; k < 300; ++k)
      keys.push_back(start + k);
  std::uniform_int_distribution<std::int64_t> any(-(std::int64_t{1} << 50), std::int64_t{1} << 50);
  for (int k = 0; k < 700; ++k)
    keys.push_back(any(rng));
  keys.push_back(std::numeric_limits<std::int64_t>::max());
  keys.push_back(std::numeric_limits<std::int64_t>::min() + 1);
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::shuffle(keys.begin(), keys.end(), rng);
  return keys;
}

/// The value a key's item carries: two words, so that to_blocks moves more than 8 bytes.
struct Item {
  std::int64_t key;
  double value;
};

Item item_of(std::int64_t key) {
  return {key, static_cast<double>(key % 1000) * 0.5};
}

void expect_matches_reference(const Communicator& c, const std::vector<std::int64_t>& mine,
                              const RowBlocks& blocks) {
  // Brute force: every key on every rank, sorted.
  std::vector<std::int64_t> all = c.allgather(mine);
  std::sort(all.begin(), all.end());
  const auto n = static_cast<std::int64_t>(all.size());
  ASSERT_EQ(blocks.n_rows(), n);
  const auto row_of = [&](std::int64_t key) {
    return std::lower_bound(all.begin(), all.end(), key) - all.begin();
  };
  ASSERT_EQ(blocks.local_rows().size(), mine.size());
  for (std::size_t i = 0; i < mine.size(); ++i)
    EXPECT_EQ(blocks.local_rows()[i], row_of(mine[i])) << "key " << mine[i];
  // Equal blocks in rank order, the same as for dense rows.
  EXPECT_EQ(blocks.first_row(), n * c.rank() / c.size());
  EXPECT_EQ(blocks.block_size(), n * (c.rank() + 1) / c.size() - n * c.rank() / c.size());
  const std::vector<std::int64_t> expected_keys(
      all.begin() + blocks.first_row(), all.begin() + blocks.first_row() + blocks.block_size());
  EXPECT_EQ(blocks.block_keys(), expected_keys);
  std::vector<Item> items;
  for (std::int64_t k : mine)
    items.push_back(item_of(k));
  const std::vector<Item> block = blocks.to_blocks(items);
  ASSERT_EQ(block.size(), expected_keys.size());
  for (std::size_t j = 0; j < block.size(); ++j) {
    EXPECT_EQ(block[j].key, expected_keys[j]);
    EXPECT_EQ(block[j].value, item_of(expected_keys[j]).value);
  }
  // rows_of: every rank asks for keys held anywhere (its neighbour's among them), and for
  // keys that are not there.
  std::vector<std::int64_t> asked;
  for (std::size_t j = static_cast<std::size_t>(c.rank()); j < all.size(); j += 7)
    asked.push_back(all[j]);
  asked.push_back(all.empty() ? 5 : all.front() - 1);
  asked.push_back(all.empty()                                              ? 6
                  : all.back() == std::numeric_limits<std::int64_t>::max() ? all.back() - 1000000
                                                                           : all.back() + 1);
  const std::vector<std::int64_t> rows = blocks.rows_of(asked);
  ASSERT_EQ(rows.size(), asked.size());
  for (std::size_t j = 0; j < asked.size(); ++j) {
    const bool present = std::binary_search(all.begin(), all.end(), asked[j]);
    EXPECT_EQ(rows[j], present ? row_of(asked[j]) : -1) << "key " << asked[j];
  }
}

TEST_F(RowBlocksTest, SparseKeysDealtUnevenlyWithAnEmptyRank) {
  const Communicator c(comm_);
  const std::vector<std::int64_t> keys = global_keys();
  // Dealt by a hash of the key: with more than one rank the last rank holds none and rank 0 a
  // double share.
  const int holders = c.size() > 1 ? c.size() - 1 : 1;
  std::vector<std::int64_t> mine;
  for (std::int64_t k : keys) {
    const auto h = static_cast<int>((static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15ull) >> 33);
    int r = h % (holders + 1);
    if (r == holders) r = 0;
    if (r == c.rank()) mine.push_back(k);
  }
  const RowBlocks blocks(c, mine);
  expect_matches_reference(c, mine, blocks);
}

TEST_F(RowBlocksTest, AllKeysOnOneRankAndDenseKeys) {
  const Communicator c(comm_);
  std::vector<std::int64_t> mine;
  if (c.rank() == 0) mine = global_keys();
  expect_matches_reference(c, mine, RowBlocks(c, mine));
  // Dense keys 0..n-1 dealt round-robin in reverse: every key is its own row.
  std::vector<std::int64_t> dense;
  for (std::int64_t k = 999; k >= 0; --k)
    if (k % c.size() == c.rank()) dense.push_back(k);
  const RowBlocks d(c, dense);
  for (std::size_t i = 0; i < dense.size(); ++i)
    EXPECT_EQ(d.local_rows()[i], dense[i]);
  expect_matches_reference(c, dense, d);
}

TEST_F(RowBlocksTest, NoKeysAnywhere) {
  const Communicator c(comm_);
  const RowBlocks blocks(c, {});
  EXPECT_EQ(blocks.n_rows(), 0);
  EXPECT_EQ(blocks.block_size(), 0);
  EXPECT_TRUE(blocks.to_blocks(std::vector<double>{}).empty());
  EXPECT_EQ(blocks.rows_of({3}), std::vector<std::int64_t>{-1});
}

TEST_F(RowBlocksTest, AKeyHeldTwiceIsRefusedOnEveryRank) {
  const Communicator c(comm_);
  // Key 42 on the first and the last rank (the same rank twice at one rank).
  std::vector<std::int64_t> mine{100 + c.rank()};
  if (c.rank() == 0) mine.push_back(42);
  if (c.rank() == c.size() - 1) mine.push_back(42);
  EXPECT_THROW(RowBlocks(c, mine), std::runtime_error);
}

}  // namespace
}  // namespace ringdem
