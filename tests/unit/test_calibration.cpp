// Pieces of `ringdem calibrate` (app/Calibration.hpp) on inputs with known answers: reading a
// reference curve, the misfit between curves, and the two optimisers on analytic functions.
// The end-to-end recovery of lambda from a ringdem curve is in tests/validation (label long).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "app/Calibration.hpp"
#include "io/InputError.hpp"

namespace ringdem {
namespace {

// series.csv of a tensile test: extra columns are ignored, comments and blank lines skipped.
TEST(ReferenceCurve, ReadsTheNamedColumnsOfASeriesFile) {
  const LoadCurve c = parse_load_curve(
      "# measured by hand\n"
      "time_s,displacement_m,load_N,broken_bonds\n"
      "0,0,0,0\n"
      "\n"
      "0.1,0.001,250.5,0\n"
      "0.2,0.002,1.5e3,1\n",
      "curve.csv");
  ASSERT_EQ(c.displacement.size(), 3u);
  EXPECT_EQ(c.displacement[2], 0.002);
  EXPECT_EQ(c.load[1], 250.5);
  EXPECT_EQ(c.load[2], 1500.0);
  // Column order does not matter.
  const LoadCurve swapped = parse_load_curve("load_N,displacement_m\n1,0\n2,0.5\n", "s.csv");
  EXPECT_EQ(swapped.displacement[1], 0.5);
  EXPECT_EQ(swapped.load[1], 2.0);
}

TEST(ReferenceCurve, ReportsTheLineOfABadRow) {
  const std::vector<std::pair<std::string, int>> bad{
      {"displacement_m,force\n0,1\n", 1},                 // no load_N column
      {"displacement_m,load_N\n0,1\n0.1,abc\n", 3},       // not a number
      {"displacement_m,load_N\n0,1\n0.2,2\n0.1,3\n", 4},  // displacement decreases
      {"displacement_m,load_N\n0,1\n", 2},                // a single row
      {"displacement_m,load_N\n0,1\n0.1\n", 3},           // missing cell
  };
  for (const auto& [text, line] : bad) {
    try {
      parse_load_curve(text, "bad.csv");
      ADD_FAILURE() << "expected an InputError for\n" << text;
    } catch (const InputError& e) {
      ASSERT_EQ(e.diagnostics.size(), 1u);
      EXPECT_EQ(e.diagnostics[0].line, line) << e.format();
      EXPECT_EQ(e.diagnostics[0].file, "bad.csv");
    }
  }
}

// The simulated curve is interpolated linearly at the reference points: a straight line sampled
// elsewhere matches exactly (to round-off); a constant offset of 50 N gives an RMS of 50 N.
TEST(CurveMisfit, InterpolatesTheSimulatedCurveAtTheReferencePoints) {
  LoadCurve reference, simulated, offset;
  for (int i = 0; i <= 10; ++i) {
    reference.displacement.push_back(0.004 * i);
    reference.load.push_back(1e6 * 0.004 * i);
  }
  for (int i = 0; i <= 13; ++i) {
    simulated.displacement.push_back(0.0031 * i);
    simulated.load.push_back(1e6 * 0.0031 * i);
    offset.displacement.push_back(0.0031 * i);
    offset.load.push_back(1e6 * 0.0031 * i + 50.0);
  }
  const CurveMisfit exact = compare_curves(reference, simulated, false);
  EXPECT_NEAR(exact.rms_load, 0.0, 1e-9);
  const CurveMisfit shifted = compare_curves(reference, offset, false);
  EXPECT_NEAR(shifted.rms_load, 50.0, 1e-9);
  EXPECT_NEAR(shifted.relative_to_peak, 50.0 / 40000.0, 1e-12);
}

// Beyond the end of the simulated curve: load 0 if the ring broke, else the last load.
// Reference 1000 N at u = 0, 1, 2, 3 mm; simulation 1000 N up to 1.5 mm: 2 of 4 points miss
// by 1000 N when broken, RMS = sqrt(2 * 1000^2 / 4).
TEST(CurveMisfit, ABrokenRingCarriesNoLoadAfterItsCurveEnds) {
  const LoadCurve reference{{0.0, 0.001, 0.002, 0.003}, {1000.0, 1000.0, 1000.0, 1000.0}};
  const LoadCurve simulated{{0.0, 0.0015}, {1000.0, 1000.0}};
  EXPECT_NEAR(compare_curves(reference, simulated, true).rms_load, 1000.0 * std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(compare_curves(reference, simulated, false).rms_load, 0.0, 1e-12);
}

/// Wraps a function of the point as a batch objective and records the batch sizes.
BatchObjective counted(std::function<double(const std::vector<double>&)> f,
                       std::vector<std::size_t>& batches) {
  return [f, &batches](const std::vector<std::vector<double>>& points) {
    batches.push_back(points.size());
    std::vector<double> out;
    for (const auto& p : points)
      out.push_back(f(p));
    return out;
  };
}

// BOBYQA on a parabola with its minimum off the centre of the bracket: the minimum within the
// tolerance, the scan in one batch, then one point at a time; a quadratic model needs far fewer
// evaluations than golden section alone (log(0.6 / 2e-4) / log(1.618) = 17 after the scan).
TEST(Optimiser, ScanThenBobyqaFindsTheMinimumOfAParabola) {
  std::vector<std::size_t> batches;
  std::vector<double> evaluated;
  const double minimum = 0.4317;
  const MinimumFound found =
      minimise_scan_then_bobyqa(counted(
                                    [&](const auto& x) {
                                      evaluated.push_back(x[0]);
                                      return 3.0 + std::pow(x[0] - minimum, 2);
                                    },
                                    batches),
                                0.3, 0.9, 5, 1e-4, 40);
  EXPECT_TRUE(found.converged);
  EXPECT_NEAR(found.point[0], minimum, 2e-4);
  EXPECT_NEAR(found.value, 3.0, 1e-7);
  ASSERT_FALSE(batches.empty());
  EXPECT_EQ(batches.front(), 5u);
  for (std::size_t k = 1; k < batches.size(); ++k)
    EXPECT_EQ(batches[k], 1u);
  EXPECT_EQ(found.evaluations, 5 + static_cast<int>(batches.size()) - 1);
  EXPECT_LT(found.evaluations, 5 + 17);
  // Each evaluation is a simulation: none is repeated, not even one round-off away (BOBYQA's
  // first interpolation points are scanned points, met again after its internal rescaling).
  for (std::size_t i = 0; i < evaluated.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_GT(std::abs(evaluated[i] - evaluated[j]), 1e-9) << i << " repeats " << j;
}

// A kink (|x - c|) has no parabola to exploit, yet the trust region shrinks onto it; a minimum
// at the bound is found too.
TEST(Optimiser, ScanThenBobyqaOnAKinkAndAtTheBound) {
  std::vector<std::size_t> batches;
  const MinimumFound kink = minimise_scan_then_bobyqa(
      counted([](const auto& x) { return std::abs(x[0] - 0.7123); }, batches), 0.2, 1.0, 5, 1e-4,
      60);
  EXPECT_TRUE(kink.converged);
  EXPECT_NEAR(kink.point[0], 0.7123, 2e-4);
  const MinimumFound bound = minimise_scan_then_bobyqa(
      counted([](const auto& x) { return x[0]; }, batches), 0.2, 1.0, 5, 1e-4, 60);
  EXPECT_NEAR(bound.point[0], 0.2, 2e-4);
  // The budget is respected and reported.
  const MinimumFound budget = minimise_scan_then_bobyqa(
      counted([](const auto& x) { return std::abs(x[0] - 0.7123); }, batches), 0.2, 1.0, 5, 1e-9,
      8);
  EXPECT_FALSE(budget.converged);
  EXPECT_EQ(budget.evaluations, 8);
}

// Nelder-Mead on an elongated quadratic bowl in the unit box; the first simplex is one batch.
// A minimum outside the box ends on its face.
TEST(Optimiser, NelderMeadInTheUnitBox) {
  std::vector<std::size_t> batches;
  const auto bowl = [](const std::vector<double>& p) {
    return std::pow(p[0] - 0.3, 2) + 10.0 * std::pow(p[1] - 0.7, 2) + (p[0] - 0.3) * (p[1] - 0.7);
  };
  const MinimumFound found =
      minimise_nelder_mead(counted(bowl, batches), {0.9, 0.1}, 0.25, 1e-4, 0.0, 200);
  EXPECT_TRUE(found.converged);
  EXPECT_NEAR(found.point[0], 0.3, 1e-3);
  EXPECT_NEAR(found.point[1], 0.7, 1e-3);
  EXPECT_EQ(batches.front(), 3u);
  const MinimumFound face = minimise_nelder_mead(
      counted([](const auto& p) { return std::pow(p[0] + 0.5, 2) + std::pow(p[1] - 0.5, 2); },
              batches),
      {0.5, 0.9}, 0.25, 1e-4, 0.0, 200);
  EXPECT_NEAR(face.point[0], 0.0, 1e-3);
  EXPECT_NEAR(face.point[1], 0.5, 1e-3);
  // The value tolerance stops it as soon as the vertices' values agree that closely.
  const MinimumFound coarse =
      minimise_nelder_mead(counted(bowl, batches), {0.9, 0.1}, 0.25, 1e-4, 1e-2, 200);
  EXPECT_TRUE(coarse.converged);
  EXPECT_LT(coarse.evaluations, found.evaluations);
  EXPECT_LT(coarse.value, 0.0 + 2e-2);
}

}  // namespace
}  // namespace ringdem
