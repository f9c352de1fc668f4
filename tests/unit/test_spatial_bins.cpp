// The spatial bins of a re-sort (domain/SpatialBins): each grain's bin is the cube of the
// given edge that holds its centre, numbered x fastest and z slowest, its indices kept modulo
// 2048 (x) and 1024 (y, z), above every unbinned particle's bin 0. Expectations are the cube
// indices worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "domain/SpatialBins.hpp"

namespace ringdem {
namespace {

constexpr std::uint32_t kB = SpatialBins::kBinned;

TEST(SpatialBins, NumbersCubesXFastestZSlowest) {
  const double w = 0.1;
  EXPECT_EQ(SpatialBins::bin_of({0.05, 0.05, 0.05}, w), kB);
  EXPECT_EQ(SpatialBins::bin_of({0.35, 0.0, 0.0}, w), kB | 3u);
  EXPECT_EQ(SpatialBins::bin_of({0.0, 0.25, 0.0}, w), kB | 2u << 11);
  EXPECT_EQ(SpatialBins::bin_of({0.0, 0.0, 0.15}, w), kB | 1u << 21);
  EXPECT_EQ(SpatialBins::bin_of({0.35, 0.25, 0.15}, w), kB | 1u << 21 | 2u << 11 | 3u);
  // x fastest: the next cube along x comes before the next along y, which comes before the
  // next up, however far along.
  EXPECT_LT(SpatialBins::bin_of({50.0, 0.0, 0.0}, w), SpatialBins::bin_of({0.0, 0.1, 0.0}, w));
  EXPECT_LT(SpatialBins::bin_of({50.0, 50.0, 0.0}, w), SpatialBins::bin_of({0.0, 0.0, 0.1}, w));
}

TEST(SpatialBins, WrapsIndicesOfEitherSign) {
  const double w = 0.01;
  // floor(-0.005 / 0.01) = -1: the last index of each axis.
  EXPECT_EQ(SpatialBins::bin_of({-0.005, 0.0, 0.0}, w), kB | 2047u);
  EXPECT_EQ(SpatialBins::bin_of({0.0, -0.005, 0.0}, w), kB | 1023u << 11);
  EXPECT_EQ(SpatialBins::bin_of({0.0, 0.0, -0.005}, w), kB | 1023u << 21);
  // 2048 cubes along x, 1024 along y and z, give the same bin as the origin's.
  EXPECT_EQ(SpatialBins::bin_of({20.485, 0.0, 0.0}, w), SpatialBins::bin_of({0.005, 0.0, 0.0}, w));
  EXPECT_EQ(SpatialBins::bin_of({0.0, 10.245, 10.245}, w),
            SpatialBins::bin_of({0.0, 0.005, 0.005}, w));
  EXPECT_NE(SpatialBins::bin_of({10.245, 0.0, 0.0}, w), SpatialBins::bin_of({0.005, 0.0, 0.0}, w));
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
  SpatialBins::assign(p, 0.1);
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
}

}  // namespace
}  // namespace ringdem
