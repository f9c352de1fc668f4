#include "app/TensileTest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "app/ScenarioRunner.hpp"
#include "app/TensileDriver.hpp"

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

void TensileMeter::restore_start_positions(const std::vector<Vec3>& start) {
  if (start.size() != start_.size())
    throw std::invalid_argument("tensile test: the checkpoint has another number of moving bodies");
  start_ = start;
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
    case TensileStopRule::Reason::kUnloaded:
      return "unloaded";
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

TensileResult run_tensile_test(const CaseConfig& config, const TensileRunOptions& options,
                               const Communicator& comm) {
  std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(config);
  auto* tensile = dynamic_cast<TensileDriver*>(driver.get());
  if (!tensile) throw std::invalid_argument("case '" + config.name + "' is not a tensile test");
  ScenarioRunOptions run;
  run.output_dir = options.output_dir;
  run.verbose = options.verbose;
  // The many short runs of a sweep or calibration cannot be continued one by one.
  run.handle_stop_requests = false;
  run_scenario(*tensile, run, comm);
  return tensile->result();
}

}  // namespace ringdem
