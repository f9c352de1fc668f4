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

using SweepTable = std::vector<std::map<std::string, std::string>>;

/// sweep.csv's rows, each a map from column to cell.
SweepTable read_sweep_table(const std::string& path) {
  std::ifstream table(path);
  std::string line;
  SweepTable rows;
  if (!std::getline(table, line)) return rows;
  const std::vector<std::string> header = sweep_table_cells(line);
  while (std::getline(table, line)) {
    const std::vector<std::string> cells = sweep_table_cells(line);
    EXPECT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < cells.size() && c < header.size(); ++c)
      row[header[c]] = cells[c];
    rows.push_back(row);
  }
  return rows;
}

/// A sphere falling from rest under g for the case's end time: velocity Verlet is exact under a
/// constant force, so the final kinetic energy is m (g t)^2 / 2 with t = steps x dt, whatever the
/// density and the end time (sweep.csv keeps 10 significant digits).
void expect_free_fall(const std::map<std::string, std::string>& row, double g) {
  ASSERT_EQ(row.at("exit_code"), "0") << row.at("case");
  const double density = std::stod(row.at("materials.0.density"));
  const double mass = density * 4.0 / 3.0 * M_PI * 1e-6;
  const double t = std::stod(row.at("steps")) * std::stod(row.at("dt_s"));
  EXPECT_NEAR(t, std::stod(row.at("simulation.end_time")), 1e-12) << row.at("case");
  const double expected = 0.5 * mass * (g * t) * (g * t);
  EXPECT_NEAR(std::stod(row.at("final_kinetic_energy_J")), expected, 1e-9 * expected)
      << row.at("case");
}

const char* const kFallingSphere = R"(schema_version: 1
simulation: {dt: 1.0e-4, end_time: 0.01, gravity: [0, 0, -9.81]}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e8}
particles:
  spheres:
    - {position: [0, 0, 1], radius: 0.01, material: rock}
)";

const char* const kFallStudy = R"(schema_version: 1
case: fall.yaml
parameters:
  - {key: simulation.end_time, values: [0.01, 0.02]}
  - {key: materials.0.density, values: [2600, 1300]}
)";

TEST(SweepCommand, ASweepOfFreeRunsTablesEachCasesSummary) {
  // One sphere falling from rest, two end times and two densities (expect_free_fall).
  const std::string dir = testing::temp_dir("sweep_free_run");
  std::ofstream(dir + "/fall.yaml") << kFallingSphere;
  std::ofstream(dir + "/study.yaml") << kFallStudy;
  const testing::CommandResult r = testing::run_command(fmt::format(
      "cd '{}' && '{}' sweep study.yaml -o '{}/out'", dir, std::string(RINGDEM_BINARY), dir));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("case_003: simulation.end_time=0.02 materials.0.density=1300: exit 0"),
            std::string::npos)
      << r.output;

  const SweepTable rows = read_sweep_table(dir + "/out/sweep.csv");
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) {
    expect_free_fall(row, 9.81);
    // Nested members of summary.json come as object.member; the time per phase does not come.
    EXPECT_EQ(row.at("energy_ledger.kinetic_J"), row.at("final_kinetic_energy_J"));
    EXPECT_EQ(row.count("time_per_phase_s.integrate.mean"), 0u);
  }
  std::filesystem::remove_all(dir);
}

