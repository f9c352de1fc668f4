// Rockfall scenario (issue 6): the energy ledger closes within 1 % of the impact energy over a
// whole run (sag, release, impact), and the boulder's free fall advanced analytically reaches
// the net at sqrt(2 g h).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "TestCases.hpp"
#include "app/RunCommand.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

double json_number(const std::string& text, const std::string& key) {
  const std::regex re("\"" + key + "\": (-?[0-9.eE+-]+)");
  std::smatch m;
  if (!std::regex_search(text, m, re)) throw std::runtime_error("summary has no " + key);
  return std::stod(m[1].str());
}

std::vector<std::vector<double>> read_csv(const std::string& path,
                                          std::vector<std::string>& header) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  for (std::string h; std::getline(hs, h, ',');)
    header.push_back(h);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ls(line);
    for (std::string v; std::getline(ls, v, ',');)
      row.push_back(v == "null" ? std::nan("") : std::stod(v));
    rows.push_back(row);
  }
  return rows;
}

TEST(Rockfall, SmallNetLedgerClosesAndFreeFallIsExact) {
  // A 5 x 5 lattice net (12 rings, 1 312 particles with shackles) catching a 20 kg boulder
  // dropped 0.5 m: every energy term at work (bonds, ring-ring friction, shackle contacts,
  // contact damping, global damping of the net in both phases).
  const std::string text = R"(
schema_version: 1
name: small_rockfall
simulation: {dt: 7.87e-7, end_time: 5.0, progress_interval: 1000}
materials:
  - {name: steel, density: 7800, youngs_modulus: 200.0e9, poisson_ratio: 0.3, restitution: 0.5, friction: 0.3}
  - {name: rock, density: 2600, youngs_modulus: 30.0e9, poisson_ratio: 0.25, restitution: 0.3, friction: 0.5}
bonds:
  - {name: ring, derive_from: {windings: 12, wire_diameter: 0.003}, radius_multiplier: 0.43,
     tensile_strength: 41.0e9, compressive_strength: 41.0e9, shear_strength: 12.0e9}
damping: {global: 0.0}
particles:
  nets:
    - {group: net, rows: 5, columns: 5, bond: ring, material: steel, mass: 0.647}
scenario:
  type: rockfall
  rockfall: {boulder_mass: 20, boulder_density: 2600, boulder_material: rock, drop_height: 0.5,
             sag_damping: 0.7, impact_damping: 0.2, sag_kinetic_energy: 0.01, duration: 0.04,
             record_interval: 2.0e-4}
)";
  const CaseConfig config = load_case_from_string(text, "small_rockfall.yaml");
  std::string dir = (fs::temp_directory_path() / "ringdem_rockfall_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  RunOptions options;
  options.quiet = true;
  const Communicator self = testing::self_comm();
  options.output_dir = dir;
  ASSERT_EQ(run_case(config, options, self), 0);

  std::ifstream in(dir + "/summary.json");
  std::stringstream s;
  s << in.rdbuf();
  const std::string summary = s.str();
  const double impact_energy = json_number(summary, "impact_energy_J");
  EXPECT_NEAR(impact_energy, 20 * 9.81 * 0.5, 1e-9);
  // Issue 6: the ledger closes within 1 % of the impact energy at every row of the whole run.
  EXPECT_LT(json_number(summary, "energy_balance_error"), 0.01);
  EXPECT_GT(json_number(summary, "sag_time_s"), 0.05);

  std::vector<std::string> header;
  const auto rows = read_csv(dir + "/series.csv", header);
  ASSERT_GT(rows.size(), 10u);
  auto col = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  // At the first row after the release, the boulder falls at sqrt(2 g (h - gap)) (the analytic
  // free fall) and nothing has touched it yet.
  const double v_release = std::sqrt(2 * 9.81 * (0.5 - 0.005));
  EXPECT_NEAR(-rows[0][col("boulder_vz_m_s")], v_release, 1e-12);
  // Every dissipation tally grows (never negative) and something was dissipated by the net.
  for (const char* k : {"contact_damping_J", "friction_J", "global_damping_J"})
    EXPECT_GE(rows.back()[col(k)], rows[0][col(k)]) << k;
  EXPECT_GT(rows.back()[col("global_damping_J")] + rows.back()[col("friction_J")] -
                rows[0][col("global_damping_J")] - rows[0][col("friction_J")],
            0.01 * impact_energy);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
