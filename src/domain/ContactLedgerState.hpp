#pragma once

#include <cmath>

#include "core/Vec3.hpp"
#include "core/Vec3f.hpp"

namespace ringdem {

/// What a particle pair carries from one step to the next for the energy ledger where it books
/// each contact's work in the pair loop (EnergyLedger::PairBooking, docs/physics.md "Energy
/// ledger"): the viscous force of the last evaluation on the pair's first end, and the geometry
/// that force acted at, the unit normal from the first end to the second and the overlap. The
/// work of the step is then that of the loads of its start at their own contact points and of
/// those of its end at theirs, each at the relative velocity of the step's middle: second order
/// in dt. In float, the normal in two (octahedral: the unit sphere folded onto the square |u| +
/// |v| <= 1, about 1e-7 everywhere): 24 bytes a contact, which at 10^6 grains in contact is the
/// run's peak. The ledger reads them into products with doubles only.
struct ContactLedgerState {
  Vec3f damping;
  float normal_u = 0.0f, normal_v = 0.0f;
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

  /// The state of a contact of unit normal `n` (from the first end to the second).
  static ContactLedgerState of(const Vec3& damping, const Vec3& n, double overlap) {
    ContactLedgerState s;
    s.damping = to_vec3f(damping);
    const double l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    double u = n.x / l1, v = n.y / l1;
    if (n.z < 0.0) {  // the lower half folded over the diagonals
      const double fu = (1.0 - std::abs(v)) * std::copysign(1.0, u);
      const double fv = (1.0 - std::abs(u)) * std::copysign(1.0, v);
      u = fu;
      v = fv;
    }
    s.normal_u = static_cast<float>(u);
    s.normal_v = static_cast<float>(v);
    s.overlap = static_cast<float>(overlap);
    return s;
  }
  /// The unit normal (the inverse of of()'s folding, normalised).
  Vec3 normal() const {
    double x = normal_u, y = normal_v;
    const double z = 1.0 - std::abs(x) - std::abs(y);
    if (z < 0.0) {
      const double fx = (1.0 - std::abs(y)) * std::copysign(1.0, x);
      const double fy = (1.0 - std::abs(x)) * std::copysign(1.0, y);
      x = fx;
      y = fy;
    }
    const Vec3 n{x, y, z};
    return n / std::sqrt(norm2(n));
  }
};
static_assert(sizeof(ContactLedgerState) == 6 * sizeof(float),
              "six floats in a row: a checkpoint stores them as one row of 6");

}  // namespace ringdem
