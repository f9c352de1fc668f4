// The flat gid -> index table against std::unordered_map as the reference: sparse and dense
// gids, runs of consecutive gids at far-apart bases and below zero, growth past the initial size, a
// later index of a gid replacing the earlier one, and stale entries of a shrunk column matching
// nothing.
#include <gtest/gtest.h>

#include <random>
#include <unordered_map>
#include <vector>

#include "domain/GidIndex.hpp"

namespace ringdem {
namespace {

TEST(GidIndex, AgreesWithUnorderedMap) {
  std::mt19937_64 rng(5);
  std::vector<std::int64_t> gids;
  for (int k = 0; k < 5000; ++k)
    gids.push_back(k % 3 == 0 ? static_cast<std::int64_t>(rng() >> 2) : 7 * k);
  // Runs of consecutive gids, as sources hand them out, at far-apart bases (the table keeps a
  // run's gids on one cache line; runs of different sources must not pile onto the same
  // lines), and one run below zero.
  for (std::int64_t base : {std::int64_t{1} << 40, std::int64_t{2} << 40, std::int64_t{3} << 40,
                            -(std::int64_t{1} << 40) - 37})
    for (std::int64_t k = 0; k < 3000; ++k)
      gids.push_back(base + k);
  for (int k = 0; k < 300; ++k)  // repeats: the later index wins
    gids.push_back(gids[static_cast<std::size_t>(k * 11)]);
  GidIndex index;
  index.reset(100);  // sized too small: must grow
  std::unordered_map<std::int64_t, std::int64_t> reference;
  for (std::uint32_t i = 0; i < gids.size(); ++i) {
    index.set(i, gids.data(), gids.size());
    reference[gids[i]] = i;
  }
  EXPECT_EQ(index.size(), reference.size());
  for (const auto& [gid, i] : reference)
    EXPECT_EQ(index.find(gid, gids.data(), gids.size()), i) << "gid " << gid;
  for (std::int64_t absent : {std::int64_t{1}, std::int64_t{8}, std::int64_t{7 * 5001},
                              (std::int64_t{1} << 40) + 3000, (std::int64_t{4} << 40)})
    EXPECT_EQ(index.find(absent, gids.data(), gids.size()), -1);
  // The column shrinks without a reset: entries past its end match nothing.
  gids.resize(1000);
  EXPECT_EQ(index.find(7 * 2000 + 7, gids.data(), gids.size()), -1);
  EXPECT_EQ(index.find(gids[500], gids.data(), gids.size()),
            reference.count(gids[500]) && reference[gids[500]] < 1000 ? reference[gids[500]] : -1);
}

// The table's size: the fewest power-of-two slots that hold the entries at most three quarters
// full, whether sized up front (reset) or grown insert by insert; 10^6 grains take 2^21 slots
// (8 MiB), not the 2^22 of a table at most half full (docs/performance.md, forty-fifth round).
TEST(GidIndex, HoldsItsEntriesAtMostThreeQuartersFull) {
  for (const std::size_t n : {std::size_t{1}, std::size_t{23}, std::size_t{24}, std::size_t{25},
                              std::size_t{1000}, std::size_t{1064800}}) {
    std::vector<std::int64_t> gids(n);
    for (std::size_t k = 0; k < n; ++k)
      gids[k] = static_cast<std::int64_t>(3 * k + 11);
    // The smallest power of two of at least 32 slots (two cache lines) with 4 n <= 3 slots.
    std::size_t expected = 32;
    while (4 * n > 3 * expected)
      expected *= 2;
    GidIndex sized, grown;
    sized.reset(n);
    grown.reset(0);
    for (std::uint32_t i = 0; i < n; ++i) {
      sized.set(i, gids.data(), n);
      grown.set(i, gids.data(), n);
    }
    EXPECT_EQ(sized.capacity(), expected) << n << " entries, sized up front";
    EXPECT_EQ(grown.capacity(), expected) << n << " entries, grown";
    ASSERT_EQ(grown.size(), n);
    for (std::size_t k = 0; k < n; k += 1 + n / 97)
      EXPECT_EQ(grown.find(gids[k], gids.data(), n), static_cast<std::int64_t>(k));
  }
  EXPECT_EQ(std::size_t{1} << 21, [] {
    GidIndex index;
    index.reset(1064800);
    return index.capacity();
  }());
}

}  // namespace
}  // namespace ringdem
