#include "app/Calibration.hpp"

#include <fmt/format.h>
#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/OutputLock.hpp"
#include "app/RunCommand.hpp"
#include "app/ScenarioDriver.hpp"
#include "app/TensileTest.hpp"
#include "app/WallClock.hpp"
#include "core/Version.hpp"
#include "domain/RingGenerator.hpp"
#include "io/CaseLoader.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

// ---- reference curve --------------------------------------------------------------------------

namespace {

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\"");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\"");
  return s.substr(first, last - first + 1);
}

[[noreturn]] void curve_error(const std::string& file, int line, const std::string& message) {
  throw InputError({Diagnostic{file, line, 0, "", message}});
}

}  // namespace

LoadCurve parse_load_curve(const std::string& csv_text, const std::string& display_name) {
  std::istringstream in(csv_text);
  std::string line;
  int line_number = 0;
  std::optional<std::size_t> displacement_column, load_column;
  LoadCurve curve;
  while (std::getline(in, line)) {
    ++line_number;
    const std::string content = trimmed(line);
    if (content.empty() || content.front() == '#') continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (!displacement_column) {  // the header
      for (std::size_t c = 0; c < cells.size(); ++c) {
        if (trimmed(cells[c]) == "displacement_m") displacement_column = c;
        if (trimmed(cells[c]) == "load_N") load_column = c;
      }
      if (!displacement_column || !load_column)
        curve_error(display_name, line_number,
                    "the header must name the columns displacement_m and load_N, got: " + content);
      continue;
    }
    double values[2] = {0.0, 0.0};
    const std::size_t columns[2] = {*displacement_column, *load_column};
    for (int k = 0; k < 2; ++k) {
      const std::string cell = columns[k] < cells.size() ? trimmed(cells[columns[k]]) : "";
      char* end = nullptr;
      values[k] = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(values[k]))
        curve_error(display_name, line_number,
                    fmt::format("column {} is not a number: '{}'",
                                k == 0 ? "displacement_m" : "load_N", cell));
    }
    if (!curve.displacement.empty() && values[0] < curve.displacement.back())
      curve_error(display_name, line_number,
                  fmt::format("displacements must not decrease: {} after {}", values[0],
                              curve.displacement.back()));
    curve.displacement.push_back(values[0]);
    curve.load.push_back(values[1]);
  }
  if (!displacement_column)
    curve_error(display_name, line_number, "no header line with displacement_m and load_N");
  if (curve.displacement.size() < 2)
    curve_error(display_name, line_number, "a reference curve needs at least 2 rows");
  return curve;
}

LoadCurve read_load_curve(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError({Diagnostic{path, 0, 0, "", "reference curve not found or unreadable"}});
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_load_curve(buffer.str(), path);
}

CurveMisfit compare_curves(const LoadCurve& reference, const LoadCurve& simulated,
                           bool simulated_failed) {
  const std::vector<double>& us = simulated.displacement;
  const std::vector<double>& ps = simulated.load;
  auto simulated_load_at = [&](double u) {
    if (us.empty()) return 0.0;
    if (u <= us.front()) return ps.front();
    if (u > us.back()) return simulated_failed ? 0.0 : ps.back();
    const auto upper = std::lower_bound(us.begin(), us.end(), u);
    const auto i = static_cast<std::size_t>(upper - us.begin());
    const double span = us[i] - us[i - 1];
    if (!(span > 0.0)) return ps[i];
    const double t = (u - us[i - 1]) / span;
    return ps[i - 1] + t * (ps[i] - ps[i - 1]);
  };
  CurveMisfit m;
  double sum_squares = 0.0, reference_peak = 0.0;
  const std::size_t n = reference.displacement.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double difference = simulated_load_at(reference.displacement[i]) - reference.load[i];
    sum_squares += difference * difference;
    reference_peak = std::max(reference_peak, reference.load[i]);
  }
  m.rms_load = n > 0 ? std::sqrt(sum_squares / static_cast<double>(n)) : 0.0;
  m.relative_to_peak =
      reference_peak > 0.0 ? m.rms_load / reference_peak : std::numeric_limits<double>::infinity();
  return m;
}

// ---- optimisers -------------------------------------------------------------------------------

