// `ringdem sweep` on a case that is not a tensile test: each case runs through `ringdem run`'s
// loop and sweep.csv gathers the numbers of its summary.json. Runs the ringdem binary.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "CommandLine.hpp"
#include "TempDir.hpp"

namespace ringdem {
namespace {

/// The cells of one line of a CSV without quoted fields.
std::vector<std::string> sweep_table_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');)
    cells.push_back(cell);
  return cells;
}

TEST(SweepCommand, ASweepOfFreeRunsTablesEachCasesSummary) {
  // One sphere falling from rest for end_time under g, at two densities: velocity Verlet is
  // exact under a constant force, so each case's final kinetic energy is m (g t)^2 / 2 with
  // t = steps x dt, whatever its density and end time.
  const std::string dir = testing::temp_dir("sweep_free_run");
  std::ofstream(dir + "/fall.yaml") << R"(schema_version: 1
simulation: {dt: 1.0e-4, end_time: 0.01, gravity: [0, 0, -9.81]}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e9}
particles:
  spheres:
    - {position: [0, 0, 1], radius: 0.01, material: rock}
)";
  std::ofstream(dir + "/study.yaml") << R"(schema_version: 1
case: fall.yaml
parameters:
  - {key: simulation.end_time, values: [0.01, 0.02]}
  - {key: materials.0.density, values: [2600, 1300]}
)";
  const testing::CommandResult r = testing::run_command(fmt::format(
      "cd '{}' && '{}' sweep study.yaml -o '{}/out'", dir, std::string(RINGDEM_BINARY), dir));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("case_003: simulation.end_time=0.02 materials.0.density=1300: exit 0"),
            std::string::npos)
      << r.output;

  std::ifstream table(dir + "/out/sweep.csv");
  std::string line;
  ASSERT_TRUE(std::getline(table, line));
  const std::vector<std::string> header = sweep_table_cells(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(table, line)) {
    const std::vector<std::string> cells = sweep_table_cells(line);
    ASSERT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < cells.size(); ++c)
      row[header[c]] = cells[c];
    rows.push_back(row);
  }
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.at("exit_code"), "0");
    const double density = std::stod(row.at("materials.0.density"));
    const double mass = density * 4.0 / 3.0 * M_PI * 1e-6;
    const double t = std::stod(row.at("steps")) * std::stod(row.at("dt_s"));
    EXPECT_NEAR(t, std::stod(row.at("simulation.end_time")), 1e-12);
    const double expected = 0.5 * mass * (9.81 * t) * (9.81 * t);
    // sweep.csv keeps 10 significant digits.
    EXPECT_NEAR(std::stod(row.at("final_kinetic_energy_J")), expected, 1e-9 * expected)
        << row.at("case");
    // Nested members of summary.json come as object.member; the time per phase does not come.
    EXPECT_NEAR(std::stod(row.at("energy_ledger.kinetic_J")), expected, 1e-9 * expected);
    EXPECT_EQ(row.count("time_per_phase_s.integrate.mean"), 0u);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
