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
  /// To the next series row or the end, whichever comes first.
  std::int64_t steps_to_advance(const Simulation& sim) const override;
  bool after_steps(Simulation& sim) override;
  DriverState state() const override;
  std::string progress(const Simulation& sim, double steps_per_second) const override;
  void finish(Simulation& sim, const LoopTimes& times) override;

 private:
  std::int64_t total_steps(const Simulation& sim) const;
  /// One row of series.csv and the running peaks. Collective.
  void record(Simulation& sim);
  /// The barrier's columns of one row, and its peaks. Collective: call it on every rank.
  void record_barrier(const Simulation& sim, const MomentumBalance& momentum,
                      std::vector<double>& row);

  CaseConfig config_;
  RunControl* control_ = nullptr;
  std::string output_dir_;
  bool verbose_ = true;
  SeriesWriter series_;
  std::int64_t total_steps_ = 0;
  double max_kinetic_ = 0.0;
  double max_utilisation_ = 0.0;
  double next_record_ = 0.0;
  /// The energy ledger (Energies::ledger()) at the start of the run, and the largest
  /// |balance error| of a row since: what series.csv and summary.json report of it.
  double ledger_start_ = 0.0;
  double max_balance_error_ = 0.0;

  /// The barrier's running values, kept in the driver state across restarts.
  struct BarrierRecord {
    double initial_net_reach = 0.0;  ///< the net's reach at the start: deflection is from it
    double last_front = 0.0, last_front_time = -1.0;  ///< the front at the record before
    double peak_force = 0.0, peak_time = 0.0, peak_net_force = 0.0, peak_posts_force = 0.0;
    double peak_depth = 0.0, peak_velocity = 0.0, max_deflection = 0.0, max_utilisation = 0.0;
    double max_utilisation_x = 0.0, max_utilisation_y = 0.0, max_utilisation_z = 0.0;
    /// The barrier's impulses at the record before (BarrierMonitor::impulse), for the mean
    /// forces over the interval since, and the peaks of those means.
    double last_net_impulse = 0.0, last_posts_impulse = 0.0, last_impulse_time = -1.0;
    double peak_mean_force = 0.0, peak_mean_time = 0.0, peak_mean_net_force = 0.0;
    double peak_mean_posts_force = 0.0;
    double largest_gauge_grain_diameter = 0.0;  ///< of the grains the gauge has seen
    /// Each value with its driver-state name (the one list that state() and start() read).
    template <class F>
    void for_each(F&& f) {
      f("barrier_initial_net_reach", initial_net_reach);
      f("barrier_last_front", last_front);
      f("barrier_last_front_time", last_front_time);
      f("barrier_peak_force", peak_force);
      f("barrier_peak_time", peak_time);
      f("barrier_peak_net_force", peak_net_force);
      f("barrier_peak_posts_force", peak_posts_force);
      f("barrier_peak_depth", peak_depth);
      f("barrier_peak_velocity", peak_velocity);
      f("barrier_max_deflection", max_deflection);
      f("barrier_max_utilisation", max_utilisation);
      f("barrier_max_utilisation_x", max_utilisation_x);
      f("barrier_max_utilisation_y", max_utilisation_y);
      f("barrier_max_utilisation_z", max_utilisation_z);
      f("barrier_last_net_impulse", last_net_impulse);
      f("barrier_last_posts_impulse", last_posts_impulse);
      f("barrier_last_impulse_time", last_impulse_time);
      f("barrier_peak_mean_force", peak_mean_force);
      f("barrier_peak_mean_time", peak_mean_time);
      f("barrier_peak_mean_net_force", peak_mean_net_force);
      f("barrier_peak_mean_posts_force", peak_mean_posts_force);
      f("barrier_largest_gauge_grain_diameter", largest_gauge_grain_diameter);
    }
  };
  std::optional<BarrierMonitor> barrier_;
  BarrierRecord barrier_record_;
  BarrierSample last_barrier_;
};

}  // namespace ringdem
