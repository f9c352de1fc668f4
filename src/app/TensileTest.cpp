#include "app/TensileTest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "app/RunCommand.hpp"
#include "core/Version.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

// ---- TensileMeter -----------------------------------------------------------------------------

TensileMeter::TensileMeter(const std::vector<RigidBody>& bodies,
                           const std::vector<std::string>& moving_bodies,
                           const Vec3& pull_direction)
    : direction_(normalized(pull_direction)) {
  for (const std::string& name : moving_bodies) {
    const auto it = std::find_if(bodies.begin(), bodies.end(),
                                 [&](const RigidBody& b) { return b.name == name; });
    if (it == bodies.end())
      throw std::invalid_argument("tensile test: no rigid body named '" + name + "'");
    moving_.push_back(static_cast<std::size_t>(it - bodies.begin()));
    start_.push_back(it->position);
  }
  if (moving_.empty()) throw std::invalid_argument("tensile test: no moving bodies");
}

double TensileMeter::load(const std::vector<RigidBody>& bodies) const {
  double sum = 0.0;
  for (std::size_t b : moving_)
    sum -= dot(bodies[b].force, direction_);
  return sum;
}

double TensileMeter::displacement(const std::vector<RigidBody>& bodies) const {
  double sum = 0.0;
  for (std::size_t k = 0; k < moving_.size(); ++k)
    sum += dot(bodies[moving_[k]].position - start_[k], direction_);
  return sum / static_cast<double>(moving_.size());
}

// ---- TensileStopRule --------------------------------------------------------------------------

TensileStopRule::Reason TensileStopRule::update(double displacement, double load,
                                                std::int64_t broken_bonds) {
  if (load > peak_load_) {
    peak_load_ = load;
    displacement_at_peak_ = displacement;
  }
  if (broken_bonds > 0 && peak_load_ > 0.0 && load < fraction_ * peak_load_)
    return Reason::kFailure;
  if (displacement >= max_displacement_) return Reason::kMaxDisplacement;
  return Reason::kRunning;
}

const char* stop_reason_name(TensileStopRule::Reason reason) {
  switch (reason) {
    case TensileStopRule::Reason::kFailure:
      return "failure";
    case TensileStopRule::Reason::kMaxDisplacement:
      return "max_displacement";
    case TensileStopRule::Reason::kRunning:
      break;
  }
  return "end_time";
}

// ---- curve analysis ---------------------------------------------------------------------------

std::optional<HingeFit> fit_hinge(const std::vector<double>& u, const std::vector<double>& p) {
  const std::size_t n = std::min(u.size(), p.size());
  if (n < 5) return std::nullopt;
  std::optional<HingeFit> best;
  // Candidate breakpoints at the samples, at least 2 samples on either side.
  for (std::size_t j = 2; j + 2 < n; ++j) {
    const double ub = u[j];
    // Least squares for P = c + s1 min(u - ub, 0) + s2 max(u - ub, 0): 3x3 normal equations.
    double a[3][3] = {}, r[3] = {};
    for (std::size_t i = 0; i < n; ++i) {
      const double f[3] = {1.0, std::min(u[i] - ub, 0.0), std::max(u[i] - ub, 0.0)};
      for (int x = 0; x < 3; ++x) {
        r[x] += f[x] * p[i];
        for (int y = 0; y < 3; ++y)
          a[x][y] += f[x] * f[y];
      }
    }
    // Cramer's rule (the matrix is small and well conditioned for distinct samples).
    auto det3 = [](const double m[3][3]) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
             m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double det = det3(a);
    if (!(std::abs(det) > 0.0)) continue;
    double coef[3];
    for (int x = 0; x < 3; ++x) {
      double m[3][3];
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
          m[row][col] = col == x ? r[row] : a[row][col];
      coef[x] = det3(m) / det;
    }
    double sse = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double fit =
          coef[0] + coef[1] * std::min(u[i] - ub, 0.0) + coef[2] * std::max(u[i] - ub, 0.0);
      sse += (p[i] - fit) * (p[i] - fit);
    }
    if (!best || sse < best->residual) best = HingeFit{ub, coef[0], coef[1], coef[2], sse};
  }
  return best;
}

