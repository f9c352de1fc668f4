// `ringdem calibrate` recovers a known radius multiplier from a curve ringdem produced
// (issue 3: "the calibration recovers lambda within 2 %"). Label "long": about 15 tensile tests
// of 40 mm at 0.5 m/s, 20 s in all.
//
// Loading rate: 0.5 m/s instead of Table 1's 0.005 m/s. Before the first bond breaks it gives
// the paper-rate curve within a few per cent (docs/tensile.md, "Loading rate"), and reference
// and trials use the same rate, so the rate cannot bias the recovered lambda.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../support/TestCases.hpp"
#include "app/Calibration.hpp"
#include "app/TensileTest.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

// The reference: ring4_derived (the calibrated 12-winding ring of Table 3, E_b from Eq. 17) at
// lambda = 0.43, pulled 40 mm: the bending stage, which the paper fits lambda to, and the
// start of the steeper rise (the whole curve's tensile stage starts at 42 mm, failure at
// 55 mm). The fit starts from lambda in [0.3, 0.9], whose centre (0.6) and scan points
// (0.3, 0.45, 0.6, 0.75, 0.9) all miss 0.43. Expected: lambda within 2 % (the issue), E_b the
// Eq. 17 value of the fitted lambda (200 GPa / (5 gamma^2), round-off), and the misfit of the
// best trial under 1 % of the reference peak (the curves' own noise, stick-slip of the ring on
// the pins, is about 0.1 % of the peak between nearby lambdas).
TEST(CalibrationValidation, RecoversTheRadiusMultiplierOfARingdemCurve) {
  const double true_lambda = 0.43;
  const std::string case_path =
      std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_derived.yaml";
  const std::vector<std::string> fast{"scenario.tensile_test.loading_rate=0.5"};
  const auto dir = std::filesystem::temp_directory_path() /
                   ("ringdem_calibration_validation_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);

  std::vector<std::string> reference_overrides = fast;
  reference_overrides.push_back("scenario.tensile_test.max_displacement=0.04");
  reference_overrides.push_back("bonds.0.radius_multiplier=" + std::to_string(true_lambda));
  TensileRunOptions reference_run;
  reference_run.output_dir = (dir / "reference").string();
  reference_run.verbose = false;
  const TensileResult reference = run_tensile_test(load_case(case_path, reference_overrides),
                                                   reference_run, testing::self_comm());
  ASSERT_EQ(reference.stop_reason, TensileStopRule::Reason::kMaxDisplacement);
  ASSERT_EQ(reference.broken_bonds, 0);

  CalibrationOptions options;
  options.case_path = case_path;
  options.reference_path = (dir / "reference" / "series.csv").string();
  options.overrides = fast;
  options.output_dir = (dir / "fit").string();
  options.lambda_lower = 0.3;
  options.lambda_upper = 0.9;
  options.quiet = true;
  const CalibrationResult fit = run_calibration(options, testing::self_comm());

  EXPECT_TRUE(fit.converged);
  EXPECT_NEAR(fit.best.radius_multiplier / true_lambda, 1.0, 0.02)
      << "fitted lambda " << fit.best.radius_multiplier;
  const double gamma = fit.best.radius_multiplier * 0.0045 / (std::sqrt(12.0) * 0.0015);
  EXPECT_NEAR(fit.best.bond_youngs_modulus / (200e9 / (5.0 * gamma * gamma)), 1.0, 1e-12);
  ASSERT_TRUE(fit.gamma.has_value());
  EXPECT_NEAR(*fit.gamma, gamma, 1e-12);
  EXPECT_LT(fit.best.misfit.relative_to_peak, 0.01);
  EXPECT_LE(static_cast<int>(fit.evaluations.size()), options.max_evaluations);

  // The documented outputs.
  for (const char* file :
       {"calibration.json", "evaluations.csv", "best_series.csv", "best_summary.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "fit" / file)) << file;
  std::stringstream json;
  json << std::ifstream(dir / "fit" / "calibration.json").rdbuf();
  for (const char* key : {"\"radius_multiplier\"", "\"bond_youngs_modulus_Pa\"", "\"gamma\"",
                          "\"eta\"", "\"misfit_rms_N\"", "\"misfit_relative_to_peak\"",
                          "\"evaluations\"", "\"converged\": true"})
    EXPECT_NE(json.str().find(key), std::string::npos) << key << "\n" << json.str();
  // The best curve read back is the best trial's: same misfit against the reference.
  const CurveMisfit again =
      compare_curves(read_load_curve(options.reference_path),
                     read_load_curve((dir / "fit" / "best_series.csv").string()), false);
  EXPECT_NEAR(again.rms_load, fit.best.misfit.rms_load, 1e-6 * fit.best.misfit.rms_load + 1e-9);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
