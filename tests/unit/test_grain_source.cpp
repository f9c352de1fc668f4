// Debris grains (issue 13 item 1): the radius distributions against their analytic moments,
// random sequential addition against a brute-force overlap search, and the grain source's
// solid fraction, gids and slices.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <vector>

#include "TestCases.hpp"
#include "domain/GrainPacking.hpp"
#include "domain/GrainSizeDistribution.hpp"
#include "engine/GrainSource.hpp"
#include "engine/ModelBuilder.hpp"

namespace ringdem {
namespace {

double volume(double r) {
  return 4.0 / 3.0 * M_PI * r * r * r;
}

/// Mean grain volume of `n` draws and its standard error.
std::pair<double, double> sampled_mean_volume(const GrainSizeDistribution& d, int n,
                                              std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double v = volume(d.draw(rng));
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n;
  return {mean, std::sqrt((sum2 / n - mean * mean) / n)};
}

TEST(GrainSizeDistribution, UniformDrawsStayInRangeAndMatchTheAnalyticMeanVolume) {
  const auto d = GrainSizeDistribution::uniform(0.005, 0.025);
  std::mt19937_64 rng(3);
  for (int i = 0; i < 10000; ++i) {
    const double r = d.draw(rng);
    ASSERT_GE(r, 0.005);
    ASSERT_LE(r, 0.025);
  }
  // E[r^3] of U(a, b) = (a + b)(a^2 + b^2) / 4, written another way than in the class.
  const double a = 0.005, b = 0.025;
  EXPECT_NEAR(d.mean_volume(), 4.0 / 3.0 * M_PI * (a + b) * (a * a + b * b) / 4.0, 1e-18);
  const auto [mean, se] = sampled_mean_volume(d, 200000, 5);
  EXPECT_NEAR(mean, d.mean_volume(), 4.0 * se);
}

TEST(GrainSizeDistribution, LogNormalHasItsMedianAndItsTruncatedMeanVolume) {
  // A wide truncation: the median of the draws is the distribution's median.
  const auto d = GrainSizeDistribution::log_normal(0.01, 0.4, 0.002, 0.05);
  std::mt19937_64 rng(7);
  std::vector<double> r(100001);
  for (double& x : r)
    x = d.draw(rng);
  std::nth_element(r.begin(), r.begin() + 50000, r.end());
  // The sample median's standard error: 1.2533 sigma_r / sqrt(n), with sigma_r ~ 0.4 * 0.01.
  EXPECT_NEAR(r[50000], 0.01, 4.0 * 1.2533 * 0.004 / std::sqrt(100001.0));
  // A tight truncation: the quadrature's mean volume against the draws.
  const auto tight = GrainSizeDistribution::log_normal(0.01, 0.8, 0.006, 0.02);
  const auto [mean, se] = sampled_mean_volume(tight, 200000, 9);
  EXPECT_NEAR(mean, tight.mean_volume(), 4.0 * se);
  EXPECT_NEAR(GrainSizeDistribution::kept_log_normal_fraction(0.01, 0.4, 1e-9, 0.01), 0.5, 1e-12);
  EXPECT_THROW(GrainSizeDistribution::log_normal(0.001, 0.1, 0.01, 0.02), std::invalid_argument);
}

TEST(GrainSizeDistribution, FractionsGiveEachClassItsShareOfTheSolidVolume) {
  const auto d = GrainSizeDistribution::fractions({{0.02, 0.5}, {0.005, 0.2}, {0.01, 0.3}});
  EXPECT_EQ(d.min_radius(), 0.005);
  EXPECT_EQ(d.max_radius(), 0.02);
  std::mt19937_64 rng(11);
  std::map<double, double> solid;
  double total = 0.0;
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const double r = d.draw(rng);
    solid[r] += volume(r);
    total += volume(r);
  }
  ASSERT_EQ(solid.size(), 3u);
  // The large class has few grains (about 2 % by number), so its share has the largest
  // sampling error: about 0.5 / sqrt(0.02 n) relative, 1.8 %; 5 % is over 2.5 of them.
  EXPECT_NEAR(solid[0.02] / total, 0.5, 0.025);
  EXPECT_NEAR(solid[0.01] / total, 0.3, 0.015);
  EXPECT_NEAR(solid[0.005] / total, 0.2, 0.01);
  // Mean volume: 1 / sum(f_i / v_i).
  EXPECT_NEAR(d.mean_volume(),
              1.0 / (0.5 / volume(0.02) + 0.3 / volume(0.01) + 0.2 / volume(0.005)), 1e-18);
}

/// Smallest gap between two grains, by brute force over every pair.
double smallest_gap(const std::vector<PackedGrain>& g) {
  double gap = 1e300;
  for (std::size_t i = 0; i < g.size(); ++i)
    for (std::size_t j = i + 1; j < g.size(); ++j)
      gap = std::min(gap, norm(g[i].centre - g[j].centre) - g[i].radius - g[j].radius);
  return gap;
}

/// The same by a sweep along x (for tens of thousands of grains): after sorting by x, grain
/// j can touch grain i < j only while x_j - x_i < r_i + r_max. Exact, and not a grid.
double smallest_gap_by_sweep(std::vector<PackedGrain> g) {
  std::sort(g.begin(), g.end(),
            [](const PackedGrain& a, const PackedGrain& b) { return a.centre.x < b.centre.x; });
  double r_max = 0.0;
  for (const PackedGrain& x : g)
    r_max = std::max(r_max, x.radius);
  double gap = 1e300;
  for (std::size_t i = 0; i < g.size(); ++i)
    for (std::size_t j = i + 1; j < g.size() && g[j].centre.x - g[i].centre.x < g[i].radius + r_max;
         ++j)
      gap = std::min(gap, norm(g[i].centre - g[j].centre) - g[i].radius - g[j].radius);
  return gap;
}

TEST(GrainPacking, RandomSequentialAdditionLeavesNoOverlapAndStaysInTheBox) {
  const auto d = GrainSizeDistribution::uniform(0.004, 0.02);
  std::mt19937_64 rng(1);
  const Vec3 lo{-0.1, 0.2, 0.0}, hi{0.1, 0.36, 0.2};
  const double box = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
  const std::vector<double> radii = draw_cell_radii(d, 0.3 * box, rng);
  ASSERT_TRUE(std::is_sorted(radii.rbegin(), radii.rend()));  // largest first
  double solid = 0.0;
  for (const double r : radii)
    solid += volume(r);
  // Drawing stops before the target: at most one largest grain short of it.
  EXPECT_LE(solid, 0.3 * box);
  EXPECT_GT(solid, 0.3 * box - volume(0.02));
  const std::vector<PackedGrain> g = place_grains(radii, lo, hi, rng);
  ASSERT_EQ(g.size(), radii.size());
  EXPECT_GE(smallest_gap(g), 0.0);
  for (std::size_t k = 0; k < g.size(); ++k) {
    EXPECT_EQ(g[k].radius, radii[k]);
    EXPECT_GE(g[k].centre.x - g[k].radius, lo.x);
    EXPECT_LE(g[k].centre.x + g[k].radius, hi.x);
    EXPECT_GE(g[k].centre.y - g[k].radius, lo.y);
    EXPECT_LE(g[k].centre.y + g[k].radius, hi.y);
    EXPECT_GE(g[k].centre.z - g[k].radius, lo.z);
    EXPECT_LE(g[k].centre.z + g[k].radius, hi.z);
  }
}

TEST(GrainPacking, AFillBeyondRandomAdditionIsRefusedWithItsGrain) {
  // Equal spheres at a solid fraction of 0.6: random sequential addition jams near 0.38.
  std::mt19937_64 rng(2);
  const double r = 0.01;
  const std::vector<double> radii(static_cast<std::size_t>(0.6 * 0.1 * 0.1 * 0.1 / volume(r)), r);
  try {
    place_grains(radii, {0, 0, 0}, {0.1, 0.1, 0.1}, rng, 2000);
    FAIL() << "expected a GrainPackingError";
  } catch (const GrainPackingError& e) {
    EXPECT_NE(std::string(e.what()).find("found no room for grain"), std::string::npos) << e.what();
  }
  EXPECT_THROW(place_grains({0.06}, {0, 0, 0}, {0.1, 0.1, 0.1}, rng), GrainPackingError);
}

GrainSource::Spec spec_of_a_mix() {
  GrainSource::Spec s;
  s.box_min = {0.0, -0.3, 0.05};
  s.box_max = {0.9, 0.3, 0.4};
  s.sizes = GrainSizeDistribution::fractions({{0.004, 0.3}, {0.008, 0.3}, {0.016, 0.4}});
  s.solid_fraction = 0.3;
  s.seed = 17;
  s.density = 2600.0;
  return s;
}

TEST(GrainSource, FillsItsBoxAtTheSolidFractionWithoutOverlapsAndSparseGids) {
  const GrainSource::Spec spec = spec_of_a_mix();
  const GrainSource source(spec);
  // Cells at least 8 largest diameters (0.256 m) wide: 3 x 2 x 1 of them.
  EXPECT_EQ(source.cells(), 6);
  Model m;
  source.emit(0, source.gid_range(), SourceBases{1000, 0, 0}, m);
  const ParticleStore& p = m.particles;
  ASSERT_EQ(static_cast<std::int64_t>(p.n_local()), source.count());
  std::vector<PackedGrain> all;
  std::set<std::int64_t> gids;
  double solid = 0.0;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    all.push_back({p.position[k], p.radius[k]});
    solid += volume(p.radius[k]);
    EXPECT_GE(p.gid[k], 1000);
    EXPECT_LT(p.gid[k], 1000 + source.gid_range());
    EXPECT_TRUE(gids.insert(p.gid[k]).second) << "gid " << p.gid[k] << " twice";
    EXPECT_DOUBLE_EQ(p.mass[k], 2600.0 * volume(p.radius[k]));
  }
  // Across cells too (the sweep sees every pair that can touch).
  EXPECT_GE(smallest_gap_by_sweep(all), 0.0);
  // Each cell ends at most one largest grain short of its share of the box.
  const double box = 0.9 * 0.6 * 0.35;
  EXPECT_LE(solid, 0.3 * box);
  EXPECT_GT(solid, 0.3 * box - 6.0 * volume(0.016));
}

