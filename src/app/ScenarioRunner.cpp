#include "app/ScenarioRunner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

namespace {
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}
}  // namespace

int run_scenario(ScenarioDriver& driver, const ScenarioRunOptions& options,
                 const Communicator& comm) {
  const auto wall_start = Clock::now();
  const CaseConfig& config = driver.config();
  const bool print = comm.is_root() && options.verbose;
  if (comm.is_root() && !options.output_dir.empty())
    std::filesystem::create_directories(options.output_dir);
  if (print) print_banner(config, options.output_dir, comm);

  RunControlOptions control_options;
  control_options.output_dir = options.output_dir;
  control_options.restart = options.restart;
  control_options.max_walltime = options.max_walltime;
  control_options.allow_changes = options.allow_changes;
  control_options.verbose = options.verbose;
  control_options.handle_stop_requests = options.handle_stop_requests;
  RunControl control(config, control_options, comm);
  std::unique_ptr<Simulation> sim_ptr = control.make_simulation(settings_from_case(config));
  Simulation& sim = *sim_ptr;
  print_preflight(sim, config, driver.planned_steps(sim), print, control.time_step_origin());

  bool done = driver.start(sim, ScenarioContext{control, options.output_dir, options.verbose});
  // Built once: after_step takes it every step.
  const std::function<DriverState()> driver_state = [&driver] { return driver.state(); };
  const auto loop_start = Clock::now();
  auto last_progress = loop_start;
  const std::int64_t first_step = sim.steps();
  while (!done) {
    const std::int64_t steps = std::max<std::int64_t>(1, driver.steps_to_advance(sim));
    for (std::int64_t k = 0; k < steps; ++k) {
      control.before_step(sim);
      sim.step();
      // A stop agreed by all ranks ends the batch here; after_step below checkpoints it.
      if (sim.stop_agreed()) break;
    }
    done = driver.after_steps(sim);
    if (control.after_step(sim, driver_state)) return kExitCheckpointed;
    if (print && seconds_since(last_progress) >= config.simulation.progress_interval) {
      last_progress = Clock::now();
      const double rate = static_cast<double>(sim.steps() - first_step) / seconds_since(loop_start);
      fmt::print("{}\n", driver.progress(sim, rate));
      std::fflush(stdout);
    }
  }
  driver.finish(sim, LoopTimes{first_step, seconds_since(loop_start), seconds_since(wall_start)});
  return 0;
}

}  // namespace ringdem
