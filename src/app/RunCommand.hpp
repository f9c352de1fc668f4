#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "app/RunControl.hpp"
#include "comm/Communicator.hpp"
#include "io/CaseConfig.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

class Simulation;

struct RunOptions {
  std::string case_path;
  std::string output_dir;  ///< empty: results/<case name>
  std::vector<std::string> overrides;
  bool quiet = false;
  std::string restart;         ///< "", "auto" or a checkpoint path
  double max_walltime = 0.0;   ///< seconds; checkpoint and exit 3 when reached (0: no limit)
  bool force_size = false;     ///< run even beyond the memory estimate
  bool break_lock = false;     ///< take over a lock of the output folder held on another host
  bool allow_changes = false;  ///< --allow-changes: a restart applies changed keys it may apply
};

/// `ringdem run`: the case's scenario driver (app/ScenarioDriver.hpp) run by the one scenario
/// loop (app/ScenarioRunner.hpp): banner, configuration, pre-flight numbers, progress lines,
/// series.csv and summary.json; frames, checkpoints and restarts for every scenario.
/// Returns the process exit code.
int run_case(const CaseConfig& config, const RunOptions& options, const Communicator& comm);

// ---- pieces shared by the scenario drivers (rank 0 prints) ----

/// "1h02m", "3m05s", "42s"; "--" for a negative or non-finite number.
std::string format_duration(double seconds);
/// Banner, case, ranks, output folder and the resolved configuration.
void print_banner(const CaseConfig& config, const std::string& out_dir, const Communicator& comm);
/// Particles, bonds, bodies, time step against its stability limits, derived bond moduli.
/// `time_step_origin` says where a restart's time step comes from (RunControl); empty: the
/// case's (fixed or auto). Collective (every rank calls it); prints only if `print`.
void print_preflight(const Simulation& sim, const CaseConfig& config, std::int64_t planned_steps,
                     bool print, const std::string& time_step_origin = {});
/// Peak resident memory against the start-up size estimate (io/SizeEstimate.hpp).
struct MemoryUse {
  double peak_largest_rank = 0.0;  ///< bytes, the largest rank's peak (0 when unknown)
  /// bytes, the most shared memory resident on one rank at the end (io/SizeEstimate.hpp's
  /// shared_resident_bytes: MPI's on-node buffers, mapped by every rank that reads them)
  double shared_largest_rank = 0.0;
  double estimate_per_rank = 0.0;  ///< bytes, what the refusal test assumed
};
/// Collective (every rank calls it): the peaks so far, and the estimate for this rank count.
MemoryUse measure_memory_use(const CaseConfig& config, const Communicator& comm);
/// summary.json's memory keys: peak_memory_largest_rank_bytes,
/// shared_memory_largest_rank_bytes and estimated_memory_per_rank_bytes.
void set_memory_use(JsonObject& summary, const MemoryUse& memory);
/// The loop's seconds in each phase of Simulation::Phase over the ranks: the least, the mean
/// and the most. A phase whose most is well above its mean is where ranks wait for others.
struct PhaseSpread {
  std::vector<std::string> names;
  std::vector<double> min, mean, max;
};
/// Collective (every rank calls it).
PhaseSpread measure_phases(const Simulation& sim);
/// {"integrate": {"min": .., "mean": .., "max": ..}, ...} for summary.json.
JsonObject phase_spread_json(const PhaseSpread& phases);
/// Steps, particle-steps/s, the time per phase over the ranks and the memory.
void print_timing(const Simulation& sim, double loop_seconds, double particle_steps_per_s,
                  int ranks, const MemoryUse& memory, const PhaseSpread& phases);

}  // namespace ringdem
