// A net's secondary mesh in a run (particles.nets[].mesh, engine/RingMeshTerm): the loader's
// checks, a coarse grain that falls through a bare ring held by the meshed one, with the energy
// ledger closing and the mesh's stability limit in the run's limits; a grain finer than the
// opening passes the meshed ring.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "CaseLoaderFixtures.hpp"
#include "TestCases.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

using namespace case_fixture;

/// Two linked rings (a 2 x 2 lattice), with `net_keys` (shackles, mesh), and one rock grain of
/// `radius` moving at 0.5 m/s along -z, without gravity.
std::string meshed_net(const std::string& net_keys, double radius = 0.05) {
  return testing::net_free_run(
      "dt: 2.0e-6, end_time: 0.25, gravity: [0, 0, 0]", "rows: 2, columns: 2, " + net_keys,
      "  spheres:\n    - {group: grains, position: [0, 0, 1], velocity: [0, 0, -0.5], radius: " +
          std::to_string(radius) + ", material: rock}\n");
}

TEST(RingMeshTerm, TheLoaderAsksForTheOpeningAndTheStiffness) {
  auto diags = errors_of(meshed_net("mesh: {stiffness: 1.0e5}"));
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].mesh.opening");
  diags = errors_of(meshed_net("mesh: {opening: 0.08, stiffness: -1}"));
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].mesh.stiffness");
  const CaseConfig c =
      load_case_from_string(meshed_net("mesh: {opening: 0.08, stiffness: 1.0e5}"), "x.yaml");
  ASSERT_TRUE(c.nets[0].mesh.has_value());
  EXPECT_EQ(c.nets[0].mesh->damping_ratio, 0.3);  // the default (docs/case-file.md)
  // An opening as wide as the rings' holds nothing they do not: a warning, at the key.
  std::vector<Diagnostic> warnings;
  load_case_from_string(meshed_net("mesh: {opening: 0.08, stiffness: 1.0e5}"), "x.yaml", {},
                        &warnings);
  EXPECT_TRUE(warnings.empty());
  load_case_from_string(meshed_net("mesh: {opening: 0.3, stiffness: 1.0e5}"), "x.yaml", {},
                        &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].key_path, "particles.nets[0].mesh.opening");
  EXPECT_NE(warnings[0].message.find("hold anyway"), std::string::npos) << warnings[0].message;
}

struct Throw {
  double side = 0.0;        ///< the grain's height over the ring's centroid at the end [m]
  Vec3 momentum;            ///< of every particle at the end [N s]
  double ledger = 0.0;      ///< the energy balance's error at the end [J]
  double damping = 0.0;     ///< what contact damping dissipated [J]
  double mesh_limit = 0.0;  ///< the run's mesh stability limit [s]
};

/// Two linked rings without shackles or gravity; the grain thrown at 0.5 m/s along -z from 60
/// mm above the centroid of the first ring, 0.25 s.
Throw throw_at_first_ring(const std::string& mesh, double radius) {
  CaseConfig c = load_case_from_string(meshed_net(mesh, radius), "x.yaml");
  const Communicator comm = testing::self_comm();
  const auto centroid_of_first_ring = [](const ParticleStore& p) {
    Vec3 sum;
    int n = 0;
    for (std::size_t k = 0; k < p.n_local(); ++k)
      if (p.body[k] == 0) {
        sum += p.position[k];
        ++n;
      }
    return sum / n;
  };
  c.spheres[0].position = centroid_of_first_ring(build_model(c, comm).particles) + Vec3{0, 0, 0.06};
  Simulation sim(build_model(c, comm), comm, settings_from_case(c));
  const Energies initial = sim.energies();
  sim.run_steps(sim.steps_until(c.simulation.end_time));
  Throw t;
  const ParticleStore& p = sim.model().particles;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    t.momentum += p.velocity[k] * p.mass[k];
    if (p.body[k] < 0) t.side = p.position[k].z - centroid_of_first_ring(p).z;
  }
  const Energies end = sim.energies();
  t.ledger = end.balance_error(initial);
  t.damping = end.contact_damping;
  t.mesh_limit = sim.limits().mesh;
  return t;
}

