#include <gtest/gtest.h>

#include <vector>

#include "core/Vec3Column.hpp"

namespace ringdem {
namespace {

// A Vec3Column must behave like the std::vector<Vec3> it replaced in the particle store: the
// reference is such a vector, driven through the same operations side by side.

TEST(Vec3Column, RowsBehaveLikeAVectorOfVec3) {
  std::vector<Vec3> reference(5);
  Vec3Column column(5);
  for (std::size_t k = 0; k < 5; ++k) {
    const Vec3 v{1.0 + k, -2.0 * k, 0.25 * k};
    reference[k] = v;
    column[k] = v;
  }
  reference[1] += Vec3{0.5, 0.5, 0.5};
  column[1] += Vec3{0.5, 0.5, 0.5};
  reference[2] -= Vec3{1.0, 2.0, 3.0};
  column[2] -= Vec3{1.0, 2.0, 3.0};
  reference[3].y = 7.0;
  column[3].y = 7.0;
  reference.push_back({9, 8, 7});
  column.push_back({9, 8, 7});
  ASSERT_EQ(column.size(), reference.size());
  EXPECT_EQ(column.rows(), reference);
  // The components live in three arrays, each with the rows in order.
  for (std::size_t k = 0; k < reference.size(); ++k) {
    EXPECT_EQ(column.x()[k], reference[k].x);
    EXPECT_EQ(column.y()[k], reference[k].y);
    EXPECT_EQ(column.z()[k], reference[k].z);
  }
}

TEST(Vec3Column, AssigningOneRowToAnotherCopiesTheValueNotTheReference) {
  Vec3Column column(3);
  column[0] = {1, 2, 3};
  column[1] = {4, 5, 6};
  column[2] = column[0];  // a Ref from a Ref: the values, as a Vec3& would copy them
  column[0] = {0, 0, 0};
  EXPECT_EQ(Vec3(column[2]), (Vec3{1, 2, 3}));
  EXPECT_EQ(Vec3(column[0]), (Vec3{0, 0, 0}));
  // A value taken from a row does not follow later writes to it.
  const Vec3 before = column[1];
  column[1] += Vec3{1, 1, 1};
  EXPECT_EQ(before, (Vec3{4, 5, 6}));
  EXPECT_EQ(Vec3(column[1]), (Vec3{5, 6, 7}));
}

TEST(Vec3Column, ResizeKeepsRowsAndFillsNewOnesWithZero) {
  Vec3Column column;
  column.push_back({1, 2, 3});
  column.resize(3);
  EXPECT_EQ(column.rows(), (std::vector<Vec3>{{1, 2, 3}, {0, 0, 0}, {0, 0, 0}}));
  column.resize(1);
  EXPECT_EQ(column.rows(), (std::vector<Vec3>{{1, 2, 3}}));
  column.assign(2, {4, 4, 4});
  EXPECT_EQ(column.rows(), (std::vector<Vec3>{{4, 4, 4}, {4, 4, 4}}));
}

TEST(Vec3Column, RowsRoundTripThroughTheRegistryHelpers) {
  // as_rows / assign_rows: what the checkpoint and frame writers use for every field.
  const std::vector<Vec3> rows{{1, 2, 3}, {-1, -2, -3}, {0.5, 0, 1e300}};
  Vec3Column column(3);
  assign_rows(column, rows);
  const auto& back = as_rows(column);
  EXPECT_EQ(back, rows);
  std::vector<double> plain(2, 0.0);
  assign_rows(plain, std::vector<double>{4.0, 5.0});
  EXPECT_EQ(&as_rows(plain), &plain);  // a plain column is handed out as it is
  EXPECT_EQ(plain, (std::vector<double>{4.0, 5.0}));
}

}  // namespace
}  // namespace ringdem
