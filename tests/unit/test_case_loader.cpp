// Case-file loader: values and defaults, --set overrides, and the diagnostics for bad input
// (each checked against the line where the mistake is in the fixture text).

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "CaseLoaderFixtures.hpp"
#include "app/SweepCommand.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

using namespace case_fixture;

TEST(CaseLoader, ValidCaseLoadsValuesAndDefaults) {
  const CaseConfig c = load_case_from_string(kValidCase, "cases/ring_drop.yaml");
  EXPECT_EQ(c.schema_version, 1);
  EXPECT_EQ(c.name, "ring_drop");  // default: file stem
  EXPECT_EQ(c.description, "a ring, debris and a boulder");
  EXPECT_EQ(c.source_path, "cases/ring_drop.yaml");
  EXPECT_FALSE(c.simulation.dt.has_value());  // auto
  EXPECT_DOUBLE_EQ(c.simulation.dt_safety, 0.3);
  EXPECT_DOUBLE_EQ(c.simulation.end_time, 0.5);
  EXPECT_EQ(c.simulation.gravity, (Vec3{0, 0, -9.81}));
  EXPECT_DOUBLE_EQ(c.simulation.skin, 0.001);
  EXPECT_EQ(c.simulation.contact_model, "hertz_mindlin");

  ASSERT_EQ(c.materials.size(), 2u);
  EXPECT_EQ(c.materials[0].name, "steel");
  EXPECT_DOUBLE_EQ(c.materials[0].youngs_modulus, 200e9);
  EXPECT_DOUBLE_EQ(c.materials[0].restitution, 0.5);  // default
  EXPECT_EQ(c.materials[1].name, "rock");
  EXPECT_DOUBLE_EQ(c.materials[1].density, 2600);
  EXPECT_DOUBLE_EQ(c.materials[1].friction, 0.6);

  ASSERT_EQ(c.interactions.size(), 1u);
  EXPECT_EQ(c.interactions[0].material_a, "steel");
  EXPECT_EQ(c.interactions[0].material_b, "rock");
  EXPECT_EQ(c.interactions[0].friction, 0.5);
  EXPECT_FALSE(c.interactions[0].restitution.has_value());

  ASSERT_EQ(c.bonds.size(), 1u);
  EXPECT_EQ(c.bonds[0].model, "timoshenko");
  EXPECT_DOUBLE_EQ(c.bonds[0].tensile_strength, 16e9);
  EXPECT_EQ(c.bonds[0].seed, 7u);

  EXPECT_DOUBLE_EQ(c.damping.global, 0.05);
  ASSERT_EQ(c.damping.groups.size(), 1u);
  EXPECT_EQ(c.damping.groups[0].group, "rings");
  EXPECT_DOUBLE_EQ(c.damping.groups[0].coefficient, 0.3);

  ASSERT_EQ(c.rings.size(), 1u);
  const RingConfig& r = c.rings[0];
  EXPECT_EQ(r.centre, (Vec3{0, 0, 1}));
  EXPECT_EQ(r.normal, (Vec3{0, 1, 0}));  // normalised
  EXPECT_EQ(r.reference, (Vec3{1, 0, 0}));
  EXPECT_EQ(r.n_particles, 100);
  EXPECT_DOUBLE_EQ(r.contact_radius, 0.008);  // default
  EXPECT_EQ(r.motion, Motion::kFree);

  ASSERT_EQ(c.lattices.size(), 1u);
  EXPECT_EQ(c.lattices[0].group, "debris");
  EXPECT_EQ(c.lattices[0].count, (std::array<int, 3>{2, 3, 4}));
  EXPECT_DOUBLE_EQ(c.lattices[0].jitter, 0.0);

  ASSERT_EQ(c.spheres.size(), 1u);
  EXPECT_EQ(c.spheres[0].group, "spheres");
  EXPECT_EQ(c.spheres[0].motion, Motion::kFixed);

  ASSERT_EQ(c.rigid_bodies.size(), 3u);
  EXPECT_EQ(c.rigid_bodies[0].shape, ShapeKind::kPlane);
  EXPECT_EQ(c.rigid_bodies[0].normal, (Vec3{0, 0, 1}));
  EXPECT_EQ(c.rigid_bodies[0].motion, Motion::kFixed);
  EXPECT_EQ(c.rigid_bodies[1].shape, ShapeKind::kCylinder);
  EXPECT_EQ(c.rigid_bodies[1].axis, (Vec3{1, 0, 0}));
  EXPECT_EQ(c.rigid_bodies[1].motion, Motion::kPrescribed);
  EXPECT_EQ(c.rigid_bodies[1].velocity, (Vec3{0, 0, 0.005}));
  EXPECT_EQ(c.rigid_bodies[1].material, "steel");
  EXPECT_EQ(c.rigid_bodies[2].shape, ShapeKind::kSphere);
  EXPECT_EQ(c.rigid_bodies[2].mass, 825.0);
  EXPECT_TRUE(c.rigid_bodies[2].gravity);
}

