#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "app/StopSignals.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseConfig.hpp"
#include "io/Checkpoint.hpp"
#include "io/FrameWriter.hpp"
#include "io/RestartChanges.hpp"

namespace ringdem {

/// Exit code of a run that wrote a checkpoint on request (SIGUSR1, --max-walltime) and stopped;
/// after a terminating signal (SIGINT, SIGTERM, SIGHUP: app/StopSignals) it is 128 + the signal.
inline constexpr int kExitCheckpointed = 3;
/// Exit status of a run that diverged (DivergenceError), as of any runtime error.
inline constexpr int kExitDiverged = 1;

/// How a run starts and what it writes besides series.csv and summary.json.
struct RunControlOptions {
  std::string output_dir;
  std::string restart;        ///< "", "auto" or a checkpoint path
  double max_walltime = 0.0;  ///< seconds; 0: no limit
  bool verbose = true;
  /// A restart applies changed keys that may be applied (io/RestartChanges) instead of
  /// refusing them.
  bool allow_changes = false;
  /// SIGUSR1 and max_walltime checkpoint and stop the run (never without an output folder).
  bool handle_stop_requests = true;
};

/// Frames, checkpoints and stop requests of one run, shared by the scenario drivers: builds the
/// simulation fresh or from a checkpoint, writes frames and periodic checkpoints when due, and on
/// a stop request agreed by all ranks writes a checkpoint so the driver can exit with
/// kExitCheckpointed. Without an output folder it writes no files and ignores stop requests.
class RunControl {
 public:
  RunControl(const CaseConfig& config, RunControlOptions options, const Communicator& comm);

  /// The simulation: fresh, or restored from the checkpoint the options name (driver state in
  /// driver_state()). Collective. A restart compares the case with the checkpoint's and throws
  /// InputError for changes it may not take over (io/RestartChanges); a fresh start throws
  /// InputError for contacts that overlap at creation (unless the case allows them).
  /// On a fresh start `prepare` (ScenarioDriver::prepare_model) sets what the scenario imposes
  /// on the built model before the simulation's first force evaluation.
  std::unique_ptr<Simulation> make_simulation(const SimulationSettings& settings,
                                              const std::function<void(Model&)>& prepare = {});

  bool restarted() const { return restarted_; }
  /// State the driver saved in the checkpoint it restarted from (empty on a fresh start).
  const DriverState& driver_state() const { return driver_state_; }
  /// Simulated time of the checkpoint restarted from (0 on a fresh start).
  double restart_time() const { return restart_time_; }
  /// Where the time step comes from on a restart ("from the checkpoint", "changed on restart
  /// ..."); empty on a fresh start.
  const std::string& time_step_origin() const { return time_step_origin_; }

  /// Before each step: passes this rank's stop request (signal or wall-time) to the step.
  void before_step(Simulation& sim) const;
  /// After each step: frames and checkpoints that are due. Returns true when all ranks agreed to
  /// stop; a checkpoint has then been written. `driver` supplies the driver's state to save.
  bool after_step(Simulation& sim, const std::function<DriverState()>& driver);
  /// Steps (at least 1) the loop may run before after_step() can have a frame or checkpoint
  /// to write: no schedule is passed within them.
  std::int64_t steps_until_due(const Simulation& sim) const;
  /// A frame now, whatever the schedule (first and last state), when the case writes frames;
  /// `for_inspection` writes one even then (the state a diverged run ended in). Collective.
  void write_frame(Simulation& sim, bool for_inspection = false);
  /// A checkpoint now. Collective.
  std::string write_checkpoint(Simulation& sim, const std::function<DriverState()>& driver);

  /// Whether frames and checkpoints are written (an output folder was given).
  bool writes_files() const;
  /// Whether SIGUSR1 and the wall-time limit stop the run.
  bool stops_enabled() const;

  const FrameWriter* frames() const { return frames_.get(); }
  const std::string& checkpoint_dir() const { return checkpoints_.dir(); }
  std::int64_t segment() const { return segment_; }

 private:
  /// Applies the changed keys of kind kApplied to a simulation restored from a checkpoint.
  void apply_changes(Simulation& sim, const std::vector<CaseChange>& changes,
                     const SimulationSettings& settings);
  /// Throws InputError when contacts of the initial state overlap beyond the tolerance.
  void check_initial_overlaps(const Simulation& sim) const;

  const CaseConfig& config_;
  RunControlOptions options_;
  const Communicator& comm_;
  CheckpointStore checkpoints_;
  std::unique_ptr<FrameWriter> frames_;
  std::int64_t segment_ = 0;
  bool restarted_ = false;
  double restart_time_ = 0.0;
  std::string time_step_origin_;
  DriverState driver_state_;
  double next_frame_time_ = 0.0;
  std::int64_t next_frame_step_ = 0;
  double next_checkpoint_time_ = 0.0;
  double last_frame_time_ = -1.0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_checkpoint_wall_ = start_;
  /// Ctrl-C, kill, scancel: a checkpoint first while this run can write one.
  TerminatingSignalsArmed terminating_signals_;
};

}  // namespace ringdem
