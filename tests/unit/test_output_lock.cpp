// The output folder's lock (issue 15, item 4), with real ringdem processes: a second run into a
// folder in use is refused naming the first (host, pid, start time) and exits with code 2; the
// lock is released on SIGUSR1 (exit 3) so that --restart auto continues, and on SIGTERM; a lock
// left by a killed run of this host is taken over; one of another host only with --break-lock;
// a folder that cannot be written is refused before anything is built.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "CommandLine.hpp"
#include "TempDir.hpp"
#include "app/OutputLock.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;
using testing::run_command;

using testing::temp_dir;

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string host_name() {
  char buffer[256] = {};
  gethostname(buffer, sizeof buffer - 1);
  return buffer;
}

/// A pid that belonged to a process of this host that has ended (a reaped child).
pid_t dead_pid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  testing::wait_for(pid);
  return pid;
}

/// Waits up to 30 s until `path` exists and holds `text`.
bool wait_for_text(const std::string& path, const std::string& text) {
  for (int k = 0; k < 3000; ++k) {
    if (read_file(path).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

const std::string kLockBinary = RINGDEM_BINARY;
const std::string kLockCase = std::string(RINGDEM_SOURCE_DIR) + "/tests/data/restart_net.yaml";

/// `ringdem run` of the restart test case into `out`, `extra` appended, in the foreground.
testing::CommandResult run_into(const std::string& out, const std::string& extra = "") {
  return run_command(fmt::format("'{}' run '{}' -o '{}' -q --set simulation.end_time=2e-5 {}",
                                 kLockBinary, kLockCase, out, extra));
}

TEST(OutputLock, SecondRunIsRefusedAndRestartTakesTheLockAfterTheFirstEnded) {
  const std::string dir = temp_dir("lock_two_runs");
  const std::string out = dir + "/out";
  const std::string lock_file = out + "/" + OutputLock::kFileName;
  // The first run: long enough to be running while the second starts; stopped by SIGUSR1.
  testing::BackgroundProcess first_run(
      {kLockBinary, "run", kLockCase, "-o", out, "-q", "--set", "simulation.end_time=0.02"},
      dir + "/first.log");
  const pid_t first = first_run.pid();
  ASSERT_TRUE(wait_for_text(lock_file, fmt::format("pid: {}\n", first))) << read_file(lock_file);
  const LockHolder holder = LockHolder::parse(read_file(lock_file));
  EXPECT_EQ(holder.host, host_name());
  EXPECT_FALSE(holder.start_time.empty());
  EXPECT_NE(holder.command.find("-o " + out), std::string::npos) << holder.command;

  const testing::CommandResult second = run_command(fmt::format(
      "'{}' run '{}' -o '{}' -q --set simulation.end_time=0.02", kLockBinary, kLockCase, out));
  EXPECT_EQ(second.status, 2) << second.output;
  EXPECT_NE(second.output.find(fmt::format("pid {} on host {}, started {}", first, host_name(),
                                           holder.start_time)),
            std::string::npos)
      << second.output;
  EXPECT_EQ(second.output.find("pre-flight"), std::string::npos) << "refused before the build";

  kill(first, SIGUSR1);
  EXPECT_EQ(first_run.wait(), 3) << read_file(dir + "/first.log");
  EXPECT_FALSE(fs::exists(lock_file)) << "released on the checkpointed stop";
  // What the SLURM script does next: the same command with --restart auto.
  const testing::CommandResult restart = run_command(
      fmt::format("'{}' run '{}' -o '{}' -q --set simulation.end_time=0.02 --restart auto",
                  kLockBinary, kLockCase, out));
  EXPECT_EQ(restart.status, 0) << restart.output;
  EXPECT_TRUE(fs::exists(out + "/summary.json"));
  EXPECT_FALSE(fs::exists(lock_file)) << "released at the end";
  fs::remove_all(dir);
}

TEST(OutputLock, SigtermRemovesTheLockFile) {
  const std::string dir = temp_dir("lock_sigterm");
  const std::string out = dir + "/out";
  const std::string lock_file = out + "/" + OutputLock::kFileName;
  testing::BackgroundProcess run({kLockBinary, "run", kLockCase, "-o", out, "-q"},
                                 dir + "/run.log");
  ASSERT_TRUE(wait_for_text(lock_file, fmt::format("pid: {}\n", run.pid())));
  kill(run.pid(), SIGTERM);
  EXPECT_EQ(run.wait(), 128 + SIGTERM);
  EXPECT_FALSE(fs::exists(lock_file));
  fs::remove_all(dir);
}

TEST(OutputLock, StaleLockOfThisHostIsTakenOver) {
  const std::string dir = temp_dir("lock_stale");
  LockHolder killed;
  killed.host = host_name();
  killed.pid = dead_pid();
  killed.start_time = "2020-01-01T00:00:00+0000";
  killed.command = "ringdem run killed.yaml";
  std::ofstream(dir + "/" + OutputLock::kFileName) << killed.text();
  const testing::CommandResult r = run_into(dir);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("taking over the stale lock"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(killed.describe()), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/" + OutputLock::kFileName));

  // The pid of a live process, but not the process that wrote the lock (its start differs):
  // stale too. This test process stands in for the later process that got the pid.
  LockHolder reused = LockHolder::self();
  reused.process_start += 1;
  std::ofstream(dir + "/" + OutputLock::kFileName) << reused.text();
  const testing::CommandResult again = run_into(dir);
  EXPECT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("stale"), std::string::npos) << again.output;

  // The same live process: the file system did not keep the flock, so the text decides.
  const LockHolder alive = LockHolder::self();
  std::ofstream(dir + "/" + OutputLock::kFileName) << alive.text();
  const testing::CommandResult refused = run_into(dir);
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find(alive.describe()), std::string::npos) << refused.output;
  fs::remove_all(dir);
}

TEST(OutputLock, LockOfAnotherHostNeedsBreakLock) {
  const std::string dir = temp_dir("lock_foreign");
  LockHolder other;
  other.host = "ringdem-test-other-host";
  other.pid = 4242;
  other.start_time = "2020-01-01T00:00:00+0000";
  other.command = "ringdem run far.yaml";
  std::ofstream(dir + "/" + OutputLock::kFileName) << other.text();
  const testing::CommandResult refused = run_into(dir);
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find(other.describe()), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--break-lock"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(dir + "/series.csv")) << "nothing written";

  const testing::CommandResult forced = run_into(dir, "--break-lock");
  EXPECT_EQ(forced.status, 0) << forced.output;
  EXPECT_NE(forced.output.find("--break-lock: taking over the lock of " + other.describe()),
            std::string::npos)
      << forced.output;
  EXPECT_TRUE(fs::exists(dir + "/summary.json"));
  fs::remove_all(dir);
}

TEST(OutputLock, UnwritableFolderIsRefusedBeforeTheRun) {
  // A folder without write permission; root may write anywhere, so it gets /proc/self, a folder
  // where no file can be created.
  const std::string dir = temp_dir("lock_readonly");
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  const std::string out = access(dir.c_str(), W_OK) == 0 ? "/proc/self" : dir;
  const testing::CommandResult r = run_command(fmt::format(
      "'{}' run '{}' -o '{}' --set simulation.end_time=1.0", kLockBinary, kLockCase, out));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(out + ": error: the output folder is not writable"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("pre-flight"), std::string::npos) << "refused before the build";
  fs::permissions(dir, fs::perms::owner_all);
  fs::remove_all(dir);
}

TEST(OutputLock, HolderTextRoundTrips) {
  const LockHolder me = LockHolder::self();
  EXPECT_EQ(me.pid, static_cast<long>(getpid()));
  EXPECT_GT(me.process_start, 0) << "from /proc/self/stat";
  const LockHolder back = LockHolder::parse(me.text());
  EXPECT_EQ(back.host, me.host);
  EXPECT_EQ(back.pid, me.pid);
  EXPECT_EQ(back.process_start, me.process_start);
  EXPECT_EQ(back.start_time, me.start_time);
  EXPECT_EQ(back.command, me.command);
}

}  // namespace
}  // namespace ringdem
