#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "app/ScenarioDriver.hpp"
#include "app/TensileTest.hpp"
#include "engine/Simulation.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

/// Scenario `tensile_test` (app/TensileTest.hpp, docs/tensile.md): pulls until failure, the
/// maximum displacement or simulation.end_time; with unload_at, turns there and drives the plate
/// back until the load is zero (the residual displacement is the ring's permanent elongation). A
/// row of the curve is recorded each record_interval of plate travel and holds the mean
/// displacement and load over the steps since the previous row. Writes series.csv (time_s,
/// displacement_m, load_N, broken_bonds, kinetic_energy_J, bond_energy_J, plastic_work_J) and
/// summary.json. Its state (the meter's start positions, the peak, the failure state, the partial
/// row sums, next record) goes into checkpoints; the curve recorded before a checkpoint is read
/// back from series.csv on a restart.
class TensileDriver : public ScenarioDriver {
 public:
  explicit TensileDriver(const CaseConfig& config);
  TensileDriver(const TensileDriver&) = delete;  // test_ refers into config_
  TensileDriver& operator=(const TensileDriver&) = delete;

  const CaseConfig& config() const override { return config_; }
  /// The moving bodies (prescribed, checked by the case loader) travel at the loading rate.
  void prepare_model(Model& model) const override;
  std::int64_t planned_steps(const Simulation& sim) const override;
  bool start(Simulation& sim, const ScenarioContext& context) override;
  std::int64_t steps_to_advance(const Simulation&) const override { return 1; }
  bool after_steps(Simulation& sim) override;
  DriverState state() const override;
  std::string progress(const Simulation& sim, double steps_per_second) const override;
  void finish(Simulation& sim, const LoopTimes& times) override;

  /// The curve and the numbers of the finished test (on every rank).
  const TensileResult& result() const { return result_; }

 private:
  void record(Simulation& sim, double displacement, double load);
  /// Records the partial row (the steps since the last row), if any.
  void flush_row(Simulation& sim);
  /// Unloading: the moving bodies travel back along the pull direction at the loading rate.
  void drive_back(Simulation& sim) const;
  void restore(Simulation& sim);
  bool past_end(const Simulation& sim) const { return sim.time() >= end_time_ * (1.0 - 1e-12); }

  CaseConfig config_;
  const TensileTestConfig& test_;
  double end_time_;
  RunControl* control_ = nullptr;
  std::string output_dir_;
  bool verbose_ = true;
  bool write_ = false;
  SeriesWriter series_;
  std::optional<TensileMeter> meter_;
  TensileStopRule stop_;
  TensileResult result_;
  TensileStopRule::Reason reason_ = TensileStopRule::Reason::kRunning;
  std::int64_t broken_ = 0;
  double next_record_ = 0.0;
  double sum_displacement_ = 0.0;
  double sum_load_ = 0.0;
  std::int64_t n_summed_ = 0;
  bool unloading_ = false;                ///< the plate has turned at unload_at
  std::size_t loading_rows_ = 0;          ///< rows of the curve recorded before the turn
  std::optional<double> zero_load_from_;  ///< unloading: displacement since which the load is 0
  double displacement_ = 0.0;             ///< of the last step (progress lines)
  double load_ = 0.0;
};

}  // namespace ringdem
