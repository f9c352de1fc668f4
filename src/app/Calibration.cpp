#include "app/Calibration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "app/RunCommand.hpp"
#include "app/ScenarioDriver.hpp"
#include "app/TensileTest.hpp"
#include "core/Version.hpp"
#include "domain/RingGenerator.hpp"
#include "io/CaseLoader.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

// ---- reference curve --------------------------------------------------------------------------

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ','))
    cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

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

MinimumFound minimise_scan_then_brent(const BatchObjective& objective, double lower, double upper,
                                      int scan_points, double tolerance, int max_evaluations) {
  scan_points = std::max(scan_points, 3);
  std::vector<std::vector<double>> grid;
  for (int i = 0; i < scan_points; ++i)
    grid.push_back({lower + (upper - lower) * i / (scan_points - 1)});
  const std::vector<double> scanned = objective(grid);
  MinimumFound found;
  found.evaluations = scan_points;
  const auto best =
      static_cast<std::size_t>(std::min_element(scanned.begin(), scanned.end()) - scanned.begin());
  // Brent's method (Brent 1973, "fmin") on the bracket around the best scanned point, started
  // from it: x the best point so far, w the second best, v the previous w.
  double a = grid[best == 0 ? 0 : best - 1][0];
  double b = grid[std::min(best + 1, grid.size() - 1)][0];
  double x = grid[best][0], w = x, v = x;
  double fx = scanned[best], fw = fx, fv = fx;
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  const double eps = std::sqrt(std::numeric_limits<double>::epsilon());
  double d = 0.0, e = 0.0;
  while (true) {
    const double middle = 0.5 * (a + b);
    const double tol1 = eps * std::abs(x) + tolerance / 3.0, tol2 = 2.0 * tol1;
    if (std::abs(x - middle) <= tol2 - 0.5 * (b - a)) {
      found.converged = true;
      break;
    }
    if (found.evaluations >= max_evaluations) break;
    bool golden_step = true;
    if (std::abs(e) > tol1) {  // try a parabola through x, w, v
      double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      r = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * r) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = middle > x ? tol1 : -tol1;
        golden_step = false;
      }
    }
    if (golden_step) {
      e = (x < middle ? b : a) - x;
      d = golden * e;
    }
    const double u = x + (std::abs(d) >= tol1 ? d : (d > 0.0 ? tol1 : -tol1));
    const double fu = objective({{u}})[0];
    ++found.evaluations;
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w;
      fv = fw;
      w = x;
      fw = fx;
      x = u;
      fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w;
        fv = fw;
        w = u;
        fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u;
        fv = fu;
      }
    }
  }
  found.point = {x};
  found.value = fx;
  return found;
}

MinimumFound minimise_nelder_mead(const BatchObjective& objective, std::vector<double> start,
                                  double initial_step, double tolerance, double value_tolerance,
                                  int max_evaluations) {
  const std::size_t n = start.size();
  auto clamp_to_box = [](std::vector<double> p) {
    for (double& c : p)
      c = std::clamp(c, 0.0, 1.0);
    return p;
  };
  start = clamp_to_box(start);
  std::vector<std::vector<double>> simplex{start};
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> vertex = start;
    vertex[i] += vertex[i] > 0.5 ? -initial_step : initial_step;  // step into the box
    simplex.push_back(clamp_to_box(vertex));
  }
  std::vector<double> values = objective(simplex);
  MinimumFound found;
  found.evaluations = static_cast<int>(simplex.size());
  auto combine = [&](const std::vector<double>& from, const std::vector<double>& to, double t) {
    std::vector<double> p(n);
    for (std::size_t i = 0; i < n; ++i)
      p[i] = from[i] + t * (to[i] - from[i]);
    return clamp_to_box(p);
  };
  while (true) {
    std::vector<std::size_t> order(simplex.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t i, std::size_t j) { return values[i] < values[j]; });
    std::vector<std::vector<double>> sorted_simplex;
    std::vector<double> sorted_values;
    for (std::size_t i : order) {
      sorted_simplex.push_back(simplex[i]);
      sorted_values.push_back(values[i]);
    }
    simplex = std::move(sorted_simplex);
    values = std::move(sorted_values);
    double size = 0.0;
    for (std::size_t k = 1; k < simplex.size(); ++k)
      for (std::size_t i = 0; i < n; ++i)
        size = std::max(size, std::abs(simplex[k][i] - simplex[0][i]));
    if (size <= tolerance || values[n] - values[0] <= value_tolerance) {
      found.converged = true;
      break;
    }
    if (found.evaluations >= max_evaluations) break;
    std::vector<double> centroid(n, 0.0);
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t i = 0; i < n; ++i)
        centroid[i] += simplex[k][i] / static_cast<double>(n);
    const std::vector<double>& worst = simplex[n];
    const std::vector<double> reflected = combine(centroid, worst, -1.0);
    const double f_reflected = objective({reflected})[0];
    ++found.evaluations;
    if (f_reflected < values[0]) {
      const std::vector<double> expanded = combine(centroid, worst, -2.0);
      const double f_expanded = objective({expanded})[0];
      ++found.evaluations;
      if (f_expanded < f_reflected) {
        simplex[n] = expanded;
        values[n] = f_expanded;
      } else {
        simplex[n] = reflected;
        values[n] = f_reflected;
      }
      continue;
    }
    if (f_reflected < values[n - 1]) {
      simplex[n] = reflected;
      values[n] = f_reflected;
      continue;
    }
    // Contract towards the better of the worst and the reflected point.
    const bool outside = f_reflected < values[n];
    const std::vector<double> contracted =
        outside ? combine(centroid, reflected, 0.5) : combine(centroid, worst, 0.5);
    const double f_contracted = objective({contracted})[0];
    ++found.evaluations;
    if (f_contracted < std::min(f_reflected, values[n])) {
      simplex[n] = contracted;
      values[n] = f_contracted;
      continue;
    }
    // Shrink every vertex towards the best one (one batch).
    std::vector<std::vector<double>> shrunk;
    for (std::size_t k = 1; k <= n; ++k)
      shrunk.push_back(combine(simplex[0], simplex[k], 0.5));
    const std::vector<double> shrunk_values = objective(shrunk);
    found.evaluations += static_cast<int>(n);
    for (std::size_t k = 1; k <= n; ++k) {
      simplex[k] = shrunk[k - 1];
      values[k] = shrunk_values[k - 1];
    }
  }
  const auto best =
      static_cast<std::size_t>(std::min_element(values.begin(), values.end()) - values.begin());
  found.point = simplex[best];
  found.value = values[best];
  return found;
}

