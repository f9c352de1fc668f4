// Scenario checks of the ring tensile tests (validation.md §2-3), run on the case files of
// inputs/tensile/. Label "long": each test runs one or two tensile tests (4-90 s each).
//
// Loading rate. The paper's 5 mm/s takes 1.2e7 - 4.4e7 steps per test. The 2-pin transition is
// geometric and is checked at 0.5 m/s; the 4-pin checks, which involve the failure point, pull
// at 0.05 m/s, which gives the paper's-rate curve and failure (RateDoesNotChangeTheCurve). At
// 0.5 m/s the curve is the same but the calibrated ring breaks 1.4 mm early (peak 10 % low):
// the ring sliding round the pins is not quite quasi-static there (docs/tensile.md, "Loading
// rate").
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <string>

#include "../support/TestCases.hpp"
#include "app/TensileTest.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

/// MPI is initialised on first use by testing::self_comm(); finalise it at the end.
class MpiEnvironment : public ::testing::Environment {
 public:
  void TearDown() override {
    int initialised = 0, finalised = 0;
    MPI_Initialized(&initialised);
    MPI_Finalized(&finalised);
    if (initialised && !finalised) MPI_Finalize();
  }
};
const auto* const kMpiEnvironment = ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

CaseConfig tensile_case(const std::string& name, std::vector<std::string> overrides) {
  return load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/" + name + ".yaml",
                   overrides);
}

TensileResult run_quietly(const CaseConfig& c) {
  TensileRunOptions options;
  options.verbose = false;
  return run_tensile_test(c, options, testing::self_comm());
}

const RigidBodyConfig& body(const CaseConfig& c, const std::string& name) {
  for (const auto& b : c.rigid_bodies)
    if (b.name == name) return b;
  throw std::invalid_argument("no rigid body " + name);
}

// physics.md §5: a ring around 2 pins of diameter d_p becomes taut after a pin travel of
// (pi/2 - 1)(D_i - d_p). The tensile stage detected from the curve starts within 10 % of it
// (the tolerance; the ring stretches a little before and the 100-bond polygon is
// slightly shorter than the circle).
TEST(TensileValidation, TwoPinTensileStageStartsWhereTheRingBecomesTaut) {
  const CaseConfig c = tensile_case("ring2", {"scenario.tensile_test.loading_rate=0.5"});
  const double inner_diameter = c.rings[0].internal_diameter;
  const double pin_diameter = 2.0 * body(c, "pin_top").radius;
  // Pins start touching the ring: the displacement is counted from there.
  ASSERT_NEAR(body(c, "pin_top").position.z - body(c, "pin_bottom").position.z,
              inner_diameter - pin_diameter, 1e-12);
  const double expected = (M_PI / 2.0 - 1.0) * (inner_diameter - pin_diameter);
  const TensileResult r = run_quietly(c);
  ASSERT_TRUE(r.analysis.stage_transition_displacement.has_value());
  EXPECT_NEAR(*r.analysis.stage_transition_displacement / expected, 1.0, 0.10)
      << "transition at " << *r.analysis.stage_transition_displacement << " m, expected "
      << expected << " m";
}

// validation.md §3 and Fig. 6: the calibrated ring with 4 contact vertices passes through the
// four stages, and its breaking load stays under what both strands of 12 wires can carry at
// full wire strength, 2 * 12 * 7.07 mm^2 * 1770 MPa = 300 kN (validation.md §2).
//  (a) bonds formed, pins start touching: no load at the start (below 1 % of the peak);
//  (b) bending with geometric nonlinearity: the load rises with a growing tangent stiffness
//      (the secant stiffness over the second half of the bending stage exceeds that over the
//      first half);
//  (c) tensile stage: a steeper rise, the hinge fit's second slope at least 3 times the first;
//  (d) failure: bonds break and the load falls below half of its peak.
TEST(TensileValidation, CalibratedFourPinRingPassesTheFourStages) {
  const CaseConfig c =
      tensile_case("ring4_calibrated", {"scenario.tensile_test.loading_rate=0.05"});
  const TensileResult r = run_quietly(c);
  const TensileCurveAnalysis& a = r.analysis;
  ASSERT_GT(r.curve.size(), 10u);
  EXPECT_LT(std::abs(r.curve.front().load), 0.01 * a.peak_load);  // (a)
  ASSERT_TRUE(a.stage_transition_displacement.has_value());
  const double ut = *a.stage_transition_displacement;
  auto load_at = [&](double u) {
    for (std::size_t i = 1; i < r.curve.size(); ++i)
      if (r.curve[i].displacement >= u) return r.curve[i].load;
    return r.curve.back().load;
  };
  const double first_half = load_at(0.5 * ut) - load_at(0.0);
  const double second_half = load_at(ut) - load_at(0.5 * ut);
  EXPECT_GT(second_half, first_half);                                     // (b)
  EXPECT_GT(a.tensile_stage_stiffness, 3.0 * a.bending_stage_stiffness);  // (c)
  EXPECT_LT(ut, a.displacement_at_peak);
  EXPECT_EQ(r.stop_reason, TensileStopRule::Reason::kFailure);  // (d)
  EXPECT_GT(r.broken_bonds, 0);
  EXPECT_LT(r.curve.back().load, 0.5 * a.peak_load);
  ASSERT_TRUE(r.elongation_at_failure.has_value());
  EXPECT_GE(*r.elongation_at_failure, ut);
  EXPECT_LT(a.peak_load, 2 * 12 * M_PI * 0.0015 * 0.0015 * 1770e6);
  EXPECT_GT(a.peak_load, 0.0);
}

// The faster loading rate used above (and offered in docs/tensile.md) gives the curve of the
// paper's rate, ten times slower: peak load within 3 %, stage transition within 5 %,
// displacement at the peak within 2 %.
TEST(TensileValidation, RateDoesNotChangeTheCurve) {
  const TensileResult fast =
      run_quietly(tensile_case("ring4_calibrated", {"scenario.tensile_test.loading_rate=0.05"}));
  const CaseConfig paper_rate = tensile_case("ring4_calibrated", {});
  ASSERT_DOUBLE_EQ(paper_rate.scenario.tensile_test.loading_rate, 0.005);  // Table 1
  const TensileResult slow = run_quietly(paper_rate);
  EXPECT_NEAR(fast.analysis.peak_load / slow.analysis.peak_load, 1.0, 0.03);
  ASSERT_TRUE(fast.analysis.stage_transition_displacement.has_value());
  ASSERT_TRUE(slow.analysis.stage_transition_displacement.has_value());
  EXPECT_NEAR(
      *fast.analysis.stage_transition_displacement / *slow.analysis.stage_transition_displacement,
      1.0, 0.05);
  EXPECT_NEAR(fast.analysis.displacement_at_peak / slow.analysis.displacement_at_peak, 1.0, 0.02);
}

}  // namespace
}  // namespace ringdem
