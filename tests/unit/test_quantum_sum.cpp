// The quantised sum (comm/QuantumSum) against independent references: the compiler's own
// 128-bit integer sum of the rounded terms, converted to double by the compiler (one rounding),
// against the three-part exact flush; the same bits in any order and over any split; terms too
// large or not finite left to the exact sum; and the distance from the exact sum of the
// unrounded terms, at most half a quantum a term.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "comm/ExactSum.hpp"
#include "comm/QuantumSum.hpp"

namespace ringdem {
namespace {

__extension__ typedef __int128 Int128;

constexpr double kQuantum = QuantumSum::kQuantum;

/// The flushed value of the terms in the given order, split into `parts` quantised sums.
double quantum_sum(const std::vector<double>& v, int parts = 1) {
  ExactSum exact;
  std::vector<QuantumSum> sums(static_cast<std::size_t>(parts));
  for (std::size_t i = 0; i < v.size(); ++i)
    sums[i % sums.size()].add(v[i], exact);
  for (QuantumSum& s : sums)
    s.flush_into(exact);
  return exact.value();
}

/// The reference: each term rounded to quanta by the library's llrint, summed in the
/// compiler's 128-bit integers, and the total converted to double in one rounding.
double reference(const std::vector<double>& v) {
  Int128 total = 0;
  for (double x : v)
    total += static_cast<Int128>(std::llrint(std::ldexp(x, 50)));
  return static_cast<double>(total) * kQuantum;
}

std::vector<double> powers(std::size_t n, unsigned seed) {
  // Powers of a grain's contacts: of either sign, from 1e-12 to 100 W.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> exponent(-12.0, 2.0);
  std::bernoulli_distribution negative(0.5);
  std::vector<double> v(n);
  for (double& x : v)
    x = (negative(rng) ? -1.0 : 1.0) * std::pow(10.0, exponent(rng));
  return v;
}

TEST(QuantumSum, EqualsTheIntegerSumOfTheRoundedTermsRoundedOnce) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<double> v = powers(100000, seed);
    EXPECT_EQ(quantum_sum(v), reference(v)) << "seed " << seed;
  }
  // A total that needs all three parts of the flush: 2^61 quanta (2048) a term, 64 times.
  const std::vector<double> big(64, 2048.0);
  EXPECT_EQ(quantum_sum(big), 64 * 2048.0);
  EXPECT_EQ(quantum_sum(big), reference(big));
}

TEST(QuantumSum, NegativeTotalsFlushExactly) {
  // A negative integer's parts carry -1 upward: the flush must still add exactly the total.
  EXPECT_EQ(quantum_sum({-5 * kQuantum}), -5 * kQuantum);
  EXPECT_EQ(quantum_sum({-kQuantum, -kQuantum}), -2 * kQuantum);
  const std::vector<double> v{-1.0, -1e-9, 3e-15, -2048.0};
  EXPECT_EQ(quantum_sum(v), reference(v));
  const std::vector<double> w = powers(5000, 9);
  std::vector<double> negated(w.size());
  std::transform(w.begin(), w.end(), negated.begin(), [](double x) { return -x; });
  EXPECT_EQ(quantum_sum(negated), -quantum_sum(w));
}

TEST(QuantumSum, TheSameBitsInAnyOrderAndOverAnySplit) {
  std::vector<double> v = powers(20000, 4);
  const double first = quantum_sum(v);
  std::mt19937_64 rng(5);
  for (int parts : {1, 2, 3, 7}) {
    std::shuffle(v.begin(), v.end(), rng);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(quantum_sum(v, parts)),
              std::bit_cast<std::uint64_t>(first))
        << parts << " parts";
  }
}

TEST(QuantumSum, LargeAndNonFiniteTermsGoToTheExactSum) {
  // 1e4 W is beyond 2^62 quanta (4096 W): added to the exact sum as it is, not rounded.
  const double large = 1e4 + 0.1;
  ExactSum exact;
  QuantumSum q;
  q.add(large, exact);
  EXPECT_TRUE(q.is_zero());
  q.add(3 * kQuantum, exact);
  q.flush_into(exact);
  ExactSum expected;
  expected.add(large);
  expected.add(3 * kQuantum);
  EXPECT_EQ(exact.value(), expected.value());
  // Which path a term takes depends on its value alone: on either side of the limit.
  EXPECT_EQ(quantum_sum({4095.0, -4095.0, 4097.0, -4097.0}), 0.0);
  ExactSum with_nan;
  QuantumSum n;
  n.add(std::numeric_limits<double>::quiet_NaN(), with_nan);
  n.flush_into(with_nan);
  EXPECT_FALSE(with_nan.is_finite());
  EXPECT_TRUE(std::isnan(with_nan.value()));
}

TEST(QuantumSum, WithinHalfAQuantumATermOfTheExactSum) {
  const std::vector<double> v = powers(100000, 6);
  ExactSum exact;
  for (double x : v)
    exact.add(x);
  const double bound = 0.5 * kQuantum * static_cast<double>(v.size());
  EXPECT_LE(std::fabs(quantum_sum(v) - exact.value()), bound + 1e-15 * std::fabs(exact.value()));
  // and not equal to it: the terms are rounded (the test would pass an exact sum, too, but the
  // comparison above would then be meaningless).
  EXPECT_NE(quantum_sum({0.3 * kQuantum}), 0.3 * kQuantum);
}

}  // namespace
}  // namespace ringdem
