// Particle sources: the slices that the ranks build, put together, are the whole model, bit for
// bit (a different code path: one pass over every source against P passes over slices), and
// the ids do not depend on the number of slices.
#include <gtest/gtest.h>

#include <sys/mman.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <tuple>

#include "TestCases.hpp"
#include "comm/Communicator.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/SizeEstimate.hpp"

namespace ringdem {
namespace {

/// Every source kind: two loose rings (one with a mass), a 4 x 5 net with shackles, a
/// jittered lattice and two listed spheres.
CaseConfig every_source() {
  CaseConfig c = testing::base_case();
  c.rings.push_back(testing::paper_ring({0, 0, 1.0}));
  auto heavy = testing::paper_ring({0.5, 0, 1.0});
  heavy.mass = 0.7;
  heavy.n_particles = 37;
  c.rings.push_back(heavy);
  RingNetConfig net;
  net.rows = 4;
  net.columns = 5;
  c.nets.push_back(net);
  LatticeConfig lattice;
  lattice.origin = {0, 0, 2.0};
  lattice.count = {7, 5, 3};
  lattice.jitter = 0.4;
  lattice.seed = 11;
  c.lattices.push_back(lattice);
  SphereConfig s;
  s.position = {3, 0, 0};
  c.spheres.push_back(s);
  s.position = {3, 1, 0};
  s.radius = 0.01;
  c.spheres.push_back(s);
  return c;
}

struct ParticleRow {
  Vec3 position, velocity;
  double radius, mass, damping;
  std::int32_t material, body, group;
  Motion motion;
};
struct BondRow {
  std::int64_t gid_a, gid_b;
  double length0, k_axial, k_bend_self, tensile;
  Quat frame_a, frame_b;
};

void collect(const Model& m, std::map<std::int64_t, ParticleRow>& particles,
             std::map<std::int64_t, BondRow>& bonds) {
  const ParticleStore& p = m.particles;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const bool fresh = particles
                           .emplace(p.gid[k], ParticleRow{p.position[k], p.velocity[k], p.radius[k],
                                                          p.mass[k], p.damping_of(k), p.material[k],
                                                          p.body[k], p.group[k], p.motion[k]})
                           .second;
    EXPECT_TRUE(fresh) << "particle " << p.gid[k] << " emitted by two slices";
  }
  const BondStore& b = m.bonds;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const BondRow row{b.gid_a[k],   b.gid_b[k],       b.length0[k],
                      b.k_axial[k], b.k_bend_self[k], b.tensile_strength[k],
                      b.frame_a[k], b.frame_b[k]};
    EXPECT_TRUE(bonds.emplace(b.id[k], row).second) << "bond " << b.id[k] << " emitted twice";
  }
}

