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
  bool writes_frames = false;  ///< the frame file stays open through the run
  /// Peak resident memory of one rank when `ranks` share the model, in bytes: measured
  /// per-item costs plus ghosts, the MPI/HDF5 base and the open frame file. Measured peaks
  /// (summary.json's peak_memory_largest_rank_bytes, native build, 2-core machine): 23-26 MiB
  /// for a run of 10^3 grains without frames; a grain adds 352 B on 1 rank (a resting bed of
  /// 2 x 10^5), 474 B in the flowing bed of 10^6 (scripts/bench/peer_granular.sh); a net
  /// particle with its bond 1.1 kB (the r12 net without frames, elastic or plastic). The
  /// figures below keep a margin over those; tests/scripts/size_estimate_bounds.sh checks that
  /// they bound measured runs from above within a factor of 2.5.
  double bytes_per_rank(int ranks) const;

  static constexpr double kBytesPerParticle = 600.0;
  static constexpr double kBytesPerBond = 800.0;
  static constexpr double kBaseBytes = 32.0 * 1024 * 1024;
  /// HDF5's metadata cache of the open frame file grows with the frames' chunk indexes up to
  /// its default maximum, 32 MiB (measured: 13 MiB more for 10^3 grains after 500 frames,
  /// 20 MiB more for the rockfall demo's 4 224 particles after 218 frames).
  static constexpr double kFrameFileBytes = 32.0 * 1024 * 1024;
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

/// The shared memory resident in this process now (RssShmem), in bytes; 0 when unknown. In a
/// run that is MPI's on-node transport: Open MPI's shared-memory segments, one per rank (4 MiB
/// at most each), which every rank that reads a peer's messages maps and counts in its own
/// resident memory. The node holds each segment once, so this part of VmHWM is counted once per
/// rank that maps it, not once per rank.
double shared_resident_bytes();

/// A one-line report: particles, bonds, memory per rank.
std::string describe(const SizeEstimate& estimate, int ranks);

}  // namespace ringdem
