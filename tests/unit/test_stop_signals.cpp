// Ctrl-C, kill and scancel during a run (app/StopSignals), with real ringdem processes: the first
// SIGTERM (or SIGINT, SIGHUP) writes a checkpoint at the next step and ends the run with
// 128 + the signal, its lock released, and --restart auto continues it to the same bits as a
// run never interrupted; a second signal ends the process at once, without a checkpoint, and
// still removes the lock.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

#include "CommandLine.hpp"
#include "FileText.hpp"
#include "TempDir.hpp"
#include "app/OutputLock.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

const std::string kStopBinary = RINGDEM_BINARY;
const std::string kStopCase = std::string(RINGDEM_SOURCE_DIR) + "/tests/data/restart_net.yaml";

/// Waits up to 60 s until the run writing into `out` has stepped: its series.csv has the
/// header and two rows (t = 0 and 1 ms), which the driver writes after the run's controls
/// (and so the signal handling) are in place.
bool wait_until_stepping(const std::string& out) {
  for (int k = 0; k < 6000; ++k) {
    std::ifstream in(out + "/series.csv");
    int lines = 0;
    for (std::string line; std::getline(in, line);)
      ++lines;
    if (lines >= 3) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

/// A run of the restart net for a simulated second (far longer than the test waits).
testing::BackgroundProcess long_run(const std::string& out, const std::string& log) {
  return testing::BackgroundProcess(
      {kStopBinary, "run", kStopCase, "-o", out, "-q", "--set", "simulation.end_time=1"}, log);
}

TEST(StopSignals, SigtermWritesACheckpointAndTheRestartEndsAsAnUninterruptedRun) {
  const std::string dir = testing::temp_dir("stop_sigterm");
  const std::string out = dir + "/split";
  testing::BackgroundProcess run = long_run(out, dir + "/run.log");
  ASSERT_TRUE(wait_until_stepping(out)) << testing::file_text(dir + "/run.log");
  kill(run.pid(), SIGTERM);
  EXPECT_EQ(run.wait(), 128 + SIGTERM) << testing::file_text(dir + "/run.log");
  EXPECT_FALSE(fs::exists(out + "/" + OutputLock::kFileName));
  const std::string log = testing::file_text(dir + "/run.log");
  std::smatch stop;
  ASSERT_TRUE(std::regex_search(
      log, stop, std::regex(R"(stop requested \(SIGTERM\): checkpoint \S+ at t = (\S+) s)")))
      << log;
  EXPECT_FALSE(fs::exists(out + "/summary.json")) << "the run stopped before its end";

  // --restart auto continues from that checkpoint; end_time may change on a restart, so the
  // continuation is short. It must end as a run to the same time that was never stopped.
  const std::string end_time = fmt::format("{:.6g}", std::stod(stop[1].str()) + 1.5e-3);
  const testing::CommandResult restart = testing::run_command(
      fmt::format("'{}' run '{}' -o '{}' -q --set simulation.end_time={} --restart auto",
                  kStopBinary, kStopCase, out, end_time));
  ASSERT_EQ(restart.status, 0) << restart.output;
  const testing::CommandResult straight = testing::run_command(
      fmt::format("'{}' run '{}' -o '{}/straight' -q --set simulation.end_time={}", kStopBinary,
                  kStopCase, dir, end_time));
  ASSERT_EQ(straight.status, 0) << straight.output;
  EXPECT_EQ(testing::file_text(out + "/series.csv"),
            testing::file_text(dir + "/straight/series.csv"));
  fs::remove_all(dir);
}

TEST(StopSignals, ASecondSignalEndsTheRunAtOnceAndRemovesTheLock) {
  const std::string dir = testing::temp_dir("stop_twice");
  const std::string out = dir + "/out";
  testing::BackgroundProcess run = long_run(out, dir + "/run.log");
  ASSERT_TRUE(wait_until_stepping(out)) << testing::file_text(dir + "/run.log");
  // Two different signals, so that the second is not merged into the first while pending.
  kill(run.pid(), SIGINT);
  kill(run.pid(), SIGTERM);
  const int code = run.wait();
  EXPECT_TRUE(code == 128 + SIGINT || code == 128 + SIGTERM) << code;
  const std::string log = testing::file_text(dir + "/run.log");
  EXPECT_EQ(log.find("stop requested"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out + "/checkpoints")) << "no checkpoint: the case writes none by 1 s";
  EXPECT_FALSE(fs::exists(out + "/" + OutputLock::kFileName));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ringdem