namespace {

/// Every point an optimiser has evaluated, so that none is evaluated twice: NLopt asks for one
/// point at a time, and for points already known (the scanned or first-simplex points the batch
/// ran beforehand, or a point it revisits) up to its own round-off, since it rescales internally.
/// Each evaluation is a whole simulation, so the distinct points are what counts.
class EvaluationMemo {
 public:
  /// `width`: the extent of the search box along each coordinate (the scale of round-off).
  EvaluationMemo(const BatchObjective& objective, std::vector<double> width, int max_evaluations)
      : objective_(objective), width_(std::move(width)), max_evaluations_(max_evaluations) {}

  /// Values of the points, the new ones evaluated in one batch (those beyond the budget are not
  /// evaluated: their value is infinite).
  std::vector<double> evaluate(const std::vector<std::vector<double>>& batch) {
    std::vector<double> values(batch.size(), std::numeric_limits<double>::infinity());
    std::vector<std::vector<double>> fresh;
    std::vector<std::size_t> fresh_slot;
    for (std::size_t j = 0; j < batch.size(); ++j) {
      if (const auto known = find(batch[j])) {
        values[j] = values_[*known];
      } else if (evaluations() + static_cast<int>(fresh.size()) < max_evaluations_) {
        fresh.push_back(batch[j]);
        fresh_slot.push_back(j);
      }
    }
    if (fresh.empty()) return values;
    const std::vector<double> fresh_values = objective_(fresh);
    for (std::size_t k = 0; k < fresh.size(); ++k) {
      points_.push_back(fresh[k]);
      values_.push_back(fresh_values[k]);
      values[fresh_slot[k]] = fresh_values[k];
    }
    return values;
  }

  std::optional<std::size_t> find(const std::vector<double>& point) const {
    for (std::size_t k = 0; k < points_.size(); ++k) {
      bool same = true;
      for (std::size_t i = 0; i < point.size(); ++i)
        same = same && std::abs(point[i] - points_[k][i]) <= 1e-12 * width_[i];
      if (same) return k;
    }
    return std::nullopt;
  }

  int evaluations() const { return static_cast<int>(points_.size()); }
  bool budget_spent() const { return evaluations() >= max_evaluations_; }

  /// What the optimiser sees: a failed trial (infinite misfit) becomes a large finite value, so
  /// that BOBYQA's quadratic model stays finite and the optimiser moves away from it.
  double penalised(double value) const {
    if (std::isfinite(value)) return value;
    double largest = 1.0;
    for (double v : values_)
      if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
    return 10.0 * largest;
  }

  MinimumFound best() const {
    MinimumFound found;
    found.evaluations = evaluations();
    if (values_.empty()) return found;
    const auto k = static_cast<std::size_t>(std::min_element(values_.begin(), values_.end()) -
                                            values_.begin());
    found.point = points_[k];
    found.value = values_[k];
    return found;
  }