TEST(CaseLoader, ContactRadiusDefaultIsAtLeastParticleRadius) {
  const CaseConfig c = load_case_from_string(
      replaced(kValidCase, "particle_radius: 0.0045", "particle_radius: 0.01"), "x.yaml");
  EXPECT_DOUBLE_EQ(c.rings[0].contact_radius, 0.01);
}

TEST(CaseLoader, ShippedInputsLoad) {
  const std::filesystem::path inputs = std::filesystem::path(RINGDEM_SOURCE_DIR) / "inputs";
  if (!std::filesystem::exists(inputs)) GTEST_SKIP() << "no inputs/ directory";
  int loaded = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(inputs)) {
    const auto path = entry.path();
    if (path.extension() != ".yaml" || path.parent_path().filename() == "sweeps") continue;
    EXPECT_NO_THROW({
      try {
        load_case(path.string());
      } catch (const InputError& e) {
        ADD_FAILURE() << e.format();
      }
    }) << path;
    ++loaded;
  }
  EXPECT_GT(loaded, 0);
}

TEST(CaseLoader, DebrisDemoIsTheFineChannelWithItsOwnSteps) {
  // inputs/debris/demo.yaml repeats fine.yaml's channel, net, mesh, posts, grains and inlet
  // (case files have no include). With fine.yaml's step, sub-steps, end and frame interval set
  // on it (and both named alike), it must resolve to the same configuration: a change to the
  // set-up of one that misses the other fails here (docs/debris.md, "The demo").
  const std::string dir = std::string(RINGDEM_SOURCE_DIR) + "/inputs/debris/";
  const std::vector<std::string> same_name = {"name=debris_channel", "description=channel"};
  std::vector<std::string> as_fine = same_name;
  for (const char* set : {"simulation.dt=7.87e-7", "simulation.substeps=24",
                          "simulation.end_time=0.8", "output.frame_interval=0.1"})
    as_fine.emplace_back(set);
  const std::string fine = dump_case(load_case(dir + "fine.yaml", same_name));
  EXPECT_EQ(dump_case(load_case(dir + "demo.yaml", as_fine)), fine);
  // The demo's own steps are what differs.
  const CaseConfig demo = load_case(dir + "demo.yaml", same_name);
  EXPECT_NE(dump_case(demo), fine);
  EXPECT_FALSE(demo.simulation.dt.has_value());  // auto: the stability rule
  EXPECT_EQ(demo.simulation.substeps, 16);
}

TEST(CaseLoader, ShippedSweepsLoadWithEveryCase) {
  // Every sweep in inputs/sweeps/ loads, and each of its cases is a valid case with the sweep's
  // overrides: what `ringdem sweep` checks before it runs any.
  const std::filesystem::path sweeps =
      std::filesystem::path(RINGDEM_SOURCE_DIR) / "inputs" / "sweeps";
  if (!std::filesystem::exists(sweeps)) GTEST_SKIP() << "no inputs/sweeps/ directory";
  int cases = 0;
  for (const auto& entry : std::filesystem::directory_iterator(sweeps)) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    try {
      const SweepConfig sweep = load_sweep(entry.path().string());
      for (const SweepCase& c : expand_sweep(sweep)) {
        load_case(sweep.case_path, c.overrides);
        ++cases;
      }
    } catch (const InputError& e) {
      ADD_FAILURE() << e.format();
    }
  }
  EXPECT_GT(cases, 0);
}