// A 100 mm rock (1.36 kg, 0.17 J) passes a bare ring of 300 mm: in 0.25 s at 0.5 m/s it ends
// 0.065 m past the ring, which it never touches. The meshed ring (80 mm opening) stops it: the
// grain ends on its own side, the momentum it brought is shared with the rings to round-off
// (no external load acts), the dashpot dissipates, and the energy ledger closes to 1e-4 of the
// grain's kinetic energy (3e-6 J of 0.17 J when written).
TEST(RingMeshTerm, AMeshedRingStopsACoarseGrainThatPassesTheBareRing) {
  const Throw bare = throw_at_first_ring("shackles: {enabled: false}", 0.05);
  EXPECT_NEAR(bare.side, 0.06 - 0.125, 1e-9);
  EXPECT_TRUE(std::isinf(bare.mesh_limit));
  const Throw held = throw_at_first_ring(
      "shackles: {enabled: false}, mesh: {opening: 0.08, stiffness: 1.0e5}", 0.05);
  const double mass = 2600 * 4.0 / 3.0 * M_PI * 0.05 * 0.05 * 0.05;
  EXPECT_GT(held.side, 0.0);
  EXPECT_LT(norm(held.momentum - Vec3{0, 0, -0.5 * mass}), 1e-10 * 0.5 * mass);
  // The mesh's dashpot dissipates beyond the contacts between the rings (zeta = 0).
  const Throw undamped = throw_at_first_ring(
      "shackles: {enabled: false}, mesh: {opening: 0.08, stiffness: 1.0e5, damping_ratio: 0}",
      0.05);
  EXPECT_GT(held.damping, 2.0 * undamped.damping);
  EXPECT_LT(std::abs(held.ledger), 1e-4 * 0.5 * mass * 0.25) << held.ledger;
  // RingMesh::time_step_limit for the lightest grain held: rock, 80 mm, against a 0.647 kg ring
  const double lightest = 2600 * M_PI / 6 * 0.08 * 0.08 * 0.08;
  EXPECT_DOUBLE_EQ(held.mesh_limit, 1.0 / std::sqrt(4 * 1.0e5 * (1 / lightest + 3 / 0.647)));
}

// A grain finer than the opening (70 mm against 80) passes the meshed ring as the bare one.
TEST(RingMeshTerm, AGrainFinerThanTheOpeningPasses) {
  const Throw fine = throw_at_first_ring(
      "shackles: {enabled: false}, mesh: {opening: 0.08, stiffness: 1.0e5}", 0.035);
  EXPECT_NEAR(fine.side, 0.06 - 0.125, 1e-9);
}

// `ringdem check`'s plan takes the mesh's limit where it is the smallest: a stiff mesh with an
// automatic step sets dt to dt_safety times RingMesh::time_step_limit of the lightest grain held.
TEST(RingMeshTerm, TheTimeStepPlanTakesTheMeshLimitWhereItIsTheSmallest) {
  std::string text = meshed_net("mesh: {opening: 0.08, stiffness: 1.0e13}");
  text = replaced(text, "dt: 2.0e-6, ", "");
  const CaseConfig c = load_case_from_string(text, "x.yaml");
  const std::optional<TimeStepPlan> plan = plan_time_steps_with_restraints(c);
  ASSERT_TRUE(plan.has_value());
  const double lightest = 2600 * M_PI / 6 * 0.08 * 0.08 * 0.08;
  EXPECT_DOUBLE_EQ(plan->limit, RingMesh::time_step_limit(1.0e13, lightest, 0.647));
  EXPECT_NE(plan->limit_what.find("mesh"), std::string::npos) << plan->limit_what;
  EXPECT_DOUBLE_EQ(plan->dt, c.simulation.dt_safety * plan->limit);
}

}  // namespace
}  // namespace ringdem
