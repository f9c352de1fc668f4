// The elastic bond term's failure test in two stages (TimoshenkoBondTerm::compute): the vector
// loop flags the bonds that may fail by BondTimoshenko::may_fail(), which compares squares and
// takes no square root, and a pass after it decides the flagged ones with Eq. 3–5 as stresses()
// states them. Checked here: may_fail() holds wherever check_failure() fails, at strengths an
// ulp from the stresses; it flags nothing 1e-8 away from every strength; and the term breaks
// exactly the bonds the direct test breaks, with the direct kernel's loads on the rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "BondChain.hpp"
#include "domain/BondStore.hpp"
#include "domain/ParticleStore.hpp"
#include "engine/TimoshenkoBondTerm.hpp"
#include "physics/BondTimoshenko.hpp"

namespace ringdem {
namespace {

using Bond = BondTimoshenko;

constexpr double kRestLength = 0.0097, kRadius = 0.0045;

Bond::Params ring_bond() {
  Bond::Params p;
  p.youngs_modulus = 288.4e9;  // r12's bond (inputs/rockfall/r12.yaml)
  p.poisson_ratio = 0.3;
  p.radius_multiplier = 0.43;
  p.tensile_strength = p.compressive_strength = 41e9;
  p.shear_strength = 12e9;
  return p;
}

ParticleStore straight_chain(std::size_t n) {
  return testing::straight_chain(n, kRestLength, kRadius);
}

/// Each particle moved by up to 0.2 mm and turned by up to 0.05 rad (scaled per particle by
/// s^3, s uniform in [0, 1]): stresses from nearly zero to a few GPa, with bending, torsion,
/// shear and stretch mixed.
void deform(ParticleStore& p, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.0, 1.0);
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const double s = size(rng), scale = s * s * s;
    p.position[k] += Vec3{unit(rng), unit(rng), unit(rng)} * (2e-4 * scale);
    p.orientation[k] =
        quat_from_rotation_vector(Vec3{unit(rng), unit(rng), unit(rng)} * (0.05 * scale));
  }
}

BondStore chain_bonds(const ParticleStore& p, std::size_t n) {
  BondStore bonds;
  testing::bond_chain(bonds, p, n, ring_bond());
  return bonds;
}

/// Strengths around a stress state: stress(criterion) scaled by 1 + factor, or moved by ulps.
Bond::Strength strengths_near(const Bond::Stresses& st, int criterion, double factor, int ulps) {
  Bond::Strength s{1e30, 1e30, 1e30};
  double& target = criterion == 0 ? s.tensile : criterion == 1 ? s.compressive : s.shear;
  double value = criterion == 0 ? st.tensile : criterion == 1 ? st.compressive : st.shear;
  value *= 1.0 + factor;
  for (int u = 0; u < std::abs(ulps); ++u)
    value = std::nextafter(value, ulps > 0 ? 1e300 : -1e300);
  target = value;
  return s;
}

TEST(BondMayFail, FlagsEveryStateThatFailsAndNoneFarFromAStrength) {
  constexpr std::size_t kBonds = 300;
  std::mt19937 rng(11);
  ParticleStore p = straight_chain(kBonds);
  const BondStore bonds = chain_bonds(p, kBonds);
  deform(p, rng);
  std::size_t failing = 0, near_not_failing = 0, tested = 0;
  for (std::size_t k = 0; k < kBonds; ++k) {
    const auto sec = TimoshenkoBondTerm::section(bonds, k);
    const auto r = Bond::compute(sec, TimoshenkoBondTerm::reference(bonds, k), p.position[k],
                                 p.orientation[k], p.position[k + 1], p.orientation[k + 1]);
    const auto st = Bond::stresses(sec, r);
    for (int criterion = 0; criterion < 3; ++criterion) {
      // Within a few ulps and up to 1e-10 on either side: both outcomes of Eq. 3–5.
      for (const double factor : {0.0, 1e-13, -1e-13, 1e-10, -1e-10}) {
        for (int ulps = -3; ulps <= 3; ++ulps) {
          const auto strength = strengths_near(st, criterion, factor, ulps);
          const bool fails = Bond::check_failure(st, strength) != Bond::Failure::kNone;
          const bool flagged = Bond::may_fail(sec, r, strength);
          ++tested;
          failing += fails;
          near_not_failing += flagged && !fails;
          if (fails && !flagged) {
            ADD_FAILURE() << "bond " << k << " criterion " << criterion << " factor " << factor
                          << " ulps " << ulps << ": fails but is not flagged";
            return;
          }
        }
      }
      // 1e-8 of the stresses' scale above the stress (the others out of reach): neither fails
      // nor is flagged.
      Bond::Strength clear{1e30, 1e30, 1e30};
      const double scale = std::abs(st.tensile) + std::abs(st.compressive) + st.shear;
      (criterion == 0   ? clear.tensile
       : criterion == 1 ? clear.compressive
                        : clear.shear) = (criterion == 0   ? st.tensile
                                          : criterion == 1 ? st.compressive
                                                           : st.shear) +
                                         1e-8 * scale;
      EXPECT_FALSE(Bond::may_fail(sec, r, clear)) << "bond " << k << " criterion " << criterion;
    }
    // The case's own strengths, far above these stresses, flag nothing.
    EXPECT_FALSE(Bond::may_fail(sec, r, TimoshenkoBondTerm::strength(bonds, k)));
  }
  EXPECT_GT(failing, tested / 4) << "both outcomes tested";
  EXPECT_GT(near_not_failing, tested / 10) << "flagged near a strength without failing";
}

