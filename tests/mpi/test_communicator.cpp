// The comm layer's reductions, checked with rank-encoded data (value = rank + 1) against
// closed forms and serial references, exactly.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "SharedTempDir.hpp"
#include "comm/Communicator.hpp"

namespace ringdem {
namespace {

class CommunicatorTest : public ::testing::Test {
 protected:
  testing::WorldCopy world_;
  MPI_Comm comm_ = world_.raw();
};

TEST_F(CommunicatorTest, RankAndSizeFromTheInjectedCommunicator) {
  int rank = -1, size = -1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &size);
  const Communicator c(comm_);
  EXPECT_EQ(c.rank(), rank);
  EXPECT_EQ(c.size(), size);
  EXPECT_EQ(c.is_root(), rank == 0);
}

TEST_F(CommunicatorTest, MinMaxSumOfRankEncodedValues) {
  const Communicator c(comm_);
  const std::int64_t n = c.size();
  const std::int64_t mine = c.rank() + 1;
  EXPECT_EQ(c.sum(mine), n * (n + 1) / 2);
  EXPECT_EQ(c.min(mine), 1);
  EXPECT_EQ(c.max(mine), n);
  EXPECT_EQ(c.min(static_cast<double>(mine)), 1.0);
  EXPECT_EQ(c.max(static_cast<double>(mine)), static_cast<double>(n));
  // Negative values: min must not be max (a reduce_min that used MPI_MAX once shipped).
  EXPECT_EQ(c.min(-static_cast<double>(mine)), -static_cast<double>(n));
  EXPECT_EQ(c.max(-mine), std::int64_t{-1});
}

TEST_F(CommunicatorTest, AnyIsTrueWhenOneRankSaysSo) {
  const Communicator c(comm_);
  EXPECT_FALSE(c.any(false));
  EXPECT_TRUE(c.any(true));
  EXPECT_TRUE(c.any(c.rank() == c.size() - 1));
}

// Exact sums over the ranks (ExactSum + one all-reduce): the terms are dealt out so that each
// rank count splits them differently, and the result must equal a serial reference that does
// not depend on the rank count, so the bits are the same at 1, 2 and 3 ranks.
TEST_F(CommunicatorTest, ExactSumsDoNotDependOnTheRankCount) {
  __extension__ typedef __int128 Int128;
  const Communicator c(comm_);
  const int n_terms = 3000;
  // The same terms on every rank (one seed): multiples of 2^-40 below 2^60 of both signs, whose
  // exact sum, scaled by 2^40, a 128-bit integer holds (the serial reference).
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> mant(1.0, 2.0);
  std::uniform_int_distribution<int> expo(-30, 59);
  std::vector<double> all(n_terms);
  Int128 scaled = 0;
  for (auto& x : all) {
    x = std::ldexp(std::nearbyint(std::ldexp(mant(rng), expo(rng) + 40)), -40) *
        (rng() % 2 ? 1.0 : -1.0);
    scaled += static_cast<Int128>(std::ldexp(x, 40));
  }
  const double reference = std::ldexp(static_cast<double>(scaled), -40);
  // Reverse round-robin: each rank count gives every rank other terms in another order.
  std::vector<double> mine, owner;
  for (int k = n_terms - 1; k >= 0; --k)
    if (k % c.size() == c.rank()) {
      mine.push_back(all[static_cast<std::size_t>(k)]);
      owner.push_back(c.rank() + 1.0);
    }
  // Rank-encoded cancellation: rank 0 adds 1e16, every rank adds (rank + 1) 2^-1074, the last
  // rank adds -1e16: P (P + 1) / 2 2^-1074 exactly, which plain summation would lose.
  std::vector<double> cancel{(c.rank() + 1) * std::numeric_limits<double>::denorm_min()};
  if (c.rank() == 0) cancel.push_back(1e16);
  if (c.rank() == c.size() - 1) cancel.push_back(-1e16);
  const auto sums = c.sum_columns({&mine, &owner, &cancel});
  ASSERT_EQ(sums.size(), 3u);
  EXPECT_EQ(sums[0], reference);
  // Term k is held by rank k mod P, which adds rank + 1: an exact integer sum.
  double expected_owner = 0.0;
  for (int k = 0; k < n_terms; ++k)
    expected_owner += static_cast<double>(k % c.size() + 1);
  EXPECT_EQ(sums[1], expected_owner);
  EXPECT_EQ(sums[2], c.size() * (c.size() + 1) / 2 * std::numeric_limits<double>::denorm_min());
  // The same through partial ExactSums, and an empty rank contributes nothing.
  std::vector<ExactSum> partial(2);
  for (double x : mine)
    partial[0].add(x);
  if (c.rank() == c.size() - 1) partial[1].add(std::numeric_limits<double>::infinity());
  const auto again = c.sum_exact(partial);
  EXPECT_EQ(again[0], reference);
  EXPECT_EQ(again[1], std::numeric_limits<double>::infinity());
  EXPECT_TRUE(c.sum_exact({}).empty());
}

TEST_F(CommunicatorTest, AllgatherConcatenatesInRankOrderAlsoWhenEmpty) {
  const Communicator c(comm_);
  // Rank r contributes r copies of r + 1: rank 0 nothing (on 1 rank the gather is empty).
  const std::vector<int> mine(static_cast<std::size_t>(c.rank()), c.rank() + 1);
  std::vector<int> expected;
  for (int r = 0; r < c.size(); ++r)
    expected.insert(expected.end(), static_cast<std::size_t>(r), r + 1);
  EXPECT_EQ(c.allgather(mine), expected);
  // Nothing anywhere: an empty result, and no memcpy from a null pointer (UBSan, asan preset).
  EXPECT_TRUE(c.allgather(std::vector<double>{}).empty());
}

TEST_F(CommunicatorTest, SplitGroupsTheRanksOfAColourInRankOrder) {
  const Communicator c(comm_);
  // Groups of two consecutive ranks (the last one alone on an odd count), as a sweep's
  // --ranks-per-case 2 makes them.
  const SplitCommunicator split(c, c.rank() / 2);
  const Communicator& group = split.get();
  const int first = c.rank() - c.rank() % 2;
  const int members = std::min(2, c.size() - first);
  EXPECT_EQ(group.size(), members);
  EXPECT_EQ(group.rank(), c.rank() - first);
  // Rank-encoded: each group sums its own members' world ranks, and only theirs.
  std::int64_t expected = 0;
  for (int r = first; r < first + members; ++r)
    expected += 100 + r;
  EXPECT_EQ(group.sum(std::int64_t{100} + c.rank()), expected);
  std::vector<std::int64_t> from_first{c.rank()};
  group.broadcast(from_first, 0);
  EXPECT_EQ(from_first, std::vector<std::int64_t>{first});
}

}  // namespace
}  // namespace ringdem
