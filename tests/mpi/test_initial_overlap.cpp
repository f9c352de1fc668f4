// Overlaps at creation (issue 15, item 7): Simulation::overlaps finds them in the first
// neighbour lists of every rank and reduces them to one report, the same on 1, 2 and 3 ranks,
// and a fresh start through RunControl refuses them on every rank alike (InputError, exit 2).
// The expectation is a brute-force search over the whole model built on one process.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <set>
#include <utility>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/RunControl.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/InputError.hpp"

namespace ringdem {
namespace {

constexpr double kTolerance = 1e-3;

/// A ring of 150 particles on a 300 mm ring (bonded neighbours 6.5 mm apart overlap by
/// design, next-but-one ones do not), a jittered lattice whose spheres partly overlap, a fixed
/// pair overlapping each other (not counted) and a sphere in the floor.
CaseConfig overlapping_case() {
  CaseConfig c = testing::base_case();
  c.simulation.dt = 1e-7;
  RingConfig ring = testing::paper_ring({0, 0, 0.3}, {0, 0, 1});
  ring.n_particles = 150;
  c.rings.push_back(ring);
  LatticeConfig lattice;
  lattice.origin = {0.5, 0.0, 0.1};
  lattice.count = {10, 10, 3};
  lattice.spacing = 0.0092;
  lattice.particle_radius = 0.005;
  lattice.jitter = 0.4;
  lattice.seed = 3;
  c.lattices.push_back(lattice);
  SphereConfig fixed;
  fixed.group = "fixed";
  fixed.motion = Motion::kFixed;
  fixed.radius = 0.01;
  fixed.position = {-0.5, 0, 0.1};
  c.spheres.push_back(fixed);
  fixed.position = {-0.5, 0, 0.115};
  c.spheres.push_back(fixed);
  SphereConfig low;
  low.radius = 0.01;
  low.position = {-0.3, 0, 0.002};
  c.spheres.push_back(low);
  RigidBodyConfig floor;
  floor.name = "floor";
  c.rigid_bodies.push_back(floor);
  return c;
}

struct Found {
  std::int64_t count = 0;
  std::vector<std::pair<std::int64_t, std::int64_t>> deepest;  ///< (gid, partner), body: -1-b
};

/// Every pair of the whole model, O(N^2), without the neighbour search.
Found brute_force(const CaseConfig& c) {
  const Model m = build_model(c);
  const ParticleStore& p = m.particles;
  std::set<std::pair<std::int64_t, std::int64_t>> bonded;
  for (std::size_t k = 0; k < m.bonds.size(); ++k)
    bonded.insert({m.bonds.gid_a[k], m.bonds.gid_b[k]});
  std::vector<std::tuple<double, std::int64_t, std::int64_t>> all;
  const std::size_t n = p.n_local();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const std::int64_t a = std::min(p.gid[i], p.gid[j]), b = std::max(p.gid[i], p.gid[j]);
      if (bonded.count({a, b})) continue;
      if (p.motion[i] != Motion::kFree && p.motion[j] != Motion::kFree) continue;
      const double rmin = std::min(p.radius[i], p.radius[j]);
      const double depth = p.radius[i] + p.radius[j] - norm(p.position[i] - p.position[j]);
      if (depth > kTolerance * rmin) all.emplace_back(-depth / rmin, a, b);
    }
    for (std::size_t b = 0; b < m.bodies.size(); ++b) {
      const double depth = p.radius[i] - m.bodies[b].closest(p.position[i]).distance;
      if (depth > kTolerance * p.radius[i])
        all.emplace_back(-depth / p.radius[i], p.gid[i], -1 - static_cast<std::int64_t>(b));
    }
  }
  std::sort(all.begin(), all.end());
  Found f;
  f.count = static_cast<std::int64_t>(all.size());
  for (std::size_t k = 0; k < all.size() && k < 5; ++k)
    f.deepest.push_back({std::get<1>(all[k]), std::get<2>(all[k])});
  return f;
}

TEST(InitialOverlap, ReportEqualsBruteForceOnAnyRankCount) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const CaseConfig c = overlapping_case();
    const Found expected = brute_force(c);
    Simulation sim(build_model(c, comm), comm, settings_from_case(c));
    const OverlapReport report = sim.overlaps(kTolerance);
    // The case must have all three kinds, and bonded neighbours that overlap.
    const Model whole = build_model(c);
    const double bonded_gap = norm(whole.particles.position[1] - whole.particles.position[0]);
    EXPECT_LT(bonded_gap, 2 * 0.0045) << "bonded ring neighbours must overlap";
    EXPECT_GT(expected.count, 5);
    EXPECT_EQ(report.count, expected.count);
    ASSERT_EQ(report.deepest.size(), expected.deepest.size());
    for (std::size_t k = 0; k < report.deepest.size(); ++k) {
      const OverlapReport::Entry& e = report.deepest[k];
      const std::int64_t partner = e.partner_is_body ? -1 - e.partner : e.partner;
      EXPECT_EQ(std::make_pair(e.gid, partner), expected.deepest[k]) << k;
    }
  }
}

TEST(InitialOverlap, FreshStartIsRefusedOnEveryRankUnlessAllowed) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    CaseConfig c = overlapping_case();
    RunControlOptions options;
    options.verbose = false;
    std::string message;
    {
      RunControl control(c, options, comm);
      try {
        control.make_simulation(settings_from_case(c));
      } catch (const InputError& e) {
        message = e.what();
      }
    }
    // Every rank refused (a rank that went on would hang in the next collective).
    EXPECT_FALSE(comm.any(message.empty())) << "a rank accepted the overlapping start";
    const Found expected = brute_force(c);
    EXPECT_NE(message.find(std::to_string(expected.count) + " contacts overlap at the start"),
              std::string::npos)
        << message;
    c.simulation.allow_initial_overlap = true;
    RunControl allowed(c, options, comm);
    EXPECT_NO_THROW(allowed.make_simulation(settings_from_case(c)));
  }
}

}  // namespace
}  // namespace ringdem
