#pragma once

/// The paper's quasi-static ring tensile test ("DEM Modeling of a Tensile Test", Figs. 5-11):
/// pins on a moving plate pull a ring (or a group of rings) held by pins on a fixed plate.
/// docs/tensile.md describes the case keys, the stopping rule and every output.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/RigidBody.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem {

/// Load and displacement of the moving plate. The load is the contact force of the particles
/// on the moving pins, against the pull direction (a ring pulled upwards pulls the pins down),
/// summed over the pins; the displacement is the pins' mean travel along the pull direction
/// since the meter was created.
class TensileMeter {
 public:
  /// `bodies` must hold every name of `moving_bodies`; throws std::invalid_argument otherwise.
  TensileMeter(const std::vector<RigidBody>& bodies, const std::vector<std::string>& moving_bodies,
               const Vec3& pull_direction);

  double load(const std::vector<RigidBody>& bodies) const;
  double displacement(const std::vector<RigidBody>& bodies) const;

  /// Where the moving bodies were when the meter was created (checkpoints save them).
  const std::vector<Vec3>& start_positions() const { return start_; }
  /// A restart: the start positions of the meter that was checkpointed.
  void restore_start_positions(const std::vector<Vec3>& start);

 private:
  std::vector<std::size_t> moving_;
  std::vector<Vec3> start_;
  Vec3 direction_;
};

/// Decides when a test is over: failure (a bond broke and the load fell below
/// `failure_load_fraction` of the peak seen so far) or the plate reached `max_displacement`.
/// The driver feeds it the rows of series.csv (loads averaged over a record interval).
class TensileStopRule {
 public:
  /// kUnloaded: the plate turned at unload_at and the load fell to zero (the driver decides it).
  enum class Reason { kRunning, kFailure, kMaxDisplacement, kUnloaded };

  TensileStopRule(double failure_load_fraction, double max_displacement)
      : fraction_(failure_load_fraction), max_displacement_(max_displacement) {}

  /// Feeds one step; returns the reason to stop (kRunning: go on).
  Reason update(double displacement, double load, std::int64_t broken_bonds);

  double peak_load() const { return peak_load_; }
  double displacement_at_peak() const { return displacement_at_peak_; }
  /// A restart: the peak seen before the checkpoint.
  void restore_peak(double peak_load, double displacement_at_peak) {
    peak_load_ = peak_load;
    displacement_at_peak_ = displacement_at_peak;
  }

 private:
  double fraction_;
  double max_displacement_;
  double peak_load_ = 0.0;
  double displacement_at_peak_ = 0.0;
};

const char* stop_reason_name(TensileStopRule::Reason reason);

/// Continuous two-segment line P = c + s1 min(u - u_b, 0) + s2 max(u - u_b, 0) fitted by least
/// squares, u_b at one of the samples.
struct HingeFit {
  double breakpoint = 0.0;          ///< u_b
  double load_at_breakpoint = 0.0;  ///< c
  double bending_stiffness = 0.0;   ///< s1
  double tensile_stiffness = 0.0;   ///< s2
  double residual = 0.0;            ///< sum of squared load errors
};

/// Best hinge fit over breakpoints at samples 2 .. n-3; empty for fewer than 5 samples.
std::optional<HingeFit> fit_hinge(const std::vector<double>& displacement,
                                  const std::vector<double>& load);

/// What the load-displacement curve says (validation.md §2-3).
struct TensileCurveAnalysis {
  double peak_load = 0.0;
  double displacement_at_peak = 0.0;
  std::size_t peak_index = 0;
  /// Start of the tensile stage: the breakpoint of the hinge fit (fit_hinge) of the curve from
  /// its start to the peak, when its second segment is the stiffer one; empty otherwise.
  std::optional<double> stage_transition_displacement;
  double bending_stage_stiffness = 0.0;  ///< slope of the hinge fit before the breakpoint
  double tensile_stage_stiffness = 0.0;  ///< slope after it
};

/// Peak load and stage transition of a curve sampled at increasing displacements.
TensileCurveAnalysis analyse_tensile_curve(const std::vector<double>& displacement,
                                           const std::vector<double>& load);

/// One recorded row of the test.
struct TensileSample {
  double time = 0.0;
  double displacement = 0.0;
  double load = 0.0;
  std::int64_t broken_bonds = 0;
};

struct TensileResult {
  std::vector<TensileSample> curve;
  TensileCurveAnalysis analysis;
  TensileStopRule::Reason stop_reason = TensileStopRule::Reason::kRunning;
  std::optional<double> elongation_at_failure;  ///< displacement when the first bond broke
  /// Unloading (unload_at): where the plate turned, and its displacement at the first step at
  /// which the load was zero again (the ring's permanent elongation).
  std::optional<double> turn_displacement;
  std::optional<double> residual_displacement;
  std::optional<double> first_bond_break_time;
  std::int64_t broken_bonds = 0;
  std::int64_t particles = 0;
  std::int64_t steps = 0;
  double dt = 0.0;
  double final_displacement = 0.0;
  double max_kinetic_energy = 0.0;
  double wall_time = 0.0;
  double particle_steps_per_s = 0.0;
};

struct TensileRunOptions {
  std::string output_dir;  ///< empty: write nothing
  bool verbose = true;     ///< banner, progress lines, timing table (rank 0)
};

/// Runs the tensile test of a case (scenario.type tensile_test) until failure, the maximum
/// displacement or simulation.end_time. A row of the curve is recorded each record_interval of
/// plate travel and holds the mean displacement and load over the steps since the previous row.
/// Writes series.csv (time_s, displacement_m, load_N, broken_bonds, kinetic_energy_J,
/// bond_energy_J, plastic_work_J) and summary.json to the output folder.
TensileResult run_tensile_test(const CaseConfig& config, const TensileRunOptions& options,
                               const Communicator& comm);

}  // namespace ringdem
