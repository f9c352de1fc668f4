#pragma once

// Running the ringdem binary (or any command) from a test: in the foreground with its output
// captured, or in the background to be signalled and waited for.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace ringdem::testing {

struct CommandResult {
  int status = -1;     ///< exit code; -1 if the command did not exit normally
  std::string output;  ///< stdout and stderr together
};

/// Runs `command` with /bin/sh, stderr merged into stdout.
inline CommandResult run_command(const std::string& command) {
  CommandResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("popen failed: " + command);
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr)
    r.output += buffer;
  const int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

/// An `env -u NAME ...` prefix that removes from a command's environment every variable a
/// launcher or an MPI singleton sets (OMPI_*, PMIX_*, PMI_*, ORTE_*, OPAL_*, SLURM_*). A test
/// process that has initialised MPI on its own (testing::self_comm) carries its singleton's
/// server address and rank there; an `mpirun` started beneath it with them takes itself for a
/// process of that job and fails, and a command meant to run outside any launcher would not.
inline std::string without_launcher_environment() {
  std::string prefix = "env";
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string text(*entry);
    const std::string name = text.substr(0, text.find('='));
    for (const char* launcher_prefix : {"OMPI_", "PMIX_", "PMI_", "ORTE_", "OPAL_", "SLURM_"}) {
      if (name.rfind(launcher_prefix, 0) == 0) {
        prefix += " -u " + name;
        break;
      }
    }
  }
  return prefix;
}

/// How many times `needle` occurs in a command's `output` (a line printed once per rank, say).
inline std::size_t occurrences(const std::string& output, const std::string& needle) {
  std::size_t count = 0;
  for (std::size_t at = output.find(needle); at != std::string::npos;
       at = output.find(needle, at + 1))
    ++count;
  return count;
}

/// Starts `argv` (argv[0] the program path) in the background, stdout and stderr to `log`.
/// Returns its pid.
inline pid_t spawn(const std::vector<std::string>& argv, const std::string& log) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    std::vector<char*> args;
    for (const std::string& a : argv)
      args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  return pid;
}

/// Waits for `pid`; its exit code, or 128 + the signal that ended it.
inline int wait_for(pid_t pid) {
  int raw = 0;
  if (waitpid(pid, &raw, 0) != pid) return -1;
  if (WIFEXITED(raw)) return WEXITSTATUS(raw);
  if (WIFSIGNALED(raw)) return 128 + WTERMSIG(raw);
  return -1;
}

/// A process started by spawn(): killed and reaped on destruction unless waited for, so that a
/// failed assertion does not leave it running.
class BackgroundProcess {
 public:
  BackgroundProcess(const std::vector<std::string>& argv, const std::string& log)
      : pid_(spawn(argv, log)) {}
  BackgroundProcess(const BackgroundProcess&) = delete;
  BackgroundProcess& operator=(const BackgroundProcess&) = delete;
  ~BackgroundProcess() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  pid_t pid() const { return pid_; }
  /// Its exit code, or 128 + the signal that ended it.
  int wait() {
    const int code = wait_for(pid_);
    pid_ = 0;
    return code;
  }

 private:
  pid_t pid_;
};

}  // namespace ringdem::testing
