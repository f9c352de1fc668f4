// Ring reduction factors (physics.md §2), the tensile-test bookkeeping (load, displacement,
// stopping) and the stage-transition detection on synthetic curves (validation.md §2).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "FileText.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "app/ScenarioRunner.hpp"
#include "app/TensileDriver.hpp"
#include "app/TensileTest.hpp"
#include "domain/RingGenerator.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/Checkpoint.hpp"

namespace ringdem {
namespace {

// Table 3 check of physics.md §2: n_w = 12, r_w = 1.5 mm, r_eq = 4.5 mm, lambda = 0.43 gives
// gamma = 0.372, eta = 1.44, E_b = 288 GPa (the paper calibrated 292 GPa). Tolerances: the
// rounding of the printed values (half a unit of the last digit).
TEST(RingReductionFactors, Table3Check) {
  const RingReductionFactors f = ring_reduction_factors(12, 0.0015, 0.0045, 0.43, 200e9);
  EXPECT_NEAR(f.equivalent_radius, std::sqrt(12.0) * 0.0015, 1e-15);
  EXPECT_NEAR(f.gamma, 0.372, 0.0005);
  EXPECT_NEAR(f.eta, 1.44, 0.005);
  EXPECT_NEAR(f.bond_youngs_modulus, 288e9, 0.5e9);
  // Eq. 14 = Eq. 16: the bond's axial stiffness E_b pi (lambda r_eq)^2 is a fifth of the wires'
  // E pi r_w^2 n_w (to round-off).
  const double bond_axial = f.bond_youngs_modulus * M_PI * std::pow(0.43 * 0.0045, 2);
  const double wires_axial = 200e9 * M_PI * 0.0015 * 0.0015 * 12 / 5.0;
  EXPECT_NEAR(bond_axial / wires_axial, 1.0, 1e-12);
  // Bending reduction eta gamma^4 = gamma^2 / 5.
  EXPECT_NEAR(f.bending_reduction(), f.gamma * f.gamma / 5.0, 1e-15);
}

// 7 and 19 windings follow from the same lambda: E_b scales with n_w (eta = R_eq^2 / (5 (lambda
// r_eq)^2) and R_eq^2 = n_w r_w^2).
TEST(RingReductionFactors, ModulusScalesWithWindings) {
  const double e12 = ring_reduction_factors(12, 0.0015, 0.0045, 0.43, 200e9).bond_youngs_modulus;
  const double e7 = ring_reduction_factors(7, 0.0015, 0.0045, 0.43, 200e9).bond_youngs_modulus;
  const double e19 = ring_reduction_factors(19, 0.0015, 0.0045, 0.43, 200e9).bond_youngs_modulus;
  EXPECT_NEAR(e7 / e12, 7.0 / 12.0, 1e-12);
  EXPECT_NEAR(e19 / e12, 19.0 / 12.0, 1e-12);
  EXPECT_THROW(ring_reduction_factors(0, 0.0015, 0.0045, 0.43, 200e9), std::invalid_argument);
}

const char* kDerivedBondCase = R"(schema_version: 1
simulation: {end_time: 1.0}
materials: [{name: steel}]
bonds:
  - name: ring
    radius_multiplier: 0.43
    derive_from: {windings: 12, wire_diameter: 0.003}
particles:
  rings:
    - {centre: [0, 0, 0], particle_radius: 0.0045}
)";

TEST(CaseLoaderBonds, DeriveFromSetsTheModulus) {
  const CaseConfig c = load_case_from_string(kDerivedBondCase, "derived.yaml");
  const double gamma = 0.43 * 0.0045 / (std::sqrt(12.0) * 0.0015);
  EXPECT_NEAR(c.bonds[0].youngs_modulus / (200e9 / (5 * gamma * gamma)), 1.0, 1e-12);
  EXPECT_EQ(c.bonds[0].derived_particle_radius, 0.0045);
  // The dump leaves youngs_modulus out (derive_from sets it) and loads again to the same case.
  const std::string dumped = dump_case(c);
  EXPECT_EQ(dumped.find("youngs_modulus: 2.88"), std::string::npos) << dumped;
  EXPECT_EQ(dump_case(load_case_from_string(dumped, "derived.yaml")), dumped);
  // The built bond uses the derived modulus.
  const Model m = build_model(c);
  EXPECT_EQ(m.bond_types[0].youngs_modulus, c.bonds[0].youngs_modulus);
}

TEST(CaseLoaderBonds, DeriveFromRejectsAGivenModulusAndMixedRadii) {
  try {
    load_case_from_string(kDerivedBondCase, "derived.yaml", {"bonds.0.youngs_modulus=200e9"});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics.size(), 1u) << e.format();
    EXPECT_EQ(e.diagnostics[0].key_path, "bonds[0].youngs_modulus");
  }
  const std::string two_rings =
      std::string(kDerivedBondCase) + "    - {centre: [1, 0, 0], particle_radius: 0.005}\n";
  try {
    load_case_from_string(two_rings, "derived.yaml");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics.size(), 1u) << e.format();
    EXPECT_EQ(e.diagnostics[0].key_path, "particles.rings[1].particle_radius");
  }
}

