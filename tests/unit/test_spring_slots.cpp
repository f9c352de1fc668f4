// The pooled springs against a plain spring column as the reference: random contacts that open
// and close, springs that grow while touching, slots given back and reused. Every candidate's
// spring must be the column's, a closed contact's must be zero, and the pool must hold no more
// springs than touch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
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
    // A chunk's mask against the column, for chunks of 64 from several starts and a short one.
    for (const std::size_t begin : {std::size_t{0}, std::size_t{37}, kCandidates - 64}) {
      for (const std::size_t n : {std::size_t{64}, std::size_t{5}}) {
        std::uint64_t expected = 0;
        for (std::size_t c = 0; c < n; ++c)
          if (touching[begin + c]) expected |= std::uint64_t{1} << c;
        ASSERT_EQ(slots.held_mask(begin, n), expected) << "step " << step << " from " << begin;
      }
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

// A rebuild's round trip without a second copy of the springs: the held springs taken out in
// candidate order (the pool permuted in place) and carried back into a fresh pool made in their
// own memory must give every candidate the spring a plain copy gives it, and the ledger state
// beside it (its damping force the spring's value times -2, so that each follows its spring).
TEST(SpringSlots, InPlacePackingAndCarryingAgreeWithCopies) {
  constexpr std::size_t kCandidates = 3000;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::bernoulli_distribution touches(0.6), opens(0.3), zero(0.05);
  SpringSlots slots;
  slots.keep_ledger();
  slots.reset(kCandidates);
  // Springs taken, some given back and taken again, so that pool order is not candidate order.
  for (int round = 0; round < 3; ++round)
    for (std::size_t m = 0; m < kCandidates; ++m) {
      if (touches(rng)) {
        Vec3& spring = slots.take(m);
        spring = zero(rng) ? Vec3{} : Vec3{value(rng), value(rng), value(rng)};
        slots.ledger(m).damping = to_vec3f(spring * -2.0);
      } else if (opens(rng)) {
        slots.release(m);
      }
    }
  const auto damping_of = [](const Vec3& spring) { return to_vec3(to_vec3f(spring * -2.0)); };
  const auto keep = [&](std::size_t m) { return slots.value(m).x != 0.0; };
  std::vector<Vec3> copied;  // what the copying pack appends, in candidate order
  std::vector<std::size_t> kept_candidates;
  for (std::size_t m = 0; m < kCandidates; ++m)
    if (slots.holds(m) && keep(m)) {
      copied.push_back(slots.value(m));
      kept_candidates.push_back(m);
    }
  ASSERT_GT(copied.size(), kCandidates / 4);
  ASSERT_LT(copied.size(), slots.n_held()) << "no spring left out: the test checks less";
  std::vector<ContactLedgerState> packed_ledger;
  const std::vector<Vec3> packed = slots.take_in_candidate_order(keep, packed_ledger);
  ASSERT_EQ(packed.size(), copied.size());
  ASSERT_EQ(packed_ledger.size(), copied.size());
  for (std::size_t r = 0; r < packed.size(); ++r)
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(packed[r][c], copied[r][c]) << "row " << r;
      ASSERT_EQ(to_vec3(packed_ledger[r].damping)[c], damping_of(copied[r])[c]) << "row " << r;
    }
  EXPECT_EQ(slots.n_candidates(), 0u);

  // Carried back to new candidates: every other kept row finds a candidate again (rows
  // increasing), into the rows' own memory and by take() into a fresh pool.
  SpringSlots carried, taken;
  const std::size_t n_new = kCandidates + 10;
  carried.reset_carrying(n_new, std::vector<Vec3>(packed),
                         std::vector<ContactLedgerState>(packed_ledger));
  taken.reset(n_new);
  std::size_t n_carried = 0;
  for (std::size_t r = 0; r < packed.size(); r += 2) {
    const std::size_t m = kept_candidates[r] + 7;  // the same order, other numbers
    carried.carry(m, r);
    taken.take(m) = packed[r];
    ++n_carried;
  }
  carried.end_carry();
  EXPECT_EQ(carried.n_held(), n_carried);
  for (std::size_t m = 0; m < n_new; ++m) {
    ASSERT_EQ(carried.holds(m), taken.holds(m)) << "candidate " << m;
    if (!carried.holds(m)) continue;
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(carried.value(m)[c], taken.value(m)[c]) << "candidate " << m;
      ASSERT_EQ(to_vec3(carried.ledger(m).damping)[c], damping_of(taken.value(m))[c])
          << "candidate " << m;
    }
  }
  // Carried without ledger states (a rebuild that booked them): none until asked for, then
  // zero beside every spring, and taken again with the springs.
  SpringSlots bare;
  bare.reset_carrying(n_new, std::vector<Vec3>(packed), {});
  for (std::size_t r = 0; r < packed.size(); ++r)
    bare.carry(kept_candidates[r], r);
  bare.end_carry();
  EXPECT_FALSE(bare.keeps_ledger());
  bare.take(kCandidates + 5) = Vec3{1, 2, 3};  // a new contact before the ledger is asked for
  bare.keep_ledger();
  for (std::size_t r = 0; r < packed.size(); ++r)
    ASSERT_TRUE(bare.ledger(kept_candidates[r]).is_empty()) << "row " << r;
  bare.ledger(kCandidates + 5).overlap = 1.0f;
  std::vector<ContactLedgerState> bare_ledger;
  const std::vector<Vec3> bare_packed =
      bare.take_in_candidate_order([](std::size_t) { return true; }, bare_ledger);
  ASSERT_EQ(bare_ledger.size(), bare_packed.size());
  EXPECT_EQ(bare_ledger.back().overlap, 1.0f);  // the new contact is the last candidate
  EXPECT_EQ(bare_packed.back().z, 3.0);

  // A contact that opens after the carry, and one that closes, behave as in any pool.
  carried.release(kept_candidates[0] + 7);
  EXPECT_EQ(carried.n_held(), n_carried - 1);
  EXPECT_EQ(carried.take(1).x, 0.0);
  EXPECT_TRUE(carried.ledger(1).is_empty());

  // Rows in no order of the candidates (after a re-sort): every third row, carried from the
  // last candidate to the first, gives each its spring, and the pool comes out in candidate
  // order (a slot number per candidate, counted up) with the rows nobody took cut off.
  SpringSlots reordered;
  reordered.reset_carrying(n_new, std::vector<Vec3>(packed),
                           std::vector<ContactLedgerState>(packed_ledger));
  std::size_t n_reordered = 0;
  for (std::size_t r = 0; r < packed.size(); r += 3) {
    reordered.carry(n_new - 1 - kept_candidates[r], r);
    ++n_reordered;
  }
  reordered.end_carry();
  EXPECT_EQ(reordered.n_held(), n_reordered);
  const Vec3* previous = nullptr;
  for (std::size_t m = 0; m < n_new; ++m) {
    const std::size_t source = n_new - 1 - m;
    const auto it = std::find(kept_candidates.begin(), kept_candidates.end(), source);
    const bool carried_here =
        it != kept_candidates.end() && (it - kept_candidates.begin()) % 3 == 0;
    ASSERT_EQ(reordered.holds(m), carried_here) << "candidate " << m;
    if (!carried_here) continue;
    const Vec3& spring = packed[static_cast<std::size_t>(it - kept_candidates.begin())];
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(reordered.value(m)[c], spring[c]) << "candidate " << m;
      ASSERT_EQ(to_vec3(reordered.ledger(m).damping)[c], damping_of(spring)[c])
          << "candidate " << m;
    }
    if (previous != nullptr) {
      EXPECT_EQ(&reordered.value(m), previous + 1) << "candidate " << m;
    }
    previous = &reordered.value(m);
  }
}

