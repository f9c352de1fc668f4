#pragma once

#include <string>

#include "comm/Communicator.hpp"

namespace ringdem {

/// Who holds an output folder: what its lock file says.
struct LockHolder {
  std::string host;
  long pid = 0;
  /// When the process started: clock ticks since boot (/proc/PID/stat), 0 if unknown. Tells a
  /// live holder from an unrelated process that got the same pid later.
  long long process_start = 0;
  std::string start_time;  ///< wall time the lock was taken, ISO 8601 with the UTC offset
  std::string command;     ///< the command line of the holder

  /// "pid 1234 on host node7, started 2025-01-31T09:00:00+0100 (ringdem run a.yaml)".
  std::string describe() const;
  /// The lock file's text: one "key: value" line per field after a comment line.
  std::string text() const;
  /// Parses text(); fields that are missing stay empty or 0.
  static LockHolder parse(const std::string& text);
  /// This process, now.
  static LockHolder self();
};

/// An exclusive lock on an output folder for the length of a run, so that two runs never
/// write into one folder (their frames, series and checkpoints would be mixed and corrupted).
///
/// The lock is the file <folder>/ringdem.lock, opened and locked with flock(2) and holding
/// LockHolder::text() of this process. The flock is the mutual exclusion (the kernel drops it
/// when the process dies, however it dies); the text names the holder in the refusal and tells
/// a lock left behind by a killed run (stale: its process is gone) from one still in use:
/// - another process holds the flock: refused, naming the holder;
/// - the file names a process of this host that is gone (or its pid now belongs to another
///   process): stale, taken over with a note;
/// - the file names a process of this host that still runs: refused (the file system does not
///   honour flock, so the text is all there is to go by);
/// - the file names another host: refused, since this host cannot tell whether that run still
///   goes on, unless `break_foreign` (--break-lock: the user knows it has ended).
/// The file is removed when the lock is released (destructor: normal end, exceptions, exit 3 on
/// SIGUSR1) and on SIGINT, SIGTERM and SIGHUP before the process ends.
class OutputLock {
 public:
  static constexpr const char* kFileName = "ringdem.lock";

  OutputLock() = default;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  ~OutputLock();

  /// Creates `folder` if needed and takes its lock in this process. Throws InputError when the
  /// folder cannot be created or written, or when the lock is refused (the message names the
  /// holder). `note` (if not null) receives what was taken over, else stays empty.
  static OutputLock acquire(const std::string& folder, bool break_foreign, std::string* note);

  bool held() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }
  /// Removes the lock file and drops the lock (idempotent).
  void release();

 private:
  int fd_ = -1;
  std::string path_;
};

/// Collective: rank 0 creates `folder` and takes its lock (OutputLock::acquire); the other ranks
/// hold nothing. When rank 0 is refused, every rank throws InputError (rank 0's names the
/// holder; the command line prints rank 0's), so all ranks exit with code 2 together. Notes
/// about a lock taken over go to stderr on rank 0.
OutputLock lock_output_folder(const std::string& folder, const Communicator& comm,
                              bool break_foreign);

}  // namespace ringdem
