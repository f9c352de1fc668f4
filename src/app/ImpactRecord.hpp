#pragma once

#include <limits>
#include <string>
#include <vector>

#include "io/Checkpoint.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

/// Results of one boulder impact of a rockfall run (docs/rockfall.md, "Repeated impacts"): what
/// summary.json lists per impact, kept in checkpoints so that a restart reports every impact.
struct ImpactRecord {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

  double release_time = kNone;     ///< simulated time of the release (s)
  double release_net_top = kNone;  ///< net top under the drop axis at the release (m)
  double contact_time = kNone;     ///< first contact (s)
  double peak_acceleration = 0.0;  ///< largest row-mean boulder acceleration (m/s^2)
  double time_of_peak = 0.0;       ///< after the contact (s)
  double peak_instant = 0.0;       ///< largest single-step acceleration (m/s^2)
  double deflection = kNone;       ///< boulder centre travel below its first-contact height (m)
  double stopping_time = kNone;    ///< first upward boulder velocity after the contact (s)
  double rebound_speed = 0.0;      ///< largest upward boulder speed after the contact (m/s)
  double max_frame_force = 0.0;    ///< largest frame load (N)
  double max_rope_tension = 0.0;   ///< largest tension of a support rope (N; 0 without ropes)
  double broken_bonds = 0.0;       ///< bonds broken between the release and the removal
  /// Energy dissipated between the release and the end of the impact (J).
  double plastic_work = 0.0, friction = 0.0, contact_damping = 0.0, global_damping = 0.0;
  double brake_work = 0.0;     ///< by the brakes of braked shackles and of support ropes
  double rope_friction = 0.0;  ///< the part of `friction` the ropes took sliding through shackles
  /// Net top under the drop axis once at rest after the boulder was removed, minus its initial
  /// top (m, negative below); NaN where the net was not re-settled (a single impact).
  double residual_height = kNone;

  /// Stores the record as `impact<number>.<field>` values.
  void save(DriverState& state, int number) const;
  static ImpactRecord load(const DriverState& state, int number);
  /// The entry of summary.json's `impacts` array; energy shares are fractions of
  /// `impact_energy` (boulder mass x g x drop height).
  JsonObject json(int number, double g, double impact_energy) const;
  /// The record as one line of the run's log ("rockfall impact <number>: ...").
  std::string log_line(int number, double g, double impact_energy) const;
};

/// summary.json's `impacts` array.
void set_impacts(JsonObject& summary, const std::vector<ImpactRecord>& impacts, double g,
                 double impact_energy);
/// One log line per impact (a repeated-impact run's closing report).
void print_impacts(const std::vector<ImpactRecord>& impacts, double g, double impact_energy);

}  // namespace ringdem
