#include "engine/EnergyGuard.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/Simulation.hpp"

namespace ringdem {

std::optional<EnergyGuard::Excess> EnergyGuard::check(const Energies& now) {
  if (!reference_valid_) {
    reference_valid_ = true;
    ledger_ = now.ledger();
    starting_energy_ = now.kinetic + now.bond_elastic + now.contact_elastic;
    potential_ = now.potential;
    boundary_work_ = now.boundary_work;
  }
  const double created = now.ledger() - ledger_;
  // What the run could hold: its start, the potential energy released and the work put in.
  const double released = std::max(0.0, potential_ - now.potential);
  const double put_in = std::max(0.0, now.boundary_work - boundary_work_);
  const double floor =
      kRelativeFloor * (std::abs(potential_) + std::abs(now.potential)) + kAbsoluteFloor;
  const double allowed = kBudgetFactor * (starting_energy_ + released + put_in) + floor;
  if (std::isfinite(created) && created <= allowed) return std::nullopt;
  return Excess{created, allowed};
}

std::string EnergyGuard::describe(const Excess& e) {
  if (!std::isfinite(e.created)) return "the energies are not finite (NaN or infinity)";
  return fmt::format(
      "the energy ledger grew by {:.4g} J, more than the {:.4g} J the run had (its starting "
      "kinetic and elastic energy, the potential energy released and the work put in)",
      e.created, e.allowed);
}

}  // namespace ringdem
