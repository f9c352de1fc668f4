// The exact sum (comm/ExactSum) against independent references: sums known in closed form
// (cancellations that plain summation gets wrong, subnormals, ties of the final rounding,
// overflow, NaN and infinities), a 128-bit integer fixed-point sum converted by the compiler,
// and a sorted quad-precision sum; and the same bits whatever the order or the split.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "comm/ExactSum.hpp"

namespace ringdem {
namespace {

__extension__ typedef __int128 Int128;
__extension__ typedef __float128 Quad;

double exact_sum(const std::vector<double>& v) {
  ExactSum s;
  for (double x : v)
    s.add(x);
  return s.value();
}

/// Bits of a double, for bitwise comparisons that tell +0 from -0 and NaN from NaN.
std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

TEST(ExactSum, CancellationsThatPlainSummationLoses) {
  EXPECT_EQ(exact_sum({1e16, 1.0, -1e16}), 1.0);  // plain: 0
  EXPECT_EQ(exact_sum({1.0, 1e100, 1.0, -1e100}), 2.0);
  EXPECT_EQ(exact_sum({DBL_MAX, DBL_MAX, -DBL_MAX}), DBL_MAX);  // no intermediate overflow
  EXPECT_EQ(exact_sum({1e308, 1e-308, -1e308}), 1e-308);
  EXPECT_EQ(exact_sum({}), 0.0);
  EXPECT_EQ(exact_sum({0.1, -0.1}), 0.0);
  // +x and -x pairs over the whole exponent range with residues k 2^-1074 in between: the
  // sum is the residues' sum, 15 2^-1074, exactly.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mant(1.0, 2.0);
  std::uniform_int_distribution<int> expo(-1070, 1020);
  std::vector<double> v;
  for (int k = 0; k < 2000; ++k) {
    const double x = std::ldexp(mant(rng), expo(rng));
    v.push_back(x);
    v.push_back(-x);
  }
  for (int k = 1; k <= 5; ++k)
    v.push_back(k * std::numeric_limits<double>::denorm_min());
  std::shuffle(v.begin(), v.end(), rng);
  EXPECT_EQ(exact_sum(v), 15 * std::numeric_limits<double>::denorm_min());
}

TEST(ExactSum, SubnormalsAndTheNormalBoundary) {
  const double tiny = std::numeric_limits<double>::denorm_min();
  std::vector<double> v(1000, tiny);
  EXPECT_EQ(exact_sum(v), 1000 * tiny);
  EXPECT_EQ(exact_sum({DBL_MIN - tiny, tiny}), DBL_MIN);
  EXPECT_EQ(exact_sum({DBL_MIN, -tiny}), DBL_MIN - tiny);
  EXPECT_EQ(exact_sum({-3 * tiny, tiny}), -2 * tiny);
  // 2^-1022 + 2^-1074 needs 53 bits: exact; 2^-1021 + 2^-1074 is a tie, to even (down).
  EXPECT_EQ(exact_sum({DBL_MIN, tiny}), DBL_MIN + tiny);
  EXPECT_EQ(exact_sum({2 * DBL_MIN, tiny}), 2 * DBL_MIN);
  EXPECT_EQ(exact_sum({2 * DBL_MIN, tiny, tiny, tiny}), 2 * DBL_MIN + 4 * tiny);  // 3 ulp/2: up
}

TEST(ExactSum, RoundsOnceToNearestTiesToEven) {
  const double two53 = 9007199254740992.0;
  EXPECT_EQ(exact_sum({two53, 1.0}), two53);                    // tie, even below
  EXPECT_EQ(exact_sum({two53, 3.0}), two53 + 4.0);              // tie, even above
  EXPECT_EQ(exact_sum({two53, 1.0, 1e-300}), two53 + 2.0);      // sticky bit: above the tie
  EXPECT_EQ(exact_sum({two53, 1.0, -1e-300}), two53);           // just below the tie
  EXPECT_EQ(exact_sum({-two53, -1.0, -1e-300}), -two53 - 2.0);  // symmetric for negatives
  EXPECT_EQ(exact_sum({1.0, std::ldexp(1.0, -53)}), 1.0);
  EXPECT_EQ(exact_sum({1.0, std::ldexp(1.0, -53), std::ldexp(1.0, -1074)}),
            std::nextafter(1.0, 2.0));
  // A sum whose rounding carries into the next binade.
  EXPECT_EQ(exact_sum({two53 - 1.0, 0.5}), two53);
}

TEST(ExactSum, OverflowNanAndInfinities) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(exact_sum({DBL_MAX, DBL_MAX}), inf);
  EXPECT_EQ(exact_sum({-DBL_MAX, -DBL_MAX}), -inf);
  // DBL_MAX + ulp/2 is a tie whose even neighbour is 2^1024: infinity, as IEEE addition.
  EXPECT_EQ(exact_sum({DBL_MAX, std::ldexp(1.0, 970)}), inf);
  EXPECT_EQ(exact_sum({DBL_MAX, std::ldexp(1.0, 969)}), DBL_MAX);
  EXPECT_EQ(exact_sum({1.0, inf, 1e300}), inf);
  EXPECT_EQ(exact_sum({-inf, 1.0}), -inf);
  EXPECT_TRUE(std::isnan(exact_sum({inf, -inf})));
  EXPECT_TRUE(std::isnan(exact_sum({1.0, std::nan(""), 2.0})));
  EXPECT_EQ(bits(exact_sum({-0.0, 0.0})), bits(0.0));
}

/// Random terms that are multiples of 2^-40 below 2^60: their exact sum, scaled by 2^40, fits a
/// 128-bit integer, and the compiler's int128 -> double conversion rounds it to nearest.
TEST(ExactSum, EqualsAn128BitFixedPointReference) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mant(1.0, 2.0);
  std::uniform_int_distribution<int> expo(-30, 59);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> v;
    Int128 scaled = 0;
    for (int k = 0; k < 5000; ++k) {
      // Rounded to a multiple of 2^-40 (exact: a scaling, an integer rounding, a scaling).
      const double x = std::ldexp(std::nearbyint(std::ldexp(mant(rng), expo(rng) + 40)), -40) *
                       (rng() % 2 ? 1 : -1);
      v.push_back(x);
      scaled += static_cast<Int128>(std::ldexp(x, 40));  // exact: an integer below 2^100
    }
    const double reference = std::ldexp(static_cast<double>(scaled), -40);
    EXPECT_EQ(bits(exact_sum(v)), bits(reference)) << "trial " << trial;
  }
}

