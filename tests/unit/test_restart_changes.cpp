// The pieces behind a trusted restart (issue 15, items 2 and 3): the canonical case text a
// checkpoint stores, the one table of what may change on a restart (and its copy in
// docs/output.md), the model fingerprint, the refusal of older checkpoint formats, and a time
// step changed mid-run (the energy ledger goes on without a jump, the step count to an end
// time is counted from the change).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include "CheckpointVersion.hpp"
#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/CaseText.hpp"
#include "io/Checkpoint.hpp"
#include "io/Hdf5File.hpp"
#include "io/InputError.hpp"
#include "io/RestartChanges.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

constexpr const char* kChangesCase = R"(schema_version: 1
simulation: {dt: 1.0e-6, end_time: 1.0}
materials: [{name: steel}]
bonds: [{name: ring, youngs_modulus: 210e9}]
particles:
  rings: [{centre: [0, 0, 0.2]}]
rigid_bodies: [{name: floor, shape: plane}]
)";

std::vector<CaseChange> changes_by(const std::vector<std::string>& overrides) {
  return case_changes(
      canonical_case_text(load_case_from_string(kChangesCase, "a.yaml")),
      canonical_case_text(load_case_from_string(kChangesCase, "a.yaml", overrides)));
}

TEST(CaseText, OneLinePerKeyWithNamedEntriesAndRoundTripNumbers) {
  const std::string text = canonical_case_text(load_case_from_string(kChangesCase, "a.yaml"));
  const auto keys = case_text_keys(text);
  const auto value_of = [&](const std::string& path) {
    for (const CaseKey& k : keys)
      if (k.path == path) return k.value;
    return std::string("(none)");
  };
  EXPECT_EQ(value_of("bonds[ring].youngs_modulus"), "2.1e11");
  EXPECT_EQ(value_of("particles.rings"), "1 entries");
  EXPECT_EQ(value_of("particles.rings[0].centre"), "[0, 0, 0.2]");
  EXPECT_EQ(value_of("rigid_bodies[floor].shape"), "plane");
  EXPECT_EQ(value_of("simulation.dt"), "1e-6");
  // 0.1 + 0.2 is one ulp above 0.3: the text tells them apart.
  const auto c = changes_by({"materials.0.friction=0.30000000000000004"});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].path, "materials[steel].friction");
  EXPECT_EQ(c[0].before, "1");
  EXPECT_EQ(c[0].after, "0.30000000000000004");
}

TEST(CaseText, AddedEntryIsACountAndItsKeys) {
  const auto c = changes_by({"particles.rings=[{centre: [0, 0, 0.2]}, {centre: [1, 0, 0.2]}]"});
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(describe_change(c[0]), "particles.rings: 1 entries -> 2 entries");
  for (std::size_t k = 1; k < c.size(); ++k) {
    EXPECT_EQ(c[k].path.rfind("particles.rings[1].", 0), 0u) << c[k].path;
    EXPECT_EQ(c[k].before, "");
    EXPECT_EQ(c[k].rule->kind, RestartKeyKind::kFixed);
  }
}

TEST(RestartRules, KindsOfTheDocumentedKeys) {
  const auto kind = [](const std::string& path) { return restart_rule_of(path).kind; };
  EXPECT_EQ(kind("simulation.end_time"), RestartKeyKind::kFree);
  EXPECT_EQ(kind("output.checkpoints_kept"), RestartKeyKind::kFree);
  EXPECT_EQ(kind("scenario.rockfall.duration"), RestartKeyKind::kFree);
  EXPECT_EQ(kind("simulation.dt"), RestartKeyKind::kApplied);
  EXPECT_EQ(restart_rule_of("simulation.dt").effect, RestartEffect::kTimeStep);
  EXPECT_EQ(restart_rule_of("damping.groups.net").effect, RestartEffect::kDamping);
  EXPECT_EQ(kind("materials[steel].friction"), RestartKeyKind::kApplied);
  EXPECT_EQ(kind("materials[steel].density"), RestartKeyKind::kFixed);
  EXPECT_EQ(kind("materials"), RestartKeyKind::kFixed);
  EXPECT_EQ(kind("bonds[ring].seed"), RestartKeyKind::kFixed);
  EXPECT_EQ(kind("rigid_bodies[pin].radius"), RestartKeyKind::kFixed);
  EXPECT_EQ(kind("simulation.gravity"), RestartKeyKind::kFixed);
  EXPECT_EQ(kind("a_key_of_a_later_version"), RestartKeyKind::kFixed);
}