 private:
  const BatchObjective& objective_;
  std::vector<double> width_;
  int max_evaluations_;
  std::vector<std::vector<double>> points_;
  std::vector<double> values_;
};

struct NloptCall {
  nlopt_opt opt;
  EvaluationMemo& memo;
  std::exception_ptr error;  ///< an exception of the objective, rethrown after nlopt_optimize
};

double nlopt_objective(unsigned n, const double* x, double* /*gradient: none*/, void* data) {
  auto& call = *static_cast<NloptCall*>(data);
  const std::vector<double> point(x, x + n);
  if (!call.memo.find(point) && call.memo.budget_spent()) {
    nlopt_force_stop(call.opt);
    return HUGE_VAL;
  }
  try {
    return call.memo.penalised(call.memo.evaluate({point})[0]);
  } catch (...) {  // no exception may cross NLopt's C code
    call.error = std::current_exception();
    nlopt_force_stop(call.opt);
    return HUGE_VAL;
  }
}

/// Runs NLopt's derivative-free `algorithm` in the box [lower, upper] from `start` with the first
/// steps `step`, until the points move less than `x_tolerance` in every coordinate, the values
/// differ by less than `value_tolerance` (0: not used), or the memo's budget is spent.
MinimumFound run_nlopt(nlopt_algorithm algorithm, EvaluationMemo& memo,
                       const std::vector<double>& lower, const std::vector<double>& upper,
                       std::vector<double> start, const std::vector<double>& step,
                       double x_tolerance, double value_tolerance) {
  const auto n = static_cast<unsigned>(start.size());
  const std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(algorithm, n),
                                                                   &nlopt_destroy);
  if (!opt) throw std::runtime_error("NLopt: cannot create the optimiser");
  NloptCall call{opt.get(), memo, nullptr};
  const bool set_up = nlopt_set_lower_bounds(opt.get(), lower.data()) == NLOPT_SUCCESS &&
                      nlopt_set_upper_bounds(opt.get(), upper.data()) == NLOPT_SUCCESS &&
                      nlopt_set_min_objective(opt.get(), nlopt_objective, &call) == NLOPT_SUCCESS &&
                      nlopt_set_initial_step(opt.get(), step.data()) == NLOPT_SUCCESS &&
                      nlopt_set_xtol_abs1(opt.get(), x_tolerance) == NLOPT_SUCCESS &&
                      nlopt_set_ftol_abs(opt.get(), value_tolerance) == NLOPT_SUCCESS;
  if (!set_up) throw std::logic_error(std::string("NLopt: ") + nlopt_get_errmsg(opt.get()));
  double value = 0.0;
  const nlopt_result outcome = nlopt_optimize(opt.get(), start.data(), &value);
  if (call.error) std::rethrow_exception(call.error);
  if (outcome == NLOPT_INVALID_ARGS || outcome == NLOPT_OUT_OF_MEMORY) {
    const char* message = nlopt_get_errmsg(opt.get());
    throw std::logic_error(std::string("NLopt: ") + (message ? message : "invalid arguments"));
  }
  MinimumFound found = memo.best();
  // Success, or stopped by a tolerance; not by the budget (a forced stop) or a failure.
  found.converged = outcome > 0 && outcome != NLOPT_MAXEVAL_REACHED;
  return found;
}

}  // namespace

MinimumFound minimise_scan_then_bobyqa(const BatchObjective& objective, double lower, double upper,
                                       int scan_points, double tolerance, int max_evaluations) {
  scan_points = std::max(scan_points, 3);
  std::vector<std::vector<double>> grid;
  for (int i = 0; i < scan_points; ++i)
    grid.push_back({lower + (upper - lower) * i / (scan_points - 1)});
  EvaluationMemo memo(objective, {upper - lower}, max_evaluations);
  const std::vector<double> scanned = memo.evaluate(grid);
  const auto best =
      static_cast<std::size_t>(std::min_element(scanned.begin(), scanned.end()) - scanned.begin());
  // BOBYQA (Powell 2009) between the neighbours of the best scanned point, started from it with
  // a first trust-region radius of half that bracket: its first interpolation points are then
  // scanned points (reused), and its quadratic model does what Brent's parabola did.
  const double a = grid[best == 0 ? 0 : best - 1][0];
  const double b = grid[std::min(best + 1, grid.size() - 1)][0];
  return run_nlopt(NLOPT_LN_BOBYQA, memo, {a}, {b}, grid[best], {0.5 * (b - a)}, tolerance, 0.0);
}

MinimumFound minimise_nelder_mead(const BatchObjective& objective, std::vector<double> start,
                                  double initial_step, double tolerance, double value_tolerance,
                                  int max_evaluations) {
  const std::size_t n = start.size();
  const std::vector<double> lower(n, 0.0), upper(n, 1.0);
  for (double& c : start)
    c = std::clamp(c, 0.0, 1.0);
  // The first simplex, the start and one step along each axis into the box (NLopt's own rule for
  // it, nldrmd.c, when the step stays inside), runs as one batch; NLopt then finds its values.
  std::vector<double> step(n);
  std::vector<std::vector<double>> simplex{start};
  for (std::size_t i = 0; i < n; ++i) {
    step[i] = start[i] > 0.5 ? -initial_step : initial_step;
    std::vector<double> vertex = start;
    vertex[i] += step[i];
    simplex.push_back(vertex);
  }
  EvaluationMemo memo(objective, std::vector<double>(n, 1.0), max_evaluations);
  memo.evaluate(simplex);
  return run_nlopt(NLOPT_LN_NELDERMEAD, memo, lower, upper, start, step, tolerance,
                   value_tolerance);
}

// ---- the command ------------------------------------------------------------------------------

