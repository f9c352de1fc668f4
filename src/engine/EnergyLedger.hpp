#pragma once

#include <cstdint>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "engine/ForceSlots.hpp"
#include "engine/GatherMap.hpp"

namespace ringdem {

/// What the energy ledger needs of one dissipative slot's load (docs/physics.md "Energy
/// ledger"): the force terms that dissipate write one record per slot through record().
struct DissipationRecord {
  Vec3 damping;                    ///< viscous force on this particle (Eq. 7 + Eq. 9)
  Vec3 friction;                   ///< tangential spring force on this particle (Coulomb-capped)
  Vec3 arm;                        ///< from this particle's centre to the contact point; 0: idle
  Vec3 rolling;                    ///< rolling-friction torque on this particle
  double tangential_energy = 0.0;  ///< this particle's share of |F_t|^2 / 2 S_t
  double elastic_energy = 0.0;     ///< this particle's share of the contact's elastic energy
  std::int32_t body = -1;          ///< rigid body on the other side, -1 for a particle
};

/// The energy ledger, written once for every force term: per-particle tallies of the work of
/// the dissipative loads and of driven bodies and particles (ParticleStore's dissipated_*,
/// boundary_work), from the records the terms write and the gather order.
class EnergyLedger {
 public:
  /// After GatherMap::finish(): one record per ledger slot, stored in the order accumulate()
  /// reads them (one contiguous stream), plus a scratch record for the other slots.
  void rebuild(const GatherMap& gather, std::size_t n_slots);

  /// The record of a slot for the term to fill (the scratch record when no owned particle
  /// books it, e.g. the ghost end of a pair).
  DissipationRecord& record(std::uint32_t slot) { return records_[record_of_slot_[slot]]; }

  /// After the second half kick of particles and rigid bodies, with the velocities of the end
  /// of the step: adds the work of the last force evaluation to each owned particle's tallies.
  /// `initial`: the loads of the initial state, entered with weight dt/2 and no work over a step.
  void accumulate(ParticleStore& p, const std::vector<RigidBody>& bodies, const ForceSlots& slots,
                  const GatherMap& gather, double dt, bool initial = false);

 private:
  std::vector<DissipationRecord> records_;
  std::vector<std::uint32_t> record_of_slot_;
  bool list_changed_ = false;  ///< particles off the list get zero power once
};

}  // namespace ringdem
