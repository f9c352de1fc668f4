// Errors of the command line that must name what they are about (issue 15, item 9): running out
// of memory names the case file, a folder given as a restart file or to `info` is called a
// folder, a bad --max-walltime quotes the value, `check` reads a sweep file as a study. Each runs
// the ringdem binary.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "CommandLine.hpp"
#include "TempDir.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;
using testing::run_command;

const std::string kBinary = RINGDEM_BINARY;
const std::string kCase = std::string(RINGDEM_SOURCE_DIR) + "/tests/data/restart_net.yaml";

using testing::temp_dir;

TEST(CliErrors, OutOfMemoryNamesTheCaseFile) {
#ifdef __SANITIZE_ADDRESS__
  GTEST_SKIP() << "AddressSanitizer needs far more address space than the limit set here, and "
                  "its allocator reports running out of memory itself";
#endif
  // 8 million spheres need about 3 GB; with the address space limited to 1 GB the build runs
  // out of memory within a second.
  const std::string dir = temp_dir("cli_oom");
  const std::string case_path = dir + "/big.yaml";
  std::ofstream(case_path) << R"(schema_version: 1
simulation: {end_time: 1.0e-4}
materials:
  - {name: rock, density: 2600, youngs_modulus: 30.0e9}
particles:
  lattices:
    - {origin: [0, 0, 0], count: [200, 200, 200], spacing: 0.02, particle_radius: 0.005, material: rock}
)";
  const testing::CommandResult r = run_command(
      fmt::format("ulimit -v 1000000 && '{}' run '{}' -o '{}/out' -q", kBinary, case_path, dir));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("out of memory (std::bad_alloc) while running " + case_path),
            std::string::npos)
      << r.output;
  fs::remove_all(dir);
}

TEST(CliErrors, FolderAsRestartFileIsCalledAFolder) {
  const std::string dir = temp_dir("cli_restart_dir");
  const testing::CommandResult r = run_command(
      fmt::format("'{}' run '{}' -o '{}/out' -q --restart '{}'", kBinary, kCase, dir, dir));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(dir + ": error: --restart: is a directory, not a checkpoint file"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("not an HDF5 file"), std::string::npos) << r.output;

  const testing::CommandResult info = run_command(fmt::format("'{}' info '{}'", kBinary, dir));
  EXPECT_EQ(info.status, 2) << info.output;
  EXPECT_NE(info.output.find(dir + ": is a directory, not an HDF5 file"), std::string::npos)
      << info.output;
  fs::remove_all(dir);
}

TEST(CliErrors, BadMaxWalltimeQuotesTheValue) {
  const std::string dir = temp_dir("cli_walltime");
  for (const std::string value : {"ten", "1e999"}) {
    const testing::CommandResult r = run_command(
        fmt::format("'{}' run '{}' -o '{}/out' -q --max-walltime {}", kBinary, kCase, dir, value));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--max-walltime: '" + value + "'"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("stod"), std::string::npos) << r.output;
  }
  fs::remove_all(dir);
}

