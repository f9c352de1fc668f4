// The engine's loop helpers against plain loops: every index of a range visited once, in the
// order the helper promises.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "engine/Loop.hpp"

namespace ringdem {
namespace {

TEST(Loop, ForEachSelectedInOrderVisitsTheSetBitsInAscendingOrder) {
  std::mt19937_64 rng(5);
  std::vector<std::uint64_t> masks = {0, ~std::uint64_t{0}, std::uint64_t{1} << 63, 1,
                                      0x8000000000000001ull};
  for (int k = 0; k < 50; ++k)
    masks.push_back(rng() & rng());  // about a quarter of the bits set
  for (const std::uint64_t mask : masks) {
    for (const std::size_t begin : {std::size_t{0}, std::size_t{1000}}) {
      const IndexRange range{begin, begin + 64};
      std::vector<std::size_t> expected, visited;
      for (std::size_t c = 0; c < 64; ++c)
        if ((mask >> c) & 1) expected.push_back(begin + c);
      for_each_selected_in_order(range, mask, [&](std::size_t i) { visited.push_back(i); });
      EXPECT_EQ(visited, expected) << std::hex << mask;
    }
  }
}

}  // namespace
}  // namespace ringdem
