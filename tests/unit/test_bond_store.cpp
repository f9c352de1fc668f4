// Bond store: a bond model's own columns join the field registry, grow with the bonds and are
// refused when they would shadow a column or come too late.
#include <gtest/gtest.h>

#include "domain/BondStore.hpp"

namespace ringdem {
namespace {

TEST(BondStore, ModelColumnsJoinTheRegistryAndGrowWithTheBonds) {
  BondStore b;
  using namespace field_flag;
  b.declare_model_columns({{"plastic_x", kMigrate | kCheckpoint}, {"work", kOutput}});
  ASSERT_EQ(b.n_model_columns(), 2u);
  for (std::int64_t k = 0; k < 3; ++k)
    b.append(10 + k, k, k + 1, 0);
  EXPECT_EQ(b.model_column(0).size(), 3u);
  EXPECT_EQ(b.model_column(1).size(), 3u);
  b.model_column(0)[2] = 4.5;
  // The registry lists them last, with their flags, and hands out the very vectors.
  std::vector<std::string> names;
  unsigned flags_of_work = 0;
  double seen = 0.0;
  b.for_each_field([&](const FieldInfo& f, auto& v) {
    names.emplace_back(f.name);
    if (f.name == "work") flags_of_work = f.flags;
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::vector<double>>)
      if (f.name == "plastic_x") seen = v[2];
  });
  ASSERT_GE(names.size(), 2u);
  EXPECT_EQ(names[names.size() - 2], "plastic_x");
  EXPECT_EQ(names.back(), "work");
  EXPECT_EQ(flags_of_work, kOutput);
  EXPECT_EQ(seen, 4.5);
}

TEST(BondStore, ModelColumnsAreRefusedTwiceLateOrUnderACommonName) {
  BondStore b;
  EXPECT_THROW(b.declare_model_columns({{"length0", 0}}), std::invalid_argument);
  BondStore c;
  EXPECT_THROW(c.declare_model_columns({{"x", 0}, {"x", 0}}), std::invalid_argument);
  BondStore d;
  d.append(0, 0, 1, 0);
  EXPECT_THROW(d.declare_model_columns({{"x", 0}}), std::logic_error);
}

}  // namespace
}  // namespace ringdem
