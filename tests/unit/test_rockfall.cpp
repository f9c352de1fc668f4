// Rockfall scenario (issue 6), checked against expectations of its own, not the driver's
// formulas: the boulder's recorded free fall is ballistic, its trajectory peaks the drop height
// above the sagged net (so it was released as if dropped from rest there), the energy terms of
// the series add up to a constant ledger, and the dissipation tallies grow.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "CommandLine.hpp"
#include "FileText.hpp"
#include "TestCases.hpp"
#include "app/RunCommand.hpp"
#include "app/ScenarioRunner.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"

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

TEST(Rockfall, SmallNetFreeFallIsBallisticAndLedgerCloses) {
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
             record_interval: 2.0e-4, sag_dt: 1.29e-6}
)";
  // The sag at 0.3 of the bonds' axial limit (sag_dt), the impact at Table 1's step: the sag
  // to 0.01 J was most of this test's time, and everything below is measured from the release.
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
  const double g = -config.simulation.gravity.z;
  const double mass = 20.0, density = 2600.0, drop = 0.5;
  const double radius = std::cbrt(3.0 * mass / (4.0 * M_PI * density));
  const double drop_energy = mass * g * drop;
  // Issue 6: the ledger closes within 1 % of the impact energy at every row of the whole run.
  EXPECT_LT(json_number(summary, "energy_balance_error"), 0.01);
  EXPECT_GT(json_number(summary, "sag_time_s"), 0.05);

  std::vector<std::string> header, sag_header;
  const auto rows = read_csv(dir + "/series.csv", header);
  const auto sag = read_csv(dir + "/sag.csv", sag_header);
  ASSERT_GT(rows.size(), 10u);
  ASSERT_FALSE(sag.empty());
  auto col = [&](const std::vector<std::string>& names, const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) throw std::runtime_error("no column " + name);
    return static_cast<std::size_t>(it - names.begin());
  };
  auto at = [&](std::size_t row, const std::string& name) { return rows[row][col(header, name)]; };

  // The first row is the release, the state the sag ended with; the net's top under the drop
  // axis is the last one the sag recorded.
  const double net_top = sag.back()[col(sag_header, "net_top_near_axis_m")];
  EXPECT_EQ(at(0, "time_s"), sag.back()[col(sag_header, "time_s")]);
  const double z0 = at(0, "boulder_z_m"), v0 = at(0, "boulder_vz_m_s");
  ASSERT_LT(v0, 0.0) << "the boulder should be falling at the release";
  EXPECT_GT(z0 - radius - net_top, 0.0) << "released clear of the net";
  // A body falling freely at v0 from z0 came from rest at z0 + v0^2 / (2 g): that apex is the
  // drop height above the net, to round-off.
  EXPECT_NEAR(z0 + v0 * v0 / (2.0 * g) - radius - net_top, drop, 1e-9);

  // Until the first contact, each interval between rows is ballistic: velocity Verlet under a
  // constant force is exact, so dv = -g dt and dz = mean velocity * dt, to round-off.
  std::size_t falling = 0;
  while (falling + 1 < rows.size() && std::isnan(at(falling + 1, "time_from_contact_s")))
    ++falling;
  ASSERT_GE(falling, 3u) << "several rows of free fall before the contact";
  for (std::size_t k = 0; k < falling; ++k) {
    const double dt = at(k + 1, "time_s") - at(k, "time_s");
    const double va = at(k, "boulder_vz_m_s"), vb = at(k + 1, "boulder_vz_m_s");
    EXPECT_NEAR(vb - va, -g * dt, 1e-10) << "row " << k;
    EXPECT_NEAR(at(k + 1, "boulder_z_m") - at(k, "boulder_z_m"), 0.5 * (va + vb) * dt, 1e-10)
        << "row " << k;
    EXPECT_EQ(at(k + 1, "boulder_x_m"), at(0, "boulder_x_m"));
    EXPECT_EQ(at(k + 1, "boulder_y_m"), at(0, "boulder_y_m"));
  }
  // The kinetic energy at the release is the boulder's plus what is left of the net's motion
  // (below the rest threshold, 0.01 J).
  const double boulder_kinetic = 0.5 * mass * v0 * v0;
  EXPECT_GE(at(0, "kinetic_J"), boulder_kinetic * (1.0 - 1e-12));
  EXPECT_LT(at(0, "kinetic_J") - boulder_kinetic, 0.01);

  // The ledger from the series' own terms (mechanical + dissipated - boundary work) stays
  // within 1 % of the drop energy from the release to the end.
  auto ledger = [&](std::size_t k) {
    double sum = -at(k, "boundary_work_J");
    for (const char* term :
         {"kinetic_J", "potential_J", "bond_elastic_J", "contact_elastic_J", "contact_damping_J",
          "friction_J", "global_damping_J", "broken_bonds_J"})
      sum += at(k, term);
    return sum;
  };
  for (std::size_t k = 1; k < rows.size(); ++k)
    EXPECT_LT(std::abs(ledger(k) - ledger(0)), 0.01 * drop_energy) << "row " << k;

  // Every dissipation tally grows (never negative) and something was dissipated by the net.
  const std::size_t last = rows.size() - 1;
  for (const char* k : {"contact_damping_J", "friction_J", "global_damping_J"})
    EXPECT_GE(at(last, k), at(0, k)) << k;
  EXPECT_GT(at(last, "global_damping_J") + at(last, "friction_J") - at(0, "global_damping_J") -
                at(0, "friction_J"),
            0.01 * drop_energy);
  fs::remove_all(dir);
}