TEST(RestartRules, FingerprintIgnoresOnlyKeysThatMayChange) {
  const auto fingerprint = [](const std::vector<std::string>& overrides) {
    return model_fingerprint(
        canonical_case_text(load_case_from_string(kChangesCase, "a.yaml", overrides)));
  };
  const std::string base = fingerprint({});
  EXPECT_EQ(base.size(), 16u);
  EXPECT_EQ(fingerprint({"simulation.end_time=2", "output.checkpoint_interval=0.1"}), base);
  EXPECT_NE(fingerprint({"simulation.dt=5e-7"}), base);
  EXPECT_NE(fingerprint({"bonds.0.youngs_modulus=292e9"}), base);
  // The identity a checkpoint is read against: only the keys that define the model.
  const auto identity = [](const std::vector<std::string>& overrides) {
    return model_identity(
        canonical_case_text(load_case_from_string(kChangesCase, "a.yaml", overrides)));
  };
  EXPECT_EQ(identity({"simulation.dt=5e-7", "simulation.end_time=2"}), identity({}));
  EXPECT_NE(identity({"bonds.0.youngs_modulus=292e9"}), identity({}));
}

TEST(RestartRules, DocsListTheTable) {
  const std::string path = std::string(RINGDEM_SOURCE_DIR) + "/docs/output.md";
  std::stringstream doc;
  doc << std::ifstream(path).rdbuf();
  const std::string table = describe_restart_rules();
  if (doc.str().find(table) == std::string::npos) {
    const auto out = fs::temp_directory_path() / "restart-rules.md";
    std::ofstream(out) << table;
    FAIL() << "docs/output.md is out of date with the table in src/io/RestartChanges.cpp; "
              "replace its table of restart keys with "
           << out;
  }
}

TEST(RestartRules, RefusalNamesEveryKeyAndAllowChangesLetsAppliedOnesPass) {
  const auto c = changes_by({"simulation.dt=5e-7", "simulation.end_time=2"});
  ASSERT_EQ(c.size(), 2u);
  try {
    check_restart_changes(c, false, "a.yaml", "cp.h5");
    ADD_FAILURE() << "a changed dt was accepted";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics.size(), 3u) << e.format();
    EXPECT_EQ(e.diagnostics[1].key_path, "simulation.dt");
    EXPECT_NE(e.diagnostics[1].message.find("1e-6 in the checkpoint, 5e-7 in the case"),
              std::string::npos);
  }
  EXPECT_NO_THROW(check_restart_changes(c, true, "a.yaml", "cp.h5"));
  EXPECT_THROW(check_restart_changes(changes_by({"bonds.0.seed=2"}), true, "a.yaml", "cp.h5"),
               InputError);
}

