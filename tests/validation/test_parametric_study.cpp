// The parametric study of Table 2 (Figs. 7-9): the three sweeps of inputs/sweeps/ run as
// `ringdem sweep` runs them, and each trend of validation.md §3 "Parametric study" is checked in
// their output (sweep.csv and each case's series.csv). Label "long": 15 tensile tests at
// 0.05 m/s, about 100 s.
//
// Loading rate: the sweep files pull at 0.05 m/s, which gives the paper's-rate results: at
// 40 GPa the elongation at failure is 113.9 mm at 0.05 and at 0.005 m/s, at 200 GPa 34.5 and
// 34.6 mm (ratio 3.30 at both); the reference case breaks at 113.3 and 117.8 kN. At 0.5 m/s the
// ring, sliding round the pins, breaks up to 4 mm early or late (docs/tensile.md).
//
// The rig (ring4_reference.yaml): 30 mm pins at +-45 degrees, ring-pin friction 0.3. The paper
// gives neither the pin diameter nor the ring-pin friction, and two of the trends depend on
// them; docs/tensile.md, "The studies of Table 2", has the map over both.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../support/TestCases.hpp"
#include "app/Calibration.hpp"
#include "app/SweepCommand.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

/// One case of a finished sweep: its row of sweep.csv and its curve.
struct SweepCaseResult {
  std::map<std::string, std::string> row;
  LoadCurve curve;
  double number(const std::string& column) const { return std::stod(row.at(column)); }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ','))
    cells.push_back(cell);
  return cells;
}

/// Runs inputs/sweeps/NAME.yaml on one rank into a temporary folder and reads its output.
std::vector<SweepCaseResult> run_study(const std::string& name) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ringdem_" + name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  SweepOptions options;
  options.sweep_path = std::string(RINGDEM_SOURCE_DIR) + "/inputs/sweeps/" + name + ".yaml";
  options.output_dir = dir.string();
  options.quiet = true;
  EXPECT_EQ(run_sweep(options, testing::self_comm()), 0);
  std::ifstream table(dir / "sweep.csv");
  std::string line;
  std::getline(table, line);
  const std::vector<std::string> header = split(line);
  std::vector<SweepCaseResult> cases;
  while (std::getline(table, line)) {
    const std::vector<std::string> cells = split(line);
    SweepCaseResult c;
    for (std::size_t k = 0; k < header.size() && k < cells.size(); ++k)
      c.row[header[k]] = cells[k];
    c.curve = read_load_curve((dir / c.row.at("folder") / "series.csv").string());
    cases.push_back(std::move(c));
  }
  std::filesystem::remove_all(dir);
  return cases;
}

double load_at(const LoadCurve& c, double u) {
  const auto upper = std::lower_bound(c.displacement.begin(), c.displacement.end(), u);
  if (upper == c.displacement.begin()) return c.load.front();
  if (upper == c.displacement.end()) return c.load.back();
  const auto i = static_cast<std::size_t>(upper - c.displacement.begin());
  const double t = (u - c.displacement[i - 1]) / (c.displacement[i] - c.displacement[i - 1]);
  return c.load[i - 1] + t * (c.load[i] - c.load[i - 1]);
}

/// Coefficient of determination of the least-squares line through (x, y).
double r_squared(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i] / n;
    my += y[i] / n;
  }
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxy * sxy / (sxx * syy);
}

/// Travel of the moving plate of the 4-pin rig (ring4_reference) at which an inextensible ring
/// is pulled taut into a rectangle around the pins: centreline length pi (D_i + 2 r) =
/// 2 w + 2 h + 2 pi (r_p + r) with w, h the spans between pin centres; travel = h - h_0.
double four_pin_taut_travel() {
  const CaseConfig c =
      load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_reference.yaml");
  const RingConfig& ring = c.rings.front();
  const RigidBodyConfig& top = c.rigid_bodies[0];
  const RigidBodyConfig& bottom = c.rigid_bodies[2];
  const double wrap_radius = top.radius + ring.particle_radius;
  const double length = M_PI * (ring.internal_diameter + 2.0 * ring.particle_radius);
  const double width = std::abs(c.rigid_bodies[1].position.x - top.position.x);
  const double height0 = top.position.z - bottom.position.z;
  return 0.5 * (length - 2.0 * width - 2.0 * M_PI * wrap_radius) - height0;
}

