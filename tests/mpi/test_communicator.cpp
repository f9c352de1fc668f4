// The comm layer's reductions, checked with rank-encoded data (value = rank + 1) against
// closed forms, exactly (integers, or doubles that are exact integers).
#include <gtest/gtest.h>
#include <mpi.h>

#include <numeric>
#include <vector>

#include "comm/Communicator.hpp"

namespace ringdem {
namespace {

class CommunicatorTest : public ::testing::Test {
 protected:
  void SetUp() override { MPI_Comm_dup(MPI_COMM_WORLD, &comm_); }
  void TearDown() override { MPI_Comm_free(&comm_); }
  MPI_Comm comm_ = MPI_COMM_NULL;
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

// Order-independent sum: every rank contributes terms keyed by a global id; the result is
// the same bits as summing all terms in key order on one process, whatever the rank count.
TEST_F(CommunicatorTest, SumByKeyEqualsTheSerialSumInKeyOrder) {
  const Communicator c(comm_);
  const int n_terms = 1000;
  std::vector<double> all(n_terms);
  for (int k = 0; k < n_terms; ++k)
    all[static_cast<std::size_t>(k)] = 1.0 / (k + 1) * (k % 2 ? 1 : -1) * 1e3;
  double serial = 0.0;
  for (double v : all)
    serial += v;
  // Terms dealt out round-robin in reverse, so no rank holds them in key order.
  std::vector<std::int64_t> keys;
  std::vector<double> values;
  for (int k = n_terms - 1; k >= 0; --k)
    if (k % c.size() == c.rank()) {
      keys.push_back(k);
      values.push_back(all[static_cast<std::size_t>(k)]);
    }
  EXPECT_EQ(c.sum_by_key(keys, values), serial);
  // Rank-encoded: each rank adds rank + 1 under key rank.
  EXPECT_EQ(c.sum_by_key({c.rank()}, {c.rank() + 1.0}), c.size() * (c.size() + 1) / 2.0);
}

// Column sums over dense rows: the same bits as summing each column in row order on one
// process; rank-encoded columns give closed forms.
TEST_F(CommunicatorTest, SumColumnsByRowEqualsTheSerialSumInRowOrder) {
  const Communicator c(comm_);
  const std::int64_t n_rows = 1000;
  double serial = 0.0;
  for (std::int64_t k = 0; k < n_rows; ++k)
    serial += 1e3 / static_cast<double>(k + 1) * (k % 2 ? 1 : -1);
  std::vector<std::int64_t> rows;
  std::vector<double> harmonic, row_plus_one, owner;
  for (std::int64_t k = n_rows - 1; k >= 0; --k)  // reverse round-robin: no rank in row order
    if (k % c.size() == c.rank()) {
      rows.push_back(k);
      harmonic.push_back(1e3 / static_cast<double>(k + 1) * (k % 2 ? 1 : -1));
      row_plus_one.push_back(static_cast<double>(k + 1));
      owner.push_back(c.rank() + 1.0);
    }
  const auto sums = c.sum_columns_by_row(rows, n_rows, {&harmonic, &row_plus_one, &owner});
  ASSERT_EQ(sums.size(), 3u);
  EXPECT_EQ(sums[0], serial);
  EXPECT_EQ(sums[1], n_rows * (n_rows + 1) / 2.0);
  // Row k is held by rank k mod P, which adds rank + 1.
  double expected_owner = 0.0;
  for (std::int64_t k = 0; k < n_rows; ++k)
    expected_owner += static_cast<double>(k % c.size() + 1);
  EXPECT_EQ(sums[2], expected_owner);
  EXPECT_EQ(sums[0], c.sum_by_key(rows, harmonic)) << "both orders are row order";
  const std::vector<double> one{1.0};  // every rank throws before the collective
  EXPECT_THROW(c.sum_columns_by_row({n_rows}, n_rows, {&one}), std::invalid_argument);
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

}  // namespace
}  // namespace ringdem