/// The rounding wherever the sum lies against the 32-bit limbs: a few terms of 53 random bits,
/// multiples of 2^e for e over the whole normal range, against the same 128-bit reference
/// (scaled by 2^-e: the result is normal, so the scaling does not round again). Sums of few
/// long terms put the highest bit, the rounding bit and the sticky bits in every position
/// relative to the limbs, ties included (the last two trials of each e are exact ties).
TEST(ExactSum, RoundsLikeAn128BitReferenceAtEveryLimbOffset) {
  std::mt19937_64 rng(13);
  std::uniform_int_distribution<std::uint64_t> bits53(0, (std::uint64_t{1} << 53) - 1);
  std::uniform_int_distribution<int> offset(0, 60), terms(1, 4);
  for (int e = -1022; e <= 900; e += 7) {
    for (int trial = 0; trial < 6; ++trial) {
      std::vector<double> v;
      Int128 scaled = 0;
      if (trial < 4) {
        for (int k = terms(rng); k > 0; --k) {
          const int o = offset(rng);
          const auto m = static_cast<std::int64_t>(bits53(rng)) * (rng() % 2 ? 1 : -1);
          v.push_back(std::ldexp(static_cast<double>(m), e + o));  // exact: 53 bits
          scaled += static_cast<Int128>(m) << o;
        }
      } else {
        // 2^54 + 1 (+ 2 for the second): halfway between two doubles, to even (down, up).
        const int o = offset(rng);
        v = {std::ldexp(1.0, e + o + 54), std::ldexp(trial == 4 ? 1.0 : 3.0, e + o)};
        scaled = (Int128{1} << (o + 54)) + (static_cast<Int128>(trial == 4 ? 1 : 3) << o);
      }
      const double reference = std::ldexp(static_cast<double>(scaled), e);
      EXPECT_EQ(bits(exact_sum(v)), bits(reference)) << "e " << e << ", trial " << trial;
    }
  }
  // A tie with one sticky bit d below the highest, at all 32 offsets in a limb: the sticky bit
  // in the same limb as the rounding bit or up to three limbs below it (rounds up, not to even).
  for (int d = 60; d <= 120; d += 10)
    for (int e = -900; e < -868; ++e) {
      const std::vector<double> v = {std::ldexp(1.0, e + d), std::ldexp(1.0, e + d - 53),
                                     std::ldexp(1.0, e)};
      const Int128 scaled = (Int128{1} << d) + (Int128{1} << (d - 53)) + 1;
      const double reference = std::ldexp(static_cast<double>(scaled), e);
      EXPECT_EQ(bits(exact_sum(v)), bits(reference)) << "d " << d << ", e " << e;
    }
}

