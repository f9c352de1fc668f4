#pragma once

#include <bit>
#include <cstdint>

namespace ringdem {

/// c ? yes : no on doubles, by masking their bits: the same bits as the select, branch-free,
/// and vectorised by GCC for AVX2 as well. A select on doubles (or a bool turned into a double)
/// is if-converted there only with AVX-512's mask registers; with AVX2 (-march=x86-64-v3) the
/// loop stays scalar ("control flow in loop").
[[gnu::always_inline]] inline double select_bits(bool c, double yes, double no) {
  const std::uint64_t mask = 0 - static_cast<std::uint64_t>(c);
  return std::bit_cast<double>((std::bit_cast<std::uint64_t>(yes) & mask) |
                               (std::bit_cast<std::uint64_t>(no) & ~mask));
}

}  // namespace ringdem
