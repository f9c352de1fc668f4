#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "app/BarrierMonitor.hpp"
#include "app/ScenarioDriver.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

/// Scenario `free_run`: steps to simulation.end_time. series.csv holds the energies, the broken
/// bonds and the contact force on each rigid body every series_interval, and with
/// scenario.barrier the barrier's loads, the flow and the net (BarrierMonitor); summary.json
/// the counts, energies, peaks and the final loads of the rigid bodies.
class FreeRunDriver : public ScenarioDriver {
 public:
  explicit FreeRunDriver(const CaseConfig& config) : config_(config) {}

  const CaseConfig& config() const override { return config_; }
  std::int64_t planned_steps(const Simulation& sim) const override;
  bool start(Simulation& sim, const ScenarioContext& context) override;
  std::int64_t steps_to_advance(const Simulation&) const override { return 1; }
  bool after_steps(Simulation& sim) override;
  DriverState state() const override;
  std::string progress(const Simulation& sim, double steps_per_second) const override;
  void finish(Simulation& sim, const LoopTimes& times) override;

 private:
  std::int64_t total_steps(const Simulation& sim) const;
  /// One row of series.csv and the running peaks. Collective.
  void record(Simulation& sim);
  /// The barrier's columns of one row, and its peaks. Collective.
  void record_barrier(const Simulation& sim, std::vector<double>& row);

  CaseConfig config_;
  RunControl* control_ = nullptr;
  std::string output_dir_;
  bool verbose_ = true;
  SeriesWriter series_;
  std::int64_t total_steps_ = 0;
  double max_kinetic_ = 0.0;
  double max_utilisation_ = 0.0;
  double next_record_ = 0.0;

  std::optional<BarrierMonitor> barrier_;
  double initial_net_reach_ = 0.0;  ///< the net's reach at the start: deflection is from it
  double last_front_ = 0.0, last_front_time_ = -1.0;  ///< the front at the record before
  double peak_barrier_force_ = 0.0, peak_barrier_time_ = 0.0, peak_net_force_ = 0.0;
  double peak_posts_force_ = 0.0, peak_depth_ = 0.0, peak_velocity_ = 0.0;
  double max_deflection_ = 0.0, max_net_utilisation_ = 0.0;
  Vec3 max_utilisation_at_;
  BarrierSample last_barrier_;
};

}  // namespace ringdem