// ---- the command ------------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;

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

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

CalibrationResult run_calibration(const CalibrationOptions& options, const Communicator& world) {
  const auto wall_start = Clock::now();
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
  const double lowest = -std::numeric_limits<double>::infinity();
  // Runs the trials (lambda, E_b) not run before, trial j of the batch on rank j mod size;
  // every rank gets every misfit (relative to the reference peak).
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
    for (std::size_t slot = 0; slot < to_run.size(); ++slot) {
      const std::size_t j = to_run[slot];
      CalibrationEvaluation ev;
      ev.radius_multiplier = trials[j].first;
      ev.bond_youngs_modulus = trials[j].second;
      ev.folder = fmt::format("evaluations/eval_{:03}", result.evaluations.size());
      double rms = lowest, relative = lowest, peak = lowest, wall = lowest;
      if (static_cast<int>(slot % static_cast<std::size_t>(world.size())) == world.rank()) {
        CaseConfig trial = base;
        trial.name = base.name + "_" + ev.folder.substr(ev.folder.find('/') + 1);
        BondConfig& b = trial.bonds[bond_index];
        b.radius_multiplier = ev.radius_multiplier;
        b.youngs_modulus = ev.bond_youngs_modulus;
        if (fit_modulus) b.derive_from.reset();
        TensileRunOptions run;
        run.output_dir = out_dir + "/" + ev.folder;
        run.verbose = false;
        try {
          const TensileResult r = run_tensile_test(trial, run, self);
          const CurveMisfit m = compare_curves(reference, curve_of(r),
                                               r.stop_reason == TensileStopRule::Reason::kFailure);
          rms = m.rms_load;
          relative = m.relative_to_peak;
          peak = r.analysis.peak_load;
          wall = r.wall_time;
        } catch (const std::exception& e) {  // a trial that blows up is a bad trial
          fmt::print(stderr, "calibrate: trial lambda = {} failed on rank {}: {}\n",
                     ev.radius_multiplier, world.rank(), e.what());
          rms = relative = std::numeric_limits<double>::infinity();
          peak = wall = 0.0;
        }
      }
      ev.misfit.rms_load = world.max(rms);
      ev.misfit.relative_to_peak = world.max(relative);
      ev.peak_load = world.max(peak);
      ev.wall_time = world.max(wall);
      misfits[j] = ev.misfit.relative_to_peak;
      result.evaluations.push_back(ev);
      if (print) {
        fmt::print(
            "eval {:3}: lambda = {:.5f}  E_b = {:7.2f} GPa  misfit {:9.4f} kN "
            "({:6.3f} % of the reference peak)  peak {:8.3f} kN  {:.1f} s\n",
            result.evaluations.size() - 1, ev.radius_multiplier, 1e-9 * ev.bond_youngs_modulus,
            1e-3 * ev.misfit.rms_load, 100.0 * ev.misfit.relative_to_peak, 1e-3 * ev.peak_load,
            ev.wall_time);
        std::fflush(stdout);
      }
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
    const MinimumFound found = minimise_scan_then_brent(
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
