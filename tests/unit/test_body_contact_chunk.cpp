// The particle–body term runs the contact law over a chunk of contacts as one vectorised loop
// (BodyContactChunk). Its lanes must give bit for bit what the contact law gives one contact at
// a time in scalar code (the reference below: the evaluator called per contact, as the term
// did before it had lanes): the force, the torque on the particle, the carried spring and the
// energy ledger's viscous force, rolling torque and energies. The contacts cover sticking and
// sliding, a fresh spring, a spring to be turned into the contact plane, a plane and a curved
// body, a fixed and a free body, rolling friction on and off, and a chunk that is not full.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/BodyContactChunk.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {
namespace {

struct Contact {
  HertzMindlin::Input in;
  Vec3 spring;
  HertzMindlin::Params params;
};

std::vector<Contact> random_contacts(std::size_t n, bool rolling, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), rad(0.004, 0.02), frac(0.0, 1.0);
  const HertzMindlin::Params rock_on_steel =
      HertzMindlin::Params::mix(1e9, 0.25, 2.1e11, 0.3, 0.3, 0.5, rolling ? 0.1 : 0.0);
  const HertzMindlin::Params rock_on_rock =
      HertzMindlin::Params::mix(3e10, 0.25, 3e10, 0.25, 0.5, 0.6, 0.0);
  std::vector<Contact> out(n);
  for (std::size_t c = 0; c < n; ++c) {
    Contact& k = out[c];
    const double radius = rad(rng);
    const Vec3 n_hat = normalized(Vec3{unit(rng), unit(rng), unit(rng)});
    const double overlap = 0.02 * radius * frac(rng);
    k.in.normal = n_hat;
    k.in.overlap = overlap;
    // A plane (R* = the particle's radius) or a curved body of radius 0.1 m.
    k.in.r_star = c % 2 == 0 ? radius : radius * 0.1 / (radius + 0.1);
    // A fixed body (m* = m) or a free one of 10 kg.
    const double mass = 2600.0 * 4.18879 * radius * radius * radius;
    k.in.m_star = c % 5 == 0 ? mass * 10.0 / (mass + 10.0) : mass;
    k.in.v_rel = Vec3{unit(rng), unit(rng), unit(rng)} * 0.5;
    k.in.arm_i = radius - 0.5 * overlap;
    k.in.arm_j = 0.0;
    k.in.omega_i = c % 7 == 0 ? Vec3{} : Vec3{unit(rng), unit(rng), unit(rng)} * 50.0;
    k.in.omega_j = c % 3 == 0 ? Vec3{unit(rng), unit(rng), unit(rng)} : Vec3{};
    switch (c % 4) {
      case 0:
        k.spring = Vec3{};
        break;
      case 1:
        k.spring = Vec3{unit(rng), unit(rng), unit(rng)} * 1e-3;  // sticking
        break;
      case 2:
        k.spring = Vec3{unit(rng), unit(rng), unit(rng)} * 1e4;  // sliding
        break;
      default:
        k.spring = n_hat * 0.5;  // purely normal: not rescaled
        break;
    }
    k.params = c % 3 == 1 ? rock_on_rock : rock_on_steel;
  }
  return out;
}

void expect_same(const Vec3& got, const Vec3& want, const char* what, std::size_t c) {
  EXPECT_EQ(got.x, want.x) << what << ", lane " << c;
  EXPECT_EQ(got.y, want.y) << what << ", lane " << c;
  EXPECT_EQ(got.z, want.z) << what << ", lane " << c;
}

// Fills a chunk with `n` contacts, runs it, and compares every lane with the scalar path;
// returns how many lanes slid and how many had a rolling torque.
std::pair<int, int> check_chunk(std::size_t n, bool rolling, unsigned seed) {
  const double dt = 2e-6;
  const auto contacts = random_contacts(n, rolling, seed);
  BodyContactChunk chunk;
  for (std::size_t c = 0; c < n; ++c)
    chunk.add(static_cast<std::uint32_t>(c), contacts[c].in, contacts[c].params,
              contacts[c].spring);
  EXPECT_EQ(chunk.any_rolling, rolling);
  chunk.compute(dt);
  int sliding = 0, rolls = 0;
  for (std::size_t c = 0; c < n; ++c) {
    HertzMindlin::Input in = contacts[c].in;
    in.dt = dt;
    Vec3 spring = contacts[c].spring;
    const auto r = HertzMindlin::compute(contacts[c].params, in, spring);
    EXPECT_EQ(chunk.candidate[c], c);
    expect_same(chunk.force.get(c), r.force_i, "force", c);
    expect_same(chunk.torque.get(c), cross(in.normal * in.arm_i, r.force_i) + r.rolling_torque_i,
                "torque", c);
    expect_same(chunk.spring.get(c), spring, "spring", c);
    expect_same(chunk.damping.get(c), r.damping_force_i, "viscous force", c);
    expect_same(chunk.rolling.get(c), r.rolling_torque_i, "rolling torque", c);
    EXPECT_EQ(chunk.tangential_energy[c], r.tangential_energy) << "lane " << c;
    EXPECT_EQ(chunk.elastic_energy[c], r.elastic_energy) << "lane " << c;
    sliding += r.sliding;
    rolls += norm2(r.rolling_torque_i) > 0.0;
  }
  return {sliding, rolls};
}

TEST(BodyContactChunk, LanesGiveTheScalarContactLawBitForBit) {
  const auto [sliding, rolls] = check_chunk(BodyContactChunk::kSize, true, 3);
  // The contacts must exercise both sides of the Coulomb cap and the rolling torque.
  EXPECT_GT(sliding, 4);
  EXPECT_LT(sliding, static_cast<int>(BodyContactChunk::kSize) - 4);
  EXPECT_GT(rolls, 4);
}

TEST(BodyContactChunk, WithoutRollingFrictionAndNotFull) {
  // No contact with rolling friction: the loop without the rolling torques runs, and must give
  // what the full contact law gives (zero torques). 29 lanes: the vector loop's remainder.
  const auto [sliding, rolls] = check_chunk(29, false, 11);
  EXPECT_GT(sliding, 2);
  EXPECT_EQ(rolls, 0);
}

}  // namespace
}  // namespace ringdem
