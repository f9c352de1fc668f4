// The rockfall demo (inputs/rockfall/demo.yaml: 40-ring net, 200 kg from 2 m) run whole, checked
// against validation.md §2: the energy balance closes within 1 % of the impact energy, and a net
// that stops the block within a travel d decelerates it at least v0^2 / (2 d) at the peak.
// Label "long" (a few minutes on one core).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "../support/TestCases.hpp"
#include "app/RunCommand.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

double json_number(const std::string& text, const std::string& key) {
  const std::regex re("\"" + key + "\": (-?[0-9.eE+-]+)");
  std::smatch m;
  if (!std::regex_search(text, m, re)) throw std::runtime_error("summary has no " + key);
  return std::stod(m[1].str());
}

TEST(RockfallValidation, DemoNetStopsTheBoulderAboveTheKinematicBoundAndBalances) {
  const CaseConfig c = load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/rockfall/demo.yaml",
                                 {"output.frame_interval=0"});
  std::string dir = (std::filesystem::temp_directory_path() / "ringdem_demo_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  RunOptions options;
  options.quiet = true;
  options.output_dir = dir;
  ASSERT_EQ(run_case(c, options, testing::self_comm()), 0);
  std::ifstream in(dir + "/summary.json");
  std::stringstream s;
  s << in.rdbuf();
  const std::string summary = s.str();
  const double v0 = json_number(summary, "impact_velocity_m_s");
  const double d = json_number(summary, "max_deflection_m");
  const double peak = json_number(summary, "peak_acceleration_m_s2");
  EXPECT_NEAR(v0, std::sqrt(2 * 9.81 * 2.0), 1e-12);
  EXPECT_GT(json_number(summary, "stopping_time_s"), 0.0) << "the net must stop the boulder";
  ASSERT_GT(d, 0.0);
  // validation.md §2: at least the mean deceleration over the braking distance.
  EXPECT_GE(peak, v0 * v0 / (2 * d));
  EXPECT_LT(json_number(summary, "energy_balance_error"), 0.01);
  EXPECT_GT(json_number(summary, "net_sag_m"), 0.0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
