// Support ropes (particles.nets[].shackles.ropes, docs/physics.md "Support ropes"): the loader's
// checks, the ropes the builder threads through each side's shackles, against the layout of the
// same net (their order, anchors, pretension and the time-step limit they set), and the rope
// tension a rockfall reports, against the pretension and the brakes' activation force.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "CaseLoaderFixtures.hpp"
#include "CheckpointVersion.hpp"
#include "CommandLine.hpp"
#include "FileText.hpp"
#include "TestCases.hpp"
#include "app/ImpactRecord.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"
#include "physics/SlidingRope.hpp"

namespace ringdem {
namespace {

using namespace case_fixture;

const std::string kPlainShackles = "shackles: {n_particles: 12}";

std::string roped(const std::string& shackles) {
  return replaced(testing::kTinyRockfall, kPlainShackles,
                  "shackles: {n_particles: 12, " + shackles + "}");
}

TEST(SupportRopes, TheLoaderAsksForTheRigidityAndOneWayOfHoldingTheShackles) {
  auto diags = errors_of(roped("ropes: {pretension: 100}"));
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].shackles.ropes.axial_stiffness");
  diags = errors_of(roped("ropes: {axial_stiffness: 2e7, brake: {stroke: 0.5}}"));
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].shackles.ropes.brake.activation_force");
  diags = errors_of(roped("ropes: {axial_stiffness: 2e7}, brake: {activation_force: 2000}"));
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].shackles.ropes");
  EXPECT_NE(diags[0].message.find("not both"), std::string::npos) << diags[0].message;
  // (and the rockfall's frame group, the shackles, is then empty: a second error)
  diags = errors_of(roped("enabled: false, ropes: {axial_stiffness: 2e7}"));
  ASSERT_FALSE(diags.empty());
  EXPECT_EQ(diags[0].key_path, "particles.nets[0].shackles.enabled");
  const CaseConfig c = load_case_from_string(roped("ropes: {axial_stiffness: 2e7}"), "x.yaml");
  ASSERT_TRUE(c.nets[0].shackles.ropes.has_value());
  EXPECT_EQ(c.nets[0].shackles.ropes->anchor_offset, 0.2);  // the defaults (docs/case-file.md)
  EXPECT_EQ(c.nets[0].shackles.ropes->pretension, 0.0);
  EXPECT_FALSE(c.nets[0].shackles.ropes->brake.has_value());
}

