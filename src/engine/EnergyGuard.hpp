#pragma once

#include <optional>
#include <string>

namespace ringdem {

struct Energies;

/// The energy part of the divergence guard (issue 15): energy that appears from nowhere.
///
/// The ledger (docs/physics.md "Energy ledger") says mechanical + dissipated - boundary work
/// stays constant up to the integrator's O(dt^2) error. A run that blows up creates energy:
/// the ledger grows. What a healthy run can ever hold is the energy it started with (kinetic
/// and elastic), the potential energy it has released since, and the work the driven bodies
/// and particles have put in. The guard fires when the ledger has grown by more than that
/// budget (kBudgetFactor times it) plus a round-off floor: an error that no integration error
/// of a stable run reaches, while a run going unstable passes it long before its particles
/// move a skin per step.
///
/// It checks every evaluation of the energies (series rows, progress, sag checks), which cost
/// one all-reduce anyway; the per-step guard of Simulation covers moves and non-finite state.
class EnergyGuard {
 public:
  static constexpr double kBudgetFactor = 1.0;
  /// Round-off floor: relative to the potential energy's magnitude, plus an absolute joule.
  static constexpr double kRelativeFloor = 1e-9;
  static constexpr double kAbsoluteFloor = 1e-9;

  /// The energy created since the reference and what the ledger allowed, when the first
  /// exceeds the second or is not finite; nothing otherwise. The first call sets the reference.
  struct Excess {
    double created;  ///< J: ledger now minus ledger at the reference
    double allowed;  ///< J: the budget times kBudgetFactor plus the floor
  };
  std::optional<Excess> check(const Energies& now);

  /// Forget the reference: energy was put in from outside the ledger (a body placed with a
  /// velocity, a restart): the next check starts a new one.
  void rebase() { reference_valid_ = false; }

  /// "created X J of energy out of nothing where the ledger allows Y J" (for messages).
  static std::string describe(const Excess& e);

 private:
  bool reference_valid_ = false;
  double ledger_ = 0.0;
  double starting_energy_ = 0.0;  ///< kinetic + elastic at the reference
  double potential_ = 0.0;
  double boundary_work_ = 0.0;
};

}  // namespace ringdem
