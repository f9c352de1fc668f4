#pragma once

/// `ringdem calibrate CASE --reference curve.csv`: fits the bond radius multiplier lambda (E_b
/// then from Eq. 17 when the bond has `derive_from`, physics.md §2), or lambda and E_b both, to
/// a measured load-displacement curve by running the tensile test of the case for each trial
/// (the paper's "Model Calibration", Fig. 10, Table 3). docs/tensile.md describes the command
/// and its outputs.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"

namespace ringdem {

/// A load-displacement curve, displacements non-decreasing.
struct LoadCurve {
  std::vector<double> displacement;  ///< m
  std::vector<double> load;          ///< N
};

/// Reads a CSV file with a header naming the columns `displacement_m` and `load_N` (others are
/// ignored, so the series.csv of a tensile test is accepted); blank lines and lines starting
/// with '#' are skipped. Throws InputError (file and line) when a column is missing, a value is
/// not a number, the displacements decrease, or there are fewer than 2 rows.
LoadCurve read_load_curve(const std::string& path);
LoadCurve parse_load_curve(const std::string& csv_text, const std::string& display_name);

/// How far a simulated curve is from the reference, at the reference's points.
struct CurveMisfit {
  double rms_load = 0.0;        ///< N: sqrt(mean over the reference points of (P_sim - P_ref)^2)
  double relative_to_peak = 0;  ///< rms_load / largest reference load
};

/// The simulated load is interpolated linearly at each reference displacement (held at its
/// first value before the simulated curve starts). Beyond the end of the simulated curve the
/// load is 0 when `simulated_failed` (the ring broke) and the last simulated load otherwise.
CurveMisfit compare_curves(const LoadCurve& reference, const LoadCurve& simulated,
                           bool simulated_failed);

// ---- optimisers over a batch evaluator ----------------------------------------------------------

/// Evaluates the objective at several points at once (they may run in parallel); returns one
/// value per point, in order.
using BatchObjective =
    std::function<std::vector<double>(const std::vector<std::vector<double>>& points)>;

struct MinimumFound {
  std::vector<double> point;
  double value = 0.0;
  int evaluations = 0;
  bool converged = false;  ///< tolerance reached before the evaluation budget ran out
};

/// One variable on [lower, upper]: the objective at `scan_points` evenly spaced points (one
/// batch), then NLopt's BOBYQA (a bounded quadratic-model method) between the neighbours of the
/// best of them, until the steps are below `tolerance` or `max_evaluations` points are spent.
/// No point is evaluated twice (within round-off); after the scan, one point per batch.
MinimumFound minimise_scan_then_bobyqa(const BatchObjective& objective, double lower, double upper,
                                       int scan_points, double tolerance, int max_evaluations);

/// NLopt's Nelder-Mead simplex in the unit box [0, 1]^n (reflections pinned onto its faces),
/// from `start` with initial steps `initial_step` along each axis, into the box (the first
/// simplex is one batch); stops when every vertex is within `tolerance` of the simplex's centroid
/// in each coordinate, when the objective differs by less than `value_tolerance` over the
/// vertices, or after `max_evaluations` points. No point is evaluated twice (within round-off).
MinimumFound minimise_nelder_mead(const BatchObjective& objective, std::vector<double> start,
                                  double initial_step, double tolerance, double value_tolerance,
                                  int max_evaluations);

// ---- the command ------------------------------------------------------------------------------

struct CalibrationOptions {
  std::string case_path;
  std::string reference_path;
  std::string fit = "lambda";  ///< lambda | lambda_and_modulus
  std::string output_dir;      ///< empty: results/<case name>_calibration
  std::vector<std::string> overrides;
  std::string bond;  ///< name of the fitted bond; empty: the only bond used by the rings
  double lambda_lower = 0.2, lambda_upper = 1.0;
  double modulus_lower = 40e9, modulus_upper = 600e9;
  int scan_points = 5;              ///< lambda fit: evenly spaced first evaluations
  double lambda_tolerance = 1e-3;   ///< on lambda (absolute)
  double modulus_tolerance = 2e-3;  ///< on log(E_b) (relative change of E_b)
  /// Two-parameter fit: also stop when the misfits of the simplex differ by at most this
  /// (relative to the reference peak): the simulated curves carry noise of about 0.1 % of the
  /// peak (the ring slipping on a pin shifts a little with the parameters), which no parameter
  /// change below it can resolve.
  double misfit_tolerance = 2e-3;
  int max_evaluations = 40;
  bool quiet = false;
  bool break_lock = false;  ///< take over a lock of the output folder held on another host
};

/// One trial of the calibration.
struct CalibrationEvaluation {
  double radius_multiplier = 0.0;
  double bond_youngs_modulus = 0.0;
  CurveMisfit misfit;
  double peak_load = 0.0;
  double wall_time = 0.0;
  std::string folder;  ///< where its series.csv and summary.json are, relative to the output
};

struct CalibrationResult {
  CalibrationEvaluation best;
  std::vector<CalibrationEvaluation> evaluations;
  bool converged = false;
  /// gamma and eta of the best values (physics.md §2), when the bond has `derive_from`.
  std::optional<double> gamma, eta;
};

/// Runs the calibration; every rank calls it with the same options. Evaluations that can run
/// together (the lambda scan, the first simplex) are spread over the ranks, each on its own
/// (Communicator::self()), and give the same evaluations on any rank count. Each evaluation is
/// printed by the rank that ran it as it ends; rank 0 writes OUT/calibration.json,
/// OUT/evaluations.csv, OUT/best_series.csv and OUT/best_summary.json; every trial's curve is in
/// OUT/evaluations/eval_NNN/. Throws InputError for a bad case, reference or option.
CalibrationResult run_calibration(const CalibrationOptions& options, const Communicator& world);

}  // namespace ringdem