// One rope per side, through every shackle of that side once, in order along the side (each
// segment turns less than 1 degree: the shackles of a side lie on a line), anchored
// anchor_offset beyond the outer ones, and tight at the pretension.
TEST(SupportRopes, EachSideHasOneTautRopeThroughItsShacklesInOrder) {
  const CaseConfig c = load_case_from_string(
      roped("ropes: {axial_stiffness: 2e7, anchor_offset: 0.15, pretension: 500}"), "x.yaml");
  const Communicator comm = testing::self_comm();
  const Model m = build_scenario_model(c, comm);
  ASSERT_EQ(m.ropes.size(), 4u);
  EXPECT_TRUE(m.brakes.empty());
  std::vector<int> on_ropes(m.bodies.size(), 0);
  std::size_t tori = 0;
  for (const RigidBody& b : m.bodies)
    tori += b.shape == RigidShape::kTorus ? 1 : 0;
  for (std::size_t r = 0; r < m.ropes.size(); ++r) {
    std::vector<Vec3> path{m.ropes.first_anchor[r]};
    for (const std::int32_t b : m.ropes.bodies_of(r)) {
      EXPECT_EQ(m.bodies[static_cast<std::size_t>(b)].shape, RigidShape::kTorus);
      EXPECT_EQ(m.bodies[static_cast<std::size_t>(b)].motion, Motion::kFree);
      ++on_ropes[static_cast<std::size_t>(b)];
      path.push_back(m.bodies[static_cast<std::size_t>(b)].position);
    }
    path.push_back(m.ropes.last_anchor[r]);
    ASSERT_GE(path.size(), 3u);
    EXPECT_NEAR(norm(path[1] - path[0]), 0.15, 1e-12);
    EXPECT_NEAR(norm(path[path.size() - 1] - path[path.size() - 2]), 0.15, 1e-12);
    for (std::size_t i = 1; i + 1 < path.size(); ++i)
      EXPECT_GT(dot(normalized(path[i] - path[i - 1]), normalized(path[i + 1] - path[i])),
                std::cos(M_PI / 180.0))
          << "rope " << r << " turns at point " << i;
    // T = EA (l_j - lambda_j) / lambda_j = 500 N in every segment of the initial path, and the
    // laid lengths add up to L0 = L EA / (EA + T).
    SlidingRope::State state;
    const std::size_t n = path.size() - 1;
    std::vector<double> rest(m.ropes.rest_of(r).begin(), m.ropes.rest_of(r).end()), length(n),
        tension(n), capstan(n + 1), start(n);
    std::vector<Vec3> loads(n + 1);
    ASSERT_EQ(rest.size(), n);
    const SlidingRope::Params p{m.ropes.axial_rigidity[r], m.ropes.friction[r],
                                m.ropes.activation_force[r], m.ropes.stroke[r]};
    EXPECT_EQ(p.axial_rigidity, 2e7);
    SlidingRope::compute(p, path, rest, state, {length, tension, capstan, start, loads});
    for (std::size_t j = 0; j < n; ++j) {
      EXPECT_NEAR(tension[j], 500.0, 1e-9 * 500.0) << "rope " << r << " segment " << j;
      EXPECT_EQ(m.ropes.segment_tension[m.ropes.segment_begin(r) + j], 500.0);
    }
    const double total = SlidingRope::length(path);
    EXPECT_NEAR(m.ropes.rest_length[r], total * 2e7 / (2e7 + 500.0), 1e-12 * total);
  }
  for (std::size_t b = 0; b < m.bodies.size(); ++b)
    EXPECT_EQ(on_ropes[b], m.bodies[b].shape == RigidShape::kTorus ? 1 : 0) << m.bodies[b].name;
  EXPECT_GT(tori, 4u);
  // The ropes bound the time step: sqrt(M / 4k) of the lightest body on the stiffest rope,
  // k = EA / L0.
  const Simulation sim(build_scenario_model(c, comm), comm, settings_from_case(c));
  double k = 0.0;
  for (std::size_t r = 0; r < m.ropes.size(); ++r)
    k = std::max(k, m.ropes.axial_rigidity[r] / m.ropes.rest_length[r]);
  const double mass = m.bodies[static_cast<std::size_t>(m.ropes.nodes[0])].mass;
  EXPECT_NEAR(sim.limits().rope, std::sqrt(mass / (4.0 * k)), 1e-15);
  // Straight and pretensioned, each rope pulls its two anchors towards each other alike: the
  // frame's load sums to zero; each holds T^2 / 2k.
  const RestraintTotals totals = restraint_totals(m);
  EXPECT_NEAR(totals.largest_tension, 500.0, 1e-9 * 500.0);
  EXPECT_LT(norm(totals.frame_load), 1e-9 * 500.0);
  double energy = 0.0;
  for (std::size_t r = 0; r < m.ropes.size(); ++r)
    energy += 0.5 * 500.0 * 500.0 * m.ropes.rest_length[r] / m.ropes.axial_rigidity[r];
  EXPECT_NEAR(totals.elastic_energy, energy, 1e-9 * energy);
}

