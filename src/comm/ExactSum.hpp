#pragma once

#include <array>
#include <bit>
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

  /// Inline, and without a branch on the sign (the sign of a contact's power is not
  /// predictable): the ledger adds a few terms a particle every step.
  void add(double x) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const auto exponent = static_cast<int>((bits >> 52) & 0x7ff);
    if (exponent == 0x7ff) [[unlikely]] {
      add_non_finite(x);
      return;
    }
    if ((bits << 1) == 0) return;  // +-0: free (a tally that books nothing at a call site)
    std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
    // x = mantissa 2^(exponent - 1075) (normal) or mantissa 2^-1074 (subnormal); its lowest
    // bit lies at `position` counted from 2^-1074.
    const bool normal = exponent != 0;
    mantissa |= static_cast<std::uint64_t>(normal) << 52;
    const int position = exponent - static_cast<int>(normal);
    const auto first = static_cast<unsigned>(position) / 32,
               shift = static_cast<unsigned>(position) % 32;
    // mantissa 2^shift < 2^85, cut into three 32-bit digits: the low 64 bits and what a shift
    // by 64 - shift moves out of them (in two shifts, as a shift by 64 is undefined).
    const std::uint64_t low = mantissa << shift;
    const std::uint64_t high = (mantissa >> 1) >> (63 - shift);
    // +1 or -1 from the sign bit, so that the three limbs are one add each.
    const std::int64_t sign = 1 - 2 * static_cast<std::int64_t>(bits >> 63);
    std::int64_t* const l = limb_.data() + first;
    l[0] += sign * static_cast<std::int64_t>(low & 0xffffffffu);
    l[1] += sign * static_cast<std::int64_t>(low >> 32);
    l[2] += sign * static_cast<std::int64_t>(high);
    if (++pending_ >= kMaxPending) [[unlikely]]
      normalise();
  }
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

  /// Whether no NaN or infinity was added.
  bool is_finite() const { return nan_ == 0 && pos_inf_ == 0 && neg_inf_ == 0; }
  /// The nonzero limbs [first, last] of balanced_limbs(); first > last for a zero sum.
  struct LimbRange {
    int first = 0, last = -1;
  };
  /// The finite part as balanced digits: limb i (weight 2^(32 i - 1074)) in out[i], each in
  /// [-2^31, 2^31) but the top one, so that a small sum of either sign has few nonzero limbs
  /// (the canonical words of export_words() spread a negative sum over every limb). Limb-wise
  /// integer sums of several sums' digits are the digits of their total (up to about 2^31
  /// partial sums). Only the returned range of `out` is written.
  LimbRange balanced_limbs(std::array<std::int64_t, kLimbs>& out) const;
  /// The finite sum whose limbs first..last are limbs[0..last-first] (any integers below
  /// 2^62 in magnitude, such as sums of balanced digits) and the others zero.
  static ExactSum from_limbs(const std::int64_t* limbs, int first, int last);
  /// from_limbs(limbs, first, last).value() without building the whole sum: a reduction that
  /// recurs every step (ExactSumReducer) rounds its window's few limbs only.
  static double value_of_limbs(const std::int64_t* limbs, int first, int last);

 private:
  /// Terms between carry propagations: a limb then stays below 2^32 (1 + 2^24) < 2^57.
  static constexpr std::int64_t kMaxPending = std::int64_t{1} << 24;
  void add_non_finite(double x);
  void normalise();
  /// Balanced digits of the integer whose limb i is in[i] (zero outside [lowest, highest], each
  /// below 2^62 in magnitude) into out, as balanced_limbs() describes.
  static LimbRange balance(const std::int64_t* in, int lowest, int highest,
                           std::array<std::int64_t, kLimbs>& out);
  /// The finite sum of balanced digits d (zero outside range, which is not empty), rounded
  /// to the nearest double. Overwrites d.
  static double round_digits(std::array<std::int64_t, kLimbs>& d, LimbRange range);

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
