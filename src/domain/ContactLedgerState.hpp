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
  [[gnu::always_inline]] static ContactLedgerState of(const Vec3& damping, const Vec3& n,
                                                      double overlap) {
    ContactLedgerState s;
    s.damping = to_vec3f(damping);
    double u, v;
    fold_normal(n, u, v);
    s.normal_u = static_cast<float>(u);
    s.normal_v = static_cast<float>(v);
    s.overlap = static_cast<float>(overlap);
    return s;
  }
  /// The unit normal.
  Vec3 normal() const { return unfold_normal(normal_u, normal_v); }

  // The two halves of the octahedral map, written with selects rather than branches so that a
  // vectorised loop can run them (PairContactChunk::compute_lanes).
  /// The unit vector `n` folded onto the square |u| + |v| <= 1.
  [[gnu::always_inline]] static void fold_normal(const Vec3& n, double& u, double& v) {
    const double l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    const double x = n.x / l1, y = n.y / l1;
    const bool lower = n.z < 0.0;  // the lower half folded over the diagonals
    u = lower ? (1.0 - std::abs(y)) * std::copysign(1.0, x) : x;
    v = lower ? (1.0 - std::abs(x)) * std::copysign(1.0, y) : y;
  }
  /// The inverse of fold_normal(), normalised.
  [[gnu::always_inline]] static Vec3 unfold_normal(double u, double v) {
    const double z = 1.0 - std::abs(u) - std::abs(v);
    const bool lower = z < 0.0;
    const Vec3 n{lower ? (1.0 - std::abs(v)) * std::copysign(1.0, u) : u,
                 lower ? (1.0 - std::abs(u)) * std::copysign(1.0, v) : v, z};
    return n / std::sqrt(norm2(n));
  }
};
static_assert(sizeof(ContactLedgerState) == 6 * sizeof(float),
              "six floats in a row: a checkpoint stores them as one row of 6");

}  // namespace ringdem
