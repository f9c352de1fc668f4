#include "app/RunControl.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "engine/ModelBuilder.hpp"
#include "io/Hdf5File.hpp"
#include "io/InputError.hpp"

namespace ringdem {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int) {
  g_stop_signal = 1;
}

}  // namespace

void install_stop_signal_handler() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGUSR1, &action, nullptr);
}

bool stop_signal_received() {
  return g_stop_signal != 0;
}
void reset_stop_signal() {
  g_stop_signal = 0;
}

RunControl::RunControl(const CaseConfig& config, RunControlOptions options,
                       const Communicator& comm)
    : config_(config),
      options_(std::move(options)),
      comm_(comm),
      checkpoints_(options_.output_dir + "/checkpoints", config.output.checkpoints_kept) {
  if (stops_enabled()) install_stop_signal_handler();
}

bool RunControl::writes_files() const {
  return !options_.output_dir.empty();
}

bool RunControl::stops_enabled() const {
  return options_.handle_stop_requests && writes_files();
}

std::unique_ptr<Simulation> RunControl::make_simulation(const SimulationSettings& settings) {
  const bool root = comm_.is_root() && options_.verbose;
  std::vector<std::string> candidates;
  if (options_.restart == "auto") {
    const auto all = checkpoints_.list();
    candidates.assign(all.rbegin(), all.rend());
    if (candidates.empty() && root)
      fmt::print("restart auto: no checkpoint in {}, starting from the beginning\n",
                 checkpoints_.dir());
  } else if (!options_.restart.empty()) {
    // A folder is a likely mistake (the output folder, or its checkpoints/): an input error
    // that says what to give instead, on every rank alike (they all see the same path).
    std::error_code ec;
    if (std::filesystem::is_directory(options_.restart, ec))
      throw InputError({Diagnostic{
          options_.restart, 0, 0, "",
          "--restart: is a directory, not a checkpoint file; give a checkpoint_NNNNNN.h5 "
          "file, or --restart auto for the newest valid one in <output>/checkpoints"}});
    candidates.push_back(options_.restart);
  }
  for (const std::string& path : candidates) {
    Model model = build_model_without_particles(config_);
    DriverState driver;
    CheckpointInfo info;
    RestartState state;
    std::string error;
    try {
      state = read_checkpoint(comm_, path, model, driver, &info);
    } catch (const std::exception& e) {
      error = e.what();
    }
    // Every rank read the same file; agree anyway (a rank may fail to read it).
    if (comm_.any(!error.empty())) {
      if (options_.restart != "auto")
        throw Hdf5Error(error.empty() ? path + ": another rank could not read it" : error);
      if (root) fmt::print("restart auto: skipping {}\n", error.empty() ? path : error);
      continue;
    }
    if (root)
      fmt::print("restart from {}: t = {:.6g} s, step {}, written by {} rank{}\n", path, info.time,
                 info.step, info.ranks, info.ranks == 1 ? "" : "s");
    restarted_ = true;
    restart_time_ = info.time;
    driver_state_ = driver;
    segment_ = info.segment + 1;
    next_frame_time_ = driver.get("run.next_frame_time", 0.0);
    next_frame_step_ = static_cast<std::int64_t>(driver.get("run.next_frame_step", 0.0));
    next_checkpoint_time_ = driver.get("run.next_checkpoint_time", 0.0);
    last_frame_time_ = -1.0;
    return std::make_unique<Simulation>(std::move(model), comm_, settings, state);
  }
  if (options_.restart == "auto" && !candidates.empty())
    throw Hdf5Error("restart auto: no readable checkpoint in " + checkpoints_.dir());
  // The drivers write the frame of the initial state themselves (write_frame()).
  next_frame_time_ = config_.output.frame_interval;
  next_frame_step_ = config_.output.frame_interval_steps;
  next_checkpoint_time_ = config_.output.checkpoint_interval;
  return std::make_unique<Simulation>(build_model(config_, comm_), comm_, settings);
}