TEST(ParticleSources, SlicesOfEverySourceMakeTheWholeModel) {
  const CaseConfig c = every_source();
  const Model whole = build_model(c);
  std::map<std::int64_t, ParticleRow> whole_particles;
  std::map<std::int64_t, BondRow> whole_bonds;
  collect(whole, whole_particles, whole_bonds);
  // Dense gids and bond ids, as counted by the sources.
  ASSERT_EQ(static_cast<std::int64_t>(whole_particles.size()), whole.initial_particles);
  ASSERT_EQ(static_cast<std::int64_t>(whole_bonds.size()), whole.initial_bonds);
  EXPECT_EQ(whole_particles.rbegin()->first, whole.initial_particles - 1);
  EXPECT_EQ(whole_bonds.rbegin()->first, whole.initial_bonds - 1);
  // Bonds: the loose rings' 100 + 37, and 100 on each of the net's 10 rings (the sites of a
  // 4 x 5 lattice with m + n odd); shackles are not bonded.
  EXPECT_EQ(whole.initial_bonds, 137 + 100 * 10);
  for (int ranks : {2, 3, 5, 7}) {
    std::map<std::int64_t, ParticleRow> particles;
    std::map<std::int64_t, BondRow> bonds;
    std::size_t largest = 0;
    for (int r = 0; r < ranks; ++r) {
      const Model slice = build_model(c, r, ranks);
      largest = std::max(largest, slice.particles.n_local());
      EXPECT_EQ(slice.initial_particles, whole.initial_particles);
      EXPECT_EQ(slice.group_names, whole.group_names);
      collect(slice, particles, bonds);
    }
    // Each source splits evenly: at most one more item per source than N / ranks.
    EXPECT_LE(static_cast<double>(largest),
              static_cast<double>(whole.initial_particles) / ranks + 5.0)
        << ranks << " ranks";
    ASSERT_EQ(particles.size(), whole_particles.size()) << ranks << " ranks";
    for (const auto& [gid, row] : whole_particles) {
      const ParticleRow& got = particles.at(gid);
      EXPECT_EQ(got.position, row.position) << "gid " << gid << ", " << ranks << " ranks";
      EXPECT_EQ(got.velocity, row.velocity);
      EXPECT_EQ(got.radius, row.radius);
      EXPECT_EQ(got.mass, row.mass);
      EXPECT_EQ(got.damping, row.damping);
      EXPECT_EQ(got.material, row.material);
      EXPECT_EQ(got.body, row.body) << "gid " << gid;
      EXPECT_EQ(got.group, row.group);
      EXPECT_EQ(got.motion, row.motion);
    }
    ASSERT_EQ(bonds.size(), whole_bonds.size()) << ranks << " ranks";
    for (const auto& [id, row] : whole_bonds) {
      const BondRow& got = bonds.at(id);
      EXPECT_EQ(got.gid_a, row.gid_a) << "bond " << id;
      EXPECT_EQ(got.gid_b, row.gid_b);
      EXPECT_EQ(got.length0, row.length0);
      EXPECT_EQ(got.k_axial, row.k_axial);
      EXPECT_EQ(got.k_bend_self, row.k_bend_self);
      EXPECT_EQ(got.tensile, row.tensile);
      EXPECT_EQ(got.frame_a, row.frame_a);
      EXPECT_EQ(got.frame_b, row.frame_b);
    }
  }
}

TEST(ParticleSources, RingBondsJoinConsecutiveParticlesOfOneRing) {
  // Independent of the source's bookkeeping: every bond joins two particles of one body whose
  // gids differ by 1, or the first and the last of the ring, at the ring's chord length.
  const CaseConfig c = every_source();
  const Model m = build_model(c);
  const ParticleStore& p = m.particles;
  for (std::size_t k = 0; k < m.bonds.size(); ++k) {
    const auto a = static_cast<std::size_t>(p.index_of(m.bonds.gid_a[k]));
    const auto b = static_cast<std::size_t>(p.index_of(m.bonds.gid_b[k]));
    EXPECT_EQ(p.body[a], p.body[b]) << "bond " << k;
    const std::int64_t d = m.bonds.gid_b[k] - m.bonds.gid_a[k];
    const auto ring_size =
        static_cast<std::int64_t>(std::count(p.body.begin(), p.body.end(), p.body[a]));
    EXPECT_TRUE(d == 1 || d == ring_size - 1) << "bond " << k << " spans " << d;
    EXPECT_NEAR(m.bonds.length0[k], norm(p.position[b] - p.position[a]), 1e-15);
  }
}

// Only bonds read a particle's orientation. A model without bonds keeps no orientation column:
// not in memory, not among the fields that migrate, go to ghosts or into checkpoints, also while
// grains arrive and leave. A model with bonds keeps one for every particle.
TEST(ParticleSources, OnlyModelsWithBondsKeepOrientations) {
  const auto registered = [](ParticleStore& p) {
    bool found = false;
    p.for_each_field([&](const FieldInfo& f, auto&) { found = found || f.name == "orientation"; });
    return found;
  };
  Model bonded = build_model(every_source());
  ASSERT_GT(bonded.bonds.size(), 0u);
  EXPECT_TRUE(bonded.particles.tracks_orientation());
  EXPECT_EQ(bonded.particles.orientation.size(), bonded.particles.n_total());
  EXPECT_TRUE(registered(bonded.particles));

  const CaseConfig c = testing::grains_entering_and_leaving();
  Model grains = build_model(c);
  ASSERT_GT(grains.particles.n_local(), 0u);
  EXPECT_FALSE(grains.particles.tracks_orientation());
  EXPECT_FALSE(registered(grains.particles));
  EXPECT_EQ(grains.particles.orientation.capacity(), 0u);
  const Communicator comm = testing::self_comm();
  Simulation sim(std::move(grains), comm, settings_from_case(c));
  const std::int64_t before = sim.inflow_totals().grains;
  sim.run_steps(2000);
  ASSERT_GT(sim.inflow_totals().grains, before) << "no grain arrived: the test checks nothing";
  ASSERT_GT(sim.outflow_totals().grains, 0) << "no grain left: the test checks nothing";
  EXPECT_EQ(sim.model().particles.orientation.capacity(), 0u);
}

