// Case-file loader, the checks that involve a model or a scenario: the rockfall's references,
// gravity and repeated impacts, the plastic bond's limits, the debris grains and inlets, and a
// barrier's names (each error checked against the line where the mistake is in the fixture text).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "CaseLoaderFixtures.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

using namespace case_fixture;

// The rockfall driver's group and material names and its gravity are input errors with a
// line, found before any particle is built (they used to surface as a runtime error, exit 1).
TEST(CaseLoader, RockfallReferencesAndGravityAreChecked) {
  std::string text = replaced(kValidCase, "gravity: [0, 0, -9.81]", "gravity: [0, -9.81, 0]");
  text +=
      "scenario:\n  type: rockfall\n  rockfall:\n    net_group: ring\n"
      "    boulder_material: rok\n";
  const auto diags = errors_of(text);
  EXPECT_EQ(diags.size(), 4u) << all(diags);
  const Diagnostic* d = find_path(diags, "scenario.rockfall.net_group");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "net_group: ring"));
  EXPECT_EQ(d->message,
            "particle group 'ring' is not used by any particles; did you mean 'rings'?");
  d = find_path(diags, "scenario.rockfall.frame_group");  // default 'shackles', not given
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "net_group: ring"));  // first line of the rockfall map
  EXPECT_NE(d->message.find("'shackles' (the default, key not given)"), std::string::npos);
  d = find_path(diags, "scenario.rockfall.boulder_material");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "boulder_material: rok"));
  EXPECT_EQ(d->message, "material 'rok' is not defined in 'materials'; did you mean 'rock'?");
  d = find_path(diags, "simulation.gravity");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "gravity: [0, -9.81, 0]"));
  EXPECT_NE(d->message.find("needs gravity along -z"), std::string::npos);

  // The same names, spelled right, load.
  std::string good = kValidCase;
  good +=
      "scenario:\n  type: rockfall\n  rockfall:\n    net_group: rings\n"
      "    frame_group: debris\n    boulder_material: rock\n";
  EXPECT_NO_THROW(load_case_from_string(good, "case.yaml", {}));
}

// A repeated rockfall (issue 14 point 4): at least one impact, a positive re-settle time,
// each error on its own line; impacts defaults to 1 (one impact, as before).
TEST(CaseLoader, RockfallImpactsAndResettleTimeAreChecked) {
  const std::string rockfall =
      kValidCase + std::string(
                       "scenario:\n  type: rockfall\n  rockfall:\n    net_group: rings\n"
                       "    frame_group: debris\n    boulder_material: rock\n");
  EXPECT_EQ(load_case_from_string(rockfall, "case.yaml", {}).scenario.rockfall.impacts, 1);
  const std::string text = rockfall + "    impacts: 0\n    resettle_max_time: 0\n";
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 2u) << all(diags);
  const Diagnostic* d = find_path(diags, "scenario.rockfall.impacts");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "impacts: 0"));
  EXPECT_EQ(d->message, "must be >= 1, got 0");
  d = find_path(diags, "scenario.rockfall.resettle_max_time");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "resettle_max_time: 0"));
  EXPECT_EQ(load_case_from_string(rockfall + "    impacts: 2\n", "case.yaml", {})
                .scenario.rockfall.impacts,
            2);
}

// bonds[].plastic (model timoshenko_plastic): required by the plastic model, refused by the
// elastic one, the wire bundle from the section or from derive_from but not from both; each
// error on the line of the key (or of the section, for a key that is missing).
TEST(CaseLoader, PlasticLimitsAreCheckedAgainstTheBondModel) {
  const std::string bond =
      "  - {name: ring, youngs_modulus: 120e9, radius_multiplier: 0.8, seed: 7}\n";
  const auto with_bond = [&](const std::string& lines) {
    return replaced(kValidCase, bond, lines);
  };

  // A complete plastic bond loads, and its dump loads again to the same case.
  const std::string good = with_bond(
      "  - name: ring\n"
      "    model: timoshenko_plastic\n"
      "    derive_from: {windings: 12, wire_diameter: 0.003}\n"
      "    plastic: {yield_stress: 1.5e9, hardening_ratio: 0.03, failure_strain: 0.04}\n");
  const CaseConfig c = load_case_from_string(good, "x.yaml");
  ASSERT_TRUE(c.bonds[0].plastic.has_value());
  EXPECT_EQ(c.bonds[0].plastic->yield_stress, 1.5e9);
  EXPECT_EQ(c.bonds[0].plastic->hardening_ratio, 0.03);
  EXPECT_EQ(c.bonds[0].plastic->failure_strain, 0.04);
  EXPECT_EQ(c.bonds[0].plastic->windings, 0);  // from derive_from
  EXPECT_FALSE(c.bonds[0].plastic->wire_diameter.has_value());
  EXPECT_EQ(dump_case(load_case_from_string(dump_case(c), "x.yaml")), dump_case(c));

  // Plastic limits on the elastic model.
  std::string text = with_bond(
      "  - name: ring\n"
      "    plastic: {yield_stress: 1.5e9, windings: 12, wire_diameter: 0.003}\n");
  expect_one_error(text, "bonds[0].plastic", "plastic: {",
                   "model 'timoshenko' is elastic and reads no plastic limits; use model "
                   "timoshenko_plastic or remove this section");

  // The plastic model without them: reported at its model key.
  text = with_bond("  - name: ring\n    model: timoshenko_plastic\n");
  auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "bonds[0].plastic");
  EXPECT_EQ(diags[0].line, line_of(text, "model: timoshenko_plastic"));
  EXPECT_NE(diags[0].message.find("needs the section bonds[0].plastic"), std::string::npos)
      << diags[0].message;

  // No derive_from and no wire diameter; windings given twice.
  text = with_bond(
      "  - name: ring\n"
      "    model: timoshenko_plastic\n"
      "    youngs_modulus: 120e9\n"
      "    plastic:\n"
      "      yield_stress: 1.5e9\n"
      "      windings: 12\n");
  // Reported at the section's first line.
  expect_one_error(text, "bonds[0].plastic.wire_diameter", "yield_stress: 1.5e9",
                   "missing key 'wire_diameter' (the bond has no derive_from to take it from)");
  text = with_bond(
      "  - name: ring\n"
      "    model: timoshenko_plastic\n"
      "    derive_from: {windings: 12, wire_diameter: 0.003}\n"
      "    plastic:\n"
      "      yield_stress: 1.5e9\n"
      "      windings: 19\n");
  expect_one_error(text, "bonds[0].plastic.windings", "windings: 19",
                   "bonds[0].derive_from gives windings: give it in one place only");
}