TEST(GrainSource, SlicesMakeTheWholePackingBitForBit) {
  CaseConfig c = testing::base_case();
  LatticeConfig lattice;  // a source before it: the grains' gids start after its items
  lattice.count = {3, 2, 2};
  lattice.origin = {0, 0, -0.1};
  c.lattices.push_back(lattice);
  GrainsConfig g;
  g.material = "steel";
  g.box_min = {0.0, -0.3, 0.05};
  g.box_max = {0.9, 0.3, 0.4};
  g.sizes.distribution = GrainDistribution::kLogNormal;
  g.sizes.median_radius = 0.006;
  g.sizes.sigma = 0.5;
  g.sizes.min_radius = 0.003;
  g.sizes.max_radius = 0.015;
  g.seed = 5;
  c.grains.push_back(g);
  const Model whole = build_model(c);
  std::map<std::int64_t, std::pair<Vec3, double>> reference;
  for (std::size_t k = 0; k < whole.particles.n_local(); ++k)
    reference[whole.particles.gid[k]] = {whole.particles.position[k], whole.particles.radius[k]};
  ASSERT_EQ(static_cast<std::int64_t>(reference.size()), whole.initial_particles);
  EXPECT_EQ(reference.begin()->first, 0);
  EXPECT_EQ(std::next(reference.begin(), 12)->first, 12);  // the first grain after the lattice
  for (int ranks : {2, 3, 5, 7}) {
    std::map<std::int64_t, std::pair<Vec3, double>> sliced;
    for (int r = 0; r < ranks; ++r) {
      const Model slice = build_model(c, r, ranks);
      for (std::size_t k = 0; k < slice.particles.n_local(); ++k)
        EXPECT_TRUE(sliced
                        .emplace(slice.particles.gid[k], std::make_pair(slice.particles.position[k],
                                                                        slice.particles.radius[k]))
                        .second)
            << "gid " << slice.particles.gid[k] << " in two slices of " << ranks;
    }
    ASSERT_EQ(sliced.size(), reference.size()) << ranks << " ranks";
    for (const auto& [gid, row] : reference) {
      ASSERT_EQ(sliced.count(gid), 1u) << "gid " << gid << ", " << ranks << " ranks";
      EXPECT_EQ(sliced.at(gid).first, row.first) << "gid " << gid << ", " << ranks << " ranks";
      EXPECT_EQ(sliced.at(gid).second, row.second);
    }
  }
}

