#pragma once

#include <cstdint>
#include <string>

#include "io/CaseConfig.hpp"

namespace ringdem {

/// What a case will create and roughly need, from its generators alone (closed forms: no
/// particle is generated), so that a case too large for the machine is refused before any
/// memory is taken.
struct SizeEstimate {
  std::int64_t particles = 0;
  std::int64_t bonds = 0;
  /// Peak resident memory of one rank when `ranks` share the model, in bytes: measured
  /// per-item costs (scripts/bench/startup_memory.sh: about 1.9 kB per grain with its
  /// contacts at 10^6 grains, 1.4 kB per net particle with its bond) plus ghosts and the
  /// MPI/HDF5 base.
  double bytes_per_rank(int ranks) const;

  static constexpr double kBytesPerParticle = 2000.0;
  static constexpr double kBytesPerBond = 300.0;
  static constexpr double kBaseBytes = 64.0 * 1024 * 1024;
  /// Owned plus ghost particles over owned ones, for more than one rank (0.39 N at 3 ranks
  /// against N / 3 in the start-up test: 1.16).
  static constexpr double kGhostFactor = 1.3;
};

/// Counts of a validated case (the net's rows and columns already resolved by the loader).
SizeEstimate estimate_size(const CaseConfig& config);

/// The memory this machine has available now (MemAvailable), in bytes; 0 when unknown.
double available_memory_bytes();

/// The peak resident memory of this process so far (VmHWM), in bytes; 0 when unknown.
double peak_resident_bytes();

/// A one-line report: particles, bonds, memory per rank.
std::string describe(const SizeEstimate& estimate, int ranks);

}  // namespace ringdem
