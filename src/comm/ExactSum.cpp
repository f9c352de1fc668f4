#include "comm/ExactSum.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace ringdem {

namespace {

constexpr std::int64_t kDigit = std::int64_t{1} << 32;

}  // namespace

void ExactSum::add_non_finite(double x) {
  if (std::isnan(x))
    ++nan_;
  else if (x > 0)
    ++pos_inf_;
  else
    ++neg_inf_;
}

ExactSum& ExactSum::operator+=(const ExactSum& o) {
  for (std::size_t i = 0; i < limb_.size(); ++i)
    limb_[i] += o.limb_[i];
  nan_ += o.nan_;
  pos_inf_ += o.pos_inf_;
  neg_inf_ += o.neg_inf_;
  // Each limb is below 2^32 (1 + pending) in magnitude: the bounds add.
  pending_ += o.pending_ + 1;
  if (pending_ >= kMaxPending) normalise();
  return *this;
}

ExactSum ExactSum::negated() const {
  ExactSum n = *this;
  for (auto& l : n.limb_)
    l = -l;
  std::swap(n.pos_inf_, n.neg_inf_);
  return n;
}

void ExactSum::normalise() {
  // Floor division by 2^32 (arithmetic shift): every limb but the top one ends in [0, 2^32),
  // the top one carries the sign. The result is the one representation of the value.
  for (std::size_t i = 0; i + 1 < limb_.size(); ++i) {
    const std::int64_t carry = limb_[i] >> 32;
    limb_[i] -= carry * kDigit;
    limb_[i + 1] += carry;
  }
  pending_ = 0;
}

std::array<std::int64_t, ExactSum::kWords> ExactSum::export_words() const {
  ExactSum c = *this;
  c.normalise();
  std::array<std::int64_t, kWords> w{};
  for (std::size_t i = 0; i < c.limb_.size(); ++i)
    w[i] = c.limb_[i];
  w[kLimbs] = nan_;
  w[kLimbs + 1] = pos_inf_;
  w[kLimbs + 2] = neg_inf_;
  return w;
}

ExactSum ExactSum::from_words(const std::int64_t* words) {
  ExactSum s;
  for (std::size_t i = 0; i < s.limb_.size(); ++i)
    s.limb_[i] = words[i];
  s.nan_ = words[kLimbs];
  s.pos_inf_ = words[kLimbs + 1];
  s.neg_inf_ = words[kLimbs + 2];
  s.normalise();
  return s;
}

ExactSum::LimbRange ExactSum::balanced_limbs(std::array<std::int64_t, kLimbs>& out) const {
  int lowest = 0;
  while (lowest < kLimbs && limb_[static_cast<std::size_t>(lowest)] == 0)
    ++lowest;
  if (lowest == kLimbs) return {};  // zero
  int highest = kLimbs - 1;
  while (limb_[static_cast<std::size_t>(highest)] == 0)
    --highest;
  return balance(limb_.data(), lowest, highest, out);
}

ExactSum::LimbRange ExactSum::balance(const std::int64_t* in, int lowest, int highest,
                                      std::array<std::int64_t, kLimbs>& out) {
  // Carries upwards from the lowest nonzero limb: digit = limb + carry rounded into
  // [-2^31, 2^31) by (x + 2^31) >> 32 (floor), until the carry dies out above the highest
  // limb; the top limb keeps what is left. A limb holds less than 2^62 and a carry less than
  // 2^31, so nothing overflows.
  constexpr std::int64_t kHalf = std::int64_t{1} << 31;
  std::int64_t carry = 0;
  int i = lowest;
  for (; i < kLimbs - 1 && (i <= highest || carry != 0); ++i) {
    const std::int64_t x = (i <= highest ? in[i] : 0) + carry;
    carry = (x + kHalf) >> 32;
    out[static_cast<std::size_t>(i)] = x - carry * kDigit;
  }
  if (i == kLimbs - 1) {
    out[static_cast<std::size_t>(i)] = (i <= highest ? in[i] : 0) + carry;
    ++i;
  }
  // The nonzero digits: a carry can cancel a limb, so trim both ends.
  int first = lowest, last = i - 1;
  while (first <= last && out[static_cast<std::size_t>(first)] == 0)
    ++first;
  while (last >= first && out[static_cast<std::size_t>(last)] == 0)
    --last;
  if (first <= last) return {first, last};
  return {};
}

ExactSum ExactSum::from_limbs(const std::int64_t* limbs, int first, int last) {
  ExactSum s;
  for (int i = first; i <= last; ++i)
    s.limb_[static_cast<std::size_t>(i)] = limbs[i - first];
  s.normalise();
  return s;
}