TEST(CliErrors, CheckValidatesASweepWithEachOfItsCases) {
  // A sweep file given to `check` is read as a study, not as a case (which reported its keys
  // as unknown and the case's sections as missing): every case is loaded, and a bad value is
  // reported where the sweep gives it, with its case.
  const std::string sweeps = std::string(RINGDEM_SOURCE_DIR) + "/inputs/sweeps/";
  const testing::CommandResult good =
      run_command(fmt::format("'{}' check '{}plastic_hardening.yaml'", kBinary, sweeps));
  EXPECT_EQ(good.status, 0) << good.output;
  // The file zips four values of each of its two parameters.
  EXPECT_NE(good.output.find("plastic_hardening.yaml: valid sweep (4 cases of "), std::string::npos)
      << good.output;
  EXPECT_NE(good.output.find("ring4_plastic.yaml, 2 parameters, combine: zip)"), std::string::npos)
      << good.output;

  const std::string dir = temp_dir("cli_check_sweep");
  const std::string sweep = dir + "/s.yaml";
  std::ofstream(sweep) << "schema_version: 1\ncase: " << RINGDEM_SOURCE_DIR
                       << "/inputs/tensile/ring4_plastic.yaml\nparameters:\n"
                          "  - key: bonds.0.plastic.hardening_ratio\n"
                          "    values: [0.05, -1]\n";
  const testing::CommandResult bad = run_command(fmt::format("'{}' check '{}'", kBinary, sweep));
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(
      bad.output.find(sweep + ":5:20: error: bonds[0].plastic.hardening_ratio: must be in [0, 1), "
                              "got -1 (in case_001: bonds.0.plastic.hardening_ratio=-1)"),
      std::string::npos)
      << bad.output;
  fs::remove_all(dir);
}

TEST(CliErrors, OnlyTheFirstLaunchedProcessPrintsTheParsersText) {
  // The command line is parsed before MPI starts; under mpirun every rank printed the same help
  // or parse error. The rank comes from the launcher's environment: the first prints, the others
  // exit with the same status in silence. Each command starts outside any launcher, whatever
  // MPI this test process started before (in a run of the whole binary, earlier tests did).
  const std::string clean = testing::without_launcher_environment();
  const std::string bogus = fmt::format("'{}' run '{}' --bogus", kBinary, kCase);
  const std::string expected = "The following argument was not expected: --bogus";
  for (const std::string launcher :
       {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"}) {
    const testing::CommandResult first =
        run_command(fmt::format("{} {}=0 {}", clean, launcher, bogus));
    EXPECT_EQ(first.status, 2) << launcher << ": " << first.output;
    EXPECT_NE(first.output.find(expected), std::string::npos) << launcher << ": " << first.output;
    const testing::CommandResult other =
        run_command(fmt::format("{} {}=3 {}", clean, launcher, bogus));
    EXPECT_EQ(other.status, 2) << launcher << ": " << other.output;
    EXPECT_EQ(other.output, "") << launcher;
  }
  const testing::CommandResult help =
      run_command(fmt::format("{} OMPI_COMM_WORLD_RANK=1 '{}' run --help", clean, kBinary));
  EXPECT_EQ(help.status, 0) << help.output;
  EXPECT_EQ(help.output, "");
  const testing::CommandResult walltime = run_command(fmt::format(
      "{} OMPI_COMM_WORLD_RANK=1 '{}' run '{}' --max-walltime ten", clean, kBinary, kCase));
  EXPECT_EQ(walltime.status, 2) << walltime.output;
  EXPECT_EQ(walltime.output, "");

  // `info` and `check` answer from the first process only.
  const std::string check = fmt::format("'{}' check '{}'", kBinary, kCase);
  const testing::CommandResult checked_first =
      run_command(fmt::format("{} OMPI_COMM_WORLD_RANK=0 {}", clean, check));
  EXPECT_EQ(checked_first.status, 0) << checked_first.output;
  EXPECT_NE(checked_first.output.find(": valid ("), std::string::npos) << checked_first.output;
  const testing::CommandResult checked_other =
      run_command(fmt::format("{} OMPI_COMM_WORLD_RANK=1 {}", clean, check));
  EXPECT_EQ(checked_other.status, 0) << checked_other.output;
  EXPECT_EQ(checked_other.output, "");

  // A real job of 2 ranks prints its help once.
  const testing::CommandResult job =
      run_command(fmt::format("{} OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                              "OMPI_MCA_rmaps_base_oversubscribe=1 mpirun -np 2 '{}' run --help",
                              clean, kBinary));
  EXPECT_EQ(job.status, 0) << job.output;
  EXPECT_EQ(testing::occurrences(job.output, "Usage:"), 1u) << job.output;
}

}  // namespace
}  // namespace ringdem
