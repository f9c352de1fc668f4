#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "app/ImpactRecord.hpp"
#include "app/ScenarioDriver.hpp"
#include "app/WallClock.hpp"
#include "core/Vec3.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

struct Energies;

/// Radius of a sphere of `mass` and `density`.
double sphere_radius(double mass, double density);

/// Scenario `rockfall` (docs/rockfall.md): the net sags under gravity until its kinetic energy
/// falls below a threshold, then a spherical boulder is released `drop_height` above the sagged
/// net and the run goes on for `duration` after its first contact. Writes series.csv (time from
/// first contact, boulder motion and acceleration, frame force, broken bonds, energies and the
/// energy ledger), sag.csv and summary.json; frames and checkpoints as the output section says.
/// With `impacts` > 1 (a repeated impact on the same net, EAD 340059-00-0106 SEL test) the
/// boulder is removed `duration` after each contact, the net re-settles (resettle.csv) and the
/// next boulder falls drop_height onto the deformed net; summary.json lists every impact.
class RockfallDriver : public ScenarioDriver {
 public:
  /// Adds the boulder (a rigid body, parked far above at rest until the release) to the case.
  explicit RockfallDriver(const CaseConfig& input);

  const CaseConfig& config() const override { return config_; }
  std::int64_t planned_steps(const Simulation&) const override { return 0; }
  bool start(Simulation& sim, const ScenarioContext& context) override;
  /// Steps up to the next thing between_steps() has to do (a rest check, a series row, the end
  /// of the impact or of the run); one step after the boulder's removal.
  std::int64_t steps_to_advance(const Simulation& sim) const override;
  bool observes_steps() const override { return true; }
  /// During an impact: the boulder's load for the row means, the first contact, its largest
  /// single-step deceleration, lowest point, stop and rebound speed.
  void observe_step(const std::vector<RigidBody>& bodies, double time) override;
  bool after_steps(Simulation& sim) override;
  DriverState state() const override;
  std::string progress(const Simulation& sim, double steps_per_second) const override;
  void finish(Simulation& sim, const LoopTimes& times) override;

 private:
  enum Phase { kSag = 0, kImpact = 1, kResettle = 2 };

  /// What is due between two steps: the sag check and the release, the rows of series.csv, the
  /// end of the impact (after the last row). Returns true when the run is over.
  bool between_steps(Simulation& sim);
  /// The rest check of the sag or re-settle phase when due; true once the net is at rest.
  bool net_at_rest(Simulation& sim);
  /// The net's top within the boulder's radius of the drop axis (collective); an error where no
  /// net particle is there (`when`: at the start, at the release).
  double net_top_under_drop_axis(const Simulation& sim, const char* when) const;
  /// Places the boulder above the sagged (or re-settled) net and starts the next impact.
  void release(Simulation& sim);
  /// The results of the impact in progress (energies, the ropes' friction work and broken bonds
  /// from now).
  ImpactRecord impact_record(const Energies& now, double rope_friction_work,
                             std::int64_t broken) const;
  /// End of an impact: its record; with more than one impact, the boulder is removed and the
  /// net re-settles. Returns true when the run is over.
  bool close_impact(Simulation& sim);
  /// The net is at rest again after impact impact_: its residual height.
  void resettled(Simulation& sim);
  /// The Cundall coefficient of the net in the current phase, where the case sets one.
  std::optional<double> net_damping() const;
  /// Steps of sag_dt while the net sags or re-settles (where the case sets one), of the case's
  /// time step from a release on; idempotent, so a restart in any phase gets its step.
  void apply_phase_time_step(Simulation& sim) const;
  bool impact_over(const Simulation& sim) const;
  /// One row of series.csv (means of the boulder load since the last row) and the peaks.
  void record(Simulation& sim);
  void restore(const DriverState& restored);
  /// The saved double values with their names and their values where a checkpoint lacks them:
  /// f(name, member, absent), one list for state() and restore().
  template <class Self, class F>
  static void for_each_saved(Self& self, F&& f);

  CaseConfig config_;
  const RockfallConfig& rf_;
  double radius_;
  RunControl* control_ = nullptr;
  std::string output_dir_;
  bool print_ = false;
  SeriesWriter series_, sag_series_, resettle_series_;
  int net_ = -1, frame_ = -1;
  std::size_t boulder_ = 0;
  double g_ = 0.0;
  double impact_energy_ = 0.0, impact_velocity_ = 0.0;

  // ---- state saved in checkpoints ----
  int phase_ = kSag;
  double next_sag_check_ = 0.0;
  double sag_end_time_ = -1.0;
  double contact_time_ = -1.0;
  double ledger_start_ = 0.0;
  double energy_added_ = 0.0;
  double contact_z_ = 0.0;
  double net_top_initial_ = 0.0;
  double net_top_sagged_ = 0.0;
  double drop_x_ = 0.0, drop_y_ = 0.0;
  double next_record_ = 0.0;
  double peak_acceleration_ = 0.0;
  double time_of_peak_ = 0.0;
  double peak_instant_ = 0.0;
  double lowest_z_ = std::numeric_limits<double>::infinity();
  double stopping_time_ = -1.0;
  bool reached_end_time_ = false;  ///< simulation.end_time stopped the run (it is a cap)
  double max_frame_force_ = 0.0;
  double max_rope_tension_ = 0.0;
  double max_balance_error_ = 0.0;
  double free_fall_time_ = 0.0;
  double peak_sag_kinetic_ = 0.0;
  double no_contact_limit_ = std::numeric_limits<double>::infinity();
  /// Boulder contact load summed over the steps since the last row (row means).
  double sum_steps_ = 0.0;
  Vec3 sum_force_{};
  double sag_wall_ = 0.0;    ///< wall seconds of the sag phase before this run segment
  bool finished_ = false;    ///< the scenario is over (a restart from the last checkpoint)
  int impact_ = 0;           ///< the impact in progress or the last one (1..impacts; 0: sag)
  double rest_start_ = 0.0;  ///< start of the sag (0) or of the re-settle phase
  double rebound_speed_ = 0.0;
  double release_time_ = 0.0, release_top_ = 0.0;  ///< of the impact in progress
  double release_broken_ = 0.0;                    ///< broken bonds at the release
  /// Dissipated energies at the release: plastic, friction, contact damping, global damping,
  /// brakes.
  std::array<double, 6> release_dissipated_{};
  std::vector<ImpactRecord> impacts_;  ///< impacts that have ended
  /// Ledger before the boulder was removed, until the step after (-inf: none pending).
  double ledger_before_removal_ = -std::numeric_limits<double>::infinity();

  // ---- this segment only ----
  double kinetic_ = std::numeric_limits<double>::infinity();  ///< at the last sag check
  WallClock::time_point segment_start_ = WallClock::now();
  WallClock::time_point impact_start_ = WallClock::now();
};

}  // namespace ringdem
