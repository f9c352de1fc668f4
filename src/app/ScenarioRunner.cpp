#include "app/ScenarioRunner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "app/OutputLock.hpp"
#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "app/WallClock.hpp"
#include "engine/DivergenceError.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/InputError.hpp"
#include "io/SizeEstimate.hpp"

namespace ringdem {

int run_scenario(ScenarioDriver& driver, const ScenarioRunOptions& options,
                 const Communicator& comm) {
  const auto wall_start = WallClock::now();
  const CaseConfig& config = driver.config();
  const bool print = comm.is_root() && options.verbose;
  // Before anything is read or written: no second run into this folder, and a folder that
  // cannot be written is found now rather than when the results are due.
  OutputLock lock;
  if (!options.output_dir.empty())
    lock = lock_output_folder(options.output_dir, comm, options.break_lock);
  if (print) print_banner(config, options.output_dir, comm);

  // Before anything is built: refuse a case that cannot fit (every rank judges its node).
  {
    const SizeEstimate size = estimate_size(config);
    const double need = size.bytes_per_rank(comm.size()) * comm.ranks_on_this_node();
    const double have = available_memory_bytes();
    const bool too_big = have > 0.0 && need > have;
    if (print) fmt::print("size estimate: {}\n", describe(size, comm.size()));
    if (comm.any(too_big) && !options.force_size) {
      Diagnostic d;
      d.file = config.source_path.empty() ? config.name : config.source_path;
      d.message = fmt::format(
          "the case needs about {:.0f} MiB per node ({}), more than the {:.0f} MiB available; "
          "run on more ranks or nodes, or give --force-size to try anyway",
          need / (1024.0 * 1024.0), describe(size, comm.size()), have / (1024.0 * 1024.0));
      throw InputError({d});
    }
  }

  RunControlOptions control_options;
  control_options.output_dir = options.output_dir;
  control_options.restart = options.restart;
  control_options.max_walltime = options.max_walltime;
  control_options.allow_changes = options.allow_changes;
  control_options.verbose = options.verbose;
  control_options.handle_stop_requests = options.handle_stop_requests;
  RunControl control(config, control_options, comm);
  std::unique_ptr<Simulation> sim_ptr = control.make_simulation(
      settings_from_case(config), [&driver](Model& model) { driver.prepare_model(model); });
  Simulation& sim = *sim_ptr;
  print_preflight(sim, config, driver.planned_steps(sim), print, control.time_step_origin());

  bool done = driver.start(sim, ScenarioContext{control, options.output_dir, options.verbose});
  // Built once: after_step takes it every step.
  const std::function<DriverState()> driver_state = [&driver] { return driver.state(); };
  const auto loop_start = WallClock::now();
  auto last_progress = loop_start;
  const std::int64_t first_step = sim.steps();
  Simulation::BodyObserver observe_bodies;
  if (driver.observes_steps())
    observe_bodies = [&driver](const std::vector<RigidBody>& bodies, double time) {
      driver.observe_step(bodies, time);
    };
  while (!done) {
    // As many steps as no schedule needs to look at, up to a batch whose wall time is short
    // beside the progress interval: the simulation runs a batch faster than single steps.
    const std::int64_t steps = std::max<std::int64_t>(
        1,
        std::min({driver.steps_to_advance(sim), control.steps_until_due(sim), options.max_batch}));
    try {
      // A stop agreed by all ranks ends the batch early; after_step below checkpoints it.
      sim.run_steps(
          steps, [&control, &sim] { control.before_step(sim); }, observe_bodies);
    } catch (const DivergenceError& e) {
      // Every rank threw at the same step. The diverged state goes into a last frame for
      // inspection, never into a checkpoint.
      control.write_frame(sim, /*for_inspection=*/true);
      if (comm.is_root()) {
        fmt::print(stderr, "ringdem: {}\n", e.what());
        if (control.frames())
          fmt::print(stderr, "ringdem: the state at the divergence is the last frame of {}\n",
                     control.frames()->xdmf_path());
      }
      return kExitDiverged;
    }
    done = driver.after_steps(sim);
    if (control.after_step(sim, driver_state)) return kExitCheckpointed;
    if (print && seconds_since(last_progress) >= config.simulation.progress_interval) {
      last_progress = WallClock::now();
      const double rate = static_cast<double>(sim.steps() - first_step) / seconds_since(loop_start);
      fmt::print("{}\n", driver.progress(sim, rate));
      std::fflush(stdout);
    }
  }
  driver.finish(sim, LoopTimes{first_step, seconds_since(loop_start), seconds_since(wall_start)});
  return 0;
}

}  // namespace ringdem