TEST(CaseLoader, OverridesScalarListIndexVectorAndMaps) {
  const CaseConfig c = load_case_from_string(
      kValidCase, "x.yaml",
      {"simulation.dt=1e-6", "rigid_bodies.1.radius=0.02", "rigid_bodies[2].velocity=[0, 0, -5]",
       "simulation.gravity=[0,0,-1.62]", "damping.groups.debris=0.5", "name=moon_drop",
       "particles.rings.0.motion=fixed"});
  EXPECT_EQ(c.simulation.dt, 1e-6);
  EXPECT_DOUBLE_EQ(c.rigid_bodies[1].radius, 0.02);
  EXPECT_EQ(c.rigid_bodies[2].velocity, (Vec3{0, 0, -5}));
  EXPECT_EQ(c.simulation.gravity, (Vec3{0, 0, -1.62}));
  ASSERT_EQ(c.damping.groups.size(), 2u);
  EXPECT_EQ(c.damping.groups[1].group, "debris");
  EXPECT_EQ(c.name, "moon_drop");
  EXPECT_EQ(c.rings[0].motion, Motion::kFixed);
}

TEST(CaseLoader, OverrideCreatesMissingSectionAndKey) {
  std::string text = kValidCase;
  text = replaced(text, "damping:\n  global: 0.05\n  groups: {rings: 0.3}\n", "");
  const CaseConfig c = load_case_from_string(text, "x.yaml", {"damping.global=0.1"});
  EXPECT_DOUBLE_EQ(c.damping.global, 0.1);
}

TEST(CaseLoader, OverrideErrorsNameTheOverride) {
  const auto diags = errors_of(kValidCase, {"simulation.dt=1e-6", "simulation.dt_safty=0.2",
                                            "rigid_bodies.7.radius=1", "simulation.skin=-1"});
  ASSERT_EQ(diags.size(), 3u) << all(diags);
  EXPECT_EQ(diags[0].file, "--set");
  EXPECT_EQ(diags[0].line, 2);  // second --set
  EXPECT_EQ(diags[0].key_path, "simulation.dt_safty");
  EXPECT_NE(diags[0].message.find("did you mean 'dt_safety'"), std::string::npos);
  EXPECT_EQ(diags[1].line, 3);
  EXPECT_NE(diags[1].message.find("has 3 entries"), std::string::npos) << diags[1].message;
  EXPECT_EQ(diags[2].line, 4);
  EXPECT_EQ(diags[2].column, 17);  // the value in "simulation.skin=-1"
  EXPECT_EQ(diags[2].key_path, "simulation.skin");
  EXPECT_NE(diags[2].message.find("must be > 0 m, got -1"), std::string::npos);
}

TEST(CaseLoader, MalformedYamlReportsParserLine) {
  const std::string text = replaced(kValidCase, "gravity: [0, 0, -9.81]", "gravity: [0, 0, -9.81");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].file, "case.yaml");
  // The parser notices the unclosed list at the next line.
  EXPECT_EQ(diags[0].line, line_of(text, "gravity:") + 1);
  EXPECT_EQ(diags[0].line, 7);
  EXPECT_NE(diags[0].message.find("invalid YAML"), std::string::npos);
}

TEST(CaseLoader, UnknownKeySuggestsClosestKey) {
  const std::string text =
      replaced(kValidCase, "      particle_radius: 0.0045", "      partcle_radius: 0.0045");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].line, line_of(text, "partcle_radius"));
  EXPECT_EQ(diags[0].line, 28);
  EXPECT_EQ(diags[0].column, 7);
  EXPECT_EQ(diags[0].key_path, "particles.rings[0].partcle_radius");
  EXPECT_NE(diags[0].message.find("unknown key 'partcle_radius'; did you mean 'particle_radius'?"),
            std::string::npos)
      << diags[0].message;
  EXPECT_EQ(InputError(diags).format(),
            "case.yaml:28:7: error: particles.rings[0].partcle_radius: unknown key "
            "'partcle_radius'; did you mean 'particle_radius'?\n");
}