TEST(CaseLoaderRings, RingMassSetsTheParticleDensity) {
  const CaseConfig c =
      load_case_from_string(kDerivedBondCase, "derived.yaml", {"particles.rings.0.mass=0.634"});
  const Model m = build_model(c);
  double total = 0.0;
  for (std::size_t k = 0; k < m.particles.n_local(); ++k)
    total += m.particles.mass[k];
  EXPECT_NEAR(total, 0.634, 1e-12);
}

const char* kTensileCase = R"(schema_version: 1
simulation: {end_time: 1.0, gravity: [0, 0, 0]}
materials: [{name: steel}]
bonds: [{name: ring}]
particles:
  rings: [{centre: [0, 0, 0]}]
rigid_bodies:
  - {name: top, shape: cylinder, position: [0, 0, 0.135], axis: [0, 1, 0], radius: 0.015,
     length: 0.1, motion: prescribed}
  - {name: bottom, shape: cylinder, position: [0, 0, -0.135], axis: [0, 1, 0], radius: 0.015,
     length: 0.1}
scenario:
  type: tensile_test
  tensile_test: {moving_bodies: [top], loading_rate: 0.25}
)";

TEST(CaseLoaderTensile, MovingBodiesMustBePrescribedWithoutVelocity) {
  const CaseConfig c = load_case_from_string(kTensileCase, "t.yaml");
  // The model builder knows no scenario; the tensile driver sets the moving pin's velocity.
  Model m = build_model(c);
  EXPECT_EQ(m.bodies[0].velocity, (Vec3{0, 0, 0}));
  TensileDriver(c).prepare_model(m);
  EXPECT_EQ(m.bodies[0].velocity, (Vec3{0, 0, 0.25}));
  EXPECT_EQ(m.bodies[1].velocity, (Vec3{0, 0, 0}));
  EXPECT_EQ(dump_case(load_case_from_string(dump_case(c), "t.yaml")), dump_case(c));
  const std::vector<std::pair<std::string, std::string>> bad{
      {"rigid_bodies.0.motion=fixed", "rigid_bodies[0].motion"},
      {"rigid_bodies.0.velocity=[0,0,1]", "rigid_bodies[0].velocity"},
      {"scenario.tensile_test.moving_bodies=[tpo]", "scenario.tensile_test.moving_bodies[0]"},
      {"scenario.tensile_test.moving_bodies=[]", "scenario.tensile_test.moving_bodies"},
      {"scenario.tensile_test.unload_at=0.5", "scenario.tensile_test.unload_at"},  // >= max
      {"scenario.tensile_test.unload_at=-0.1", "scenario.tensile_test.unload_at"},
  };
  for (const auto& [override_text, key_path] : bad) {
    try {
      load_case_from_string(kTensileCase, "t.yaml", {override_text});
      ADD_FAILURE() << "expected an InputError for " << override_text;
    } catch (const InputError& e) {
      ASSERT_EQ(e.diagnostics.size(), 1u) << e.format();
      EXPECT_EQ(e.diagnostics[0].key_path, key_path) << e.format();
    }
  }
}

RigidBody pin(const std::string& name, const Vec3& position) {
  RigidBody b;
  b.name = name;
  b.shape = RigidShape::kCylinder;
  b.position = position;
  return b;
}