TensileCurveAnalysis analyse_tensile_curve(const std::vector<double>& u,
                                           const std::vector<double>& p) {
  TensileCurveAnalysis a;
  const std::size_t n = std::min(u.size(), p.size());
  if (n == 0) return a;
  for (std::size_t i = 0; i < n; ++i) {
    if (p[i] > a.peak_load) {
      a.peak_load = p[i];
      a.peak_index = i;
    }
  }
  a.displacement_at_peak = u[a.peak_index];
  const auto up_to_peak = static_cast<std::ptrdiff_t>(a.peak_index + 1);
  const auto hinge = fit_hinge(std::vector<double>(u.begin(), u.begin() + up_to_peak),
                               std::vector<double>(p.begin(), p.begin() + up_to_peak));
  // A transition needs the second stage to be the stiffer one.
  if (hinge && hinge->tensile_stiffness > hinge->bending_stiffness) {
    a.stage_transition_displacement = hinge->breakpoint;
    a.bending_stage_stiffness = hinge->bending_stiffness;
    a.tensile_stage_stiffness = hinge->tensile_stiffness;
  }
  return a;
}

// ---- the run ----------------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Earliest break time of any bond, or nothing if none broke.
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

}  // namespace

TensileResult run_tensile_test(const CaseConfig& config, const TensileRunOptions& options,
                               const Communicator& comm) {
  if (config.scenario.type != "tensile_test")
    throw std::invalid_argument("case '" + config.name + "' is not a tensile test");
  const TensileTestConfig& test = config.scenario.tensile_test;
  const bool print = comm.is_root() && options.verbose;
  const bool write = comm.is_root() && !options.output_dir.empty();
  const auto wall_start = Clock::now();
  if (write) std::filesystem::create_directories(options.output_dir);
  if (print) print_banner(config, options.output_dir, comm);

  Simulation sim(build_model(config), comm, settings_from_case(config));
  const TensileMeter meter(sim.model().bodies, test.moving_bodies, test.pull_direction);
  TensileStopRule stop(test.failure_load_fraction, test.max_displacement);
  const double travel_time = test.max_displacement / test.loading_rate;
  const double end_time = std::min(config.simulation.end_time, travel_time * (1.0 + 1e-9));
  const auto planned_steps = static_cast<std::int64_t>(std::ceil(end_time / sim.dt() - 1e-9));
  print_preflight(sim, config, planned_steps, print);
  if (print) {
    fmt::print(
        "tensile test: {} moving bod{} at {:.4g} m/s along [{:.3g}, {:.3g}, {:.3g}], "
        "stop at failure (load < {:.3g} x peak after a bond broke) or {:.4g} m travel\n",
        test.moving_bodies.size(), test.moving_bodies.size() == 1 ? "y" : "ies", test.loading_rate,
        test.pull_direction.x, test.pull_direction.y, test.pull_direction.z,
        test.failure_load_fraction, test.max_displacement);
    std::fflush(stdout);
  }

  SeriesWriter series;
  if (write)
    series = SeriesWriter(options.output_dir + "/series.csv",
                          {"time_s", "displacement_m", "load_N", "broken_bonds", "kinetic_energy_J",
                           "bond_energy_J"});

  TensileResult result;
  result.dt = sim.dt();
  std::int64_t broken = 0;
  auto record = [&](double displacement, double load) {
    const Energies e = sim.energies();
    result.max_kinetic_energy = std::max(result.max_kinetic_energy, e.kinetic);
    result.curve.push_back({sim.time(), displacement, load, broken});
    if (write)
      series.row(
          {sim.time(), displacement, load, static_cast<double>(broken), e.kinetic, e.bond_elastic});
  };

  record(meter.displacement(sim.model().bodies), meter.load(sim.model().bodies));
  // Each row holds the mean displacement and load over the steps since the previous row, so
  // single-step spikes (a snapping bond's particles hitting a pin) do not count as load.
  double next_record = test.record_interval;
  double sum_displacement = 0.0, sum_load = 0.0;
  std::int64_t n_summed = 0;
  TensileStopRule::Reason reason = TensileStopRule::Reason::kRunning;
  auto last_progress = Clock::now();
  const auto loop_start = Clock::now();
  while (sim.time() < end_time * (1.0 - 1e-12)) {
    sim.step();
    const double displacement = meter.displacement(sim.model().bodies);
    const double load = meter.load(sim.model().bodies);
    // A collective call: the condition must be the same on every rank.
    if (sim.bonds_broke_anywhere() || broken > 0) {
      const std::int64_t now_broken = sim.global_broken_bonds();
      if (now_broken > 0 && broken == 0) result.elongation_at_failure = displacement;
      broken = now_broken;
    }
    sum_displacement += displacement;
    sum_load += load;
    ++n_summed;
    const bool last_step = sim.time() >= end_time * (1.0 - 1e-12);
    if (displacement >= next_record || last_step) {
      const double mean_displacement = sum_displacement / static_cast<double>(n_summed);
      const double mean_load = sum_load / static_cast<double>(n_summed);
      sum_displacement = sum_load = 0.0;
      n_summed = 0;
      record(mean_displacement, mean_load);
      while (next_record <= displacement)
        next_record += test.record_interval;
      reason = stop.update(mean_displacement, mean_load, broken);
      if (reason == TensileStopRule::Reason::kRunning && displacement >= test.max_displacement)
        reason = TensileStopRule::Reason::kMaxDisplacement;
      if (reason != TensileStopRule::Reason::kRunning) break;
    }
    if (print && seconds_since(last_progress) >= config.simulation.progress_interval) {
      last_progress = Clock::now();
      const double rate = sim.steps() / seconds_since(loop_start);
      fmt::print(
          "step {:>10} t = {:.4f} s  u = {:7.2f} mm  load = {:9.3f} kN  peak {:9.3f} kN  "
          "broken {}  {:>7.0f} steps/s  ETA {:>7}\n",
          sim.steps(), sim.time(), 1e3 * displacement, 1e-3 * load, 1e-3 * stop.peak_load(), broken,
          rate, format_duration((planned_steps - sim.steps()) / rate));
      std::fflush(stdout);
    }
  }
  const double loop_seconds = seconds_since(loop_start);

  std::vector<double> u, p;
  for (const TensileSample& s : result.curve) {
    u.push_back(s.displacement);
    p.push_back(s.load);
  }
  result.analysis = analyse_tensile_curve(u, p);
  result.stop_reason = reason;
  result.first_bond_break_time = first_break_time(sim);
  result.broken_bonds = sim.global_broken_bonds();
  result.particles = sim.global_particles();
  const std::int64_t n_bonds = sim.global_bonds();  // collective: on every rank, before `write`
  result.steps = sim.steps();
  result.final_displacement = meter.displacement(sim.model().bodies);
  result.particle_steps_per_s =
      loop_seconds > 0 ? static_cast<double>(result.particles) * sim.steps() / loop_seconds : 0.0;
  result.wall_time = seconds_since(wall_start);

  if (write) {
    JsonObject summary;
    summary.set("ringdem_version", kVersion)
        .set("case", config.name)
        .set("scenario", "tensile_test")
        .set("ranks", comm.size())
        .set("particles", static_cast<long long>(result.particles))
        .set("bonds", static_cast<long long>(n_bonds))
        .set("loading_rate_m_per_s", test.loading_rate)
        .set("dt_s", sim.dt())
        .set("stop_reason", stop_reason_name(reason))
        .set("peak_load_N", result.analysis.peak_load)
        .set("displacement_at_peak_m", result.analysis.displacement_at_peak)
        .set("elongation_at_failure_m", or_nan(result.elongation_at_failure))
        .set("first_bond_break_time_s", or_nan(result.first_bond_break_time))
        .set("broken_bonds", static_cast<long long>(result.broken_bonds))
        .set("stage_transition_displacement_m",
             or_nan(result.analysis.stage_transition_displacement))
        .set("bending_stage_stiffness_N_per_m", result.analysis.bending_stage_stiffness)
        .set("tensile_stage_stiffness_N_per_m", result.analysis.tensile_stage_stiffness)
        .set("final_displacement_m", result.final_displacement)
        .set("end_time_s", sim.time())
        .set("max_kinetic_energy_J", result.max_kinetic_energy)
        .set("steps", static_cast<long long>(result.steps))
        .set("wall_time_s", result.wall_time)
        .set("particle_steps_per_s", result.particle_steps_per_s);
    summary.write(options.output_dir + "/summary.json");
  }
  if (print) {
    fmt::print(
        "stopped: {} at u = {:.2f} mm; peak load {:.3f} kN at u = {:.2f} mm; {} broken "
        "bonds; tensile stage from u = {:.2f} mm\n",
        stop_reason_name(reason), 1e3 * result.final_displacement, 1e-3 * result.analysis.peak_load,
        1e3 * result.analysis.displacement_at_peak, result.broken_bonds,
        1e3 * or_nan(result.analysis.stage_transition_displacement));
    print_timing(sim, loop_seconds, result.particle_steps_per_s, comm.size());
    if (!options.output_dir.empty())
      fmt::print("results: {0}/summary.json, {0}/series.csv\n", options.output_dir);
  }
  return result;
}

}  // namespace ringdem