TEST(CaseLoader, UnknownKeyWithoutCloseMatchListsValidKeys) {
  const std::string text = replaced(kValidCase, "  dt: auto", "  dt: auto\n  banana: 3");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].line, line_of(text, "banana"));
  EXPECT_NE(diags[0].message.find("valid keys: dt, dt_safety"), std::string::npos);
}

TEST(CaseLoader, NegativeRadiusReportsValueAndRange) {
  const std::string text = replaced(kValidCase, "radius: 0.01, material: rock, motion: fixed",
                                    "radius: -0.002, material: rock, motion: fixed");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].line, line_of(text, "radius: -0.002"));
  EXPECT_EQ(diags[0].key_path, "particles.spheres[0].radius");
  EXPECT_EQ(diags[0].message, "must be > 0 m, got -0.002");
}

TEST(CaseLoader, MissingSectionIsNamed) {
  std::string text = kValidCase;
  const std::size_t begin = text.find("materials:\n");
  const std::size_t end = text.find("interactions:");
  text.erase(begin, end - begin);
  const auto diags = errors_of(text);
  const Diagnostic* d = find_path(diags, "materials");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, 1);  // the document (parent of the missing section)
  EXPECT_NE(d->message.find("missing required section 'materials'"), std::string::npos);
  // References to the missing materials are not reported on top of it.
  EXPECT_EQ(diags.size(), 1u) << all(diags);
}

TEST(CaseLoader, MissingRequiredKeyUsesParentLine) {
  const std::string text = replaced(kValidCase, "  end_time: 0.5\n", "");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "simulation.end_time");
  EXPECT_EQ(diags[0].line, line_of(text, "  dt: auto"));  // first line of the simulation map
}

TEST(CaseLoader, WrongTypesNameTheExpectedType) {
  std::string text = replaced(kValidCase, "density: 2600", "density: heavy");
  text = replaced(text, "interactions:\n  - {materials: [steel, rock], friction: 0.5}",
                  "interactions: {materials: [steel, rock]}");
  text = replaced(text, "centre: [0, 0, 1]", "centre: [0, 1]");
  text = replaced(text, "n_particles: 100", "n_particles: 10.5");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 4u) << all(diags);
  const Diagnostic* d = find_path(diags, "materials[1].density");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->line, line_of(text, "heavy"));
  EXPECT_EQ(d->message, "expected a number, got 'heavy'");
  d = find_path(diags, "interactions");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->line, line_of(text, "interactions:"));
  EXPECT_NE(d->message.find("expected a list of maps"), std::string::npos);
  EXPECT_NE(d->message.find("got a map"), std::string::npos);
  d = find_path(diags, "particles.rings[0].centre");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->line, line_of(text, "centre: [0, 1]"));
  EXPECT_NE(d->message.find("expected a 3-vector [x, y, z] m, got a list of 2 entries"),
            std::string::npos)
      << d->message;
  d = find_path(diags, "particles.rings[0].n_particles");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->message, "expected an integer, got '10.5'");
}

TEST(CaseLoader, SeveralErrorsReportedAtOnceInFileOrder) {
  std::string text = replaced(kValidCase, "schema_version: 1", "schema_version: 2");
  text = replaced(text, "dt: auto", "dt: -1");
  text = replaced(text, "poisson_ratio: 0.3}", "poisson_ratio: 0.5}");
  text = replaced(text, "global: 0.05", "global: 1.0");
  text = replaced(text, "motion: prescribed", "motion: prescribd");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 5u) << all(diags);
  EXPECT_EQ(diags[0].line, 1);
  EXPECT_EQ(diags[0].message, "must be 1, got 2");
  EXPECT_EQ(diags[1].line, line_of(text, "dt: -1"));
  EXPECT_EQ(diags[1].message, "must be > 0 s, got -1");
  EXPECT_EQ(diags[2].line, line_of(text, "poisson_ratio: 0.5"));
  EXPECT_EQ(diags[2].message, "must be in (-1, 0.5), got 0.5");
  EXPECT_EQ(diags[3].line, line_of(text, "global: 1.0"));
  EXPECT_EQ(diags[3].message, "must be in [0, 1), got 1.0");
  EXPECT_EQ(diags[4].line, line_of(text, "prescribd"));
  EXPECT_EQ(diags[4].message,
            "'prescribd' is not one of: free, fixed, prescribed; did you mean 'prescribed'?");
}