TEST(SweepCommand, ARestartedSweepKeepsWhatIsDoneAndContinuesTheRest) {
  // The free-fall study with a checkpoint every 2.5 ms. Stopped before it starts (a wall-time
  // limit already spent), then continued with --restart: every case runs and falls as
  // expect_free_fall says. Then one case is made to look killed mid-run (its row and summary
  // gone, its checkpoints after t = 0.01 s too): a restart keeps the other three and continues
  // that one from t = 0.01 s to the same numbers as its whole run. A restart with another value
  // for every case is refused, and so is one after the case file was edited.
  const std::string dir = testing::temp_dir("sweep_restart");
  std::ofstream(dir + "/fall.yaml")
      << kFallingSphere << "output: {checkpoint_interval: 0.0025, checkpoints_kept: 10}\n";
  std::ofstream(dir + "/study.yaml") << kFallStudy;
  const std::string sweep = fmt::format("cd '{}' && '{}' sweep study.yaml -o '{}/out'", dir,
                                        std::string(RINGDEM_BINARY), dir);

  testing::CommandResult r = testing::run_command(sweep + " --max-walltime 0.000001");
  ASSERT_EQ(r.status, 3) << r.output;
  EXPECT_NE(r.output.find("--restart"), std::string::npos) << r.output;
  SweepTable rows = read_sweep_table(dir + "/out/sweep.csv");
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("exit_code"), "3");
    EXPECT_FALSE(std::filesystem::exists(dir + "/out/" + row.at("folder") + "/series.csv"));
  }

  r = testing::run_command(sweep + " --restart");
  ASSERT_EQ(r.status, 0) << r.output;
  const SweepTable whole = read_sweep_table(dir + "/out/sweep.csv");
  ASSERT_EQ(whole.size(), 4u);
  for (const auto& row : whole)
    expect_free_fall(row, 9.81);

  // case_003 (end time 0.02 s) as if its job had been killed at t = 0.0125 s.
  const std::string killed = dir + "/out/case_003";
  std::filesystem::remove(killed + "/sweep_row.csv");
  std::filesystem::remove(killed + "/summary.json");
  int kept_checkpoints = 0;
  for (const auto& entry : std::filesystem::directory_iterator(killed + "/checkpoints")) {
    const std::string name = entry.path().filename().string();  // checkpoint_<step>.h5
    const long long step = std::stoll(name.substr(name.find('_') + 1));
    if (step > 100)
      std::filesystem::remove(entry.path());
    else
      ++kept_checkpoints;
  }
  ASSERT_GT(kept_checkpoints, 0);
  r = testing::run_command(sweep + " --restart");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(testing::occurrences(r.output, "done before (exit 0), kept"), 3u) << r.output;
  EXPECT_NE(r.output.find("case_003: simulation.end_time=0.02 materials.0.density=1300: exit 0"),
            std::string::npos)
      << r.output;
  // Continued from its checkpoint, not run again from the start: the checkpoint at its end is
  // of the run's second segment.
  const testing::CommandResult info =
      testing::run_command(fmt::format("'{}' info '{}/checkpoints/checkpoint_000000000200.h5'",
                                       std::string(RINGDEM_BINARY), killed));
  EXPECT_NE(info.output.find("frame segment 1"), std::string::npos) << info.output;
  const SweepTable continued = read_sweep_table(dir + "/out/sweep.csv");
  ASSERT_EQ(continued.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    expect_free_fall(continued[k], 9.81);
    // The same numbers as the whole run (an exact restart), but for the wall clock's.
    for (const auto& [column, value] : whole[k]) {
      if (column == "wall_time_s" || column == "particle_steps_per_s" ||
          column == "peak_memory_largest_rank_bytes" ||
          column == "shared_memory_largest_rank_bytes")
        continue;
      EXPECT_EQ(continued[k].at(column), value) << continued[k].at("folder") << " " << column;
    }
  }

  r = testing::run_command(sweep + " --restart --set simulation.gravity=[0,0,-1]");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("case_000 was run with other values"), std::string::npos) << r.output;

  // The case file edited after the study ran: its finished cases are not this study's any more.
  std::ofstream(dir + "/fall.yaml")
      << std::string(kFallingSphere).replace(std::string(kFallingSphere).find("1.0e8"), 5, "2.0e8")
      << "output: {checkpoint_interval: 0.0025, checkpoints_kept: 10}\n";
  r = testing::run_command(sweep + " --restart");
  EXPECT_EQ(r.status, 2) << r.output;
  for (const char* folder : {"case_000", "case_001", "case_002", "case_003"})
    EXPECT_NE(r.output.find(fmt::format("{} was run from another case", folder)), std::string::npos)
        << r.output;
  EXPECT_NE(r.output.find("youngs_modulus"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
