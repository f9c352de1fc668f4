// The pooled springs against a plain spring column as the reference: random contacts that open
// and close, springs that grow while touching, slots given back and reused. Every candidate's
// spring must be the column's, a closed contact's must be zero, and the pool must hold no more
// springs than touch.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "domain/SpringSlots.hpp"

namespace ringdem {
namespace {

TEST(SpringSlots, AgreesWithASpringColumn) {
  constexpr std::size_t kCandidates = 2000;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> increment(-1.0, 1.0);
  std::bernoulli_distribution flips(0.05);  // a contact changes state at 5 % of the steps
  std::vector<Vec3> column(kCandidates);
  std::vector<char> touching(kCandidates, 0);
  SpringSlots slots;
  slots.reset(kCandidates);
  std::size_t largest_pool_use = 0;
  for (int step = 0; step < 200; ++step) {
    std::size_t n_touching = 0;
    for (std::size_t m = 0; m < kCandidates; ++m) {
      if (flips(rng)) touching[m] = !touching[m];
      if (!touching[m]) {
        column[m] = Vec3{};
        slots.release(m);
        continue;
      }
      ++n_touching;
      const Vec3 d{increment(rng), increment(rng), increment(rng)};
      column[m] += d;
      Vec3& spring = slots.take(m);
      spring += d;
    }
    ASSERT_EQ(slots.n_held(), n_touching) << "step " << step;
    largest_pool_use = std::max(largest_pool_use, n_touching);
    for (std::size_t m = 0; m < kCandidates; ++m) {
      ASSERT_EQ(slots.holds(m), touching[m] != 0) << "step " << step << " candidate " << m;
      const Vec3 value = slots.holds(m) ? slots.value(m) : Vec3{};
      // Same additions in the same order: the same bits.
      ASSERT_EQ(value.x, column[m].x);
      ASSERT_EQ(value.y, column[m].y);
      ASSERT_EQ(value.z, column[m].z);
    }
  }
  EXPECT_GT(largest_pool_use, 0u);
}

TEST(SpringSlots, AReusedSlotStartsAtZero) {
  SpringSlots slots;
  slots.reset(3);
  slots.take(0) = Vec3{1.0, 2.0, 3.0};
  slots.release(0);
  EXPECT_FALSE(slots.holds(0));
  const Vec3& reused = slots.take(2);  // takes the slot candidate 0 gave back
  EXPECT_EQ(slots.n_held(), 1u);
  EXPECT_EQ(reused.x, 0.0);
  EXPECT_EQ(reused.y, 0.0);
  EXPECT_EQ(reused.z, 0.0);
  slots.reset(3);
  EXPECT_EQ(slots.n_held(), 0u);
  EXPECT_FALSE(slots.holds(2));
}

}  // namespace
}  // namespace ringdem
