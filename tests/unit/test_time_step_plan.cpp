// The time step and step count that `ringdem check` prints (io/CaseMagnitudes plan_time_steps,
// from the case alone) against the stability limits of the model a run builds (Simulation,
// physics/TimeStep: another code path, over the particles actually created).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "CommandLine.hpp"
#include "TempDir.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/CaseMagnitudes.hpp"

namespace ringdem {
namespace {

void expect_plan_of_the_built_model(const CaseConfig& c) {
  const std::optional<TimeStepPlan> plan = plan_time_steps_with_restraints(c);
  ASSERT_TRUE(plan.has_value());
  const Communicator comm = testing::self_comm();
  const Simulation sim(build_scenario_model(c, comm), comm, settings_from_case(c));
  EXPECT_NEAR(plan->limit, sim.limits().min(), 1e-12 * plan->limit) << plan->limit_what;
  EXPECT_NEAR(plan->dt, sim.dt(), 1e-12 * plan->dt);
  EXPECT_EQ(plan->fixed, c.simulation.dt.has_value());
  EXPECT_NEAR(plan->steps, plan->duration / sim.dt(), 1e-9 * plan->steps);
}

TEST(TimeStepPlan, AFixedStepAndItsLimitAreThoseOfTheBuiltNet) {
  // The tiny rockfall: a fixed 2 us against the net's bonds; a rockfall runs at most its sag,
  // its fall and its duration.
  const CaseConfig c = load_case_from_string(testing::kTinyRockfall, "tiny.yaml");
  expect_plan_of_the_built_model(c);
  const TimeStepPlan plan = *plan_time_steps(c);
  EXPECT_EQ(plan.dt, 2.0e-6);
  EXPECT_FALSE(plan.limit_what.empty());
  EXPECT_EQ(plan.duration_key.rfind("scenario.rockfall.", 0), 0u) << plan.duration_key;
}

TEST(TimeStepPlan, AnAutomaticStepIsTheSafetyTimesTheBuiltModelsLimit) {
  const CaseConfig c =
      load_case_from_string(testing::kTinyRockfall, "tiny.yaml", {"simulation.dt=auto"});
  ASSERT_FALSE(c.simulation.dt.has_value());
  expect_plan_of_the_built_model(c);
}

std::string with_shackles(const char* holding) {
  const std::string plain = "shackles: {n_particles: 12}";
  std::string yaml = testing::kTinyRockfall;
  const std::size_t at = yaml.find(plain);
  EXPECT_NE(at, std::string::npos);
  return yaml.replace(at, plain.size(), fmt::format("shackles: {{n_particles: 12, {}}}", holding));
}

// A stiff brake, or a stiff rope, on the light shackle tori sets a smaller limit than any of the
// net's particles and bonds: the plan takes it, as the run does (its pre-flight limits), and the
// automatic step follows it.
TEST(TimeStepPlan, AStiffBrakeOrRopeSetsTheStepAsInTheRun) {
  for (const char* holding :
       {"brake: {stiffness: 1e13, activation_force: 2000}", "ropes: {axial_stiffness: 1e14}"}) {
    const CaseConfig c =
        load_case_from_string(with_shackles(holding), "tiny.yaml", {"simulation.dt=auto"});
    expect_plan_of_the_built_model(c);
    const TimeStepPlan plan = *plan_time_steps_with_restraints(c);
    const TimeStepPlan particles_only = *plan_time_steps(c);
    EXPECT_LT(plan.limit, 0.5 * particles_only.limit) << holding;
    const bool brake = std::string(holding).rfind("brake", 0) == 0;
    EXPECT_NE(plan.limit_what.find(brake ? "brake limit" : "rope limit"), std::string::npos)
        << plan.limit_what;
  }
  // Soft restraints leave the particles' limit.
  const CaseConfig soft = load_case_from_string(with_shackles("ropes: {axial_stiffness: 1e5}"),
                                                "tiny.yaml", {"simulation.dt=auto"});
  EXPECT_EQ(plan_time_steps_with_restraints(soft)->limit, plan_time_steps(soft)->limit);
  expect_plan_of_the_built_model(soft);
}

// A fixed step above a stiff brake's limit: the loader cannot know that limit and says nothing,
// so `ringdem check` warns of it, with the ratio and the limit the run's pre-flight report
// shows; under it, with an automatic step, or above the net's own limit (the loader's warning)
// it does not.
TEST(TimeStepPlan, AFixedStepAboveARestraintsLimitIsWarnedOf) {
  const std::string stiff = with_shackles("brake: {stiffness: 1e13, activation_force: 2000}");
  const CaseConfig c = load_case_from_string(stiff, "tiny.yaml");
  ASSERT_TRUE(c.simulation.dt.has_value());
  const TimeStepPlan plan = *plan_time_steps_with_restraints(c);
  const Communicator comm = testing::self_comm();
  const Simulation sim(build_scenario_model(c, comm), comm, settings_from_case(c));
  ASSERT_GT(*c.simulation.dt, sim.limits().brake);  // the run's own limit, another code path
  const std::optional<std::string> warning = restraint_step_warning(c, plan);
  ASSERT_TRUE(warning.has_value());
  // The run's limit and ratio, in the loader's words.
  EXPECT_EQ(*warning,
            fixed_step_above_limit(*c.simulation.dt, sim.limits().brake, plan.limit_what));
  EXPECT_NE(warning->find("brake limit"), std::string::npos) << *warning;

  const CaseConfig automatic = load_case_from_string(stiff, "tiny.yaml", {"simulation.dt=auto"});
  EXPECT_FALSE(restraint_step_warning(automatic, *plan_time_steps_with_restraints(automatic)));
  const CaseConfig under = load_case_from_string(
      stiff, "tiny.yaml", {fmt::format("simulation.dt={}", 0.9 * sim.limits().brake)});
  EXPECT_FALSE(restraint_step_warning(under, *plan_time_steps_with_restraints(under)));
  const CaseConfig above_net = load_case_from_string(
      stiff, "tiny.yaml", {fmt::format("simulation.dt={}", 2.0 * plan_time_steps(c)->limit)});
  EXPECT_FALSE(restraint_step_warning(above_net, *plan_time_steps_with_restraints(above_net)));

  // The command prints it as a warning of the case file's simulation.dt, and exits 0.
  const std::string dir = testing::temp_dir("stiff_brake");
  const std::string path = dir + "/stiff_brake.yaml";
  std::ofstream(path) << stiff;
  const testing::CommandResult r =
      testing::run_command(std::string("'") + RINGDEM_BINARY + "' check '" + path + "'");
  std::filesystem::remove_all(dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(path + ": warning: simulation.dt: " + *warning), std::string::npos)
      << r.output;
}

TEST(TimeStepPlan, CheckPrintsIt) {
  const testing::CommandResult r =
      testing::run_command(std::string("'") + RINGDEM_BINARY + "' check '" + RINGDEM_SOURCE_DIR +
                           "/inputs/rockfall/r12.yaml'");
  ASSERT_EQ(r.status, 0) << r.output;
  // Table 1's step against the axial limit of the r12 bond (4.302e-6 s, as the run's
  // pre-flight report prints it); the sag at most 2 s, the fall from 3 m sqrt(2 (3 + 1) / g)
  // + 1 s (the driver's wait for a contact), the impact 0.6 s: 4.503 s, 5 721 789 steps.
  EXPECT_NE(r.output.find(
                "time step: 7.87e-07 s (fixed, 0.183 of the smallest stability "
                "limit, 4.302e-06 s: the bond axial limit of bond 'ring' on particles.nets[0]); "
                "at most 5721789 steps in the 4.503 s the run may last (the rockfall's "
                "phases at their longest)"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace ringdem