TEST(BondMayFail, AnInfiniteStrengthCannotFailAndLeavesTheOthersTested) {
  std::mt19937 rng(5);
  ParticleStore p = straight_chain(50);
  const BondStore bonds = chain_bonds(p, 50);
  deform(p, rng);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < 50; ++k) {
    const auto sec = TimoshenkoBondTerm::section(bonds, k);
    const auto r = Bond::compute(sec, TimoshenkoBondTerm::reference(bonds, k), p.position[k],
                                 p.orientation[k], p.position[k + 1], p.orientation[k + 1]);
    const auto st = Bond::stresses(sec, r);
    EXPECT_FALSE(Bond::may_fail(sec, r, {kInf, kInf, kInf}));
    // Infinite tensile strength, a compressive one just under the compressive stress: flagged.
    if (st.compressive > 0.0) {
      EXPECT_TRUE(Bond::may_fail(sec, r, {kInf, std::nextafter(st.compressive, 0.0), kInf}));
    }
    if (st.tensile > 0.0) {
      EXPECT_TRUE(Bond::may_fail(sec, r, {std::nextafter(st.tensile, 0.0), kInf, kInf}));
    }
    EXPECT_TRUE(Bond::may_fail(sec, r, {kInf, kInf, std::nextafter(st.shear, 0.0)}));
  }
}

TEST(BondMayFail, TheTermBreaksWhatTheDirectTestBreaksWithTheKernelsLoadsOnTheRest) {
  constexpr std::size_t kBonds = 400;
  std::mt19937 rng(23);
  ParticleStore p = straight_chain(kBonds);
  BondStore bonds = chain_bonds(p, kBonds);
  deform(p, rng);
  // Strengths per bond at, an ulp under and just over its own stresses (flagged, failing or
  // not), some far away; some bonds broken already.
  std::uniform_int_distribution<int> pick(0, 5);
  for (std::size_t k = 0; k < kBonds; ++k) {
    if (k % 29 == 3) bonds.broken[k] = 1;
    const int how = pick(rng);
    if (how == 5) continue;  // the case's strengths
    const auto sec = TimoshenkoBondTerm::section(bonds, k);
    const auto r = Bond::compute(sec, TimoshenkoBondTerm::reference(bonds, k), p.position[k],
                                 p.orientation[k], p.position[k + 1], p.orientation[k + 1]);
    const auto st = Bond::stresses(sec, r);
    const int criterion = how % 3;
    const auto s = strengths_near(st, criterion, how < 3 ? 0.0 : 1e-12, how < 3 ? -1 : 0);
    bonds.tensile_strength[k] = s.tensile;
    bonds.compressive_strength[k] = s.compressive;
    bonds.shear_strength[k] = s.shear;
  }
  struct Expected {
    Vec3 fa, ta, fb, tb;
    bool broken = false;
  };
  std::vector<Expected> expected(kBonds);
  std::size_t failing = 0, flagged_intact = 0;
  for (std::size_t k = 0; k < kBonds; ++k) {
    Expected& e = expected[k];
    e.broken = bonds.broken[k] != 0;
    if (e.broken) continue;
    const auto sec = TimoshenkoBondTerm::section(bonds, k);
    const auto r = Bond::compute(sec, TimoshenkoBondTerm::reference(bonds, k), p.position[k],
                                 p.orientation[k], p.position[k + 1], p.orientation[k + 1]);
    const auto strength = TimoshenkoBondTerm::strength(bonds, k);
    if (Bond::check_failure(Bond::stresses(sec, r), strength) != Bond::Failure::kNone) {
      e.broken = true;  // no loads from this evaluation on
      ++failing;
      continue;
    }
    flagged_intact += Bond::may_fail(sec, r, strength);
    e.fa = r.force_a;
    e.ta = r.torque_a;
    e.fb = r.force_b;
    e.tb = r.torque_b;
  }
  ASSERT_GT(failing, 30u);
  ASSERT_GT(flagged_intact, 30u);

  TimoshenkoBondTerm term(bonds, {ring_bond()});
  testing::TermBench bench;
  bench.rebuild(term, p);
  ForceSlots& slots = bench.slots;
  ASSERT_EQ(slots.fx.size(), 2 * kBonds);  // end a's slots, then end b's
  // Stale loads in every slot: the term must write or clear each one.
  for (std::size_t s = 0; s < slots.fx.size(); ++s)
    slots.set(s, Vec3{1, 2, 3}, Vec3{4, 5, 6});
  bench.compute(term, p, 1e-6);

  const auto same = [](const Vec3& a, const Vec3& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z && std::signbit(a.x) == std::signbit(b.x) &&
           std::signbit(a.y) == std::signbit(b.y) && std::signbit(a.z) == std::signbit(b.z);
  };
  std::size_t differ = 0;
  for (std::size_t k = 0; k < kBonds; ++k) {
    const Expected& e = expected[k];
    const bool ok = same(slots.force(k), e.fa) && same(slots.torque(k), e.ta) &&
                    same(slots.force(kBonds + k), e.fb) && same(slots.torque(kBonds + k), e.tb) &&
                    (bonds.broken[k] != 0) == e.broken;
    if (!ok && ++differ <= 5) ADD_FAILURE() << "bond " << k << " differs";
  }
  EXPECT_EQ(differ, 0u) << "of " << kBonds << " bonds (" << failing << " failing, "
                        << flagged_intact << " flagged and intact)";
  EXPECT_TRUE(term.topology_changed());
}

}  // namespace
}  // namespace ringdem
