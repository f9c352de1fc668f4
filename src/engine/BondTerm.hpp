#pragma once

#include "engine/ForceTerm.hpp"

namespace ringdem {

/// A force term of bonds (one bond model over the model's bond store): what the simulation
/// asks of every bond model besides the force evaluation.
class BondTerm : public ForceTerm {
 public:
  /// Recomputes the store's output columns (axial force, largest bending moment, utilisation,
  /// energy) for the current configuration; returns the summed elastic energy.
  virtual double update_diagnostics(const ParticleStore& p) const = 0;
};

}  // namespace ringdem