// Load = contact force on the moving pins against the pull direction, summed; displacement =
// their mean travel along it. Hand-computed values.
TEST(TensileMeter, LoadAndDisplacementOfTheMovingPins) {
  std::vector<RigidBody> bodies{pin("left", {-0.1, 0, 0.1}), pin("fixed", {0, 0, -0.1}),
                                pin("right", {0.1, 0, 0.1})};
  const TensileMeter meter(bodies, {"left", "right"}, {0, 0, 2});  // direction is normalised
  bodies[0].force = {500, 0, -1000};  // the ring pulls the moving pins back (down)
  bodies[2].force = {-500, 3, -1500};
  bodies[1].force = {0, 0, 2500};  // not on the moving plate: not counted
  EXPECT_DOUBLE_EQ(meter.load(bodies), 2500.0);
  bodies[0].position.z += 0.010;
  bodies[2].position.z += 0.012;
  bodies[2].position.x += 0.5;  // sideways motion does not count
  EXPECT_NEAR(meter.displacement(bodies), 0.011, 1e-15);
  EXPECT_THROW(TensileMeter(bodies, {"nope"}, {0, 0, 1}), std::invalid_argument);
}

// Failure needs a broken bond and the load below the fraction of the peak; a dip without a
// broken bond (a sliding ring) goes on; the maximum displacement stops the test.
TEST(TensileStopRule, FailureAndMaximumDisplacement) {
  TensileStopRule rule(0.5, 0.1);
  using R = TensileStopRule::Reason;
  EXPECT_EQ(rule.update(0.01, 1000.0, 0), R::kRunning);
  EXPECT_EQ(rule.update(0.02, 4000.0, 0), R::kRunning);
  EXPECT_EQ(rule.update(0.03, 1000.0, 0), R::kRunning);  // dip without failure
  EXPECT_EQ(rule.update(0.04, 5000.0, 1), R::kRunning);  // broke, load still high
  EXPECT_EQ(rule.peak_load(), 5000.0);
  EXPECT_EQ(rule.displacement_at_peak(), 0.04);
  EXPECT_EQ(rule.update(0.05, 2600.0, 1), R::kRunning);  // above half the peak
  EXPECT_EQ(rule.update(0.06, 2400.0, 1), R::kFailure);
  TensileStopRule other(0.5, 0.1);
  EXPECT_EQ(other.update(0.0999, 10.0, 0), R::kRunning);
  EXPECT_EQ(other.update(0.1, 10.0, 0), R::kMaxDisplacement);
}

// Bending stage P = k1 u up to u_t, tensile stage P = k1 u_t + k2 (u - u_t) after it, sampled
// every 0.2 mm with 1 % (of the transition load) noise: the hinge fit finds u_t within one
// sample spacing and both slopes within 2 %.
TEST(TensileCurve, HingeFitFindsTheKneeOfANoisyBilinearCurve) {
  const double k1 = 2e5, k2 = 1.5e7, ut = 0.154;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01 * k1 * ut);
  std::vector<double> u, p;
  for (double x = 0.0; x <= 0.172; x += 2e-4) {
    u.push_back(x);
    p.push_back((x < ut ? k1 * x : k1 * ut + k2 * (x - ut)) + noise(rng));
  }
  // Failure: the load drops after the peak; the analysis ignores everything after it.
  u.push_back(0.1722);
  p.push_back(100.0);
  const TensileCurveAnalysis a = analyse_tensile_curve(u, p);
  ASSERT_TRUE(a.stage_transition_displacement.has_value());
  EXPECT_NEAR(*a.stage_transition_displacement, ut, 2e-4);
  EXPECT_NEAR(a.bending_stage_stiffness / k1, 1.0, 0.02);
  EXPECT_NEAR(a.tensile_stage_stiffness / k2, 1.0, 0.02);
  EXPECT_EQ(a.peak_index, u.size() - 2);
  EXPECT_NEAR(a.peak_load, k1 * ut + k2 * (u[a.peak_index] - ut), 0.05 * k1 * ut);
}

// A smooth knee (the bending stage of a ring stiffens before it becomes taut): the curve
// P = k2 * s * log(1 + exp((u - u_t) / s)) is a softened hinge of width s around u_t. Its
// best hinge fit is symmetric about u_t: the breakpoint lies within s / 2 of it.
TEST(TensileCurve, HingeFitOfASmoothKnee) {
  const double k2 = 1e7, ut = 0.04, width = 0.004;
  std::vector<double> u, p;
  for (double x = 0.0; x <= 0.06; x += 1e-4) {
    u.push_back(x);
    p.push_back(k2 * width * std::log1p(std::exp((x - ut) / width)));
  }
  const TensileCurveAnalysis a = analyse_tensile_curve(u, p);
  ASSERT_TRUE(a.stage_transition_displacement.has_value());
  EXPECT_NEAR(*a.stage_transition_displacement, ut, 0.5 * width);
  EXPECT_GT(a.tensile_stage_stiffness, 10 * a.bending_stage_stiffness);
}