/// Positive terms over 600 binades: a quad-precision sum in increasing order is within
/// 2^-100 of the exact sum relative, so the correctly rounded double is within half an ulp
/// (and a little) of it.
TEST(ExactSum, WithinHalfAnUlpOfASortedQuadSum) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(1.0, 2.0);
  std::uniform_int_distribution<int> expo(-300, 300);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> v;
    for (int k = 0; k < 3000; ++k)
      v.push_back(std::ldexp(mant(rng), expo(rng) - trial % 3 * 20));
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    Quad q = 0;
    for (double x : sorted)
      q += x;
    const double got = exact_sum(v);
    const Quad half_ulp = static_cast<Quad>(std::nextafter(got, DBL_MAX) - got) / 2;
    const Quad err = q > got ? q - got : got - q;
    EXPECT_LE(static_cast<double>(err / half_ulp), 1.0 + 1e-9) << "trial " << trial;
  }
}

TEST(ExactSum, OrderAndSplitDoNotChangeTheBits) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> mant(-2.0, 2.0);
  std::uniform_int_distribution<int> expo(-60, 60);
  std::vector<double> v;
  for (int k = 0; k < 10000; ++k)
    v.push_back(std::ldexp(mant(rng), expo(rng)));
  const double first = exact_sum(v);
  double plain = 0.0, plain_shuffled = 0.0;
  for (double x : v)
    plain += x;
  for (int trial = 0; trial < 5; ++trial) {
    std::shuffle(v.begin(), v.end(), rng);
    EXPECT_EQ(bits(exact_sum(v)), bits(first));
    // Split into three partial sums, merged through the exported words (as the all-reduce).
    ExactSum a, b, c;
    for (std::size_t k = 0; k < v.size(); ++k)
      (k % 3 == 0 ? a : k % 3 == 1 ? b : c).add(v[k]);
    auto words = a.export_words();
    for (const ExactSum* s : {&b, &c}) {
      const auto w = s->export_words();
      for (std::size_t i = 0; i < words.size(); ++i)
        words[i] += w[i];
    }
    EXPECT_EQ(bits(ExactSum::from_words(words.data()).value()), bits(first));
    a += b;
    a += c;
    EXPECT_EQ(bits(a.value()), bits(first));
  }
  for (double x : v)
    plain_shuffled += x;
  // The check has teeth: plain summation does depend on the order here.
  EXPECT_NE(bits(plain), bits(plain_shuffled));
}

