#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "comm/ExactSum.hpp"
#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"
#include "engine/GrainSource.hpp"
#include "engine/InflowSpec.hpp"

namespace ringdem {

/// The inlets and what they brought in (docs/physics.md "Inflow"). A batch is due at the
/// first step that starts at or after its time; it is put in only when no particle reaches
/// into the inlet box (a flow backed up to the inlet delays it), and the next is due one
/// interval after it. Every rank builds the packing cells of its slice of the batch's items,
/// as the start-up sources do, so the grains are the same bits on any rank count; a rebuild
/// then moves them to their owners. What they bring in (count, mass, momentum, kinetic +
/// potential energy) is summed exactly per rank for the ledger.
class InflowSource {
 public:
  enum Column { kCount, kMass, kMomentumX, kMomentumY, kMomentumZ, kEnergy, kColumns };

  explicit InflowSource(std::vector<InflowSpec> inlets = {});

  bool empty() const { return inlets_.empty(); }
  std::size_t size() const { return inlets_.size(); }
  /// Whether inlet i's batch is due at `time` (the same on every rank).
  bool due(std::size_t i, double time) const;
  /// Whether an owned particle of `p` reaches into inlet i's box (this rank).
  bool occupied(std::size_t i, const ParticleStore& p) const;
  /// Puts inlet i's next batch into `p` (this rank's slice of it) at `time`, with the loads
  /// of free flight (m g) for the first half kick. Drops the ghosts: a rebuild must follow.
  /// Returns the grains this rank added.
  std::size_t emit(std::size_t i, ParticleStore& p, double time, const Vec3& gravity, int rank,
                   int ranks);

  const std::vector<ExactSum>& partial() const { return partial_; }

  /// Checkpoint state: per inlet the batches put in and the time the next is due, and the
  /// totals over the ranks as ExactSum words (export_totals is collective).
  std::vector<std::int64_t> batches() const;
  std::vector<double> next_due() const;
  std::vector<std::int64_t> export_totals(const Communicator& comm) const;
  /// From a checkpoint (empty vectors: nothing put in yet); the root takes the totals.
  void restore(const std::vector<std::int64_t>& batches, const std::vector<double>& next_due,
               const std::vector<std::int64_t>& totals, bool root);

 private:
  struct Inlet {
    InflowSpec spec;
    GrainSource packing;
    std::int64_t batches = 0;
    double next_due = 0.0;
  };
  std::vector<Inlet> inlets_;
  std::vector<ExactSum> partial_;
};

}  // namespace ringdem