TEST(CheckpointFormat, OlderVersionIsRefusedWithTheReason) {
  const CaseConfig c = load_case_from_string(kChangesCase, "a.yaml");
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  std::string dir = (fs::temp_directory_path() / "ringdem_format_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  const std::string path =
      CheckpointStore(dir).write(self, sim.model(), sim.restart_state(), DriverState{}, 0, c);
  EXPECT_EQ(read_checkpoint_info(path).case_text, canonical_case_text(c));
  EXPECT_EQ(read_checkpoint_info(path).model_fingerprint,
            model_fingerprint(canonical_case_text(c)));
  testing::set_checkpoint_format_version(path, 2);
  try {
    read_checkpoint_info(path);
    ADD_FAILURE() << "a version 2 checkpoint was accepted";
  } catch (const Hdf5Error& e) {
    EXPECT_NE(
        std::string(e.what()).find("format version 2 is not one this ringdem reads (11 to 18): "
                                   "it was written by an older ringdem"),
        std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

// Format 17 carries the move bounds relative to a common translation and toward each body
// (engine/MoveBounds); a file of 16 has only the absolute one, which bounds both. Two clouds
// thrown at each other (+-4 m/s) and onto the floor (3 m/s): after 30 steps without a rebuild
// the relative bound (the box's half diagonal, 4 m/s) and the floor's (its normal speed,
// 3 m/s) are below the absolute one (the largest speed, 5 m/s); relabelled as 16, the file
// restarts with the absolute one for both, and the run goes on with the same positions as the
// one restarted from 17 (the forces do not depend on when lists are rebuilt).
TEST(CheckpointFormat, VersionSixteenRestartsWithItsMoveBoundForEveryBound) {
  const CaseConfig c = testing::colliding_clouds();
  const Communicator self = testing::self_comm();
  std::string dir = (fs::temp_directory_path() / "ringdem_bounds_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  std::string path;
  {
    Simulation sim(build_model(c, self), self, settings_from_case(c));
    const std::int64_t rebuilds = sim.rebuilds();
    sim.run_steps(30);
    ASSERT_EQ(sim.rebuilds(), rebuilds) << "the bounds must be those of 30 steps";
    path = CheckpointStore(dir).write(self, sim.model(), sim.restart_state(), DriverState{}, 0, c);
  }
  const auto read = [&] {
    Model model = build_model_without_particles(c);
    DriverState driver;
    RestartState state = read_checkpoint(self, path, c, model, driver);
    return std::make_pair(std::move(model), std::move(state));
  };
  auto [model17, state17] = read();
  const double absolute = state17.move_bound;
  EXPECT_NEAR(absolute, 30 * 1e-6 * 5.0, 30 * 1e-6 * 0.1);
  EXPECT_NEAR(state17.relative_move_bound, 30 * 1e-6 * 4.0, 30 * 1e-6 * 0.1);
  ASSERT_EQ(state17.surface_move_bound.size(), 1u);
  EXPECT_NEAR(state17.surface_move_bound[0], 30 * 1e-6 * 3.0, 30 * 1e-6 * 0.1);
  testing::set_checkpoint_format_version(path, 16);
  auto [model16, state16] = read();
  EXPECT_EQ(state16.move_bound, absolute);
  EXPECT_EQ(state16.relative_move_bound, absolute);
  EXPECT_EQ(state16.surface_move_bound, std::vector<double>{absolute});
  Simulation from17(std::move(model17), self, settings_from_case(c), state17);
  Simulation from16(std::move(model16), self, settings_from_case(c), state16);
  from17.run_steps(200);
  from16.run_steps(200);
  EXPECT_EQ(from16.model().particles.position, from17.model().particles.position);
  fs::remove_all(dir);
}

/// A paper ring dropped onto a plane with damping and friction: every ledger tally moves.
CaseConfig damped_ring_on_floor() {
  CaseConfig c = testing::base_case();
  c.simulation.dt = 1e-6;
  c.simulation.gravity = {0, 0, -9.81};
  c.damping.global = 0.3;
  c.materials[0].friction = 0.3;
  auto ring = testing::paper_ring({0, 0, 0.1545 + 0.0045 - 2e-4}, {0, 1, 0});
  ring.velocity = {0.2, 0, -1.0};
  c.rings.push_back(ring);
  RigidBodyConfig floor;
  floor.name = "floor";
  c.rigid_bodies.push_back(floor);
  return c;
}

TEST(TimeStepChange, LedgerTalliesGoOnAndStepsCountFromTheChange) {
  const CaseConfig c = damped_ring_on_floor();
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  sim.run_steps(8);  // mid-contact
  const Energies before = sim.energies();
  ASSERT_GT(before.contact_damping, 0.0);
  ASSERT_GT(before.global_damping, 0.0);
  ASSERT_NE(before.friction, 0.0);  // slip minus the change of the spring energy: either sign
  EXPECT_EQ(sim.steps_until(20e-6), 20);
  sim.change_time_step(0.25e-6);
  const Energies after = sim.energies();
  // The tallies up to now do not depend on the step that follows (a jump of dt/2 P otherwise).
  EXPECT_NEAR(after.contact_damping, before.contact_damping, 1e-12 * before.contact_damping);
  EXPECT_NEAR(after.global_damping, before.global_damping, 1e-12 * before.global_damping);
  EXPECT_NEAR(after.friction, before.friction, 1e-12 * std::abs(before.friction));
  // 8 steps of 1 us, then (20 - 8) / 0.25 = 48 steps to t = 20 us.
  EXPECT_EQ(sim.steps_until(20e-6), 8 + 48);
  sim.run_steps(48);
  EXPECT_NEAR(sim.time(), 20e-6, 1e-18);
  EXPECT_EQ(sim.restart_state().dt_origin_step, 8);
}

}  // namespace
}  // namespace ringdem