// Debris grains: the distribution's own keys, the size classes and the box, each error at the
// line of its mistake; a good entry loads with its values.
TEST(CaseLoader, GrainsEntriesAreCheckedWithTheirLines) {
  const auto with_grains = [](const std::string& entry) {
    return replaced(kValidCase, "  spheres:\n", "  grains:\n" + entry + "  spheres:\n");
  };
  std::string text = with_grains(
      "    - material: rock\n"
      "      box_min: [0, 0, 0]\n"
      "      box_max: [1, 1, 0.5]\n"
      "      sizes:\n"
      "        distribution: fractions\n"
      "        min_radius: 0.01\n"
      "        fractions: [{radius: 0.01, fraction: 0.5}, {radius: 0.02, fraction: 0.4}]\n");
  auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 2u) << all(diags);
  const Diagnostic* d = find_path(diags, "particles.grains[0].sizes.min_radius");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "min_radius: 0.01"));
  EXPECT_EQ(d->message, "does not apply to distribution 'fractions' (remove it)");
  d = find_path(diags, "particles.grains[0].sizes.fractions");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "fractions: [{"));
  EXPECT_EQ(d->message, "the fractions must sum to 1, got 0.9");

  text = with_grains(
      "    - material: rok\n"
      "      box_min: [0, 0, 0]\n"
      "      box_max: [1, 1, 0.5]\n"
      "      solid_fraction: 0.5\n"
      "      sizes: {distribution: log_normal, median_radius: 0.01, max_radius: 0.02}\n");
  diags = errors_of(text);
  ASSERT_EQ(diags.size(), 3u) << all(diags);
  d = find_path(diags, "particles.grains[0].solid_fraction");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "solid_fraction: 0.5"));
  d = find_path(diags, "particles.grains[0].material");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->message, "material 'rok' is not defined in 'materials'; did you mean 'rock'?");
  d = find_path(diags, "particles.grains[0].sizes.sigma");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "sizes: {"));
  EXPECT_EQ(d->message, "missing key 'sigma' (distribution 'log_normal' needs it)");

  text = with_grains(
      "    - material: rock\n"
      "      box_min: [0, 0, 0]\n"
      "      box_max: [1, 0.03, 0.5]\n"
      "      sizes: {min_radius: 0.005, max_radius: 0.02}\n");
  expect_one_error(text, "particles.grains[0].box_max", "box_max: [1, 0.03",
                   "the box is 0.03 m wide along y, less than the largest grain's diameter 0.04 m");

  text = with_grains(
      "    - material: rock\n"
      "      group: debris\n"
      "      box_min: [0, 0, 3]\n"
      "      box_max: [1, 0.5, 3.5]\n"
      "      solid_fraction: 0.25\n"
      "      sizes: {distribution: log_normal, median_radius: 0.01, sigma: 0.3, max_radius: 0.03}\n"
      "      seed: 4\n");
  const CaseConfig c = load_case_from_string(text, "case.yaml");
  ASSERT_EQ(c.grains.size(), 1u);
  EXPECT_EQ(c.grains[0].sizes.distribution, GrainDistribution::kLogNormal);
  EXPECT_EQ(c.grains[0].sizes.min_radius, 0.0025);  // the default
  EXPECT_EQ(c.grains[0].solid_fraction, 0.25);
  EXPECT_EQ(c.grains[0].seed, 4u);
}

