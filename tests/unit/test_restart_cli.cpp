// `ringdem run` as a user runs it (issue 15, items 2, 3 and 7): a restart compares the case
// with the one the checkpoint was written by and refuses, naming the keys, what it may not take
// over; with --allow-changes it applies what it can (time step, damping) and says so; a start
// with particles that overlap is refused naming both, unless the case allows it. Each test runs
// the CLI binary on a ring of 100 bonded particles falling towards a floor, with one sphere,
// for 20 steps of 1 us (checkpoints after 10 and 20 steps).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "FileText.hpp"
#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTrustCase = R"(schema_version: 1
name: trust
simulation: {dt: 1.0e-6, end_time: 2.0e-5, gravity: [0, 0, -9.81]}
materials: [{name: steel}]
bonds: [{name: ring, youngs_modulus: 210e9}]
damping: {global: 0.1}
particles:
  rings: [{centre: [0, 0, 0.2], normal: [0, 0, 1], velocity: [0, 0, -1]}]
  spheres: [{position: [0, 0, 0.1], radius: 0.01, velocity: [1, 0, 0]}]
rigid_bodies: [{name: floor, shape: plane, material: steel}]
output: {checkpoint_interval: 1.0e-5, checkpoints_kept: 10}
)";

using testing::file_text;

/// A number of summary.json ("key": value).
double summary_number(const fs::path& summary, const std::string& key) {
  const std::string text = file_text(summary);
  std::smatch m;
  if (!std::regex_search(text, m, std::regex("\"" + key + "\": ([-0-9.eE+]+)")))
    throw std::runtime_error(key + " not in " + summary.string());
  return std::stod(m[1].str());
}

class RestartCli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "ringdem_restart_cli_XXXXXX").string();
    ASSERT_NE(mkdtemp(templ.data()), nullptr);
    dir_ = templ;
    case_ = dir_ / "trust.yaml";
    std::ofstream(case_) << kTrustCase;
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Runs `ringdem run CASE -o OUT ARGS`; returns the exit code, fills out_ and err_.
  int run(const std::string& out, const std::string& args) {
    const std::string binary = RINGDEM_BINARY;
    const fs::path o = dir_ / "stdout.txt", e = dir_ / "stderr.txt";
    const std::string command = "'" + binary + "' run '" + case_.string() + "' -o '" +
                                (dir_ / out).string() + "' " + args + " > '" + o.string() +
                                "' 2> '" + e.string() + "'";
    const int status = std::system(command.c_str());
    out_ = file_text(o);
    err_ = file_text(e);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  /// A first run to the end, with checkpoints after 10 and 20 steps.
  std::string checkpoint_after_10_steps() {
    EXPECT_EQ(run("out", "-q"), 0) << err_;
    const fs::path c = dir_ / "out/checkpoints/checkpoint_000000000010.h5";
    EXPECT_TRUE(fs::exists(c));
    return "--restart '" + c.string() + "'";
  }
  bool err_has(const std::string& words) const { return err_.find(words) != std::string::npos; }
  bool out_has(const std::string& words) const { return out_.find(words) != std::string::npos; }

  fs::path dir_, case_;
  std::string out_, err_;
};

TEST_F(RestartCli, CheckpointOfAnotherBondModulusIsRefusedNamingTheKey) {
  const std::string restart = checkpoint_after_10_steps();
  // The same counts of particles, bonds and bodies: only the modulus differs.
  EXPECT_EQ(run("out", restart + " -q --set bonds.0.youngs_modulus=292e9"), 2) << out_ << err_;
  EXPECT_TRUE(err_has("bonds[ring].youngs_modulus: 2.1e11 in the checkpoint, 2.92e11 in the case"))
      << err_;
  // Not even with --allow-changes: the bonds' stiffness is part of the saved state.
  EXPECT_EQ(run("out", restart + " -q --allow-changes --set bonds.0.youngs_modulus=292e9"), 2);
  EXPECT_TRUE(err_has("cannot be applied to the saved state")) << err_;
}

TEST_F(RestartCli, MovedRingIsRefusedEvenWithAllowChanges) {
  const std::string restart = checkpoint_after_10_steps();
  EXPECT_EQ(run("out", restart + " -q --allow-changes --set particles.rings.0.centre=[0,0,0.3]"), 2)
      << out_ << err_;
  EXPECT_TRUE(err_has("particles.rings[0].centre: [0, 0, 0.2] in the checkpoint, [0, 0, 0.3]"))
      << err_;
}

TEST_F(RestartCli, LaterEndTimeIsTakenAndListed) {
  const std::string restart = checkpoint_after_10_steps();
  ASSERT_EQ(run("out", restart + " --set simulation.end_time=3e-5"), 0) << out_ << err_;
  EXPECT_TRUE(out_has("simulation.end_time: 2e-5 -> 3e-5")) << out_;
  EXPECT_TRUE(out_has("time step 1e-06 s (fixed, from the checkpoint)")) << out_;
  EXPECT_EQ(summary_number(dir_ / "out/summary.json", "steps"), 30.0);
}