double ExactSum::value_of_limbs(const std::int64_t* limbs, int first, int last) {
  // The window's limbs at their places (zeros elsewhere), then the same digits and rounding
  // as value(): only the window and the carries above it are walked.
  std::array<std::int64_t, kLimbs> in{};
  int lowest = kLimbs, highest = -1;
  for (int i = first; i <= last; ++i) {
    in[static_cast<std::size_t>(i)] = limbs[i - first];
    if (limbs[i - first] != 0) {
      lowest = std::min(lowest, i);
      highest = i;
    }
  }
  if (highest < 0) return 0.0;
  std::array<std::int64_t, kLimbs> d{};
  const LimbRange range = balance(in.data(), lowest, highest, d);
  return range.first > range.last ? 0.0 : round_digits(d, range);
}

double ExactSum::value() const {
  if (nan_ > 0 || (pos_inf_ > 0 && neg_inf_ > 0)) return std::numeric_limits<double>::quiet_NaN();
  if (pos_inf_ > 0) return std::numeric_limits<double>::infinity();
  if (neg_inf_ > 0) return -std::numeric_limits<double>::infinity();
  std::array<std::int64_t, kLimbs> d{};
  const LimbRange range = balanced_limbs(d);
  return range.first > range.last ? 0.0 : round_digits(d, range);
}

double ExactSum::round_digits(std::array<std::int64_t, kLimbs>& d, LimbRange range) {
  // The sign is the top nonzero digit's (the ones below it are under half a unit of it).
  const bool negative = d[static_cast<std::size_t>(range.last)] < 0;
  if (negative)
    for (int i = range.first; i <= range.last; ++i)
      d[static_cast<std::size_t>(i)] = -d[static_cast<std::size_t>(i)];
  // The magnitude in digits [0, 2^32) by floor carries. It is positive, so the carries (0 or
  // -1) end in the top digit, which stays >= 0 (and may hold more than 32 bits only as the
  // last limb).
  std::int64_t carry = 0;
  for (int i = range.first; i < range.last; ++i) {
    const std::int64_t x = d[static_cast<std::size_t>(i)] + carry;
    carry = x >> 32;
    d[static_cast<std::size_t>(i)] = x - carry * kDigit;
  }
  d[static_cast<std::size_t>(range.last)] += carry;
  int top = range.last;
  while (top >= range.first && d[static_cast<std::size_t>(top)] == 0)
    --top;
  if (top < range.first) return 0.0;
  const auto limb = [&](int i) {
    return i < 0 ? std::uint64_t{0} : static_cast<std::uint64_t>(d[static_cast<std::size_t>(i)]);
  };
  // The top three limbs as one integer: window bit j is bit base + j of the sum. The top limb
  // is nonzero, so the window reaches 64 bits above base: more than the 53 kept and the
  // rounding bit. (Limbs below limb 0 are zeros.)
  __extension__ typedef unsigned __int128 Window;
  const int base = 32 * (top - 2);
  const Window window = (static_cast<Window>(limb(top)) << 64) |
                        (static_cast<Window>(limb(top - 1)) << 32) | limb(top - 2);
  const int msb = 32 * top + 63 - std::countl_zero(limb(top));
  // Keep 53 bits from the highest one down. Below 2^-1021 every bit is kept: such a sum is a
  // multiple of 2^-1074 below 2^53 2^-1074, a double (subnormal or not) exactly.
  const int lsb = std::max(msb - 52, 0);
  const int shift = lsb - base;  // > 0 where lsb > 0: the rounding bit lies in the window
  auto mantissa = static_cast<std::uint64_t>(window >> shift);
  if (lsb > 0) {
    const bool round_bit = ((window >> (shift - 1)) & 1u) != 0;
    // Whether any bit below the rounding bit is set: in the window, or in a lower limb (the
    // digits below range.first are zeros).
    bool sticky = (window & ((Window{1} << (shift - 1)) - 1)) != 0;
    for (int j = range.first; j < top - 2 && !sticky; ++j)
      sticky = limb(j) != 0;
    if (round_bit && (sticky || (mantissa & 1u) != 0))
      ++mantissa;  // round half to even; 2^53 stays exact and ldexp moves the exponent
  }
  const double v = std::ldexp(static_cast<double>(mantissa), lsb - 1074);
  return negative ? -v : v;
}

std::vector<std::int64_t> words_of_sums(const std::vector<ExactSum>& sums) {
  std::vector<std::int64_t> words;
  words.reserve(sums.size() * ExactSum::kWords);
  for (const ExactSum& s : sums) {
    const auto w = s.export_words();
    words.insert(words.end(), w.begin(), w.end());
  }
  return words;
}

std::vector<ExactSum> sums_of_words(const std::vector<std::int64_t>& words, std::size_t count,
                                    const std::string& what) {
  if (words.empty()) return {};
  if (words.size() != count * ExactSum::kWords)
    throw std::runtime_error("checkpoint: " + what + " of the wrong size");
  std::vector<ExactSum> sums;
  sums.reserve(count);
  for (std::size_t c = 0; c < count; ++c)
    sums.push_back(ExactSum::from_words(words.data() + c * ExactSum::kWords));
  return sums;
}

}  // namespace ringdem