namespace {

[[noreturn]] void option_error(const std::string& option, const std::string& message) {
  throw InputError({Diagnostic{"(command line)", 0, 0, option, message}});
}

void check_options(const CalibrationOptions& o) {
  if (o.fit != "lambda" && o.fit != "lambda_and_modulus")
    option_error("--fit", "must be lambda or lambda_and_modulus, got '" + o.fit + "'");
  // radius_multiplier: the case schema allows (0, 2].
  if (!(o.lambda_lower > 0.0 && o.lambda_lower < o.lambda_upper && o.lambda_upper <= 2.0))
    option_error("--lambda-range", fmt::format("needs 0 < lower < upper <= 2, got {} {}",
                                               o.lambda_lower, o.lambda_upper));
  if (!(o.modulus_lower > 0.0 && o.modulus_lower < o.modulus_upper))
    option_error("--modulus-range", fmt::format("needs 0 < lower < upper, got {} {}",
                                                o.modulus_lower, o.modulus_upper));
  if (o.scan_points < 3) option_error("--scan", "needs at least 3 points");
  if (!(o.lambda_tolerance > 0.0)) option_error("--tolerance", "must be positive");
  if (!(o.modulus_tolerance > 0.0)) option_error("--modulus-tolerance", "must be positive");
  if (!(o.misfit_tolerance >= 0.0)) option_error("--misfit-tolerance", "must not be negative");
  if (o.max_evaluations < o.scan_points)
    option_error("--max-evaluations", "must be at least the number of scan points");
}

/// Index of the bond to fit: the named one, or the only bond the rings use.
std::size_t fitted_bond_index(const CaseConfig& config, const std::string& name) {
  if (!name.empty()) {
    for (std::size_t i = 0; i < config.bonds.size(); ++i)
      if (config.bonds[i].name == name) return i;
    option_error("--bond", "the case has no bond named '" + name + "'");
  }
  std::vector<std::size_t> used;
  for (std::size_t i = 0; i < config.bonds.size(); ++i)
    for (const RingConfig& r : config.rings)
      if (r.bond == config.bonds[i].name) {
        used.push_back(i);
        break;
      }
  if (used.size() != 1)
    option_error("--bond", fmt::format("the rings use {} bonds; name the one to fit", used.size()));
  return used.front();
}

/// gamma and eta of a bond (physics.md §2) for lambda and E_b, when it has `derive_from`.
std::optional<RingReductionFactors> reduction_factors(const BondConfig& bond, double lambda) {
  if (!bond.derive_from || bond.derived_particle_radius <= 0.0) return std::nullopt;
  return ring_reduction_factors(bond.derive_from->windings, 0.5 * bond.derive_from->wire_diameter,
                                bond.derived_particle_radius, lambda,
                                bond.derive_from->steel_youngs_modulus);
}

LoadCurve curve_of(const TensileResult& r) {
  LoadCurve c;
  for (const TensileSample& s : r.curve) {
    c.displacement.push_back(s.displacement);
    c.load.push_back(s.load);
  }
  return c;
}

}  // namespace