// More terms than the carry interval (2^24): 2^25 copies of a full 53-bit mantissa (all
// ones) spread over three digits, so a missed carry would lose bits. The sum is 2^25 x.
TEST(ExactSum, CarriesOverManyTerms) {
  const double x = std::ldexp(9007199254740991.0, 17);  // (2^53 - 1) 2^17
  ExactSum s, neg;
  const int n = 1 << 25;
  for (int k = 0; k < n; ++k) {
    s.add(x);
    neg.add(-x);
  }
  EXPECT_EQ(s.value(), std::ldexp(x, 25));
  EXPECT_EQ(neg.value(), -std::ldexp(x, 25));
  s += neg;
  EXPECT_EQ(s.value(), 0.0);
}

// negated() is the sum of the negated terms: adding it to the original cancels exactly, its
// value is the negated value (also for infinities, which swap), and it agrees with a sum of
// the negated terms to the bit.
TEST(ExactSum, NegatedIsTheSumOfTheNegatedTerms) {
  const std::vector<double> terms = {1e300, 3.0, -1e-300, 0.1, -7.5e-310, 2.0 / 3.0};
  ExactSum s, minus;
  for (double x : terms) {
    s.add(x);
    minus.add(-x);
  }
  const ExactSum n = s.negated();
  EXPECT_EQ(bits(n.value()), bits(minus.value()));
  EXPECT_EQ(n.value(), -s.value());
  ExactSum zero = s;
  zero += n;
  EXPECT_EQ(zero.value(), 0.0);
  ExactSum inf;
  inf.add(std::numeric_limits<double>::infinity());
  EXPECT_EQ(inf.negated().value(), -std::numeric_limits<double>::infinity());
}

