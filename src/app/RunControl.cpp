#include "app/RunControl.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <system_error>

#include "app/StopSignals.hpp"
#include "engine/ModelBuilder.hpp"
#include "io/CaseText.hpp"
#include "io/Hdf5File.hpp"
#include "io/InputError.hpp"

namespace ringdem {

RunControl::RunControl(const CaseConfig& config, RunControlOptions options,
                       const Communicator& comm)
    : config_(config),
      options_(std::move(options)),
      comm_(comm),
      checkpoints_(options_.output_dir + "/checkpoints", config.output.checkpoints_kept),
      terminating_signals_(stops_enabled()) {
  if (stops_enabled()) install_stop_signal_handler();
}

bool RunControl::writes_files() const {
  return !options_.output_dir.empty();
}

bool RunControl::stops_enabled() const {
  return options_.handle_stop_requests && writes_files();
}

std::unique_ptr<Simulation> RunControl::make_simulation(
    const SimulationSettings& settings, const std::function<void(Model&)>& prepare) {
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
  std::string newest_error;  // why the newest checkpoint was skipped, for the final message
  // Every rank reads the same file; agree anyway (a rank may fail to read it). Returns false
  // when `auto` is to try the next one.
  const auto agreed = [&](const std::string& path, const std::string& error) {
    if (!comm_.any(!error.empty())) return true;
    if (options_.restart != "auto")
      throw Hdf5Error(error.empty() ? path + ": another rank could not read it" : error);
    if (root) fmt::print("restart auto: skipping {}\n", error.empty() ? path : error);
    if (newest_error.empty()) newest_error = error.empty() ? path : error;
    return false;
  };
  for (const std::string& path : candidates) {
    CheckpointInfo info;
    std::string error;
    try {
      info = read_checkpoint_info(path);
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (!agreed(path, error)) continue;
    // The case the checkpoint was written by against this one: a readable checkpoint of a
    // changed case is refused, never skipped for an older one (they hold the same case).
    const std::vector<CaseChange> changes =
        case_changes(info.case_text, canonical_case_text(config_));
    check_restart_changes(changes, options_.allow_changes,
                          config_.source_path.empty() ? config_.name : config_.source_path, path);
    Model model = build_model_without_particles(config_);
    DriverState driver;
    RestartState state;
    try {
      state = read_checkpoint(comm_, path, config_, model, driver, &info);
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (!agreed(path, error)) continue;
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
    auto sim = std::make_unique<Simulation>(std::move(model), comm_, settings, std::move(state));
    time_step_origin_ = "from the checkpoint";
    apply_changes(*sim, changes, settings);
    return sim;
  }
  if (options_.restart == "auto" && !candidates.empty())
    throw Hdf5Error("restart auto: no readable checkpoint in " + checkpoints_.dir() +
                    " (the newest: " + newest_error + ")");
  // The drivers write the frame of the initial state themselves (write_frame()).
  next_frame_time_ = config_.output.frame_interval;
  next_frame_step_ = config_.output.frame_interval_steps;
  next_checkpoint_time_ = config_.output.checkpoint_interval;
  Model model = build_model(config_, comm_);
  if (prepare) prepare(model);
  auto sim = std::make_unique<Simulation>(std::move(model), comm_, settings);
  if (!config_.simulation.allow_initial_overlap) check_initial_overlaps(*sim);
  return sim;
}

void RunControl::apply_changes(Simulation& sim, const std::vector<CaseChange>& changes,
                               const SimulationSettings& settings) {
  bool time_step = false, damping = false;
  for (const CaseChange& c : changes) {
    if (c.rule->kind != RestartKeyKind::kApplied) continue;
    time_step = time_step || c.rule->effect == RestartEffect::kTimeStep;
    damping = damping || c.rule->effect == RestartEffect::kDamping;
  }
  // Every group's coefficient from the case (a rockfall driver then sets its net's own again).
  if (damping) {
    const auto& groups = sim.model().group_names;
    for (std::size_t g = 0; g < groups.size(); ++g)
      sim.set_group_damping(static_cast<int>(g), group_damping(config_, groups[g]));
  }
  std::string dt_text;
  if (time_step) {
    const double dt = settings.dt > 0.0 ? settings.dt : settings.dt_safety * sim.limits().min();
    if (dt != sim.dt()) {
      dt_text = fmt::format("time step {:.6g} s -> {:.6g} s from step {} (t = {:.6g} s) on",
                            sim.dt(), dt, sim.steps(), sim.time());
      time_step_origin_ = fmt::format("changed on restart from {:.6g} s", sim.dt());
      sim.change_time_step(dt);
    }
  }
  if (!comm_.is_root() || changes.empty()) return;
  std::size_t applied = 0;
  for (const CaseChange& c : changes)
    applied += c.rule->kind == RestartKeyKind::kApplied;
  if (applied > 0) {
    fmt::print("restart: applied {} changed key{} (--allow-changes):\n", applied,
               applied == 1 ? "" : "s");
    for (const CaseChange& c : changes)
      if (c.rule->kind == RestartKeyKind::kApplied)
        fmt::print("  {} ({})\n", describe_change(c), c.rule->note);
    if (!dt_text.empty()) fmt::print("  {}\n", dt_text);
  }
  if (options_.verbose && applied < changes.size()) {
    fmt::print("restart: changed keys that may change on any restart:\n");
    for (const CaseChange& c : changes)
      if (c.rule->kind == RestartKeyKind::kFree)
        fmt::print("  {} ({})\n", describe_change(c), c.rule->note);
  }
  std::fflush(stdout);
}

void RunControl::check_initial_overlaps(const Simulation& sim) const {
  const double tolerance = config_.simulation.initial_overlap_tolerance;
  const OverlapReport report = sim.overlaps(tolerance);
  if (report.count == 0) return;
  const Model& model = sim.model();
  const auto vec = [](const Vec3& v) {
    return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z);
  };
  const auto group = [&](std::int32_t g) {
    return g >= 0 && static_cast<std::size_t>(g) < model.group_names.size()
               ? model.group_names[static_cast<std::size_t>(g)]
               : std::string("?");
  };
  const std::string file = config_.source_path.empty() ? config_.name : config_.source_path;
  std::vector<Diagnostic> d;
  d.push_back({file, 0, 0, "",
               fmt::format("{} contact{} overlap{} at the start by more than {:g} of the smaller "
                           "radius (simulation.initial_overlap_tolerance); {} would start with "
                           "large contact forces and energy:",
                           report.count, report.count == 1 ? "" : "s", report.count == 1 ? "s" : "",
                           tolerance, report.count == 1 ? "it" : "they")});
  for (const OverlapReport::Entry& e : report.deepest) {
    const std::string partner =
        e.partner_is_body
            ? fmt::format("rigid body '{}' (at {})",
                          model.bodies[static_cast<std::size_t>(e.partner)].name,
                          vec(e.partner_position))
            : fmt::format("particle {} (group {}, at {}, radius {:.6g} m)", e.partner,
                          group(e.partner_group), vec(e.partner_position), e.partner_radius);
    d.push_back({file, 0, 0, "",
                 fmt::format("particle {} (group {}, at {}, radius {:.6g} m) and {} overlap by "
                             "{:.4g} m, {:.3g} % of the smaller radius",
                             e.gid, group(e.group), vec(e.position), e.radius, partner, e.depth,
                             100.0 * e.relative_depth)});
  }
  if (report.count > static_cast<std::int64_t>(report.deepest.size()))
    d.push_back({file, 0, 0, "",
                 fmt::format("... and {} more",
                             report.count - static_cast<std::int64_t>(report.deepest.size()))});
  d.push_back({file, 0, 0, "simulation.allow_initial_overlap",
               "move the particles apart, or set it to true if the overlap is intended"});
  throw InputError(std::move(d));
}

void RunControl::before_step(Simulation& sim) const {
  if (!stops_enabled()) return;
  int stop = stop_request_code();
  if (options_.max_walltime > 0.0 &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >
          options_.max_walltime)
    stop = std::max(stop, kStopRequested);
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
                 sim.steps(), sim.model().ropes);
  last_frame_time_ = sim.time();
}

std::string RunControl::write_checkpoint(Simulation& sim,
                                         const std::function<DriverState()>& driver) {
  DriverState state = driver ? driver() : DriverState{};
  state.set("run.next_frame_time", next_frame_time_);
  state.set("run.next_frame_step", static_cast<double>(next_frame_step_));
  state.set("run.next_checkpoint_time", next_checkpoint_time_);
  const std::string path =
      checkpoints_.write(sim.comm(), sim.model(), sim.restart_state(), state, segment_, config_);
  last_checkpoint_wall_ = std::chrono::steady_clock::now();
  return path;
}

std::int64_t RunControl::steps_until_due(const Simulation& sim) const {
  std::int64_t n = std::numeric_limits<std::int64_t>::max();
  if (!writes_files()) return n;
  const OutputConfig& out = config_.output;
  // The same schedules and tolerances as after_step().
  if (out.frame_interval > 0.0)
    n = std::min(n, sim.steps_short_of(next_frame_time_, 0.01 * sim.dt()));
  if (out.frame_interval_steps > 0)
    n = std::min(n, std::max<std::int64_t>(1, next_frame_step_ - sim.steps()));
  if (out.checkpoint_interval > 0.0)
    n = std::min(n, sim.steps_short_of(next_checkpoint_time_, 0.01 * sim.dt()));
  if (out.checkpoint_wall_interval > 0.0) n = std::min(n, 1000 - sim.steps() % 1000);
  return n;
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
    // A Ctrl-C or kill that reached one rank stops the job as if sent to all (app/StopSignals).
    adopt_agreed_stop(sim.stop_reason());
    const std::string path = write_checkpoint(sim, driver);
    if (comm_.is_root()) {
      const int sig = terminating_signal();
      fmt::print(
          "stop requested ({}): checkpoint {} at t = {:.6g} s, step {}; continue with --restart "
          "auto\n",
          sig != 0 ? signal_name(sig) : "SIGUSR1 or wall-time limit", path, sim.time(),
          sim.steps());
    }
    std::fflush(stdout);
    return true;
  }
  if (checkpoint_due) write_checkpoint(sim, driver);
  return false;
}

}  // namespace ringdem