CalibrationResult run_calibration(const CalibrationOptions& options, const Communicator& world) {
  const auto wall_start = WallClock::now();
  check_options(options);
  CaseConfig base = load_case(options.case_path, options.overrides);
  if (scenario_kind(base) != ScenarioKind::kTensileTest)
    throw InputError({Diagnostic{options.case_path, 0, 0, "scenario.type",
                                 "ringdem calibrate fits a tensile test; the case's scenario.type "
                                 "is " +
                                     base.scenario.type}});
  const std::size_t bond_index = fitted_bond_index(base, options.bond);
  const BondConfig& bond = base.bonds[bond_index];
  const bool fit_modulus = options.fit == "lambda_and_modulus";
  const bool modulus_from_eq17 = !fit_modulus && bond.derive_from.has_value();
  const LoadCurve reference = read_load_curve(options.reference_path);
  const double reference_peak = *std::max_element(reference.load.begin(), reference.load.end());
  if (!(reference_peak > 0.0))
    throw InputError({Diagnostic{options.reference_path, 0, 0, "",
                                 "the reference load is never "
                                 "positive"}});
  // Nothing beyond the reference's range is compared: stop each trial just past it.
  TensileTestConfig& test = base.scenario.tensile_test;
  test.max_displacement = reference.displacement.back() + test.record_interval;

  const std::string out_dir =
      options.output_dir.empty() ? "results/" + base.name + "_calibration" : options.output_dir;
  const bool print = world.is_root() && !options.quiet;
  // Held to the end of the fit: no second calibration into this folder (app/OutputLock.hpp).
  const OutputLock lock = lock_output_folder(out_dir, world, options.break_lock);
  if (world.is_root()) std::filesystem::create_directories(out_dir + "/evaluations");
  if (print) {
    fmt::print(
        "ringdem {} calibrate: case {} ({}), reference {} ({} points, {:.4g} to {:.4g} mm, "
        "peak {:.4g} kN), {} rank{}\n",
        kVersion, base.name, options.case_path, options.reference_path,
        reference.displacement.size(), 1e3 * reference.displacement.front(),
        1e3 * reference.displacement.back(), 1e-3 * reference_peak, world.size(),
        world.size() == 1 ? "" : "s");
    fmt::print("fit {} of bond '{}': lambda in [{}, {}]", options.fit, bond.name,
               options.lambda_lower, options.lambda_upper);
    if (fit_modulus)
      fmt::print(", E_b in [{:.4g}, {:.4g}] GPa (log scale)", 1e-9 * options.modulus_lower,
                 1e-9 * options.modulus_upper);
    else if (modulus_from_eq17)
      fmt::print(", E_b from Eq. 17 ({} windings of {:.4g} mm wire)", bond.derive_from->windings,
                 1e3 * bond.derive_from->wire_diameter);
    else
      fmt::print(", E_b held at {:.4g} GPa (the bond has no derive_from)",
                 1e-9 * bond.youngs_modulus);
    fmt::print("; each trial pulls at {:.4g} m/s to {:.4g} mm; output in {}\n", test.loading_rate,
               1e3 * test.max_displacement, out_dir);
    std::fflush(stdout);
  }
  world.barrier();

  // The bond modulus of a trial.
  auto modulus_for = [&](double lambda, double free_modulus) {
    if (fit_modulus) return free_modulus;
    if (modulus_from_eq17) return reduction_factors(bond, lambda)->bond_youngs_modulus;
    return bond.youngs_modulus;
  };

  CalibrationResult result;
  const Communicator self = Communicator::self();
  // Runs the trials (lambda, E_b) not run before, trial j of the batch on rank j mod size;
  // every rank gets every misfit (relative to the reference peak). A rank runs its trials one
  // after the other with no collective between them, and one gather at the end of the batch
  // hands every rank every result: a reduction after each trial made each rank wait for the
  // others' trials before its next, which ran a batch one trial at a time on any rank count.
  struct TrialOutcome {
    std::uint64_t slot;
    double rms, relative, peak, wall;
  };
  auto run_trials = [&](const std::vector<std::pair<double, double>>& trials) {
    std::vector<double> misfits(trials.size());
    std::vector<std::size_t> to_run;
    for (std::size_t j = 0; j < trials.size(); ++j) {
      const auto previous =
          std::find_if(result.evaluations.begin(), result.evaluations.end(), [&](const auto& ev) {
            return ev.radius_multiplier == trials[j].first &&
                   ev.bond_youngs_modulus == trials[j].second;
          });
      if (previous != result.evaluations.end())
        misfits[j] = previous->misfit.relative_to_peak;
      else
        to_run.push_back(j);
    }
    const std::size_t first_evaluation = result.evaluations.size();
    auto folder_of = [&](std::size_t slot) {
      return fmt::format("evaluations/eval_{:03}", first_evaluation + slot);
    };
    std::vector<TrialOutcome> mine;
    for (std::size_t slot = static_cast<std::size_t>(world.rank()); slot < to_run.size();
         slot += static_cast<std::size_t>(world.size())) {
      const std::pair<double, double>& t = trials[to_run[slot]];
      const std::string folder = folder_of(slot);
      CaseConfig trial = base;
      trial.name = base.name + "_" + folder.substr(folder.find('/') + 1);
      BondConfig& b = trial.bonds[bond_index];
      b.radius_multiplier = t.first;
      b.youngs_modulus = t.second;
      if (fit_modulus) b.derive_from.reset();
      TensileRunOptions run;
      run.output_dir = out_dir + "/" + folder;
      run.verbose = false;
      TrialOutcome outcome{slot, 0.0, 0.0, 0.0, 0.0};
      try {
        const TensileResult r = run_tensile_test(trial, run, self);
        const CurveMisfit m = compare_curves(reference, curve_of(r),
                                             r.stop_reason == TensileStopRule::Reason::kFailure);
        outcome = {slot, m.rms_load, m.relative_to_peak, r.analysis.peak_load, r.wall_time};
      } catch (const std::exception& e) {  // a trial that blows up is a bad trial
        fmt::print(stderr, "calibrate: trial lambda = {} failed on rank {}: {}\n", t.first,
                   world.rank(), e.what());
        const double bad = std::numeric_limits<double>::infinity();
        outcome = {slot, bad, bad, 0.0, 0.0};
      }
      mine.push_back(outcome);
      // Printed as each trial ends, by the rank that ran it: numbered, as ranks interleave.
      if (!options.quiet) {
        fmt::print(
            "eval {:3}: lambda = {:.5f}  E_b = {:7.2f} GPa  misfit {:9.4f} kN "
            "({:6.3f} % of the reference peak)  peak {:8.3f} kN  {:.1f} s\n",
            first_evaluation + slot, t.first, 1e-9 * t.second, 1e-3 * outcome.rms,
            100.0 * outcome.relative, 1e-3 * outcome.peak, outcome.wall);
        std::fflush(stdout);
      }
    }
    std::vector<TrialOutcome> outcomes(to_run.size());
    for (const TrialOutcome& o : world.allgather(mine))
      outcomes[o.slot] = o;
    for (std::size_t slot = 0; slot < to_run.size(); ++slot) {
      const std::size_t j = to_run[slot];
      CalibrationEvaluation ev;
      ev.radius_multiplier = trials[j].first;
      ev.bond_youngs_modulus = trials[j].second;
      ev.folder = folder_of(slot);
      ev.misfit.rms_load = outcomes[slot].rms;
      ev.misfit.relative_to_peak = outcomes[slot].relative;
      ev.peak_load = outcomes[slot].peak;
      ev.wall_time = outcomes[slot].wall;
      misfits[j] = ev.misfit.relative_to_peak;
      result.evaluations.push_back(ev);
    }
    return misfits;
  };

  const double log_modulus_span = std::log(options.modulus_upper / options.modulus_lower);
  // Unit-box coordinates of the two-parameter fit: lambda linear, E_b logarithmic.
  auto trial_of_unit_point = [&](const std::vector<double>& u) {
    const double lambda =
        options.lambda_lower + u[0] * (options.lambda_upper - options.lambda_lower);
    const double modulus = options.modulus_lower * std::exp(u[1] * log_modulus_span);
    return std::make_pair(lambda, modulus);
  };

  if (fit_modulus) {
    const BatchObjective objective = [&](const std::vector<std::vector<double>>& points) {
      std::vector<std::pair<double, double>> trials;
      for (const auto& u : points)
        trials.push_back(trial_of_unit_point(u));
      return run_trials(trials);
    };
    const double lambda_span = options.lambda_upper - options.lambda_lower;
    const std::vector<double> start{
        (bond.radius_multiplier - options.lambda_lower) / lambda_span,
        std::log(bond.youngs_modulus / options.modulus_lower) / log_modulus_span};
    const double tolerance = std::min(options.lambda_tolerance / lambda_span,
                                      options.modulus_tolerance / log_modulus_span);
    const MinimumFound found = minimise_nelder_mead(
        objective, start, 0.25, tolerance, options.misfit_tolerance, options.max_evaluations);
    result.converged = found.converged;
  } else {
    const BatchObjective objective = [&](const std::vector<std::vector<double>>& points) {
      std::vector<std::pair<double, double>> trials;
      for (const auto& p : points)
        trials.emplace_back(p[0], modulus_for(p[0], 0.0));
      return run_trials(trials);
    };
    const MinimumFound found = minimise_scan_then_bobyqa(
        objective, options.lambda_lower, options.lambda_upper, options.scan_points,
        options.lambda_tolerance, options.max_evaluations);
    result.converged = found.converged;
  }
  result.best = *std::min_element(result.evaluations.begin(), result.evaluations.end(),
                                  [](const auto& a, const auto& b) {
                                    return a.misfit.relative_to_peak < b.misfit.relative_to_peak;
                                  });
  const std::optional<RingReductionFactors> factors =
      reduction_factors(bond, result.best.radius_multiplier);
  if (factors) {
    result.gamma = factors->gamma;
    result.eta = result.best.bond_youngs_modulus / bond.derive_from->steel_youngs_modulus;
  }
  world.barrier();  // every trial's files are written

  if (world.is_root()) {
    const auto copy = [&](const std::string& from, const std::string& to) {
      std::filesystem::copy_file(out_dir + "/" + result.best.folder + "/" + from,
                                 out_dir + "/" + to,
                                 std::filesystem::copy_options::overwrite_existing);
    };
    copy("series.csv", "best_series.csv");
    copy("summary.json", "best_summary.json");
    std::ofstream table(out_dir + "/evaluations.csv");
    table << "evaluation,radius_multiplier,bond_youngs_modulus_Pa,misfit_rms_N,"
             "misfit_relative_to_peak,peak_load_N,wall_time_s,folder\n";
    std::vector<double> lambdas, moduli, misfits;
    for (std::size_t k = 0; k < result.evaluations.size(); ++k) {
      const CalibrationEvaluation& ev = result.evaluations[k];
      table << fmt::format("{},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.4g},{}\n", k,
                           ev.radius_multiplier, ev.bond_youngs_modulus, ev.misfit.rms_load,
                           ev.misfit.relative_to_peak, ev.peak_load, ev.wall_time, ev.folder);
      lambdas.push_back(ev.radius_multiplier);
      moduli.push_back(ev.bond_youngs_modulus);
      misfits.push_back(ev.misfit.rms_load);
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    JsonObject history;
    history.set("radius_multiplier", lambdas)
        .set("bond_youngs_modulus_Pa", moduli)
        .set("misfit_rms_N", misfits);
    JsonObject json;
    json.set("ringdem_version", kVersion)
        .set("case", base.name)
        .set("case_file", options.case_path)
        .set("reference", options.reference_path)
        .set("reference_points", static_cast<long long>(reference.displacement.size()))
        .set("reference_peak_load_N", reference_peak)
        .set("fit", options.fit)
        .set("bond", bond.name)
        .set("modulus_rule", fit_modulus         ? "fitted"
                             : modulus_from_eq17 ? "eq17_from_derive_from"
                                                 : "held_at_case_value")
        .set("radius_multiplier", result.best.radius_multiplier)
        .set("bond_youngs_modulus_Pa", result.best.bond_youngs_modulus)
        .set("gamma", result.gamma ? *result.gamma : nan)
        .set("eta", result.eta ? *result.eta : nan)
        .set("axial_stiffness_ratio",
             result.gamma ? 5.0 * *result.eta * *result.gamma * *result.gamma : nan)
        .set("misfit_rms_N", result.best.misfit.rms_load)
        .set("misfit_relative_to_peak", result.best.misfit.relative_to_peak)
        .set("best_evaluation", result.best.folder)
        .set("evaluations", static_cast<long long>(result.evaluations.size()))
        .set("converged", result.converged)
        .set("lambda_range", std::vector<double>{options.lambda_lower, options.lambda_upper})
        .set("modulus_range_Pa",
             fit_modulus ? std::vector<double>{options.modulus_lower, options.modulus_upper}
                         : std::vector<double>{})
        .set("loading_rate_m_per_s", test.loading_rate)
        .set("max_displacement_m", test.max_displacement)
        .set("ranks", world.size())
        .set("wall_time_s", seconds_since(wall_start))
        .set("history", history);
    json.write(out_dir + "/calibration.json");
  }
  if (print) {
    fmt::print("fitted: lambda = {:.5f}, E_b = {:.4g} GPa", result.best.radius_multiplier,
               1e-9 * result.best.bond_youngs_modulus);
    if (result.gamma)
      fmt::print(", gamma = {:.4f}, eta = {:.4f}, 5 eta gamma^2 = {:.4f}", *result.gamma,
                 *result.eta, 5.0 * *result.eta * *result.gamma * *result.gamma);
    fmt::print("\nmisfit {:.4g} kN RMS ({:.3f} % of the reference peak), {} runs, {}, {}\n",
               1e-3 * result.best.misfit.rms_load, 100.0 * result.best.misfit.relative_to_peak,
               result.evaluations.size(),
               result.converged ? "converged" : "NOT converged (evaluation budget spent)",
               format_duration(seconds_since(wall_start)));
    fmt::print("results: {0}/calibration.json, {0}/evaluations.csv, {0}/best_series.csv\n",
               out_dir);
  }
  return result;
}

}  // namespace ringdem
