#pragma once

/// Range and finiteness of the quantities a case derives from its keys. Every key may be a
/// finite number in its own range and still give a derived value that overflows to infinity,
/// underflows to zero, or counts more steps than a run can: `end_time: 1e308` planned
/// -9223372036854775808 steps, a particle radius of 1e-200 m gives a particle of mass 0.
/// These checks compute what the model builder and the time-step estimate will compute
/// (particle volumes, masses and moments of inertia, densities from ring masses, bond moduli,
/// sections and stiffnesses, the stability limits, the step and frame counts, rigid-body masses,
/// the extent of the model against the block grid of the domain decomposition) and report a
/// value out of range at the key that sets it, with file:line:col.

#include <optional>
#include <string>
#include <utility>

#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

/// Most steps (and frames, checkpoints) one run may count. The time advances by t += dt: a dt
/// below about 2^-52 t no longer moves it, and step counts are stored as doubles (exact to
/// 2^53 ~ 9e15). 1e15 keeps dt above 4 ulp of the end time; at 10^7 steps per second such a
/// run would take three years.
inline constexpr double kMaxStepsPerRun = 1e15;

/// Blocks of the domain decomposition and cells of the neighbour search are numbered with 21
/// bits per axis, 2^20 each way from the origin; particles must start within half of that
/// (2^19 cells of 2 * largest particle radius + skin) so that they can still move.
inline constexpr double kMaxCellsFromOrigin = 524288.0;

/// How long a run of the case's scenario may go on (simulated seconds; for a rockfall the most
/// its phases may take), and the key that sets it.
std::pair<double, std::string> run_duration(const CaseConfig& config);

/// The time step and step count a run of the case will have, as far as the case tells before
/// a model is built: the smallest stability limit of its particles and bonds (the pre-flight
/// report at the start of a run takes the minimum over the particles actually created), the
/// fixed dt or dt_safety times that limit, and the longest the scenario may run. None where the
/// case's magnitudes are out of range. The brakes' and ropes' limits need the built restraints:
/// plan_time_steps_with_restraints (engine/FrameRestraints) adds them through tighten().
struct TimeStepPlan {
  double dt = 0.0;
  bool fixed = false;        ///< simulation.dt given (else dt_safety x the limit)
  double limit = 0.0;        ///< the smallest stability limit [s]
  std::string limit_what;    ///< which limit, and of what
  double duration = 0.0;     ///< the longest the run may go on [simulated s]
  std::string duration_key;  ///< the key that sets it
  double steps = 0.0;        ///< duration / dt

  /// Takes `limit` (described by `what`) where it is below the plan's, with the automatic dt
  /// (dt_safety x the limit) and the step count that follow; a fixed dt stays.
  void tighten(double limit, const std::string& what, double dt_safety);
};
std::optional<TimeStepPlan> plan_time_steps(const CaseConfig& config);

/// What the warning for a fixed time step `dt` above the smallest stability limit `limit`
/// (described by `what`) says: the loader's for the particles' and bonds' limits, `ringdem
/// check`'s for a brake's or a rope's (which need the built restraints).
std::string fixed_step_above_limit(double dt, double limit, const std::string& what);

/// Reports derived quantities out of range to `ctx`. Runs after the other cross-key checks
/// (cross_validate_case calls it last); entries with errors already are skipped.
void check_case_magnitudes(const CaseConfig& config, schema::Context& ctx);

}  // namespace ringdem