using testing::kTinyRockfall;

TEST(Rockfall, LogNeverPrintsPlaceholderValues) {
  // A 2 x 3 net and a 5 kg boulder, cut off 2 ms after the first contact: the boulder is still
  // moving down at the end, so there is no stopping time (issue 15 saw "stopped after -1.0000
  // s"). Progress lines every millisecond of wall time come before the first rest check at
  // t = sag_min_time, when the net's kinetic energy is not known yet (it printed "inf J").
  std::string dir = (fs::temp_directory_path() / "ringdem_rockfall_log_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  const std::string case_path = dir + "/tiny.yaml";
  std::ofstream(case_path) << kTinyRockfall;
  const testing::CommandResult r = testing::run_command(
      fmt::format("'{}' run '{}' -o '{}/out'", RINGDEM_BINARY, case_path, dir));
  const std::string& log = r.output;
  ASSERT_EQ(r.status, 0) << log;
  EXPECT_EQ(log.find("inf J"), std::string::npos) << log;
  EXPECT_EQ(log.find("-1.0000"), std::string::npos) << log;
  EXPECT_NE(log.find("net kinetic energy: first rest check at t = 0.01 s"), std::string::npos)
      << log;
  EXPECT_NE(log.find("still moving down at the end"), std::string::npos) << log;

  // Independently of the driver's bookkeeping: the last row of the series has the boulder
  // still going down, and the summary has no stopping time.
  std::vector<std::string> header;
  const auto rows = read_csv(dir + "/out/series.csv", header);
  ASSERT_FALSE(rows.empty());
  const auto vz = std::find(header.begin(), header.end(), "boulder_vz_m_s");
  ASSERT_NE(vz, header.end());
  EXPECT_LT(rows.back()[static_cast<std::size_t>(vz - header.begin())], 0.0);
  std::ifstream in(dir + "/out/summary.json");
  std::stringstream summary;
  summary << in.rdbuf();
  EXPECT_NE(summary.str().find("\"stopping_time_s\": null"), std::string::npos) << summary.str();
  fs::remove_all(dir);
}

TEST(Rockfall, EndTimeCapsTheScenario) {
  // simulation.end_time is a cap on every scenario: 4 ms of the tiny case's sag (its first
  // rest check is at 10 ms) stop at 4 ms = 2000 steps of 2 us, still in the sag phase.
  std::string dir = (fs::temp_directory_path() / "ringdem_rockfall_cap_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  const std::string case_path = dir + "/tiny.yaml";
  std::ofstream(case_path) << kTinyRockfall;
  const testing::CommandResult r = testing::run_command(fmt::format(
      "'{}' run '{}' -o '{}/out' --set simulation.end_time=0.004", RINGDEM_BINARY, case_path, dir));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("stopped at simulation.end_time = 0.004 s, still in the sag phase"),
            std::string::npos)
      << r.output;
  std::ifstream in(dir + "/out/summary.json");
  std::stringstream summary;
  summary << in.rdbuf();
  EXPECT_EQ(json_number(summary.str(), "steps"), 2000.0) << summary.str();
  EXPECT_NE(summary.str().find("\"stopped_at_end_time\": true"), std::string::npos)
      << summary.str();
  fs::remove_all(dir);
}

// Repeated impact (issue 14 point 4, EAD 340059-00-0106 service energy level test): the tiny
// case with two impacts. Helpers read the results as a user would.
using testing::file_text;

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) throw std::runtime_error("no column " + name);
  return static_cast<std::size_t>(it - header.begin());
}

