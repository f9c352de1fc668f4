// Warnings of the case loader: input that is valid but most likely not what was meant is
// reported at its line and loads as it is; a sweep reports each warning once, with its cases.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "CaseLoaderFixtures.hpp"
#include "CommandLine.hpp"
#include "TempDir.hpp"
#include "app/SweepCommand.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

using case_fixture::kValidCase;
using case_fixture::line_of;
using case_fixture::replaced;

/// One rock sphere of radius 1 cm falling freely, at the fixed step `dt`.
std::string falling_sphere(const std::string& dt) {
  return fmt::format(R"(schema_version: 1
simulation: {{dt: {}, end_time: 0.01}}
materials:
  - {{name: rock, density: 2600, youngs_modulus: 1.0e9, poisson_ratio: 0.25}}
particles:
  spheres:
    - {{position: [0, 0, 1], radius: 0.01, material: rock}}
)",
                     dt);
}

/// The Rayleigh time-step limit of that sphere, written out here from its formula (docs/physics.md,
/// "Integration and time step"): pi r sqrt(rho / G) / (0.1631 nu + 0.8766), G = E / (2 (1 + nu)).
double falling_sphere_rayleigh_limit() {
  const double shear_modulus = 1.0e9 / (2.0 * 1.25);
  return M_PI * 0.01 * std::sqrt(2600.0 / shear_modulus) / (0.1631 * 0.25 + 0.8766);
}

std::vector<Diagnostic> warnings_of(const std::string& text) {
  std::vector<Diagnostic> warnings;
  load_case_from_string(text, "case.yaml", {}, &warnings);  // loads: a warning is no error
  return warnings;
}

TEST(CaseLoaderWarnings, AFixedTimeStepAboveTheStabilityLimitIsReportedAtItsLine) {
  const double limit = falling_sphere_rayleigh_limit();  // 8.83e-5 s
  EXPECT_TRUE(warnings_of(falling_sphere(fmt::format("{:.6e}", 0.99 * limit))).empty());

  const std::string text = falling_sphere(fmt::format("{:.6e}", 1.5 * limit));
  const std::vector<Diagnostic> warnings = warnings_of(text);
  ASSERT_EQ(warnings.size(), 1u);
  const Diagnostic& w = warnings[0];
  EXPECT_EQ(w.severity, Severity::kWarning);
  EXPECT_EQ(w.key_path, "simulation.dt");
  EXPECT_EQ(w.line, line_of(text, "dt:"));
  EXPECT_EQ(w.column, static_cast<int>(text.find("1.3") - text.find("simulation")) + 1);
  EXPECT_NE(w.message.find("is 1.5 times the smallest stability limit"), std::string::npos)
      << w.message;
  EXPECT_NE(w.message.find("the Rayleigh limit of particles.spheres[0]"), std::string::npos)
      << w.message;
  EXPECT_EQ(format_diagnostic(w).rfind(fmt::format("case.yaml:2:{}: warning: simulation.dt: the "
                                                   "fixed time step ",
                                                   w.column),
                                       0),
            0u)
      << format_diagnostic(w);
  // dt: auto takes dt_safety x the limit: nothing to warn of.
  EXPECT_TRUE(warnings_of(falling_sphere("auto")).empty());
}

TEST(CaseLoaderWarnings, AnInletThatOpensAfterTheRunEndsIsReported) {
  EXPECT_TRUE(warnings_of(kValidCase).empty());  // end_time 0.5 s
  const auto with_inlet = [](const std::string& start_time) {
    return case_fixture::case_with_inlet("[2, 0, 0]", "0.01",
                                         "    start_time: " + start_time + "\n");
  };
  EXPECT_TRUE(warnings_of(with_inlet("0.45")).empty());
  const std::string text = with_inlet("0.5");
  const std::vector<Diagnostic> warnings = warnings_of(text);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].key_path, "inflow[0].start_time");
  EXPECT_EQ(warnings[0].line, line_of(text, "start_time: 0.5"));
  EXPECT_EQ(warnings[0].message,
            "the inlet 'inlet' opens at 0.5 s, when the run has ended (at 0.5 s at the latest): it "
            "adds no grains");
}

