#include "app/OutputLock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <system_error>
#include <utility>

#include "app/StopSignals.hpp"
#include "io/InputError.hpp"

namespace ringdem {

namespace {

// ---- removal of the lock files on SIGINT, SIGTERM, SIGHUP ---------------------------------------
// What a terminating signal runs before it ends the process (app/StopSignals): async-signal-safe
// calls only, so it unlinks the registered paths from fixed buffers. A sweep holds two locks at
// once (the study's folder and the case's), hence a few slots.

constexpr std::size_t kSlots = 8;
constexpr std::size_t kPathMax = 4096;
char g_paths[kSlots][kPathMax];
volatile std::sig_atomic_t g_used[kSlots] = {};

void remove_registered_locks() {
  for (std::size_t k = 0; k < kSlots; ++k)
    if (g_used[k]) ::unlink(g_paths[k]);
}

void register_path(const std::string& path) {
  if (path.size() >= kPathMax) return;  // not removed on a signal; the next run finds it stale
  set_termination_cleanup(remove_registered_locks);
  for (std::size_t k = 0; k < kSlots; ++k) {
    if (g_used[k]) continue;
    std::memcpy(g_paths[k], path.c_str(), path.size() + 1);
    g_used[k] = 1;
    return;
  }
}

void unregister_path(const std::string& path) {
  for (std::size_t k = 0; k < kSlots; ++k)
    if (g_used[k] && path == g_paths[k]) g_used[k] = 0;
}

// ---- this process and others ----------------------------------------------------------------

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof buffer - 1) != 0) return "unknown";
  return buffer;
}

/// Field 22 of /proc/PID/stat (start time in clock ticks since boot), 0 if unknown.
long long start_ticks_of(long pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string stat;
  if (!std::getline(in, stat)) return 0;
  // Field 2 is the command in parentheses and may hold spaces: count from the last ')'.
  const std::size_t close = stat.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream fields(stat.substr(close + 1));
  std::string field;
  for (int k = 3; k <= 22; ++k)
    if (!(fields >> field)) return 0;
  try {
    return std::stoll(field);
  } catch (const std::exception&) {
    return 0;
  }
}

/// Whether `holder` (a process of this host) still runs: its pid exists and, where both start
/// times are known, it is the same process and not a later one that got the pid.
bool still_runs(const LockHolder& holder) {
  if (holder.pid <= 0) return false;
  if (::kill(static_cast<pid_t>(holder.pid), 0) != 0 && errno != EPERM) return false;
  const long long start = start_ticks_of(holder.pid);
  return holder.process_start == 0 || start == 0 || start == holder.process_start;
}

std::string command_line() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string out;
  for (char c : raw)
    out += (c == '\0' || c == '\n' || c == '\r') ? ' ' : c;
  while (!out.empty() && out.back() == ' ')
    out.pop_back();
  if (out.size() > 1000) out = out.substr(0, 1000) + " ...";
  return out.empty() ? "ringdem" : out;
}

std::string now_iso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char buffer[64];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%S%z", &local);
  return buffer;
}

std::string read_all(int fd) {
  std::string text;
  char buffer[4096];
  off_t offset = 0;
  while (true) {
    const ssize_t n = ::pread(fd, buffer, sizeof buffer, offset);
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    offset += n;
  }
  return text;
}

[[noreturn]] void refuse(const std::string& folder, const std::string& message) {
  throw InputError({Diagnostic{folder, 0, 0, "", message}});
}

std::string errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

}  // namespace

// ---- LockHolder -------------------------------------------------------------------------------

std::string LockHolder::describe() const {
  return fmt::format("pid {} on host {}, started {}{}", pid, host.empty() ? "?" : host,
                     start_time.empty() ? "?" : start_time,
                     command.empty() ? "" : " (" + command + ")");
}

std::string LockHolder::text() const {
  return fmt::format(
      "# ringdem output lock: a run is writing into this folder (docs/output.md).\n"
      "host: {}\npid: {}\nprocess_start: {}\nstart_time: {}\ncommand: {}\n",
      host, pid, process_start, start_time, command);
}

LockHolder LockHolder::parse(const std::string& text) {
  LockHolder h;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t colon = line.find(": ");
    if (line.empty() || line[0] == '#' || colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon), value = line.substr(colon + 2);
    try {
      if (key == "host") h.host = value;
      if (key == "pid") h.pid = std::stol(value);
      if (key == "process_start") h.process_start = std::stoll(value);
      if (key == "start_time") h.start_time = value;
      if (key == "command") h.command = value;
    } catch (const std::exception&) {
      // A damaged field stays unknown.
    }
  }
  return h;
}

