#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include "app/ScenarioDriver.hpp"
#include "core/Vec3.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

/// Radius of a sphere of `mass` and `density`.
double sphere_radius(double mass, double density);

/// Scenario `rockfall` (docs/rockfall.md): the net sags under gravity until its kinetic energy
/// falls below a threshold, then a spherical boulder is released `drop_height` above the sagged
/// net and the run goes on for `duration` after its first contact. Writes series.csv (time from
/// first contact, boulder motion and acceleration, frame force, broken bonds, energies and the
/// energy ledger), sag.csv and summary.json; frames and checkpoints as the output section says.
class RockfallDriver : public ScenarioDriver {
 public:
  /// Adds the boulder (a rigid body, parked far above at rest until the release) to the case.
  explicit RockfallDriver(const CaseConfig& input);

  const CaseConfig& config() const override { return config_; }
  std::int64_t planned_steps(const Simulation&) const override { return 0; }
  bool start(Simulation& sim, const ScenarioContext& context) override;
  std::int64_t steps_to_advance(const Simulation&) const override { return 1; }
  bool after_steps(Simulation& sim) override;
  DriverState state() const override;
  std::string progress(const Simulation& sim, double steps_per_second) const override;
  void finish(Simulation& sim, const LoopTimes& times) override;

 private:
  using Clock = std::chrono::steady_clock;
  enum Phase { kSag = 0, kImpact = 1 };

  /// What is due between two steps: the sag check and the release, the rows of series.csv, the
  /// end of the impact (after the last row). Returns true when the run is over.
  bool between_steps(Simulation& sim);
  /// The sag check when due; true once the net is at rest.
  bool net_at_rest(Simulation& sim);
  /// Places the boulder above the sagged net and starts the impact phase.
  void release(Simulation& sim);
  bool impact_over(const Simulation& sim) const;
  /// One row of series.csv (means of the boulder load since the last row) and the peaks.
  void record(Simulation& sim);
  void restore(const DriverState& restored);

  CaseConfig config_;
  const RockfallConfig& rf_;
  double radius_;
  RunControl* control_ = nullptr;
  std::string output_dir_;
  bool print_ = false;
  SeriesWriter series_, sag_series_;
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
  double max_balance_error_ = 0.0;
  double free_fall_time_ = 0.0;
  double peak_sag_kinetic_ = 0.0;
  double no_contact_limit_ = std::numeric_limits<double>::infinity();
  /// Boulder contact load summed over the steps since the last row (row means).
  double sum_steps_ = 0.0;
  Vec3 sum_force_{};
  double sag_wall_ = 0.0;  ///< wall seconds of the sag phase before this run segment

  // ---- this segment only ----
  double kinetic_ = std::numeric_limits<double>::infinity();  ///< at the last sag check
  Clock::time_point segment_start_ = Clock::now();
  Clock::time_point impact_start_ = Clock::now();
};

}  // namespace ringdem
