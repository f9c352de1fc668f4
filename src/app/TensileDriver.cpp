#include "app/TensileDriver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "core/Version.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

namespace {

const char* const kSeriesColumns[] = {"time_s",        "displacement_m",   "load_N",
                                      "broken_bonds",  "kinetic_energy_J", "bond_energy_J",
                                      "plastic_work_J"};

/// Earliest break time of any bond, or nothing if none broke. Collective.
std::optional<double> first_break_time(const Simulation& sim) {
  const BondStore& bonds = sim.model().bonds;
  double t = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < bonds.size(); ++k)
    if (bonds.broken[k] != 0) t = std::min(t, bonds.break_time[k]);
  t = sim.comm().min(t);
  if (!std::isfinite(t)) return std::nullopt;
  return t;
}

double or_nan(const std::optional<double>& v) {
  return v ? *v : std::numeric_limits<double>::quiet_NaN();
}

/// The rows of a series.csv as numbers (written with 17 digits, so read back exactly).
std::vector<std::vector<double>> read_series_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> row;
    const char* p = line.c_str();
    while (true) {
      char* end = nullptr;
      row.push_back(std::strtod(p, &end));
      if (*end != ',') break;
      p = end + 1;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

TensileDriver::TensileDriver(const CaseConfig& config)
    : config_(config),
      test_(config_.scenario.tensile_test),
      // With unloading the plate travels to unload_at and back (the load is zero before it is
      // back at the start; one record interval more is a margin for the step it turns at).
      end_time_(std::min(config_.simulation.end_time,
                         (test_.unload_at ? 2.0 * *test_.unload_at + test_.record_interval
                                          : test_.max_displacement) /
                             test_.loading_rate * (1.0 + 1e-9))),
      stop_(test_.failure_load_fraction, test_.max_displacement) {}

void TensileDriver::prepare_model(Model& model) const {
  for (const std::string& name : test_.moving_bodies) {
    const auto it = std::find_if(model.bodies.begin(), model.bodies.end(),
                                 [&](const RigidBody& b) { return b.name == name; });
    if (it == model.bodies.end() || it->motion != Motion::kPrescribed)
      throw std::invalid_argument("tensile test: '" + name + "' is not a prescribed rigid body");
    it->velocity = test_.loading_rate * normalized(test_.pull_direction);
  }
}

std::int64_t TensileDriver::planned_steps(const Simulation& sim) const {
  return sim.steps_until(end_time_);
}

bool TensileDriver::start(Simulation& sim, const ScenarioContext& context) {
  control_ = &context.control;
  output_dir_ = context.output_dir;
  verbose_ = context.verbose;
  const Communicator& comm = sim.comm();
  write_ = comm.is_root() && !output_dir_.empty();
  meter_.emplace(sim.model().bodies, test_.moving_bodies, test_.pull_direction);
  result_.dt = sim.dt();
  if (comm.is_root() && verbose_) {
    fmt::print(
        "tensile test: {} moving bod{} at {:.4g} m/s along [{:.3g}, {:.3g}, {:.3g}], "
        "stop at failure (load < {:.3g} x peak after a bond broke) or {:.4g} m travel\n",
        test_.moving_bodies.size(), test_.moving_bodies.size() == 1 ? "y" : "ies",
        test_.loading_rate, test_.pull_direction.x, test_.pull_direction.y, test_.pull_direction.z,
        test_.failure_load_fraction, test_.max_displacement);
    std::fflush(stdout);
  }
  const std::vector<std::string> columns(std::begin(kSeriesColumns), std::end(kSeriesColumns));
  if (write_)
    series_ = control_->restarted() ? SeriesWriter::resume(output_dir_ + "/series.csv", columns,
                                                           control_->restart_time())
                                    : SeriesWriter(output_dir_ + "/series.csv", columns);
  if (control_->restarted()) {
    restore(sim);
    return reason_ != TensileStopRule::Reason::kRunning || past_end(sim);
  }
  record(sim, meter_->displacement(sim.model().bodies), meter_->load(sim.model().bodies));
  // Each row holds the mean displacement and load over the steps since the previous row, so
  // single-step spikes (a snapping bond's particles hitting a pin) do not count as load.
  next_record_ = test_.record_interval;
  return past_end(sim);
}

void TensileDriver::restore(Simulation& sim) {
  const DriverState& d = control_->driver_state();
  std::vector<Vec3> start = meter_->start_positions();
  for (std::size_t k = 0; k < start.size(); ++k)
    start[k] = {d.get(fmt::format("tensile.start_{}_x", k), start[k].x),
                d.get(fmt::format("tensile.start_{}_y", k), start[k].y),
                d.get(fmt::format("tensile.start_{}_z", k), start[k].z)};
  meter_->restore_start_positions(start);
  stop_.restore_peak(d.get("tensile.peak_load"), d.get("tensile.displacement_at_peak"));
  reason_ = static_cast<TensileStopRule::Reason>(static_cast<int>(d.get("tensile.stop_reason")));
  broken_ = static_cast<std::int64_t>(d.get("tensile.broken_bonds"));
  if (d.get("tensile.failed") != 0.0)
    result_.elongation_at_failure = d.get("tensile.elongation_at_failure");
  unloading_ = d.get("tensile.unloading", 0.0) != 0.0;
  loading_rows_ = static_cast<std::size_t>(d.get("tensile.loading_rows", 0.0));
  if (unloading_) {
    result_.turn_displacement = d.get("tensile.turn_displacement");
    drive_back(sim);  // the checkpoint holds the velocity too; this does not depend on it
  }
  if (d.get("tensile.zero_load", 0.0) != 0.0) zero_load_from_ = d.get("tensile.zero_load_from");
  if (d.get("tensile.unloaded", 0.0) != 0.0)
    result_.residual_displacement = d.get("tensile.residual_displacement");
  result_.max_kinetic_energy = d.get("tensile.max_kinetic_energy");
  next_record_ = d.get("tensile.next_record", test_.record_interval);
  sum_displacement_ = d.get("tensile.sum_displacement");
  sum_load_ = d.get("tensile.sum_load");
  n_summed_ = static_cast<std::int64_t>(d.get("tensile.n_summed"));
  displacement_ = meter_->displacement(sim.model().bodies);
  load_ = meter_->load(sim.model().bodies);

  // The curve so far: the rows of series.csv up to the checkpoint (rank 0 has the file).
  std::vector<double> flat;
  if (sim.comm().is_root())
    for (const std::vector<double>& row : read_series_rows(output_dir_ + "/series.csv")) {
      if (row.size() != std::size(kSeriesColumns))
        throw std::runtime_error(output_dir_ + "/series.csv: a row has the wrong width");
      flat.insert(flat.end(), row.begin(), row.begin() + 4);
    }
  sim.comm().broadcast(flat, 0);
  result_.curve.clear();
  for (std::size_t i = 0; i + 3 < flat.size(); i += 4)
    result_.curve.push_back(
        {flat[i], flat[i + 1], flat[i + 2], static_cast<std::int64_t>(flat[i + 3])});
}

void TensileDriver::record(Simulation& sim, double displacement, double load) {
  const Energies e = sim.energies();
  result_.max_kinetic_energy = std::max(result_.max_kinetic_energy, e.kinetic);
  result_.curve.push_back({sim.time(), displacement, load, broken_});
  if (write_)
    series_.row({sim.time(), displacement, load, static_cast<double>(broken_), e.kinetic,
                 e.bond_elastic, e.plastic_work});
}

void TensileDriver::flush_row(Simulation& sim) {
  if (n_summed_ == 0) return;
  const double n = static_cast<double>(n_summed_);
  const double mean_displacement = sum_displacement_ / n;
  const double mean_load = sum_load_ / n;
  sum_displacement_ = sum_load_ = 0.0;
  n_summed_ = 0;
  record(sim, mean_displacement, mean_load);
}

void TensileDriver::drive_back(Simulation& sim) const {
  std::vector<RigidBody>& bodies = sim.model().bodies;
  for (const std::string& name : test_.moving_bodies)
    for (RigidBody& b : bodies)
      if (b.name == name) b.velocity = -test_.loading_rate * test_.pull_direction;
}

bool TensileDriver::after_steps(Simulation& sim) {
  displacement_ = meter_->displacement(sim.model().bodies);
  load_ = meter_->load(sim.model().bodies);
  // A collective call: the condition must be the same on every rank.
  if (sim.bonds_broke_anywhere() || broken_ > 0) {
    const std::int64_t now_broken = sim.global_broken_bonds();
    if (now_broken > 0 && broken_ == 0) result_.elongation_at_failure = displacement_;
    broken_ = now_broken;
  }
  sum_displacement_ += displacement_;
  sum_load_ += load_;
  ++n_summed_;
  const bool last_step = past_end(sim);
  if (unloading_) {
    // Unloading: rows every record_interval of travel back. The load (a sum of contact forces)
    // is zero once no particle pushes on the moving pins; the test ends when it has stayed zero
    // for one record_interval of travel (a ring that lost the pin for a few steps, bouncing,
    // comes back), and the residual displacement is where it became zero.
    if (load_ > 0.0)
      zero_load_from_.reset();
    else if (!zero_load_from_)
      zero_load_from_ = displacement_;
    if (zero_load_from_ && *zero_load_from_ - displacement_ >= test_.record_interval) {
      flush_row(sim);
      result_.residual_displacement = *zero_load_from_;
      reason_ = TensileStopRule::Reason::kUnloaded;
      return true;
    }
    if (displacement_ <= next_record_ || last_step) {
      flush_row(sim);
      while (next_record_ >= displacement_)
        next_record_ -= test_.record_interval;
    }
    return last_step;
  }
  if (displacement_ >= next_record_ || last_step) {
    const double mean_displacement = sum_displacement_ / static_cast<double>(n_summed_);
    const double mean_load = sum_load_ / static_cast<double>(n_summed_);
    sum_displacement_ = sum_load_ = 0.0;
    n_summed_ = 0;
    record(sim, mean_displacement, mean_load);
    while (next_record_ <= displacement_)
      next_record_ += test_.record_interval;
    reason_ = stop_.update(mean_displacement, mean_load, broken_);
    if (reason_ == TensileStopRule::Reason::kRunning && displacement_ >= test_.max_displacement)
      reason_ = TensileStopRule::Reason::kMaxDisplacement;
    if (reason_ != TensileStopRule::Reason::kRunning) return true;
  }
  if (test_.unload_at && displacement_ >= *test_.unload_at && !last_step) {
    // The turn: the row so far ends here, the plate reverses from the next step on.
    flush_row(sim);
    unloading_ = true;
    loading_rows_ = result_.curve.size();
    result_.turn_displacement = displacement_;
    next_record_ = displacement_ - test_.record_interval;
    drive_back(sim);
  }
  return last_step;
}

DriverState TensileDriver::state() const {
  DriverState d;
  const std::vector<Vec3>& start = meter_->start_positions();
  for (std::size_t k = 0; k < start.size(); ++k) {
    d.set(fmt::format("tensile.start_{}_x", k), start[k].x);
    d.set(fmt::format("tensile.start_{}_y", k), start[k].y);
    d.set(fmt::format("tensile.start_{}_z", k), start[k].z);
  }
  d.set("tensile.peak_load", stop_.peak_load());
  d.set("tensile.displacement_at_peak", stop_.displacement_at_peak());
  d.set("tensile.stop_reason", static_cast<double>(static_cast<int>(reason_)));
  d.set("tensile.broken_bonds", static_cast<double>(broken_));
  d.set("tensile.failed", result_.elongation_at_failure ? 1.0 : 0.0);
  d.set("tensile.elongation_at_failure", result_.elongation_at_failure.value_or(0.0));
  d.set("tensile.max_kinetic_energy", result_.max_kinetic_energy);
  d.set("tensile.next_record", next_record_);
  d.set("tensile.sum_displacement", sum_displacement_);
  d.set("tensile.sum_load", sum_load_);
  d.set("tensile.n_summed", static_cast<double>(n_summed_));
  d.set("tensile.unloading", unloading_ ? 1.0 : 0.0);
  d.set("tensile.loading_rows", static_cast<double>(loading_rows_));
  d.set("tensile.turn_displacement", result_.turn_displacement.value_or(0.0));
  d.set("tensile.zero_load", zero_load_from_ ? 1.0 : 0.0);
  d.set("tensile.zero_load_from", zero_load_from_.value_or(0.0));
  d.set("tensile.unloaded", result_.residual_displacement ? 1.0 : 0.0);
  d.set("tensile.residual_displacement", result_.residual_displacement.value_or(0.0));
  return d;
}

std::string TensileDriver::progress(const Simulation& sim, double rate) const {
  return fmt::format(
      "step {:>10} t = {:.4f} s  u = {:7.2f} mm  load = {:9.3f} kN  peak {:9.3f} kN  "
      "broken {}  {:>7.0f} steps/s  ETA {:>7}",
      sim.steps(), sim.time(), 1e3 * displacement_, 1e-3 * load_, 1e-3 * stop_.peak_load(), broken_,
      rate, format_duration(static_cast<double>(planned_steps(sim) - sim.steps()) / rate));
}

void TensileDriver::finish(Simulation& sim, const LoopTimes& times) {
  const Communicator& comm = sim.comm();
  control_->write_frame(sim);
  // Peak and stage transition from the loading branch (the rows before the turn, if any).
  std::vector<double> u, p;
  const std::size_t n_loading = unloading_ ? loading_rows_ : result_.curve.size();
  for (std::size_t i = 0; i < n_loading; ++i) {
    u.push_back(result_.curve[i].displacement);
    p.push_back(result_.curve[i].load);
  }
  result_.analysis = analyse_tensile_curve(u, p);
  result_.stop_reason = reason_;
  result_.first_bond_break_time = first_break_time(sim);
  result_.broken_bonds = sim.global_broken_bonds();
  result_.particles = sim.global_particles();
  const std::int64_t n_bonds = sim.global_bonds();  // collective: on every rank, before `write_`
  const double plastic_work = sim.energies().plastic_work;     // collective too
  const MemoryUse memory = measure_memory_use(config_, comm);  // collective too
  const PhaseSpread phases = measure_phases(sim);              // collective
  result_.steps = sim.steps();
  result_.final_displacement = meter_->displacement(sim.model().bodies);
  result_.particle_steps_per_s = times.loop_seconds > 0
                                     ? static_cast<double>(result_.particles) *
                                           static_cast<double>(sim.steps() - times.first_step) /
                                           times.loop_seconds
                                     : 0.0;
  result_.wall_time = times.wall_seconds;

  if (write_) {
    JsonObject summary;
    summary.set("ringdem_version", kVersion)
        .set("case", config_.name)
        .set("scenario", scenario_name(ScenarioKind::kTensileTest))
        .set("ranks", comm.size())
        .set("particles", static_cast<long long>(result_.particles))
        .set("bonds", static_cast<long long>(n_bonds))
        .set("loading_rate_m_per_s", test_.loading_rate)
        .set("dt_s", sim.dt())
        .set("stop_reason", stop_reason_name(reason_))
        .set("peak_load_N", result_.analysis.peak_load)
        .set("displacement_at_peak_m", result_.analysis.displacement_at_peak)
        .set("elongation_at_failure_m", or_nan(result_.elongation_at_failure))
        .set("first_bond_break_time_s", or_nan(result_.first_bond_break_time))
        .set("broken_bonds", static_cast<long long>(result_.broken_bonds))
        .set("stage_transition_displacement_m",
             or_nan(result_.analysis.stage_transition_displacement))
        .set("bending_stage_stiffness_N_per_m", result_.analysis.bending_stage_stiffness)
        .set("tensile_stage_stiffness_N_per_m", result_.analysis.tensile_stage_stiffness)
        .set("final_displacement_m", result_.final_displacement)
        .set("end_time_s", sim.time())
        .set("max_kinetic_energy_J", result_.max_kinetic_energy)
        .set("plastic_work_J", plastic_work)
        .set("unload_turn_displacement_m", or_nan(result_.turn_displacement))
        .set("residual_displacement_m", or_nan(result_.residual_displacement))
        .set("steps", static_cast<long long>(result_.steps))
        .set("wall_time_s", result_.wall_time)
        .set("particle_steps_per_s", result_.particle_steps_per_s);
    set_memory_use(summary, memory);
    summary.write(output_dir_ + "/summary.json");
  }
  if (comm.is_root() && verbose_) {
    fmt::print(
        "stopped: {} at u = {:.2f} mm; peak load {:.3f} kN at u = {:.2f} mm; {} broken "
        "bonds; tensile stage from u = {:.2f} mm\n",
        stop_reason_name(reason_), 1e3 * result_.final_displacement,
        1e-3 * result_.analysis.peak_load, 1e3 * result_.analysis.displacement_at_peak,
        result_.broken_bonds, 1e3 * or_nan(result_.analysis.stage_transition_displacement));
    if (result_.turn_displacement)
      fmt::print("unloaded from u = {:.2f} mm: {}\n", 1e3 * *result_.turn_displacement,
                 result_.residual_displacement
                     ? fmt::format("the load is zero at u = {:.3f} mm (residual displacement)",
                                   1e3 * *result_.residual_displacement)
                     : std::string("the load did not fall to zero"));
    print_timing(sim, times.loop_seconds, result_.particle_steps_per_s, comm.size(), memory,
                 phases);
    if (!output_dir_.empty())
      fmt::print("results: {0}/summary.json, {0}/series.csv\n", output_dir_);
  }
}

}  // namespace ringdem
