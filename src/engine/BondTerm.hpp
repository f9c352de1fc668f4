#pragma once

#include <cstdint>
#include <vector>

#include "core/Quat.hpp"
#include "core/Vec3.hpp"
#include "domain/BondStore.hpp"
#include "engine/ForceTerm.hpp"

namespace ringdem {

/// One end of a bond being created: what a bond law needs of the particle (its state at
/// creation), whether or not the particle is in this rank's store yet.
struct BondEnd {
  std::int64_t gid = -1;
  Vec3 position;
  Quat orientation;
  double radius = 0.0;
};

/// A force term of bonds (one bond model over the model's bond store): what the simulation
/// asks of every bond model besides the force evaluation.
class BondTerm : public ForceTerm {
 public:
  explicit BondTerm(BondStore& bonds) : bonds_(bonds) {}
  /// The bonds this term computes: the model's bond store (sources fill it before any term
  /// exists), handed to migration and checkpoints as this term's pair store.
  std::optional<PairStore> pair_store() final { return PairStore{&bonds_}; }

  /// Recomputes the store's output columns (axial force, largest bending moment, utilisation,
  /// energy) for the current configuration; returns the summed elastic energy.
  virtual double update_diagnostics(const ParticleStore& p) const = 0;
  /// Plastic work each bond of the store has dissipated since its creation (J, one value per
  /// bond, kept when it breaks): the energy ledger's plastic_work column. nullptr: the law is
  /// elastic.
  virtual const std::vector<double>* plastic_work() const { return nullptr; }

 protected:
  BondStore& bonds_;
};

}  // namespace ringdem