// Balanced digits (the few-word form of ExactSumReducer): a sum read back from its digits has
// the same value, a small sum of either sign has the same few nonzero limbs, and digits summed
// limb by limb are the digits of the total.
TEST(ExactSum, BalancedLimbsRoundTripAndAdd) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> mant(-2.0, 2.0);
  std::uniform_int_distribution<int> expo(-1060, 1000), count(1, 40);
  for (int trial = 0; trial < 300; ++trial) {
    ExactSum a, b, total;
    const int e = expo(rng);
    for (int k = count(rng); k > 0; --k) {
      const double x = std::ldexp(mant(rng), e - static_cast<int>(rng() % 40));
      const double y = std::ldexp(mant(rng), e - static_cast<int>(rng() % 40));
      a.add(x);
      b.add(y);
      total.add(x);
      total.add(y);
    }
    std::array<std::int64_t, ExactSum::kLimbs> da{}, db{};
    const auto ra = a.balanced_limbs(da), rb = b.balanced_limbs(db);
    ASSERT_LE(ra.first, ra.last);
    EXPECT_EQ(bits(ExactSum::from_limbs(&da[static_cast<std::size_t>(ra.first)], ra.first, ra.last)
                       .value()),
              bits(a.value()));
    for (int i = ra.first; i < ra.last; ++i)  // every digit but the top one is balanced
      EXPECT_TRUE(da[static_cast<std::size_t>(i)] >= -(std::int64_t{1} << 31) &&
                  da[static_cast<std::size_t>(i)] < (std::int64_t{1} << 31));
    // The negated sum: the negated digits (a small negative sum is as short as a positive one).
    std::array<std::int64_t, ExactSum::kLimbs> dn{};
    const auto rn = a.negated().balanced_limbs(dn);
    EXPECT_EQ(rn.first, ra.first);
    EXPECT_LE(rn.last - rn.first, ra.last - ra.first + 1);
    // Digits over the union of both ranges, added limb by limb: the total.
    const int first = std::min(ra.first, rb.first), last = std::max(ra.last, rb.last);
    std::vector<std::int64_t> sum(static_cast<std::size_t>(last - first + 1), 0);
    for (int i = ra.first; i <= ra.last; ++i)
      sum[static_cast<std::size_t>(i - first)] += da[static_cast<std::size_t>(i)];
    for (int i = rb.first; i <= rb.last; ++i)
      sum[static_cast<std::size_t>(i - first)] += db[static_cast<std::size_t>(i)];
    EXPECT_EQ(bits(ExactSum::from_limbs(sum.data(), first, last).value()), bits(total.value()))
        << "trial " << trial;
    // The reducer's path: the same limbs rounded in place, and in a window padded with zeros
    // on both sides (wider than the sums need), against the whole sum's value().
    EXPECT_EQ(bits(ExactSum::value_of_limbs(sum.data(), first, last)), bits(total.value()))
        << "trial " << trial;
    const int pad_lo = std::max(first - 2, 0), pad_hi = std::min(last + 2, ExactSum::kLimbs - 1);
    std::vector<std::int64_t> padded(static_cast<std::size_t>(pad_hi - pad_lo + 1), 0);
    for (int i = first; i <= last; ++i)
      padded[static_cast<std::size_t>(i - pad_lo)] = sum[static_cast<std::size_t>(i - first)];
    EXPECT_EQ(bits(ExactSum::value_of_limbs(padded.data(), pad_lo, pad_hi)), bits(total.value()))
        << "trial " << trial;
  }
  // Digits of many partial sums added limb by limb (limbs far beyond 32 bits, as on thousands
  // of ranks), of either sign and cancelling: rounded in place as the whole sum rounds.
  for (int trial = 0; trial < 50; ++trial) {
    ExactSum total;
    std::vector<std::int64_t> limbs(ExactSum::kLimbs, 0);
    const int e = expo(rng);
    for (int part = 0; part < 3000; ++part) {
      ExactSum s;
      for (int k = 0; k < 3; ++k) {
        const double x = std::ldexp(mant(rng), e - static_cast<int>(rng() % 90));
        s.add(x);
        total.add(x);
      }
      std::array<std::int64_t, ExactSum::kLimbs> d{};
      const auto r = s.balanced_limbs(d);
      for (int i = r.first; i <= r.last; ++i)
        limbs[static_cast<std::size_t>(i)] += d[static_cast<std::size_t>(i)];
    }
    EXPECT_EQ(bits(ExactSum::value_of_limbs(limbs.data(), 0, ExactSum::kLimbs - 1)),
              bits(total.value()))
        << "trial " << trial;
  }
  EXPECT_EQ(bits(ExactSum::value_of_limbs(std::vector<std::int64_t>(5, 0).data(), 3, 7)),
            bits(0.0));
  std::array<std::int64_t, ExactSum::kLimbs> d{};
  const auto zero = ExactSum{}.balanced_limbs(d);
  EXPECT_GT(zero.first, zero.last);
}

// A checkpoint's record of several sums: the words give back the same sums, no words give
// none, and a record of another length is refused with what it was.
TEST(ExactSum, WordsOfSeveralSumsRoundTrip) {
  std::vector<ExactSum> sums(3);
  sums[0].add(1.0 / 3.0);
  sums[1].add(-2.5e-200);
  sums[2].add(std::numeric_limits<double>::quiet_NaN());
  const std::vector<std::int64_t> words = words_of_sums(sums);
  ASSERT_EQ(words.size(), 3u * ExactSum::kWords);
  const std::vector<ExactSum> back = sums_of_words(words, 3, "test record");
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(bits(back[0].value()), bits(sums[0].value()));
  EXPECT_EQ(bits(back[1].value()), bits(sums[1].value()));
  EXPECT_TRUE(std::isnan(back[2].value()));
  EXPECT_TRUE(sums_of_words({}, 3, "test record").empty());
  try {
    sums_of_words(words, 2, "test record");
    ADD_FAILURE() << "a record of three sums was read as two";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "checkpoint: test record of the wrong size");
  }
}

}  // namespace
}  // namespace ringdem
