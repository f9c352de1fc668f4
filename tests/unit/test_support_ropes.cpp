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
#include "CommandLine.hpp"
#include "FileText.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
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
    // T = EA / L0 (L - L0) = 500 N on the initial path, with k = EA / L0.
    SlidingRope::State state;
    std::vector<Vec3> loads(path.size());
    const SlidingRope::Params p{m.ropes.stiffness[r], m.ropes.rest_length[r],
                                m.ropes.activation_force[r], m.ropes.stroke[r]};
    EXPECT_NEAR(SlidingRope::compute(p, path, state, loads), 500.0, 1e-9 * 500.0);
    EXPECT_NEAR(p.stiffness * p.rest_length, 2e7, 1e-9 * 2e7);
  }
  for (std::size_t b = 0; b < m.bodies.size(); ++b)
    EXPECT_EQ(on_ropes[b], m.bodies[b].shape == RigidShape::kTorus ? 1 : 0) << m.bodies[b].name;
  EXPECT_GT(tori, 4u);
  // The ropes bound the time step: sqrt(M / 4k) of the lightest body on the stiffest rope.
  const Simulation sim(build_scenario_model(c, comm), comm, settings_from_case(c));
  double k = 0.0;
  for (std::size_t r = 0; r < m.ropes.size(); ++r)
    k = std::max(k, m.ropes.stiffness[r]);
  const double mass = m.bodies[static_cast<std::size_t>(m.ropes.nodes[0])].mass;
  EXPECT_NEAR(sim.limits().rope, std::sqrt(mass / (4.0 * k)), 1e-15);
  // Straight and pretensioned, each rope pulls its two anchors towards each other alike: the
  // frame's load sums to zero; each holds T^2 / 2k.
  const RestraintTotals totals = restraint_totals(m);
  EXPECT_NEAR(totals.largest_tension, 500.0, 1e-9 * 500.0);
  EXPECT_LT(norm(totals.frame_load), 1e-9 * 500.0);
  double energy = 0.0;
  for (std::size_t r = 0; r < m.ropes.size(); ++r)
    energy += 0.5 * 500.0 * 500.0 / m.ropes.stiffness[r];
  EXPECT_NEAR(totals.elastic_energy, energy, 1e-9 * energy);
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

}  // namespace
}  // namespace ringdem
