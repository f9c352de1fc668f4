// The pair kernel runs the contact law over a chunk of contacts as one vectorised loop
// (PairContactChunk). Its lanes must give bit for bit what the contact law gives one contact
// at a time in scalar code (the reference below, written from physics.md §3 with the
// evaluator called per contact): the force, both torques, the carried spring and the energy
// ledger's loads, moments and energies. The contacts cover the contact law's cases: sticking
// and sliding, a fresh spring, a spring to be turned into the contact plane, two materials,
// rolling friction on and off, and a chunk that is not full.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/PairContactChunk.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {
namespace {

struct PairCase {
  Vec3 d, va, vb, wa, wb, spring;
  double ra, rb, m_star;
  HertzMindlin::Params params;
};

std::vector<PairCase> random_pair_cases(std::size_t n, bool rolling, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), rad(0.004, 0.02), frac(0.0, 1.0);
  const HertzMindlin::Params rock =
      HertzMindlin::Params::mix(1e9, 0.25, 1e9, 0.25, 0.3, 0.5, rolling ? 0.1 : 0.0);
  const HertzMindlin::Params steel =
      HertzMindlin::Params::mix(2.1e11, 0.3, 1e9, 0.25, 0.5, 0.3, 0.0);
  std::vector<PairCase> out(n);
  for (std::size_t c = 0; c < n; ++c) {
    PairCase& k = out[c];
    k.ra = rad(rng);
    k.rb = rad(rng);
    Vec3 dir{unit(rng), unit(rng), unit(rng)};
    dir = normalized(dir);
    k.d = dir * ((k.ra + k.rb) * (1.0 - 0.02 * frac(rng)));  // overlap up to 2 % of the reach
    k.va = Vec3{unit(rng), unit(rng), unit(rng)} * 0.5;
    k.vb = Vec3{unit(rng), unit(rng), unit(rng)} * 0.5;
    k.wa = Vec3{unit(rng), unit(rng), unit(rng)} * 50.0;
    k.wb = c % 7 == 0 ? Vec3{} : Vec3{unit(rng), unit(rng), unit(rng)} * 50.0;  // no spin
    // Carried springs: none, small ones (sticking), large ones (sliding), and purely normal
    // ones (turned into the plane they have no length in: not rescaled).
    switch (c % 4) {
      case 0:
        k.spring = Vec3{};
        break;
      case 1:
        k.spring = Vec3{unit(rng), unit(rng), unit(rng)} * 1e-3;
        break;
      case 2:
        k.spring = Vec3{unit(rng), unit(rng), unit(rng)} * 1e4;
        break;
      default:
        k.spring = dir * 0.5;
        break;
    }
    k.m_star = 0.5 * (1.0 + frac(rng));
    k.params = c % 3 == 0 ? steel : rock;
  }
  return out;
}

struct PairExpected {
  Vec3 force, torque_a, torque_b, spring, damping, damping_moment_a, damping_moment_b,
      friction_moment_a, friction_moment_b;
  double half_tangential, half_elastic;
  bool sliding, rolling;
};

// One contact at a time, as the term computed it before the kernel had lanes.
PairExpected scalar_reference(const PairCase& k, double dt) {
  const double dist = std::sqrt(norm2(k.d));
  const Vec3 n = k.d / dist;
  const double reach = k.ra + k.rb;
  const double overlap = reach - dist;
  const double arm_a = k.ra - 0.5 * overlap, arm_b = k.rb - 0.5 * overlap;
  HertzMindlin::Input in;
  in.normal = n;
  in.overlap = overlap;
  in.r_star = k.ra * k.rb / reach;
  in.m_star = k.m_star;
  in.v_rel = (k.vb + cross(k.wb, n * (-arm_b))) - (k.va + cross(k.wa, n * arm_a));
  in.dt = dt;
  in.arm_i = arm_a;
  in.arm_j = arm_b;
  in.omega_i = k.wa;
  in.omega_j = k.wb;
  PairExpected e;
  e.spring = k.spring;
  const auto r = HertzMindlin::compute(k.params, in, e.spring);
  const Vec3 lever_a = n * arm_a, lever_b = n * -arm_b;
  e.force = r.force_i;
  e.torque_a = cross(lever_a, r.force_i) + r.rolling_torque_i;
  e.torque_b = cross(n * arm_b, r.force_i) + r.rolling_torque_j;
  e.damping = r.damping_force_i;
  e.damping_moment_a = cross(lever_a, r.damping_force_i);
  e.damping_moment_b = cross(lever_b, -r.damping_force_i);
  e.friction_moment_a = cross(lever_a, e.spring) + r.rolling_torque_i;
  e.friction_moment_b = cross(lever_b, -e.spring) + r.rolling_torque_j;
  e.half_tangential = 0.5 * r.tangential_energy;
  e.half_elastic = 0.5 * r.elastic_energy;
  e.sliding = r.sliding;
  e.rolling = norm2(r.rolling_torque_i) > 0.0;
  return e;
}

void expect_same_vector(const Vec3& got, const Vec3& want, const char* what, std::size_t c) {
  EXPECT_EQ(got.x, want.x) << what << ", lane " << c;
  EXPECT_EQ(got.y, want.y) << what << ", lane " << c;
  EXPECT_EQ(got.z, want.z) << what << ", lane " << c;
}