// Inlets: the velocity the grains enter at, the solid fraction the discharge needs in the box,
// and the end after the start, each error at the line of its mistake; a good inlet loads with
// its values. (A zero velocity was accepted, and the run made an empty batch every step: it has
// no batch interval, hence no solid fraction and no grains, which read as a box reported
// already.)
TEST(CaseLoader, InflowEntriesAreCheckedWithTheirLines) {
  std::string text = case_fixture::case_with_inlet("[0, 0, 0]", "0.01", "");
  expect_one_error(text, "inflow[0].velocity", "velocity: [0, 0, 0]",
                   "must not be zero: the grains enter at this velocity");

  // A batch every 0.2 m / 2 m/s = 0.1 s of a 0.2 x 0.5 x 0.3 m box: 0.5 m^3/s fills 1.67 of it.
  text = case_fixture::case_with_inlet("[2, 0, 0]", "0.5", "");
  expect_one_error(
      text, "inflow[0].discharge", "discharge: 0.5",
      "needs a solid fraction of 1.67 in the inlet box, above the 0.35 that random "
      "sequential addition reaches: raise the velocity or widen the box across the flow");

  text = case_fixture::case_with_inlet("[2, 0, 0]", "0.01",
                                       "    start_time: 0.3\n    end_time: 0.2\n");
  expect_one_error(text, "inflow[0].end_time", "end_time: 0.2", "must be after start_time = 0.3");

  // The flow may run along any axis, either way: a batch comes each time the last has moved the
  // box's depth along it.
  text = case_fixture::case_with_inlet("[0, -2, 0]", "0.01", "    end_time: 0.4\n");
  const CaseConfig c = load_case_from_string(text, "case.yaml");
  ASSERT_EQ(c.inflow.size(), 1u);
  EXPECT_EQ(c.inflow[0].velocity.y, -2.0);
  EXPECT_EQ(c.inflow[0].discharge, 0.01);
  ASSERT_TRUE(c.inflow[0].end_time.has_value());
  EXPECT_EQ(*c.inflow[0].end_time, 0.4);
}

// A barrier's bodies and groups: each name defined, the bed a plane and no post, the net's groups
// not the flow's (its load and deflection would count the flow's), each error at the line of its
// mistake; a good barrier loads.
TEST(CaseLoader, BarrierBodiesAndGroupsAreCheckedWithTheirLines) {
  const auto with_barrier = [](const std::string& lines) {
    return std::string(kValidCase) +
           "scenario:\n"
           "  type: free_run\n"
           "  barrier:\n"
           "    direction: [1, 0, 0]\n"
           "    position: [0, 0, 0]\n" +
           lines;
  };
  std::string text = with_barrier(
      "    bed: floor\n"
      "    posts: [pin, floor, pole]\n"
      "    net_group: debris\n"
      "    grain_groups: [debris]\n");
  auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 3u) << all(diags);
  const int posts_line = line_of(text, "posts: [pin");
  const Diagnostic* d = find_path(diags, "scenario.barrier.posts[1]");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, posts_line);
  EXPECT_EQ(d->message,
            "rigid body 'floor' is the bed: the flow's friction on it would count as load on the "
            "barrier");
  d = find_path(diags, "scenario.barrier.posts[2]");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->message,
            "rigid body 'pole' is not defined in 'rigid_bodies' (defined: floor, pin, boulder)");
  d = find_path(diags, "scenario.barrier.net_group");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "net_group: debris"));
  EXPECT_EQ(d->message,
            "particle group 'debris' is one of grain_groups too: a group is the flow's or the "
            "barrier's, not both");

  text = with_barrier("    bed: pin\n");
  expect_one_error(text, "scenario.barrier.bed", "bed: pin",
                   "rigid body 'pin' must be a plane (the bed the flow runs on)");

  text = with_barrier(
      "    bed: floor\n"
      "    posts: [pin]\n"
      "    net_group: rings\n"
      "    grain_groups: [debris]\n");
  const CaseConfig c = load_case_from_string(text, "case.yaml");
  ASSERT_TRUE(c.scenario.barrier.has_value());
  EXPECT_EQ(c.scenario.barrier->posts, std::vector<std::string>{"pin"});
  EXPECT_EQ(c.scenario.barrier->net_group, "rings");
}

// An outflow box takes free particles in no ring: a group of ring particles only is refused at
// its entry (it would do nothing); a group of grains loads.
TEST(CaseLoader, OutflowGroupsMustHoldParticlesItCanTake) {
  const auto with_outflow = [](const std::string& groups) {
    return replaced(kValidCase, "rigid_bodies:\n",
                    "outflow:\n  - {name: out, box_min: [-5, -5, -5], box_max: [5, 5, 5], "
                    "groups: " +
                        groups + "}\nrigid_bodies:\n");
  };
  const std::string text = with_outflow("[debris, rings]");
  expect_one_error(text, "outflow[0].groups[1]", "groups: [debris, rings]",
                   "particle group 'rings' holds only ring particles, which an outflow box never "
                   "takes");
  const CaseConfig c = load_case_from_string(with_outflow("[debris]"), "case.yaml");
  ASSERT_EQ(c.outflow.size(), 1u);
  EXPECT_EQ(c.outflow[0].groups, std::vector<std::string>{"debris"});
}

}  // namespace
}  // namespace ringdem
