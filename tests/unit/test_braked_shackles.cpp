// Braked shackles (particles.nets[].shackles.brake, docs/physics.md "Brake elements"): the
// loader's checks, and the tori that stand for the shackle rings, against the rings of spheres
// the same net gets without brakes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "CaseLoaderFixtures.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

using namespace case_fixture;

const std::string kShackles = "shackles: {n_particles: 12}";

std::string braked(const std::string& brake) {
  return replaced(testing::kTinyRockfall, kShackles,
                  "shackles: {n_particles: 12, brake: " + brake + "}");
}

TEST(BrakedShackles, TheBrakeNeedsItsActivationForceAndPositiveValues) {
  auto diags = errors_of(braked("{stroke: 0.5}"));
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].shackles.brake.activation_force");
  diags = errors_of(braked("{activation_force: 2000, stiffness: -1}"));
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].shackles.brake.stiffness");
  const CaseConfig c = load_case_from_string(braked("{activation_force: 2000}"), "x.yaml");
  ASSERT_TRUE(c.nets[0].shackles.brake.has_value());
  EXPECT_EQ(c.nets[0].shackles.brake->stroke, 1.0);  // the defaults (docs/case-file.md)
  EXPECT_EQ(c.nets[0].shackles.brake->stiffness, 1.0e7);
}

// Each torus sits where a ring of shackle spheres sits without brakes: its centre at the ring's
// centroid, its axis normal to the ring's plane, its centreline through the sphere centres.
TEST(BrakedShackles, ToriStandOnTheShackleRingsOfSpheres) {
  const CaseConfig spheres_case = load_case_from_string(testing::kTinyRockfall, "x.yaml");
  const CaseConfig tori_case = load_case_from_string(braked("{activation_force: 2000}"), "x.yaml");
  const Communicator comm = testing::self_comm();
  const Model spheres = build_scenario_model(spheres_case, comm);
  const Model tori = build_scenario_model(tori_case, comm);
  const int group = spheres.group_id("shackles");
  std::vector<std::vector<Vec3>> rings;  // the shackle spheres, 12 a ring in gid order
  for (std::size_t k = 0; k < spheres.particles.n_local(); ++k) {
    if (spheres.particles.group[k] != group) continue;
    if (rings.empty() || rings.back().size() == 12) rings.emplace_back();
    rings.back().push_back(spheres.particles.position[k]);
  }
  ASSERT_FALSE(rings.empty());
  for (std::size_t k = 0; k < tori.particles.n_local(); ++k)
    EXPECT_NE(tori.particles.group[k], tori.group_id("shackles")) << "no shackle particles";
  ASSERT_EQ(tori.brakes.size(), rings.size());
  const double radius = spheres_case.nets[0].shackles.particle_radius;
  for (std::size_t s = 0; s < rings.size(); ++s) {
    const RigidBody& b = tori.bodies[static_cast<std::size_t>(tori.brakes.body[s])];
    EXPECT_EQ(b.shape, RigidShape::kTorus);
    EXPECT_EQ(b.motion, Motion::kFree);
    EXPECT_EQ(b.tube_radius, radius);
    EXPECT_EQ(tori.brakes.anchor[s], b.position);
    Vec3 centroid;
    for (const Vec3& x : rings[s])
      centroid += x / 12.0;
    EXPECT_LT(norm(b.position - centroid), 1e-12);
    const Vec3 axis = rotate(b.orientation, {0, 0, 1});
    for (const Vec3& x : rings[s]) {
      EXPECT_NEAR(norm(x - centroid), b.radius, 1e-12);    // on the centreline
      EXPECT_NEAR(dot(x - centroid, axis), 0.0, 1e-12);    // in the torus's plane
      EXPECT_NEAR(b.closest(x).distance, -radius, 1e-12);  // the sphere's centre: the tube's
    }
    // A steel tube of radius r on a circle of radius R (Pappus): 2 pi^2 R r^2 rho.
    EXPECT_NEAR(b.mass, 7800 * 2.0 * M_PI * M_PI * b.radius * radius * radius, 1e-12 * b.mass);
  }
  // The brake's spring bounds the time step: sqrt(M / k).
  const Simulation sim(build_scenario_model(tori_case, comm), comm, settings_from_case(tori_case));
  EXPECT_NEAR(sim.limits().brake, std::sqrt(tori.bodies[0].mass / 1.0e7), 1e-15);
}

}  // namespace
}  // namespace ringdem
