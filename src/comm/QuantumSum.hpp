#pragma once

#include <cmath>
#include <cstdint>

#include "comm/ExactSum.hpp"

namespace ringdem {

/// A sum of doubles rounded each to an integer number of `kQuantum` (2^-50) and added as
/// integers: an integer sum is the same in any order and over any split of its terms, as
/// ExactSum's is, for the cost of one conversion and a 128-bit add a term instead of three
/// limbs of a 68-limb accumulator. A term of 2^62 quanta or more (4 096 in the term's unit), or
/// one that is not finite, goes to the ExactSum given to add() as it is: which path a term
/// takes depends on its value alone. flush_into() adds the integer to an ExactSum exactly.
///
/// The energy ledger's per-particle pass adds a few powers a particle (watts) this way: a term
/// is off by at most 2^-51 W, against the ledger's O(dt^2) closure (docs/physics.md "Energy
/// ledger"), and the per-contact booking rounds its halves to the same unit.
class QuantumSum {
 public:
  static constexpr double kQuantum = 0x1p-50;
  static constexpr double kLimit = 0x1p62;  ///< quanta: the largest term kept as an integer

  /// Adds x rounded to quanta, or x itself to `large` where it is beyond kLimit quanta.
  [[gnu::always_inline]] void add(double x, ExactSum& large) {
    const double quanta = x * (1.0 / kQuantum);
    if (std::fabs(quanta) < kLimit)
      sum_ += static_cast<std::int64_t>(std::nearbyint(quanta));
    else
      large.add(x);  // (NaN fails the test too: ExactSum counts it)
  }
  /// Adds the integer times kQuantum to `exact`, exactly (in three parts that doubles hold),
  /// and starts again from zero.
  void flush_into(ExactSum& exact) {
    if (sum_ == 0) return;
    Int128 rest = sum_;
    double scale = kQuantum;
    for (int part = 0; part < 2; ++part) {
      // The low 42 bits (>> rounds towards -inf, so they are in [0, 2^42)), the rest above.
      const Int128 high = rest >> 42;
      exact.add(static_cast<double>(rest - high * (Int128{1} << 42)) * scale);
      rest = high;
      scale = std::ldexp(scale, 42);
    }
    // What is above 2^84 quanta: below 2^43 in magnitude (the sum is below 2^127), exact too.
    exact.add(static_cast<double>(rest) * scale);
    sum_ = 0;
  }
  bool is_zero() const { return sum_ == 0; }

 private:
  __extension__ typedef __int128 Int128;
  /// At most 2^62 a term: no overflow before 2^65 terms.
  Int128 sum_ = 0;
};

}  // namespace ringdem