TEST(GrainPacking, OrderBySpaceSortsByBinZFastestAndKeepsEachBinsOrder) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 lo{-0.2, 0.1, 0.0};
  const double bin = 0.1;  // 4 x 4 x 4 bins over the 0.4 m box below
  std::vector<PackedGrain> grains;
  for (int k = 0; k < 500; ++k)  // the radius numbers the grains in their first order
    grains.push_back({lo + Vec3{0.4 * u(rng), 0.4 * u(rng), 0.4 * u(rng)}, 1.0 + k});
  std::vector<PackedGrain> ordered = grains;
  order_by_space(ordered, lo, bin);
  ASSERT_EQ(ordered.size(), grains.size());
  const auto bins = [&](const PackedGrain& g) {
    const Vec3 d = g.centre - lo;
    return std::array<int, 3>{static_cast<int>(d.x / bin), static_cast<int>(d.y / bin),
                              static_cast<int>(d.z / bin)};
  };
  std::multiset<double> before, after;
  for (std::size_t k = 0; k < grains.size(); ++k) {
    before.insert(grains[k].radius);
    after.insert(ordered[k].radius);
    const auto& g = ordered[k];
    const std::size_t first = static_cast<std::size_t>(g.radius) - 1;
    EXPECT_EQ(g.centre, grains[first].centre) << "a grain was changed, not moved";
    if (k == 0) continue;
    const auto b0 = bins(ordered[k - 1]), b1 = bins(g);
    EXPECT_LE(b0, b1) << "grain " << k;  // x, then y, then z: z fastest
    if (b0 == b1) {
      EXPECT_LT(ordered[k - 1].radius, g.radius) << "a bin's order changed";
    }
  }
  EXPECT_EQ(before, after);  // a permutation
}