TEST(CaseLoader, UnknownMaterialReference) {
  const std::string text = replaced(kValidCase, "position: [1, 1, 1], radius: 0.01, material: rock",
                                    "position: [1, 1, 1], radius: 0.01, material: rok");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].line, line_of(text, "material: rok"));
  EXPECT_EQ(diags[0].key_path, "particles.spheres[0].material");
  EXPECT_EQ(diags[0].message, "material 'rok' is not defined in 'materials'; did you mean 'rock'?");
}

TEST(CaseLoader, CrossChecks) {
  std::string text = replaced(kValidCase, "bond: ring", "bond: chain");        // unknown bond
  text = replaced(text, "spacing: 0.02", "spacing: 0.008");                    // < 2 * radius
  text = replaced(text, "groups: {rings: 0.3}", "groups: {ring: 0.3}");        // unknown group
  text = replaced(text, "interactions:", "  - {name: steel}\ninteractions:");  // duplicate
  text = replaced(text, "material: steel}\n", "material: steel, motion: free, radius: 1}\n");
  text = replaced(text, "    length: 0.1\n", "");  // cylinder without length
  const auto diags = errors_of(text);
  EXPECT_EQ(diags.size(), 7u) << all(diags);
  const Diagnostic* d = find_path(diags, "materials[2].name");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "  - {name: steel}"));
  d = find_path(diags, "particles.rings[0].bond");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "bond: chain"));
  EXPECT_EQ(d->message, "bond 'chain' is not defined in 'bonds' (defined: ring)");
  d = find_path(diags, "particles.lattices[0].spacing");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_NE(d->message.find("must be >= 2 * particle_radius = 0.01 m"), std::string::npos);
  d = find_path(diags, "damping.groups.ring");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_NE(d->message.find("did you mean 'rings'?"), std::string::npos);
  d = find_path(diags, "rigid_bodies[0].motion");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_NE(d->message.find("not allowed for a plane"), std::string::npos);
  d = find_path(diags, "rigid_bodies[0].radius");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_NE(d->message.find("does not apply to shape 'plane'"), std::string::npos);
  d = find_path(diags, "rigid_bodies[1].length");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_EQ(d->line, line_of(text, "  - name: pin"));
}

// A free run may go without the energy ledger; the tests that report its shares may not.
TEST(CaseLoader, EnergyLedgerOffIsForFreeRunsOnly) {
  EXPECT_TRUE(load_case_from_string(kValidCase, "x.yaml").simulation.energy_ledger);
  const CaseConfig c =
      load_case_from_string(kValidCase, "x.yaml", {"simulation.energy_ledger=false"});
  EXPECT_FALSE(c.simulation.energy_ledger);
  const auto diags =
      errors_of(kValidCase, {"simulation.energy_ledger=false", "scenario.type=tensile_test"});
  const Diagnostic* d = find_path(diags, "simulation.energy_ledger");
  ASSERT_NE(d, nullptr) << all(diags);
  EXPECT_NE(d->message.find("free_run only; a tensile_test reports the energy ledger"),
            std::string::npos)
      << d->message;
}

TEST(CaseLoader, DuplicateKeyAndNonVectorNormal) {
  std::string text = replaced(kValidCase, "  end_time: 0.5\n", "  end_time: 0.5\n  end_time: 1\n");
  text = replaced(text, "normal: [0, 2, 0]", "normal: [0, 0, 0]");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 2u) << all(diags);
  EXPECT_EQ(diags[0].line, line_of(text, "end_time: 1"));
  EXPECT_EQ(diags[0].message, "duplicate key 'end_time'");
  EXPECT_EQ(diags[1].key_path, "particles.rings[0].normal");
  EXPECT_EQ(diags[1].message, "must be a non-zero vector, got [0, 0, 0]");
}

