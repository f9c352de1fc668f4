// comm/RowBlocks at one rank: sparse, unsorted keys get their rank in the sorted order as row,
// the block is every key in increasing order, and a key held twice is refused.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "TestCases.hpp"
#include "comm/RowBlocks.hpp"

namespace ringdem {
namespace {

TEST(RowBlocks, SparseKeysAtOneRankAreRankedInKeyOrder) {
  const Communicator self = testing::self_comm();
  // Two "sources" with gid ranges [1000, 1003) and [1 << 40, (1 << 40) + 2), and -5.
  const std::int64_t big = std::int64_t{1} << 40;
  const std::vector<std::int64_t> keys{1002, big + 1, -5, 1000, big, 1001};
  const RowBlocks blocks(self, keys);
  EXPECT_EQ(blocks.n_rows(), 6);
  EXPECT_EQ(blocks.first_row(), 0);
  EXPECT_EQ(blocks.block_size(), 6);
  // Sorted: -5, 1000, 1001, 1002, big, big + 1.
  EXPECT_EQ(blocks.local_rows(), (std::vector<std::int64_t>{3, 5, 0, 1, 4, 2}));
  EXPECT_EQ(blocks.block_keys(), (std::vector<std::int64_t>{-5, 1000, 1001, 1002, big, big + 1}));
  const std::vector<double> values{3.0, 5.0, 0.0, 1.0, 4.0, 2.0};  // the expected row of each
  EXPECT_EQ(blocks.to_blocks(values), (std::vector<double>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(blocks.rows_of({big, -5, 999, big + 2, -6}),
            (std::vector<std::int64_t>{4, 0, -1, -1, -1}));
  EXPECT_THROW(RowBlocks(self, {7, 3, 7}), std::runtime_error);
}

}  // namespace
}  // namespace ringdem
