// A net's secondary mesh in a run (particles.nets[].mesh, engine/RingMeshTerm): the loader's
// checks, a coarse grain that falls through a bare ring held by the meshed one, with the energy
// ledger closing and the mesh's stability limit in the run's limits; a grain finer than the
// opening passes the meshed ring; a mesh changed at a restart applies from there on.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "CaseLoaderFixtures.hpp"
#include "TempDir.hpp"
#include "TestCases.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"
#include "io/RestartChanges.hpp"

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

Vec3 centroid_of_first_ring(const ParticleStore& p) {
  Vec3 sum;
  int n = 0;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.body[k] == 0) {
      sum += p.position[k];
      ++n;
    }
  return sum / n;
}

/// Two linked rings without shackles or gravity; the grain thrown at 0.5 m/s along -z from 60
/// mm above the centroid of the first ring, 0.25 s.
CaseConfig thrown_at_first_ring(const std::string& mesh, double radius) {
  CaseConfig c = load_case_from_string(meshed_net(mesh, radius), "x.yaml");
  c.spheres[0].position =
      centroid_of_first_ring(build_model(c, testing::self_comm()).particles) + Vec3{0, 0, 0.06};
  return c;
}

Throw throw_at_first_ring(const std::string& mesh, double radius) {
  const CaseConfig c = thrown_at_first_ring(mesh, radius);
  const Communicator comm = testing::self_comm();
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
/// The grain's position and velocity after a run of `first` steps of `written`, a checkpoint,
/// and `second` steps restarted with `read`.
std::pair<Vec3, Vec3> grain_after_restart(const CaseConfig& written, const CaseConfig& read,
                                          std::int64_t first, std::int64_t second,
                                          const std::string& dir) {
  const Communicator self = testing::self_comm();
  std::string path;
  {
    Simulation sim(build_model(written, self), self, settings_from_case(written));
    sim.run_steps(first);
    path = CheckpointStore(dir).write(self, sim.model(), sim.restart_state(), DriverState{}, 0,
                                      written);
  }
  Model model = build_model_without_particles(read);
  DriverState driver;
  const RestartState state = read_checkpoint(self, path, read, model, driver);
  Simulation resumed(std::move(model), self, settings_from_case(read), state);
  resumed.run_steps(second);
  const ParticleStore& p = resumed.model().particles;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.body[k] < 0) return {p.position[k], p.velocity[k]};
  ADD_FAILURE() << "no grain";
  return {};
}

// The mesh's stiffness, damping and opening may be changed at a restart (--allow-changes,
// docs/output.md). Checkpointed at 4 ms, before the grain meets the mesh (from 16 to 22 ms),
// and restarted with a stiffer and more damped mesh, the run ends at 0.1 s with the same bits
// as a run with that mesh from the start, and not as the restart with the mesh unchanged.
TEST(RingMeshTerm, AChangedMeshAppliesFromTheRestartOnAnUnchangedOneContinues) {
  for (const char* key : {"stiffness", "damping_ratio", "opening"}) {
    const RestartKeyRule& rule = restart_rule_of(std::string("particles.nets[0].mesh.") + key);
    EXPECT_EQ(rule.kind, RestartKeyKind::kApplied) << key;
  }
  EXPECT_EQ(restart_rule_of("particles.nets[0].mesh.stiffness").effect, RestartEffect::kTimeStep);
  EXPECT_EQ(restart_rule_of("particles.nets[0].rows").kind, RestartKeyKind::kFixed);
  const CaseConfig soft = thrown_at_first_ring(
      "shackles: {enabled: false}, mesh: {opening: 0.08, stiffness: 1.0e5}", 0.05);
  const CaseConfig stiff = thrown_at_first_ring(
      "shackles: {enabled: false}, mesh: {opening: 0.08, stiffness: 4.0e5, damping_ratio: 0.6}",
      0.05);
  constexpr std::int64_t kFirst = 2000, kSecond = 48000;  // dt = 2 us
  const std::string dir = testing::temp_dir("mesh-restart");
  const auto changed = grain_after_restart(soft, stiff, kFirst, kSecond, dir + "/changed");
  const auto unchanged = grain_after_restart(soft, soft, kFirst, kSecond, dir + "/unchanged");
  const Communicator self = testing::self_comm();
  Simulation fresh(build_model(stiff, self), self, settings_from_case(stiff));
  fresh.run_steps(kFirst + kSecond);
  const ParticleStore& p = fresh.model().particles;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.body[k] < 0) {
      EXPECT_EQ(changed.first, p.position[k]);
      EXPECT_EQ(changed.second, p.velocity[k]);
    }
  EXPECT_NE(changed.second, unchanged.second);  // the grain met the mesh after the restart
  // Unchanged, a restart in the middle of the grain's contact with the mesh (at 18 ms) ends as
  // the run never stopped: the mesh keeps no state a rebuild does not find again.
  const auto mid_contact = grain_after_restart(soft, soft, 9000, 41000, dir + "/mid");
  Simulation uninterrupted(build_model(soft, self), self, settings_from_case(soft));
  const auto grain_velocity = [](const Simulation& sim) {
    const ParticleStore& store = sim.model().particles;
    for (std::size_t k = 0; k < store.n_local(); ++k)
      if (store.body[k] < 0) return store.velocity[k];
    return Vec3{};
  };
  uninterrupted.run_steps(9000);
  const Vec3 at_checkpoint = grain_velocity(uninterrupted);
  uninterrupted.run_steps(1);
  ASSERT_NE(grain_velocity(uninterrupted), at_checkpoint) << "the mesh pushes it there";
  ASSERT_LT(at_checkpoint.z, 0.0) << "not yet pushed back";
  uninterrupted.run_steps(40999);
  const ParticleStore& q = uninterrupted.model().particles;
  for (std::size_t k = 0; k < q.n_local(); ++k)
    if (q.body[k] < 0) {
      EXPECT_EQ(mid_contact.first, q.position[k]);
      EXPECT_EQ(mid_contact.second, q.velocity[k]);
      EXPECT_EQ(unchanged.second, q.velocity[k]);
    }
  std::filesystem::remove_all(dir);
}

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