TEST(GrainSource, GrainsThatTouchGetNearbyGids) {
  // The grains' gids are their storage and contact order: grains in contact should be close in
  // it. Within a cell, in random placement order, the mean gid distance of two near grains is
  // a third of the cell's count; in bins of one largest diameter, z fastest, it is about
  // (1 + n_z + n_y n_z) / 3 bins of the n_x n_y n_z: under a tenth here.
  const GrainSource::Spec spec = spec_of_a_mix();
  const GrainSource source(spec);
  Model m;
  source.emit(0, source.gid_range(), SourceBases{0, 0, 0}, m);
  const ParticleStore& p = m.particles;
  std::map<std::int64_t, std::vector<std::size_t>> cells;  // cell -> its grains
  for (std::size_t k = 0; k < p.n_local(); ++k)
    cells[p.gid[k] / source.per_cell()].push_back(k);
  double relative = 0.0;
  int pairs = 0;
  for (const auto& [cell, members] : cells)
    for (std::size_t x = 0; x < members.size(); ++x)
      for (std::size_t y = x + 1; y < members.size(); ++y) {
        const std::size_t a = members[x], b = members[y];
        const double gap = norm(p.position[b] - p.position[a]) - p.radius[a] - p.radius[b];
        if (gap > 0.002) continue;
        relative += static_cast<double>(std::llabs(p.gid[b] - p.gid[a])) /
                    static_cast<double>(members.size());
        ++pairs;
      }
  ASSERT_GT(pairs, 1000);
  EXPECT_LT(relative / pairs, 0.1) << pairs << " near pairs";
  std::printf("near pairs %d, mean gid distance %.4f of a cell's grains\n", pairs,
              relative / pairs);
}

}  // namespace
}  // namespace ringdem