// A straight line has no stage transition a hinge can find with a stiffer second stage
// beyond noise; a curve with no samples reports nothing.
TEST(TensileCurve, NoTransitionOnASofteningCurve) {
  std::vector<double> u, p;
  for (double x = 0.0; x <= 0.05; x += 1e-3) {
    u.push_back(x);
    p.push_back(1e6 * std::sqrt(x));  // softening: every hinge has s2 < s1
  }
  EXPECT_FALSE(analyse_tensile_curve(u, p).stage_transition_displacement.has_value());
  EXPECT_FALSE(analyse_tensile_curve({}, {}).stage_transition_displacement.has_value());
}

// Through the step loop: the 2-pin rig pulled 60 mm at 1 m/s. The ring is in quasi-static
// balance, so the load on the moving pin equals the reaction of the fixed pin along the pull
// direction (1 % of the load, averaged over the last 1000 steps), and the displacement is
// the prescribed travel v t (round-off).
TEST(TensileRig, LoadOnTheMovingPinBalancesTheFixedPin) {
  const CaseConfig c = load_case_from_string(
      kTensileCase, "t.yaml",
      {"scenario.tensile_test.loading_rate=1.0", "damping.global=0.95", "simulation.dt=7.87e-7"});
  const Communicator comm = testing::self_comm();
  Simulation sim(build_scenario_model(c, comm), comm, settings_from_case(c));
  const TensileMeter meter(sim.model().bodies, {"top"}, {0, 0, 1});
  const auto steps = static_cast<std::int64_t>(0.06 / 1.0 / sim.dt());
  sim.run_steps(steps - 1000);
  double load = 0.0, reaction = 0.0;
  for (int k = 0; k < 1000; ++k) {
    sim.step();
    load += meter.load(sim.model().bodies);
    reaction += sim.model().bodies[1].force.z;  // the ring pulls the fixed pin up
  }
  EXPECT_GT(load, 0.0);
  EXPECT_NEAR(reaction / load, 1.0, 0.01);
  EXPECT_NEAR(meter.displacement(sim.model().bodies), 1.0 * sim.time(), 1e-12);
}

