#pragma once

#include "core/Vec3f.hpp"

namespace ringdem {

/// What a particle pair carries from one step to the next for the energy ledger where it books
/// each contact's work in the pair loop (EnergyLedger::PairBooking, docs/physics.md "Energy
/// ledger"): the viscous force of the last evaluation on the pair's first end, and the geometry
/// that force acted at, the unit normal from the first end to the second and the overlap. The
/// work of the step is then that of the loads of its start at their own contact points and of
/// those of its end at theirs, each at the relative velocity of the step's middle: second order
/// in dt. In float: the ledger reads them into products with doubles only.
struct ContactLedgerState {
  Vec3f damping;
  Vec3f normal;
  float overlap = 0.0f;

  /// Whether the pair carries the work of its last loads: a contact that just closed carries
  /// none (nor does one whose work a rebuild booked: PairContactTerm::book_carried_work()), and
  /// the spring it carries then does no work at the start of the step.
  bool carries_work() const { return normal.x != 0.0f || normal.y != 0.0f || normal.z != 0.0f; }
  bool is_zero() const {
    return damping.x == 0.0f && damping.y == 0.0f && damping.z == 0.0f && normal.x == 0.0f &&
           normal.y == 0.0f && normal.z == 0.0f && overlap == 0.0f;
  }
};
static_assert(sizeof(ContactLedgerState) == 7 * sizeof(float),
              "seven floats in a row: a checkpoint stores them as one row of 7");

}  // namespace ringdem
