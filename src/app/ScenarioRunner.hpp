#pragma once

#include <string>

#include "app/ScenarioDriver.hpp"
#include "comm/Communicator.hpp"

namespace ringdem {

struct ScenarioRunOptions {
  std::string output_dir;      ///< empty: write nothing (no series, summary, frames, checkpoints)
  bool verbose = true;         ///< banner, pre-flight, progress lines, timing table (rank 0)
  std::string restart;         ///< "", "auto" or a checkpoint path
  double max_walltime = 0.0;   ///< seconds; checkpoint and exit 3 when reached (0: no limit)
  bool allow_changes = false;  ///< a restart applies changed keys it may apply (RunControl)
  /// SIGUSR1 and --max-walltime checkpoint and stop the run. Off for the many short runs of a
  /// sweep or a calibration, which cannot be continued as a whole.
  bool handle_stop_requests = true;
  /// Run even when the size estimate exceeds the memory available on a node.
  bool force_size = false;
  /// Take over the output folder's lock even when it names a run on another host (--break-lock).
  bool break_lock = false;
  /// The most steps between two looks at the schedules and the progress line: a few seconds at
  /// most for a million grains a rank, and one unfused step in a hundred (Simulation::
  /// run_steps). 1 steps one at a time, the path the batches must match bit for bit.
  std::int64_t max_batch = 100;
};

/// The one run loop of every scenario (app/ScenarioDriver.hpp): the output folder's lock
/// (app/OutputLock.hpp, held to the end of the run), banner, simulation (fresh or
/// from a checkpoint), pre-flight, driver.start(), then steps, driver.after_steps(), frames and
/// checkpoints when due, stop requests and progress lines until the driver is done, then
/// driver.finish(). Returns 0, or kExitCheckpointed after a requested stop.
int run_scenario(ScenarioDriver& driver, const ScenarioRunOptions& options,
                 const Communicator& comm);

}  // namespace ringdem
