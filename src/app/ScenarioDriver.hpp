#pragma once

/// One interface for every scenario (free run, tensile test, rockfall). A driver is made from
/// the case by make_scenario_driver (the one table that maps scenario.type to a driver) and run
/// by run_scenario (app/ScenarioRunner.hpp), the one loop all scenarios share:
///
///   start()  →  loop { advance steps_to_advance() steps (observe_step() after each);
///                      after_steps(); frames, checkpoints and stop requests (RunControl);
///                      progress line }  →  finish()
///
/// A driver keeps what it needs to continue (peaks, next record time, phase, ...) in members and
/// hands it to checkpoints through state(); start() restores it from the checkpoint restarted
/// from, so every scenario can stop on request and continue with --restart.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/RigidBody.hpp"
#include "io/CaseConfig.hpp"
#include "io/Checkpoint.hpp"
#include "io/ScenarioKind.hpp"

namespace ringdem {

class Simulation;
class RunControl;
struct Model;

/// What the loop hands a driver at the start.
struct ScenarioContext {
  RunControl& control;     ///< restart state, frames; restarted() says whether state() is restored
  std::string output_dir;  ///< empty: write no files
  bool verbose = true;     ///< rank 0 prints what the driver has to say
};

/// Timings of the loop, for the summary.
struct LoopTimes {
  std::int64_t first_step = 0;  ///< step the loop started from (the checkpoint's on a restart)
  double loop_seconds = 0.0;    ///< wall time of the loop
  double wall_seconds = 0.0;    ///< wall time since the run started (set-up included)
};

class ScenarioDriver {
 public:
  virtual ~ScenarioDriver() = default;

  /// The case the simulation is built from (a driver may add to the case it was made from: the
  /// rockfall adds its boulder).
  virtual const CaseConfig& config() const = 0;
  /// Sets what the scenario imposes on a freshly built model before its first force evaluation
  /// (a tensile test's pin velocity). Not called on a restart: the checkpoint holds that state.
  virtual void prepare_model(Model& /*model*/) const {}
  /// Steps the pre-flight report announces (0 when the driver cannot know).
  virtual std::int64_t planned_steps(const Simulation& sim) const = 0;
  /// After the simulation is built (fresh or from a checkpoint): restores the driver's state on
  /// a restart, otherwise records the initial state. Collective. Returns true when nothing is
  /// left to run (a restart from the last step).
  virtual bool start(Simulation& sim, const ScenarioContext& context) = 0;
  /// Steps to advance before the next after_steps() (at least 1).
  virtual std::int64_t steps_to_advance(const Simulation& sim) const = 0;
  /// Whether observe_step() wants every step of a batch.
  virtual bool observes_steps() const { return false; }
  /// At the end of every step of a batch, where observes_steps(): the rigid bodies at the end
  /// of the step and its time (Simulation::BodyObserver; the particles are not complete
  /// there). For what must be seen every step, such as a boulder's largest load. Not
  /// collective: it must not change the simulation.
  virtual void observe_step(const std::vector<RigidBody>& /*bodies*/, double /*time*/) {}
  /// After the steps: records series rows, updates the driver's state, changes phase; returns
  /// true when the scenario is over. Collective.
  virtual bool after_steps(Simulation& sim) = 0;
  /// Everything start() needs to continue from this point (saved in checkpoints).
  virtual DriverState state() const = 0;
  /// One progress line (rank 0), without the newline.
  virtual std::string progress(const Simulation& sim, double steps_per_second) const = 0;
  /// The last frame, summary.json and the final report. Collective.
  virtual void finish(Simulation& sim, const LoopTimes& times) = 0;
};

/// The driver of the case's scenario.
std::unique_ptr<ScenarioDriver> make_scenario_driver(const CaseConfig& config);

/// A fresh model of `config` as its scenario starts it: build_model, then the driver's
/// prepare_model (for code that steps a Simulation without the scenario loop: tests, tools).
Model build_scenario_model(const CaseConfig& config, const Communicator& comm);

}  // namespace ringdem