TEST(CaseLoader, EmptyFileReportsEveryRequiredSection) {
  const auto diags = errors_of("");
  ASSERT_EQ(diags.size(), 4u) << all(diags);
  for (const char* key : {"schema_version", "simulation", "materials", "particles"})
    EXPECT_NE(find_path(diags, key), nullptr) << key;
}

TEST(CaseLoader, NoParticlesIsAnError) {
  std::string text = kValidCase;
  const std::size_t begin = text.find("particles:\n");
  const std::size_t end = text.find("rigid_bodies:");
  text.replace(begin, end - begin, "particles: {rings: []}\n");
  text = replaced(text, "groups: {rings: 0.3}", "groups: {}");
  const auto diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << all(diags);
  EXPECT_EQ(diags[0].key_path, "particles");
  EXPECT_EQ(diags[0].line, line_of(text, "particles:"));
}

TEST(CaseLoader, MissingFileIsAnInputError) {
  try {
    load_case("/nonexistent/case.yaml");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics.size(), 1u);
    EXPECT_EQ(e.format(), "/nonexistent/case.yaml: error: case file not found\n");
  }
}

TEST(CaseLoader, FixtureFileReportsItsPath) {
  const std::string path =
      std::string(RINGDEM_SOURCE_DIR) + "/tests/data/bad_cases/negative_radius.yaml";
  try {
    load_case(path);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics.size(), 1u) << e.format();
    EXPECT_EQ(e.diagnostics[0].file, path);
    EXPECT_EQ(e.diagnostics[0].line, 19);
    EXPECT_EQ(e.diagnostics[0].key_path, "particles.rings[0].particle_radius");
  }
}

TEST(CaseLoader, DumpRoundTrips) {
  const CaseConfig c = load_case_from_string(kValidCase, "x.yaml", {"simulation.dt=2e-7"});
  const std::string dumped = dump_case(c);
  EXPECT_NE(dumped.find("dt: 2e-7"), std::string::npos) << dumped;
  EXPECT_NE(dumped.find("contact_radius: 0.008"), std::string::npos) << dumped;
  const CaseConfig again = load_case_from_string(dumped, "x.yaml");
  EXPECT_EQ(dump_case(again), dumped);
  EXPECT_EQ(again.rigid_bodies[2].mass, 825.0);
  EXPECT_EQ(again.rings[0].normal, c.rings[0].normal);
}

TEST(CaseLoader, DocsMatchTheSchema) {
  const std::string path = std::string(RINGDEM_SOURCE_DIR) + "/docs/case-file.md";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string reference = describe_case_schema();
  if (doc.str().find(reference) == std::string::npos) {
    const auto out = std::filesystem::temp_directory_path() / "case-file-reference.md";
    std::ofstream(out) << reference;
    FAIL() << "docs/case-file.md is out of date with the schema in src/io/CaseSchema.cpp; "
              "replace its reference section with "
           << out;
  }
}

TEST(CaseLoader, CliCheckExitsWithCode2AndPrintsLocation) {
  const std::string binary = RINGDEM_BINARY;
  ASSERT_TRUE(std::filesystem::exists(binary)) << binary;
  const std::string bad =
      std::string(RINGDEM_SOURCE_DIR) + "/tests/data/bad_cases/negative_radius.yaml";
  const auto err = std::filesystem::temp_directory_path() /
                   ("ringdem_check_" + std::to_string(::getpid()) + ".txt");
  const std::string command = "'" + binary + "' check '" + bad + "' 2> '" + err.string() + "'";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream in(err);
  std::stringstream stderr_text;
  stderr_text << in.rdbuf();
  std::filesystem::remove(err);
  EXPECT_NE(stderr_text.str().find(bad + ":19:"), std::string::npos) << stderr_text.str();
}