// Fills a chunk with `n` contacts, runs it, and compares every lane with the scalar path;
// returns how many lanes slid and how many had a rolling torque.
std::pair<int, int> check_pair_chunk(std::size_t n, bool rolling, unsigned seed) {
  const double dt = 2e-6;
  const auto contacts = random_pair_cases(n, rolling, seed);
  PairContactChunk chunk;
  for (std::size_t c = 0; c < n; ++c) {
    const PairCase& k = contacts[c];
    chunk.add(static_cast<std::uint32_t>(c), 0, 1, k.d, norm2(k.d), k.ra, k.rb, k.m_star, k.va,
              k.vb, k.wa, k.wb, k.params, k.spring);
  }
  EXPECT_EQ(chunk.any_rolling, rolling);
  chunk.compute<PairContactChunk::Ledger::kPerParticle>(dt);
  int sliding = 0, rolls = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const PairExpected e = scalar_reference(contacts[c], dt);
    expect_same_vector(chunk.force_a.get(c), e.force, "force", c);
    expect_same_vector(chunk.torque_a.get(c), e.torque_a, "torque on a", c);
    expect_same_vector(chunk.torque_b.get(c), e.torque_b, "torque on b", c);
    expect_same_vector(chunk.spring.get(c), e.spring, "spring", c);
    expect_same_vector(chunk.damping_a.get(c), e.damping, "viscous force", c);
    expect_same_vector(chunk.damping_moment_a.get(c), e.damping_moment_a, "viscous moment on a", c);
    expect_same_vector(chunk.damping_moment_b.get(c), e.damping_moment_b, "viscous moment on b", c);
    expect_same_vector(chunk.friction_moment_a.get(c), e.friction_moment_a, "spring moment on a",
                       c);
    expect_same_vector(chunk.friction_moment_b.get(c), e.friction_moment_b, "spring moment on b",
                       c);
    EXPECT_EQ(chunk.half_tangential_energy[c], e.half_tangential) << "lane " << c;
    EXPECT_EQ(chunk.half_elastic_energy[c], e.half_elastic) << "lane " << c;
    sliding += e.sliding;
    rolls += e.rolling;
  }
  return {sliding, rolls};
}

TEST(PairContactChunk, LanesGiveTheScalarContactLawBitForBit) {
  const auto [sliding, rolls] = check_pair_chunk(PairContactChunk::kSize, true, 5);
  // The contacts must exercise both sides of the Coulomb cap and the rolling torque.
  EXPECT_GT(sliding, 4);
  EXPECT_LT(sliding, static_cast<int>(PairContactChunk::kSize) - 4);
  EXPECT_GT(rolls, 4);
}

TEST(PairContactChunk, WithoutRollingFrictionAndNotFull) {
  // No pair with rolling friction: the kernel without the rolling torques runs, and must give
  // what the full contact law gives (zero torques). 37 lanes: the vector loop's remainder.
  const auto [sliding, rolls] = check_pair_chunk(37, false, 9);
  EXPECT_GT(sliding, 2);
  EXPECT_EQ(rolls, 0);
}

TEST(PairContactChunk, LanesPastTheLastContactRunOnItsInputs) {
  // The law runs in whole vectors (PairContactChunk::kLaneMultiple): a chunk of 37 contacts
  // runs 40 lanes, and lanes 37..39 must run on a copy of lane 36's inputs, not on whatever an
  // earlier chunk left there (stale or denormal inputs cost time, NaNs would only hide). Equal
  // inputs give equal results, so every result of those lanes must be lane 36's, bit for bit,
  // while lane 36 itself is still the scalar law's.
  constexpr std::size_t n = 37;
  static_assert(n % PairContactChunk::kLaneMultiple != 0);
  const double dt = 2e-6;
  const auto contacts = random_pair_cases(PairContactChunk::kSize, false, 13);
  PairContactChunk chunk;
  // A full chunk first, so that the lanes past 37 hold another contact's inputs.
  for (std::size_t c = 0; c < PairContactChunk::kSize; ++c) {
    const PairCase& k = contacts[c];
    chunk.add(static_cast<std::uint32_t>(c), 0, 1, k.d, norm2(k.d), k.ra, k.rb, k.m_star, k.va,
              k.vb, k.wa, k.wb, k.params, k.spring);
  }
  chunk.n = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const PairCase& k = contacts[PairContactChunk::kSize - 1 - c];
    chunk.add(static_cast<std::uint32_t>(c), 0, 1, k.d, norm2(k.d), k.ra, k.rb, k.m_star, k.va,
              k.vb, k.wa, k.wb, k.params, k.spring);
    // A carried ledger state: a damping force and an overlap of a step earlier.
    chunk.carried_ledger.set(c, ContactLedgerState::of(k.va * 0.01, 1e-5));
  }
  chunk.compute<PairContactChunk::Ledger::kPerContactWithEnergies>(dt);
  const std::size_t last = n - 1;
  const PairExpected e = scalar_reference(contacts[PairContactChunk::kSize - n], dt);
  expect_same_vector(chunk.force_a.get(last), e.force, "force", last);
  for (std::size_t c = n; c < 40; ++c) {
    expect_same_vector(chunk.force_a.get(c), chunk.force_a.get(last), "force", c);
    expect_same_vector(chunk.torque_b.get(c), chunk.torque_b.get(last), "torque on b", c);
    expect_same_vector(chunk.spring.get(c), chunk.spring.get(last), "spring", c);
    for (const auto* half : {&chunk.start_half_work, &chunk.end_half_work}) {
      EXPECT_EQ(half->damping[c], half->damping[last]) << "lane " << c;
      EXPECT_EQ(half->friction[c], half->friction[last]) << "lane " << c;
    }
    EXPECT_EQ(chunk.ledger_to_carry.overlap[c], chunk.ledger_to_carry.overlap[last])
        << "lane " << c;
    EXPECT_EQ(chunk.half_elastic_energy[c], chunk.half_elastic_energy[last]) << "lane " << c;
  }
}

}  // namespace
}  // namespace ringdem
