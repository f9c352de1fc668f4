// The barrier measures of a free run (app/BarrierMonitor, scenario.barrier, issue 13 item 3):
// grains placed at known distances from the barrier plane, with known velocities, against the
// sums and maxima worked out here by hand; the net's largest bond utilisation located by the
// rule "lowest gid pair among equals"; the loader's errors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "TestCases.hpp"
#include "app/BarrierMonitor.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/InputError.hpp"

namespace ringdem {
namespace {

using testing::self_comm;

// A bed z = 0, a post, five grains of radius 10 mm along the flow direction x from the
// barrier plane x = 0, and a ring standing across the flow at x = 0.4 (the net).
CaseConfig barrier_case() {
  CaseConfig c = testing::base_case();
  c.bonds[0].youngs_modulus = 200e9;
  c.bonds[0].radius_multiplier = 0.43;
  c.bonds[0].tensile_strength = c.bonds[0].compressive_strength = c.bonds[0].shear_strength = 1e9;
  RigidBodyConfig bed;
  bed.name = "bed";
  bed.shape = ShapeKind::kPlane;
  RigidBodyConfig post;
  post.name = "post";
  post.shape = ShapeKind::kCylinder;
  post.position = {0.45, 1.0, 0.5};
  post.radius = 0.05;
  post.length = 1.0;
  c.rigid_bodies = {bed, post};
  // (x, z, v_x, r): A and B in the gauge section s in [-1.5, -1], C upstream near the barrier,
  // D past it, E far upstream; E is the coarsest, B the coarsest in the gauge.
  const double grains[5][4] = {{-1.2, 0.3, 2.0, 0.01},
                               {-1.4, 0.1, 4.0, 0.02},
                               {-0.5, 0.2, 1.0, 0.01},
                               {0.3, 0.6, 5.0, 0.01},
                               {-3.0, 0.05, 0.5, 0.04}};
  for (const auto& g : grains) {
    SphereConfig s;
    s.group = "debris";
    s.radius = g[3];
    s.position = {g[0], 0.0, g[1]};
    s.velocity = {g[2], 0.0, 0.0};
    c.spheres.push_back(s);
  }
  RingConfig ring = testing::paper_ring({0.4, 0.0, 0.5}, {1, 0, 0});
  ring.group = "net";
  ring.reference = {0, 0, 1};
  c.rings = {ring};
  BarrierConfig b;
  b.direction = {1, 0, 0};
  b.position = {0, 0, 0};
  b.grain_groups = {"debris"};
  b.net_group = "net";
  b.posts = {"post"};
  b.bed = "bed";
  b.gauge_distance = 1.0;
  b.gauge_length = 0.5;
  b.retention_length = 2.0;
  b.width = 0.4;
  c.scenario.barrier = b;
  return c;
}

TEST(BarrierMonitor, FlowMeasuresAreTheHandSums) {
  const CaseConfig c = barrier_case();
  const Communicator comm = self_comm();
  SimulationSettings st = settings_from_case(c);
  st.dt = 1e-7;
  Simulation sim(build_model(c), comm, st);
  const BarrierMonitor monitor(*c.scenario.barrier, sim);
  const BarrierSample s = monitor.sample(sim);
  const ParticleStore& p = sim.model().particles;
  // The ring's 100 particles come first (gids 0-99), then the grains A-E (100-104).
  const auto mass = [&](std::int64_t gid) { return p.mass[p.index_of(gid)]; };
  const double ma = mass(100), mb = mass(101), mc = mass(102), md = mass(103);
  // Exact sums of up to three masses, and a ratio of two: 1e-15 relative.
  EXPECT_NEAR(s.gauge_mass, ma + mb, 1e-15 * (ma + mb));
  EXPECT_NEAR(s.flow_velocity, (2.0 * ma + 4.0 * mb) / (ma + mb), 1e-14);
  EXPECT_DOUBLE_EQ(s.flow_depth, 0.3 + 0.01);  // A's top above the bed
  EXPECT_EQ(s.largest_gauge_radius, 0.02);     // B's, not E's upstream of the gauge
  EXPECT_NEAR(s.flow_depth_centroid, 2.0 * (0.3 * ma + 0.1 * mb) / (ma + mb), 1e-14);
  EXPECT_NEAR(s.bulk_density, (ma + mb) / (0.5 * 0.4 * 0.31), 1e-12 * s.bulk_density);
  EXPECT_NEAR(s.retained_mass, ma + mb + mc, 1e-15 * (ma + mb + mc));  // s in [-2, 0]
  EXPECT_NEAR(s.overflow_mass, md, 1e-15 * md);
  EXPECT_DOUBLE_EQ(s.front, 0.3 + 0.01);  // D's leading edge
  // The ring stands in the plane x = 0.4: every particle at s = 0.4 (to rounding).
  EXPECT_NEAR(s.net_reach, 0.4, 1e-12);
  // No contact yet: no load on the post, none on a frame (none given).
  EXPECT_EQ(s.posts_force, 0.0);
  EXPECT_EQ(s.net_force, 0.0);
  // An undeformed ring: every utilisation is 0, so the lowest gid pair (0, 1) is reported, at
  // the midpoint of particles 0 and 1.
  EXPECT_EQ(s.max_utilisation, 0.0);
  const Vec3 mid = 0.5 * (p.position[p.index_of(0)] + p.position[p.index_of(1)]);
  EXPECT_LT(norm(s.utilisation_at - mid), 1e-15);
}

// The centroid depth of a uniform layer is its depth: a lattice of grains 4 deep resting on the
// bed in the gauge section (its centres at r, 3r, 5r, 7r: twice their mean is 8r, the layer's
// top). One grain saltating at five times that height sets the highest-top depth to its own
// top, and moves the centroid depth only by twice its mass share of its height above the mean.
TEST(BarrierMonitor, CentroidDepthIsTheLayerDepthAndBarelyFeelsASaltatingGrain) {
  CaseConfig c = barrier_case();
  const double r = 0.01, layer = 8 * r;
  LatticeConfig bed_layer;
  bed_layer.group = "debris";
  bed_layer.origin = {-1.45, -0.04, r};
  bed_layer.count = {20, 5, 4};
  bed_layer.spacing = 2 * r;
  bed_layer.particle_radius = r;
  c.lattices = {bed_layer};
  SphereConfig saltating;
  saltating.group = "debris";
  saltating.radius = r;
  saltating.position = {-1.25, 0.0, 5 * layer};
  c.spheres = {saltating};
  const Communicator comm = self_comm();
  SimulationSettings st = settings_from_case(c);
  st.dt = 1e-7;
  Simulation sim(build_model(c), comm, st);
  const BarrierSample s = BarrierMonitor(*c.scenario.barrier, sim).sample(sim);
  const double grains = 20 * 5 * 4 + 1;
  EXPECT_DOUBLE_EQ(s.flow_depth, 5 * layer + r);
  // Equal masses: twice the mean height is (400 layer + 2 (5 layer)) / 401 = layer + 2 (4.5 layer)
  // / 401, the layer's depth plus the saltating grain's share.
  const double expected = layer + 2.0 * (5 * layer - 0.5 * layer) / grains;
  EXPECT_NEAR(s.flow_depth_centroid, expected, 1e-12);
  EXPECT_LT(s.flow_depth_centroid - layer, 0.03 * layer);
}

// The mean forces over an interval (BarrierMonitor::impulse, from the momentum ledger) are the
// trapezoid rule of the loads each step reports: grains thrown along a bed at a post and at a
// fixed sphere (the net's frame), the post's contact force and the frame's load sampled after
// every step and integrated here, in plain doubles, against the ledger's exact sums.
TEST(BarrierMonitor, MeanForcesAreTheTrapezoidOfTheStepLoads) {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.materials.push_back(testing::soft_rock());
  c.rigid_bodies = testing::bed_and_post({0.05, 0.03, 0.1}, 0.02);
  SphereConfig frame;
  frame.group = "frame";
  frame.position = {0.05, -0.03, 0.011};
  frame.radius = 0.01;
  frame.material = "rock";
  frame.motion = Motion::kFixed;
  c.spheres.push_back(frame);
  LatticeConfig grains;
  grains.group = "debris";
  grains.origin = {-0.05, -0.04, 0.011};
  grains.count = {2, 4, 2};
  grains.spacing = 0.021;
  grains.particle_radius = 0.01;
  grains.material = "rock";
  grains.velocity = {2.0, 0.0, 0.0};
  c.lattices = {grains};
  BarrierConfig b;
  b.direction = {1, 0, 0};
  b.position = {0.05, 0, 0};
  b.grain_groups = {"debris"};
  b.frame_group = "frame";
  b.posts = {"post"};
  b.bed = "bed";
  c.scenario.barrier = b;
  const Communicator comm = self_comm();
  SimulationSettings st = settings_from_case(c);
  st.dt = 2e-5;
  Simulation sim(build_model(c), comm, st);
  const BarrierMonitor monitor(*c.scenario.barrier, sim);
  BarrierSample before = monitor.sample(sim);
  const BarrierMonitor::Impulse start = monitor.impulse(sim.momentum_balance());
  double net = 0.0, posts = 0.0;  // trapezoid of the sampled loads
  for (int n = 0; n < 3000; ++n) {
    sim.step();
    const BarrierSample now = monitor.sample(sim);
    net += 0.5 * sim.dt() * (before.net_force + now.net_force);
    posts += 0.5 * sim.dt() * (before.posts_force + now.posts_force);
    before = now;
  }
  const BarrierMonitor::Impulse end = monitor.impulse(sim.momentum_balance());
  // Both were struck, for about a third of the run each, pushed along the flow.
  EXPECT_GT(net, 1e-3);
  EXPECT_GT(posts, 1e-3);
  EXPECT_NEAR(end.net - start.net, net, 1e-12 * net);
  EXPECT_NEAR(end.posts - start.posts, posts, 1e-12 * posts);
}

// The largest utilisation is found wherever it is: bend one bond of the ring by turning one
// particle, and the reported bond is the one with the largest utilisation in the store.
TEST(BarrierMonitor, LargestUtilisationIsLocated) {
  CaseConfig c = barrier_case();
  const Communicator comm = self_comm();
  SimulationSettings st = settings_from_case(c);
  st.dt = 1e-7;
  Simulation sim(build_model(c), comm, st);
  ParticleStore& p = sim.model().particles;
  p.position[p.index_of(37)] += Vec3{0.002, 0.0, 0.0};  // out of the ring's plane
  sim.energies();                                       // refreshes the bonds' utilisation
  const BondStore& bonds = sim.model().bonds;
  std::size_t best = 0;
  for (std::size_t k = 1; k < bonds.size(); ++k)
    if (bonds.utilisation[k] > bonds.utilisation[best]) best = k;
  ASSERT_GT(bonds.utilisation[best], 0.0);
  const ParticleStore& q = sim.model().particles;
  const BarrierSample s = BarrierMonitor(*c.scenario.barrier, sim).sample(sim);
  EXPECT_EQ(s.max_utilisation, bonds.utilisation[best]);
  EXPECT_TRUE(bonds.gid_a[best] == 36 || bonds.gid_a[best] == 37) << bonds.gid_a[best];
  const Vec3 mid =
      0.5 * (q.position[q.index_of(bonds.gid_a[best])] + q.position[q.index_of(bonds.gid_b[best])]);
  EXPECT_LT(norm(s.utilisation_at - mid), 1e-15);
}

constexpr const char* kBarrierCase = R"(schema_version: 1
simulation: {end_time: 0.1}
materials: [{name: steel}]
rigid_bodies:
  - {name: bed, shape: plane}
  - {name: post, shape: cylinder, radius: 0.05, length: 1.0}
particles:
  spheres: [{group: debris, position: [0, 0, 0.1]}]
scenario:
  type: free_run
  barrier: {direction: [2, 0, 0], position: [0, 0, 0], bed: bed, posts: [post],
            grain_groups: [debris]}
)";

std::string error_at(const std::vector<std::string>& sets, const std::string& key) {
  try {
    load_case_from_string(kBarrierCase, "barrier.yaml", sets);
  } catch (const InputError& e) {
    for (const auto& d : e.diagnostics)
      if (d.key_path == key) return d.message;
    return "no error at " + key + ": " + e.format();
  }
  return "no error";
}

TEST(BarrierMonitor, LoaderChecksTheBarrierSection) {
  const CaseConfig c = load_case_from_string(kBarrierCase, "barrier.yaml");
  ASSERT_TRUE(c.scenario.barrier);
  EXPECT_EQ(c.scenario.barrier->direction, (Vec3{1, 0, 0}));  // normalised
  const std::string p = "scenario.barrier";
  EXPECT_NE(error_at({"scenario.barrier.bed=post"}, p + ".bed").find("must be a plane"),
            std::string::npos);
  EXPECT_NE(error_at({"scenario.barrier.bed=floor"}, p + ".bed").find("not defined"),
            std::string::npos);
  EXPECT_NE(error_at({"scenario.barrier.posts=[pole]"}, p + ".posts[0]").find("not defined"),
            std::string::npos);
  EXPECT_NE(error_at({"scenario.barrier.grain_groups=[mud]"}, p + ".grain_groups[0]")
                .find("not used by any particles"),
            std::string::npos);
  EXPECT_NE(error_at({"scenario.type=rockfall"}, p).find("free_run only"), std::string::npos);
}

}  // namespace
}  // namespace ringdem