// Fig. 7, E_b from 40 to 200 GPa.
// - The load at a given displacement rises with E_b: at 5, 10, 20 and 30 mm (every case is
//   still intact at 30 mm; the first breaks at 34.5 mm), strictly increasing.
// - "At 200 GPa the ring breaks while it is still changing shape": its elongation at failure is
//   below the travel at which an inextensible ring is taut around the 4 pins (42.3 mm); at
//   40 GPa the ring is pulled taut and stretched before it breaks (above it).
// - "Elongation at failure at 40 GPa more than three times that at 200 GPa": 113.9 / 34.5 mm =
//   3.30 here. The 200 GPa ring breaks in bending as it wraps a pin, once its curvature radius
//   reaches E_b r_b / sigma_T = 45 mm (32-37 mm of travel for any pin and friction tried). The
//   40 GPa ring wraps the pins and breaks in tension; how far it stretches first depends on the
//   rig: the bending stress at the pin, E_b r_b / (r_p + r_eq), takes part of the strength, and
//   friction on the pins (a capstan) keeps the stretch out of the top and bottom of the ring.
//   With the friction of Table 1 (1.0) on the pins the ratio is 2.5-2.8 for 20-40 mm pins.
TEST(ParametricStudy, BondYoungsModulus) {
  const std::vector<SweepCaseResult> cases = run_study("table2_youngs_modulus");
  ASSERT_EQ(cases.size(), 5u);
  for (std::size_t k = 1; k < cases.size(); ++k)
    ASSERT_GT(cases[k].number("bonds.0.youngs_modulus"),
              cases[k - 1].number("bonds.0.youngs_modulus"));
  for (const double u : {0.005, 0.01, 0.02, 0.03})
    for (std::size_t k = 1; k < cases.size(); ++k)
      EXPECT_GT(load_at(cases[k].curve, u), load_at(cases[k - 1].curve, u))
          << "at u = " << u << " m, case " << k;
  for (const SweepCaseResult& c : cases) {
    EXPECT_EQ(c.row.at("stop_reason"), "failure");
    EXPECT_GT(c.number("elongation_at_failure_m"), 0.03);  // intact at 30 mm (above)
  }
  const double taut = four_pin_taut_travel();
  EXPECT_NEAR(taut, 0.0423, 0.0005);  // the case file's comment: 42 mm
  const double soft = cases.front().number("elongation_at_failure_m");
  const double stiff = cases.back().number("elongation_at_failure_m");
  EXPECT_LT(stiff, taut);
  EXPECT_GT(soft, taut);
  EXPECT_GT(soft / stiff, 3.0);
  for (std::size_t k = 1; k < cases.size(); ++k)
    EXPECT_LT(cases[k].number("elongation_at_failure_m"),
              cases[k - 1].number("elongation_at_failure_m"));
}