/// summary.json without what depends on the wall clock, the process's memory or on having
/// restarted.
nlohmann::json summary_without_timings(const fs::path& file) {
  nlohmann::json j = nlohmann::json::parse(file_text(file));
  for (const char* key :
       {"wall_time_s", "sag_wall_time_s", "impact_wall_time_s", "particle_steps_per_s",
        "particle_steps_per_s_per_rank", "time_per_phase_s", "frame_output_s", "restarted",
        "peak_memory_largest_rank_bytes", "shared_memory_largest_rank_bytes"})
    j.erase(key);
  return j;
}

TEST(RockfallRepeated, SecondBoulderFallsDropHeightOntoTheResettledNet) {
  std::string dir = (fs::temp_directory_path() / "ringdem_rockfall_twice_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  const std::string case_path = dir + "/tiny.yaml";
  std::ofstream(case_path) << kTinyRockfall;
  const testing::CommandResult r = testing::run_command(
      fmt::format("'{}' run '{}' -o '{}/out' --set scenario.rockfall.impacts=2", RINGDEM_BINARY,
                  case_path, dir));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("rockfall impact 1: peak acceleration"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rockfall impact 2: peak acceleration"), std::string::npos) << r.output;

  const nlohmann::json s = nlohmann::json::parse(file_text(dir + "/out/summary.json"));
  ASSERT_EQ(s.at("impacts").size(), 2u) << s.dump(1);
  const nlohmann::json& first = s["impacts"][0];
  const nlohmann::json& second = s["impacts"][1];
  for (const nlohmann::json* i : {&first, &second}) {
    SCOPED_TRACE(i->dump());
    ASSERT_TRUE(i->at("residual_height_m").is_number());
    EXPECT_GT(i->at("max_deflection_m").get<double>(), 0.0);
    EXPECT_GE(i->at("rebound_speed_m_s").get<double>(), 0.0);
    EXPECT_GT(i->at("friction_share").get<double>(), 0.0);
    EXPECT_LT(i->at("global_damping_share").get<double>(), 1.0);
  }
  // The summary's keys of one impact are the first impact's.
  EXPECT_EQ(s["peak_acceleration_m_s2"].get<double>(),
            first["peak_acceleration_m_s2"].get<double>());

  // The rows of each impact, from series.csv; the rest checks from resettle.csv.
  std::vector<std::string> h, rh;
  const auto rows = read_csv(dir + "/out/series.csv", h);
  const auto rest = read_csv(dir + "/out/resettle.csv", rh);
  const std::size_t impact = column(h, "impact"), z = column(h, "boulder_z_m"),
                    vz = column(h, "boulder_vz_m_s"), t = column(h, "time_s"),
                    balance = column(h, "balance_error_J");
  std::vector<std::size_t> start;  // first row of each impact
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (k == 0 || rows[k][impact] != rows[k - 1][impact]) start.push_back(k);
  ASSERT_EQ(start.size(), 2u);
  EXPECT_EQ(rows[start[0]][impact], 1.0);
  EXPECT_EQ(rows[start[1]][impact], 2.0);

  // Both boulders start release_gap (0.005 m) above the net top under the drop axis, falling
  // at sqrt(2 g (h - gap)) as if dropped from rest drop_height (0.2 m) above it. The first
  // net top is the sagged one (net_sag_m below the initial top); the second is the initial
  // top plus the residual height after the first impact, which resettle.csv's last check
  // after impact 1 measured at the release.
  const double radius = s["boulder_radius_m"].get<double>(), gap = 0.005, g = 9.81;
  const double initial_top = rows[start[0]][z] - radius - gap + s["net_sag_m"].get<double>();
  const double resettled_top = initial_top + first["residual_height_m"].get<double>();
  EXPECT_NEAR(rows[start[1]][z] - radius - gap, resettled_top, 1e-12);
  std::size_t last_check = 0;
  for (std::size_t k = 0; k < rest.size(); ++k)
    if (rest[k][column(rh, "after_impact")] == 1.0) last_check = k;
  EXPECT_EQ(rest[last_check][column(rh, "time_s")], rows[start[1]][t]);
  EXPECT_NEAR(rest[last_check][column(rh, "net_top_near_axis_m")], resettled_top, 1e-12);
  EXPECT_NE(resettled_top, initial_top - s["net_sag_m"].get<double>());  // a new release height
  for (const std::size_t k : start)
    EXPECT_NEAR(rows[k][vz], -std::sqrt(2.0 * g * (0.2 - gap)), 1e-12);
  // The last check after impact 2 is its residual height.
  EXPECT_EQ(rest.back()[column(rh, "after_impact")], 2.0);
  EXPECT_NEAR(rest.back()[column(rh, "net_top_near_axis_m")] - initial_top,
              second["residual_height_m"].get<double>(), 1e-12);

  // The ledger closes through both impacts: the boulder's energy leaves the ledger with it
  // when it is removed and comes back with the next release (at most 1e-4 of m g h).
  const double drop_energy = 5.0 * g * 0.2;
  for (const auto& row : rows)
    EXPECT_LT(std::abs(row[balance]), 1e-4 * drop_energy) << "t = " << row[t];
  fs::remove_all(dir);
}

// A restart from a checkpoint taken while the net re-settles after the first impact ends
// exactly as the run never interrupted: series.csv, resettle.csv and summary.json (timings
// aside) are the same bytes and values, numbers written with 17 digits.
// The same with sag_dt: the re-settle steps at sag_dt, the release goes back to dt, and the
// restart must find its step from the phase it lands in.
class RockfallRestart : public ::testing::TestWithParam<const char*> {};

TEST_P(RockfallRestart, RestartWhileTheNetResettlesIsBitForBit) {
  std::vector<std::string> twice{"scenario.rockfall.impacts=2"};
  if (*GetParam() != '\0') twice.emplace_back(GetParam());
  const CaseConfig plain = load_case_from_string(kTinyRockfall, "tiny.yaml", twice);
  std::vector<std::string> with_checkpoints = twice;
  with_checkpoints.push_back("output.checkpoint_interval=0.01");
  with_checkpoints.push_back("output.checkpoints_kept=100");
  const CaseConfig checkpointed =
      load_case_from_string(kTinyRockfall, "tiny.yaml", with_checkpoints);
  const fs::path dir =
      fs::temp_directory_path() / ("ringdem_rockfall_restart_" + std::to_string(getpid()));
  fs::remove_all(dir);
  ScenarioRunOptions run;
  run.verbose = false;
  for (const auto& [folder, config] :
       {std::pair{"straight", &plain}, {"checkpointed", &checkpointed}}) {
    run.output_dir = (dir / folder).string();
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(*config);
    ASSERT_EQ(run_scenario(*driver, run, testing::self_comm()), 0);
  }
  EXPECT_EQ(file_text(dir / "checkpointed/series.csv"), file_text(dir / "straight/series.csv"));

  // The re-settle phase: from `duration` after the first contact to the second release.
  const nlohmann::json s = summary_without_timings(dir / "straight/summary.json");
  ASSERT_EQ(s.at("impacts").size(), 2u);
  const double removed = s["impacts"][0]["first_contact_time_s"].get<double>() + 0.002;
  const double released = s["impacts"][1]["release_time_s"].get<double>();
  std::string chosen;
  for (const std::string& path :
       CheckpointStore((dir / "checkpointed/checkpoints").string()).list()) {
    const double time = read_checkpoint_info(path).time;
    if (time > removed && time < released) {
      chosen = path;
      break;
    }
  }
  ASSERT_FALSE(chosen.empty()) << removed << " .. " << released;

  const fs::path restarted = dir / "restarted";
  fs::create_directories(restarted);
  for (const char* file : {"series.csv", "sag.csv", "resettle.csv"})
    fs::copy_file(dir / "checkpointed" / file, restarted / file);
  run.output_dir = restarted.string();
  run.restart = chosen;
  std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(checkpointed);
  ASSERT_EQ(run_scenario(*driver, run, testing::self_comm()), 0);
  for (const char* file : {"series.csv", "sag.csv", "resettle.csv"})
    EXPECT_TRUE(file_text(restarted / file) == file_text(dir / "straight" / file)) << file;
  EXPECT_EQ(summary_without_timings(restarted / "summary.json").dump(1), s.dump(1));
  fs::remove_all(dir);
}

// A sag that does not reach rest in sag_max_time says which half of the rest test failed: the
// kinetic energy above the threshold, or below it while the net still gathers speed (an earlier
// message claimed "3.5 J > 6 J" for the latter).
TEST(Rockfall, SagTimeoutSaysWhichHalfOfTheRestTestFailed) {
  const auto message = [](const std::vector<std::string>& keys) {
    ScenarioRunOptions run;
    run.verbose = false;
    run.output_dir = (fs::temp_directory_path() /
                      ("ringdem_sag_timeout_" + std::to_string(getpid()) + "_" + keys[0]))
                         .string();
    std::unique_ptr<ScenarioDriver> driver =
        make_scenario_driver(load_case_from_string(kTinyRockfall, "tiny.yaml", keys));
    std::string what;
    try {
      run_scenario(*driver, run, testing::self_comm());
    } catch (const std::exception& e) {
      what = e.what();
    }
    fs::remove_all(run.output_dir);
    return what;
  };
  // The tiny net holds far more than 1e-9 J while it falls.
  const std::string above =
      message({"scenario.rockfall.sag_kinetic_energy=1e-9", "scenario.rockfall.sag_max_time=0.02"});
  EXPECT_NE(above.find("not below scenario.rockfall.sag_kinetic_energy 1e-09 J"), std::string::npos)
      << above;
  // Below a huge threshold from the start, but 20 ms into the fall it is still speeding up.
  const std::string falling =
      message({"scenario.rockfall.sag_kinetic_energy=1e9", "scenario.rockfall.sag_max_time=0.02"});
  EXPECT_NE(falling.find("below sag_kinetic_energy 1e+09 J but not yet half its peak"),
            std::string::npos)
      << falling;
  EXPECT_NE(falling.find("the net is still falling"), std::string::npos) << falling;
}

// A drop point over a ring's opening (the tiny net's ring at (0.25, 0.1) is wider than the 5 kg
// boulder) has no net top to release the boulder above: a clear error before the sag, where the
// boulder had been placed at minus infinity and the run reported non-finite energies.
TEST(Rockfall, ADropPointOffTheWiresIsRefusedBeforeTheSag) {
  ScenarioRunOptions run;
  run.verbose = false;
  run.output_dir =
      (fs::temp_directory_path() / ("ringdem_drop_point_" + std::to_string(getpid()))).string();
  for (const char* point : {"[0.25, 0.1, 0]", "[2.0, 0, 0]"}) {
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(load_case_from_string(
        kTinyRockfall, "tiny.yaml", {std::string("scenario.rockfall.drop_point=") + point}));
    std::string what;
    try {
      run_scenario(*driver, run, testing::self_comm());
    } catch (const std::exception& e) {
      what = e.what();
    }
    EXPECT_NE(what.find("scenario.rockfall.drop_point: no particle of the net group 'net' lies "
                        "within the boulder's radius 0.07714 m"),
              std::string::npos)
        << point << ": " << what;
  }
  fs::remove_all(run.output_dir);
}

// The driver advances in batches up to its next row, rest check or end of an impact, and sees
// the boulder every step through observe_step(): the same files, bit for bit, as stepping one
// step at a time (max_batch 1), through two impacts, the removal of the first boulder and the
// re-settle between them.
TEST(RockfallRepeated, BatchesGiveTheSameBitsAsSingleSteps) {
  const CaseConfig twice =
      load_case_from_string(kTinyRockfall, "tiny.yaml", {"scenario.rockfall.impacts=2"});
  const fs::path dir =
      fs::temp_directory_path() / ("ringdem_rockfall_batches_" + std::to_string(getpid()));
  fs::remove_all(dir);
  ScenarioRunOptions run;
  run.verbose = false;
  for (const auto& [folder, batch] : {std::pair{"single", 1}, {"batched", 100}}) {
    run.output_dir = (dir / folder).string();
    run.max_batch = batch;
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(twice);
    ASSERT_EQ(run_scenario(*driver, run, testing::self_comm()), 0);
  }
  for (const char* file : {"series.csv", "sag.csv", "resettle.csv"})
    EXPECT_TRUE(file_text(dir / "batched" / file) == file_text(dir / "single" / file)) << file;
  const nlohmann::json single = summary_without_timings(dir / "single/summary.json");
  EXPECT_EQ(summary_without_timings(dir / "batched/summary.json").dump(1), single.dump(1));
  // What only the every-step look sees, there in both impacts.
  for (const nlohmann::json& impact : single["impacts"]) {
    EXPECT_GT(impact["peak_acceleration_single_step_m_s2"].get<double>(), 0.0);
    EXPECT_GT(impact["max_deflection_m"].get<double>(), 0.0);
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(RockfallRepeated, RockfallRestart,
                         ::testing::Values("", "scenario.rockfall.sag_dt=2.4e-6"));

// sag_dt (issue 12: a sag that reaches rest sooner without changing the settled state): the
// tiny case's net, twice, with dt = 2 us throughout and with the sag and re-settle at 2.4 us
// (0.49 of its smallest stability limit). The sagged net must be the same within 1 % of its
// sag (measured: 5e-5), the impacts the same within 1 % of their deflection (4e-5), and the
// impacts must step at dt again: every row of series.csv after a release lies a whole number
// of 2 us steps after it (not of 2.4 us ones). A sag_dt above the limit is refused.
TEST(Rockfall, SagDtSettlesTheSameNetInFewerSteps) {
  const std::vector<std::string> twice{"scenario.rockfall.impacts=2"};
  std::vector<std::string> faster = twice;
  faster.emplace_back("scenario.rockfall.sag_dt=2.4e-6");
  const fs::path dir = fs::temp_directory_path() / ("ringdem_sag_dt_" + std::to_string(getpid()));
  fs::remove_all(dir);
  ScenarioRunOptions run;
  run.verbose = false;
  for (const auto& [folder, keys] : {std::pair{"plain", &twice}, {"sag_dt", &faster}}) {
    run.output_dir = (dir / folder).string();
    std::unique_ptr<ScenarioDriver> driver =
        make_scenario_driver(load_case_from_string(kTinyRockfall, "tiny.yaml", *keys));
    ASSERT_EQ(run_scenario(*driver, run, testing::self_comm()), 0);
  }
  const nlohmann::json plain = nlohmann::json::parse(file_text(dir / "plain/summary.json"));
  const nlohmann::json fast = nlohmann::json::parse(file_text(dir / "sag_dt/summary.json"));
  const double sag = plain["net_sag_m"].get<double>();
  ASSERT_GT(sag, 1e-3);
  EXPECT_NEAR(fast["net_sag_m"].get<double>(), sag, 0.01 * sag);
  ASSERT_EQ(fast["impacts"].size(), 2u);
  // The re-settle ends at the first check (every 5 ms) at which the net's kinetic energy is
  // below 0.05 J: its 3 rings (1.94 kg) may then still move at sqrt(2 * 0.05 / 1.94) m/s, so
  // the rest test itself defines the re-settled net only to that speed times the check interval
  // (1.1 mm; measured difference 0.09 mm). The first sag starts from the same state in both
  // runs and is held to 1 % of the sag.
  const double resettle_resolution = std::sqrt(2.0 * 0.05 / (3 * 0.647)) * 0.005;
  for (std::size_t i = 0; i < 2; ++i) {
    const double top = plain["impacts"][i]["release_net_top_m"].get<double>();
    EXPECT_NEAR(fast["impacts"][i]["release_net_top_m"].get<double>(), top,
                i == 0 ? 0.01 * sag : resettle_resolution)
        << i;
    const double deflection = plain["impacts"][i]["max_deflection_m"].get<double>();
    EXPECT_NEAR(fast["impacts"][i]["max_deflection_m"].get<double>(), deflection, 0.01 * deflection)
        << i;
  }
  EXPECT_EQ(fast["dt_s"].get<double>(), 2e-6);
  EXPECT_EQ(fast["sag_dt_s"].get<double>(), 2.4e-6);
  EXPECT_EQ(plain["sag_dt_s"].get<double>(), 2e-6);
  EXPECT_LT(fast["steps"].get<double>(), 0.9 * plain["steps"].get<double>());

  std::vector<std::string> header;
  const auto rows = read_csv((dir / "sag_dt/series.csv").string(), header);
  const std::size_t t = column(header, "time_s"), impact = column(header, "impact");
  std::size_t checked = 0;
  for (std::size_t i = 0; i < 2; ++i) {
    const double released = fast["impacts"][i]["release_time_s"].get<double>();
    for (const auto& row : rows) {
      if (row[impact] != static_cast<double>(i + 1) || row[t] <= released) continue;
      const double steps = (row[t] - released) / 2e-6;
      EXPECT_NEAR(steps, std::round(steps), 1e-3) << "impact " << i + 1 << " at " << row[t];
      ++checked;
    }
  }
  EXPECT_GT(checked, 4u);

  run.output_dir = (dir / "too_large").string();
  std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(
      load_case_from_string(kTinyRockfall, "tiny.yaml", {"scenario.rockfall.sag_dt=1e-5"}));
  try {
    run_scenario(*driver, run, testing::self_comm());
    ADD_FAILURE() << "a sag_dt twice the stability limit was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("scenario.rockfall.sag_dt 1e-05 s is 2.06 times the "
                                         "smallest stability limit"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
