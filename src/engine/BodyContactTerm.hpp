#pragma once

#include <cstdint>
#include <vector>

#include "engine/ForceTerm.hpp"

namespace ringdem {

/// Contacts between particles and rigid bodies (Hertz–Mindlin with R_j, m_j of the body,
/// physics.md §3): candidates within the skin of a body's surface, one slot per contact, the
/// tangential spring in its ContactSpringStore (one row per candidate, keyed by (gid, body)). Also
/// each contact's load on its body, for the rank-independent reduction of the body loads.
class BodyContactTerm final : public ForceTerm {
 public:
  std::string_view name() const override { return "body_contacts"; }
  double ghost_width(const ParticleStore&) const override { return 0.0; }
  void rebuild(RebuildContext& ctx) override;
  void compute(ComputeContext& ctx) override;
  ContactSpringStore* springs() override { return &springs_; }
  const ContactSpringStore* springs() const override { return &springs_; }
  void find_overlaps(const ParticleStore& p, const std::vector<RigidBody>& bodies, double fraction,
                     std::vector<ContactOverlap>& out) const override;

  /// One particle's contact load on a rigid body in the last compute(), summed by the
  /// simulation in (body, gid) order over all ranks.
  struct BodyLoad {
    std::int64_t gid;
    std::int32_t body;
    Vec3 force;   ///< on the body
    Vec3 torque;  ///< on the body, about its reference point
  };
  const std::vector<BodyLoad>& body_loads() const { return body_loads_; }

 private:
  std::vector<std::uint32_t> particle_, body_;
  /// Row w: contact w (gid of particle_[w], partner the body's number).
  ContactSpringStore springs_{ContactSpringStore::Partner::kRigidBody};
  SlotRange slots_;
  std::vector<BodyLoad> body_loads_;
};

}  // namespace ringdem