// Fig. 8, tensile (and compressive, swept together) strength from 4 to 20 GPa.
// - The curves overlap until failure: the strength enters only the failure test, so every pair
//   of cases runs the same steps until the weaker one's first bond breaks; their rows agree to
//   round-off (1e-9 of the peak) up to one record interval before it.
// - Breaking load and elongation at failure grow with the strength (strictly).
// - "Linear relations are observed after the ring is stretched into a rectangular shape" (the
//   paper): the cases share one curve, whose tensile stage starts at the transition detected on
//   the longest of them (the 20 GPa ring, 34.3 mm). The rings that break beyond it (12, 16 and
//   20 GPa, 38-47 mm) have a breaking load linear in the strength (R^2 >= 0.99). The weaker
//   ones break in the soft bending stage (the 4 GPa ring at 21 mm), below that line. The
//   elongation is close to linear in the strength from 8 to 20 GPa (R^2 >= 0.95).
TEST(ParametricStudy, BondTensileStrength) {
  const std::vector<SweepCaseResult> cases = run_study("table2_tensile_strength");
  ASSERT_EQ(cases.size(), 5u);
  std::vector<double> strength, breaking, elongation;
  for (const SweepCaseResult& c : cases) {
    EXPECT_EQ(c.row.at("stop_reason"), "failure");
    EXPECT_EQ(c.number("bonds.0.compressive_strength"), c.number("bonds.0.tensile_strength"));
    strength.push_back(c.number("bonds.0.tensile_strength"));
    breaking.push_back(c.number("peak_load_N"));
    elongation.push_back(c.number("elongation_at_failure_m"));
  }
  for (std::size_t k = 1; k < cases.size(); ++k) {
    ASSERT_GT(strength[k], strength[k - 1]);
    EXPECT_GT(breaking[k], breaking[k - 1]);
    EXPECT_GT(elongation[k], elongation[k - 1]);
    const LoadCurve& weaker = cases[k - 1].curve;
    const LoadCurve& stronger = cases[k].curve;
    const double record_interval = 2e-4;
    std::size_t compared = 0;
    for (std::size_t i = 0; i < weaker.displacement.size() && i < stronger.displacement.size();
         ++i) {
      if (weaker.displacement[i] > elongation[k - 1] - record_interval) break;
      EXPECT_NEAR(stronger.displacement[i], weaker.displacement[i], 1e-12);
      EXPECT_NEAR(stronger.load[i], weaker.load[i], 1e-9 * breaking[k]) << "row " << i;
      ++compared;
    }
    EXPECT_GT(compared, 50u);
  }
  const double tensile_stage_start = cases.back().number("stage_transition_displacement_m");
  std::vector<double> tensile_strength, tensile_breaking;
  for (std::size_t k = 0; k < cases.size(); ++k)
    if (elongation[k] > tensile_stage_start) {
      tensile_strength.push_back(strength[k]);
      tensile_breaking.push_back(breaking[k]);
    }
  ASSERT_GE(tensile_strength.size(), 3u) << "tensile stage from " << tensile_stage_start << " m";
  EXPECT_GE(r_squared(tensile_strength, tensile_breaking), 0.99);
  EXPECT_GE(r_squared(std::vector<double>(strength.begin() + 1, strength.end()),
                      std::vector<double>(elongation.begin() + 1, elongation.end())),
            0.95);
  EXPECT_LT(elongation.front(), tensile_stage_start);
}

// Fig. 9, bond radius multiplier from 0.5 to 0.9.
// - Strong effect on the breaking load, growing with lambda (strictly increasing; it changes
//   the bond's cross-section, so more than doubles over the range: bond area ratio 3.2).
// - The elongation at failure grows slightly as lambda decreases: strictly decreasing with
//   lambda, and "slightly" / "less significant than varying E_b": its relative spread
//   (max/min - 1) is under a fifth of that of the breaking load and under a fifth of that of
//   the elongation in the E_b study (measured there: 2.30; the bound here uses the 3 - 1 that
//   BondYoungsModulus asserts, so the two tests stay independent).
TEST(ParametricStudy, BondRadiusMultiplier) {
  const std::vector<SweepCaseResult> cases = run_study("table2_radius_multiplier");
  ASSERT_EQ(cases.size(), 5u);
  std::vector<double> breaking, elongation;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    EXPECT_EQ(cases[k].row.at("stop_reason"), "failure");
    if (k > 0) {
      ASSERT_GT(cases[k].number("bonds.0.radius_multiplier"),
                cases[k - 1].number("bonds.0.radius_multiplier"));
    }
    breaking.push_back(cases[k].number("peak_load_N"));
    elongation.push_back(cases[k].number("elongation_at_failure_m"));
  }
  for (std::size_t k = 1; k < cases.size(); ++k) {
    EXPECT_GT(breaking[k], breaking[k - 1]);
    EXPECT_LT(elongation[k], elongation[k - 1]);
  }
  EXPECT_GT(breaking.back() / breaking.front(), 2.0);
  const double elongation_spread = elongation.front() / elongation.back() - 1.0;
  const double breaking_spread = breaking.back() / breaking.front() - 1.0;
  EXPECT_LT(elongation_spread, breaking_spread / 5.0);
  EXPECT_LT(elongation_spread, (3.0 - 1.0) / 5.0);
}

}  // namespace
}  // namespace ringdem