// run_tensile_test writes the documented outputs.
TEST(TensileRig, WritesSummaryAndSeries) {
  const CaseConfig c = load_case_from_string(
      kTensileCase, "t.yaml",
      {"scenario.tensile_test.loading_rate=1.0", "scenario.tensile_test.max_displacement=0.004",
       "scenario.tensile_test.record_interval=0.001"});
  const auto dir = std::filesystem::temp_directory_path() /
                   ("ringdem_tensile_outputs_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  TensileRunOptions options;
  options.output_dir = dir.string();
  options.verbose = false;
  const TensileResult r = run_tensile_test(c, options, testing::self_comm());
  EXPECT_EQ(r.stop_reason, TensileStopRule::Reason::kMaxDisplacement);
  EXPECT_NEAR(r.final_displacement, 0.004, 1.0 * r.dt);
  ASSERT_EQ(r.curve.size(), 5u);  // the start and one row per millimetre
  std::ifstream series(dir / "series.csv");
  std::string header;
  std::getline(series, header);
  EXPECT_EQ(header,
            "time_s,displacement_m,load_N,broken_bonds,kinetic_energy_J,bond_energy_J,"
            "plastic_work_J");
  std::stringstream summary;
  summary << std::ifstream(dir / "summary.json").rdbuf();
  for (const char* key :
       {"\"peak_load_N\"", "\"displacement_at_peak_m\"", "\"elongation_at_failure_m\": null",
        "\"first_bond_break_time_s\": null", "\"broken_bonds\": 0",
        "\"stage_transition_displacement_m\"", "\"steps\"", "\"wall_time_s\"",
        "\"particle_steps_per_s\"", "\"stop_reason\": \"max_displacement\""})
    EXPECT_NE(summary.str().find(key), std::string::npos) << key << "\n" << summary.str();
  std::filesystem::remove_all(dir);
}

// Contents of a summary.json without its timings and memory (the lines naming a wall time, a
// rate or the peak memory of the process).
std::string summary_text_without_timings(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, kept;
  while (std::getline(in, line))
    if (line.find("wall_time_s") == std::string::npos &&
        line.find("particle_steps_per_s") == std::string::npos &&
        line.find("memory_largest_rank_bytes") == std::string::npos)
      kept += line + "\n";
  return kept;
}

using testing::file_text;

// A tensile test continued from a checkpoint ends exactly as the run never interrupted: its
// series.csv and summary.json (timings aside) are the same bytes, numbers written with 17
// digits. Checkpoints before and after `event_time` (peak, failure or unloading state, partial
// row sums and the meter's start positions all come from the checkpoint; checkpoints every
// 3.7 mm of travel fall between the rows, every 1 mm, so the sums are not empty). The restarted
// folder holds the whole series.csv of the checkpointed run: the rows after the checkpoint must
// be dropped and written again.
void expect_restarts_bit_for_bit(const std::string& case_text,
                                 const std::vector<std::string>& overrides,
                                 const std::string& folder,
                                 double (*event_time)(const TensileResult&)) {
  const CaseConfig plain = load_case_from_string(case_text, "t.yaml", overrides);
  std::vector<std::string> with_checkpoints = overrides;
  with_checkpoints.push_back("output.checkpoint_interval=0.0037");
  with_checkpoints.push_back("output.checkpoints_kept=100");
  const CaseConfig checkpointed = load_case_from_string(case_text, "t.yaml", with_checkpoints);

  const auto dir =
      std::filesystem::temp_directory_path() / (folder + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  TensileRunOptions quiet;
  quiet.verbose = false;
  quiet.output_dir = (dir / "straight").string();
  const TensileResult straight = run_tensile_test(plain, quiet, testing::self_comm());
  const double event = event_time(straight);

  ScenarioRunOptions run;
  run.verbose = false;
  run.output_dir = (dir / "checkpointed").string();
  {
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(checkpointed);
    ASSERT_EQ(run_scenario(*driver, run, testing::self_comm()), 0);
  }
  // Writing checkpoints does not change the run.
  EXPECT_EQ(file_text(dir / "checkpointed/series.csv"), file_text(dir / "straight/series.csv"));

  // One checkpoint before the event, one after it.
  std::vector<std::string> chosen;
  const auto all = CheckpointStore((dir / "checkpointed/checkpoints").string()).list();
  for (const std::string& path : all)
    if (read_checkpoint_info(path).time < event) chosen = {path};
  for (const std::string& path : all)
    if (read_checkpoint_info(path).time > event) {
      chosen.push_back(path);
      break;
    }
  ASSERT_EQ(chosen.size(), 2u);

  for (const std::string& checkpoint : chosen) {
    SCOPED_TRACE(checkpoint);
    const auto restarted = dir / "restarted";
    std::filesystem::remove_all(restarted);
    std::filesystem::create_directories(restarted);
    std::filesystem::copy_file(dir / "checkpointed/series.csv", restarted / "series.csv");
    run.output_dir = restarted.string();
    run.restart = checkpoint;
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(checkpointed);
    ASSERT_EQ(run_scenario(*driver, run, testing::self_comm()), 0);
    const TensileResult& r = dynamic_cast<const TensileDriver&>(*driver).result();
    EXPECT_EQ(file_text(restarted / "series.csv"), file_text(dir / "straight/series.csv"));
    EXPECT_EQ(summary_text_without_timings(restarted / "summary.json"),
              summary_text_without_timings(dir / "straight/summary.json"));
    EXPECT_EQ(r.stop_reason, straight.stop_reason);
    EXPECT_EQ(r.analysis.peak_load, straight.analysis.peak_load);
    EXPECT_EQ(r.elongation_at_failure, straight.elongation_at_failure);
    EXPECT_EQ(r.residual_displacement, straight.residual_displacement);
    EXPECT_EQ(r.steps, straight.steps);
    EXPECT_EQ(r.curve.size(), straight.curve.size());
  }
  std::filesystem::remove_all(dir);
}

// Checkpoints before and after the first bond broke.
TEST(TensileRestart, ContinuesFromACheckpointBitForBit) {
  expect_restarts_bit_for_bit(
      kTensileCase,
      {"scenario.tensile_test.loading_rate=1.0", "scenario.tensile_test.max_displacement=0.06",
       "scenario.tensile_test.record_interval=0.001", "bonds.0.tensile_strength=2e9"},
      "ringdem_tensile_restart", [](const TensileResult& r) {
        EXPECT_EQ(r.stop_reason, TensileStopRule::Reason::kFailure);
        return r.first_bond_break_time.value_or(-1.0);  // -1: no checkpoint before, fails
      });
}

// The 2-pin rig of kTensileCase with the bond given in full.
std::string tensile_case_with_bond(const std::string& bond) {
  std::string text = kTensileCase;
  const std::string elastic = "bonds: [{name: ring}]";
  text.replace(text.find(elastic), elastic.size(), "bonds: [" + bond + "]");
  return text;
}

const char* kYieldingBond =
    "{name: ring, model: timoshenko_plastic, plastic: {yield_stress: 4e8, hardening_ratio: "
    "0.03, windings: 12, wire_diameter: 0.003}}";

std::vector<std::string> unloading_overrides(double rate) {
  return {fmt::format("scenario.tensile_test.loading_rate={}", rate),
          "scenario.tensile_test.unload_at=0.04", "scenario.tensile_test.record_interval=0.001",
          "damping.global=0.95", "simulation.dt=7.87e-7"};
}

// unload_at: the 2-pin ring (Table 1 bond) is pulled 40 mm into its bending stage at 0.25 m/s and
// the plate driven back until the load is zero. The elastic ring springs back: its residual
// displacement is under 2 % of the 40 mm. What is left is the damped ring lagging behind the
// receding pin, which falls with the rate: 9.3 mm at 1 m/s, 0.31 mm at 0.25 m/s, 0.04 mm at
// 0.1 m/s (measured; the bound leaves room for round-off on other machines, not for a rate). With
// the plastic bond (hinges at M_p = 12 f_y d^3 / 6 = 21.6 N m, f_y = 400 MPa, reached well before
// 40 mm) the ring keeps the shape of its hinges: a residual displacement of more than a quarter of
// the travel.
TEST(TensileUnloading, ElasticRingSpringsBackAPlasticRingKeepsItsElongation) {
  TensileRunOptions quiet;
  quiet.verbose = false;
  const TensileResult elastic =
      run_tensile_test(load_case_from_string(kTensileCase, "t.yaml", unloading_overrides(0.25)),
                       quiet, testing::self_comm());
  const TensileResult plastic =
      run_tensile_test(load_case_from_string(tensile_case_with_bond(kYieldingBond), "t.yaml",
                                             unloading_overrides(0.25)),
                       quiet, testing::self_comm());
  for (const TensileResult* r : {&elastic, &plastic}) {
    EXPECT_EQ(r->stop_reason, TensileStopRule::Reason::kUnloaded);
    ASSERT_TRUE(r->turn_displacement.has_value());
    ASSERT_TRUE(r->residual_displacement.has_value());
    EXPECT_NEAR(*r->turn_displacement, 0.04, 0.25 * r->dt);  // the travel of one step
    EXPECT_EQ(r->broken_bonds, 0);
    EXPECT_LT(r->final_displacement, *r->turn_displacement);
  }
  EXPECT_GE(*elastic.residual_displacement, 0.0);
  EXPECT_LT(*elastic.residual_displacement, 0.02 * 0.04);
  EXPECT_GT(*plastic.residual_displacement, 0.25 * 0.04);
  std::printf("residual displacement after 40 mm: elastic %.4f mm, plastic %.3f mm\n",
              1e3 * *elastic.residual_displacement, 1e3 * *plastic.residual_displacement);
}

// Checkpoints before and after the plate turned (unloading state, the reversed velocity).
TEST(TensileRestart, UnloadingContinuesFromACheckpointBitForBit) {
  expect_restarts_bit_for_bit(tensile_case_with_bond(kYieldingBond), unloading_overrides(1.0),
                              "ringdem_tensile_unload_restart", [](const TensileResult& r) {
                                EXPECT_EQ(r.stop_reason, TensileStopRule::Reason::kUnloaded);
                                const double turn = r.turn_displacement.value_or(-1.0);
                                return turn / 1.0;  // at 1 m/s the time of the turn
                              });
}

}  // namespace
}  // namespace ringdem