// A grain source against the outflow boxes that take its group: wholly outside one, every grain
// it makes is taken out at its first step (an error: the coarse debris demo with its outflow box
// moved past the release and the inlet ran on with none of its grains); reaching out of one, some
// are (a warning). A box that does not take the group, or holds the source, says nothing.
TEST(CaseLoaderWarnings, GrainSourcesOutsideAnOutflowBoxAreReported) {
  // The grains entry goes last under particles (the fixture's spheres), the flow group's.
  const auto with = [](const std::string& outflow_box, const std::string& groups) {
    return replaced(kValidCase, "rigid_bodies:\n",
                    "  grains:\n"
                    "    - {group: flow, material: rock, box_min: [0, 0, 2], box_max: [0.2, 0.2, "
                    "2.2], sizes: {min_radius: 0.01, max_radius: 0.02}}\n"
                    "inflow:\n"
                    "  - {name: inlet, group: flow, material: rock, box_min: [-1, 0, 0], "
                    "box_max: [-0.8, 0.5, 0.3], velocity: [2, 0, 0], discharge: 0.01, sizes: "
                    "{min_radius: 0.01, max_radius: 0.02}}\n"
                    "outflow:\n"
                    "  - {name: out, " +
                        outflow_box + (groups.empty() ? "" : ", groups: " + groups) +
                        "}\nrigid_bodies:\n");
  };
  const std::string inside = with("box_min: [-2, -1, -1], box_max: [2, 1, 3]", "[flow]");
  EXPECT_TRUE(warnings_of(inside).empty()) << inside;

  // The inlet (x from -1 to -0.8) reaches out of a box from x = -0.9.
  std::string text = with("box_min: [-0.9, -1, -1], box_max: [2, 1, 3]", "[flow]");
  std::vector<Diagnostic> warnings = warnings_of(text);
  ASSERT_EQ(warnings.size(), 1u) << InputError(warnings).format();
  EXPECT_EQ(warnings[0].key_path, "inflow[0].box_min");
  EXPECT_EQ(warnings[0].line, line_of(text, "  - {name: inlet"));
  EXPECT_EQ(warnings[0].message,
            "the inlet 'inlet' ([-1, 0, 0] to [-0.8, 0.5, 0.3]) reaches out of the outflow box "
            "'out' ([-0.9, -1, -1] to [2, 1, 3]), which takes its group 'flow': grains it "
            "makes out there are taken out at their first step");
  // The same box for another group (the lattice's) says nothing about the flow.
  EXPECT_TRUE(warnings_of(with("box_min: [-0.9, -1, -1], box_max: [2, 1, 3]", "[debris]")).empty());

  // Wholly outside: the release box (z from 2 to 2.2) above a box that ends at z = 1.5.
  text = with("box_min: [-2, -1, -1], box_max: [2, 1, 1.5]", "[flow]");
  case_fixture::expect_one_error(
      text, "particles.grains[0].box_min", "    - {group: flow, material: rock, box_min",
      "the release box ([0, 0, 2] to [0.2, 0.2, 2.2]) lies wholly outside the outflow box 'out' "
      "([-2, -1, -1] to [2, 1, 1.5]), which takes its group 'flow': every grain it makes would "
      "be taken out at its first step");
  // An outflow box without groups takes every free grain.
  text = with("box_min: [-2, -1, -1], box_max: [2, 1, 1.5]", "");
  const std::vector<Diagnostic> errors = case_fixture::errors_of(text);
  ASSERT_EQ(errors.size(), 1u) << case_fixture::all(errors);
  EXPECT_EQ(errors[0].key_path, "particles.grains[0].box_min");
}

TEST(CaseLoaderWarnings, ASweepReportsEachWarningOnceWithItsCasesAndWhereItsValueIs) {
  // The case's dt is over the limit in every case; an inlet opening at 0.015 s is after the end
  // of the case that ends at 0.01 s only; the swept dt of the last case is over the limit there.
  const std::string dir = testing::temp_dir("sweep_warnings");
  const double limit = falling_sphere_rayleigh_limit();
  std::ofstream(dir + "/fall.yaml")
      << falling_sphere(fmt::format("{:.6e}", 2.0 * limit)) << R"(inflow:
  - {name: inlet, material: rock, box_min: [-1, 0, 0], box_max: [-0.8, 0.5, 0.3],
     velocity: [2, 0, 0], discharge: 0.001, start_time: 0.015,
     sizes: {min_radius: 0.01, max_radius: 0.02}}
)";
  const std::string study = R"(schema_version: 1
case: fall.yaml
parameters:
  - {key: simulation.end_time, values: [0.01, 0.02]}
)";
  std::ofstream(dir + "/study.yaml") << study;
  const SweepConfig sweep = load_sweep(dir + "/study.yaml");
  std::vector<Diagnostic> warnings;
  load_sweep_cases(sweep, expand_sweep(sweep), &warnings);
  ASSERT_EQ(warnings.size(), 2u) << InputError(warnings).format();
  EXPECT_EQ(warnings[0].key_path, "simulation.dt");
  EXPECT_EQ(warnings[0].line, 2);
  EXPECT_NE(warnings[0].message.find("is 2 times"), std::string::npos) << warnings[0].message;
  EXPECT_EQ(warnings[0].message.substr(warnings[0].message.size() - 16), " (in every case)");
  EXPECT_EQ(warnings[1].key_path, "inflow[0].start_time");
  EXPECT_EQ(warnings[1].message,
            "the inlet 'inlet' opens at 0.015 s, when the run has ended (at 0.01 s at the "
            "latest): it adds no grains (in case_000: simulation.end_time=0.01)");

  // A warning that a swept value causes points at that value in the sweep file.
  std::ofstream(dir + "/fall.yaml") << falling_sphere("auto");
  std::ofstream(dir + "/study.yaml") << replaced(study, "simulation.end_time, values: [0.01, 0.02]",
                                                 fmt::format("simulation.dt, values: [{:.6e}, "
                                                             "{:.6e}]",
                                                             0.5 * limit, 3.0 * limit));
  const SweepConfig dt_sweep = load_sweep(dir + "/study.yaml");
  load_sweep_cases(dt_sweep, expand_sweep(dt_sweep), &warnings);
  ASSERT_EQ(warnings.size(), 1u) << InputError(warnings).format();
  EXPECT_EQ(warnings[0].file, dir + "/study.yaml");
  EXPECT_EQ(warnings[0].line, 4);
  EXPECT_NE(warnings[0].message.find("is 3 times"), std::string::npos) << warnings[0].message;
  EXPECT_NE(warnings[0].message.find("(in case_001: simulation.dt="), std::string::npos)
      << warnings[0].message;

  // `ringdem check` prints them and still calls the file valid (exit 0).
  const testing::CommandResult r = testing::run_command(
      fmt::format("'{}' check '{}/study.yaml'", std::string(RINGDEM_BINARY), dir));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("study.yaml:4:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(": warning: simulation.dt: the fixed time step"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("valid sweep (2 cases"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
