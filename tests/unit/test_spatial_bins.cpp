// The spatial bins of a re-sort (domain/SpatialBins): each grain's bin is the cube of the
// given edge that holds its centre, numbered slowest along the order's axis (z: x fastest), the
// fastest axis's index kept modulo 2048 and the others' modulo 1024, above every unbinned
// particle's bin 0. The slowest axis is the longest of the grains' box. Expectations are the
// cube indices worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "domain/SpatialBins.hpp"

namespace ringdem {
namespace {

constexpr std::uint32_t kB = SpatialBins::kBinned;

TEST(SpatialBins, NumbersCubesXFastestZSlowest) {
  const double w = 0.1;
  EXPECT_EQ(SpatialBins::bin_of({0.05, 0.05, 0.05}, {w}), kB);
  EXPECT_EQ(SpatialBins::bin_of({0.35, 0.0, 0.0}, {w}), kB | 3u);
  EXPECT_EQ(SpatialBins::bin_of({0.0, 0.25, 0.0}, {w}), kB | 2u << 11);
  EXPECT_EQ(SpatialBins::bin_of({0.0, 0.0, 0.15}, {w}), kB | 1u << 21);
  EXPECT_EQ(SpatialBins::bin_of({0.35, 0.25, 0.15}, {w}), kB | 1u << 21 | 2u << 11 | 3u);
  // x fastest: the next cube along x comes before the next along y, which comes before the
  // next up, however far along.
  EXPECT_LT(SpatialBins::bin_of({50.0, 0.0, 0.0}, {w}), SpatialBins::bin_of({0.0, 0.1, 0.0}, {w}));
  EXPECT_LT(SpatialBins::bin_of({50.0, 50.0, 0.0}, {w}), SpatialBins::bin_of({0.0, 0.0, 0.1}, {w}));
}

TEST(SpatialBins, NumbersTheOrdersSlowestAxisLastAndTheOthersXBeforeYBeforeZ) {
  const double w = 0.1;
  const Vec3 x{0.35, 0.0, 0.0}, y{0.0, 0.25, 0.0}, z{0.0, 0.0, 0.15};
  // x slowest: y fastest, then z.
  const SpatialBins::Order along_x{w, SpatialBins::kX};
  EXPECT_EQ(SpatialBins::bin_of(y, along_x), kB | 2u);
  EXPECT_EQ(SpatialBins::bin_of(z, along_x), kB | 1u << 11);
  EXPECT_EQ(SpatialBins::bin_of(x, along_x), kB | 3u << 21);
  EXPECT_LT(SpatialBins::bin_of({0.0, 50.0, 50.0}, along_x),
            SpatialBins::bin_of({0.1, 0.0, 0.0}, along_x));
  // y slowest: x fastest, then z.
  const SpatialBins::Order along_y{w, SpatialBins::kY};
  EXPECT_EQ(SpatialBins::bin_of(x, along_y), kB | 3u);
  EXPECT_EQ(SpatialBins::bin_of(z, along_y), kB | 1u << 11);
  EXPECT_EQ(SpatialBins::bin_of(y, along_y), kB | 2u << 21);
  // The fastest axis keeps its 2048 cubes: y's wraps at 2048 with x slowest.
  EXPECT_EQ(SpatialBins::bin_of({0.0, -0.05, 0.0}, along_x), kB | 2047u);
  EXPECT_EQ(SpatialBins::bin_of({-0.05, 0.0, 0.0}, along_x), kB | 1023u << 21);
}

TEST(SpatialBins, TheSlowestAxisIsTheLongestOfTheBoxTiesGoingToZThenY) {
  EXPECT_EQ(SpatialBins::slowest_axis({5.0, 1.24, 0.5}), SpatialBins::kX);  // a channel
  EXPECT_EQ(SpatialBins::slowest_axis({1.0, 2.0, 0.5}), SpatialBins::kY);
  EXPECT_EQ(SpatialBins::slowest_axis({1.0, 1.0, 3.0}), SpatialBins::kZ);
  EXPECT_EQ(SpatialBins::slowest_axis({1.0, 1.0, 1.0}), SpatialBins::kZ);  // a cube: as before
  EXPECT_EQ(SpatialBins::slowest_axis({2.0, 1.0, 2.0}), SpatialBins::kZ);
  EXPECT_EQ(SpatialBins::slowest_axis({2.0, 2.0, 1.0}), SpatialBins::kY);
}

TEST(SpatialBins, WrapsIndicesOfEitherSign) {
  const double w = 0.01;
  // floor(-0.005 / 0.01) = -1: the last index of each axis.
  EXPECT_EQ(SpatialBins::bin_of({-0.005, 0.0, 0.0}, {w}), kB | 2047u);
  EXPECT_EQ(SpatialBins::bin_of({0.0, -0.005, 0.0}, {w}), kB | 1023u << 11);
  EXPECT_EQ(SpatialBins::bin_of({0.0, 0.0, -0.005}, {w}), kB | 1023u << 21);
  // 2048 cubes along x, 1024 along y and z, give the same bin as the origin's.
  EXPECT_EQ(SpatialBins::bin_of({20.485, 0.0, 0.0}, {w}),
            SpatialBins::bin_of({0.005, 0.0, 0.0}, {w}));
  EXPECT_EQ(SpatialBins::bin_of({0.0, 10.245, 10.245}, {w}),
            SpatialBins::bin_of({0.0, 0.005, 0.005}, {w}));
  EXPECT_NE(SpatialBins::bin_of({10.245, 0.0, 0.0}, {w}),
            SpatialBins::bin_of({0.005, 0.0, 0.0}, {w}));
}

TEST(SpatialBins, BinsOnlyOwnedGrainsOfNoRingOrClump) {
  ParticleStore p;
  const auto add = [&p](std::int64_t gid, Vec3 x, double r, std::int32_t body) {
    ParticleStore::NewParticle np;
    np.gid = gid;
    np.position = x;
    np.radius = r;
    np.density = 1000.0;
    np.body = body;
    p.add(np);
  };
  add(0, {0.31, 0.0, 0.0}, 0.004, -1);
  add(1, {0.31, 0.0, 0.0}, 0.001, 7);  // a ring's particle: smaller, but never binned
  add(2, {0.0, 0.0, 0.21}, 0.003, -1);
  add(3, {0.5, 0.5, 0.5}, 0.002, -1);  // becomes a ghost below
  p.resize_local(3);
  p.resize_ghosts(1);
  p.sort_bin[3] = 12345;  // a ghost's bin is its owner's, sent by the comm layer
  EXPECT_EQ(SpatialBins::smallest_binned_radius(p), 0.003);
  // The box of the owned grains only: not the ring's particle, not the ghost.
  const auto [lo, hi] = SpatialBins::binned_box(p);
  EXPECT_EQ(lo.x, 0.0);
  EXPECT_EQ(lo.y, 0.0);
  EXPECT_EQ(lo.z, 0.0);
  EXPECT_EQ(hi.x, 0.31);
  EXPECT_EQ(hi.y, 0.0);
  EXPECT_EQ(hi.z, 0.21);
  SpatialBins::assign(p, {0.1});
  EXPECT_EQ(p.sort_bin[0], kB | 3u);
  EXPECT_EQ(p.sort_bin[1], 0u);
  EXPECT_EQ(p.sort_bin[2], kB | 2u << 21);
  EXPECT_EQ(p.sort_bin[3], 12345u);
  // Key order: the ring's particle (bin 0) first, then by bin (gid 2 lies higher in z).
  EXPECT_TRUE(p.sorts_before(1, 0));
  EXPECT_TRUE(p.sorts_before(0, 2));
  // Equal bins go by gid.
  p.sort_bin[2] = p.sort_bin[0];
  EXPECT_TRUE(p.sorts_before(0, 2));
  EXPECT_FALSE(p.sorts_before(2, 0));

  ParticleStore rings_only;
  EXPECT_EQ(SpatialBins::smallest_binned_radius(rings_only),
            std::numeric_limits<double>::infinity());
  EXPECT_EQ(SpatialBins::binned_box(rings_only).first.x, std::numeric_limits<double>::infinity());
  EXPECT_EQ(SpatialBins::binned_box(rings_only).second.z, -std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace ringdem