TEST_F(RestartCli, ChangedTimeStepNeedsAllowChangesAndIsApplied) {
  const std::string restart = checkpoint_after_10_steps();
  EXPECT_EQ(run("out", restart + " -q --set simulation.dt=5e-7"), 2) << out_ << err_;
  EXPECT_TRUE(err_has("simulation.dt: 1e-6 in the checkpoint, 5e-7 in the case")) << err_;
  EXPECT_TRUE(err_has("--allow-changes")) << err_;

  ASSERT_EQ(run("out", restart + " --allow-changes --set simulation.dt=5e-7"), 0) << err_;
  EXPECT_TRUE(out_has("simulation.dt: 1e-6 -> 5e-7")) << out_;
  EXPECT_TRUE(out_has("time step 5e-07 s (fixed, changed on restart from 1e-06 s)")) << out_;
  // 10 steps of 1 us, then (2e-5 - 1e-5) / 5e-7 = 20 steps of the new dt to the same end time.
  const fs::path summary = dir_ / "out/summary.json";
  EXPECT_EQ(summary_number(summary, "dt_s"), 5e-7);
  EXPECT_EQ(summary_number(summary, "steps"), 30.0);
  EXPECT_NEAR(summary_number(summary, "end_time_s"), 2e-5, 1e-15);
}

TEST_F(RestartCli, ChangedDampingIsAppliedFromTheRestartOn) {
  const std::string restart = checkpoint_after_10_steps();
  ASSERT_EQ(run("same", restart), 0) << err_;
  const double unchanged = summary_number(dir_ / "same/summary.json", "final_kinetic_energy_J");
  EXPECT_EQ(run("damped", restart + " -q --set damping.global=0.6"), 2);
  EXPECT_TRUE(err_has("damping.global: 0.1 in the checkpoint, 0.6 in the case")) << err_;
  ASSERT_EQ(run("damped", restart + " --allow-changes --set damping.global=0.6"), 0) << err_;
  EXPECT_TRUE(out_has("damping.global: 0.1 -> 0.6")) << out_;
  const double damped = summary_number(dir_ / "damped/summary.json", "final_kinetic_energy_J");

  // The same change made in memory (library API): 10 steps, coefficient 0.6, 10 steps.
  const CaseConfig c = load_case_from_string(kTrustCase, "trust.yaml");
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  sim.run_steps(10);
  for (std::size_t g = 0; g < sim.model().group_names.size(); ++g)
    sim.set_group_damping(static_cast<int>(g), 0.6);
  sim.run_steps(10);
  const double expected = sim.energies().kinetic;
  EXPECT_NE(damped, unchanged);
  // A restart continues bit for bit, so the change lands at the same step: the same bits.
  EXPECT_EQ(damped, expected);
}

// What scripts/slurm/ringdem.sbatch does: an edited case resubmitted into the same folder with
// --restart auto is refused, not continued from the old state (nor from an older checkpoint).
TEST_F(RestartCli, EditedCaseIsRefusedByRestartAuto) {
  checkpoint_after_10_steps();
  const std::string before = file_text(dir_ / "out/summary.json");
  EXPECT_EQ(run("out", "--restart auto -q --set materials.0.density=7000"), 2) << out_ << err_;
  EXPECT_TRUE(err_has("materials[steel].density: 7800 in the checkpoint, 7000 in the case"))
      << err_;
  EXPECT_FALSE(fs::exists(dir_ / "out/checkpoints/checkpoint_000000000030.h5"));
  EXPECT_EQ(file_text(dir_ / "out/summary.json"), before);
}

TEST_F(RestartCli, SphereInsideTheRingIsRefusedNamingBothParticles) {
  // The sphere (gid 100) centred 5 mm above ring particle 0 (gid 0, at x = 0.1545 m).
  const std::string overlap = " -q --set particles.spheres.0.position=[0.1545,0,0.205]";
  EXPECT_EQ(run("out", overlap), 2) << out_ << err_;
  EXPECT_TRUE(err_has("3 contacts overlap at the start")) << err_;
  EXPECT_TRUE(
      err_has("particle 0 (group rings, at (0.1545, 0, 0.2), radius 0.0045 m) and "
              "particle 100 (group spheres, at (0.1545, 0, 0.205), radius 0.01 m) "
              "overlap by 0.0095 m"))
      << err_;
  // Allowed, the overlap is not refused; this one is so deep (9.5 mm of a 4.5 mm particle)
  // that the divergence guard then stops the run in its first step (exit 1), naming it.
  EXPECT_EQ(run("out2", overlap + " --set simulation.allow_initial_overlap=true"), 1) << err_;
  EXPECT_FALSE(err_has("overlap at the start")) << err_;
  EXPECT_TRUE(err_has("the run diverged at step 1")) << err_;
  // A shallow allowed overlap (0.5 mm) runs to the end.
  EXPECT_EQ(run("out3",
                " -q --set particles.spheres.0.position=[0.1545,0,0.214] --set "
                "simulation.allow_initial_overlap=true"),
            0)
      << err_;
}

TEST_F(RestartCli, SphereInTheFloorIsRefused) {
  const std::string overlap = " -q --set particles.spheres.0.position=[0.5,0,0.005]";
  EXPECT_EQ(run("out", overlap), 2) << out_ << err_;
  EXPECT_TRUE(
      err_has("particle 100 (group spheres, at (0.5, 0, 0.005), radius 0.01 m) and "
              "rigid body 'floor'"))
      << err_;
  EXPECT_TRUE(err_has("overlap by 0.005 m, 50 % of the smaller radius")) << err_;
  // Within a tolerance raised above 50 %, it runs.
  EXPECT_EQ(run("out", overlap + " --set simulation.initial_overlap_tolerance=0.6"), 0) << err_;
}

}  // namespace
}  // namespace ringdem