// A checkpoint of format 12 held each rope's state as one tension; this one's ropes need their
// segments' lambda_j and tensions: such a file with ropes is refused with the reason (one
// without ropes still reads, the restart tests' 12-format cases).
TEST(SupportRopes, ACheckpointWrittenBeforeRopeSegmentsIsRefused) {
  const CaseConfig c = load_case_from_string(roped("ropes: {axial_stiffness: 2e7}"), "x.yaml");
  const Communicator comm = testing::self_comm();
  Simulation sim(build_scenario_model(c, comm), comm, settings_from_case(c));
  std::string dir = (std::filesystem::temp_directory_path() / "ringdem_ropes_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  const std::string path =
      CheckpointStore(dir).write(comm, sim.model(), sim.restart_state(), DriverState{}, 0, c);
  {
    Model model = build_model_without_particles(c);
    DriverState driver;
    EXPECT_NO_THROW(read_checkpoint(comm, path, c, model, driver));
  }
  testing::set_checkpoint_format_version(path, 12);
  Model model = build_model_without_particles(c);
  DriverState driver;
  try {
    read_checkpoint(comm, path, c, model, driver);
    ADD_FAILURE() << "a format 12 checkpoint with ropes was read";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("checkpoint format version 12 holds each support rope's "
                                         "state as one tension"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
}

/// The values of one column of a CSV file with a header line.
std::vector<double> csv_column_values(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  std::size_t index = 0;
  for (; std::getline(header, cell, ','); ++index)
    if (cell == name) break;
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    for (std::size_t c = 0; std::getline(row, cell, ','); ++c)
      if (c == index) values.push_back(std::stod(cell));
  }
  return values;
}

TEST(SupportRopes, ARockfallReportsTheRopeTensionFromPretensionToTheBrakesForce) {
  // The tiny net's shackles are held still until the release, so the ropes start the series
  // at their pretension (200 N); the net's weight and the 5 kg boulder then load them until
  // their brakes pay out rope at 205 N (without brakes the tension reaches 216 N), which caps the
  // tension.
  std::string dir = (std::filesystem::temp_directory_path() / "ringdem_ropes_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  std::ofstream(dir + "/tiny.yaml")
      << roped("ropes: {axial_stiffness: 2e6, pretension: 200, brake: {activation_force: 205}}");
  const testing::CommandResult r = testing::run_command(
      fmt::format("'{}' run '{}/tiny.yaml' -o '{}/out'", RINGDEM_BINARY, dir, dir));
  ASSERT_EQ(r.status, 0) << r.output;
  const std::vector<double> tension = csv_column_values(dir + "/out/series.csv", "rope_tension_N");
  ASSERT_GT(tension.size(), 2u);
  EXPECT_NEAR(tension.front(), 200.0, 1e-9 * 200.0);
  const nlohmann::json summary =
      nlohmann::json::parse(testing::file_text(dir + "/out/summary.json"));
  EXPECT_NEAR(summary["max_rope_tension_N"].get<double>(), 205.0, 1e-9 * 205.0);
  EXPECT_GT(summary["brake_largest_travel_m"].get<double>(), 0.0);
  EXPECT_LE(*std::max_element(tension.begin(), tension.end()), 205.0 * (1.0 + 1e-9));
  std::filesystem::remove_all(dir);
}

// An impact's record keeps the ropes' share of its friction through a checkpoint of the driver's
// state, and gives it in summary.json and the log beside the friction it is part of. (The tiny
// net's ropes do not slide in its rockfall: its shackles move alike on each side, and the ropes
// turn by less than a degree at them; the MPI restraint test and docs/rockfall.md's roped r12
// show friction that works.)
TEST(SupportRopes, AnImpactRecordGivesTheRopesFrictionApart) {
  ImpactRecord r;
  r.friction = 40.0;
  r.rope_friction = 10.0;
  DriverState state;
  r.save(state, 1);
  const ImpactRecord back = ImpactRecord::load(state, 1);
  EXPECT_EQ(back.rope_friction, 10.0);
  EXPECT_EQ(back.friction, 40.0);
  const nlohmann::json json = nlohmann::json::parse(back.json(1, 9.81, 100.0).str());
  EXPECT_EQ(json["rope_friction_share"].get<double>(), 0.1);
  EXPECT_EQ(json["friction_share"].get<double>(), 0.4);
  EXPECT_NE(back.log_line(1, 9.81, 100.0).find("friction 40 % (10 % on the ropes)"),
            std::string::npos)
      << back.log_line(1, 9.81, 100.0);
  r.rope_friction = 0.0;  // no ropes, or none slid: the log says nothing of them
  EXPECT_EQ(r.log_line(1, 9.81, 100.0).find("on the ropes"), std::string::npos);
}

}  // namespace
}  // namespace ringdem
