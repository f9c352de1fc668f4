// `ringdem calibrate` on several ranks: the trials of a batch (the lambda scan) are spread over
// the ranks and their results gathered at the batch's end. The fit must be the one a single
// rank finds, trial for trial and bit for bit: each trial runs on one rank alone, so only the
// gathering can differ, and a trial's result put in another's place would show.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>

#include "SharedTempDir.hpp"
#include "app/Calibration.hpp"
#include "app/TensileTest.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

TEST(CalibrationRanks, TheFitIsTheSingleRanksTrialForTrial) {
  const testing::WorldCopy world_copy;
  {
    const Communicator world(world_copy.raw());
    const Communicator self = Communicator::self();
    const std::filesystem::path dir(testing::shared_temp_dir(world, "calibration"));

    // A short, fast pull of the calibrated ring at lambda = 0.43 as the measured curve.
    const std::string case_path =
        std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_derived.yaml";
    const std::vector<std::string> fast{"scenario.tensile_test.loading_rate=0.5",
                                        "scenario.tensile_test.max_displacement=0.008"};
    if (world.is_root()) {
      std::vector<std::string> reference_overrides = fast;
      reference_overrides.push_back("bonds.0.radius_multiplier=0.43");
      TensileRunOptions run;
      run.output_dir = (dir / "reference").string();
      run.verbose = false;
      run_tensile_test(load_case(case_path, reference_overrides), run, self);
    }
    world.barrier();

    CalibrationOptions options;
    options.case_path = case_path;
    options.reference_path = (dir / "reference" / "series.csv").string();
    options.overrides = fast;
    options.lambda_lower = 0.35;
    options.lambda_upper = 0.55;
    options.scan_points = 3;      // one batch, spread over the ranks
    options.max_evaluations = 4;  // then the refinement, one trial at a time
    options.quiet = true;
    // Every rank fits alone (at the same time, in folders of its own), then all fit together.
    options.output_dir = (dir / ("alone_" + std::to_string(world.rank()))).string();
    const CalibrationResult alone = run_calibration(options, self);
    options.output_dir = (dir / "together").string();
    const CalibrationResult together = run_calibration(options, world);

    ASSERT_EQ(together.evaluations.size(), alone.evaluations.size());
    EXPECT_GE(alone.evaluations.size(), 4u);  // the scan and at least one refinement
    for (std::size_t i = 0; i < alone.evaluations.size(); ++i) {
      const CalibrationEvaluation& a = alone.evaluations[i];
      const CalibrationEvaluation& t = together.evaluations[i];
      EXPECT_EQ(t.radius_multiplier, a.radius_multiplier) << "evaluation " << i;
      EXPECT_EQ(t.bond_youngs_modulus, a.bond_youngs_modulus) << "evaluation " << i;
      EXPECT_EQ(t.misfit.rms_load, a.misfit.rms_load) << "evaluation " << i;
      EXPECT_EQ(t.misfit.relative_to_peak, a.misfit.relative_to_peak) << "evaluation " << i;
      EXPECT_EQ(t.peak_load, a.peak_load) << "evaluation " << i;
      EXPECT_EQ(t.folder, a.folder) << "evaluation " << i;
      // Each trial's curve is where the table says, written by whichever rank ran it.
      EXPECT_TRUE(std::filesystem::exists(dir / "together" / t.folder / "series.csv")) << i;
    }
    EXPECT_EQ(together.best.radius_multiplier, alone.best.radius_multiplier);
    // The scan's trials differ: a mix-up of the gathered results would move the fit.
    EXPECT_NEAR(together.best.radius_multiplier, 0.43, 0.03);
    world.barrier();
    if (world.is_root()) std::filesystem::remove_all(dir);
  }
}

}  // namespace
}  // namespace ringdem