// A rank sizes its store once, for its share of every source, before the first particle is
// added: grown one particle at a time, the columns' discarded smaller copies stayed resident
// (about 60 MiB at 10^6 grains). Dense sources give each rank an exact count, so on one rank
// the columns hold no slack, and on several exactly the headroom for the first distribution;
// so does a sparse one (packing cells) on one rank. On several, its share is estimated from
// its average (5 % over): a rank whose cells are fuller grows once.
TEST(ParticleSources, EachRankSizesItsStoreOnceForItsShare) {
  const CaseConfig dense = every_source();
  for (int ranks : {1, 2, 3}) {
    std::int64_t total = 0;
    for (int rank = 0; rank < ranks; ++rank) {
      const Model m = build_model(dense, rank, ranks);
      const std::size_t n = m.particles.n_local();
      ASSERT_GT(n, 0u);
      const std::size_t reserved =
          ranks == 1 ? n
                     : static_cast<std::size_t>(static_cast<double>(n) *
                                                ParticleStore::kDistributedHeadroom);
      EXPECT_EQ(m.particles.mass.capacity(), reserved) << "rank " << rank << " of " << ranks;
      EXPECT_EQ(m.particles.position.capacity(), reserved);
      total += static_cast<std::int64_t>(m.particles.n_local());
    }
    EXPECT_EQ(total, build_model(dense).initial_particles);
  }
  const CaseConfig sparse = testing::grains_entering_and_leaving();
  const Model whole = build_model(sparse);
  ASSERT_GT(whole.particles.n_local(), 0u);
  EXPECT_EQ(whole.particles.mass.capacity(), whole.particles.n_local());
}

}  // namespace
}  // namespace ringdem

namespace ringdem {
namespace {

TEST(SizeEstimate, ClosedFormsCountWhatTheSourcesBuild) {
  // Against the built model (a different code path: the net generator and the sources),
  // for nets with even and odd rows and columns, with and without shackles.
  for (const auto& [rows, columns, shackles] :
       {std::tuple{4, 5, true}, std::tuple{5, 5, true}, std::tuple{6, 4, false},
        std::tuple{3, 7, true}, std::tuple{2, 2, true}}) {
    CaseConfig c = every_source();
    c.nets[0].rows = rows;
    c.nets[0].columns = columns;
    c.nets[0].shackles.enabled = shackles;
    const Model m = build_model(c);
    const SizeEstimate e = estimate_size(c);
    EXPECT_EQ(e.particles, m.initial_particles) << rows << " x " << columns;
    EXPECT_EQ(e.bonds, m.initial_bonds) << rows << " x " << columns;
  }
  // Memory per rank falls with the ranks, ghosts and the base aside.
  SizeEstimate big;
  big.particles = 1000000;
  EXPECT_NEAR(big.bytes_per_rank(1),
              SizeEstimate::kBaseBytes + 1.0e6 * SizeEstimate::kBytesPerParticle, 1.0);
  EXPECT_LT(big.bytes_per_rank(4), 0.4 * big.bytes_per_rank(1));
}

TEST(ResidentMemory, SharedPagesTouchedAreCountedAsShared) {
  // A shared mapping of 8 MiB, every page touched: the shared resident memory rises by what
  // was touched (the kernel counts it in 4 KiB pages; a page or two of slack), the peak with it.
  constexpr std::size_t kBytes = 8u << 20;
  const double before = shared_resident_bytes();
  void* block = mmap(nullptr, kBytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(block, MAP_FAILED);
  std::memset(block, 1, kBytes);
  const double touched = shared_resident_bytes() - before;
  EXPECT_NEAR(touched, static_cast<double>(kBytes), 64.0 * 1024) << "before " << before;
  EXPECT_GE(peak_resident_bytes(), static_cast<double>(kBytes));
  munmap(block, kBytes);
  EXPECT_NEAR(shared_resident_bytes(), before, 64.0 * 1024);
}

}  // namespace
}  // namespace ringdem
