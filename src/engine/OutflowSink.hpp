#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "comm/ExactSum.hpp"
#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// A box that grains may not leave (`outflow[]` in the case file): a free grain in no ring
/// whose centre is outside it is taken out of the model.
struct OutflowBox {
  std::string name;
  Vec3 lo, hi;
  std::vector<std::int32_t> groups;  ///< particle groups it takes; empty: every grain
};

/// The outflow boundaries and what has gone out through them (docs/physics.md "Outflow").
/// Grains are taken out between two steps, at the synchronised state (x^n, v^n, the ledger
/// tallies at t_n), so that what they carry out closes the energy ledger: their kinetic and
/// potential energy, their share of contact elastic energy, and what the ledger booked per
/// particle (global damping; the tangential energy their springs held, which the friction
/// tally counts as still held). The contact terms' tallies are the ledger's per rank
/// (EnergyLedger), which ends a leaving grain's trapezoid at its last step. Mass, momentum and
/// count are kept too (the momentum balance of a debris flow). Each rank sums exactly
/// (comm/ExactSum) what its own grains carry, so totals are the same bits on any rank count.
class OutflowSink {
 public:
  enum Column {
    kCount,
    kMass,
    kMomentumX,
    kMomentumY,
    kMomentumZ,
    kEnergy,            ///< kinetic + potential (-m g.x) + contact elastic share
    kTangentialEnergy,  ///< the tangential spring energy share, part of kEnergy
    kGlobalDamping,     ///< the global-damping tally
    kColumns
  };

  explicit OutflowSink(std::vector<OutflowBox> boxes = {});

  bool empty() const { return boxes_.empty(); }
  /// Owned particle k is a grain (free, in no ring) of a box's groups, outside that box.
  bool leaving(const ParticleStore& p, std::size_t k) const;
  /// Notes how near the owned grains that a box takes are to its faces, at the positions of a
  /// neighbour-list rebuild: until they have moved that far, none can be outside.
  void note_positions(const ParticleStore& p);
  /// Some owned particle is leaving (this rank). `moved` bounds how far any owned particle
  /// moved since note_positions(): below the clearance noted there, no position is read.
  bool any_leaving(const ParticleStore& p, double moved) const;
  /// Takes the owned grains that are leaving out of `p`, adding what they carry to this rank's
  /// sums, with the elastic and the tangential spring energy that their contacts held after
  /// the last step (EnergyLedger::held_by_leaving(), this rank's sums over them). Owned
  /// indices change: a neighbour-list rebuild must follow. Returns how many left.
  std::size_t remove_leaving(ParticleStore& p, const Vec3& gravity, double dt,
                             const ExactSum& contact_energy, const ExactSum& tangential_energy);

  /// This rank's partial sums, by Column.
  const std::vector<ExactSum>& partial() const { return partial_; }
  /// The totals over the ranks as ExactSum words (kColumns x ExactSum::kWords). Collective.
  std::vector<std::int64_t> export_totals(const Communicator& comm) const;
  /// From a checkpoint: the root takes the totals, the other ranks start from zero (empty
  /// `words`: nothing went out yet).
  void import_totals(const std::vector<std::int64_t>& words, bool root);

 private:
  static constexpr double kClearanceMargin = 1e-6;  ///< m
  std::vector<OutflowBox> boxes_;
  std::vector<ExactSum> partial_;
  /// The least distance of a grain that may leave to the face of its box at note_positions(),
  /// less a margin for the rounding of the drifts; 0 (every step scans) until noted.
  double clearance_ = 0.0;
};

}  // namespace ringdem