TEST(CaseLoader, BadCasesAreRefusedWhereTheirHeadersSay) {
  // Every file in tests/data/bad_cases states in "# expect: LINE:COL KEY: TEXT" lines the
  // diagnostics it must give, all of them: the loader must report exactly those (TEXT a part of
  // the message), and `ringdem check` must exit with code 2 and print them with file:line:col.
  const std::regex expect_line(R"(^# expect: (\d+):(\d+) (\S+): (.*)$)");
  const fs::path dir = fs::path(RINGDEM_SOURCE_DIR) / "tests/data/bad_cases";
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 13u);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    struct Expected {
      int line, column;
      std::string key, text;
    };
    std::vector<Expected> expected;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
      std::smatch m;
      if (std::regex_match(line, m, expect_line))
        expected.push_back({std::stoi(m[1]), std::stoi(m[2]), m[3], m[4]});
    }
    ASSERT_FALSE(expected.empty()) << "no '# expect:' line";
    try {
      load_case(file.string());
      ADD_FAILURE() << "accepted";
      continue;
    } catch (const InputError& e) {
      ASSERT_EQ(e.diagnostics.size(), expected.size()) << e.format();
      for (std::size_t k = 0; k < expected.size(); ++k) {
        const Diagnostic& d = e.diagnostics[k];
        EXPECT_EQ(d.file, file.string());
        EXPECT_EQ(d.line, expected[k].line) << e.format();
        EXPECT_EQ(d.column, expected[k].column) << e.format();
        EXPECT_EQ(d.key_path, expected[k].key) << e.format();
        EXPECT_NE(d.message.find(expected[k].text), std::string::npos) << e.format();
      }
    }
    const std::string command =
        "'" + std::string(RINGDEM_BINARY) + "' check '" + file.string() + "' > /dev/null 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2);
  }
}

TEST(CaseLoader, SweepNameMustStayInsideResults) {
  // The study's name is its output folder results/<name>, as a case's (bad_cases/
  // name_outside_results.yaml): no path separators, no '..'.
  const std::string text =
      "schema_version: 1\nname: ../../X\ncase: c.yaml\n"
      "parameters:\n  - {key: simulation.dt, values: [1e-6]}\n";
  try {
    load_sweep_from_string(text, "s.yaml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics.size(), 1u) << e.format();
    EXPECT_EQ(e.diagnostics[0].key_path, "name");
    EXPECT_EQ(e.diagnostics[0].line, 2);
    EXPECT_NE(e.diagnostics[0].message.find("contains a path separator"), std::string::npos);
  }
  EXPECT_EQ(load_sweep_from_string(replaced(text, "../../X", "ok_X"), "s.yaml").name, "ok_X");
}

TEST(CaseLoader, ZippedSweepMayRepeatAValueButNoCase) {
  // Zipped, one parameter may hold the same value in several cases that differ in another (the
  // hardening of inputs/sweeps/bundle_yield.yaml); a case that would run twice is refused, at
  // the value that repeats it, in either way of combining.
  const std::string zip =
      "schema_version: 1\ncase: c.yaml\ncombine: zip\nparameters:\n"
      "  - {key: a.b, values: [1, 2, 3]}\n"
      "  - {key: a.c, values: [5, 5, 5]}\n";
  const std::vector<SweepCase> cases = expand_sweep(load_sweep_from_string(zip, "s.yaml"));
  ASSERT_EQ(cases.size(), 3u);
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::vector<std::string> expected{"a.b=" + std::to_string(k + 1), "a.c=5"};
    EXPECT_EQ(cases[k].overrides, expected) << k;
  }
  const auto refused = [](const std::string& text, int line, const std::string& message) {
    try {
      load_sweep_from_string(text, "s.yaml");
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const InputError& e) {
      ASSERT_EQ(e.diagnostics.size(), 1u) << e.format();
      EXPECT_EQ(e.diagnostics[0].line, line) << e.format();
      EXPECT_NE(e.diagnostics[0].message.find(message), std::string::npos) << e.format();
    }
  };
  refused(replaced(zip, "[1, 2, 3]", "[1, 2, 1]"), 5, "case 2 repeats case 0");
  refused(replaced(replaced(zip, "combine: zip", "combine: product"), "[5, 5, 5]", "[5, 6, 5]"), 6,
          "duplicate value '5'");
  // A range of one value repeats too, and is reported at the range.
  refused(replaced(replaced(zip, "values: [1, 2, 3]", "range: {from: 1, to: 1, count: 2}"),
                   "[5, 5, 5]", "[5, 5]"),
          5, "case 1 repeats case 0");
}