void RunControl::before_step(Simulation& sim) const {
  if (!stops_enabled()) return;
  bool stop = stop_signal_received();
  if (options_.max_walltime > 0.0)
    stop =
        stop || std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >
                    options_.max_walltime;
  sim.request_stop(stop);
}

void RunControl::write_frame(Simulation& sim, bool for_inspection) {
  if (!writes_files()) return;
  if (!for_inspection && config_.output.frame_interval <= 0.0 &&
      config_.output.frame_interval_steps <= 0)
    return;
  if (sim.time() == last_frame_time_) return;
  if (!frames_) {
    const std::string base = fmt::format("{}/frames_{:04d}", options_.output_dir, segment_);
    frames_ = std::make_unique<FrameWriter>(comm_, base + ".h5", base + ".xdmf",
                                            config_.output.compression);
  }
  sim.refresh_bond_diagnostics();
  frames_->write(sim.model().particles, sim.model().bonds, sim.model().bodies, sim.time(),
                 sim.steps());
  last_frame_time_ = sim.time();
}

std::string RunControl::write_checkpoint(Simulation& sim,
                                         const std::function<DriverState()>& driver) {
  DriverState state = driver ? driver() : DriverState{};
  state.set("run.next_frame_time", next_frame_time_);
  state.set("run.next_frame_step", static_cast<double>(next_frame_step_));
  state.set("run.next_checkpoint_time", next_checkpoint_time_);
  const std::string path = checkpoints_.write(sim.comm(), sim.model(), sim.restart_state(), state,
                                              segment_, config_.name);
  last_checkpoint_wall_ = std::chrono::steady_clock::now();
  return path;
}

bool RunControl::after_step(Simulation& sim, const std::function<DriverState()>& driver) {
  if (!writes_files()) return false;
  const OutputConfig& out = config_.output;
  // Frames due, by simulated time (with a tolerance of a hundredth of a step against rounding)
  // or by steps.
  bool frame_due = false;
  if (out.frame_interval > 0.0 && sim.time() + 0.01 * sim.dt() >= next_frame_time_) {
    frame_due = true;
    while (next_frame_time_ <= sim.time() + 0.01 * sim.dt())
      next_frame_time_ += out.frame_interval;
  }
  if (out.frame_interval_steps > 0 && sim.steps() >= next_frame_step_) {
    frame_due = true;
    next_frame_step_ = (sim.steps() / out.frame_interval_steps + 1) * out.frame_interval_steps;
  }
  if (frame_due) write_frame(sim);

  bool checkpoint_due = false;
  if (out.checkpoint_interval > 0.0 && sim.time() + 0.01 * sim.dt() >= next_checkpoint_time_) {
    checkpoint_due = true;
    while (next_checkpoint_time_ <= sim.time() + 0.01 * sim.dt())
      next_checkpoint_time_ += out.checkpoint_interval;
  }
  if (out.checkpoint_wall_interval > 0.0) {
    // Rank 0's clock decides, so every rank agrees.
    const double since =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint_wall_)
            .count();
    // Checked every 1000 steps only: the broadcast is a collective.
    if (sim.steps() % 1000 == 0) {
      std::vector<double> v{since};
      comm_.broadcast(v, 0);
      checkpoint_due = checkpoint_due || v[0] >= out.checkpoint_wall_interval;
    }
  }
  if (sim.stop_agreed()) {
    const std::string path = write_checkpoint(sim, driver);
    if (comm_.is_root())
      fmt::print(
          "stop requested (SIGUSR1 or wall-time limit): checkpoint {} at t = {:.6g} s, "
          "step {}; continue with --restart auto\n",
          path, sim.time(), sim.steps());
    std::fflush(stdout);
    return true;
  }
  if (checkpoint_due) write_checkpoint(sim, driver);
  return false;
}

}  // namespace ringdem
