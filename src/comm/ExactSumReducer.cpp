#include "comm/ExactSumReducer.hpp"

#include <algorithm>
#include <array>

namespace ringdem {

const std::vector<double>& ExactSumReducer::sum(const Communicator& comm,
                                                const std::vector<ExactSum>& partial) {
  const std::size_t width = static_cast<std::size_t>(window_limbs());
  // Word 0: sums that do not fit the window (or hold a NaN or an infinity); then each sum's
  // digits lo..hi.
  words_.assign(1 + partial.size() * width, 0);
  std::array<std::int64_t, ExactSum::kLimbs> digits{};
  int first = ExactSum::kLimbs, last = -1;  // this rank's extent, for a fallback
  for (std::size_t c = 0; c < partial.size(); ++c) {
    if (!partial[c].is_finite()) {
      ++words_[0];
      continue;
    }
    const ExactSum::LimbRange r = partial[c].balanced_limbs(digits);
    if (r.first > r.last) continue;  // zero: fits any window
    first = std::min(first, r.first);
    last = std::max(last, r.last);
    if (r.first < lo_ || r.last > hi_) {
      ++words_[0];
      continue;
    }
    std::int64_t* const out = &words_[1 + c * width];
    for (int i = r.first; i <= r.last; ++i)
      out[i - lo_] = digits[static_cast<std::size_t>(i)];
  }
  comm.sum_in_place(words_.data(), words_.size());
  if (words_[0] > 0) {
    // Some rank's sum did not fit: the full reduction (which also gives NaN and infinities
    // their IEEE sums), and a window wide enough for every rank's sums of this call.
    ++fallbacks_;
    const auto extent =
        comm.max(std::array<double, 2>{-static_cast<double>(first), static_cast<double>(last)});
    const int global_first = -static_cast<int>(extent[0]),
              global_last = static_cast<int>(extent[1]);
    if (global_first <= global_last) {
      const int lo = std::max(global_first - 1, 0);
      const int hi = std::min(global_last + 1, ExactSum::kLimbs - 1);
      lo_ = window_limbs() > 0 ? std::min(lo_, lo) : lo;
      hi_ = std::max(hi_, hi);
    }
    totals_ = comm.sum_exact(partial);
    return totals_;
  }
  totals_.resize(partial.size());
  for (std::size_t c = 0; c < partial.size(); ++c)
    totals_[c] = width == 0 ? 0.0 : ExactSum::value_of_limbs(&words_[1 + c * width], lo_, hi_);
  return totals_;
}

}  // namespace ringdem