TEST(CaseLoader, ASweepCaseErrorPointsWhereTheSweepGaveTheValue) {
  // Each case's overrides are checked as --set's are, but a bad value in a sweep is no --set of
  // the user's: it is reported at the sweep file's value or `set` entry (the command line's
  // --set keeps its own number), with the case it is in.
  const std::string text = "schema_version: 1\ncase: " + std::string(RINGDEM_SOURCE_DIR) +
                           "/inputs/tensile/ring4_plastic.yaml\n"
                           "set: [scenario.tensile_test.loading_rate=0.5]\n"
                           "parameters:\n"
                           "  - {key: bonds.0.plastic.hardening_ratio, values: [0.05, -1]}\n";
  const auto first_error = [](const SweepConfig& sweep) {
    try {
      load_sweep_cases(sweep, expand_sweep(sweep));
    } catch (const InputError& e) {
      EXPECT_EQ(e.diagnostics.size(), 1u) << e.format();
      return e.diagnostics.front();
    }
    ADD_FAILURE() << "accepted";
    return Diagnostic{};
  };
  Diagnostic d = first_error(load_sweep_from_string(text, "s.yaml"));
  EXPECT_EQ(d.file, "s.yaml");
  EXPECT_EQ(d.line, 5);
  EXPECT_EQ(d.column, 59);  // the -1
  EXPECT_EQ(d.key_path, "bonds[0].plastic.hardening_ratio");
  EXPECT_EQ(d.message,
            "must be in [0, 1), got -1 (in case_001: bonds.0.plastic.hardening_ratio=-1)");

  d = first_error(load_sweep_from_string(replaced(text, "rate=0.5", "rate=0"), "s.yaml"));
  EXPECT_EQ(d.file, "s.yaml");
  EXPECT_EQ(d.line, 3);
  EXPECT_EQ(d.key_path, "scenario.tensile_test.loading_rate");
  EXPECT_EQ(d.message,
            "must be > 0 m/s, got 0 (in case_000: bonds.0.plastic.hardening_ratio=0.05)");

  d = first_error(load_sweep_from_string(replaced(text, ", -1]", "]"), "s.yaml",
                                         {"simulation.end_time=2", "simulation.dt=-1"}));
  EXPECT_EQ(d.file, "--set");
  EXPECT_EQ(d.line, 2);
  EXPECT_EQ(d.key_path, "simulation.dt");
}

}  // namespace
}  // namespace ringdem

namespace ringdem {
namespace {

TEST(CaseLoader, LargeNetIsCheckedOnAPatchOfTheSameParity) {
  // A net of 3000 x 21 rings loads in a blink (its periodic layout is checked on a patch) and
  // counts every particle; the same net with nearly flat rings (linked rings intersect) is
  // still refused, as a small one is.
  const std::string net = replaced(kValidCase, "  lattices:",
                                   "  nets:\n    - {rows: 3000, columns: 21, material: steel, "
                                   "bond: ring}\n  lattices:");
  const CaseConfig c = load_case_from_string(net, "case.yaml", {});
  ASSERT_EQ(c.nets.size(), 1u);
  EXPECT_EQ(c.nets[0].rows, 3000);
  const auto flat = errors_of(replaced(net, "bond: ring}", "bond: ring, tilt: 0.02}"));
  EXPECT_NE(all(flat).find("rings touch at creation"), std::string::npos) << all(flat);
  const auto flat_small =
      errors_of(replaced(replaced(net, "rows: 3000, columns: 21", "rows: 4, columns: 5"),
                         "bond: ring}", "bond: ring, tilt: 0.02}"));
  EXPECT_NE(all(flat_small).find("rings touch at creation"), std::string::npos);
}

}  // namespace
}  // namespace ringdem
