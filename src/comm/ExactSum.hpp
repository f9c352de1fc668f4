#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ringdem {

/// Exact sum of doubles (a superaccumulator): every finite double is added without rounding
/// into a fixed-point integer that covers the whole double range, so the total does not depend
/// on the order of the terms or on how they are split over ranks; value() rounds it once, to
/// nearest, ties to even. This is what makes the energy sums the same bits on any rank count
/// without gathering the terms (DESIGN §4, "exact fixed-point accumulation").
///
/// The integer is kLimbs signed 64-bit limbs of 32-bit digits: limb i weighs 2^(32 i - 1074),
/// so limb 0 holds the smallest subnormal and the limbs up to 65 the largest double; the two
/// above absorb carries of up to 2^60 terms. A term touches three limbs. Carries are
/// propagated every 2^24 terms (a limb then holds less than 2^57) and before the words are
/// exported. NaN and infinities are counted apart and give the IEEE result of their sum (NaN,
/// +inf, -inf, or NaN for +inf + -inf).
class ExactSum {
 public:
  static constexpr int kLimbs = 68;
  /// Words of export(): the limbs, then the NaN, +inf and -inf counts.
  static constexpr int kWords = kLimbs + 3;

  void add(double x);
  /// Adds another partial sum (exact).
  ExactSum& operator+=(const ExactSum& o);
  /// The sum of the negated terms (exact).
  ExactSum negated() const;
  /// The sum rounded to the nearest double (ties to even); +-inf beyond the double range.
  double value() const;

  /// Canonical words (carries propagated: limbs 0..kLimbs-2 in [0, 2^32), the top limb
  /// signed). Word-wise integer sums of the exports of several partial sums, such as an
  /// MPI_SUM all-reduce, are the export of their total (up to about 2^31 partial sums).
  std::array<std::int64_t, kWords> export_words() const;
  static ExactSum from_words(const std::int64_t* words);

 private:
  void normalise();

  std::array<std::int64_t, kLimbs> limb_{};
  std::int64_t nan_ = 0, pos_inf_ = 0, neg_inf_ = 0;
  std::int64_t pending_ = 0;  ///< terms added since the last normalise()
};

/// The canonical words of several sums, one after another (a checkpoint's record of them).
std::vector<std::int64_t> words_of_sums(const std::vector<ExactSum>& sums);
/// The sums of words_of_sums(): `count` of them, or none from no words; any other number of
/// words throws "checkpoint: <what> of the wrong size".
std::vector<ExactSum> sums_of_words(const std::vector<std::int64_t>& words, std::size_t count,
                                    const std::string& what);

}  // namespace ringdem
