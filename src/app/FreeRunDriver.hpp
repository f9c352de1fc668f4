#pragma once

#include <cstdint>
#include <string>

#include "app/ScenarioDriver.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

/// Scenario `free_run`: steps to simulation.end_time. series.csv holds the energies, the broken
/// bonds and the contact force on each rigid body every series_interval; summary.json the
/// counts, energies, peaks and the final loads of the rigid bodies.
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

  CaseConfig config_;
  RunControl* control_ = nullptr;
  std::string output_dir_;
  bool verbose_ = true;
  SeriesWriter series_;
  std::int64_t total_steps_ = 0;
  double max_kinetic_ = 0.0;
  double max_utilisation_ = 0.0;
  double next_record_ = 0.0;
};

}  // namespace ringdem