LockHolder LockHolder::self() {
  LockHolder h;
  h.host = host_name();
  h.pid = static_cast<long>(::getpid());
  h.process_start = start_ticks_of(h.pid);
  h.start_time = now_iso8601();
  h.command = command_line();
  return h;
}

// ---- OutputLock -------------------------------------------------------------------------------

OutputLock::OutputLock(OutputLock&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)) {}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
  }
  return *this;
}

OutputLock::~OutputLock() {
  release();
}

void OutputLock::release() {
  if (fd_ < 0) return;
  unregister_path(path_);
  // Unlinked while still locked: a run waiting on this file finds, once it gets the lock, that
  // the path no longer leads to it and starts over with a new file (see acquire).
  ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
}

OutputLock OutputLock::acquire(const std::string& folder, bool break_foreign, std::string* note) {
  if (note != nullptr) note->clear();
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) refuse(folder, "cannot create the output folder: " + ec.message());
  if (!std::filesystem::is_directory(folder, ec))
    refuse(folder, "the output folder exists but is not a folder");
  const std::string path = (std::filesystem::path(folder) / kFileName).string();
  const LockHolder me = LockHolder::self();

  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      refuse(folder, "the output folder is not writable: cannot create " + path + " (" +
                         errno_text(errno) + "); choose another with -o");
    OutputLock lock;
    lock.fd_ = fd;
    lock.path_ = path;
    bool exclusive = true;  // false where the file system does not support flock
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      if (error == EWOULDBLOCK) {
        const LockHolder holder = LockHolder::parse(read_all(fd));
        ::close(std::exchange(lock.fd_, -1));
        refuse(folder,
               "in use by another ringdem run: " +
                   (holder.pid > 0 ? holder.describe() : std::string("(it is just starting)")) +
                   "; wait until it has ended, or write this run elsewhere with -o");
      }
      if (error != ENOLCK && error != EOPNOTSUPP && error != EINVAL) {
        ::close(std::exchange(lock.fd_, -1));
        refuse(folder, "cannot lock " + path + ": " + errno_text(error));
      }
      exclusive = false;
    }
    // A run that ended between our open and our flock has unlinked the file we hold: start over
    // with the file now at the path (or a new one).
    struct stat held {
    }, current{};
    if (::fstat(fd, &held) != 0 || ::stat(path.c_str(), &current) != 0 ||
        held.st_dev != current.st_dev || held.st_ino != current.st_ino) {
      ::close(std::exchange(lock.fd_, -1));
      continue;
    }

    const LockHolder previous = LockHolder::parse(read_all(fd));
    if (previous.pid > 0) {  // left behind by a run that did not end normally
      if (previous.host == me.host) {
        if (still_runs(previous) || !exclusive) {
          ::close(std::exchange(lock.fd_, -1));
          refuse(folder, "in use by another ringdem run: " + previous.describe() +
                             "; wait until it has ended, or write this run elsewhere with -o");
        }
        if (note != nullptr)
          *note =
              fmt::format("{}: taking over the stale lock of a run that is no longer running: {}",
                          folder, previous.describe());
      } else if (!break_foreign) {
        ::close(std::exchange(lock.fd_, -1));
        refuse(folder, "locked by a ringdem run on another host: " + previous.describe() +
                           "; this host cannot tell whether it still runs. If it has ended "
                           "(for example its node failed), run again with --break-lock");
      } else if (note != nullptr) {
        *note = fmt::format("{}: --break-lock: taking over the lock of {}", folder,
                            previous.describe());
      }
    }
    // Registered before the text is written: whoever reads our pid there may signal us.
    register_path(path);
    const std::string text = me.text();
    if (::ftruncate(fd, 0) != 0 ||
        ::pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()) ||
        ::fsync(fd) != 0) {
      const int error = errno;
      lock.release();
      refuse(folder, "the output folder is not writable: cannot write " + path + " (" +
                         errno_text(error) + ")");
    }
    return lock;
  }
  refuse(folder, "could not take the lock " + path + ": it kept being replaced");
}

OutputLock lock_output_folder(const std::string& folder, const Communicator& comm,
                              bool break_foreign) {
  OutputLock lock;
  std::string error_text, note;
  InputError error({});
  if (comm.is_root()) {
    try {
      lock = OutputLock::acquire(folder, break_foreign, &note);
    } catch (const InputError& e) {
      error = e;
      error_text = e.format();
    }
  }
  if (comm.any(!error_text.empty())) {
    if (comm.is_root()) throw error;
    throw InputError({});  // rank 0 has the message and prints it
  }
  if (!note.empty()) {
    std::cerr << "ringdem: " << note << "\n";
    std::cerr.flush();
  }
  return lock;
}

}  // namespace ringdem
