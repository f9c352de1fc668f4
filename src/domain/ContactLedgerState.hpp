#pragma once

#include <cmath>

#include "core/Vec3.hpp"
#include "core/Vec3f.hpp"

namespace ringdem {

/// What a particle pair carries from one step to the next for the energy ledger where it books
/// each contact's work in the pair loop (EnergyLedger::PairBooking, docs/physics.md "Energy
/// ledger"): the viscous force of the last evaluation on the pair's first end, and the overlap
/// it acted at. The work of the step is then that of the loads of its start at their own contact
/// points and of those of its end at theirs, each at the relative velocity of the step's middle:
/// second order in dt. The normal of the start's contact point is not carried: it is the
/// separation one drift back (step_start_normal()), exact to round-off where the pair's law
/// runs at every step, which per-contact booking requires (one rate). In float: 16 bytes a
/// contact, which at 10^6 grains in contact is part of the run's peak (with the normal folded
/// into two more floats it was 24: docs/performance.md, fifty-fifth round). The ledger reads
/// them into products with doubles only.
struct ContactLedgerState {
  Vec3f damping;
  /// The overlap of the last evaluation, >= 0 for a contact that touched; negative (the default
  /// state) where the pair carries no work: a contact that just closed, or one whose work a
  /// rebuild booked (PairContactTerm::book_carried_work()).
  float overlap = -1.0f;

  /// Whether the pair carries the work of its last loads (the spring it carries does no work
  /// at the start of the step otherwise).
  bool carries_work() const { return overlap >= 0.0f; }
  /// The state of no work: nothing to carry through a rebuild.
  bool is_empty() const {
    return !carries_work() && damping.x == 0.0f && damping.y == 0.0f && damping.z == 0.0f;
  }

  /// The state of a contact with viscous force `damping` on its first end at `overlap`.
  [[gnu::always_inline]] static ContactLedgerState of(const Vec3& damping, double overlap) {
    ContactLedgerState s;
    s.damping = to_vec3f(damping);
    s.overlap = static_cast<float>(overlap);
    return s;
  }
};

/// The unit normal (from the first end to the second) of a pair's contact at the start of the
/// step, the evaluation before this one: its separation `separation` (second end minus first)
/// less the step's drift of each end, `relative_velocity` (the second end's velocity minus the
/// first's, those of the step's middle, which the drift used) times `dt`. Written with no
/// branch, so that a vectorised loop can run it (PairContactChunk::compute_lanes).
[[gnu::always_inline]] inline Vec3 step_start_normal(const Vec3& separation,
                                                     const Vec3& relative_velocity, double dt) {
  const Vec3 start = separation - relative_velocity * dt;
  return start / std::sqrt(norm2(start));
}

static_assert(sizeof(ContactLedgerState) == 4 * sizeof(float),
              "four floats in a row: a checkpoint stores them as one row of 4");

}  // namespace ringdem