// The normal of a contact's start is not carried: step_start_normal() rebuilds it from the
// separation after the drift. Pairs drifted as the integrator drifts them (x + v dt, one rounding
// each) must give back the normal of their positions before the drift within a few roundings of
// the positions (|x| up to 20 m, 1e-15 relative, over a separation of a few mm: 1e-11), in every
// direction, with velocities across and along the pair; and the rest of the state is as it was.
TEST(ContactLedgerState, TheStartNormalIsTheSeparationBeforeTheDrift) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(-20.0, 20.0);
  const double dt = 1.31e-5;
  double worst = 0.0, moved = 0.0;
  for (int k = 0; k < 100000; ++k) {
    const Vec3 xa{uniform(rng), uniform(rng), uniform(rng)};
    Vec3 g{gauss(rng), gauss(rng), k % 3 == 0 ? 0.0 : gauss(rng)};  // horizontal ones too
    const Vec3 xb = xa + g / std::sqrt(norm2(g)) * 0.009;
    const Vec3 va{5.0 * gauss(rng), 5.0 * gauss(rng), 5.0 * gauss(rng)};
    const Vec3 vb{5.0 * gauss(rng), 5.0 * gauss(rng), 5.0 * gauss(rng)};
    const Vec3 xa_drifted{xa.x + va.x * dt, xa.y + va.y * dt, xa.z + va.z * dt};
    const Vec3 xb_drifted{xb.x + vb.x * dt, xb.y + vb.y * dt, xb.z + vb.z * dt};
    const Vec3 start = normalized(xb - xa);
    const Vec3 rebuilt = step_start_normal(xb_drifted - xa_drifted, vb - va, dt);
    worst = std::max(worst, std::sqrt(norm2(rebuilt - start)));
    moved = std::max(moved, std::sqrt(norm2(normalized(xb_drifted - xa_drifted) - start)));
  }
  EXPECT_LT(worst, 1e-11);
  EXPECT_GT(moved, 1e-3) << "the drifts did not turn the pairs: the test shows nothing";
  const ContactLedgerState s = ContactLedgerState::of(Vec3{1, -2, 3}, 0.0);
  EXPECT_EQ(to_vec3(s.damping).y, -2.0);
  EXPECT_EQ(s.overlap, 0.0f);
  EXPECT_TRUE(s.carries_work()) << "a contact that just touches carries its work";
  EXPECT_FALSE(ContactLedgerState{}.carries_work());
  EXPECT_TRUE(ContactLedgerState{}.is_empty());
}

}  // namespace
}  // namespace ringdem
