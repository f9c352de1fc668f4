// ExactSumReducer against the full reduction (Communicator::sum_exact) with rank-encoded
// terms: the same bits on every call, the window learnt once and widened only when a sum does
// not fit it, and NaN, infinities and zeros as the full reduction gives them.
#include <gtest/gtest.h>
#include <mpi.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "SharedTempDir.hpp"
#include "comm/Communicator.hpp"
#include "comm/ExactSumReducer.hpp"

namespace ringdem {
namespace {

class ExactSumReducerTest : public ::testing::Test {
 protected:
  testing::WorldCopy world_;
  MPI_Comm comm_ = world_.raw();
};

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

/// Six sums of this rank's terms, like a body's load columns: `terms` values of magnitude
/// about 2^scale, signs and mantissas drawn from (seed, rank, column), some columns of mixed
/// signs that nearly cancel.
std::vector<ExactSum> rank_sums(int rank, std::uint64_t seed, int scale, int terms) {
  std::vector<ExactSum> sums(6);
  for (int c = 0; c < 6; ++c) {
    std::mt19937_64 rng(seed * 1000003u + static_cast<std::uint64_t>(rank) * 101u +
                        static_cast<std::uint64_t>(c));
    std::uniform_real_distribution<double> mantissa(1.0, 2.0);
    std::uniform_int_distribution<int> spread(-30, 0);
    for (int k = 0; k < terms; ++k) {
      const double sign = c == 5 ? (k % 2 == 0 ? 1.0 : -1.0) : (rng() % 3 == 0 ? -1.0 : 1.0);
      sums[static_cast<std::size_t>(c)].add(sign * std::ldexp(mantissa(rng), scale + spread(rng)));
    }
  }
  return sums;
}

void expect_same_bits(const std::vector<double>& got, const std::vector<double>& want,
                      const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t c = 0; c < got.size(); ++c)
    EXPECT_EQ(bits(got[c]), bits(want[c])) << what << ", column " << c;
}

TEST_F(ExactSumReducerTest, SameBitsAsTheFullReductionAndTheWindowIsLearntOnce) {
  const Communicator comm(comm_);
  ExactSumReducer reducer;
  EXPECT_EQ(reducer.window_limbs(), 0);
  // Loads of about 2^10 (a kN): the first call learns the window, the next 20 fit it.
  for (std::uint64_t step = 0; step < 21; ++step) {
    const auto partial = rank_sums(comm.rank(), step, 10, 5 + comm.rank());
    expect_same_bits(reducer.sum(comm, partial), comm.sum_exact(partial), "kN loads");
  }
  EXPECT_EQ(reducer.fallbacks(), 1);
  // A window of a few limbs, not the 68 of the full words.
  EXPECT_GT(reducer.window_limbs(), 0);
  EXPECT_LE(reducer.window_limbs(), 6);
  // The same magnitudes negated: balanced digits are as short for either sign.
  for (std::uint64_t step = 0; step < 5; ++step) {
    std::vector<ExactSum> partial = rank_sums(comm.rank(), step, 10, 3);
    for (ExactSum& s : partial)
      s = s.negated();
    expect_same_bits(reducer.sum(comm, partial), comm.sum_exact(partial), "negated loads");
  }
  EXPECT_EQ(reducer.fallbacks(), 1);
  // A larger load on one rank only: every rank falls back once and widens the window.
  const int width = reducer.window_limbs();
  std::vector<ExactSum> partial = rank_sums(comm.rank(), 99, 10, 4);
  if (comm.rank() == comm.size() - 1) partial[2].add(std::ldexp(1.0, 300));
  expect_same_bits(reducer.sum(comm, partial), comm.sum_exact(partial), "one large load");
  EXPECT_EQ(reducer.fallbacks(), 2);
  EXPECT_GT(reducer.window_limbs(), width);
  expect_same_bits(reducer.sum(comm, partial), comm.sum_exact(partial), "the same again");
  EXPECT_EQ(reducer.fallbacks(), 2);
}

TEST_F(ExactSumReducerTest, ZerosCancellationsAndNonFiniteSums) {
  const Communicator comm(comm_);
  ExactSumReducer reducer;
  // Nothing to sum anywhere: +0 without a fallback, with an empty window.
  std::vector<ExactSum> zeros(6);
  expect_same_bits(reducer.sum(comm, zeros), comm.sum_exact(zeros), "zeros");
  EXPECT_EQ(reducer.fallbacks(), 0);
  // Terms that cancel over the ranks: rank r adds r + 1 and, at the last rank, minus the
  // total; the sum is +0 with a window learnt from nonzero partial sums.
  std::vector<ExactSum> cancel(2);
  const int n = comm.size();
  cancel[0].add(0.1 * (comm.rank() + 1));
  cancel[1].add(1e-3);
  if (comm.rank() == n - 1)
    for (int r = 0; r < n; ++r)
      cancel[0].add(-0.1 * (r + 1));
  const auto once = reducer.sum(comm, cancel);
  expect_same_bits(once, comm.sum_exact(cancel), "cancellation");
  expect_same_bits(reducer.sum(comm, cancel), once, "cancellation, in the window");
  EXPECT_EQ(reducer.fallbacks(), 1);
  // A NaN on one rank, an infinity on another: the full reduction's IEEE results.
  std::vector<ExactSum> odd(3);
  odd[0].add(1.0);
  if (comm.rank() == 0) odd[1].add(std::numeric_limits<double>::quiet_NaN());
  if (comm.rank() == n - 1) odd[2].add(-std::numeric_limits<double>::infinity());
  const auto got = reducer.sum(comm, odd);
  EXPECT_EQ(got[0], static_cast<double>(n));
  EXPECT_TRUE(std::isnan(got[1]));
  EXPECT_EQ(got[2], -std::numeric_limits<double>::infinity());
  EXPECT_EQ(reducer.fallbacks(), 2);
}

}  // namespace
}  // namespace ringdem
