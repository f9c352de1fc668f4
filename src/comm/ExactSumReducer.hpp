#pragma once

#include <cstdint>
#include <vector>

#include "comm/Communicator.hpp"
#include "comm/ExactSum.hpp"

namespace ringdem {

/// Communicator::sum_exact for a reduction that recurs (a rigid body's loads every step) in
/// few words. A whole ExactSum is 71 words, most of them the limbs of magnitudes that no term
/// has: a step's 6 load sums of the five bodies of a debris channel were 17 KB, past the
/// shared-memory eager limit. This reducer sends only the limbs of a window [lo, hi] that every
/// rank's partial sums have fitted so far, as balanced digits (ExactSum::balanced_limbs), and
/// one word that counts the sums that did not fit or are not finite. When that count is not
/// zero on the sum over the ranks, every rank falls back to the full reduction and widens the
/// window to the ranks' largest extent, one limb to spare on each side. The totals are the
/// same bits as sum_exact's whatever the window: it decides only how many words travel, so a
/// restart that begins with an empty window gives the same results. Every rank calls sum() at
/// the same points with the same number of sums (a collective).
class ExactSumReducer {
 public:
  /// Each sum's total over the ranks, rounded once (Communicator::sum_exact); valid until the
  /// next call.
  const std::vector<double>& sum(const Communicator& comm, const std::vector<ExactSum>& partial);
  /// Calls that took the full reduction (the window was too narrow, or a sum not finite).
  std::int64_t fallbacks() const { return fallbacks_; }
  /// Limbs in the window now (0: none yet).
  int window_limbs() const { return hi_ - lo_ + 1; }

 private:
  int lo_ = 0, hi_ = -1;  ///< the window's limbs; empty at first
  std::int64_t fallbacks_ = 0;
  // Kept between calls, so that the step loop does not allocate.
  std::vector<std::int64_t> words_;
  std::vector<double> totals_;
};

}  // namespace ringdem
